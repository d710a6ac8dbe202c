//! The checks of one thread: a cycle's, or one written as plain moves (docs/simulation.md, the
//! table of `threadcut check`). Each check reports once per thread, naming the passes it concerns.

use crate::diag::{Code, Diagnostic, Severity};
use crate::machine::Machine;
use crate::sim::{groove, tip_in_mm, GrooveForm, Tool};
use crate::thread::{Exit, Side};
use crate::threads::{Origin, Thread};
use crate::toolpath::MotionKind;
use crate::units::{Resolution, Tolerance};

use super::blank::{Blank, Known};
use super::measure::{self, Judging};
use super::spindle::SpindleSpeed;
use super::standard;
use super::{length, passes_list, Note, Options};

/// The usual servo time constant of a lathe's Z axis (s): Fanuc's manuals quote 0.033 s.
pub const DEFAULT_SERVO_TIME_CONSTANT: f64 = 0.033;
/// The lead error accepted where the thread starts (1 %).
pub const DEFAULT_LEAD_ERROR: f64 = 0.01;

/// Everything `check` finds about one thread, and what it assumed.
pub fn check_thread(
    t: &Thread,
    machine: &Machine,
    opts: &Options,
    spindle: &impl SpindleSpeed,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let job = &t.job;
    // Programmed values are compared at the program's resolution (docs/reliability.md).
    let res = machine.program_resolution(job.units, t.diameter_x);
    length_checks(t, machine, res, out);
    let blank = Blank::new(
        job,
        t.path.start,
        opts.stock_diameter,
        opts.stock_start,
        t.crest_known(),
        res,
    );
    if blank.face == Known::Given && !blank.z_tol.lt(blank.before_face(blank.z_end), 0.0) {
        let show = |mm: f64| length(job.units, mm);
        out.push(
            Diagnostic::error(
                Code::Geometry,
                job.span,
                format!(
                    "the blank's face (Z{}) lies at or past the thread's end (Z{}): there is nothing to cut",
                    show(blank.z_face),
                    show(blank.z_end)
                ),
            )
            .with_hint("--stock-start names the face on the side where the thread starts"),
        );
        return;
    }
    section_checks(t, opts, &blank, out, notes);
    rapid_checks(t, &blank, out);
    spindle_checks(t, machine, &blank, spindle, out, notes);
    if let Some(thread) = &opts.thread {
        judge(t, machine, opts, thread, &blank, out, notes);
    }
    if let Some(what) = blank.assumptions() {
        notes.push(Note::new(job.span, format!("blank: {what}")));
    }
}

/// The lead against the controller's maximum, the thread against one lead, a cycle's chamfer
/// against the thread.
fn length_checks(t: &Thread, machine: &Machine, res: Resolution, out: &mut Vec<Diagnostic>) {
    let job = &t.job;
    let span = job.span;
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let g = &job.geometry;
    let axial = g.side.along(g.travel()).abs();
    let lead = job.lead.lead;
    let tol = res.length();
    if let Some(max) = machine.limits.max_lead_mm {
        if tol.gt(lead, max) {
            out.push(
                Diagnostic::error(
                    Code::LeadLimit,
                    span,
                    format!(
                        "the lead {} is beyond this controller's maximum {} ({})",
                        show(lead),
                        show(max),
                        units.name()
                    ),
                )
                .with_hint("check F: a lead written without its decimal point?"),
            );
        }
    }
    if tol.lt(axial, lead) {
        out.push(
            Diagnostic::error(
                Code::Geometry,
                span,
                format!(
                    "the thread is {} long, shorter than one lead ({}): the tool turns less than one revolution along it",
                    show(axial),
                    show(lead)
                ),
            )
            .with_hint("check the thread's end Z and the lead"),
        );
    }
    if let Exit::PullOut { start_before, .. } = job.exit {
        if !tol.lt(start_before, axial) && t.origin == Origin::Cycle {
            out.push(Diagnostic::error(
                Code::Geometry,
                span,
                format!(
                    "the chamfer (tail-out) starts {} before the thread's end, but the thread is only {} long",
                    show(start_before),
                    show(axial)
                ),
            ));
        }
    }
}

/// The simulated section: depth and form. The tool is the cycle's angle (a 0° cycle, a radial
/// infeed, is cut with a tool of the thread's angle: the standard's, else 60°) with the tip given.
fn section_checks(
    t: &Thread,
    opts: &Options,
    blank: &Blank,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let job = &t.job;
    let angle = if job.tool_angle_deg > 0.0 {
        job.tool_angle_deg
    } else {
        let a = opts.thread.as_ref().map_or(60.0, measure::angle_of);
        notes.push(Note::new(
            job.span,
            format!(
                "the cycle's tool angle is 0° (a radial infeed): the section is cut with a {}° tool",
                super::number(a)
            ),
        ));
        a
    };
    let tool = Tool {
        angle_deg: angle,
        tip: tip_in_mm(opts.tip.unwrap_or(crate::sim::Tip::Sharp), job.units),
    };
    let with_angle = crate::thread::Job {
        tool_angle_deg: angle,
        ..job.clone()
    };
    match groove(&with_angle, &t.passes, &tool, blank.stock_above) {
        Ok(groove) => form_checks(t, blank.z_tol, blank.x_tol, &groove, out),
        // The machine can still run the cycle; only the depth and form checks are lost.
        Err(e) => out.push(Diagnostic {
            code: Code::Form,
            severity: Severity::Warning,
            message: format!(
                "the groove cannot be simulated, so its depth and form are not checked: {}",
                e.message
            ),
            ..e
        }),
    }
}

/// The thread against the standard named with `--thread`, on the side the program cuts.
fn judge(
    t: &Thread,
    machine: &Machine,
    opts: &Options,
    thread: &crate::thread::standard::StandardThread,
    blank: &Blank,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let units = t.job.units;
    let face = match blank.face {
        Known::Given => Some(measure::Face {
            z: blank.z_face,
            given: true,
        }),
        Known::Assumed => Some(measure::Face {
            z: blank.z_face,
            given: false,
        }),
        Known::Unknown => None,
    };
    let surface = match t.job.geometry.side {
        Side::Internal => crate::thread::standard::Surface::Internal,
        _ => crate::thread::standard::Surface::External,
    };
    match measure::target(thread, surface) {
        Ok(target) => standard::judge(
            t,
            &Judging {
                target: &target,
                tip: opts.tip.map(|tip| tip_in_mm(tip, units)),
                resolution: machine
                    .program_resolution(units, t.diameter_x)
                    .increment_mm(),
                face,
                wire: opts.wire.map(|w| thread.units.to_mm(w)),
            },
            out,
            notes,
        ),
        Err(why) => out.push(
            Diagnostic::error(Code::OutOfClass, t.job.span, why)
                .with_hint("name the class of the side the program cuts (6g/6H, 2A/2B)"),
        ),
    }
}

/// The groove's depth and form; a ridge or a size error within one increment of the program's
/// resolution (`length` for heights, `x` for X's convention) is not there.
fn form_checks(
    t: &Thread,
    length_tol: Tolerance,
    x_tol: Tolerance,
    g: &GrooveForm,
    out: &mut Vec<Diagnostic>,
) {
    let job = &t.job;
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    // A thread written as moves has no stated depth: its deepest pass is its depth.
    if t.origin == Origin::Cycle
        && g.depth_reached < g.depth_target - crate::thread::plan::DEPTH_TOLERANCE
    {
        out.push(Diagnostic::error(
            Code::DepthNotReached,
            job.span,
            format!(
                "the passes reach {} deep, the thread needs {} (radius)",
                show(g.depth_reached),
                show(g.depth_target)
            ),
        ));
    }
    if length_tol.gt(g.ridge, 0.0) {
        out.push(
            Diagnostic::warning(
                Code::Form,
                job.span,
                format!(
                    "a ridge {} high is left standing between passes; the groove's centre is {} deep",
                    show(g.ridge),
                    show(g.depth_at_axis)
                ),
            )
            .with_hint("finish on the groove's axis, or add a finishing pass there"),
        );
    }
    // The pitch line is measured from the crest: without it there is none.
    if !t.crest_known() {
        return;
    }
    if let Some(e) = g.pitch_diameter_error {
        // `e` is a diameter; X's tolerance is a radius.
        if x_tol.gt((e / 2.0).abs(), 0.0) {
            out.push(
                Diagnostic::warning(
                    Code::Form,
                    job.span,
                    format!(
                        "the groove is cut {} at the pitch line: the pitch diameter comes out {} {} (diameter)",
                        if (e < 0.0) == (job.geometry.side == Side::External) { "wide" } else { "narrow" },
                        show(e.abs()),
                        if e < 0.0 { "under size" } else { "over size" }
                    ),
                )
                .with_hint("the passes do not finish on one groove axis (alternating infeed finishing off the axis?)"),
            );
        }
    }
}

fn rapid_checks(t: &Thread, blank: &Blank, out: &mut Vec<Diagnostic>) {
    let units = t.job.units;
    let x_word = |x: f64| length(units, x);
    let bad: Vec<_> = t
        .path
        .segments()
        .filter(|(from, m)| m.kind == MotionKind::Rapid && blank.entered_by(*from, m.to))
        .collect();
    let Some((from, m)) = bad.first() else {
        return;
    };
    let mut passes: Vec<u32> = bad.iter().map(|(_, m)| m.pass).collect();
    passes.dedup();
    let more = bad.len() - 1;
    let given = blank.given();
    let message = format!(
        "{}: a rapid move from (radius {}, Z{}) to (radius {}, Z{}) runs through the blank{}{}",
        passes_list(&passes),
        x_word(from.x),
        x_word(from.z),
        x_word(m.to.x),
        x_word(m.to.z),
        if more > 0 {
            format!(
                " ({more} more rapid move{} too)",
                if more == 1 { " does" } else { "s do" }
            )
        } else {
            String::new()
        },
        match blank.assumptions() {
            Some(a) if !given => format!(", with {a}"),
            _ => String::new(),
        }
    );
    let hint = if given {
        "start the cycle clear of the part: its start point must lie outside the blank, and flank infeed shifts each pass's start along Z"
    } else {
        "start the thread clear of the part (flank infeed shifts each pass's start along Z); --stock-start and --stock-diameter give the blank when it is not what check assumed"
    };
    let span = t.pass_span(m.pass);
    out.push(if given {
        Diagnostic::error(Code::Collision, span, message).with_hint(hint)
    } else {
        Diagnostic::warning(Code::CollisionAssumed, span, message).with_hint(hint)
    });
}

/// The synchronised moves of the path: (from, motion, lead), in order.
type Synced<'a> = Vec<(crate::units::Pos, &'a crate::toolpath::Motion, f64)>;

fn spindle_checks(
    t: &Thread,
    machine: &Machine,
    blank: &Blank,
    spindle: &impl SpindleSpeed,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let job = &t.job;
    let units = job.units;
    let threads: Synced = t
        .path
        .segments()
        .filter_map(|(from, m)| match m.kind {
            MotionKind::Thread { lead, .. } => Some((from, m, lead)),
            _ => None,
        })
        .collect();
    let Some(&(first_from, _, _)) = threads.first() else {
        return;
    };
    if spindle.rpm_at(units, first_from.x).is_none() {
        out.push(
            Diagnostic::warning(
                Code::Spindle,
                job.span,
                "no spindle speed (S) is programmed before this thread: the synchronised feed, the run-up and the run-out were not checked",
            )
            .with_hint("program the spindle speed (G97 S..) before the thread"),
        );
        return;
    }
    if spindle.css() {
        out.push(
            Diagnostic::warning(
                Code::Spindle,
                job.span,
                "the thread is cut under constant surface speed (G96): the spindle speed changes with X from pass to pass",
            )
            .with_hint("cut threads at a constant spindle speed: G97 S.."),
        );
    }
    feed_check(t, machine, &threads, spindle, out);
    let t1 = machine
        .limits
        .servo_time_constant_s
        .unwrap_or(DEFAULT_SERVO_TIME_CONSTANT);
    let a = machine
        .limits
        .thread_lead_error
        .unwrap_or(DEFAULT_LEAD_ERROR);
    run_up(t, blank, &threads, spindle, t1, a, out, notes);
    run_out(t, blank.z_tol, &threads, spindle, t1, out);
}

/// Synchronised feed: lead × rpm along each move's long axis.
fn feed_check(
    t: &Thread,
    machine: &Machine,
    threads: &Synced,
    spindle: &impl SpindleSpeed,
    out: &mut Vec<Diagnostic>,
) {
    let Some(max) = machine.limits.max_feed_mm_per_min else {
        return;
    };
    let units = t.job.units;
    let worst = threads
        .iter()
        .filter_map(|&(from, m, lead)| {
            let r = from.x.abs().min(m.to.x.abs());
            spindle
                .rpm_at(units, r)
                .map(|rpm| (lead * rpm, rpm, m.pass))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((feed, rpm, pass)) = worst {
        if feed > max {
            out.push(
                Diagnostic::error(
                    Code::FeedLimit,
                    t.pass_span(pass),
                    format!(
                        "pass {pass}: the synchronised feed is {:.0} mm/min (lead {} × {:.0} rpm), above the machine's {:.0} mm/min",
                        feed,
                        length(units, feed / rpm),
                        rpm,
                        max
                    ),
                )
                .with_hint(format!(
                    "lower the spindle speed to {:.0} rpm or less",
                    (max / (feed / rpm)).floor()
                )),
            );
        }
    }
}

/// Run-up: each pass's synchronised motion starts from rest; its lead is within the accepted error
/// only after δ1 = T1·V·(−1 − ln a), V = lead·rpm/60 (Fanuc's "incorrect threaded length", the
/// HUST manual's S1 = S·F/1800·(−1 − ln A)).
#[allow(clippy::too_many_arguments)]
fn run_up(
    t: &Thread,
    blank: &Blank,
    threads: &Synced,
    spindle: &impl SpindleSpeed,
    t1: f64,
    a: f64,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let job = &t.job;
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let factor = -1.0 - a.ln();
    // (pass, needed, available) of each pass that starts from rest.
    let mut starts: Vec<(u32, f64, f64)> = Vec::new();
    for (i, &(from, m, lead)) in threads.iter().enumerate() {
        let from_rest = i == 0 || threads[i - 1].1.to != from;
        if !from_rest {
            continue;
        }
        let Some(rpm) = spindle.rpm_at(units, from.x) else {
            continue;
        };
        starts.push((
            m.pass,
            t1 * lead * rpm / 60.0 * factor,
            blank.before_face(from.z),
        ));
    }
    let Some(&(_, needed_first, _)) = starts.first() else {
        return;
    };
    if job.geometry.side.is_face() {
        notes.push(Note::new(
            job.span,
            "the run-up is not checked for a face thread".to_string(),
        ));
        return;
    }
    if blank.face == Known::Unknown {
        notes.push(Note::new(
            job.span,
            format!(
                "the run-up was not checked: the part's face is not known (the synchronised feed needs {} {} before it; --stock-start gives the face)",
                show(needed_first),
                units.name()
            ),
        ));
        return;
    }
    let short: Vec<&(u32, f64, f64)> = starts
        .iter()
        .filter(|(_, needed, available)| blank.z_tol.gt(*needed, *available))
        .collect();
    let Some(&&(pass, needed, available)) = short
        .iter()
        .max_by(|x, y| (x.1 - x.2).total_cmp(&(y.1 - y.2)))
    else {
        return;
    };
    let mut passes: Vec<u32> = short.iter().map(|s| s.0).collect();
    passes.dedup();
    let face = if blank.face == Known::Assumed {
        " (the part's face assumed at Z0)"
    } else {
        ""
    };
    let worst = if passes.len() > 1 {
        format!(" (pass {pass} the shortest)")
    } else {
        String::new()
    };
    out.push(
        Diagnostic::warning(
            Code::RunUp,
            t.pass_span(pass),
            format!(
                "{}{worst}: {}{face} but the synchronised feed needs {} {} of run-up to settle within {}% of the lead (servo time constant {t1} s)",
                passes_list(&passes),
                if blank.z_tol.gt(available, 0.0) {
                    format!("the thread move starts {} {} before the blank", show(available), units.name())
                } else if blank.z_tol.lt(available, 0.0) {
                    format!("the thread move starts {} {} inside the blank", show(-available), units.name())
                } else {
                    "the thread move starts at the blank's face".to_string()
                },
                show(needed),
                units.name(),
                a * 100.0
            ),
        )
        .with_hint(format!(
            "start the thread {} {} further from the part's face, or lower the spindle speed (--stock-start gives the face if it is not {})",
            show(needed - available),
            units.name(),
            if blank.face == Known::Assumed { "at Z0" } else { "where check took it" }
        )),
    );
}

/// Run-out: at the end of each pass's synchronised motion the axis lags the command by
/// δ2 = T1·V (Fanuc's "incorrect threaded length", equation (1)), so the last δ2 of the motion is
/// cut with a lead error. A synchronised pull-out (chamfer) at least δ2 long takes the error into
/// the chamfer; a shorter one leaves it on the full-depth thread. A straight exit leaves it on the
/// last δ2 before the programmed end, where a thread usually runs out into a relief: a note says
/// how long it is.
fn run_out(
    t: &Thread,
    tol: Tolerance,
    threads: &Synced,
    spindle: &impl SpindleSpeed,
    t1: f64,
    out: &mut Vec<Diagnostic>,
) {
    let job = &t.job;
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let pull = match job.exit {
        Exit::PullOut { length, .. } => length,
        _ => return,
    };
    // The end of each chain of synchronised moves: (pass, δ2 there).
    let mut short: Vec<(u32, f64)> = Vec::new();
    for (i, &(_, m, lead)) in threads.iter().enumerate() {
        let chain_ends = threads.get(i + 1).is_none_or(|next| next.0 != m.to);
        if !chain_ends {
            continue;
        }
        let Some(rpm) = spindle.rpm_at(units, m.to.x) else {
            continue;
        };
        let delta2 = t1 * lead * rpm / 60.0;
        if tol.gt(delta2, pull) {
            short.push((m.pass, delta2));
        }
    }
    let Some(&(pass, delta2)) = short.iter().max_by(|a, b| a.1.total_cmp(&b.1)) else {
        return;
    };
    let mut passes: Vec<u32> = short.iter().map(|s| s.0).collect();
    passes.dedup();
    out.push(
        Diagnostic::warning(
            Code::RunOut,
            t.pass_span(pass),
            format!(
                "{}: the pull-out is {} {} long but the synchronised feed needs δ2 = {} {} to stop (servo time constant {t1} s): the last {} {} of full-depth thread before it are cut with a lead error",
                passes_list(&passes),
                show(pull),
                units.name(),
                show(delta2),
                units.name(),
                show(delta2 - pull),
                units.name()
            ),
        )
        .with_hint("lengthen the pull-out (chamfer) to δ2 or more, or lower the spindle speed"),
    );
}
