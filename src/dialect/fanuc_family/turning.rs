//! The Fanuc family's turning cycles (numbers of system A; [`TurningCodes`] gives B's and C's):
//!
//! ```text
//! G71 U(Δd) R(e) ;                       first block: depth of cut (radius), retract
//! G71 P(ns) Q(nf) U(Δu) W(Δw) F S T ;    stock removal in turning to the contour N(ns)…N(nf)
//! G72 W(Δd) R(e) ; G72 P Q U W F S T ;   … in facing
//! G73 U(Δi) W(Δk) R(d) ;                 first block: relief in X (radius) and Z, passes
//! G73 P Q U W F S T ;                    pattern repeating
//! G70 P(ns) Q(nf) ;                      finishing along a contour read before
//! G74 R(e) ; G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F ;   end-face peck drilling (P, Q in increments)
//! G75 R(e) ; G75 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F ;   grooving along X
//! G90 X(U) Z(W) R F ; G94 X(U) Z(W) R F ;          box cycles, modal: `X..` repeats
//! ```
//!
//! GSK 980TDi writes them the same way. A cycle with a contour waits for it: the blocks that
//! follow are read by [`contour`](super::contour) (the control does not run them), and the cycle
//! is complete at N(nf). Decisions: `docs/dialects/fanuc.md`, "Turning cycles".

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::{alone_in_block, only_words, Read};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, MotionMode, Word};
use crate::turning::{
    Along, BoxCycle, Contour, Cycle, Finish, Pattern, Peck, Rough, Strategy, TurningJob,
};
use crate::units::Pos;

use super::codes::{g_name, TurningCodes};
use super::contour::{BoxModal, Pending, Reading, Step, Written};
use super::family::*;

/// The G codes a contour block may carry (×10), besides the motion codes: dwell, tool nose
/// radius compensation, constant surface speed, feed per minute / per revolution (both systems'
/// numbers: A's G98/G99, B's and C's G94/G95), absolute/incremental in B and C.
const CONTOUR_CODES: &[u16] = &[
    0, 10, 20, 30, 40, 400, 410, 420, 900, 910, 940, 950, 960, 970, 980, 990,
];

impl FanucFamily {
    /// Whether `line` has one of the turning cycles' codes.
    pub(super) fn turning_code<'l>(&self, line: &'l Line) -> Option<(&'l Word, u16)> {
        let all = self.codes.turning.all();
        line.words
            .iter()
            .filter(|w| w.letter == b'G')
            .find_map(|w| g_code(w.value).filter(|c| all.contains(c)).map(|c| (w, c)))
    }

    /// Reads `line` if it belongs to a turning cycle: a cycle's block, a block of a contour being
    /// read, a block repeating a modal box cycle. `None` otherwise.
    pub(super) fn read_turning(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Read>> {
        if self.turning.reading.is_some() {
            return self.contour_block(conv, line, modal).map(Some);
        }
        let Some((gword, code)) = self.turning_code(line) else {
            return self.box_repeat(conv, line, modal);
        };
        let t = self.codes.turning;
        let bare = line.words.iter().all(|w| matches!(w.letter, b'G' | b'N'));
        if bare || ((code == t.box_z || code == t.box_x) && !self.box_block(line, code)) {
            // A cycle's code without any of its words sets nothing: read as before, a mode
            // change without a move (G70–G75 and G90/G94 mean other things on other controls,
            // whose programs are often checked against this one).
            self.turning.box_modal = None;
            return Ok(None);
        }
        self.turning.box_modal = None;
        self.g92 = None;
        self.run_phase = None;
        let name = g_name(code);
        let distance: &[u16] = if self.codes.g90_g91 { &[900, 910] } else { &[] };
        alone_in_block(line, gword.span, &name, distance)?;
        for w in line.words.iter().filter(|w| w.letter == b'G') {
            match g_code(w.value) {
                Some(900) if self.codes.g90_g91 => modal.absolute = true,
                Some(910) if self.codes.g90_g91 => modal.absolute = false,
                _ => {}
            }
        }
        let span = gword.span;
        let read = if code == t.box_z || code == t.box_x {
            Read::Turning(Some(Box::new(
                self.read_box(conv, line, modal, span, code, None)?,
            )))
        } else if code == t.peck_z || code == t.peck_x {
            self.read_peck(conv, line, modal, span, code)?
        } else {
            self.read_with_contour(line, modal, (span, code), warnings)?
        };
        Ok(Some(read))
    }

    /// Whether a block with the box cycle's code `code` runs the cycle: it names an end point, and
    /// no motion code of its group (G0–G3, the thread move) comes after the box code in it ("when
    /// G codes of one group share a block, the last one is effective"). A box code alone is read
    /// as before, a mode without a move (`G90` is absolute distance on most other controls, and a
    /// program for one of them is often checked against this one).
    fn box_block(&self, line: &Line, code: u16) -> bool {
        let axes = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        let group_01 = [0, 10, 20, 30, self.codes.thread_move, code];
        let last = line
            .words
            .iter()
            .filter(|w| w.letter == b'G')
            .filter_map(|w| g_code(w.value))
            .rfind(|c| group_01.contains(c));
        axes && last == Some(code)
    }

    /// A block while a contour is read: part of it, or its last block (the cycle complete).
    fn contour_block(&mut self, conv: &Conventions, line: &Line, modal: &Modal) -> Result<Read> {
        let Some(state) = self.turning.reading.as_mut() else {
            return Ok(Read::Plain);
        };
        let name = g_name(state.1.code);
        match state.0.block(conv, line, &name)? {
            Step::Read => Ok(Read::Turning(None)),
            Step::Done(written) => {
                let Some(state) = self.turning.reading.take() else {
                    return Ok(Read::Plain);
                };
                let job = self.with_contour(state.1, &written, modal)?;
                self.turning.kept.keep(written);
                Ok(Read::Turning(Some(Box::new(job))))
            }
        }
    }

    /// The waiting cycle with its contour.
    fn with_contour(&self, pending: Pending, w: &Written, modal: &Modal) -> Result<TurningJob> {
        let mut job = pending.job;
        let name = g_name(pending.code);
        let start = job.start();
        let tol = modal.resolution().length();
        let contour = w.contour(start, tol, &name)?;
        match &mut job.cycle {
            Cycle::Rough(r) => {
                r.contour = contour;
                // Type II by the first block's two axes, or as the cycle's words chose (Haas's R1).
                r.pockets = r.pockets || w.first_both_axes;
            }
            Cycle::Pattern(p) => p.contour = contour,
            Cycle::Finish(f) => f.contour = contour,
            Cycle::Removal(r) => r.contour = contour,
            Cycle::Box(_) | Cycle::Peck(_) => {}
        }
        Ok(job)
    }

    /// A block of axis words alone while a box cycle is modal repeats it; any G code but G90/G91
    /// in systems B and C ends it.
    fn box_repeat(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
    ) -> Result<Option<Read>> {
        let Some(m) = self.turning.box_modal else {
            return Ok(None);
        };
        let distance = |c: u16| self.codes.g90_g91 && matches!(c, 900 | 910);
        let other_g = line
            .words
            .iter()
            .any(|w| w.letter == b'G' && !g_code(w.value).is_some_and(distance));
        if other_g {
            self.turning.box_modal = None;
            return Ok(None);
        }
        if !line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'))
        {
            return Ok(None);
        }
        let job = self.read_box(conv, line, modal, line.span(), m.code, Some(m))?;
        Ok(Some(Read::Turning(Some(Box::new(job)))))
    }

    fn job(&self, line: &Line, span: Span, modal: &Modal, cycle: Cycle) -> TurningJob {
        TurningJob {
            cycle,
            line: line.number,
            span,
            units: modal.units,
            controller: self.flavour.controller,
        }
    }

    /// G90/G94 (G77/G79 in B, G20/G24 in C): `X(U) Z(W) R F`, R the taper (radius for G90).
    fn read_box(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        code: u16,
        repeat: Option<BoxModal>,
    ) -> Result<TurningJob> {
        let t: TurningCodes = self.codes.turning;
        let name = g_name(code);
        let along = if code == t.box_z { Along::Z } else { Along::X };
        let taper_letter = match (self.flavour.taper_letter, along) {
            (b'R', _) => b'R',
            (_, Along::Z) => b'I',
            (_, Along::X) => b'K',
        };
        let mut letters = b"GNXZUWFST".to_vec();
        letters.push(taper_letter);
        let tl = taper_letter as char;
        only_words(
            line,
            &letters,
            &format!("a {name} block"),
            &format!("X(U) Z(W) {tl} F"),
        )?;
        let a = start_point(modal, span, &name)?;
        let mut end = modal.target(conv, line, a)?;
        let has_x = line.word(b'X').or(line.word(b'U')).is_some();
        let has_z = line.word(b'Z').or(line.word(b'W')).is_some();
        match repeat {
            Some(m) => {
                if !has_x {
                    end.x = m.end.x;
                }
                if !has_z {
                    end.z = m.end.z;
                }
            }
            None if !has_x || !has_z => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    format!("{name} needs its end point: X (or U) and Z (or W)"),
                ))
            }
            None => {}
        }
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        let taper = match line.word(taper_letter) {
            Some(r) => modal.length_mm(r),
            None => repeat.map_or(0.0, |m| m.taper),
        };
        // The cut starts at the end plus the taper, on the side of the start point: a taper
        // beyond the start point's X (Z for the facing cycle) would start the cut behind it.
        let (s, e) = match along {
            Along::Z => (a.x, end.x),
            Along::X => (a.z, end.z),
        };
        let tol = modal.resolution().length();
        if tol.gt(taper.abs(), 0.0) && tol.lt((e + taper - s) * (e - s).signum(), 0.0) {
            return Err(geometry(
                span,
                format!(
                    "{tl}{} puts the start of the cut beyond the start point: when {tl}'s sign differs from the depth's, |{tl}| must not exceed it",
                    modal.units.from_mm(taper)
                ),
            ));
        }
        self.turning.box_modal = Some(BoxModal { code, end, taper });
        modal.motion = MotionMode::Cycle;
        let cycle = Cycle::Box(BoxCycle {
            along,
            start: a,
            end,
            taper,
        });
        Ok(self.job(line, span, modal, cycle))
    }

    /// G74/G75: the first block `R(e)`, the second `X(U) Z(W) P(Δi) Q(Δk) R(Δd) F`.
    fn read_peck(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        code: u16,
    ) -> Result<Read> {
        let name = g_name(code);
        let second = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        if !second {
            only_words(line, b"GNR", &format!("the first {name} block"), "R(e)")?;
            if let Some(r) = line.word(b'R') {
                self.turning.first.peck_retract = Some(non_negative(modal, r, &name, "R(e)")?);
            }
            return Ok(Read::Settings);
        }
        only_words(
            line,
            b"GNXZUWPQRFST",
            &format!("the second {name} block"),
            "X(U) Z(W) P(Δi) Q(Δk) R(Δd) F",
        )?;
        let along = if code == self.codes.turning.peck_z {
            Along::Z
        } else {
            Along::X
        };
        let a = start_point(modal, span, &name)?;
        let end = modal.target(conv, line, a)?;
        let di = match line.word(b'P') {
            Some(w) => self.increments(modal, w, &format!("P(Δi) of {name}"), "the X amount")?,
            None => 0.0,
        };
        let dk = match line.word(b'Q') {
            Some(w) => self.increments(modal, w, &format!("Q(Δk) of {name}"), "the Z amount")?,
            None => 0.0,
        };
        let (peck, shift, across) = match along {
            Along::Z => (dk, di, end.x - a.x),
            Along::X => (di, dk, end.z - a.z),
        };
        let travel = match along {
            Along::Z => end.z - a.z,
            Along::X => end.x - a.x,
        };
        let tol = modal.resolution().length();
        let (peck_word, shift_word) = match along {
            Along::Z => ("Q(Δk)", "P(Δi)"),
            Along::X => ("P(Δi)", "Q(Δk)"),
        };
        if !tol.is_zero(across) && tol.is_zero(shift) {
            return Err(alarm_62(
                span,
                &name,
                format!("{shift_word} is zero while the end point lies across from the start point: the shift between cuts is missing"),
            ));
        }
        if !tol.is_zero(travel) && tol.is_zero(peck) {
            return Err(alarm_62(
                span,
                &name,
                format!("{peck_word}, the depth of each peck, is zero"),
            ));
        }
        let relief = match line.word(b'R') {
            Some(r) => modal.length_mm(r),
            None => 0.0,
        };
        if !tol.is_zero(across) && relief < 0.0 {
            return Err(alarm_62(
                span,
                &name,
                "R(Δd) is negative though the shift gives the relief's direction".into(),
            ));
        }
        // The relief is taken back toward the start point's side (away from the next cut).
        let relief = if tol.is_zero(across) {
            relief
        } else {
            -relief * across.signum()
        };
        let retract = self.turning.first.peck_retract.ok_or_else(|| {
            Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{name} has no retract e: write the first block {name} R(e) before it"),
            )
            .with_hint("the control takes e from parameter 5139 otherwise, which the machine profile does not state")
        })?;
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        let cycle = Cycle::Peck(Peck {
            along,
            start: a,
            end,
            peck,
            shift,
            retract,
            relief,
        });
        Ok(Read::Turning(Some(Box::new(
            self.job(line, span, modal, cycle),
        ))))
    }

    /// G70, G71, G72, G73: the first block (settings) or the cycle, which waits for its contour.
    /// A member with the one-block form (Haas) writes G71/G72/G73 in one block
    /// ([`Self::one_block_cycle`]).
    fn read_with_contour(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        (span, code): (Span, u16),
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        let t = self.codes.turning;
        let name = g_name(code);
        let has_pq = line.word(b'P').is_some() || line.word(b'Q').is_some();
        let one_block = code != t.finish && matches!(self.flavour.g76, G76Form::OneBlock(_));
        if one_block && self.one_block_turning.is_none() {
            return Err(one_block_not_read(
                line,
                span,
                &name,
                self.flavour.controller,
            ));
        }
        if one_block && !has_pq {
            return Err(one_block_needs_pq(span, &name, self.flavour.controller));
        }
        if !has_pq {
            if code == t.finish {
                return Err(alarm_61(span, &name));
            }
            self.first_block(line, modal, code)?;
            return Ok(Read::Settings);
        }
        let (words, format): (&[u8], &str) = if code == t.finish {
            (b"GNPQ", "P(ns) Q(nf)")
        } else if one_block && code == t.pattern {
            (b"GNPQUWIKDFST", ONE_BLOCK_G73)
        } else if one_block {
            (b"GNPQUWDIKRFST", ONE_BLOCK_G71)
        } else {
            (b"GNPQUWFST", "P(ns) Q(nf) U(Δu) W(Δw) F S T")
        };
        only_words(
            line,
            words,
            &format!("the {name} block with P and Q"),
            format,
        )?;
        let (Some(p), Some(q)) = (line.word(b'P'), line.word(b'Q')) else {
            return Err(alarm_61(span, &name));
        };
        let (ns, nf) = (sequence(p, &name)?, sequence(q, &name)?);
        let start = start_point(modal, span, &name)?;
        let allowance_x = line
            .word(b'U')
            .map_or(0.0, |w| modal.x_to_mm(modal.value(w)));
        let allowance_z = line.word(b'W').map_or(0.0, |w| modal.length_mm(w));
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        let cycle = if code == t.finish {
            Cycle::Finish(Finish {
                start,
                contour: Contour::default(),
                offsets: None,
            })
        } else if one_block {
            let allowance = (allowance_x, allowance_z);
            self.one_block_cycle(line, modal, (span, code), start, allowance, warnings)?
        } else if code == t.pattern {
            let first = self.turning.first;
            let unset = |what: &str, p: &str| unset_first(span, &name, "U(Δi) W(Δk) R(d)", what, p);
            Cycle::Pattern(Pattern {
                start,
                relief_x: first.relief_x.ok_or_else(|| unset("relief Δi", "5135"))?,
                relief_z: first.relief_z.ok_or_else(|| unset("relief Δk", "5136"))?,
                passes: first
                    .passes
                    .ok_or_else(|| unset("number of passes d", "5137"))?,
                allowance_x,
                allowance_z,
                contour: Contour::default(),
            })
        } else {
            let first = self.turning.first;
            let d = if code == t.rough_z {
                "U(Δd)"
            } else {
                "W(Δd)"
            };
            let words = format!("{d} R(e)");
            let unset = |what: &str, p: &str| unset_first(span, &name, &words, what, p);
            Cycle::Rough(Rough {
                strategy: Strategy::Layers,
                then_outline: None,
                along: if code == t.rough_z {
                    Along::Z
                } else {
                    Along::X
                },
                start,
                depth: first
                    .depth
                    .ok_or_else(|| unset("depth of cut Δd", "5132"))?,
                retract: first.retract.ok_or_else(|| unset("retract e", "5133"))?,
                allowance_x,
                allowance_z,
                pockets: false,
                contour: Contour::default(),
            })
        };
        let pending = Pending {
            code,
            job: self.job(line, span, modal, cycle),
        };
        if let Some(w) = self.turning.kept.get(ns, nf).cloned() {
            // The contour was read before (by a cycle with the same P and Q).
            let job = self.with_contour(pending, &w, modal)?;
            return Ok(Read::Turning(Some(Box::new(job))));
        }
        if code == t.finish {
            return Err(alarm_63(span, &name, ns, "no cycle before it read a contour with these P and Q")
                .with_hint("threadcut reads a contour where a G71, G72 or G73 before the G70 reads it: the blocks that follow that cycle"));
        }
        let reading = Reading::new(ns, nf, line, span, modal, CONTOUR_CODES);
        self.turning.reading = Some(Box::new((reading, pending)));
        Ok(Read::Turning(None))
    }

    /// Haas's one-block G71/G72 `P Q U W D F [I K] [R1]` and G73 `P Q U W I K D F`
    /// (docs/dialects/haas.md, "Turning cycles"): D the depth of cut (a radius) or G73's number of
    /// passes; G71/G72's I, K the rough pass allowance (I a radius), beyond the finishing
    /// allowance U, W: the layers and a first pass along the contour stop at both, a second pass
    /// at U, W alone; R1 type II; the retract after each cut the machine's (Setting 73). G73's I,
    /// K are the relief from the first cut to the last (I a radius).
    fn one_block_cycle(
        &self,
        line: &Line,
        modal: &Modal,
        (span, code): (Span, u16),
        start: Pos,
        (allowance_x, allowance_z): (f64, f64),
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Cycle> {
        let t = self.codes.turning;
        let name = g_name(code);
        let controller = self.flavour.controller;
        let length = |letter: u8| line.word(letter).map_or(0.0, |w| modal.length_mm(w));
        let tol = modal.resolution().length();
        let d = line.word(b'D');
        if code == t.pattern {
            let Some(d) = d else {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    format!("{controller}'s {name} needs D, the number of cutting passes"),
                )
                .with_hint(ONE_BLOCK_G73));
            };
            if d.value < 1.0 || d.value.fract() != 0.0 || d.value > 9999.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    d.span,
                    format!(
                        "D{} of {name} is the number of cutting passes: a whole number from 1 to 9999",
                        d.value
                    ),
                ));
            }
            return Ok(Cycle::Pattern(Pattern {
                start,
                relief_x: length(b'I'),
                relief_z: length(b'K'),
                passes: d.value as u32,
                allowance_x,
                allowance_z,
                contour: Contour::default(),
            }));
        }
        let Some(d) = d else {
            return Err(Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{name} has no D, the depth of cut of each pass (a radius)"),
            )
            .with_hint("the control takes Setting 72 otherwise, which the machine profile does not state: write D on the block"));
        };
        let depth = modal.length_mm(d);
        if !tol.gt(depth, 0.0) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                d.span,
                format!(
                    "D{} of {name}, the depth of cut of each pass, must be a positive radius",
                    d.value
                ),
            ));
        }
        let pockets = match line.word(b'R') {
            None => false,
            Some(r) if r.value == 1.0 => true,
            Some(r) => {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    r.span,
                    format!(
                        "R{} of {name}: R takes only the value 1 (type 2 roughing)",
                        r.value
                    ),
                ))
            }
        };
        let Some(setting) = self.one_block_turning else {
            return Err(one_block_not_read(line, span, &name, controller));
        };
        if setting.assumed {
            warnings.push(assumed_retract(span, &name, setting.retract_mm, modal));
        }
        let (rough_x, rough_z) = (length(b'I'), length(b'K'));
        let rough = !tol.is_zero(rough_x) || !tol.is_zero(rough_z);
        Ok(Cycle::Rough(Rough {
            strategy: Strategy::Layers,
            along: if code == t.rough_z {
                Along::Z
            } else {
                Along::X
            },
            start,
            depth,
            retract: setting.retract_mm,
            allowance_x: allowance_x + rough_x,
            allowance_z: allowance_z + rough_z,
            pockets,
            contour: Contour::default(),
            then_outline: rough.then_some((allowance_x, allowance_z)),
        }))
    }

    /// The first block of G71/G72 (`U(Δd) R(e)`, `W(Δd) R(e)`) or G73 (`U(Δi) W(Δk) R(d)`).
    fn first_block(&mut self, line: &Line, modal: &Modal, code: u16) -> Result<()> {
        let t = self.codes.turning;
        let name = g_name(code);
        let first = &mut self.turning.first;
        // GSK's first block also takes F, S and T (valid for the roughing, as on its second).
        let fst: &[u8] = if self.flavour.turning_fst_first {
            b"FST"
        } else {
            b""
        };
        if code == t.pattern {
            only_words(
                line,
                &[&b"GNUWR"[..], fst].concat(),
                &format!("the first {name} block"),
                "U(Δi) W(Δk) R(d)",
            )?;
            if let Some(u) = line.word(b'U') {
                first.relief_x = Some(modal.length_mm(u));
            }
            if let Some(w) = line.word(b'W') {
                first.relief_z = Some(modal.length_mm(w));
            }
            if let Some(r) = line.word(b'R') {
                if r.value < 1.0 || r.value.fract() != 0.0 || r.value > 9999.0 {
                    return Err(alarm_62(
                        r.span,
                        &name,
                        format!(
                            "R(d)={} must be a whole number of passes, at least 1",
                            r.value
                        ),
                    ));
                }
                first.passes = Some(r.value as u32);
            }
            return Ok(());
        }
        let d = if code == t.rough_z { b'U' } else { b'W' };
        let dname = if code == t.rough_z {
            "U(Δd)"
        } else {
            "W(Δd)"
        };
        let mut letters = [&b"GNR"[..], fst].concat();
        letters.push(d);
        only_words(
            line,
            &letters,
            &format!("the first {name} block"),
            &format!("{dname} R(e)"),
        )?;
        if let Some(w) = line.word(d) {
            let depth = modal.length_mm(w);
            if !modal.resolution().length().gt(depth, 0.0) {
                return Err(alarm_62(
                    w.span,
                    &name,
                    format!(
                        "the depth of cut {dname}={} must be greater than 0",
                        w.value
                    ),
                ));
            }
            first.depth = Some(depth);
        }
        if let Some(r) = line.word(b'R') {
            first.retract = Some(non_negative(modal, r, &name, "R(e)")?);
        }
        Ok(())
    }

    /// At the end of the program: a contour still being read never found its last block.
    pub fn end_of_input(&mut self) -> Result<()> {
        match self.turning.reading.take() {
            Some(state) => {
                let (r, p) = *state;
                Err(alarm_63(
                    r.span,
                    &g_name(p.code),
                    if r.started() { r.nf } else { r.ns },
                    "the program ends before it",
                ))
            }
            None => Ok(()),
        }
    }

    /// Whether a turning cycle keeps the reader busy with every line (a contour being read, a
    /// modal box cycle).
    #[inline(always)]
    pub(super) fn turning_in_progress(&self) -> bool {
        self.turning.reading.is_some() || self.turning.box_modal.is_some()
    }
}

/// A sequence number P(ns) or Q(nf): a whole number 1–99999.
fn sequence(w: &Word, name: &str) -> Result<u32> {
    if w.has_dot && !w.is_computed()
        || w.value.fract() != 0.0
        || !(1.0..=99999.0).contains(&w.value)
    {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            w.span,
            format!(
                "{}{} of {name} is not a sequence number: write the N number of the contour's block, 1–99999, without a decimal point",
                w.letter as char, w.value
            ),
        ));
    }
    Ok(w.value as u32)
}

fn non_negative(modal: &Modal, w: &Word, name: &str, word: &str) -> Result<f64> {
    let v = modal.length_mm(w);
    if v < 0.0 {
        return Err(alarm_62(
            w.span,
            name,
            format!("{word}={} must not be negative", w.value),
        ));
    }
    Ok(v)
}

/// The one-block forms' words, as Haas's G71 and G73 pages list them.
const ONE_BLOCK_G71: &str = "P Q U W D F [I K] [R1] S T";
const ONE_BLOCK_G73: &str = "P Q U W I K D F S T";

/// The one-block stock removal and pattern cycles of the FS15 program format
/// (`G71 P Q U W D F`, `G73 P Q U W I K D F`): not read in this build (the FS15 format's retract
/// is a parameter no profile states). Haas's are read when its profile states Setting 73.
fn one_block_not_read(line: &Line, span: Span, name: &str, controller: &str) -> Diagnostic {
    let at = line.word(b'D').map_or(span, |w| w.span);
    Diagnostic::error(
        Code::Unsupported,
        at,
        format!("{controller}'s one-block {name} (P Q U W D …) is not read by threadcut"),
    )
    .with_hint("its retract is a machine setting (on a Haas, Setting 73: `roughing_retract_in` in the profile's [haas] table) that the profile does not state; the cycle's moves would be guessed")
}

/// A one-block G71/G72/G73 without P and Q (Fanuc's first block `U(Δd) R(e)` is not the form).
fn one_block_needs_pq(span: Span, name: &str, controller: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!(
            "{controller}'s {name} is one block: P and Q name the contour's first and last blocks"
        ),
    )
    .with_hint(format!(
        "{name} {}",
        if name == "G73" {
            ONE_BLOCK_G73
        } else {
            ONE_BLOCK_G71
        }
    ))
}

/// The warning at a stock removal that uses an assumed retract (the built-in Haas profile's
/// Setting 73).
fn assumed_retract(span: Span, name: &str, retract_mm: f64, modal: &Modal) -> Diagnostic {
    let unit = if modal.units == crate::units::Units::Inch {
        "in"
    } else {
        "mm"
    };
    Diagnostic::warning(
        Code::Suspicious,
        span,
        format!(
            "{name}'s retract after each cut is Setting 73, assumed {} {unit} (the profile's value, not one Haas publishes): the moves between cuts may differ on the machine",
            modal.units.from_mm(retract_mm)
        ),
    )
    .with_hint("state the machine's Setting 73 as `roughing_retract_in` in a profile's [haas] table, with `roughing_retract_assumed = false`")
}

fn alarm_61(span: Span, name: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("{name} alarm (PS0061): P or Q is missing: the cycle names its contour's first block with P(ns) and its last with Q(nf)"),
    )
}

fn alarm_62(span: Span, name: &str, what: String) -> Diagnostic {
    Diagnostic::error(
        Code::OutOfRange,
        span,
        format!("{name} alarm (PS0062): {what}"),
    )
}

fn alarm_63(span: Span, name: &str, n: u32, why: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("{name} alarm (PS0063): the block N{n} is not found: {why}"),
    )
}

/// A two-block cycle's value its first block (`words`) should have set and did not: the
/// control would take parameter `param`, which no profile states.
fn unset_first(span: Span, name: &str, words: &str, what: &str, param: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("{name} has no {what}: write the first block {name} {words} before it"),
    )
    .with_hint(format!(
        "the control takes it from parameter {param} otherwise, which the machine profile does not state"
    ))
}
