//! Numbers without a decimal point on a control that reads them as least increments (Fanuc's
//! standard input: `X32` is 0.032 mm on an IS-B control). The reader reads them as the control
//! does; `check` warns once, at the first such axis or lead word, with the value meant if a
//! decimal point was intended and a count of the others.
//!
//! Words looked at: the axis words X, Z, U and W (not on a dwell block, whose X is a time) and the
//! lead F on threading blocks. A feed F on other blocks is left alone: controls differ in how they
//! read a feed written without a point. Zero reads the same either way.

use crate::diag::{Code, Diagnostic, Span};
use crate::gcode::lexer::show;
use crate::gcode::reader::g_code;
use crate::gcode::Line;
use crate::machine::{DecimalPoint, Machine};
use crate::units::Units;

/// The first word without a decimal point: where, what was written, how it is read.
struct First {
    span: Span,
    letter: u8,
    raw: String,
    value: f64,
    units: Units,
    lead: bool,
}

/// The words without a decimal point seen so far.
pub struct DecimalWords {
    /// The least increment in mm and inch programs.
    increment: [f64; 2],
    first: Option<First>,
    others: u32,
    /// Lines of the other words (the first few).
    lines: Vec<u32>,
}

/// Lines listed in the message at most.
const LINES_SHOWN: usize = 6;

impl DecimalWords {
    /// `None` on a control that reads `X32` as 32 units.
    pub fn new(machine: &Machine) -> Option<DecimalWords> {
        (machine.decimal_point == DecimalPoint::LeastIncrement).then(|| DecimalWords {
            increment: [
                machine.resolution(Units::Mm),
                machine.resolution(Units::Inch),
            ],
            first: None,
            others: 0,
            lines: Vec::new(),
        })
    }

    /// A block; `units` are the program's at the block, `thread` says whether its F is a lead.
    pub fn line(&mut self, line: &Line, units: Units, thread: bool) {
        let dwell = line
            .words
            .iter()
            .any(|w| w.letter == b'G' && g_code(w.value) == Some(40));
        for w in line.words {
            let axis = matches!(w.letter, b'X' | b'Z' | b'U' | b'W') && !dwell;
            let lead = w.letter == b'F' && thread;
            if !(axis || lead) || w.has_dot || w.value == 0.0 {
                continue;
            }
            if self.first.is_none() {
                self.first = Some(First {
                    span: w.span,
                    letter: w.letter,
                    raw: show(w.raw(line.text)),
                    value: w.value,
                    units,
                    lead,
                });
            } else {
                self.others += 1;
                if self.lines.last() != Some(&line.number) && self.lines.len() <= LINES_SHOWN {
                    self.lines.push(line.number);
                }
            }
        }
    }

    /// The warning, if any word was written without a decimal point.
    pub fn finding(self) -> Option<Diagnostic> {
        let f = self.first?;
        let inc = self.increment[(f.units == Units::Inch) as usize];
        let unit = f.units.name();
        let read = plain(f.value * inc);
        let what = if f.lead { "a lead of " } else { "" };
        let mut message = format!(
            "{}{} has no decimal point: this control reads it as {what}{read} {unit} ({} least increments of {} {unit}); if {} {unit} was meant, write {}{}. instead.",
            f.letter as char,
            f.raw,
            f.raw.trim_start_matches(['+', '-']),
            plain(inc),
            plain(f.value),
            f.letter as char,
            f.raw
        );
        if self.others > 0 {
            let mut lines: Vec<String> = self
                .lines
                .iter()
                .take(LINES_SHOWN)
                .map(u32::to_string)
                .collect();
            if self.lines.len() > LINES_SHOWN {
                lines.push("…".into());
            }
            message.push_str(&format!(
                " {} more axis or lead word{} without a decimal point (line{} {})",
                self.others,
                if self.others == 1 { " is" } else { "s are" },
                if self.lines.len() == 1 { "" } else { "s" },
                lines.join(", ")
            ));
        }
        Some(
            Diagnostic::warning(Code::DecimalPoint, f.span, message).with_hint(
                "write lengths and leads with a decimal point; if this control is set to read X32 as 32 units, set decimal_point = \"calculator\" in its machine profile",
            ),
        )
    }
}

/// A number as a message writes it: up to 6 decimals, no trailing zeros or point.
fn plain(v: f64) -> String {
    let s = format!("{v:.6}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}
