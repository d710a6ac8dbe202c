//! Reading a plain block through the source controller's [`Lexicon`]: its words and codes become
//! a [`Block`] of machine-neutral meanings. Nothing here names a controller.

use crate::diag::{Code as DiagCode, Diagnostic, Result, Span};
use crate::dialect::Dialect;
use crate::gcode::reader::g_code;
use crate::gcode::{Line, Modal, MotionMode, Word};

use crate::dialect::lexicon::{
    Code, DwellForm, Function, Lexicon, LimitForm, Meanings, Term, ToolForm,
};

/// An axis word of the block (its value comes from the modal state, which has applied it).
#[derive(Clone, Copy, Debug)]
pub struct Axis {
    /// The value as written, in program units (and the X convention in force).
    pub value: f64,
    /// U/W, or an X/Z in incremental mode.
    pub incremental: bool,
    pub span: Span,
}

/// What a block says about tools.
#[derive(Clone, Debug, PartialEq)]
pub enum ToolTerm {
    /// A tool with its offset (`T0101`: tool 1, offset 1; `T4`: tool 4 with its own).
    Call { tool: u32, offset: u32, span: Span },
    /// A tool prepared for the next change (LinuxCNC's `T1`), or selected with its first edge
    /// (Sinumerik's `T7`).
    Select { tool: u32, span: Span },
    /// A cutting edge of the current tool (Sinumerik's `D1`; `D0`: none).
    Edge { edge: u32, span: Span },
    /// The tool named, not numbered.
    Name { name: String, span: Span },
    /// The offset applied from a register (LinuxCNC's `G43 H2`); `None`: the current tool's.
    Offset { register: Option<u32>, span: Span },
}

/// One plain block, machine-neutral.
#[derive(Clone, Debug, Default)]
pub struct Block {
    pub n: Option<u32>,
    /// Every code's function with where it is written and how (for messages), in order.
    pub functions: Vec<(Function, Span, String)>,
    pub x: Option<Axis>,
    pub z: Option<Axis>,
    /// F as a feed rate (program units per minute or per revolution).
    pub feed: Option<(f64, Span)>,
    /// S as the spindle speed or surface speed.
    pub speed: Option<(f64, Span)>,
    /// The largest spindle speed (rpm).
    pub limit: Option<(f64, Span)>,
    pub tools: Vec<ToolTerm>,
    /// Seconds.
    pub dwell: Option<(f64, Span)>,
    /// An arc's radius R (program units).
    pub radius: Option<(f64, Span)>,
    /// A program number or name.
    pub program: Option<String>,
    /// Machine-axis words of a reference return (`X1=0`, `Z1=0`).
    pub machine_axes: [Option<Span>; 2],
    /// The line only sets values for later blocks (parameters, declarations, a program header):
    /// the converted blocks carry them, and the line becomes a comment.
    pub data: bool,
    /// The line's comments, joined.
    pub comment: String,
    /// The line is the program's name header (`%_N_NAME_MPF`).
    pub name_line: bool,
}

impl Block {
    /// The block only names the program (a program number and comments, or a name header): a
    /// converted program begins with it, before what it states (docs/translation.md).
    pub fn names_program(&self) -> bool {
        self.name_line
            || (self.program.is_some()
                && self.functions.is_empty()
                && self.x.is_none()
                && self.z.is_none()
                && self.feed.is_none()
                && self.speed.is_none()
                && self.limit.is_none()
                && self.tools.is_empty()
                && self.dwell.is_none()
                && self.radius.is_none()
                && self.machine_axes.iter().all(Option::is_none))
    }

    pub fn has(&self, f: Function) -> bool {
        self.functions.iter().any(|(g, _, _)| *g == f)
    }

    fn take(&mut self, f: Function) -> Option<(Span, String)> {
        let i = self.functions.iter().position(|(g, _, _)| *g == f)?;
        let (_, span, text) = self.functions.remove(i);
        Some((span, text))
    }
}

/// What conversion needs of the source controller.
pub struct Source<'a> {
    pub name: &'a str,
    pub meanings: Meanings,
    pub dialect: &'a dyn Dialect,
    /// U/W are incremental X/Z.
    pub uw_incremental: bool,
    pub canned_cycles: &'static [u16],
    /// `(` opens a comment.
    pub paren_comments: bool,
    /// Names declared with DEF earlier in the program (settings to them are data).
    pub declared: std::collections::HashSet<String>,
}

/// A word or code the source controller has that conversion has no meaning for.
fn meaningless(span: Span, what: String, source: &str) -> Diagnostic {
    Diagnostic::error(
        DiagCode::Unsupported,
        span,
        format!("{what} has no meaning threadcut converts from {source}"),
    )
    .with_hint("rewrite this block by hand for the target, or remove it (docs/translation.md lists what is converted)")
}

/// Reads `line` (which the source's modal reader has applied: `modal` is the state after it).
pub fn decode(line: &Line, src: &mut Source, modal: &Modal) -> Result<Block> {
    let mut block = Block {
        comment: comments(line.text, src.paren_comments),
        ..Block::default()
    };
    let owned: Vec<Word>;
    let words: &[Word] = if line.shape.unread {
        let terms = match src.dialect.terms(line) {
            Some(t) => t?,
            None => Vec::new(),
        };
        owned = own_terms(terms, src, &mut block)?;
        &owned
    } else {
        line.words
    };
    // The block's codes first: a dwell, a thread move and a spindle limit decide what other
    // words mean.
    for w in words {
        read_code(w, src, &mut block)?;
    }
    let sets_position = block.has(Function::SetPosition) || block.has(Function::RestatePosition);
    let reading = Words::after_codes(line, src, modal, &block);
    let mut seen_axis = false;
    for w in words {
        seen_axis |= reading.read(w, &mut block)?;
    }
    settle(&mut block, sets_position, seen_axis);
    Ok(block)
}

/// Records the functions of a G or M word in the block, in order; other words wait for the
/// second reading. Fails on a code the source controller gives no function.
fn read_code(w: &Word, src: &Source, block: &mut Block) -> Result<()> {
    let code = match w.letter {
        b'G' => Code::G(
            g_code(w.value)
                .ok_or_else(|| meaningless(w.span, format!("G{}", w.value), src.name))?,
        ),
        b'M' if w.value.fract() == 0.0 && (0.0..=9999.0).contains(&w.value) => {
            Code::M(w.value as u16)
        }
        b'M' => return Err(meaningless(w.span, format!("M{}", w.value), src.name)),
        _ => return Ok(()),
    };
    let fs: Vec<Function> = src.meanings.functions(code).collect();
    if fs.is_empty() {
        let text = code.text();
        if let Code::G(c) = code {
            if src.canned_cycles.contains(&c) {
                return Err(Diagnostic::error(
                    DiagCode::Unsupported,
                    w.span,
                    format!("{text} is a canned cycle other than threading: threadcut does not convert it"),
                )
                .with_hint("write the cycle's moves out, or convert the threading part only"));
            }
        }
        return Err(meaningless(w.span, text, src.name));
    }
    for f in fs {
        block.functions.push((f, w.span, code.text()));
    }
    Ok(())
}

/// The second reading of a block's words: what its codes and the modal state decided they mean.
struct Words<'a> {
    line: &'a Line<'a>,
    src: &'a Source<'a>,
    modal: &'a Modal,
    /// The block dwells: its dwell word is a time.
    dwell: bool,
    /// A thread move is in force: its own words belong to it.
    thread: bool,
    /// An arc move is in force: R is its radius.
    arc: bool,
    /// The spindle limit is a code in this block: S is the limit.
    limit_code: bool,
}

impl<'a> Words<'a> {
    /// Decides the meanings that the block's codes (already read into `block`) and the modal
    /// motion give the other words.
    fn after_codes(
        line: &'a Line<'a>,
        src: &'a Source<'a>,
        modal: &'a Modal,
        block: &Block,
    ) -> Words<'a> {
        Words {
            line,
            src,
            modal,
            dwell: block.has(Function::Dwell),
            thread: modal.motion == MotionMode::Thread,
            arc: matches!(modal.motion, MotionMode::ArcCw | MotionMode::ArcCcw),
            limit_code: src.meanings.spindle_limit == Some(LimitForm::Code)
                && block.has(Function::SpindleLimit),
        }
    }

    /// Puts one word where its meaning says in `block`; true when it is an X or Z axis word.
    /// Fails on a word the source controller gives no meaning here.
    fn read(&self, w: &Word, block: &mut Block) -> Result<bool> {
        let (lex, src, modal) = (&self.src.meanings, self.src, self.modal);
        let dwell = self.dwell;
        let value = modal.value(w);
        let axis = |incremental: bool| Axis {
            value,
            incremental,
            span: w.span,
        };
        match w.letter {
            b'G' | b'M' => {}
            b'N' => block.n = Some(w.value as u32),
            b'O' if lex.program_number => block.program = Some(self.program(w)),
            b'X' | b'U' if dwell && dwell_word(lex, w.letter) => {
                block.dwell = Some((value, w.span));
            }
            b'P' if dwell && dwell_word(lex, w.letter) => {
                block.dwell = Some((p_dwell(lex, w), w.span));
            }
            b'F' if dwell && dwell_word(lex, w.letter) => block.dwell = Some((w.value, w.span)),
            b'X' => {
                block.x = Some(axis(!modal.absolute));
                return Ok(true);
            }
            b'Z' => {
                block.z = Some(axis(!modal.absolute));
                return Ok(true);
            }
            b'U' if src.uw_incremental => {
                block.x = Some(axis(true));
                return Ok(true);
            }
            b'W' if src.uw_incremental => {
                block.z = Some(axis(true));
                return Ok(true);
            }
            l if self.thread && lex.thread_words.contains(&l) => {}
            b'F' => block.feed = Some((value_of(modal, w), w.span)),
            b'S' if self.limit_code => block.limit = Some((w.value, w.span)),
            b'S' => block.speed = Some((w.value, w.span)),
            b'D' if lex.spindle_limit == Some(LimitForm::OnSurfaceSpeed(b'D')) => {
                block.limit = Some((w.value, w.span))
            }
            b'T' => block.tools.push(tool_word(lex.tool, w)?),
            b'D' if lex.tool == ToolForm::ToolAndEdge => block.tools.push(ToolTerm::Edge {
                edge: whole(w)?,
                span: w.span,
            }),
            b'H' if lex.tool == ToolForm::ChangeAndOffset && block.has(Function::ToolOffset) => {
                block.tools.push(ToolTerm::Offset {
                    register: Some(whole(w)?),
                    span: w.span,
                })
            }
            b'R' if self.arc => block.radius = Some((value, w.span)),
            l => {
                return Err(meaningless(
                    w.span,
                    format!(
                        "{}{}",
                        l as char,
                        crate::post::number(w.value, 6, false).trim_end_matches('.')
                    ),
                    src.name,
                ))
            }
        }
        Ok(false)
    }

    /// The program number of an O word, as written (`O` and its digits).
    fn program(&self, w: &Word) -> String {
        let digits = if self.line.shape.unread {
            format!("{}", w.value)
        } else {
            crate::gcode::lexer::show(w.raw(self.line.text))
        };
        format!("O{digits}")
    }
}

/// Settles the functions that depend on the block's words: a tool offset without its register
/// applies the current tool's; a spindle limit without a value, and a position set or restated
/// without an axis word, say nothing and are dropped.
fn settle(block: &mut Block, sets_position: bool, seen_axis: bool) {
    if let Some((span, _)) = block.take(Function::ToolOffset) {
        if !block
            .tools
            .iter()
            .any(|t| matches!(t, ToolTerm::Offset { .. }))
        {
            block.tools.push(ToolTerm::Offset {
                register: None,
                span,
            });
        }
    }
    if block.has(Function::SpindleLimit) && block.limit.is_none() {
        block.take(Function::SpindleLimit);
    }
    if sets_position && !seen_axis {
        block.take(Function::SetPosition);
        block.take(Function::RestatePosition);
    }
}

/// Whether `letter` carries a dwell's time in this lexicon.
fn dwell_word(lex: &Lexicon, letter: u8) -> bool {
    match lex.dwell {
        Some(DwellForm::XSecondsOrPMilliseconds) => matches!(letter, b'X' | b'U' | b'P'),
        Some(DwellForm::PSeconds | DwellForm::PSecondsOrMilliseconds) => letter == b'P',
        Some(DwellForm::FSeconds) => letter == b'F',
        None => false,
    }
}

/// A dwell's P in seconds.
fn p_dwell(lex: &Lexicon, w: &Word) -> f64 {
    match lex.dwell {
        Some(DwellForm::PSeconds) => w.value,
        Some(DwellForm::PSecondsOrMilliseconds) if w.has_dot => w.value,
        _ => w.value / 1000.0,
    }
}

/// F in program units (the decimal-point convention applied).
fn value_of(modal: &Modal, w: &Word) -> f64 {
    modal.value(w)
}

fn whole(w: &Word) -> Result<u32> {
    if w.value.fract() != 0.0 || w.value < 0.0 || w.value > f64::from(u32::MAX) {
        return Err(Diagnostic::error(
            DiagCode::OutOfRange,
            w.span,
            format!("{}{} is not a whole number", w.letter as char, w.value),
        ));
    }
    Ok(w.value as u32)
}

/// A `T` word as the source writes tools.
fn tool_word(form: ToolForm, w: &Word) -> Result<ToolTerm> {
    let v = whole(w)?;
    Ok(match form {
        ToolForm::Combined { digits } => {
            let scale = 10u32.pow(digits);
            ToolTerm::Call {
                tool: v / scale,
                offset: v % scale,
                span: w.span,
            }
        }
        ToolForm::Single => ToolTerm::Call {
            tool: v,
            offset: v,
            span: w.span,
        },
        ToolForm::ToolAndEdge | ToolForm::ChangeAndOffset => ToolTerm::Select {
            tool: v,
            span: w.span,
        },
    })
}

/// The terms of a line in the source's own syntax: address words come back for the shared loop;
/// keywords, named tools, settings and machine axes are read here.
fn own_terms(terms: Vec<Term>, src: &mut Source, block: &mut Block) -> Result<Vec<Word>> {
    let lex = &src.meanings;
    let mut words = Vec::new();
    for t in terms {
        match t {
            Term::Word(w) => words.push(w),
            Term::Assigned { letter, span } => match letter {
                // Present, its value unknown here: the modal state has the position.
                b'X' | b'Z' => words.push(Word::assigned(letter, f64::NAN, span)),
                l => {
                    return Err(meaningless(
                        span,
                        format!("{}= given by a parameter", l as char),
                        src.name,
                    ))
                }
            },
            Term::Keyword { name, span } => {
                let fs: Vec<Function> = lex
                    .codes
                    .iter()
                    .flat_map(|g| g.iter())
                    .filter(|(c, _)| matches!(c, Code::Keyword(k) if *k == name))
                    .map(|(_, f)| *f)
                    .collect();
                if fs.is_empty() {
                    return Err(meaningless(span, name, src.name));
                }
                for f in fs {
                    block.functions.push((f, span, name.clone()));
                }
            }
            Term::ToolName { name, span } => block.tools.push(ToolTerm::Name { name, span }),
            Term::Setting { name, value, span } => {
                if lex.thread_settings.contains(&name.as_str()) {
                    // The thread moves carry their start angle.
                } else if matches!(lex.spindle_limit, Some(LimitForm::Setting(s)) if s == name) {
                    let v = value.ok_or_else(|| {
                        meaningless(span, format!("{name}= given by a parameter"), src.name)
                    })?;
                    block.limit = Some((v, span));
                } else if src.declared.contains(&name) {
                    block.data = true;
                } else {
                    return Err(meaningless(span, format!("{name}="), src.name));
                }
            }
            Term::MachineAxis { name, span } => {
                let i = if name.starts_with('X') { 0 } else { 1 };
                block.machine_axes[i] = Some(span);
            }
            Term::Data { declares } => {
                src.declared.extend(declares);
                block.data = true;
            }
            Term::Passive { .. } => block.data = true,
            Term::ProgramName => {
                block.data = true;
                block.name_line = true;
            }
            Term::Unknown { what, span } => return Err(meaningless(span, what, src.name)),
        }
    }
    Ok(words)
}

/// A line's text without its comments (`(…)` groups where `(` opens one, and a `;` tail).
pub fn without_comments(raw: &[u8], parens: bool) -> Vec<u8> {
    let mut out = Vec::with_capacity(raw.len());
    let mut inside = false;
    for &b in raw {
        match b {
            b'(' if parens => inside = true,
            b')' if inside => inside = false,
            b';' if !inside => break,
            _ if !inside => out.push(b),
            _ => {}
        }
    }
    out
}

/// The text of a line's comments: `(…)` groups (where `(` opens one) and a `;` tail.
pub fn comments(text: &[u8], parens: bool) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < text.len() {
        match text[i] {
            b'(' if parens => {
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
