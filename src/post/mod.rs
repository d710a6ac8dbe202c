//! Writing: numbers rounded once from absolute values, plain G-code moves in a controller's format,
//! and JSON lines. Readers never write and writers never read the source.

use std::io::{self, Write};

use crate::machine::{CommentStyle, Machine};
use crate::toolpath::{Motion, MotionKind, Toolpath};
use crate::units::Units;

/// How a controller writes plain moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Format {
    pub rapid: &'static str,
    pub feed: &'static str,
    /// The synchronised single move (`G32`, `G33`).
    pub thread: &'static str,
    /// The word that carries the lead on a thread move (`F` or `K`).
    pub lead_letter: char,
    /// The variable-lead thread move and the word of its lead change per revolution (Fanuc
    /// `G34 … K`), if the controller has one. Without it a job with a variable lead cannot be
    /// written as plain moves: callers must refuse it (the APT post does).
    pub variable_thread: Option<(&'static str, char)>,
    pub diameter_x: bool,
    /// Decimals of X and Z in mm and in inch programs.
    pub decimals: [u32; 2],
    /// Decimals of the lead word in mm and in inch programs.
    pub lead_decimals: [u32; 2],
    pub trailing_zeros: bool,
    pub comment: CommentStyle,
}

impl Format {
    /// The common lathe format: positions at the machine's input resolution, leads to 0.0001 mm /
    /// 0.00001 inch (the GSK and Fanuc F ranges).
    pub fn lathe(machine: &Machine, thread: &'static str, lead_letter: char) -> Format {
        Format {
            rapid: "G0",
            feed: "G1",
            thread,
            lead_letter,
            variable_thread: None,
            diameter_x: machine.diameter_x,
            decimals: [machine.decimals(Units::Mm), machine.decimals(Units::Inch)],
            lead_decimals: [4, 5],
            trailing_zeros: machine.output.trailing_zeros,
            comment: machine.output.comment,
        }
    }

    fn digits(&self, units: Units) -> u32 {
        self.decimals[(units == Units::Inch) as usize]
    }

    fn lead_digits(&self, units: Units) -> u32 {
        self.lead_decimals[(units == Units::Inch) as usize]
    }

    /// The X a program in this format writes for a radius in mm.
    pub fn x_word(&self, radius_mm: f64, units: Units) -> f64 {
        let v = units.from_mm(radius_mm);
        if self.diameter_x {
            v * 2.0
        } else {
            v
        }
    }

    /// A comment line, or nothing when the profile writes none.
    pub fn comment(&self, text: &str) -> Option<String> {
        let clean: String = text.chars().filter(|c| !matches!(c, '(' | ')')).collect();
        match self.comment {
            CommentStyle::Paren => Some(format!("({clean})")),
            CommentStyle::Semicolon => Some(format!("; {clean}")),
            CommentStyle::None => None,
        }
    }
}

/// Formats `value` rounded to `decimals`, always with a decimal point (`10.`, `-0.5`), never with an
/// exponent, never `-0.`. Rounding happens once, here, from the absolute value.
pub fn number(value: f64, decimals: u32, trailing_zeros: bool) -> String {
    debug_assert!(
        value.is_finite(),
        "non-finite values are rejected before writing"
    );
    let scale = 10f64.powi(decimals as i32);
    let units = (value * scale).round();
    let negative = units < 0.0;
    let magnitude = units.abs() as u128;
    let divisor = 10u128.pow(decimals);
    let whole = magnitude / divisor;
    let frac = magnitude % divisor;
    let mut s = String::with_capacity(16);
    if negative && magnitude != 0 {
        s.push('-');
    }
    s.push_str(&whole.to_string());
    s.push('.');
    if decimals > 0 {
        let f = format!("{:0width$}", frac, width = decimals as usize);
        let f = if trailing_zeros {
            f.as_str()
        } else {
            f.trim_end_matches('0')
        };
        s.push_str(f);
    }
    s
}

/// Formats `value` rounded once to a multiple of `step` (a controller resolution such as OmniTurn's
/// .00005"), with as many decimals as the step needs.
pub fn number_on_grid(value: f64, step: f64, trailing_zeros: bool) -> String {
    let decimals = (0..=9)
        .find(|&d| {
            let scaled = step * 10f64.powi(d);
            (scaled - scaled.round()).abs() < 1e-9
        })
        .unwrap_or(9) as u32;
    number((value / step).round() * step, decimals, trailing_zeros)
}

/// Whether `format` can write `job`'s moves as plain blocks: a lead that changes every revolution
/// needs the controller's variable-lead move.
pub fn expressible(
    format: &Format,
    job: &crate::thread::Job,
) -> Result<(), crate::diag::Diagnostic> {
    if job.lead.dlead != 0.0 && format.variable_thread.is_none() {
        return Err(crate::diag::Diagnostic::error(
            crate::diag::Code::Unsupported,
            job.span,
            format!(
                "the lead changes by {} mm every revolution, and this controller has no variable-lead move in threadcut",
                job.lead.dlead
            ),
        )
        .with_hint("choose a controller with a variable-lead thread move (G34)"));
    }
    Ok(())
}

/// A value about to be written: a non-finite number is refused here, where numbers are written, so
/// that no `NaN` or `inf` can reach a program whatever happened upstream.
pub fn finite(value: f64) -> io::Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("refusing to write the non-finite value {value}"),
        ))
    }
}

/// Writes the moves of a toolpath as plain blocks, one per motion.
pub fn write_moves(
    out: &mut dyn Write,
    format: &Format,
    units: Units,
    path: &Toolpath,
) -> io::Result<()> {
    let nd = format.digits(units);
    let mut line = String::with_capacity(48);
    for m in &path.motions {
        line.clear();
        let (code, lead, dlead) = match m.kind {
            MotionKind::Rapid => (format.rapid, None, None),
            MotionKind::Feed => (format.feed, None, None),
            MotionKind::Thread { lead, dlead, .. } => match format.variable_thread {
                Some((code, letter)) if dlead != 0.0 => (code, Some(lead), Some((letter, dlead))),
                // Never a variable lead as a constant one: callers check first (`expressible`);
                // this is the last guard.
                None if dlead != 0.0 => {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidData,
                        "refusing to write a variable lead as a constant-lead move",
                    ))
                }
                _ => (format.thread, Some(lead), None),
            },
        };
        line.push_str(code);
        line.push_str(" X");
        line.push_str(&number(
            finite(format.x_word(m.to.x, units))?,
            nd,
            format.trailing_zeros,
        ));
        line.push_str(" Z");
        line.push_str(&number(
            finite(units.from_mm(m.to.z))?,
            nd,
            format.trailing_zeros,
        ));
        if let Some(lead) = lead {
            line.push(' ');
            line.push(format.lead_letter);
            line.push_str(&number(
                finite(units.from_mm(lead))?,
                format.lead_digits(units),
                format.trailing_zeros,
            ));
        }
        if let Some((letter, dlead)) = dlead {
            line.push(' ');
            line.push(letter);
            line.push_str(&number(
                units.from_mm(dlead),
                format.lead_digits(units),
                format.trailing_zeros,
            ));
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// One motion as a JSON object in program units, X as a radius:
/// `{"kind":"thread","x":…,"z":…,"lead":…,"pass":n,"line":l}` (`"dlead"` after `"lead"` when the
/// lead varies).
pub fn motion_json(m: &Motion, units: Units) -> String {
    let x = units.from_mm(m.to.x);
    let z = units.from_mm(m.to.z);
    match m.kind {
        MotionKind::Rapid | MotionKind::Feed => format!(
            r#"{{"kind":"{}","x":{},"z":{},"pass":{},"line":{}}}"#,
            if m.kind == MotionKind::Rapid {
                "rapid"
            } else {
                "feed"
            },
            json_num(x),
            json_num(z),
            m.pass,
            m.line
        ),
        // A variable lead adds `"dlead"` (change of lead per revolution, at the move's start lead).
        MotionKind::Thread { lead, dlead, .. } if dlead != 0.0 => format!(
            r#"{{"kind":"thread","x":{},"z":{},"lead":{},"dlead":{},"pass":{},"line":{}}}"#,
            json_num(x),
            json_num(z),
            json_num(units.from_mm(lead)),
            json_num(units.from_mm(dlead)),
            m.pass,
            m.line
        ),
        MotionKind::Thread { lead, .. } => format!(
            r#"{{"kind":"thread","x":{},"z":{},"lead":{},"pass":{},"line":{}}}"#,
            json_num(x),
            json_num(z),
            json_num(units.from_mm(lead)),
            m.pass,
            m.line
        ),
    }
}

/// Shortest round-trip text of a finite f64 (serde_json's), `0` for negative zero.
pub fn json_num(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    serde_json::Number::from_f64(v).map_or_else(|| "null".to_string(), |n| n.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_once_and_keep_the_point() {
        assert_eq!(number(10.0, 3, false), "10.");
        assert_eq!(number(62.4, 3, false), "62.4");
        assert_eq!(number(62.4, 3, true), "62.400");
        assert_eq!(number(-0.0004, 3, false), "0.");
        assert_eq!(number(0.0005, 3, false), "0.001");
        assert_eq!(number(-12.5, 0, false), "-13.");
        assert_eq!(number(1e9, 4, false), "1000000000.");
    }

    #[test]
    fn grid_numbers_round_to_the_step() {
        assert_eq!(number_on_grid(0.2200294, 0.00005, false), "0.22005");
        assert_eq!(number_on_grid(0.2200294, 0.00025, false), "0.22");
        assert_eq!(number_on_grid(0.33333, 0.00025, false), "0.33325");
        assert_eq!(number_on_grid(0.33333, 0.0005, true), "0.3335");
        assert_eq!(number_on_grid(-0.5, 0.00005, false), "-0.5");
    }

    #[test]
    fn json_numbers_are_plain() {
        assert_eq!(json_num(-0.0), "0.0");
        assert_eq!(json_num(1.5), "1.5");
    }
}
