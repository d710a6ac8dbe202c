//! The thread's start angle in the Fanuc family's words: `Q` in 0.001° without a decimal point, on
//! a plain thread move, G92 and the one-block G76.

use crate::diag::{Code, Diagnostic, Result};
use crate::gcode::Word;
use crate::post::{AngleUnit, StartAngleWord};

/// `Q` on a plain thread move (`G32 … Q180000`): the start angle of the run it begins, in 0.001°
/// without a decimal point, for its own block only (not modal).
pub const START_ANGLE_Q: StartAngleWord = StartAngleWord {
    name: "Q",
    unit: AngleUnit::Millidegrees,
    modal: false,
};

/// `Q`, the thread's start angle: a count of 0.001° without a decimal point, 0 to 360000 (Fanuc:
/// "Angle for shifting the threading start angle (Increment: 0.001 degrees, Valid setting range: 0
/// to 360 degrees)"; Haas: "Thread Start Angle (Do not use a decimal point)"). In degrees, below 360.
pub fn read(q: &Word) -> Result<f64> {
    if q.has_dot || q.value.fract() != 0.0 {
        return Err(Diagnostic::error(
            Code::Syntax,
            q.span,
            "Q (the thread's start angle) is written in 0.001° without a decimal point",
        )
        .with_hint("Q180000 is 180°; a decimal point is not allowed"));
    }
    if !(0.0..=360_000.0).contains(&q.value) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            q.span,
            format!(
                "Q{}: the start angle is 0 to 360000 (0.001°: 0 to 360°)",
                q.value
            ),
        ));
    }
    Ok((q.value / 1000.0) % 360.0)
}
