//! Posting a CL file to a controller: every THREAD/ON cycle through
//! [`crate::translate::write_job`] (the target's native cycle when reading it back reproduces the
//! toolpath, plain moves otherwise), every other move as a plain block in the target's
//! [`crate::post::Format`]. The program states at its start what it relies on — its units,
//! absolute distances, X on diameter or radius, the ZX plane, feed per revolution and rpm — in the
//! target's words where the target has them ([`Lexicon`]), never the control's power-on state;
//! each FEDRAT that changes the feed mode writes the mode's code. Nothing here knows a controller:
//! the target's dialect, lexicon and profile do.

use std::io::{BufRead, Write};

use crate::diag::{Code, Diagnostic};
use crate::dialect;
use crate::dialect::lexicon::{Code as LexCode, Function, Meanings, Plane};
use crate::machine::Machine;
use crate::post::{self, Format};
use crate::program::{Error, Summary};
use crate::thread::Job;
use crate::toolpath::{Motion, MotionKind, Toolpath};
use crate::translate;
use crate::units::{Pos, Units};

use super::{run, Event};

/// Writes the program for `target`. Numbers are written in the target profile's units, whatever
/// the CL units, and the program's first block states them ([`header`]).
pub fn write<R: BufRead>(
    mut input: R,
    out: &mut dyn Write,
    target: &Machine,
) -> Result<Summary, Error> {
    // The posted program ends its lines as the CL file does (CRLF in, CRLF out).
    let ending = crate::eol::LineEnding::peek(&mut input)?;
    let out = &mut crate::eol::Writer::new(out, ending);
    let d = dialect::open(target).map_err(Error::Setup)?;
    let format = d.format();
    let lexicon = d.meanings();
    let units = target.units;
    let mut at: Option<Pos> = None;
    // The feed (target units per minute or per revolution) and whether the F register holds it.
    let mut feed: Option<(f64, bool)> = None;
    let mut f_current = false;
    // The feed mode stated: per revolution at the start.
    let mut per_rev_mode = true;
    if let Some(c) = format.comment(&format!(
        "threadcut post for {}, {}, feed per revolution",
        target.name,
        units.name()
    )) {
        writeln!(out, "{c}")?;
    }
    if let Some(h) = header(&lexicon, target) {
        writeln!(out, "{h}")?;
    }
    let m_code = |f: Function| -> std::result::Result<String, Error> {
        lexicon.code(f).map(LexCode::text).ok_or_else(|| {
            Error::Setup(format!(
                "{} has no code for the {} in threadcut's lexicon",
                target.name,
                f.describe()
            ))
        })
    };
    run(input, |interp, ev| {
        match ev {
            Event::Comment(text) => {
                if let Some(c) = format.comment(text) {
                    writeln!(out, "{c}")?;
                }
            }
            Event::Feed { value, per_rev } => {
                let v = units.from_mm(interp.units().to_mm(value));
                feed = Some((v, per_rev));
                f_current = false;
                if per_rev != per_rev_mode {
                    // Every built-in lathe control has both modes; one without would need F
                    // converted with the spindle speed, which a CL file need not hold constant.
                    let mode = if per_rev {
                        Function::FeedPerRevolution
                    } else {
                        Function::FeedPerMinute
                    };
                    writeln!(out, "{}", m_code(mode)?)?;
                    per_rev_mode = per_rev;
                }
                if let Some(c) = format.comment(&format!(
                    "FEDRAT: F{} {} per {}",
                    post::number(v, 4, false),
                    units.name(),
                    if per_rev { "revolution" } else { "minute" }
                )) {
                    writeln!(out, "{c}")?;
                }
            }
            Event::Spindle(Some((rpm, cw))) => {
                writeln!(
                    out,
                    "S{} {}",
                    post::number(rpm, 0, false).trim_end_matches('.'),
                    m_code(if cw {
                        Function::SpindleCw
                    } else {
                        Function::SpindleCcw
                    })?
                )?;
            }
            Event::Spindle(None) => writeln!(out, "{}", m_code(Function::SpindleStop)?)?,
            Event::End => writeln!(out, "{}", m_code(Function::EndRewind)?)?,
            Event::Move(m) => {
                let line = plain_move(&format, units, at, &m)?;
                match m.kind {
                    MotionKind::Feed => {
                        let Some((f, _)) = feed else {
                            return Err(Diagnostic::error(
                                Code::MissingWord,
                                crate::diag::Span::new(0, 0, m.line, 1),
                                "GOTO at feed rate before any FEDRAT",
                            )
                            .with_hint("write FEDRAT/… before the first feed move, or RAPID before a rapid GOTO")
                            .into());
                        };
                        let mut line = line;
                        if !f_current {
                            line.push_str(" F");
                            line.push_str(&post::number(f, 4, false));
                            f_current = true;
                        }
                        writeln!(out, "{line}")?;
                    }
                    MotionKind::Thread { .. } => {
                        f_current = false; // F now holds a lead
                        writeln!(out, "{line}")?;
                    }
                    MotionKind::Rapid => writeln!(out, "{line}")?,
                    // APT/CL motion is GOTOs: the reader makes no arc.
                    MotionKind::Arc { .. } => unreachable!("an APT program has no arc move"),
                }
                at = Some(m.to);
            }
            Event::Cycle(job) => {
                let mut job = *job;
                let rule = translate::DriftRule::new(job.units);
                job.units = units;
                check_lead(&format, &job, target)?;
                if let Some(c) =
                    format.comment(&format!("THREAD/ON … THREAD/OFF of line {}", job.line))
                {
                    writeln!(out, "{c}")?;
                }
                if at != Some(job.start) {
                    // The cycle starts at the initial point: make sure the tool is there.
                    let m = Motion {
                        kind: MotionKind::Rapid,
                        to: job.start,
                        pass: 0,
                        line: job.line,
                    };
                    writeln!(out, "{}", plain_move(&format, units, at, &m)?)?;
                }
                translate::write_job_with(out, target, &job, &rule)?;
                f_current = false;
                at = Some(job.start);
            }
        }
        Ok(())
    })
}

/// The block that states what a posted program relies on, in the target's codes: its units (the
/// profile's), absolute distances, X on diameter or radius (the profile's), the ZX plane, feed per
/// revolution and the spindle speed in rpm. `None` for a control with none of these codes.
pub fn header(lexicon: &Meanings, target: &Machine) -> Option<String> {
    let states = [
        Function::Units(target.units),
        Function::Absolute,
        if target.diameter_x {
            Function::Diameter
        } else {
            Function::Radius
        },
        Function::Plane(Plane::Zx),
        Function::FeedPerRevolution,
        Function::Rpm,
    ];
    let codes: Vec<String> = states
        .iter()
        .filter_map(|f| lexicon.code(*f))
        .map(LexCode::text)
        .collect();
    (!codes.is_empty()).then(|| codes.join(" "))
}

/// One move as a block in the target's format (rounded once, from the absolute position).
fn plain_move(
    format: &Format,
    units: Units,
    from: Option<Pos>,
    m: &Motion,
) -> Result<String, Error> {
    if let MotionKind::Thread { dlead, .. } = m.kind {
        if dlead != 0.0 && format.variable_thread.is_none() {
            return Err(no_variable_lead(crate::diag::Span::new(0, 0, m.line, 1)).into());
        }
    }
    let path = Toolpath {
        start: from.unwrap_or(m.to),
        motions: vec![*m],
    };
    let mut buf = Vec::with_capacity(48);
    post::write_moves(&mut buf, format, units, &path)?;
    while buf.last() == Some(&b'\n') {
        buf.pop();
    }
    Ok(String::from_utf8_lossy(&buf).into_owned())
}

fn no_variable_lead(span: crate::diag::Span) -> Diagnostic {
    Diagnostic::error(
        Code::Unsupported,
        span,
        "the target has no variable-lead thread move in threadcut: INCR/DECR cannot be posted to it",
    )
    .with_hint("post to a controller with a variable-lead move (G34), or cut a constant lead")
}

/// A variable lead needs the target's native cycle or its variable-lead move: plain constant-lead
/// moves would cut the wrong thread.
fn check_lead(format: &Format, job: &Job, target: &Machine) -> Result<(), Error> {
    if job.lead.dlead == 0.0 || format.variable_thread.is_some() {
        return Ok(());
    }
    let d = dialect::open(target).map_err(Error::Setup)?;
    let path = crate::toolpath::build(job)?;
    let native = translate::native(target, d.as_ref(), job, &path).is_ok();
    if native {
        return Ok(());
    }
    Err(no_variable_lead(job.span).into())
}
