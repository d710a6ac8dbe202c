//! A small reader for the G-code `threadcut mill` writes: enough to check that a program reproduces
//! its helix (tests, `--check` tools). It understands G0 G1 G2 G3 (I/J incremental, XY plane),
//! G20/G21, G40/G41/G42, F, and comments in parentheses or after `;`. It is not a general G-code
//! reader: `gcode::Reader` is.

use super::CompSide;
use crate::units::Units;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SegKind {
    Rapid,
    Feed,
    /// Centre (absolute, program units) and direction.
    Arc {
        center: [f64; 2],
        cw: bool,
    },
}

/// One move as the control would execute it, program units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    pub kind: SegKind,
    pub from: [f64; 3],
    pub to: [f64; 3],
    pub feed: Option<f64>,
    pub comp: Option<CompSide>,
    /// 1-based line number.
    pub line: usize,
}

impl Segment {
    /// Radius at the start and at the end (arcs).
    pub fn radii(&self) -> Option<(f64, f64)> {
        match self.kind {
            SegKind::Arc { center, .. } => Some((
                (self.from[0] - center[0]).hypot(self.from[1] - center[1]),
                (self.to[0] - center[0]).hypot(self.to[1] - center[1]),
            )),
            _ => None,
        }
    }

    /// Signed sweep of an arc in radians (positive counter-clockwise); a full circle when the end
    /// point equals the start point.
    pub fn sweep(&self) -> Option<f64> {
        let SegKind::Arc { center, cw } = self.kind else {
            return None;
        };
        let a0 = (self.from[1] - center[1]).atan2(self.from[0] - center[0]);
        let a1 = (self.to[1] - center[1]).atan2(self.to[0] - center[0]);
        let tau = std::f64::consts::TAU;
        let mut d = a1 - a0;
        if cw {
            while d >= 0.0 {
                d -= tau;
            }
        } else {
            while d <= 0.0 {
                d += tau;
            }
        }
        // Same end point as start: a full circle.
        if (self.to[0] - self.from[0]).abs() < 1e-12 && (self.to[1] - self.from[1]).abs() < 1e-12 {
            d = if cw { -tau } else { tau };
        }
        Some(d)
    }
}

/// What a program read back contains.
#[derive(Debug, Default)]
pub struct Program {
    pub units: Option<Units>,
    pub segments: Vec<Segment>,
}

/// Reads a program; an error names the line.
pub fn read(text: &str) -> Result<Program, String> {
    let mut prog = Program::default();
    let mut pos: [Option<f64>; 3] = [None; 3];
    let mut motion: Option<u32> = None;
    let mut feed = None;
    let mut comp = None;
    for (n, raw) in text.lines().enumerate() {
        let line_no = n + 1;
        let code = strip_comments(raw);
        let words = words(&code).map_err(|e| format!("line {line_no}: {e}"))?;
        let mut target = pos;
        let mut ij = [None, None];
        let mut has_axis = false;
        for (letter, value) in words {
            match letter {
                'G' => match value as u32 {
                    0..=3 if value.fract() == 0.0 => motion = Some(value as u32),
                    20 => prog.units = Some(Units::Inch),
                    21 => prog.units = Some(Units::Mm),
                    40 => comp = None,
                    41 => comp = Some(CompSide::Left),
                    42 => comp = Some(CompSide::Right),
                    _ => {}
                },
                'X' | 'Y' | 'Z' => {
                    target[(letter as u8 - b'X') as usize] = Some(value);
                    has_axis = true;
                }
                'I' => ij[0] = Some(value),
                'J' => ij[1] = Some(value),
                'F' => feed = Some(value),
                _ => {}
            }
        }
        if !has_axis {
            continue;
        }
        let Some(mode) = motion else {
            return Err(format!("line {line_no}: a move with no motion mode"));
        };
        let known = |p: [Option<f64>; 3]| -> Option<[f64; 3]> { Some([p[0]?, p[1]?, p[2]?]) };
        let to = known(target);
        let from = known(pos);
        pos = target;
        let (Some(from), Some(to)) = (from, to) else {
            if mode >= 2 {
                return Err(format!("line {line_no}: an arc from an unknown position"));
            }
            continue;
        };
        let kind = match mode {
            0 => SegKind::Rapid,
            1 => SegKind::Feed,
            _ => {
                let (Some(i), Some(j)) = (ij[0], ij[1]) else {
                    return Err(format!("line {line_no}: an arc needs I and J"));
                };
                SegKind::Arc {
                    center: [from[0] + i, from[1] + j],
                    cw: mode == 2,
                }
            }
        };
        prog.segments.push(Segment {
            kind,
            from,
            to,
            feed: if mode == 0 { None } else { feed },
            comp,
            line: line_no,
        });
    }
    Ok(prog)
}

fn strip_comments(raw: &str) -> String {
    let mut out = String::with_capacity(raw.len());
    let mut depth = 0;
    for c in raw.chars() {
        match c {
            ';' if depth == 0 => break,
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

fn words(code: &str) -> Result<Vec<(char, f64)>, String> {
    let mut out = Vec::new();
    let b: Vec<char> = code.chars().filter(|c| !c.is_whitespace()).collect();
    let mut i = 0;
    while i < b.len() {
        let letter = b[i].to_ascii_uppercase();
        if !letter.is_ascii_alphabetic() {
            return Err(format!("unexpected `{}`", b[i]));
        }
        i += 1;
        let start = i;
        while i < b.len() && (b[i].is_ascii_digit() || b[i] == '.' || b[i] == '-' || b[i] == '+') {
            i += 1;
        }
        let text: String = b[start..i].iter().collect();
        let value: f64 = text
            .parse()
            .map_err(|_| format!("`{letter}{text}` is not a number"))?;
        out.push((letter, value));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_a_full_helical_circle() {
        let p = read("G21\nG0 X1. Y0 Z0\nG41 D1 G3 X1. Y0. Z1.5 I-1. J0 F100.\n").unwrap();
        assert_eq!(p.units, Some(Units::Mm));
        assert_eq!(
            p.segments.len(),
            1,
            "the first move starts from an unknown position"
        );
        let s = p.segments[0];
        assert_eq!(
            s.kind,
            SegKind::Arc {
                center: [0.0, 0.0],
                cw: false
            }
        );
        assert_eq!(s.comp, Some(CompSide::Left));
        assert_eq!(s.sweep(), Some(std::f64::consts::TAU));
        assert_eq!(s.to[2], 1.5);
    }

    #[test]
    fn refuses_an_arc_without_centre() {
        assert!(read("G0 X1 Y0 Z0\nG2 X1 Y0 Z1\n").is_err());
    }
}
