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
    pub diameter_x: bool,
    /// Decimals of X and Z in mm and in inch programs.
    pub decimals: [u32; 2],
    /// Decimals of the lead word in mm and in inch programs.
    pub lead_decimals: [u32; 2],
    pub trailing_zeros: bool,
    pub comment: CommentStyle,
    /// The lead word is the travel per revolution along the move's path (LinuxCNC's `G33 K`), not
    /// along its longer axis (Fanuc's `G32 F`); the writer converts the model's lead.
    pub lead_along_path: bool,
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
            diameter_x: machine.diameter_x,
            decimals: [machine.decimals(Units::Mm), machine.decimals(Units::Inch)],
            lead_decimals: [4, 5],
            trailing_zeros: machine.output.trailing_zeros,
            comment: machine.output.comment,
            lead_along_path: false,
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

/// Writes the moves of a toolpath as plain blocks, one per motion.
pub fn write_moves(
    out: &mut dyn Write,
    format: &Format,
    units: Units,
    path: &Toolpath,
) -> io::Result<()> {
    let nd = format.digits(units);
    let mut line = String::with_capacity(48);
    for (from, m) in path.segments() {
        line.clear();
        let (code, lead) = match m.kind {
            MotionKind::Rapid => (format.rapid, None),
            MotionKind::Feed => (format.feed, None),
            MotionKind::Thread { lead, .. } => (format.thread, Some(lead)),
        };
        line.push_str(code);
        line.push_str(" X");
        line.push_str(&number(
            format.x_word(m.to.x, units),
            nd,
            format.trailing_zeros,
        ));
        line.push_str(" Z");
        line.push_str(&number(units.from_mm(m.to.z), nd, format.trailing_zeros));
        if let Some(lead) = lead {
            let lead = if format.lead_along_path {
                path_lead(lead, m.to.minus(from))
            } else {
                lead
            };
            line.push(' ');
            line.push(format.lead_letter);
            line.push_str(&number(
                units.from_mm(lead),
                format.lead_digits(units),
                format.trailing_zeros,
            ));
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
    }
    Ok(())
}

/// The travel per revolution along a move's path, from the lead along its longer axis (the model's
/// convention, [`crate::toolpath::lead_along_long_axis`]).
pub fn path_lead(lead: f64, d: crate::units::Vec2) -> f64 {
    let long = d.x.abs().max(d.z.abs());
    if long == 0.0 {
        lead
    } else {
        lead * d.x.hypot(d.z) / long
    }
}

/// The lead along a move's longer axis, from the travel per revolution along its path.
pub fn long_axis_lead(path_lead: f64, d: crate::units::Vec2) -> f64 {
    let len = d.x.hypot(d.z);
    if len == 0.0 {
        path_lead
    } else {
        path_lead * d.x.abs().max(d.z.abs()) / len
    }
}

/// One motion as a JSON object in program units, X as a radius:
/// `{"kind":"thread","x":…,"z":…,"lead":…,"pass":n,"line":l}`.
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
    fn json_numbers_are_plain() {
        assert_eq!(json_num(-0.0), "0.0");
        assert_eq!(json_num(1.5), "1.5");
    }
}
