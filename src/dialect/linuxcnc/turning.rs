//! LinuxCNC 2.9's lathe cycles G70 (finishing) and G71/G72 (roughing; `.1` without pockets,
//! `.2` only after the first pocket), with the profile in the o-word subroutine named by Q
//! (g-code.adoc, "G70 Lathe finishing cycle", "G71 G72 Lathe roughing cycles"), read as its
//! interpreter reads them (`interp_g7x.cc`, `convert_g7x`): the cycle's words, then the
//! subroutine's blocks read — not executed — into a contour. docs/dialects/linuxcnc-turning.md.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::{Line, Modal, Position, Word};
use crate::toolpath::MotionKind;
use crate::turning::{
    Along, Contour, Cycle, Finish, FinishOffsets, Pockets, Rough, Segment, Shape, Strategy,
    TurningJob,
};
use crate::units::{Pos, Units};

/// A G7x cycle waiting for its profile.
#[derive(Clone, Debug)]
pub(super) struct Pending {
    /// The cycle ×10 (700, 710, 711, 712, 720, 721, 722).
    code: u16,
    line: u32,
    span: Span,
    q: f64,
    /// The cycle's words in program units (D, E, I, P, R, U, W).
    words: [Option<f64>; 7],
    /// Where the cycle starts (mm, X radius).
    start: Pos,
    units: Units,
    /// The distance mode (G90) and arc-centre mode (G90.1) at the cycle.
    absolute: bool,
    ijk_absolute: bool,
    diameter: bool,
    /// The profile so far: the motion mode in force and the last point (mm).
    motion: u16,
    at: Pos,
    segments: Vec<Segment>,
}

const LETTERS: [u8; 7] = *b"DEIPRUW";

fn error(span: Span, code: Code, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(code, span, msg)
}

impl Pending {
    /// The cycle's block: its words, and the rapid to X/Z (where the profile starts).
    pub(super) fn read(
        line: &Line,
        modal: &Modal,
        code: u16,
        code_span: Span,
        state: (u16, bool, bool),
    ) -> Result<Pending> {
        let (motion, ijk_absolute, cutter_comp) = state;
        let (cycle, sub) = (code / 10, code % 10);
        let Some(q) = line.word(b'Q') else {
            return Err(error(
                code_span,
                Code::MissingWord,
                "G7x.x  requires a Q word",
            )
            .with_hint("Q names the o-word subroutine that holds the profile: G71 Q100 … with o100 sub"));
        };
        if cutter_comp && cycle != 70 {
            return Err(error(
                code_span,
                Code::Conflict,
                format!("G{cycle}.{sub} cannot be used with cutter compensation enabled"),
            ));
        }
        let named = |axis: u8| modal.absolute && line.word(axis).is_some();
        let from = match modal.position.known() {
            Some(p) => p,
            // X and Z of the block name the start: where the tool was does not matter.
            None if named(b'X') && named(b'Z') => Pos::new(0.0, 0.0),
            None => {
                return Err(error(
                    code_span,
                    Code::MissingWord,
                    format!(
                        "the tool's position ({} unknown) is where G{cycle} starts: move to X and Z before it, or give them on the block",
                        modal.position.unknown_axes().join(", ")
                    ),
                ))
            }
        };
        let start = start_point(line, modal, from);
        let mut words = [None; 7];
        for (slot, letter) in words.iter_mut().zip(LETTERS) {
            *slot = line.word(letter).map(|w| modal.value(w));
        }
        Ok(Pending {
            code,
            line: line.number,
            span: line.span(),
            q: modal.value(q),
            words,
            start,
            units: modal.units,
            absolute: modal.absolute,
            ijk_absolute,
            diameter: modal.diameter_x,
            motion,
            at: start,
            segments: Vec::new(),
        })
    }

    pub(super) fn start(&self) -> Pos {
        self.start
    }

    pub(super) fn q(&self) -> f64 {
        self.q
    }

    /// A block of the profile: its motion code and end point (X, Z, or U, W as increments in
    /// G90), an arc's centre (I, K, or R).
    pub(super) fn block(&mut self, line: &Line, modal: &mut Modal) -> Result<()> {
        for w in line.words {
            if w.letter == b'G' {
                let c = (w.value * 10.0).round() as u16;
                if matches!(c, 0 | 10 | 20 | 30) {
                    self.motion = c;
                }
            }
            if matches!(w.letter, b'A' | b'C') {
                return Err(error(
                    w.span,
                    Code::Unsupported,
                    "threadcut does not read a profile's fillets (A) and chamfers (C) yet",
                )
                .with_hint("write the fillet as a G2/G3 arc and the chamfer as a G1 line"));
            }
        }
        let to = self.end(line, modal)?;
        if to == self.at {
            return Ok(());
        }
        modal.position = Position::at(to);
        let shape = match self.motion {
            20 | 30 => Shape::Arc {
                centre: self.centre(line, modal, to)?,
                clockwise: self.motion == 20,
            },
            _ => Shape::Line,
        };
        if matches!(self.motion, 0 | 10 | 20 | 30) {
            self.segments.push(Segment {
                to,
                shape,
                line: line.number,
            });
        }
        self.at = to;
        Ok(())
    }

    fn end(&self, line: &Line, modal: &Modal) -> Result<Pos> {
        let x_mm = |w: &Word| {
            let v = modal.value(w);
            self.units.to_mm(if self.diameter { v / 2.0 } else { v })
        };
        let mut to = if self.absolute {
            self.at
        } else {
            Pos::new(0.0, 0.0)
        };
        let pairs = [(b'X', b'U', true), (b'Z', b'W', false)];
        for (axis, inc, is_x) in pairs {
            let (a, i) = (line.word(axis), line.word(inc));
            let v = match (a, i) {
                (Some(_), Some(i)) => {
                    return Err(error(
                        i.span,
                        Code::Conflict,
                        format!(
                            "G7x error: Cannot use {} and {} in the same block",
                            inc as char, axis as char
                        ),
                    ))
                }
                (None, Some(i)) if !self.absolute => {
                    return Err(error(
                        i.span,
                        Code::Conflict,
                        format!(
                            "G7x error: Cannot use {} in incremental mode (G91)",
                            inc as char
                        ),
                    ))
                }
                (None, Some(i)) => {
                    let d = if is_x { x_mm(i) } else { modal.length_mm(i) };
                    Some(if is_x { to.x + d } else { to.z + d })
                }
                (Some(a), None) => Some(if is_x { x_mm(a) } else { modal.length_mm(a) }),
                (None, None) => None,
            };
            if let Some(v) = v {
                if is_x {
                    to.x = v;
                } else {
                    to.z = v;
                }
            }
        }
        if !self.absolute {
            to = Pos::new(to.x + self.at.x, to.z + self.at.z);
        }
        Ok(to)
    }

    /// The arc's centre: from R (the short way for R > 0 … as LinuxCNC computes it), or I/K
    /// (incremental from the arc's start under G91.1; I a radius).
    fn centre(&self, line: &Line, modal: &Modal, to: Pos) -> Result<Pos> {
        let (i, k) = (line.word(b'I'), line.word(b'K'));
        if let Some(r) = line.word(b'R') {
            if let Some(w) = i.or(k) {
                return Err(error(
                    w.span,
                    Code::Conflict,
                    "G7X error: both R and I or K flag used for arc",
                ));
            }
            // The centre on the chord's perpendicular bisector, to the left (G3) or right (G2)
            // of the chord by √(r² − c²/4)·|chord|/|chord|.
            let r = modal.length_mm(r);
            let (sz, sx) = (self.at.z, self.at.x);
            let (dz, dx) = (to.z - sz, to.x - sx);
            let n = dz * dz + dx * dx;
            let k = ((r * r - n / 4.0) / n).sqrt();
            let sign = if self.motion == 30 { 1.0 } else { -1.0 };
            return Ok(Pos::new(
                (sx + to.x) / 2.0 + sign * k * dz,
                (sz + to.z) / 2.0 - sign * k * dx,
            ));
        }
        if i.is_none() && k.is_none() {
            return Err(error(
                line.span(),
                Code::MissingWord,
                "G7X error: either I or K must be present for arc",
            ));
        }
        let ci = i.map_or(0.0, |w| modal.length_mm(w));
        let ck = k.map_or(0.0, |w| modal.length_mm(w));
        Ok(if self.ijk_absolute {
            Pos::new(ci, ck)
        } else {
            Pos::new(self.at.x + ci, self.at.z + ck)
        })
    }

    /// The profile is read: the cycle, and where it leaves the tool (the modal position is set).
    /// The motion mode its last move leaves (×10).
    /// Errors found once the profile is read are reported where LinuxCNC reports them: at the
    /// block that ended the subroutine (`end`), the hint naming the cycle's line.
    pub(super) fn finish(self, modal: &mut Modal, end: Span) -> Result<(TurningJob, u16)> {
        let [d, e, i, p, r, u, w] = self.words;
        let at_end = |d: Diagnostic| Diagnostic {
            span: end,
            ..d.with_hint(format!(
                "in the profile of the G{} at line {}",
                self.code / 10,
                self.line
            ))
        };
        if i.is_some_and(|i| i <= 0.0) {
            return Err(at_end(error(
                end,
                Code::OutOfRange,
                "G7X error: I must be greater than zero.",
            )));
        }
        let mm = |v: Option<f64>, default: f64| self.units.to_mm(v.unwrap_or(default));
        let contour = Contour {
            start: self.start,
            segments: self.segments,
        };
        let pockets = match self.code % 10 {
            1 => Pockets::None,
            2 => Pockets::AfterFirst,
            _ => Pockets::All,
        };
        let cycle = match self.code / 10 {
            70 => Cycle::Finish(Finish {
                start: self.start,
                contour,
                offsets: Some(FinishOffsets {
                    first: mm(d, 0.0),
                    last: mm(e, 0.0),
                    passes: p.unwrap_or(1.0),
                }),
            }),
            c => Cycle::Rough(Rough {
                along: if c == 72 { Along::X } else { Along::Z },
                start: self.start,
                depth: mm(i, 1.0),
                retract: mm(r, 0.5),
                allowance_x: mm(u, 0.0),
                allowance_z: mm(w, 0.0),
                pockets: pockets != Pockets::None,
                contour,
                strategy: Strategy::Offset {
                    distance: mm(d, 0.0),
                    pockets,
                },
                then_outline: None,
            }),
        };
        let job = TurningJob {
            cycle,
            line: self.line,
            span: self.span,
            units: self.units,
            controller: "LinuxCNC",
        };
        let path = crate::turning::toolpath(&job).map_err(at_end)?;
        modal.position = Position::at(path.end());
        let last = match path.motions.last().map(|m| m.kind) {
            Some(MotionKind::Rapid) | None => 0,
            Some(MotionKind::Arc {
                clockwise: true, ..
            }) => 20,
            Some(MotionKind::Arc { .. }) => 30,
            Some(_) => 10,
        };
        Ok((job, last))
    }
}

/// Where the cycle starts: X and Z of its block (increments under G91), else where the tool is.
fn start_point(line: &Line, modal: &Modal, from: Pos) -> Pos {
    let mut at = from;
    if let Some(x) = line.word(b'X') {
        let v = modal.x_to_mm(modal.value(x));
        at.x = if modal.absolute { v } else { from.x + v };
    }
    if let Some(z) = line.word(b'Z') {
        let v = modal.length_mm(z);
        at.z = if modal.absolute { v } else { from.z + v };
    }
    at
}
