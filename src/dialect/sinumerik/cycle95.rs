//! CYCLE95, stock removal: `CYCLE95(NPP, MID, FALZ, FALX, FAL, FF1, FF2, FF3, VARI, DT, DAM,
//! _VRT)` read into the machine-neutral [`Removal`]; its contour (the subprogram NPP, or the
//! section `START:END` of the same program) is read block by block as the interpreter runs it as
//! the cycle's profile. docs/dialects/sinumerik.md ("CYCLE95") has each sentence and decision.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::{Line, Modal, MotionMode, PlainMove, Position};
use crate::turning::{self, Along, Contour, Cycle, Removal, Segment, Shape, TurningJob};
use crate::units::Pos;

/// The parameters, in their order.
pub(super) const NAMES: [&str; 12] = [
    "NPP", "MID", "FALZ", "FALX", "FAL", "FF1", "FF2", "FF3", "VARI", "DT", "DAM", "_VRT",
];

/// The lift-off when `_VRT` is 0 or not written (mm).
const DEFAULT_LIFT_MM: f64 = 1.0;

/// A call's numeric parameters (NPP, the text, is the interpreter's) with where each is written.
pub(super) struct Call {
    pub name: Span,
    pub args: [Option<(f64, Span)>; 12],
}

/// A CYCLE95 whose contour is being read.
pub(super) struct Pending {
    removal: Removal,
    /// The position at the call was not known: the cycle starts at its own start point.
    from_known: bool,
    /// The modal state at the call: the cycle leaves it as it found it.
    saved: Modal,
    line: u32,
    span: Span,
    /// The contour's first point (the end of its first block), then its blocks.
    first: Option<Pos>,
    segments: Vec<Segment>,
    spans: Vec<(u32, Span)>,
}

/// The call read: its values checked, the machining type decoded, in mm.
pub(super) fn read(call: &Call, line: &Line, modal: &Modal) -> Result<Pending> {
    let arg = |i: usize| call.args[i];
    let span_of = |i: usize| arg(i).map_or(call.name, |a| a.1);
    let vari = arg(8).map_or(0.0, |a| a.0);
    if !(1.0..=12.0).contains(&vari) || vari.fract() != 0.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span_of(8),
            format!("CYCLE95 alarm 61002 \"Machining type defined incorrectly\": VARI is {vari}, and must be 1 to 12"),
        )
        .with_hint("1–4 roughing, 5–8 finishing, 9–12 complete; within each: longitudinal outside, face outside, longitudinal inside, face inside"));
    }
    let kind = vari as u32 - 1;
    let (rough, finish) = match kind / 4 {
        0 => (true, false),
        1 => (false, true),
        _ => (true, true),
    };
    let unsigned = |i: usize| -> Result<f64> {
        let v = arg(i).map_or(0.0, |a| a.0);
        if v < 0.0 || !v.is_finite() {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                span_of(i),
                format!("CYCLE95: {} is {v}: it is written without a sign", NAMES[i]),
            ));
        }
        Ok(modal.units.to_mm(v))
    };
    let depth = unsigned(1)?;
    if rough && depth <= 0.0 {
        return Err(Diagnostic::error(
            Code::MissingWord,
            span_of(1),
            "CYCLE95: roughing needs the infeed depth MID, greater than 0",
        ));
    }
    if let Some((v, span)) = arg(10).filter(|a| a.0 != 0.0) {
        return Err(Diagnostic::error(
            Code::Unsupported,
            span,
            format!("CYCLE95: DAM={v}, the chip-breaking interruption of each roughing cut, is not simulated by threadcut"),
        )
        .with_hint("leave DAM empty or 0; docs/dialects/sinumerik.md, \"CYCLE95\""));
    }
    let lift = match unsigned(11)? {
        0.0 => DEFAULT_LIFT_MM,
        v => v,
    };
    let from = modal.position.known();
    let removal = Removal {
        along: if kind.is_multiple_of(2) {
            Along::Z
        } else {
            Along::X
        },
        internal: kind % 4 >= 2,
        from: from.unwrap_or(Pos::new(0.0, 0.0)),
        depth,
        lift,
        allowance_z: unsigned(2)?,
        allowance_x: unsigned(3)?,
        allowance: unsigned(4)?,
        rough,
        finish,
        contour: Contour::default(),
    };
    Ok(Pending {
        removal,
        from_known: from.is_some(),
        saved: modal.clone(),
        line: line.number,
        span: call.name,
        first: None,
        segments: Vec::new(),
        spans: Vec::new(),
    })
}

impl Pending {
    /// A block of the contour, as the dialect read it: a move adds to the contour (the first
    /// move's end is the contour's first point); a block without a move adds nothing.
    pub(super) fn block(&mut self, line: &Line, mv: Option<PlainMove>) -> Result<()> {
        let Some(mv) = mv else {
            return Ok(());
        };
        let span = line.span();
        let Some(from) = self.segments.last().map(|s| s.to).or(self.first) else {
            if matches!(mv.mode, MotionMode::ArcCw | MotionMode::ArcCcw) {
                return Err(contour_error(
                    span,
                    "the contour's first block is its first point: a G0 or G1, not an arc",
                ));
            }
            self.first = Some(mv.to);
            return Ok(());
        };
        if mv.to.distance(from) <= 1e-9 {
            return Ok(());
        }
        let shape = match mv.mode {
            MotionMode::Rapid | MotionMode::Feed => Shape::Line,
            MotionMode::ArcCw | MotionMode::ArcCcw => Shape::Arc {
                centre: mv
                    .centre
                    .ok_or_else(|| contour_error(span, "this arc's words give no centre"))?,
                clockwise: mv.mode == MotionMode::ArcCw,
            },
            _ => {
                return Err(contour_error(
                    span,
                    "a thread move in a stock removal's contour: the contour holds G0, G1, G2 and G3 only (alarm 10930, interpolation type not allowed in stock removal contour)",
                ))
            }
        };
        self.segments.push(Segment {
            to: mv.to,
            shape,
            line: line.number,
        });
        self.spans.push((line.number, span));
        Ok(())
    }

    /// The contour ended (at `end`): the cycle, its moves checked, the modal state as the call
    /// left it and the tool at the cycle's start point.
    pub(super) fn finish(mut self, modal: &mut Modal, end: Span) -> Result<TurningJob> {
        let Some(first) = self.first else {
            return Err(contour_error(end, "CYCLE95's contour has no move"));
        };
        self.removal.contour = Contour {
            start: first,
            segments: std::mem::take(&mut self.segments),
        };
        let at_block = |d: Diagnostic| {
            let span = self
                .spans
                .iter()
                .find(|s| s.0 == d.span.line)
                .map_or(self.span, |s| s.1);
            let hint = match &d.hint {
                // The model's words for FAL's refusal, in the cycle's.
                Some(h) if d.message.contains("allowance along the contour") => format!(
                    "{h}: FALZ and FALX, FAL empty (in the contour of the CYCLE95 at line {})",
                    self.line
                ),
                Some(h) => format!("{h} (in the contour of the CYCLE95 at line {})", self.line),
                None => format!("in the contour of the CYCLE95 at line {}", self.line),
            };
            Diagnostic { span, ..d }.with_hint(hint)
        };
        let start = turning::removal::start_point(&self.removal).map_err(at_block)?;
        if !self.from_known {
            self.removal.from = start;
        }
        let job = TurningJob {
            cycle: Cycle::Removal(self.removal),
            line: self.line,
            span: self.span,
            units: self.saved.units,
            controller: "Sinumerik",
        };
        turning::toolpath(&job).map_err(at_block)?;
        *modal = self.saved;
        modal.position = Position::at(start);
        Ok(job)
    }
}

fn contour_error(span: Span, what: &str) -> Diagnostic {
    Diagnostic::error(Code::Geometry, span, format!("CYCLE95: {what}"))
}
