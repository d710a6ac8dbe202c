//! The converted text of one block inside a macro program's structure, from its runs.
//!
//! Every block is converted exactly as a straight-line program's is (`convert::block`,
//! `convert::write`, cycles through `translate::write_job`), once for each time the program
//! runs it. The runs' texts must have the same words; a number that differs from run to run must
//! follow one of the block's expression words as `a·value + b` (the same value, half of it when
//! the target's X is a radius, a units factor, plus a constant such as a cycle's clearance) on
//! every run, and is written as that expression in the target's syntax. A number that is the same
//! on every run stays a number, or is written as the expression it equals. Anything else has no
//! one text and is refused.

use crate::diag::{Diagnostic, Span};

use super::read::{unsupported, Ex, Val, Word};

/// One run of a line: the values its words had and the text its conversion wrote.
#[derive(Clone, Debug, Default)]
pub struct Run {
    /// Each executed word's column and value.
    pub words: Vec<(u32, f64)>,
    pub text: String,
    /// The line of the call it ran inside (the innermost), if any.
    pub caller: Option<u32>,
}

/// A piece of a block's converted text.
#[derive(Clone, Debug)]
pub enum Piece {
    Text(String),
    /// `a·expression + b`.
    Expr {
        ex: Ex,
        a: f64,
        b: f64,
    },
}

/// The factors a value may take on its way to the target's word.
const FACTORS: [f64; 8] = [1.0, 0.5, 2.0, -1.0, -0.5, -2.0, 25.4, 1.0 / 25.4];

enum Tok {
    Text(String),
    Num(f64, String),
}

/// The text split at its numbers (those that follow a word's letter, outside comments).
fn tokens(text: &str) -> Vec<Tok> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut lit = String::new();
    let mut i = 0;
    let mut comment = None;
    while i < b.len() {
        let c = b[i];
        match (comment, c) {
            (Some(close), _) if c == close => comment = None,
            (None, b'(') => comment = Some(b')'),
            (None, b';') => comment = Some(b'\n'),
            _ => {}
        }
        lit.push(c as char);
        i += 1;
        let starts_number = |k: usize| {
            b.get(k).is_some_and(|d| d.is_ascii_digit() || *d == b'.')
                || (matches!(b.get(k), Some(b'+' | b'-'))
                    && b.get(k + 1)
                        .is_some_and(|d| d.is_ascii_digit() || *d == b'.'))
        };
        if comment.is_none() && c.is_ascii_uppercase() && starts_number(i) {
            let from = i;
            i += 1;
            while b.get(i).is_some_and(|d| d.is_ascii_digit() || *d == b'.') {
                i += 1;
            }
            let raw = &text[from..i];
            out.push(Tok::Text(std::mem::take(&mut lit)));
            out.push(Tok::Num(raw.parse().unwrap_or(f64::NAN), raw.to_string()));
        }
    }
    out.push(Tok::Text(lit));
    out
}

/// The block's text for every run: `runs` (at least one), the block's source words, `tol` half the
/// output resolution.
pub fn template(
    runs: &[Run],
    words: &[Word],
    span: Span,
    number: u32,
    tol: f64,
) -> Result<Vec<Piece>, Diagnostic> {
    let toks: Vec<Vec<Tok>> = runs.iter().map(|r| tokens(&r.text)).collect();
    let first = &toks[0];
    let same_words = toks.iter().all(|t| {
        t.len() == first.len()
            && t.iter().zip(first).all(|p| match p {
                (Tok::Text(a), Tok::Text(b)) => a == b,
                (Tok::Num(..), Tok::Num(..)) => true,
                _ => false,
            })
    });
    if !same_words {
        return Err(differs(span, number, runs));
    }
    // The block's expression words and their value on each run.
    let exprs: Vec<(u8, &Ex, Vec<f64>)> = words
        .iter()
        .filter_map(|w| match &w.value {
            Val::Expr(e) => {
                let values: Option<Vec<f64>> = runs
                    .iter()
                    .map(|r| r.words.iter().find(|v| v.0 == w.span.column).map(|v| v.1))
                    .collect();
                values.map(|v| (w.letter, e, v))
            }
            Val::Lit(_) => None,
        })
        .collect();
    let mut out = Vec::new();
    for (k, tok) in first.iter().enumerate() {
        match tok {
            Tok::Text(t) => out.push(Piece::Text(t.clone())),
            Tok::Num(_, raw) => {
                let values: Vec<f64> = toks
                    .iter()
                    .map(|t| match &t[k] {
                        Tok::Num(v, _) => *v,
                        Tok::Text(_) => f64::NAN,
                    })
                    .collect();
                let letter = match &out.last() {
                    Some(Piece::Text(t)) => t.as_bytes().last().copied().unwrap_or(0),
                    _ => 0,
                };
                match number_piece(&values, letter, &exprs, tol) {
                    Some(p) => out.push(p),
                    None if values.iter().all(|v| (v - values[0]).abs() <= tol) => {
                        out.push(Piece::Text(raw.clone()))
                    }
                    None => return Err(differs(span, number, runs)),
                }
            }
        }
    }
    Ok(out)
}

/// The expression a number follows: on every run `a·value + b` within `tol`.
fn number_piece(
    values: &[f64],
    letter: u8,
    exprs: &[(u8, &Ex, Vec<f64>)],
    tol: f64,
) -> Option<Piece> {
    let constant = values.iter().all(|v| (v - values[0]).abs() <= tol);
    for (l, ex, vs) in exprs {
        let related = *l == letter || (is_lead(*l) && is_lead(letter));
        for a in FACTORS {
            // A number the same on every run is written as an expression only when it is the
            // expression's own value (scaled), in the word of its letter.
            if constant && !(related && (a == 1.0 || (letter == b'X' && (a == 0.5 || a == 2.0)))) {
                continue;
            }
            // The constant: the runs' mean offset (each number rounded to the output's
            // increment), itself rounded.
            let b = if constant {
                0.0
            } else {
                let mean = values.iter().zip(vs).map(|(t, v)| t - a * v).sum::<f64>()
                    / values.len() as f64;
                let b = (mean * 1e4).round() / 1e4;
                if b.abs() <= tol {
                    0.0
                } else {
                    b
                }
            };
            if values
                .iter()
                .zip(vs)
                .all(|(t, v)| (a * v + b - t).abs() <= tol)
            {
                return Some(Piece::Expr {
                    ex: (*ex).clone(),
                    a,
                    b: if b.abs() <= tol { 0.0 } else { b },
                });
            }
        }
    }
    None
}

fn is_lead(l: u8) -> bool {
    matches!(l, b'F' | b'K' | b'E')
}

fn differs(span: Span, number: u32, runs: &[Run]) -> Diagnostic {
    // The first output line in which two runs differ.
    let first: Vec<&str> = runs[0].text.lines().collect();
    let (a, b) = runs
        .iter()
        .skip(1)
        .find_map(|r| {
            let other: Vec<&str> = r.text.lines().collect();
            (0..first.len().max(other.len())).find_map(|k| {
                let (x, y) = (
                    first.get(k).copied().unwrap_or(""),
                    other.get(k).copied().unwrap_or(""),
                );
                (x != y).then_some((x, y))
            })
        })
        .unwrap_or(("", ""));
    unsupported(
        span,
        format!(
            "line {number} converts to different blocks on different runs (`{a}` on one, `{b}` on another), and no expression of its words gives them: the block's conversion depends on values it does not hold (U/W or G91 inside a loop or a subprogram, a cycle's passes computed from several parameters)"
        ),
    )
    .with_hint("--flatten writes the executed program instead")
}
