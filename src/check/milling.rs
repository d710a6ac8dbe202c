//! `check` (and `passes`, `plot`) of a machining centre's program: the program read by the
//! milling reader ([`crate::millprog`]), its milled threads found ([`crate::mill::recognise`]) and
//! judged ([`super::milled`]), its tapping cycles judged ([`super::tapping`]), and a helix cut
//! with the spindle stopped.

use std::io::BufRead;

use super::measure::{target, Target};
use super::{Note, Report};
use crate::diag::{Code, Diagnostic, Span};
use crate::mill::motion::{MillKind, MillMotion, Rotation, TapCycle};
use crate::mill::profile::MillProfile;
use crate::mill::recognise::{self, MilledThread, Recogniser};
use crate::mill::{Hand, Side};
use crate::millprog;
use crate::sim::Tip;
use crate::thread::standard::{StandardThread, Surface};
use crate::units::Units;

/// A cutter's diameter by its tool number (`T5`) or its offset register (`D16`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToolSize {
    /// A tool number and its cutter's diameter.
    Tool(u32, f64),
    Register(u32, f64),
}

impl ToolSize {
    /// `D16=17.0` or `T5=12` (`--tool`); `None` for any other text.
    pub fn parse(text: &str) -> Option<ToolSize> {
        let (key, value) = text.split_once('=')?;
        let value: f64 = value.trim().parse().ok()?;
        Self::of(key, value)
    }

    /// A register (`D16`) or tool (`T5`) and the cutter's diameter (positive).
    pub fn of(key: &str, value: f64) -> Option<ToolSize> {
        if !(value.is_finite() && value > 0.0) {
            return None;
        }
        let key = key.trim();
        let letter = key.chars().next()?.to_ascii_uppercase();
        let number: u32 = key.get(1..)?.parse().ok()?;
        match letter {
            'D' => Some(ToolSize::Register(number, value)),
            'T' => Some(ToolSize::Tool(number, value)),
            _ => None,
        }
    }
}

/// A standard thread by its name, with the hand the name states (`…-LH`: left).
pub fn named_thread(name: &str) -> Result<(StandardThread, Hand), Diagnostic> {
    let t = crate::thread::standard::lookup(name)?;
    let hand = if crate::thread::standard::split_hand(name).1 {
        Hand::Left
    } else {
        Hand::Right
    };
    Ok((t, hand))
}

/// What checking a milling program is told.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// `--thread NAME`: the thread, and the hand its name states.
    pub thread: Option<(StandardThread, Hand)>,
    /// `--tip-flat` / `--nose-radius`: the cutter's tooth tip (mm).
    pub tip: Option<Tip>,
    /// `--wire D` (mm).
    pub wire: Option<f64>,
    /// `--internal` / `--external`.
    pub side: Option<Side>,
    /// `--tool-diameter`: the cutter of every thread, in the program's units (converted with the
    /// units of each move).
    pub tool_diameter: Option<f64>,
    /// `--tool T5=12` / `--tool D16=17`, in the program's units.
    pub tools: Vec<ToolSize>,
    /// `--teeth N`: a thread comb's teeth (1 if not given).
    pub teeth: Option<u32>,
    /// The reader's bounds.
    pub max_blocks: Option<u64>,
}

/// What a milling program holds: its milled threads, its tapping cycles, the reader's summary.
#[derive(Debug, Default)]
pub struct Milled {
    pub threads: Vec<MilledThread>,
    pub taps: Vec<TapCycle>,
    pub summary: millprog::Summary,
    /// Cutting moves made with the spindle stopped after it had turned (an M5 or M19 the
    /// program wrote): the first one's line, and how many.
    pub stopped_cuts: Option<(u32, u32)>,
    /// The first cutting move made before the program ever started the spindle (it may turn
    /// from before the program: an assumption).
    pub never_started: Option<u32>,
    /// The units of the program's last move (none: no move).
    pub units: Option<Units>,
}

/// Reads a milling program and finds its threads and taps. Recognition is told the cutter's
/// diameter of each thread's tool when the options give one.
pub fn read<R: BufRead>(
    input: R,
    profile: &MillProfile,
    o: &Options,
) -> Result<Milled, Diagnostic> {
    let mut sink = Collect {
        o,
        turned: false,
        recogniser: None,
        milled: Milled::default(),
    };
    let mut ro = millprog::Options::default();
    if let Some(m) = o.max_blocks {
        ro.max_blocks = m;
    }
    let summary = millprog::run(input, profile, &ro, &mut sink)?;
    let mut milled = sink.milled;
    if let Some(r) = sink.recogniser {
        milled.threads.extend(r.finish());
    }
    milled.summary = summary;
    Ok(milled)
}

struct Collect<'o> {
    o: &'o Options,
    /// The spindle has turned (M3 or M4) since the program's start.
    turned: bool,
    recogniser: Option<Recogniser>,
    milled: Milled,
}

impl Collect<'_> {
    fn recognition(&self, m: &MillMotion) -> recognise::Options {
        let units = m.state.units;
        recognise::Options {
            eps: units.to_mm(match units {
                Units::Mm => 0.001,
                Units::Inch => 0.0001,
            }),
            side: self.o.side,
            tool_diameter: cutter(self.o, m),
            teeth: self.o.teeth.unwrap_or(1),
        }
    }
}

/// The cutter's diameter at a move (mm): the D register's or the tool's size given, else
/// `--tool-diameter`.
fn cutter(o: &Options, m: &MillMotion) -> Option<f64> {
    let d = match m.state.comp {
        crate::mill::motion::Comp::Left { d } | crate::mill::motion::Comp::Right { d } => d,
        crate::mill::motion::Comp::Off => None,
    };
    o.tools
        .iter()
        .find_map(|t| match *t {
            ToolSize::Register(n, v) if Some(n) == d => Some(v),
            ToolSize::Tool(n, v) if Some(n) == m.state.tool => Some(v),
            _ => None,
        })
        .or(o.tool_diameter)
        .map(|v| m.state.units.to_mm(v))
}

impl millprog::Sink for Collect<'_> {
    fn motion(&mut self, m: &MillMotion, _work: u16) -> Result<(), Diagnostic> {
        self.milled.units = Some(m.state.units);
        let cuts = !matches!(m.kind, MillKind::Rapid);
        self.turned |= m.state.rotation != Rotation::Stopped;
        if cuts && m.state.rotation == Rotation::Stopped {
            if self.turned {
                let s = self.milled.stopped_cuts.get_or_insert((m.line, 0));
                s.1 += 1;
            } else if self.milled.never_started.is_none() {
                self.milled.never_started = Some(m.line);
            }
        }
        let options = self.recognition(m);
        let r = self
            .recogniser
            .get_or_insert_with(|| Recogniser::new(options));
        r.set_tool_diameter(options.tool_diameter);
        if let Some(t) = r.push(m) {
            self.milled.threads.push(t);
        }
        Ok(())
    }

    fn tap(&mut self, t: &TapCycle) -> Result<(), Diagnostic> {
        self.milled.taps.push(*t);
        Ok(())
    }
}

/// Checks a milling program: the reader's alarms, every milled thread, every tapping cycle.
pub fn check<R: BufRead>(input: R, profile: &MillProfile, o: &Options) -> Report {
    let mut report = Report {
        thread_codes: "G2/G3 helices, G84, G74, G33.1".into(),
        ..Report::default()
    };
    let milled = match read(input, profile, o) {
        Ok(m) => m,
        Err(d) => {
            report.diagnostics.push(d);
            report.stopped = true;
            return report;
        }
    };
    report.lines = milled.summary.lines;
    judge(&milled, profile, o, &mut report);
    report
}

/// The findings about what was read.
pub fn judge(milled: &Milled, profile: &MillProfile, o: &Options, report: &mut Report) {
    let span_of = Span::at_line;
    let units = milled.units.unwrap_or(Units::Mm);
    let eps = units.to_mm(match units {
        Units::Mm => 0.001,
        Units::Inch => 0.0001,
    });
    if let Some((line, n)) = milled.stopped_cuts {
        report.diagnostics.push(Diagnostic::error(
            Code::MachineState,
            span_of(line),
            format!(
                "the cutter feeds with the spindle stopped ({} such move{}): no M3 or M4 since the program's start or the last M5/M19",
                n,
                if n == 1 { "" } else { "s" }
            ),
        ));
    }
    if let Some(line) = milled.never_started {
        report.diagnostics.push(Diagnostic::warning(
            Code::MachineStateAssumed,
            span_of(line),
            "the cutter feeds and the program has not started the spindle (assumed: it turns from before the program, as for a block inserted in a longer one)",
        ).with_hint("start it with S… M3 before the first cut"));
    }
    let mut before: Option<&MilledThread> = None;
    for t in &milled.threads {
        let side = t.side.map(|s| s.0).unwrap_or(Side::Internal);
        let tg = o
            .thread
            .as_ref()
            .and_then(|(th, _)| target_on(th, side, report, t));
        let j = super::milled::Judging {
            target: tg.as_ref().zip(o.thread.as_ref().map(|t| t.1)),
            tip: o.tip,
            resolution: eps,
            units,
            wire: o.wire,
            span_of: &span_of,
            feed_reference: profile.comp_feed,
        };
        super::milled::judge(t, before, &j, &mut report.diagnostics, &mut report.notes);
        before = Some(t);
    }
    let lang = millprog::language_of(profile).ok();
    for tap in &milled.taps {
        let left = match tap.code {
            331 => None,
            code => lang
                .and_then(|l| l.cycles.taps.iter().find(|c| c.code == code))
                .map(|c| c.left),
        };
        let tg = o
            .thread
            .as_ref()
            .and_then(|(th, _)| target(th, Surface::Internal).ok());
        let j = super::tapping::Judging {
            target: tg.as_ref().zip(o.thread.as_ref().map(|t| t.1)),
            left,
            units,
            feed_resolution: units.to_mm(match units {
                Units::Mm => 0.001,
                Units::Inch => 0.0001,
            }),
            span_of: &span_of,
        };
        super::tapping::judge(tap, &j, &mut report.diagnostics, &mut report.notes);
    }
    report.threads = u32::try_from(milled.threads.len() + milled.taps.len()).unwrap_or(u32::MAX);
    report.diagnostics.sort_by_key(|d| d.span.line);
}

/// The class to judge a milled thread against on its side, or a note why there is none.
fn target_on<'t>(
    th: &'t StandardThread,
    side: Side,
    report: &mut Report,
    t: &MilledThread,
) -> Option<Target<'t>> {
    let surface = match side {
        Side::Internal => Surface::Internal,
        Side::External => Surface::External,
    };
    match target(th, surface) {
        Ok(tg) => Some(tg),
        Err(why) => {
            report.notes.push(Note::new(
                Span::at_line(t.helices[0].lines.0),
                format!("not judged against the class: {why}"),
            ));
            None
        }
    }
}
