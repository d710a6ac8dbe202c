//! Writing a [`Block`] of meanings through the target controller's [`Lexicon`], and the state of
//! the program being written (its units, the F register, the tool, the spindle limit). A meaning
//! the target has no words for is a refusal that names the target; nothing here names a
//! controller.

use std::io::Write;

use crate::diag::{Code as DiagCode, Diagnostic, Span};
use crate::dialect::Dialect;
use crate::gcode::{Line, Modal, MotionMode, PlainMove, Position};
use crate::machine::Machine;
use crate::post::{self, path_lead, Format};
use crate::program::Error;
use crate::thread::Job;
use crate::translate::{self, Written};
use crate::units::Units;

use super::block::{Axis, Block, ToolTerm};
use super::tools::ToolMap;
use super::Report;
use crate::dialect::lexicon::{
    Code, DwellForm, Function, LimitForm, Meanings, Plane, ReturnForm, ToolForm,
};

/// Feet in a metre: a surface speed in m/min is 3.28084 ft/min.
const FEET_PER_METRE: f64 = 1000.0 / 304.8;

pub(super) struct Writer<'o, 'm> {
    out: &'o mut dyn Write,
    to: &'m Machine,
    tlex: Meanings,
    format: Format,
    /// Lines written before the first line that is not a `%` delimiter.
    header: Option<Vec<String>>,
    /// The header's comment naming the conversion.
    header_comment: Option<String>,
    /// The units the converted program is written in: the source's where the target has them.
    out_units: Units,
    /// What the target's F register holds, as written (`None`: not known).
    target_f: Option<String>,
    /// Where the tool is before the line, axis by axis (source and target move alike).
    prev: Position,
    /// The last move written was synchronised: the next thread move continues its run.
    in_run: bool,
    /// The source's tool in the spindle, the tool prepared for a change, the offset in force.
    tool: Option<u32>,
    prepared: Option<u32>,
    offset: u32,
    /// The spindle is on constant surface speed.
    css: bool,
    /// A spindle limit the source set that the target has no word for (rpm): a later speed above
    /// it, or constant surface speed, is refused.
    unstated_limit: Option<f64>,
    /// A spindle limit waiting for the target's constant-surface-speed block (a word on it).
    pending_limit: Option<f64>,
    /// How the source selects tools.
    source_tool: ToolForm,
    /// A source's return code without axis words returns every axis.
    source_returns_all: bool,
    /// The largest drift of a lead over its thread (output units; `None`: a quarter of the
    /// thread's class tolerance on the pitch diameter).
    max_lead_drift: Option<f64>,
    /// Named tools and their numbers.
    names: ToolMap,
    /// The tool last called by its name, and the offset its first cutting edge applies.
    named: Option<(u32, u32)>,
    report: Report,
}

/// What the command chose for a conversion besides the two machines.
pub(super) struct Choices {
    /// The largest drift of a lead over its thread (output units; `None`: a quarter of the
    /// thread's class tolerance on the pitch diameter).
    pub max_lead_drift: Option<f64>,
    /// Named tools and their numbers.
    pub names: ToolMap,
}

/// The words of one output block, in the groups they are written in.
#[derive(Default)]
struct Out {
    /// The sequence number and program number.
    head: Vec<String>,
    /// Mode codes, the move and its words.
    g: Vec<String>,
    /// S and the tool.
    tail: Vec<String>,
    /// M functions.
    m: Vec<String>,
    /// Comments, after the words.
    notes: Vec<String>,
    /// Whole lines written before the block (LinuxCNC's `G91 G28 …` / `G90`).
    extra: Vec<String>,
}

/// A refusal with its own hint.
fn refuse_with(span: Span, message: String, hint: String) -> Error {
    Error::Input(Diagnostic::error(DiagCode::Unsupported, span, message).with_hint(hint))
}

/// A refusal: the target has no counterpart of what the source wrote at `span`.
fn refuse(span: Span, message: String) -> Error {
    Error::Input(
        Diagnostic::error(DiagCode::Unsupported, span, message).with_hint(
            "rewrite this block by hand for the target, or remove it (docs/translation.md lists each controller's words)",
        ),
    )
}

impl<'o, 'm> Writer<'o, 'm> {
    pub fn new(
        out: &'o mut dyn Write,
        from: &'m Machine,
        to: &'m Machine,
        target: &dyn Dialect,
        source: &Meanings,
        choices: Choices,
    ) -> Result<Writer<'o, 'm>, Error> {
        let tlex = target.meanings();
        let format = target.format();
        let out_units = if tlex.has_units(from.units) {
            from.units
        } else {
            tlex.only_units.unwrap_or(from.units)
        };
        // What the source program relied on at power-on, in the target's words.
        let states = [
            Function::Units(out_units),
            Function::Absolute,
            if to.diameter_x {
                Function::Diameter
            } else {
                Function::Radius
            },
            Function::Plane(Plane::Zx),
            source.power_on_feed,
            Function::Rpm,
        ];
        let codes: Vec<String> = states
            .iter()
            .filter_map(|f| tlex.code(*f))
            .map(Code::text)
            .collect();
        let header_comment = format.comment(&format!(
            "threadcut convert: {} to {}, {}, {}",
            from.name,
            to.name,
            out_units.name(),
            source.power_on_feed.describe()
        ));
        let mut header: Vec<String> = header_comment.iter().cloned().collect();
        if !codes.is_empty() {
            header.push(codes.join(" "));
        }
        Ok(Writer {
            out,
            to,
            tlex,
            format,
            header: Some(header),
            header_comment,
            out_units,
            target_f: None,
            prev: Position::UNKNOWN,
            in_run: false,
            tool: None,
            prepared: None,
            offset: 0,
            css: false,
            unstated_limit: None,
            pending_limit: None,
            source_tool: source.tool,
            source_returns_all: source.return_all_without_axes,
            max_lead_drift: choices.max_lead_drift,
            names: choices.names,
            named: None,
            report: Report::default(),
        })
    }

    pub fn finish(self) -> Report {
        self.report
    }

    /// The header's first line, the comment naming the conversion (`None`: the target has no
    /// comments).
    pub fn header_comment(&self) -> Option<String> {
        self.header_comment.clone()
    }

    /// The header, before the first line that is neither a `%` delimiter nor the line that names
    /// the program (`names`: its number or name comes first, as the target's manuals lay a
    /// program out: `%`, `O0001`, the blocks).
    pub fn header_before(&mut self, line: &Line, names: bool) -> Result<(), Error> {
        if !line.shape.percent && !names {
            if let Some(h) = self.header.take() {
                for l in h {
                    writeln!(self.out, "{l}")?;
                }
            }
        }
        Ok(())
    }

    /// A `%` line: kept where the target delimits programs with it.
    pub fn delimiter(&mut self) -> Result<(), Error> {
        if self.tlex.delimiters {
            writeln!(self.out, "%")?;
        }
        Ok(())
    }

    /// An empty line.
    pub fn blank_line(&mut self) -> Result<(), Error> {
        writeln!(self.out)?;
        Ok(())
    }

    /// The target profile's name, for messages.
    pub fn target_name(&self) -> &str {
        &self.to.name
    }

    /// A line whose only content for the target is its comment.
    pub fn comment_only(&mut self, text: &str) -> Result<(), Error> {
        if !text.is_empty() {
            if let Some(c) = self.format.comment(text) {
                writeln!(self.out, "{c}")?;
            }
        }
        Ok(())
    }

    fn code(&self, f: Function) -> Option<String> {
        self.tlex.code(f).map(Code::text)
    }

    /// The target's code for a function the source wrote as `text` at `span`; `None` when the
    /// target needs none (a cancel of a state it cannot be in, the only plane of a lathe).
    fn required(&self, f: Function, span: Span, text: &str) -> Result<Option<String>, Error> {
        if let Some(c) = self.code(f) {
            return Ok(Some(c));
        }
        let needless = match f {
            Function::Plane(Plane::Zx) | Function::CycleSetting => true,
            f => f
                .cancelled_family()
                .is_some_and(|family| family.iter().all(|g| !self.tlex.has(*g))),
        };
        if needless {
            return Ok(None);
        }
        Err(refuse(
            span,
            format!(
                "{text} ({}): {} has no code for it in threadcut's lexicon",
                f.describe(),
                self.to.name
            ),
        ))
    }

    /// Numbers in the output: a length in mm, an X radius in mm, in the output units.
    fn length(&self, mm: f64) -> String {
        let d = self.format.decimals[(self.out_units == Units::Inch) as usize];
        post::number(self.out_units.from_mm(mm), d, self.format.trailing_zeros)
    }

    fn x(&self, radius_mm: f64) -> String {
        let d = self.format.decimals[(self.out_units == Units::Inch) as usize];
        post::number(
            self.format.x_word(radius_mm, self.out_units),
            d,
            self.format.trailing_zeros,
        )
    }

    /// A feed or lead (program units of `from_units`) in the output units.
    fn rate(&self, value: f64, from_units: Units) -> String {
        let d = self.format.lead_decimals[(self.out_units == Units::Inch) as usize];
        post::number(
            self.out_units.from_mm(from_units.to_mm(value)),
            d,
            self.format.trailing_zeros,
        )
    }

    /// A spindle speed, a count: whole where it is whole.
    fn speed(v: f64) -> String {
        if v.fract() == 0.0 {
            format!("{}", v as i64)
        } else {
            post::number(v, 3, false)
        }
    }

    /// A plain block (`modal`: the source's state after it; `mv`: the move it makes).
    pub fn plain(
        &mut self,
        line: &Line,
        b: &Block,
        mv: Option<PlainMove>,
        modal: &Modal,
    ) -> Result<(), Error> {
        let before = self.prev;
        self.prev = modal.position;
        if b.data {
            return self.comment_only(String::from_utf8_lossy(line.text).trim());
        }
        let mut o = Out::default();
        if let Some(n) = b.n.filter(|_| self.tlex.sequence_numbers) {
            o.head.push(format!("N{n}"));
        }
        if let Some(p) = &b.program {
            if self.tlex.program_number {
                o.head.push(p.clone());
            } else {
                o.notes.push(format!("program {p}"));
            }
        }
        let css_here = self.codes(b, &mut o)?;
        let fspan = |f: Function| {
            b.functions
                .iter()
                .find(|(g, _, _)| *g == f)
                .map(|(_, s, t)| (*s, t.clone()))
        };
        // Blocks that are no move: a reference return, a new position, a dwell.
        if let Some((span, text)) = fspan(Function::ReferenceReturn) {
            self.reference_return(b, before, modal, (span, &text), &mut o)?;
        } else if let Some((span, text)) = fspan(Function::SetPosition) {
            self.set_position(b, before, modal, span, &text, &mut o.g)?;
        } else if let Some((span, text)) = fspan(Function::Dwell) {
            self.dwell(b, span, &text, &mut o.g)?;
        } else if b.has(Function::RestatePosition) {
            // The coordinates the tool has (the source's reader checked): nothing to write.
        } else {
            self.motion(b, mv, modal, &mut o.g)?;
        }
        if let Some((v, span)) = b.limit {
            self.limit(v, span, &mut o.g, &mut o.notes)?;
        }
        if css_here {
            if let (Some(v), Some(LimitForm::OnSurfaceSpeed(l))) =
                (self.pending_limit.take(), self.tlex.spindle_limit)
            {
                o.g.push(format!("{}{}", l as char, Self::speed(v)));
            }
        }
        self.spindle_speed(b, modal, &mut o.tail)?;
        self.tools(b, &mut o.tail)?;
        if !b.comment.is_empty() {
            o.notes.push(b.comment.clone());
        }
        self.emit(line, o)
    }

    /// The codes of a block's modes and M functions, in the target's words (`o.g`, `o.m`); the
    /// output state they change. Whether the block turns constant surface speed on.
    fn codes(&mut self, b: &Block, o: &mut Out) -> Result<bool, Error> {
        let mut css_here = false;
        for (f, span, text) in &b.functions {
            match *f {
                Function::Units(u) => {
                    self.target_f = None;
                    if self.tlex.has_units(u) {
                        self.out_units = u;
                        if let Some(c) = self.code(*f) {
                            o.g.push(c);
                        }
                    }
                }
                // Absorbed (positions are absolute in the target's X mode), carried by the
                // cycles' jobs, or written with the block's move or its other words.
                Function::Absolute
                | Function::Incremental
                | Function::Diameter
                | Function::Radius
                | Function::CycleSetting
                | Function::RestatePosition
                | Function::Rapid
                | Function::Feed
                | Function::ArcCw
                | Function::ArcCcw
                | Function::Thread
                | Function::Dwell
                | Function::SetPosition
                | Function::SpindleLimit
                | Function::ReferenceReturn
                | Function::ToolChange
                | Function::ToolOffset
                | Function::ToolOffsetOff => {}
                Function::FeedPerMinute | Function::FeedPerRevolution => {
                    self.target_f = None;
                    o.g.extend(self.required(*f, *span, text)?);
                }
                Function::SurfaceSpeed => {
                    if let Some(limit) = self.unstated_limit {
                        return Err(refuse(
                            *span,
                            format!(
                                "{text} (constant surface speed): the program limits the spindle to {} rpm, and {} has no spindle-limit word in threadcut's lexicon",
                                Self::speed(limit),
                                self.to.name
                            ),
                        ));
                    }
                    self.css = true;
                    css_here = true;
                    o.g.extend(self.required(*f, *span, text)?);
                }
                Function::Rpm => {
                    self.css = false;
                    o.g.extend(self.required(*f, *span, text)?);
                }
                Function::Plane(_)
                | Function::CompensationOff
                | Function::CompensationLeft
                | Function::CompensationRight
                | Function::WorkOffset(_) => o.g.extend(self.required(*f, *span, text)?),
                Function::SpindleCw
                | Function::SpindleCcw
                | Function::SpindleStop
                | Function::SpindleOrient
                | Function::CoolantOn
                | Function::MistOn
                | Function::CoolantOff
                | Function::End
                | Function::EndRewind
                | Function::Stop
                | Function::OptionalStop => o.m.extend(self.required(*f, *span, text)?),
            }
        }
        Ok(css_here)
    }

    /// S: the spindle speed, or a surface speed converted between m/min and ft/min where the
    /// output's units are not the program's; refused above a limit the target cannot state.
    fn spindle_speed(&self, b: &Block, modal: &Modal, tail: &mut Vec<String>) -> Result<(), Error> {
        let Some((s, span)) = b.speed else {
            return Ok(());
        };
        let v = if self.css && modal.units != self.out_units {
            match self.out_units {
                Units::Inch => s * FEET_PER_METRE,
                Units::Mm => s / FEET_PER_METRE,
            }
        } else {
            s
        };
        if let (false, Some(limit)) = (self.css, self.unstated_limit) {
            if s > limit {
                return Err(refuse(
                    span,
                    format!(
                        "S{}: the program limits the spindle to {} rpm, and {} has no spindle-limit word in threadcut's lexicon",
                        Self::speed(s),
                        Self::speed(limit),
                        self.to.name
                    ),
                ));
            }
        }
        tail.push(format!("S{}", Self::speed(v)));
        Ok(())
    }

    /// Writes a block's lines: the extra lines before it, then its words in order (sequence
    /// number and program number, modes and the move, S, T, M), the comment last.
    fn emit(&mut self, line: &Line, o: Out) -> Result<(), Error> {
        let mut words = o.head;
        words.extend(o.g);
        words.extend(o.tail);
        words.extend(o.m);
        let note = (!o.notes.is_empty())
            .then(|| self.format.comment(&o.notes.join("; ")))
            .flatten();
        for l in o.extra {
            writeln!(self.out, "{l}")?;
        }
        if words.is_empty() {
            match note {
                Some(c) => writeln!(self.out, "{c}")?,
                None if line.words.is_empty() && !line.shape.unread => writeln!(self.out)?,
                None => {}
            }
            return Ok(());
        }
        let mut text = words.join(" ");
        if line.shape.block_delete {
            text.insert(0, '/');
        }
        if let Some(c) = note {
            text.push(' ');
            text.push_str(&c);
        }
        writeln!(self.out, "{text}")?;
        Ok(())
    }

    /// The move of a block: its motion code always (a native cycle written before may have
    /// changed the target's modal one), its axes as absolute positions, the lead and start angle
    /// of a thread move, the feed of a cutting move.
    fn motion(
        &mut self,
        b: &Block,
        mv: Option<PlainMove>,
        modal: &Modal,
        g: &mut Vec<String>,
    ) -> Result<(), Error> {
        let axes = b.x.is_some() || b.z.is_some();
        let mode = match mv {
            Some(mv) => Some(mv.mode),
            None if axes => Some(modal.motion),
            None => None,
        };
        let span = b.x.or(b.z).map(|a| a.span).unwrap_or_default();
        let f = match mode {
            None => None,
            Some(MotionMode::Rapid) => Some(Function::Rapid),
            Some(MotionMode::Feed) => Some(Function::Feed),
            Some(MotionMode::ArcCw) => Some(Function::ArcCw),
            Some(MotionMode::ArcCcw) => Some(Function::ArcCcw),
            Some(MotionMode::Thread) => Some(Function::Thread),
            Some(MotionMode::Cycle) => {
                return Err(refuse(
                    span,
                    "the words of a canned cycle other than threading are not converted".into(),
                ))
            }
        };
        if let Some(f) = f {
            let Some(code) = self.code(f) else {
                return Err(refuse(
                    span,
                    if f == Function::Thread {
                        format!(
                            "a synchronised thread move: {} has no plain thread move ({} is always its threading cycle)",
                            self.to.name, self.format.thread
                        )
                    } else {
                        format!(
                            "a {}: {} has no code for it in threadcut's lexicon",
                            f.describe(),
                            self.to.name
                        )
                    },
                ));
            };
            g.push(code);
        }
        match mv {
            Some(mv) => {
                if b.x.is_some() {
                    g.push(format!("X{}", self.x(mv.to.x)));
                }
                if b.z.is_some() {
                    g.push(format!("Z{}", self.length(mv.to.z)));
                }
            }
            None => {
                for (letter, axis) in [(b'X', b.x), (b'Z', b.z)] {
                    let Some(a) = axis else { continue };
                    if a.incremental || !a.value.is_finite() {
                        return Err(refuse(
                            a.span,
                            "a move from an unknown position whose end is not written as an absolute number cannot be rewritten".into(),
                        ));
                    }
                    g.push(if letter == b'X' {
                        format!("X{}", self.x(modal.x_to_mm(a.value)))
                    } else {
                        format!("Z{}", self.length(modal.units.to_mm(a.value)))
                    });
                }
            }
        }
        if let Some((r, _)) = b.radius {
            g.push(format!("R{}", self.length(modal.units.to_mm(r))));
        }
        if f == Some(Function::Thread) {
            let Some(mv) = mv else {
                return Err(refuse(
                    span,
                    "a thread move from an unknown position cannot be converted".into(),
                ));
            };
            self.thread_words(&mv, span, g)?;
        } else if mv.is_some() {
            self.in_run = false;
        }
        let cutting = matches!(f, Some(Function::Feed | Function::ArcCw | Function::ArcCcw));
        if cutting || b.feed.is_some() {
            if let Some(value) = modal.f_word {
                let text = self.rate(value, modal.units);
                if b.feed.is_some() || self.target_f.as_deref() != Some(text.as_str()) {
                    g.push(format!("F{text}"));
                    self.target_f = Some(text);
                }
            }
        }
        Ok(())
    }

    /// A thread move's lead (the target's word and convention) and, at the start of a run, its
    /// start angle.
    fn thread_words(
        &mut self,
        mv: &PlainMove,
        span: Span,
        g: &mut Vec<String>,
    ) -> Result<(), Error> {
        let lead = mv.lead.unwrap_or(0.0);
        // The path, where the target's words depend on it (a lead along the path, a letter for
        // steep threads). A move's start is unknown only on an axis the block moves (its end is
        // known), so an unknown start is an unknown path.
        let needs_path = self.format.lead_along_path || self.format.steep_lead_letter.is_some();
        let d = match mv.from.known() {
            Some(from) => mv.to.minus(from),
            None if needs_path => {
                return Err(refuse(
                    span,
                    format!(
                        "a thread move from an unknown position ({} not known): {}'s thread move needs its path",
                        mv.from.unknown_axes().join(", "),
                        self.to.name
                    ),
                ))
            }
            None => crate::units::Vec2 { x: 0.0, z: 0.0 },
        };
        let along = if self.format.lead_along_path {
            path_lead(lead, d)
        } else {
            lead
        };
        let letter = match self.format.steep_lead_letter {
            Some(steep) if d.x.abs() > d.z.abs() => steep,
            _ => self.format.lead_letter,
        };
        let text = self.rate(along, Units::Mm);
        g.push(format!("{letter}{text}"));
        if letter == 'F' {
            self.target_f = Some(text);
        }
        if !self.in_run {
            match self.format.start_angle {
                Some(word) if word.modal || mv.phase_deg != 0.0 => {
                    let mut buf = Vec::new();
                    word.push(&mut buf, mv.phase_deg, self.format.trailing_zeros)?;
                    g.push(String::from_utf8_lossy(&buf).trim().to_string());
                }
                None if mv.phase_deg != 0.0 => {
                    return Err(refuse(
                        span,
                        format!(
                            "this thread move starts {}° after the spindle's index, and {}'s thread move cannot state a start angle in threadcut",
                            post::number(mv.phase_deg, 3, false),
                            self.to.name
                        ),
                    ))
                }
                _ => {}
            }
        }
        self.in_run = true;
        Ok(())
    }

    /// A return straight to the reference point, of the axes the block names (all, where a bare
    /// return means every axis). The source's intermediate point must be where the tool is.
    fn reference_return(
        &mut self,
        b: &Block,
        before: Position,
        modal: &Modal,
        (span, text): (Span, &str),
        o: &mut Out,
    ) -> Result<(), Error> {
        self.in_run = false;
        let named = [
            b.x.is_some() || b.machine_axes[0].is_some(),
            b.z.is_some() || b.machine_axes[1].is_some(),
        ];
        let res = modal.resolution();
        for (i, axis) in [b.x, b.z].into_iter().enumerate() {
            let Some(a) = axis else { continue };
            // The intermediate point on this axis is where the tool is, at the program's
            // resolution: an incremental zero, or the tool's known coordinate.
            let here = |a: &Axis| -> bool {
                let (mm, tol, at) = if i == 0 {
                    (modal.x_to_mm(a.value), res.x(), before.x)
                } else {
                    (modal.units.to_mm(a.value), res.length(), before.z)
                };
                if a.incremental {
                    return tol.is_zero(mm);
                }
                at.is_some_and(|at| tol.eq(mm, at))
            };
            if !here(&a) {
                return Err(refuse(
                    a.span,
                    format!("{text} through an intermediate point away from the tool: threadcut converts a return straight from where the tool is"),
                ));
            }
        }
        let axes = if named.iter().any(|n| *n) {
            named
        } else if self.source_returns_all {
            // A bare return: every axis where that is the source's rule (its conventions').
            [true, true]
        } else {
            return Ok(());
        };
        let Some((form, code)) = self
            .tlex
            .reference
            .zip(self.code(Function::ReferenceReturn))
        else {
            return self.reference_position(axes, (span, text), o);
        };
        let (extra, g) = (&mut o.extra, &mut o.g);
        match form {
            ReturnForm::IncrementalWords { x, z } => {
                g.push(code);
                if axes[0] {
                    g.push(format!("{}0.", x as char));
                }
                if axes[1] {
                    g.push(format!("{}0.", z as char));
                }
            }
            ReturnForm::IncrementalMode => {
                let (Some(inc), Some(abs)) = (
                    self.code(Function::Incremental),
                    self.code(Function::Absolute),
                ) else {
                    return Err(refuse(span, "no incremental mode to return in".into()));
                };
                let mut l = vec![inc, code];
                if axes[0] {
                    l.push("X0.".into());
                }
                if axes[1] {
                    l.push("Z0.".into());
                }
                extra.push(l.join(" "));
                extra.push(abs);
            }
            ReturnForm::MachineAxes { x, z } => {
                g.push(code);
                if axes[0] {
                    g.push(format!("{x}=0"));
                }
                if axes[1] {
                    g.push(format!("{z}=0"));
                }
            }
        }
        Ok(())
    }

    /// A return to the reference point on a target without one: a rapid to where the target
    /// profile's `[reference] g28` places the returning axes (program coordinates at power-on,
    /// the profile's units and X mode), else refused.
    fn reference_position(
        &mut self,
        axes: [bool; 2],
        (span, text): (Span, &str),
        o: &mut Out,
    ) -> Result<(), Error> {
        let point = self.to.reference.map(|r| r.g28).unwrap_or_default();
        let mut words = Vec::new();
        for (i, value) in [point.x, point.z].into_iter().enumerate() {
            if !axes[i] {
                continue;
            }
            let axis = if i == 0 { 'x' } else { 'z' };
            let Some(v) = value else {
                return Err(refuse_with(
                    span,
                    format!(
                        "{text} (return to the reference point): {} has no reference return in threadcut's lexicon, and its profile does not place the reference point's {}",
                        self.to.name,
                        axis.to_ascii_uppercase()
                    ),
                    format!(
                        "state where the return leaves the tool in the target profile's [reference] table (g28 = {{ {axis} = … }}, program coordinates at power-on): threadcut then writes a rapid there (docs/translation.md, \"Reference returns\")"
                    ),
                ));
            };
            let mm = self.to.units.to_mm(v);
            words.push(if i == 0 {
                let radius = if self.to.diameter_x { mm / 2.0 } else { mm };
                format!("X{}", self.x(radius))
            } else {
                format!("Z{}", self.length(mm))
            });
        }
        let rapid = self.required(Function::Rapid, span, text)?;
        o.g.extend(rapid);
        o.g.extend(words);
        o.notes.push(format!(
            "{text}: the reference point, where the profile's [reference] g28 places it"
        ));
        Ok(())
    }

    /// New coordinates for the current position: nothing to write when they are the ones it has.
    fn set_position(
        &mut self,
        b: &Block,
        before: Position,
        modal: &Modal,
        span: Span,
        text: &str,
        g: &mut Vec<String>,
    ) -> Result<(), Error> {
        let res = modal.resolution();
        let mut words = Vec::new();
        // Nothing to write when every coordinate the block gives is the one the tool has (at the
        // program's resolution, on an axis whose position is known).
        let mut same = true;
        for (i, axis) in [b.x, b.z].into_iter().enumerate() {
            let Some(a) = axis else { continue };
            if a.incremental || !a.value.is_finite() {
                return Err(refuse(
                    a.span,
                    format!("{text} with an incremental or computed coordinate is not converted"),
                ));
            }
            let mm = if i == 0 {
                modal.x_to_mm(a.value)
            } else {
                modal.units.to_mm(a.value)
            };
            let (at, tol) = if i == 0 {
                (before.x, res.x())
            } else {
                (before.z, res.length())
            };
            same &= at.is_some_and(|at| tol.eq(mm, at));
            words.push(if i == 0 {
                format!("X{}", self.x(mm))
            } else {
                format!("Z{}", self.length(mm))
            });
        }
        if same {
            return Ok(());
        }
        let code = self.code(Function::SetPosition).ok_or_else(|| {
            refuse(
                span,
                format!(
                    "{text} (setting the current position's coordinates): {} has no code for it in threadcut's lexicon",
                    self.to.name
                ),
            )
        })?;
        g.push(code);
        g.extend(words);
        Ok(())
    }

    fn dwell(
        &mut self,
        b: &Block,
        span: Span,
        text: &str,
        g: &mut Vec<String>,
    ) -> Result<(), Error> {
        let seconds = b.dwell.map_or(0.0, |d| d.0);
        let (Some(code), Some(form)) = (self.code(Function::Dwell), self.tlex.dwell) else {
            return Err(refuse(
                span,
                format!(
                    "{text} (a dwell): {} has no dwell word in threadcut's lexicon",
                    self.to.name
                ),
            ));
        };
        let s = post::number(seconds, 3, false);
        g.push(code);
        g.push(match form {
            DwellForm::XSecondsOrPMilliseconds => format!("X{s}"),
            DwellForm::PSeconds | DwellForm::PSecondsOrMilliseconds => format!("P{s}"),
            DwellForm::FSeconds => format!("F{s}"),
        });
        Ok(())
    }

    /// The largest spindle speed, in the target's form.
    fn limit(
        &mut self,
        v: f64,
        span: Span,
        g: &mut Vec<String>,
        notes: &mut Vec<String>,
    ) -> Result<(), Error> {
        match self.tlex.spindle_limit {
            Some(LimitForm::Code) => {
                let code = self
                    .code(Function::SpindleLimit)
                    .ok_or_else(|| refuse(span, "no spindle-limit code".into()))?;
                if !g.contains(&code) {
                    g.push(code);
                }
                g.push(format!("S{}", Self::speed(v)));
            }
            Some(LimitForm::Setting(name)) => g.push(format!("{name}={}", Self::speed(v))),
            Some(LimitForm::OnSurfaceSpeed(_)) => {
                self.pending_limit = Some(v);
                notes.push(format!(
                    "spindle limit {} rpm: written on the next constant-surface-speed block, if any",
                    Self::speed(v)
                ));
            }
            None => {
                if self.css {
                    return Err(refuse(
                        span,
                        format!(
                            "a spindle limit under constant surface speed: {} has no spindle-limit word in threadcut's lexicon",
                            self.to.name
                        ),
                    ));
                }
                self.unstated_limit = Some(v);
                notes.push(format!(
                    "spindle limit {} rpm not written: {} has no word for it (a faster speed or constant surface speed later is refused)",
                    Self::speed(v),
                    self.to.name
                ));
            }
        }
        Ok(())
    }

    /// The tools a block calls, in the target's form: each (tool, offset) the source's words
    /// amount to, the offset `None` where it stays as it was (a change without an offset).
    fn tools(&mut self, b: &Block, tail: &mut Vec<String>) -> Result<(), Error> {
        if b.tools.is_empty() && !b.has(Function::ToolChange) && !b.has(Function::ToolOffsetOff) {
            return Ok(());
        }
        // A bare T selects the tool at once (with its first cutting edge) where the source has no
        // tool change to wait for; otherwise it prepares the next change.
        let immediate = self.source_tool == ToolForm::ToolAndEdge;
        let mut calls: Vec<(u32, Option<u32>, bool, Span)> = Vec::new();
        let mut current = self.tool;
        let selected = self.selections(b, immediate)?;
        if let Some((span, _)) = b
            .functions
            .iter()
            .find(|(f, _, _)| *f == Function::ToolChange)
            .map(|(_, s, t)| (*s, t.clone()))
        {
            let tool = self
                .prepared
                .ok_or_else(|| refuse(span, "a tool change without a tool prepared".into()))?;
            current = Some(tool);
            calls.push((tool, None, true, span));
        }
        let has_edge = b.tools.iter().any(|t| matches!(t, ToolTerm::Edge { .. }));
        if let Some((tool, span)) = selected {
            current = Some(tool);
            if !has_edge {
                calls.push((tool, Some(self.own_offset(tool)), true, span));
            }
        }
        for t in &b.tools {
            match t {
                ToolTerm::Select { .. } | ToolTerm::Name { .. } => {}
                ToolTerm::Call { tool, offset, span } => {
                    current = Some(*tool);
                    calls.push((*tool, Some(*offset), true, *span));
                }
                ToolTerm::Edge { edge, span } => {
                    let tool = current
                        .ok_or_else(|| refuse(*span, "a cutting edge before any tool".into()))?;
                    let offset = match edge {
                        0 => 0,
                        1 => self.own_offset(tool),
                        e => {
                            return Err(refuse(
                                *span,
                                format!("D{e}: threadcut converts a tool's first cutting edge (D1) as the tool's own offset, and no other"),
                            ))
                        }
                    };
                    calls.push((tool, Some(offset), selected.is_some(), *span));
                }
                ToolTerm::Offset { register, span } => {
                    let tool = current.ok_or_else(|| {
                        refuse(*span, "a tool offset before any tool change".into())
                    })?;
                    calls.push((tool, Some(register.unwrap_or(tool)), false, *span));
                }
            }
        }
        if let Some((span, _)) = b
            .functions
            .iter()
            .find(|(f, _, _)| *f == Function::ToolOffsetOff)
            .map(|(_, s, t)| (*s, t.clone()))
        {
            calls.push((current.unwrap_or(0), Some(0), false, span));
        }
        // One call per tool: a change and an offset in one block are one tool call.
        let mut merged: Vec<(u32, Option<u32>, bool, Span)> = Vec::new();
        for c in calls {
            match merged.last_mut() {
                Some(last) if last.0 == c.0 => {
                    last.1 = c.1.or(last.1);
                    last.2 |= c.2;
                }
                _ => merged.push(c),
            }
        }
        for (tool, offset, change, span) in merged {
            let offset = offset.unwrap_or(self.offset);
            self.write_tool(tool, offset, change, span, tail)?;
            self.tool = Some(tool);
            self.offset = offset;
        }
        Ok(())
    }

    /// The tool a block selects by number or by name: selected at once where `immediate` (the
    /// last one), else prepared for the next change. A name is its number from the tool map.
    fn selections(&mut self, b: &Block, immediate: bool) -> Result<Option<(u32, Span)>, Error> {
        let mut selected = None;
        for t in &b.tools {
            let (tool, span) = match t {
                ToolTerm::Select { tool, span } => {
                    self.named = None;
                    (*tool, *span)
                }
                ToolTerm::Name { name, span } => {
                    let n = self.names.by_name(name).ok_or_else(|| {
                        refuse_with(
                            *span,
                            format!(
                                "the tool is called by its name {name}: {} selects tools by number",
                                self.to.name
                            ),
                            format!("give its number: --tool {name}=T0101 (tool 1, offset 1), or the target profile's [tools] table (docs/translation.md, \"Tools by name\")"),
                        )
                    })?;
                    self.named = Some((n.tool, n.offset));
                    (n.tool, *span)
                }
                _ => continue,
            };
            if immediate {
                selected = Some((tool, span));
            } else {
                self.prepared = Some(tool);
            }
        }
        Ok(selected)
    }

    /// The offset a tool's first cutting edge applies: the one its name's number gives where
    /// it was called by name, else its own.
    fn own_offset(&self, tool: u32) -> u32 {
        match self.named {
            Some((t, offset)) if t == tool => offset,
            _ => tool,
        }
    }

    fn write_tool(
        &mut self,
        tool: u32,
        offset: u32,
        change: bool,
        span: Span,
        tail: &mut Vec<String>,
    ) -> Result<(), Error> {
        if let (ToolForm::ToolAndEdge, Some(n)) = (self.tlex.tool, self.names.by_tool(tool)) {
            // The tool by its name: its first cutting edge is the offset its number gives.
            let edge = if offset == n.offset {
                "D1"
            } else if offset == 0 {
                "D0"
            } else {
                return Err(refuse(
                    span,
                    format!(
                        "tool {tool} with offset {offset}: tool {tool} is named {} with offset {} (its first cutting edge, D1), and threadcut writes no other edge for it",
                        n.name, n.offset
                    ),
                ));
            };
            tail.push(format!("T=\"{}\"", n.name));
            tail.push(edge.into());
            return Ok(());
        }
        match self.tlex.tool {
            ToolForm::Combined { digits } => {
                tail.push(format!("T{tool:02}{offset:0width$}", width = digits as usize));
            }
            ToolForm::Single if offset == tool => tail.push(format!("T{tool}")),
            ToolForm::ToolAndEdge if offset == tool => {
                tail.push(format!("T{tool}"));
                tail.push("D1".into());
            }
            ToolForm::ToolAndEdge if offset == 0 => {
                tail.push(format!("T{tool}"));
                tail.push("D0".into());
            }
            ToolForm::ChangeAndOffset => {
                if change {
                    tail.push(format!("T{tool}"));
                    if let Some(m6) = self.code(Function::ToolChange) {
                        tail.push(m6);
                    }
                }
                let (on, off) = (
                    self.code(Function::ToolOffset),
                    self.code(Function::ToolOffsetOff),
                );
                match (offset, on, off) {
                    (0, _, Some(off)) => tail.push(off),
                    (o, Some(on), _) if o == tool => tail.push(on),
                    (o, Some(on), _) => {
                        tail.push(on);
                        tail.push(format!("H{o}"));
                    }
                    _ => {}
                }
            }
            _ => {
                return Err(refuse(
                    span,
                    format!(
                        "tool {tool} with offset {offset}: {} applies a tool's own offset with it and no other",
                        self.to.name
                    ),
                ))
            }
        }
        Ok(())
    }

    /// A threading cycle: through the model, in the output units (the lead's rounding stated when
    /// the units change), native where a candidate reads back, else plain moves or a refusal.
    pub fn cycle(&mut self, line: &Line, mut job: Job, comment: &str) -> Result<(), Error> {
        self.comment_only(comment)?;
        let source_units = job.units;
        if !self.tlex.has_units(job.units) {
            job.units = self.out_units;
        }
        let rule = translate::DriftRule {
            max: self.max_lead_drift,
            source_units,
        };
        let translate::Outcome {
            written,
            drift,
            settings,
        } = translate::write_job_for(
            self.out,
            self.to,
            &job,
            &rule,
            translate::SettingsRule::NotAssumed,
        )?;
        if let Some(drift) = drift {
            self.report.warnings.push(drift.warning(&job));
        }
        for s in settings {
            if !self.report.settings.iter().any(|r| r.name == s.name) {
                self.report.settings.push(s);
            }
        }
        match written {
            Written::Native => self.report.native += 1,
            Written::Plain(why) => self.report.plain.push((line.number, why)),
        }
        self.prev = Position::at(job.end_point());
        self.in_run = false;
        if self.format.lead_letter == 'F' {
            self.target_f = None;
        }
        Ok(())
    }
}
