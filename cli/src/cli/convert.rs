//! `threadcut convert FILE --from C1 --to C2`: a program for one controller rewritten for another.
//!
//! * Each threading cycle goes through the model and [`threadcut::translate::write_job`]: the target's
//!   native cycle when reading it back reproduces the motion, plain moves with a comment otherwise.
//! * Other blocks are rewritten word by word where the words mean the same thing on both controllers:
//!   positions become absolute in the target's X convention (diameter or radius; U/W, G91, G7/G8 are
//!   absorbed), numbers always carry a decimal point, the synchronised move becomes the target's
//!   (G32 F ↔ G33 K, with the lead converted between "along the longer axis" and "along the path").
//!   A word with no counterpart is an error at its line and column. Details: `docs/translation.md`.

use std::io::Write;

use threadcut::diag::{Code, Diagnostic};
use threadcut::dialect;
use threadcut::gcode::reader::g_code;
use threadcut::gcode::{Line, Modal, MotionMode, PlainMove};
use threadcut::machine::Machine;
use threadcut::post::{self, path_lead, Format};
use threadcut::program::{self, Error, Event, Summary};
use threadcut::toolpath::{self, MotionKind};
use threadcut::translate;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Family {
    /// Fanuc system A and its copies (GSK): G32 F, U/W, G98/G99, G50.
    Fanuc,
    /// LinuxCNC: G33 K, G90/G91, G7/G8, G94/G95.
    LinuxCnc,
}

fn family(m: &Machine) -> Family {
    if m.dialect == "linuxcnc" {
        Family::LinuxCnc
    } else {
        Family::Fanuc
    }
}

/// What a G code (×10) of the source becomes on the target: `Ok(Some(code))`, `Ok(None)` when the
/// rewrite absorbs it (distance and diameter modes), `Err` when it has no counterpart.
fn map_g(code: u16, from: Family, to: Family) -> Result<Option<u16>, ()> {
    use Family::*;
    let thread = |f: Family| if f == Fanuc { 320 } else { 330 };
    Ok(Some(match (code, from) {
        (0 | 10 | 20 | 30 | 40 | 170 | 180 | 190 | 200 | 210 | 400 | 410 | 420 | 960 | 970, _) => {
            code
        }
        (540..=590, _) => code,
        (320, Fanuc) | (330, LinuxCnc) => thread(to),
        (980, Fanuc) => {
            if to == Fanuc {
                980
            } else {
                940
            }
        }
        (990, Fanuc) => {
            if to == Fanuc {
                990
            } else {
                950
            }
        }
        (940, LinuxCnc) => {
            if to == Fanuc {
                980
            } else {
                940
            }
        }
        (950, LinuxCnc) => {
            if to == Fanuc {
                990
            } else {
                950
            }
        }
        (70 | 80 | 900 | 910, LinuxCnc) => return Ok(None),
        (500 | 280, Fanuc) if to == Fanuc => code,
        _ => return Err(()),
    }))
}

fn g_text(code: u16) -> String {
    if code.is_multiple_of(10) {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

pub fn convert(
    input: Box<dyn std::io::BufRead>,
    out: &mut dyn Write,
    from: &Machine,
    to: &Machine,
    options: &program::Options,
) -> Result<Summary, Error> {
    let target = dialect::open(to).map_err(Error::Setup)?;
    let tformat = target.format();
    let tname = target.name();
    let source = dialect::open(from).map_err(Error::Setup)?;
    let sname = source.name();
    drop((target, source));
    let same = from == to;
    // The block rewriting below knows Fanuc's G-code system A only (G32, G50, U/W); a system B or
    // C machine would get blocks it reads otherwise. Refused until conversion lives in the library.
    for m in [from, to] {
        if let Some(system) = m
            .fanuc
            .as_ref()
            .map(|p| p.gcode_system)
            .filter(|s| *s != threadcut::machine::GCodeSystem::A)
        {
            if !same {
                return Err(Error::Setup(format!(
                    "convert does not rewrite Fanuc G-code system {system:?} blocks yet (profile `{}`); expand and passes read it",
                    m.name
                )));
            }
        }
    }
    let (ff, tf) = (family(from), family(to));
    // A header before the first line that is not a `%` delimiter: what was converted, and for
    // LinuxCNC the modes the rewritten positions assume (absolute, the profile's X convention).
    let mut header = Vec::new();
    if let Some(c) = tformat.comment(&format!("threadcut convert: {sname} to {tname}")) {
        header.push(c);
    }
    if tf == Family::LinuxCnc && !same {
        header.push(format!("G90 {}", if to.diameter_x { "G7" } else { "G8" }));
    }
    let mut converter = Converter {
        out,
        to,
        same,
        ff,
        tf,
        tformat,
        tname,
        flatten: options.flatten,
        header: Some(header),
        pending_f: None,
        unrun: Vec::new(),
    };
    let summary = program::run_output(input, from, options, &mut converter)?;
    converter.after_end()?;
    Ok(summary)
}

/// `convert`'s side of a run.
struct Converter<'o> {
    out: &'o mut dyn Write,
    to: &'o Machine,
    same: bool,
    ff: Family,
    tf: Family,
    tformat: Format,
    tname: &'static str,
    flatten: bool,
    header: Option<Vec<String>>,
    /// Where the target's thread move writes its lead with F (Fanuc, GSK), F is also the feed
    /// rate: after thread moves whose F differs from the source's F register, the next other
    /// block gets the source's F back, so a later G1 does not feed at the lead.
    pending_f: Option<String>,
    /// The lines after the program's end (not run).
    unrun: Vec<u8>,
}

impl Converter<'_> {
    fn header(&mut self, line: &Line) -> Result<(), Error> {
        if !line.shape.percent {
            if let Some(h) = self.header.take() {
                for l in h {
                    writeln!(self.out, "{l}")?;
                }
            }
        }
        Ok(())
    }

    /// The lines after the program's end: the same controller's copied; for another
    /// controller, blank lines, comments and `%` are copied, a line with words is an error (with
    /// `--flatten`, which writes what runs, it is left out).
    fn after_end(&mut self) -> Result<(), Error> {
        if self.same {
            self.out.write_all(&self.unrun)?;
            return Ok(());
        }
        for raw in self.unrun.split_inclusive(|&b| b == b'\n') {
            let text: Vec<u8> = strip_comments(raw);
            let t = text.trim_ascii();
            if t.is_empty() || t == b"%" {
                self.out.write_all(raw)?;
            } else if !self.flatten {
                return Err(Error::Input(
                    Diagnostic::error(
                        Code::Unsupported,
                        threadcut::diag::Span::new(0, 0, 0, 0),
                        format!(
                            "`{}` follows the program's end (M2/M30): it is not run, and threadcut does not rewrite it for {}",
                            String::from_utf8_lossy(raw.trim_ascii()),
                            self.tname
                        ),
                    )
                    .with_hint("--flatten writes only what the program runs"),
                ));
            }
        }
        Ok(())
    }

    fn plain(&mut self, modal: &Modal, line: &Line, mv: Option<PlainMove>) -> Result<(), Error> {
        if line.words.is_empty() {
            self.out.write_all(line.raw)?;
            return Ok(());
        }
        let threading = mv.is_some_and(|m| m.mode == MotionMode::Thread);
        if !threading {
            if let Some(f) = self.pending_f.take() {
                if line.word(b'F').is_none() {
                    writeln!(self.out, "{f}")?;
                }
            }
        }
        let (text, lead) = block(line, mv, modal, self.ff, self.tf, &self.tformat, self.tname)?;
        writeln!(self.out, "{text}")?;
        if let Some(lead) = lead {
            self.pending_f = restore_f(&self.tformat, modal, lead);
        }
        Ok(())
    }

    fn cycle(&mut self, modal: &Modal, job: &threadcut::thread::Job) -> Result<(), Error> {
        if let Some(f) = self.pending_f.take() {
            writeln!(self.out, "{f}")?;
        }
        let written = translate::write_job(self.out, self.to, job)?;
        // The F register after the cycle: the native cycle's F, or the last plain thread move's.
        let last = match written {
            translate::Written::Native => Some(job.lead.lead),
            translate::Written::Plain(_) => toolpath::build(job)?
                .segments()
                .filter_map(|(from, m)| match m.kind {
                    MotionKind::Thread { lead, .. } => Some(if self.tformat.lead_along_path {
                        path_lead(lead, m.to.minus(from))
                    } else {
                        lead
                    }),
                    _ => None,
                })
                .last(),
        };
        if let Some(lead) = last {
            self.pending_f = restore_f(&self.tformat, modal, modal.units.from_mm(lead));
        }
        Ok(())
    }
}

impl program::Output for Converter<'_> {
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        let line = match &ev {
            Event::Plain { line, .. } | Event::Settings { line } | Event::Cycle { line, .. } => {
                line
            }
        };
        self.header(line)?;
        match ev {
            // Same controller: every line, cycles included, is already right.
            Event::Plain { line, .. } | Event::Settings { line } | Event::Cycle { line, .. }
                if self.same =>
            {
                self.out.write_all(line.raw)?;
                Ok(())
            }
            Event::Plain { line, mv } => self.plain(modal, line, mv),
            Event::Settings { .. } => Ok(()),
            Event::Cycle { job, .. } => self.cycle(modal, &job),
        }
    }

    fn unrun(&mut self, text: &[u8]) -> Result<(), Error> {
        self.unrun.extend_from_slice(text);
        Ok(())
    }

    fn interpreting(&mut self, line: u32) -> Result<(), Error> {
        if self.same || self.flatten {
            return Ok(());
        }
        Err(Error::Input(
            Diagnostic::error(
                Code::Unsupported,
                threadcut::diag::Span::new(0, 0, line, 1),
                format!(
                    "the program has control flow from line {line} on (subroutines, loops or parameters), which threadcut does not rewrite for {}",
                    self.tname
                ),
            )
            .with_hint("--flatten writes the executed program as straight-line code for the target"),
        ))
    }

    fn interpreted(&mut self, modal: &Modal, ev: Event, at: &program::Where) -> Result<(), Error> {
        if !self.flatten {
            // The same controller's program is copied as it is (interpreted_end).
            return Ok(());
        }
        if self.same {
            let line = match &ev {
                Event::Plain { line, .. }
                | Event::Settings { line }
                | Event::Cycle { line, .. } => line,
            };
            self.header(line)?;
            program::write_executed_block(self.out, line, at.verbatim, modal)?;
            return Ok(());
        }
        self.event(modal, ev)
    }

    fn interpreted_end(
        &mut self,
        text: &threadcut::interp::Text,
        from: usize,
    ) -> Result<(), Error> {
        if self.same && !self.flatten {
            self.out.write_all(text.bytes_from(from))?;
        }
        Ok(())
    }
}

/// A line's text without its comments.
fn strip_comments(raw: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(raw.len());
    let mut depth = false;
    for &b in raw {
        match b {
            b'(' => depth = true,
            b')' => depth = false,
            b';' if !depth => break,
            _ if !depth => out.push(b),
            _ => {}
        }
    }
    out
}

#[allow(clippy::too_many_arguments)]
fn block(
    line: &Line,
    mv: Option<PlainMove>,
    modal: &Modal,
    from: Family,
    to: Family,
    tformat: &Format,
    tname: &str,
) -> Result<(String, Option<f64>), Error> {
    let cannot = |span, what: String| {
        Error::Input(
            Diagnostic::error(Code::Unsupported, span, what)
                .with_hint("rewrite this block by hand for the target, or remove it"),
        )
    };
    let units = modal.units;
    let nd = tformat.decimals[(units == threadcut::units::Units::Inch) as usize];
    let num = |v: f64| post::number(v, nd, false);
    let mut words: Vec<String> = Vec::new();
    let mut thread = false;
    let mut dwell = false;
    let mut home = false;
    for w in line.words.iter().filter(|w| w.letter == b'G') {
        let code = g_code(w.value)
            .ok_or_else(|| cannot(w.span, format!("G{} is not a G code", w.value)))?;
        match map_g(code, from, to) {
            Ok(Some(c)) => {
                thread |= c == 320 || c == 330;
                dwell |= c == 40;
                home |= c == 280;
                words.push(g_text(c));
            }
            Ok(None) => {}
            Err(()) => {
                return Err(cannot(
                    w.span,
                    format!(
                        "{} has no counterpart on {tname} that threadcut can write",
                        g_text(code)
                    ),
                ))
            }
        }
    }
    if let Some(n) = line.word(b'N') {
        words.insert(0, format!("N{}", n.value));
    }
    let in_thread = thread || (modal.motion == MotionMode::Thread && mv.is_some());
    // A move without its motion code relies on the modal one, which a native cycle written before
    // it may have changed on the target: always name it.
    let named = line
        .words
        .iter()
        .any(|w| w.letter == b'G' && matches!(g_code(w.value), Some(0 | 10 | 20 | 30 | 320 | 330)));
    if mv.is_some() && !named {
        let code = match modal.motion {
            MotionMode::Rapid => Some("G0"),
            MotionMode::Feed => Some("G1"),
            MotionMode::ArcCw => Some("G2"),
            MotionMode::ArcCcw => Some("G3"),
            MotionMode::Thread => Some(tformat.thread),
            MotionMode::Cycle => None,
        };
        if let Some(code) = code {
            words.push(code.to_string());
        }
    }
    if modal.motion == MotionMode::Cycle
        && line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'))
    {
        return Err(cannot(
            line.span(),
            "the words of a canned cycle other than threading are not converted".into(),
        ));
    }
    // Positions: absolute, in the target's X convention.
    let has = |l: u8| line.word(l).is_some();
    let x_written = has(b'X') || (from == Family::Fanuc && has(b'U'));
    let z_written = has(b'Z') || (from == Family::Fanuc && has(b'W'));
    if dwell {
        let seconds = match from {
            Family::Fanuc => line
                .word(b'X')
                .or(line.word(b'U'))
                .map(|w| w.value)
                .or(line.word(b'P').map(|p| p.value / 1000.0)),
            Family::LinuxCnc => line.word(b'P').map(|p| p.value),
        };
        if let Some(s) = seconds {
            words.push(match to {
                Family::Fanuc => format!("X{}", post::number(s, 3, false)),
                Family::LinuxCnc => format!("P{}", post::number(s, 3, false)),
            });
        }
    } else if home {
        // A reference return's words are its intermediate point, written as the source wrote
        // them (the target is of the same family).
        for w in line.words {
            if matches!(w.letter, b'X' | b'Z' | b'U' | b'W') {
                words.push(format!(
                    "{}{}",
                    w.letter as char,
                    threadcut::gcode::lexer::show(w.raw(line.text))
                ));
            }
        }
    } else if x_written || z_written {
        // The position after the block, axis by axis: an axis the block names is known unless
        // the block moved it by an increment from an unknown position.
        for (written, known, letters) in [
            (
                x_written,
                modal.position.x.map(|x| tformat.x_word(x, units)),
                b"XU",
            ),
            (z_written, modal.position.z.map(|z| units.from_mm(z)), b"ZW"),
        ] {
            if !written {
                continue;
            }
            match known {
                Some(v) => words.push(format!("{}{}", letters[0] as char, num(v))),
                None => {
                    let w = line
                        .words
                        .iter()
                        .find(|w| letters.contains(&w.letter))
                        .expect("the block names the axis");
                    return Err(cannot(
                        w.span,
                        "an incremental move from an unknown position cannot be rewritten as an absolute one".into(),
                    ));
                }
            }
        }
    }
    let mut lead_written = None;
    if in_thread {
        if let (Some(mv), Some(lead)) = (mv, mv.and_then(|m| m.lead)) {
            // A target whose lead runs along the path needs the path: the start on every axis
            // the block moves.
            if tformat.lead_along_path
                && ((x_written && mv.from.x.is_none()) || (z_written && mv.from.z.is_none()))
            {
                return Err(cannot(
                    line.span(),
                    "a thread move from an unknown position: its lead along the path is not known"
                        .into(),
                ));
            }
            // An axis the block does not name does not move.
            let from = threadcut::units::Pos::new(
                mv.from.x.unwrap_or(mv.to.x),
                mv.from.z.unwrap_or(mv.to.z),
            );
            let d = mv.to.minus(from);
            // `Modal::apply` already gives the lead along the longer axis.
            let model = lead;
            let written = if tformat.lead_along_path {
                path_lead(model, d)
            } else {
                model
            };
            let digits = tformat.lead_decimals[(units == threadcut::units::Units::Inch) as usize];
            lead_written = Some(units.from_mm(written));
            words.push(format!(
                "{}{}",
                tformat.lead_letter,
                post::number(units.from_mm(written), digits, false)
            ));
        }
    }
    for w in line.words {
        // The number as written, without the blanks LinuxCNC allows inside it (`S 1 2 0 0`).
        let text = || {
            if w.is_computed() {
                // A value the program computed (`M#1`): the word as the run used it.
                return format!("{}{}", w.letter as char, post::number(w.value, 6, false));
            }
            let raw: Vec<u8> = w
                .raw(line.text)
                .iter()
                .copied()
                .filter(|b| !matches!(b, b' ' | b'\t' | b'\r'))
                .collect();
            format!(
                "{}{}",
                w.letter as char,
                threadcut::gcode::lexer::show(&raw)
            )
        };
        match w.letter {
            b'G' | b'N' | b'X' | b'Z' => {}
            b'U' | b'W' if from == Family::Fanuc => {}
            b'P' if dwell => {}
            b'M' | b'S' => words.push(text()),
            b'F' if from == Family::Fanuc && in_thread => {}
            b'K' if from == Family::LinuxCnc && in_thread => {}
            b'F' => words.push(format!("F{}", post::number(modal.value(w), 6, false))),
            b'R' if matches!(modal.motion, MotionMode::ArcCw | MotionMode::ArcCcw) => {
                words.push(format!("R{}", num(modal.value(w))))
            }
            b'T' | b'O' if from == to => words.push(text()),
            // A Fanuc program number is a subroutine label on LinuxCNC: kept as a comment.
            b'O' => {
                if let Some(c) = tformat.comment(&format!("program {}", text())) {
                    words.push(c);
                }
            }
            _ => {
                return Err(cannot(
                    w.span,
                    format!(
                    "{} means something else on {tname}, or nothing: threadcut does not rewrite it",
                    text()
                ),
                ))
            }
        }
    }
    let comments = comments(line.text);
    if !comments.is_empty() {
        if let Some(c) = tformat.comment(&comments) {
            words.push(c);
        }
    }
    Ok((words.join(" "), lead_written))
}

/// The `F…` block that gives the F register back its source value after a thread move that wrote
/// `lead` (program units) with F, when the two differ.
fn restore_f(tformat: &Format, modal: &Modal, lead: f64) -> Option<String> {
    if tformat.lead_letter != 'F' {
        return None;
    }
    let f = modal.f_word?;
    let digits = tformat.lead_decimals[(modal.units == threadcut::units::Units::Inch) as usize];
    let want = post::number(f, 6, false);
    let have = post::number(lead, digits, false);
    (post::number(f, digits, false) != have).then(|| format!("F{want}"))
}

/// The text of a line's comments: `(…)` groups and a `;` tail.
fn comments(text: &[u8]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < text.len() {
        match text[i] {
            b'(' => {
                let end = text[i..]
                    .iter()
                    .position(|&c| c == b')')
                    .map_or(text.len(), |p| i + p);
                parts.push(
                    String::from_utf8_lossy(&text[i + 1..end])
                        .trim()
                        .to_string(),
                );
                i = end + 1;
            }
            b';' => {
                parts.push(String::from_utf8_lossy(&text[i + 1..]).trim().to_string());
                break;
            }
            _ => i += 1,
        }
    }
    parts.retain(|p| !p.is_empty());
    parts.join("; ")
}
