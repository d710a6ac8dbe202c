//! APT/CL source: the statements a lathe thread program needs, read as a stream.
//!
//! ```text
//! PARTNO text            UNITS/MM|INCHES         FROM/x,y,z          GOTO/x,y,z[,i,j,k]
//! RAPID                  FEDRAT/f[,IPM|MMPM|IPR|MMPR]                SPINDL/n[,RPM][,CLW|CCLW] | SPINDL/OFF
//! PITCH/[TPI|IPR|MMPR|PERREV,]p[,MULTRD,n][,INCR|DECR,v]            COUPLE/ON … COUPLE/OFF
//! THREAD/TURN|FACE|TAPER (single pass)      THREAD/ON,params … THREAD/OFF (multi-pass)     FINI
//! ```
//!
//! CL points: X is radial (a radius), Z axial, Y is ignored. Lengths are in CL units (UNITS). Any
//! other statement is an error naming its line: nothing is dropped silently. Every decision on an
//! ambiguity of the seed is a row of `docs/dialects/apt-thread.md`.

pub mod post;
pub mod reader;
pub mod thread;

use std::io::{BufRead, Write};

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::program::{Error, Summary};
use crate::thread::Job;
use crate::toolpath::{self, Motion, MotionKind};
use crate::units::{Pos, Units};

pub use reader::{Reader, Statement};
pub use thread::{Pitch, ThreadOn};

/// The statements an APT/CL program threads with (what a program without a thread is told).
pub const THREAD_STATEMENTS: &str = "THREAD/ON, THREAD/TURN, COUPLE/ON";

/// Coordinates beyond this (mm) are refused: no lathe is 100 m long, and the output must stay finite.
pub const MAX_COORDINATE_MM: f64 = 1e5;

/// What one statement produced.
#[derive(Debug)]
pub enum Event<'a> {
    /// PARTNO: text for a comment.
    Comment(&'a str),
    /// FEDRAT: the feed in CL units per minute or per revolution.
    Feed { value: f64, per_rev: bool },
    /// SPINDL: speed (rpm) and clockwise, or off.
    Spindle(Option<(f64, bool)>),
    /// A plain move (GOTO outside THREAD/ON; a synchronised move under COUPLE or THREAD/TURN).
    Move(Motion),
    /// THREAD/ON … THREAD/OFF.
    Cycle(Box<Job>),
    /// FINI.
    End,
}

/// Whether a file holds APT/CL source rather than G-code: by its extension (`.apt`, `.cl`, `.cls`)
/// or, for other names, by its first statement's major word.
pub fn looks_like_apt(name: &std::path::Path, head: &[u8]) -> bool {
    let ext = name
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase());
    if matches!(ext.as_deref(), Some("apt" | "cl" | "cls")) {
        return true;
    }
    let text = String::from_utf8_lossy(head);
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with("$$"))
        .is_some_and(|l| {
            let upper = l.to_ascii_uppercase();
            [
                "PARTNO", "UNITS/", "MACHIN/", "FROM/", "GOTO/", "PITCH/", "CLPRNT",
            ]
            .iter()
            .any(|k| upper.starts_with(k))
        })
}

/// The statement interpreter: modal state between statements.
pub struct Interp {
    units: Units,
    units_seen: bool,
    warned_units: bool,
    warned_y: bool,
    position: Option<Pos>,
    rapid_next: bool,
    pitch: Option<Pitch>,
    coupled: bool,
    single_pass: Option<Span>,
    block: Option<Block>,
    ended: Option<u32>,
}

struct Block {
    on: ThreadOn,
    initial: Pos,
    gotos: Vec<thread::At<Pos>>,
}

impl Default for Interp {
    fn default() -> Self {
        Interp::new()
    }
}

impl Interp {
    pub fn new() -> Interp {
        Interp {
            units: Units::Mm,
            units_seen: false,
            warned_units: false,
            warned_y: false,
            position: None,
            rapid_next: false,
            pitch: None,
            coupled: false,
            single_pass: None,
            block: None,
            ended: None,
        }
    }

    pub fn units(&self) -> Units {
        self.units
    }

    pub fn position(&self) -> Option<Pos> {
        self.position
    }

    fn point(&mut self, st: &Statement, warnings: &mut Vec<Diagnostic>) -> Result<Pos> {
        let numbers: Vec<f64> = st.args.iter().filter_map(|a| a.number()).collect();
        if numbers.len() != st.args.len() || !(numbers.len() == 3 || numbers.len() == 6) {
            let at = st
                .args
                .iter()
                .find(|a| a.number().is_none())
                .map_or(st.major_span, |a| a.span);
            return Err(Diagnostic::error(
                Code::Syntax,
                at,
                format!("{}/ takes x,y,z or x,y,z,i,j,k: numbers only", st.major),
            ));
        }
        if !self.units_seen && !self.warned_units {
            self.warned_units = true;
            warnings.push(
                Diagnostic::warning(
                    Code::Suspicious,
                    st.major_span,
                    "no UNITS statement before the first point: CL values are read as millimetres",
                )
                .with_hint("write UNITS/MM or UNITS/INCHES at the top of the CL file"),
            );
        }
        if numbers[1] != 0.0 && !self.warned_y {
            self.warned_y = true;
            warnings.push(Diagnostic::warning(
                Code::Suspicious,
                st.args[1].span,
                format!(
                    "Y{} is ignored: lathe CL points are X (radius) and Z",
                    numbers[1]
                ),
            ));
        }
        let p = Pos::new(self.units.to_mm(numbers[0]), self.units.to_mm(numbers[2]));
        if !p.is_finite() || p.x.abs() > MAX_COORDINATE_MM || p.z.abs() > MAX_COORDINATE_MM {
            return Err(Diagnostic::error(
                Code::BadNumber,
                st.major_span,
                format!("{}/ names a point beyond ±{MAX_COORDINATE_MM} mm", st.major),
            ));
        }
        Ok(p)
    }

    fn no_args(st: &Statement) -> Result<()> {
        match st.args.first() {
            Some(a) => Err(Diagnostic::error(
                Code::Syntax,
                a.span,
                format!("{} takes no arguments", st.major),
            )),
            None => Ok(()),
        }
    }

    fn single_word<'s>(st: &'s Statement, allowed: &[&str]) -> Result<&'s str> {
        let bad = || {
            Diagnostic::error(
                Code::Unsupported,
                st.args.first().map_or(st.major_span, |a| a.span),
                format!("{}/ takes one of {} here", st.major, allowed.join(", ")),
            )
        };
        match (st.args.first().and_then(|a| a.word()), st.args.len()) {
            (Some(w), 1) if allowed.contains(&w) => Ok(w),
            _ => Err(bad()),
        }
    }

    /// Interprets one statement. Errors carry the statement's place.
    pub fn statement<'s>(
        &mut self,
        st: &'s Statement,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Event<'s>>> {
        if let Some(line) = self.ended {
            return Err(Diagnostic::error(
                Code::Syntax,
                st.major_span,
                format!(
                    "{} follows FINI (line {line}): FINI ends the CL file",
                    st.major
                ),
            ));
        }
        if self.block.is_some() && !(st.major == "GOTO" || st.major == "THREAD") {
            return Err(Diagnostic::error(
                Code::Unsupported,
                st.major_span,
                format!(
                    "{} is not allowed between THREAD/ON and THREAD/OFF: only the GOTOs of the thread contour",
                    st.major
                ),
            ));
        }
        if self.single_pass.is_some() && st.major != "GOTO" {
            return Err(Diagnostic::error(
                Code::Syntax,
                st.major_span,
                "THREAD/TURN|FACE|TAPER must be followed by GOTO/end_of_thread",
            ));
        }
        match st.major.as_str() {
            "PARTNO" => Ok(Some(Event::Comment(&st.text))),
            "UNITS" => {
                let w = Self::single_word(st, &["MM", "INCHES", "INCH", "MILLIMETERS"])?;
                self.units = if w.starts_with("IN") {
                    Units::Inch
                } else {
                    Units::Mm
                };
                self.units_seen = true;
                Ok(None)
            }
            "FROM" => {
                let p = self.point(st, warnings)?;
                self.position = Some(p);
                Ok(None)
            }
            "RAPID" => {
                Self::no_args(st)?;
                self.rapid_next = true;
                Ok(None)
            }
            "GOTO" => self.goto(st, warnings),
            "FEDRAT" => self.fedrat(st),
            "SPINDL" => self.spindl(st),
            "PITCH" => {
                self.pitch = Some(self.pitch_statement(st)?);
                Ok(None)
            }
            "COUPLE" => {
                let w = Self::single_word(st, &["ON", "OFF"])?;
                self.coupled = w == "ON";
                Ok(None)
            }
            "THREAD" => self.thread(st),
            "FINI" => {
                Self::no_args(st)?;
                if self.coupled {
                    return Err(Diagnostic::error(
                        Code::Syntax,
                        st.major_span,
                        "FINI while COUPLE/ON is in effect",
                    ));
                }
                self.ended = Some(st.line);
                Ok(Some(Event::End))
            }
            other => Err(Diagnostic::error(
                Code::Unsupported,
                st.major_span,
                format!("{other} is not supported by threadcut's APT reader"),
            )
            .with_hint(
                "supported: PARTNO UNITS FROM GOTO RAPID FEDRAT SPINDL PITCH COUPLE THREAD FINI",
            )),
        }
    }

    fn goto<'s>(
        &mut self,
        st: &'s Statement,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Event<'s>>> {
        let to = self.point(st, warnings)?;
        if let Some(block) = &mut self.block {
            if block.gotos.len() == 3 {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    st.major_span,
                    "a thread contour has at most three GOTOs: start, end and end of chamfer",
                ));
            }
            block.gotos.push(thread::At {
                value: to,
                span: st.major_span,
            });
            return Ok(None);
        }
        let kind = if self.coupled || self.single_pass.is_some() {
            let pitch = self.pitch.ok_or_else(|| {
                Diagnostic::error(
                    Code::MissingWord,
                    st.major_span,
                    "a synchronised move needs a PITCH statement before it",
                )
            })?;
            if pitch.starts > 1 {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    st.major_span,
                    "a single synchronised pass cuts one start: use THREAD/ON for a multi-start thread",
                ));
            }
            let from = self.position.ok_or_else(|| {
                Diagnostic::error(
                    Code::UnknownPosition,
                    st.major_span,
                    "a synchronised move needs a known start point: GOTO or FROM first",
                )
            })?;
            let d = to.minus(from);
            self.single_pass = None;
            MotionKind::Thread {
                lead: toolpath::lead_on_move(pitch.lead, d, d.x.abs() > d.z.abs()),
                dlead: pitch.dlead,
                phase_deg: 0.0,
            }
        } else if std::mem::take(&mut self.rapid_next) {
            MotionKind::Rapid
        } else {
            MotionKind::Feed
        };
        self.rapid_next = false;
        self.position = Some(to);
        Ok(Some(Event::Move(Motion {
            kind,
            to,
            pass: 0,
            line: st.line,
        })))
    }

    fn fedrat<'s>(&mut self, st: &'s Statement) -> Result<Option<Event<'s>>> {
        let mut args = thread::Args::new(&st.args);
        let value = match args.take() {
            Some(a) if a.number().is_some_and(|v| v > 0.0 && v < 1e6) => {
                a.number().unwrap_or_default()
            }
            Some(a) => {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    a.span,
                    "FEDRAT/ needs a positive feed rate (below 1e6) first",
                ))
            }
            None => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    st.major_span,
                    "FEDRAT/ needs a feed rate",
                ))
            }
        };
        let (per_rev, unit) = match args.take() {
            None => (false, self.units),
            Some(a) => match a.word() {
                Some("IPM") => (false, Units::Inch),
                Some("MMPM") => (false, Units::Mm),
                Some("IPR") => (true, Units::Inch),
                Some("MMPR") => (true, Units::Mm),
                _ => {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        a.span,
                        "FEDRAT/ takes IPM, MMPM, IPR or MMPR after the rate",
                    ))
                }
            },
        };
        if let Some(a) = args.take() {
            return Err(Diagnostic::error(
                Code::Syntax,
                a.span,
                "FEDRAT/ takes a rate and one mode word",
            ));
        }
        Ok(Some(Event::Feed {
            value: self.units.from_mm(unit.to_mm(value)),
            per_rev,
        }))
    }

    fn spindl<'s>(&mut self, st: &'s Statement) -> Result<Option<Event<'s>>> {
        if st.args.first().and_then(|a| a.word()) == Some("OFF") {
            Self::single_word(st, &["OFF"])?;
            return Ok(Some(Event::Spindle(None)));
        }
        let mut rpm = None;
        let mut cw = true;
        for a in &st.args {
            match (&a.value, a.word()) {
                (reader::Value::Number(v), _) if rpm.is_none() && *v > 0.0 => rpm = Some(*v),
                (_, Some("RPM")) => {}
                (_, Some("CLW")) => cw = true,
                (_, Some("CCLW")) => cw = false,
                _ => {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        a.span,
                        "SPINDL/ takes a speed, RPM, CLW or CCLW (or OFF); constant surface speed is not supported",
                    ))
                }
            }
        }
        let rpm = rpm.ok_or_else(|| {
            Diagnostic::error(
                Code::MissingWord,
                st.major_span,
                "SPINDL/ needs a positive speed in RPM",
            )
        })?;
        Ok(Some(Event::Spindle(Some((rpm, cw)))))
    }

    /// `PITCH/…`: replaces the modal pitch. An unqualified value is threads per CL unit.
    fn pitch_statement(&self, st: &Statement) -> Result<Pitch> {
        let mut words = thread::PitchWords::default();
        let mut args = thread::Args::new(&st.args);
        let unit_word = |a: Option<&reader::Arg>| {
            a.and_then(|a| a.word())
                .is_some_and(|w| matches!(w, "TPI" | "IPR" | "MMPR" | "PERREV"))
        };
        while let Some(a) = args.take() {
            if let Some(v) = a.number() {
                // `PITCH/p,TPI` (the value before its unit word) or `PITCH/p` alone.
                if words.lead.is_some() {
                    return Err(Diagnostic::error(
                        Code::Conflict,
                        a.span,
                        "the pitch is given twice",
                    ));
                }
                if v <= 0.0 {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        a.span,
                        format!("PITCH {v} must be positive"),
                    ));
                }
                let lead = if unit_word(args.peek()) {
                    let w = args.take().and_then(|w| w.word()).unwrap_or_default();
                    match w {
                        "TPI" => crate::units::lead_from_tpi(v),
                        "IPR" => Units::Inch.to_mm(v),
                        "MMPR" => v,
                        _ => self.units.to_mm(v),
                    }
                } else {
                    // Threads per CL unit.
                    self.units.to_mm(1.0 / v)
                };
                words.lead = Some(thread::At {
                    value: lead,
                    span: a.span,
                });
                continue;
            }
            let w = a.word().unwrap_or_default();
            if !thread::pitch_word(a, w, &mut args, self.units, &mut words)? {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    a.span,
                    format!("{w} is not a PITCH parameter"),
                )
                .with_hint("PITCH/[TPI|IPR|MMPR|PERREV,]pitch[,MULTRD,n][,INCR|DECR,value]"));
            }
        }
        if words.lead.is_none() {
            return Err(Diagnostic::error(
                Code::MissingWord,
                st.major_span,
                "PITCH/ needs the pitch",
            ));
        }
        words.over(None, st.major_span)
    }

    fn thread<'s>(&mut self, st: &'s Statement) -> Result<Option<Event<'s>>> {
        let first = st.args.first().and_then(|a| a.word());
        match first {
            Some("TURN" | "FACE" | "TAPER") if st.args.len() == 1 && self.block.is_none() => {
                if self.coupled {
                    return Err(Diagnostic::error(
                        Code::Conflict,
                        st.major_span,
                        "THREAD/TURN inside COUPLE/ON … COUPLE/OFF",
                    ));
                }
                self.single_pass = Some(st.major_span);
                Ok(None)
            }
            Some("ON") if self.block.is_none() => {
                let initial = self.position.ok_or_else(|| {
                    Diagnostic::error(
                        Code::UnknownPosition,
                        st.major_span,
                        "THREAD/ON starts from the initial point, and no GOTO or FROM has set it",
                    )
                })?;
                if self.coupled {
                    return Err(Diagnostic::error(
                        Code::Conflict,
                        st.major_span,
                        "THREAD/ON inside COUPLE/ON … COUPLE/OFF",
                    ));
                }
                let on = thread::parse_on(st, self.units)?;
                // A RAPID before THREAD/ON belongs to the cycle's approach (always a rapid here).
                self.rapid_next = false;
                self.block = Some(Block {
                    on,
                    initial,
                    gotos: Vec::with_capacity(3),
                });
                Ok(None)
            }
            Some("OFF") if st.args.len() == 1 => {
                let Some(block) = self.block.take() else {
                    return Err(Diagnostic::error(
                        Code::Syntax,
                        st.major_span,
                        "THREAD/OFF without THREAD/ON",
                    ));
                };
                if block.gotos.len() < 2 {
                    return Err(Diagnostic::error(
                        Code::MissingWord,
                        st.major_span,
                        format!(
                            "the thread contour of THREAD/ON (line {}) needs two GOTOs (start and end of thread); it has {}",
                            block.on.line,
                            block.gotos.len()
                        ),
                    ));
                }
                let pitch = block.on.pitch.over(self.pitch, block.on.span)?;
                let contour = thread::Contour {
                    initial: block.initial,
                    start: block.gotos[0],
                    end: block.gotos[1],
                    chamfer: block.gotos.get(2).copied(),
                };
                let job = thread::lower(&block.on, &contour, pitch, self.units, st.major_span)?;
                self.position = Some(job.start);
                Ok(Some(Event::Cycle(Box::new(job))))
            }
            Some("ON") => Err(Diagnostic::error(
                Code::Syntax,
                st.major_span,
                "THREAD/ON inside another THREAD/ON: THREAD/OFF is missing",
            )),
            _ => Err(Diagnostic::error(
                Code::Unsupported,
                st.args.first().map_or(st.major_span, |a| a.span),
                "THREAD/ takes TURN, FACE or TAPER (single pass), ON,… or OFF",
            )
            .with_hint("ON must be the first parameter of THREAD/ON")),
        }
    }

    /// Checks at the end of the input.
    pub fn finish(&self) -> Result<()> {
        if let Some(b) = &self.block {
            return Err(Diagnostic::error(
                Code::Syntax,
                b.on.span,
                "THREAD/ON has no THREAD/OFF",
            ));
        }
        if let Some(span) = self.single_pass {
            return Err(Diagnostic::error(
                Code::Syntax,
                span,
                "THREAD/TURN|FACE|TAPER is not followed by GOTO/end_of_thread",
            ));
        }
        Ok(())
    }
}

/// Streams `input` statement by statement through the interpreter, handing each event to `sink`.
pub fn run<R: BufRead>(
    input: R,
    mut sink: impl FnMut(&Interp, Event) -> std::result::Result<(), Error>,
) -> std::result::Result<Summary, Error> {
    let mut reader = Reader::new(input);
    let mut interp = Interp::new();
    let mut summary = Summary::default();
    while let Some(st) = reader.next_statement() {
        let st = st?;
        summary.lines = st.line;
        if let Some(ev) = interp.statement(st, &mut summary.warnings)? {
            if matches!(ev, Event::Cycle(_)) {
                summary.cycles += 1;
            }
            sink(&interp, ev)?;
        }
    }
    interp.finish()?;
    Ok(summary)
}

/// Every THREAD/ON cycle of a CL file (holds them all in memory; for tests and library users).
pub fn jobs<R: BufRead>(input: R) -> std::result::Result<Vec<Job>, Error> {
    let mut jobs = Vec::new();
    run(input, |_, ev| {
        if let Event::Cycle(job) = ev {
            jobs.push(*job);
        }
        Ok(())
    })?;
    Ok(jobs)
}

/// `threadcut expand FILE.apt --format jsonl`: one JSON object per motion, CL units, X a radius.
pub fn expand_jsonl<R: BufRead>(
    input: R,
    out: &mut dyn Write,
) -> std::result::Result<Summary, Error> {
    run(input, |interp, ev| {
        match ev {
            Event::Move(m) => writeln!(out, "{}", crate::post::motion_json(&m, interp.units()))?,
            Event::Cycle(job) => {
                for m in &toolpath::build(&job)?.motions {
                    writeln!(out, "{}", crate::post::motion_json(m, job.units))?;
                }
            }
            _ => {}
        }
        Ok(())
    })
}
