//! The evaluator: runs a compiled program one instruction at a time, keeps the parameters and the
//! call stack, and hands every executed block to its host (the run loop, which reads it with the
//! dialect and the modal state exactly as it reads a line of a straight-line program).

use std::collections::HashMap;

use crate::diag::{Code as DiagCode, Diagnostic, Span};
use crate::gcode::{lex_line_syntax, Modal, Word};
use crate::units::Units;

use super::code::{Block, Call, CallKind, CallTarget, Code, Inst, MacroOp, Target, WordValue};
use super::expr::{whole, Budget, Expr, Lang, Vars};
use super::library::{Missing, Wanted};
use super::text::TextLine;
use super::{Limits, Linked, Syntax};

/// What the evaluator needs from the run loop.
pub trait Host {
    type Error: From<Diagnostic>;
    /// Executes one block: `words` are evaluated, their spans point into `line`.
    fn block(
        &mut self,
        line: TextLine<'_>,
        words: &[Word],
        block_delete: bool,
        ctx: &Context,
    ) -> Result<(), Self::Error>;
    /// The modal state (for the parameters that report it: `#<_x>`, `#5001`).
    fn modal(&self) -> &Modal;
    /// A machining centre's position, X Y Z in program units in the work coordinate system,
    /// each axis known or not: the position parameters then read these three axes (Fanuc's
    /// `#5001`–`#5003`, LinuxCNC's `#5420`–`#5422` and `#<_x>` `#<_y>` `#<_z>`) rather than a
    /// lathe's X and Z. `None` (the default): a lathe.
    fn mill_position(&self) -> Option<[Option<f64>; 3]> {
        None
    }
    /// The input resolution in the current units (Fanuc rounds computed lengths to it).
    fn resolution(&self, units: Units) -> f64;
    fn warn(&mut self, d: Diagnostic);
    /// An error raised inside called programs: `calls` are the lines of the calls, outermost
    /// first (the host records them on the error's diagnostic).
    fn in_calls(&self, e: Self::Error, _calls: &[Span]) -> Self::Error {
        e
    }
    /// After a block: the o-word subroutine (its number) the block asks to be run as a profile
    /// (LinuxCNC's G70/G71/G72 `Q`): its blocks are read, not executed, until it returns.
    fn profile_call(&mut self) -> Option<f64> {
        None
    }
    /// The profile subroutine returned; `line` is the block that called it, `end` the one that
    /// returned.
    fn profile_end(&mut self, _line: TextLine<'_>, _end: TextLine<'_>) -> Result<(), Self::Error> {
        Ok(())
    }
    /// The parameters the lines before the interpreter's first set (Sinumerik's `R1`, a DEF
    /// name), as the dialect keeps them.
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    /// A parameter the program set: the dialect keeps it too, for the lines it reads itself
    /// (and `--flatten` writes it, for the lines it copies as written).
    fn set_parameter(&mut self, _name: &str, _value: f64) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// Where a block runs.
pub struct Context<'a> {
    /// The lines of the calls it runs inside, outermost first.
    pub callers: &'a [u32],
    /// The same calls' lines as spans (their files named by their offsets).
    pub calls: &'a [Span],
    /// The block is its line exactly as written (a plain line): its text may be copied as it is.
    pub verbatim: bool,
    /// The line is in the control's own syntax, unread: the dialect reads it.
    pub unread: bool,
}

/// How a run ended.
#[derive(Debug, Default)]
pub struct Outcome {
    /// Blocks and statements executed.
    pub executed: u64,
    /// Calls run (of subroutines and subprograms; a call repeated by L counts once).
    pub calls: u64,
}

struct Frame {
    kind: CallKind,
    /// The call instruction (the run goes on after it), in the caller's unit.
    call: u32,
    /// The caller's unit ([`Linked::units`]): the run returns to it.
    unit: u32,
    /// The first instruction of the called body (for repeats).
    entry: u32,
    /// Passes of the body still to run after this one (M98 L, G65 L).
    remaining: u64,
    /// LinuxCNC: #1–#30 of the caller.
    saved: Option<Box<[f64; 30]>>,
    /// LinuxCNC: named parameters local to this call.
    named: HashMap<u32, f64>,
    /// LinuxCNC: counts of the repeat loops running in this call.
    repeats: Vec<i64>,
    /// A profile read for a turning cycle ([`Host::profile_call`]).
    profile: bool,
}

impl Frame {
    fn new(kind: CallKind, call: u32, entry: u32, slots: u32) -> Frame {
        Frame {
            kind,
            call,
            unit: 0,
            entry,
            remaining: 0,
            saved: None,
            named: HashMap::new(),
            repeats: vec![0; slots as usize],
            profile: false,
        }
    }
}

/// LinuxCNC's numbered parameters: 1 to 5601 (RS274NGC_MAX_PARAMETERS is 5602).
const NGC_PARAMETERS: usize = 5602;

/// The parameters.
struct State {
    lang: Lang,
    /// LinuxCNC numbered parameters (index 0 unused).
    params: Vec<f64>,
    /// LinuxCNC global named parameters.
    globals: HashMap<u32, f64>,
    /// Fanuc local variables, one set per macro level (#1–#33; index 0 unused).
    locals: Vec<[Option<f64>; 34]>,
    /// Fanuc common variables #100–#199 and #500–#999 (indexed by number − 100), and where the
    /// control has them ([`Syntax::wide_commons`]) #10000–#10999 after them (number − 9100).
    commons: Vec<Option<f64>>,
    wide_commons: bool,
    /// The value a LinuxCNC subroutine returned, if it returned one.
    value: Option<f64>,
    line_number: u32,
    /// Sinumerik: the parameters set since the host was last told.
    changed: Vec<(Changed, f64)>,
}

/// A Sinumerik parameter the program set.
#[derive(Clone, Copy)]
enum Changed {
    R(i64),
    Name(u32),
}

/// The state and the frames, seen by an expression.
struct View<'a> {
    state: &'a mut State,
    frame: &'a mut Frame,
    modal: &'a Modal,
    /// A machining centre's X, Y, Z ([`Host::mill_position`]).
    mill: Option<[Option<f64>; 3]>,
    names: &'a [String],
}

impl Vars for View<'_> {
    fn get(&mut self, n: i64, span: Span) -> Result<Option<f64>, Diagnostic> {
        match self.state.lang {
            Lang::Ngc => {
                if n < 1 || n as usize >= NGC_PARAMETERS {
                    return Err(Diagnostic::error(
                        DiagCode::OutOfRange,
                        span,
                        "Parameter number out of range",
                    ));
                }
                if let (Some(m), 5420..=5422) = (self.mill, n) {
                    return Ok(Some(mill_axis(m, (n - 5420) as usize, span)?));
                }
                Ok(Some(match n {
                    5420 => position(self.modal, span, true)?,
                    5422 => position(self.modal, span, false)?,
                    _ => self.state.params[n as usize],
                }))
            }
            Lang::Sinumerik => match self.state.commons.get(n as usize) {
                Some(Some(v)) if n >= 0 => Ok(Some(*v)),
                Some(None) if n >= 0 => Err(Diagnostic::error(
                    DiagCode::Unsupported,
                    span,
                    format!(
                        "R{n} is not set earlier in this program: its value lives on the control"
                    ),
                )
                .with_hint(format!("set it before it is used, e.g. `R{n}=1.5`"))),
                _ => Err(r_out_of_range(n, span)),
            },
            Lang::MacroB => match n {
                0 => Ok(None),
                1..=33 => Ok(self.state.locals.last().and_then(|l| l[n as usize])),
                100..=199 | 500..=999 => Ok(self.state.commons[n as usize - 100]),
                10_000..=10_999 if self.state.wide_commons => {
                    Ok(self.state.commons[n as usize - 10_000 + 900])
                }
                // A machining centre's X, Y, Z are axes 1 to 3 (#5001–#5003, #5041–#5043).
                5001..=5003 | 5041..=5043 if self.mill.is_some() => Ok(Some(mill_axis(
                    self.mill.unwrap_or_default(),
                    (n % 10 - 1) as usize,
                    span,
                )?)),
                // Position of the block's end point, X as the program writes it (#5001, #5041
                // and the other axes' numbers: X is axis 1 and Z axis 2 on a two-axis lathe).
                5001 | 5041 => Ok(Some(program_x(self.modal, span)?)),
                5002 | 5042 => Ok(Some(position(self.modal, span, false)?)),
                _ => Err(unknown_variable(n, span)),
            },
        }
    }

    fn named(&mut self, name: u32, span: Span) -> Result<f64, Diagnostic> {
        let text = &self.names[name as usize];
        if self.state.lang == Lang::Sinumerik {
            return self
                .frame
                .named
                .get(&name)
                .copied()
                .ok_or_else(|| undeclared(text, span));
        }
        if let Some(v) = self.frame.named.get(&name) {
            return Ok(*v);
        }
        if let Some(v) = self.state.globals.get(&name) {
            return Ok(*v);
        }
        if let (Some(m), Some(axis)) =
            (self.mill, ["_x", "_y", "_z"].iter().position(|a| a == text))
        {
            return mill_axis(m, axis, span);
        }
        if let Some(v) = predefined(text, self.modal, self.state, span)? {
            return Ok(v);
        }
        Err(Diagnostic::error(
            DiagCode::MissingWord,
            span,
            format!("Named parameter #<{text}> not defined"),
        ))
    }

    fn exists(&mut self, name: u32) -> bool {
        self.frame.named.contains_key(&name)
            || self.state.globals.contains_key(&name)
            || is_predefined(&self.names[name as usize])
    }
}

/// Sinumerik's R parameters threadcut keeps: R0–R999 (machine data 28050 sets how many a control
/// has; 100 as delivered).
const R_PARAMETERS: usize = 1000;

fn r_out_of_range(n: i64, span: Span) -> Diagnostic {
    Diagnostic::error(
        DiagCode::OutOfRange,
        span,
        format!("R{n} is not an R parameter threadcut keeps (alarm 12550, name not defined)"),
    )
    .with_hint("threadcut keeps R0 to R999")
}

fn undeclared(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(
        DiagCode::MissingWord,
        span,
        format!(
            "{name} is not a variable declared in this program (alarm 12550, name not defined)"
        ),
    )
    .with_hint(format!(
        "declare it with `DEF REAL {name}` in the program or subprogram that uses it"
    ))
}

fn unknown_variable(n: i64, span: Span) -> Diagnostic {
    Diagnostic::error(
        DiagCode::OutOfRange,
        span,
        format!("#{n} is not a variable threadcut keeps (alarm PS0115, variable number out of range)"),
    )
    .with_hint("threadcut simulates #0, the local variables #1–#33, the common variables #100–#199 and #500–#999, and the positions #5001/#5002 (#5041/#5042)")
}

fn unknown_position(span: Span, axis: &str) -> Diagnostic {
    Diagnostic::error(
        DiagCode::UnknownPosition,
        span,
        format!("the tool's {axis} is not known here"),
    )
    .with_hint("position the tool with G0 X.. Z.. before reading its position")
}

/// The position on one axis in program units (X as a radius when `x`, Z otherwise): the axis must
/// be known, whatever the other (the position is kept axis by axis).
fn position(modal: &Modal, span: Span, x: bool) -> Result<f64, Diagnostic> {
    let (axis, name) = if x {
        (modal.position.x, "X")
    } else {
        (modal.position.z, "Z")
    };
    let v = axis.ok_or_else(|| unknown_position(span, name))?;
    Ok(modal.units.from_mm(v))
}

/// X as the program writes it (a diameter on a diameter machine).
fn program_x(modal: &Modal, span: Span) -> Result<f64, Diagnostic> {
    let x = modal
        .position
        .x
        .ok_or_else(|| unknown_position(span, "X"))?;
    Ok(modal.x_from_mm(x))
}

/// One axis (0 X, 1 Y, 2 Z) of a machining centre's position: it must be known.
fn mill_axis(m: [Option<f64>; 3], axis: usize, span: Span) -> Result<f64, Diagnostic> {
    m[axis].ok_or_else(|| unknown_position(span, ["X", "Y", "Z"][axis]))
}

const PREDEFINED: &[&str] = &[
    "_value",
    "_value_returned",
    "_x",
    "_y",
    "_z",
    "_metric",
    "_imperial",
    "_absolute",
    "_incremental",
    "_lathe_diameter_mode",
    "_lathe_radius_mode",
    "_feed",
    "_line",
];

fn is_predefined(name: &str) -> bool {
    PREDEFINED.contains(&name)
}

/// LinuxCNC's predefined named parameters that threadcut's modal state answers.
fn predefined(
    name: &str,
    modal: &Modal,
    state: &State,
    span: Span,
) -> Result<Option<f64>, Diagnostic> {
    let flag = |b: bool| Some(if b { 1.0 } else { 0.0 });
    Ok(match name {
        "_value" => Some(state.value.unwrap_or(0.0)),
        "_value_returned" => flag(state.value.is_some()),
        // In a lathe configuration #<_x> is always a radius (overview.adoc).
        "_x" => Some(position(modal, span, true)?),
        "_z" => Some(position(modal, span, false)?),
        "_metric" => flag(modal.units == Units::Mm),
        "_imperial" => flag(modal.units == Units::Inch),
        "_absolute" => flag(modal.absolute),
        "_incremental" => flag(!modal.absolute),
        "_lathe_diameter_mode" => flag(modal.diameter_x),
        "_lathe_radius_mode" => flag(!modal.diameter_x),
        "_feed" => Some(modal.f_word.unwrap_or(0.0)),
        "_line" => Some(f64::from(state.line_number)),
        _ => None,
    })
}

/// The evaluator of one program.
pub struct Vm<'c> {
    /// The code running now: `units[unit]`.
    code: &'c Code,
    units: &'c [Code],
    unit: u32,
    external: &'c HashMap<Wanted, Result<(u32, u32), Missing>>,
    syntax: Syntax,
    limits: Limits,
    state: State,
    frames: Vec<Frame>,
    /// Line numbers of the calls being run (for [`Context`]).
    callers: Vec<u32>,
    /// The calls' lines as spans.
    calls: Vec<Span>,
    /// Calls run so far.
    called: u64,
    stack: Vec<Option<f64>>,
    words: Vec<Word>,
    budget: Budget,
    executed: u64,
    /// Sinumerik's sections being repeated (`REPEAT LABEL P=n`), innermost last.
    sections: Vec<Section>,
    /// The last backward jump: the loop's first line and the line that jumped.
    last_loop: Option<(u32, u32)>,
}

type R<T, E> = Result<T, E>;

impl<'c> Vm<'c> {
    pub fn new(linked: &'c Linked, syntax: Syntax, limits: Limits) -> Vm<'c> {
        let code = &linked.units[0];
        let lang = code.lang;
        Vm {
            code,
            units: &linked.units,
            unit: 0,
            external: &linked.external,
            syntax,
            limits,
            state: State {
                lang,
                params: if lang == Lang::Ngc {
                    vec![0.0; NGC_PARAMETERS]
                } else {
                    Vec::new()
                },
                globals: HashMap::new(),
                locals: vec![[None; 34]],
                commons: match lang {
                    Lang::MacroB if syntax.wide_commons => vec![None; 1900],
                    Lang::MacroB => vec![None; 900],
                    Lang::Sinumerik => vec![None; R_PARAMETERS],
                    Lang::Ngc => Vec::new(),
                },
                wide_commons: syntax.wide_commons,
                value: None,
                line_number: 0,
                changed: Vec::new(),
            },
            frames: vec![Frame::new(CallKind::OWord, 0, 0, code.repeat_slots)],
            callers: Vec::new(),
            calls: Vec::new(),
            called: 0,
            stack: Vec::new(),
            words: Vec::new(),
            budget: Budget {
                steps_left: limits.max_blocks.saturating_mul(STEPS_PER_BLOCK),
            },
            executed: 0,
            sections: Vec::new(),
            last_loop: None,
        }
    }

    /// Runs from instruction `start` to the program's end.
    pub fn run<H: Host>(mut self, start: u32, host: &mut H) -> R<Outcome, H::Error> {
        if self.code.lang == Lang::Sinumerik {
            self.take_parameters(host);
        }
        let mut pc = start;
        loop {
            if !self.sections.is_empty() {
                pc = self.section_end(pc, host)?;
            }
            let Some(inst) = self.code.insts.get(pc as usize) else {
                self.end_of_text(pc)?;
                break;
            };
            self.executed += 1;
            if self.executed > self.limits.max_blocks || self.budget.steps_left == 0 {
                return Err(self.too_long(pc).into());
            }
            self.state.line_number = self.code.line_number(pc);
            let unit = self.unit;
            let step = match self.step(pc, inst, host) {
                Ok(step) => step,
                Err(e) if !self.calls.is_empty() => return Err(host.in_calls(e, &self.calls)),
                Err(e) => return Err(e),
            };
            match step {
                Next::Go(to) => {
                    // (A call or a return between files is no loop.)
                    if to <= pc && unit == self.unit {
                        self.last_loop =
                            Some((self.code.line_number(to), self.code.line_number(pc)));
                    }
                    pc = to;
                }
                Next::Stop => break,
            }
        }
        Ok(Outcome {
            executed: self.executed,
            calls: self.called,
        })
    }

    /// Sinumerik: the R parameters and DEF variables the lines before the interpreter set.
    fn take_parameters<H: Host>(&mut self, host: &H) {
        for (name, v) in host.parameters() {
            let r = name.strip_prefix('R').and_then(|n| n.parse::<usize>().ok());
            match r {
                Some(n) if n < R_PARAMETERS => self.state.commons[n] = Some(v),
                Some(_) => {}
                None => {
                    if let Some(id) = self.code.exprs.find(&name) {
                        self.frames[0].named.insert(id, v);
                    }
                }
            }
        }
    }

    /// Tells the host the parameters the last block set (Sinumerik).
    fn tell<H: Host>(&mut self, host: &mut H) -> Result<(), H::Error> {
        for (which, v) in std::mem::take(&mut self.state.changed) {
            match which {
                Changed::R(n) => host.set_parameter(&format!("R{n}"), v)?,
                Changed::Name(id) => host.set_parameter(self.code.exprs.name(id), v)?,
            }
        }
        Ok(())
    }

    fn line(&self, pc: u32) -> TextLine<'c> {
        self.code
            .text
            .line(self.code.inst_line[pc as usize] as usize)
    }

    fn step<H: Host>(&mut self, pc: u32, inst: &Inst, host: &mut H) -> R<Next, H::Error> {
        let next = Next::Go(pc + 1);
        Ok(match inst {
            Inst::Nop => next,
            Inst::Plain => {
                self.plain(pc, host)?;
                self.profile_call(pc, host)?.unwrap_or(next)
            }
            Inst::Block(b) => {
                self.block(pc, &self.code.blocks[*b as usize], host)?;
                self.profile_call(pc, host)?.unwrap_or(next)
            }
            Inst::Jump(t) => Next::Go(*t),
            Inst::JumpUnless { cond, target } => {
                if self.truth(*cond, host)? {
                    next
                } else {
                    Next::Go(*target)
                }
            }
            Inst::JumpIf { cond, target } => {
                if self.truth(*cond, host)? {
                    Next::Go(*target)
                } else {
                    next
                }
            }
            Inst::Goto { target, program } => Next::Go(self.goto(pc, *target, *program, host)?),
            Inst::IfGoto {
                cond,
                target,
                program,
            } => {
                if self.truth(*cond, host)? {
                    Next::Go(self.goto(pc, *target, *program, host)?)
                } else {
                    next
                }
            }
            Inst::RepeatStart { count, slot } => {
                let n = self.eval(*count, host)?.unwrap_or(0.0);
                let frame = self.frames.last_mut().expect("main frame");
                // LinuxCNC rounds the count to an integer.
                frame.repeats[*slot as usize] = n.round().clamp(-1e18, 1e18) as i64;
                next
            }
            Inst::RepeatTest { slot, exit } => {
                let frame = self.frames.last_mut().expect("main frame");
                let left = &mut frame.repeats[*slot as usize];
                if *left > 0 {
                    *left -= 1;
                    next
                } else {
                    Next::Go(*exit)
                }
            }
            Inst::Call(c) => {
                let profile = self.code.profiles.contains(c);
                self.call(pc, &self.code.calls[*c as usize], profile, host)?
            }
            Inst::Return { value, to_label } => self.ret(pc, *value, *to_label, host)?,
            // Sinumerik: a program called as a subprogram (a file without PROC) returns at its
            // end code (M17, M2, M30, RET) as a subprogram does.
            Inst::End if self.code.lang == Lang::Sinumerik && self.frames.len() > 1 => {
                self.ret(pc, None, None, host)?
            }
            Inst::End => Next::Stop,
            Inst::NextProgram => {
                if self.frames.len() > 1 {
                    return Err(self.no_return(pc).into());
                }
                Next::Stop
            }
            Inst::MacroOp(i) => self.macro_op(pc, &self.code.ops[*i as usize], host)?,
            Inst::Fail(i) => return Err(self.code.failures[*i as usize].clone().into()),
        })
    }

    /// The text ended: fine in the main program, an error in a subprogram.
    fn end_of_text(&self, pc: u32) -> Result<(), Diagnostic> {
        if self.frames.len() > 1 {
            let last = self.code.insts.len().saturating_sub(1) as u32;
            return Err(self.no_return(pc.min(last)));
        }
        Ok(())
    }

    fn no_return(&self, pc: u32) -> Diagnostic {
        let call = self.callers.last().copied().unwrap_or(0);
        Diagnostic::error(
            DiagCode::Syntax,
            self.line(pc).whole(),
            match self.code.lang {
                Lang::Ngc => "the subroutine ends without endsub".to_string(),
                Lang::MacroB => format!(
                    "the subprogram called at line {call} runs into the next program without M99"
                ),
                Lang::Sinumerik => {
                    format!("the subprogram called at line {call} ends without RET or M17")
                }
            },
        )
        .with_hint(match self.code.lang {
            Lang::Sinumerik => "end a subprogram with RET or M17",
            _ => "end a subprogram with M99",
        })
    }

    fn too_long(&self, pc: u32) -> Diagnostic {
        let what = match self.last_loop {
            Some((first, last)) if first != last => {
                format!("the loop of lines {first} to {last}")
            }
            Some((first, _)) => format!("the loop of line {first}"),
            None => "the program".to_string(),
        };
        let span = match self
            .last_loop
            .and_then(|(first, _)| self.code.text.index_of(first))
        {
            Some(i) => self.code.text.line(i).whole(),
            None => self.line(pc).whole(),
        };
        let limit = if self.executed > self.limits.max_blocks {
            format!("{} executed blocks", self.limits.max_blocks)
        } else {
            "the evaluation budget of its expressions".to_string()
        };
        Diagnostic::error(
            DiagCode::OutOfRange,
            span,
            format!("{what} ran past {limit}: is it an endless loop?"),
        )
        .with_hint(format!(
            "threadcut stops a program after --max-blocks executed blocks ({} now); raise it if the program really runs this long",
            self.limits.max_blocks
        ))
    }

    fn view<'a>(
        &'a mut self,
        modal: &'a Modal,
        mill: Option<[Option<f64>; 3]>,
    ) -> (View<'a>, &'a mut Vec<Option<f64>>, &'a mut Budget) {
        let frame = self.frames.last_mut().expect("main frame");
        (
            View {
                state: &mut self.state,
                frame,
                modal,
                mill,
                names: &self.code.exprs.names,
            },
            &mut self.stack,
            &mut self.budget,
        )
    }

    fn eval<H: Host>(&mut self, e: Expr, host: &H) -> Result<Option<f64>, Diagnostic> {
        let code = self.code;
        let (mut view, stack, budget) = self.view(host.modal(), host.mill_position());
        code.exprs.eval(e, code.lang, &mut view, stack, budget)
    }

    fn truth<H: Host>(&mut self, e: Expr, host: &H) -> Result<bool, Diagnostic> {
        Ok(self.eval(e, host)?.is_some_and(|v| v != 0.0))
    }

    fn plain<H: Host>(&mut self, pc: u32, host: &mut H) -> R<(), H::Error> {
        let line = self.line(pc);
        let shape = match lex_line_syntax(
            line.text,
            line.number,
            line.offset,
            &mut self.words,
            &self.code.lexer,
        ) {
            Ok(shape) => shape,
            // A line in the control's own syntax: the dialect reads it.
            Err(_) if self.code.lexer.hand_over_unread => {
                return host.block(
                    line,
                    &[],
                    false,
                    &Context {
                        callers: &self.callers,
                        calls: &self.calls,
                        verbatim: true,
                        unread: true,
                    },
                );
            }
            Err(e) => return Err(e.into()),
        };
        if self.words.is_empty() {
            return Ok(());
        }
        let words = std::mem::take(&mut self.words);
        let r = host.block(
            line,
            &words,
            shape.block_delete,
            &Context {
                callers: &self.callers,
                calls: &self.calls,
                verbatim: true,
                unread: false,
            },
        );
        self.words = words;
        r
    }

    fn block<H: Host>(&mut self, pc: u32, b: &Block, host: &mut H) -> R<(), H::Error> {
        let line = self.line(pc);
        let mut words = std::mem::take(&mut self.words);
        words.clear();
        let r = if self.code.lang == Lang::Sinumerik {
            // Sinumerik's settings come before the block's addresses (the front end refuses a
            // setting written after an address it could change).
            let r = self.assign(&b.assigns, host);
            self.tell(host)?;
            r.and_then(|()| self.evaluate_words(b, host, &mut words))
        } else {
            let r = self.evaluate_words(b, host, &mut words);
            r.and_then(|()| self.assign(&b.assigns, host))
        };
        let r = match r {
            Ok(()) if !words.is_empty() => host.block(
                line,
                &words,
                b.block_delete,
                &Context {
                    callers: &self.callers,
                    calls: &self.calls,
                    verbatim: false,
                    unread: false,
                },
            ),
            Ok(()) => Ok(()),
            Err(e) => Err(e.into()),
        };
        self.words = words;
        r
    }

    /// The block's words with their values; a Fanuc word whose variable is vacant is left out (the
    /// address is as if not written).
    fn evaluate_words<H: Host>(
        &mut self,
        b: &Block,
        host: &H,
        words: &mut Vec<Word>,
    ) -> Result<(), Diagnostic> {
        for w in &b.words {
            match &w.value {
                WordValue::Lit {
                    value,
                    has_dot,
                    skip,
                } => words.push(Word::literal(w.letter, *value, *has_dot, w.span, *skip)),
                WordValue::Expr(e) => {
                    if let Some(v) = self.eval(*e, host)? {
                        let v = self.address_value(w.letter, v, host);
                        words.push(Word::computed(w.letter, v, w.span));
                    }
                }
            }
        }
        Ok(())
    }

    /// Fanuc uses a variable's value in an address rounded to the address's precision: lengths
    /// to the least input increment, codes and counts to whole numbers (docs/dialects/fanuc.md).
    /// LinuxCNC uses the value as it is.
    fn address_value<H: Host>(&self, letter: u8, v: f64, host: &H) -> f64 {
        if self.code.lang == Lang::Ngc {
            return v;
        }
        match letter {
            b'X' | b'Z' | b'U' | b'W' | b'I' | b'K' | b'R' => {
                // Rounded in decimal: 19.4 stays the double nearest 19.4.
                let per_unit = (1.0 / host.resolution(host.modal().units)).round();
                (v * per_unit).round() / per_unit
            }
            b'M' | b'S' | b'T' | b'L' | b'H' | b'D' | b'N' | b'O' => v.round(),
            _ => v,
        }
    }

    /// Parameter settings: every value is read first, then all are stored (LinuxCNC sets them in
    /// parallel, after the line's values are read).
    fn assign<H: Host>(
        &mut self,
        assigns: &[super::code::Assign],
        host: &H,
    ) -> Result<(), Diagnostic> {
        if assigns.is_empty() {
            return Ok(());
        }
        let mut values = Vec::with_capacity(assigns.len());
        for a in assigns {
            let target = match &a.target {
                Target::Number(e) => {
                    let n = self.eval(*e, host)?;
                    Err(whole(self.code.lang, n, self.code.exprs.span(*e))?)
                }
                Target::Named(id) | Target::Declare(id) => Ok(*id),
            };
            let v = self.eval(a.value, host)?;
            values.push((target, v, a.span));
        }
        for ((target, v, span), a) in values.into_iter().zip(assigns) {
            match target {
                Err(n) => self.store(n, v, span)?,
                Ok(name) if self.code.lang == Lang::Sinumerik => {
                    let declare = matches!(a.target, Target::Declare(_));
                    self.store_variable(name, v.unwrap_or(0.0), declare, span)?
                }
                Ok(name) => self.store_named(name, v.unwrap_or(0.0), span)?,
            }
        }
        Ok(())
    }

    /// Sinumerik: a DEF variable of the running program (declared by `declare`).
    fn store_variable(
        &mut self,
        name: u32,
        v: f64,
        declare: bool,
        span: Span,
    ) -> Result<(), Diagnostic> {
        let frame = self.frames.last_mut().expect("main frame");
        if !declare && !frame.named.contains_key(&name) {
            return Err(undeclared(self.code.exprs.name(name), span));
        }
        frame.named.insert(name, v);
        self.state.changed.push((Changed::Name(name), v));
        Ok(())
    }

    fn store(&mut self, n: i64, v: Option<f64>, span: Span) -> Result<(), Diagnostic> {
        match self.code.lang {
            Lang::Sinumerik => {
                if n < 0 || n as usize >= R_PARAMETERS {
                    return Err(r_out_of_range(n, span));
                }
                let v = v.unwrap_or(0.0);
                self.state.commons[n as usize] = Some(v);
                self.state.changed.push((Changed::R(n), v));
            }
            Lang::Ngc => {
                if n < 1 || n as usize >= NGC_PARAMETERS {
                    return Err(Diagnostic::error(
                        DiagCode::OutOfRange,
                        span,
                        "Parameter number out of range",
                    ));
                }
                if (5420..=5428).contains(&n) {
                    return Err(Diagnostic::error(
                        DiagCode::OutOfRange,
                        span,
                        "Parameter is readonly",
                    ));
                }
                self.state.params[n as usize] = v.unwrap_or(0.0);
            }
            Lang::MacroB => match n {
                1..=33 => {
                    if let Some(l) = self.state.locals.last_mut() {
                        l[n as usize] = v;
                    }
                }
                100..=199 | 500..=999 => self.state.commons[n as usize - 100] = v,
                10_000..=10_999 if self.state.wide_commons => {
                    self.state.commons[n as usize - 10_000 + 900] = v
                }
                3000 => {
                    let n = v.unwrap_or(0.0);
                    return Err(Diagnostic::error(
                        DiagCode::Conflict,
                        span,
                        format!("macro alarm {} (#3000 = {n})", 3000.0 + n),
                    )
                    .with_hint("the program raises this alarm itself"));
                }
                0 | 5001 | 5002 | 5041 | 5042 => {
                    return Err(Diagnostic::error(
                        DiagCode::OutOfRange,
                        span,
                        format!("#{n} cannot be written (alarm PS0116, write protected variable)"),
                    ))
                }
                _ => return Err(unknown_variable(n, span)),
            },
        }
        Ok(())
    }

    fn store_named(&mut self, name: u32, v: f64, span: Span) -> Result<(), Diagnostic> {
        let text = &self.code.exprs.names[name as usize];
        if is_predefined(text) {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                span,
                format!("Cannot assign to read-only parameter #<{text}>"),
            ));
        }
        if text.starts_with('_') {
            self.state.globals.insert(name, v);
        } else {
            self.frames
                .last_mut()
                .expect("main frame")
                .named
                .insert(name, v);
        }
        Ok(())
    }

    /// Fanuc `GOTO n` in program `program`: the block numbered `n`, searched from the next block
    /// to the program's end, then from its start.
    fn goto<H: Host>(
        &mut self,
        pc: u32,
        target: Expr,
        program: u32,
        host: &H,
    ) -> Result<u32, Diagnostic> {
        let span = self.code.exprs.span(target);
        let n = self.eval(target, host)?;
        let n = n.filter(|v| *v >= 0.0 && v.fract() == 0.0 && *v <= 99_999.0);
        let Some(n) = n else {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                span,
                "the sequence number must be a whole number from 1 to 99999 (alarm PS0128)",
            ));
        };
        self.find_label(pc, n as u32, program, span)
    }

    fn find_label(&self, pc: u32, n: u32, program: u32, span: Span) -> Result<u32, Diagnostic> {
        let p = &self.code.programs[program as usize];
        let found = p
            .labels
            .get(&n)
            .and_then(|at| at.iter().find(|&&i| i > pc).or_else(|| at.first()).copied());
        found.ok_or_else(|| {
            let mut d = Diagnostic::error(
                DiagCode::MissingWord,
                span,
                format!("there is no block N{n} in this program (alarm PS0078, sequence number not found)"),
            );
            if program == 0 && self.code.text.line(0).number > 1 {
                d = d.with_hint(format!(
                    "the program's first {} lines were run before its first macro statement and are no longer held (threadcut keeps {} KiB of them)",
                    self.code.text.line(0).number - 1,
                    super::PREFIX_KEPT >> 10
                ));
            }
            d
        })
    }

    /// The subroutine a block asked to read as its profile: called with no arguments, its frame
    /// marked so that its return tells the host.
    fn profile_call<H: Host>(&mut self, pc: u32, host: &mut H) -> Result<Option<Next>, Diagnostic> {
        let Some(q) = host.profile_call() else {
            return Ok(None);
        };
        let line = self.line(pc);
        let name = format!("{q}");
        let entry = self
            .code
            .exprs
            .find(&name)
            .and_then(|id| self.code.subs.get(&id).copied());
        let Some(entry) = entry else {
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                line.whole(),
                format!("EOF seeking o-word: o<{name}> from line: {}", line.number),
            )
            .with_hint(format!(
                "define the profile's subroutine in the file: o{name} sub … o{name} endsub"
            )));
        };
        if self.frames.len() >= self.syntax.max_call_depth as usize {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                line.whole(),
                "Too many subroutine levels",
            ));
        }
        let mut saved = Box::new([0.0; 30]);
        saved.copy_from_slice(&self.state.params[1..31]);
        self.state.params[1..31].fill(0.0);
        self.state.value = None;
        let mut frame = Frame::new(CallKind::OWord, pc, entry, self.code.repeat_slots);
        frame.saved = Some(saved);
        frame.profile = true;
        self.enter(frame, pc, self.unit);
        Ok(Some(Next::Go(entry)))
    }

    /// A call; `profile`: it reads a turning cycle's contour (its end is told to the host).
    fn call<H: Host>(
        &mut self,
        pc: u32,
        call: &Call,
        profile: bool,
        host: &mut H,
    ) -> R<Next, H::Error> {
        match call.kind {
            CallKind::OWord => self.call_oword(pc, call, host).map_err(Into::into),
            CallKind::M98 | CallKind::G65 => self.call_program(pc, call, host).map_err(Into::into),
            CallKind::Proc => self.call_proc(pc, call, profile, host).map_err(Into::into),
            CallKind::Section => self
                .repeat_section(pc, call, profile, host)
                .map_err(Into::into),
        }
    }

    fn call_oword<H: Host>(&mut self, pc: u32, call: &Call, host: &H) -> Result<Next, Diagnostic> {
        let name = match &call.target {
            CallTarget::Name(id) => Some(*id),
            CallTarget::Number(e) => {
                let v = self.eval(*e, host)?;
                let n = whole(Lang::Ngc, v, self.code.exprs.span(*e))?;
                self.code.exprs.find(&n.to_string())
            }
            CallTarget::Program { .. } | CallTarget::Label { .. } | CallTarget::Section { .. } => {
                None
            }
        };
        let own = name.and_then(|id| self.code.subs.get(&id).copied());
        let shown = match (&call.target, name) {
            _ if own.is_some() => String::new(),
            (_, Some(id)) => self.code.exprs.name(id).to_string(),
            (CallTarget::Number(e), None) => {
                let v = self.eval(*e, host)?.unwrap_or(0.0);
                format!("{v}")
            }
            _ => String::new(),
        };
        let found = match own {
            Some(entry) => Some((self.unit, entry)),
            None => self
                .external(&Wanted::Name(shown.clone()), call.span)
                .transpose()?,
        };
        let Some((unit, entry)) = found else {
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                call.span,
                format!(
                    "EOF seeking o-word: o<{shown}> from line: {}",
                    self.line(pc).number
                ),
            )
            .with_hint(format!(
                "define the subroutine in the file: o{shown} sub … o{shown} endsub"
            )));
        };
        // LinuxCNC: call levels 1–9 below the main program (INTERP_SUB_ROUTINE_LEVELS is 10).
        if self.frames.len() >= self.syntax.max_call_depth as usize {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                "Too many subroutine levels",
            )
            .with_hint(format!(
                "LinuxCNC nests subroutine calls {} levels deep, the main program included",
                self.syntax.max_call_depth
            )));
        }
        let mut args = [0.0; 30];
        for (slot, a) in args.iter_mut().zip(&call.args) {
            *slot = self.eval(*a, host)?.unwrap_or(0.0);
        }
        let mut saved = Box::new([0.0; 30]);
        saved.copy_from_slice(&self.state.params[1..31]);
        self.state.params[1..31].copy_from_slice(&args);
        self.state.value = None;
        let mut frame = Frame::new(CallKind::OWord, pc, entry, self.code.repeat_slots);
        frame.saved = Some(saved);
        self.enter(frame, pc, unit);
        Ok(Next::Go(entry))
    }

    fn call_program<H: Host>(
        &mut self,
        pc: u32,
        call: &Call,
        host: &H,
    ) -> Result<Next, Diagnostic> {
        let (number, packed) = match &call.target {
            CallTarget::Program { number, packed } => (number, packed),
            CallTarget::Label { label, program } => {
                return self.call_label(pc, call, *label, *program, host)
            }
            CallTarget::Name(_) | CallTarget::Number(_) | CallTarget::Section { .. } => {
                return Err(Diagnostic::error(
                    DiagCode::Syntax,
                    call.span,
                    "a call without a program number",
                ))
            }
        };
        let p_span = self.code.exprs.span(*number);
        let p = self.eval(*number, host)?.unwrap_or(-1.0);
        if p < 0.0 || p.fract() != 0.0 || p >= 1e8 {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                p_span,
                format!("P{p} is not a program number (alarm PS0076)"),
            ));
        }
        let mut count = self.call_count(call, host)?;
        let mut program = p as u64;
        // The packed form P(count)(program): the last four digits are the program number.
        if *packed && program > 9999 {
            count = program / 10_000;
            program %= 10_000;
        }
        if count == 0 {
            return Ok(Next::Go(pc + 1));
        }
        let own = self
            .code
            .programs
            .iter()
            .find(|info| info.number == Some(program as u32))
            .map(|info| (self.unit, info.first));
        let found = match own {
            Some(at) => Some(at),
            None => self
                .external(&Wanted::Number(program as u32), p_span)
                .transpose()?,
        };
        let Some((unit, entry)) = found else {
            if self.code.lang == Lang::Ngc {
                return Err(Diagnostic::error(
                    DiagCode::MissingWord,
                    p_span,
                    format!(
                        "EOF seeking o-word: o<{program}> from line: {}",
                        self.line(pc).number
                    ),
                )
                .with_hint(format!(
                    "define the numbered program after the main program: o{program} … M99"
                )));
            }
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                p_span,
                format!(
                    "program O{program:04} is not in the file (alarm PS0078, number not found)"
                ),
            )
            .with_hint(format!(
                "put O{program:04} after the main program's end (M30), in the same file"
            )));
        };
        // LinuxCNC counts every call level together (the main program too); Fanuc counts
        // subprogram and macro calls apart.
        let depth = if self.code.lang == Lang::Ngc {
            self.frames.len() as u32
        } else {
            self.frames.iter().filter(|f| f.kind == call.kind).count() as u32
        };
        let (max, what) = match call.kind {
            CallKind::G65 => (self.syntax.max_macro_depth, "macro calls (G65) nest"),
            _ => (self.syntax.max_call_depth, "subprogram calls (M98) nest"),
        };
        if depth >= max {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                match self.code.lang {
                    Lang::Ngc => "Too many subroutine levels".to_string(),
                    Lang::MacroB | Lang::Sinumerik => {
                        format!("{what} at most {max} levels deep (alarm PS0077)")
                    }
                },
            ));
        }
        let mut frame = Frame::new(call.kind, pc, entry, self.code.repeat_slots);
        frame.remaining = count - 1;
        if call.kind == CallKind::G65 {
            let mut locals = [None; 34];
            // Arguments: evaluated in the caller, in order (argument specification I and II).
            let mapped = super::fanuc::argument_slots(&call.arg_letters);
            for (k, e) in call.args.iter().enumerate() {
                let (letter, span) = call.arg_letters[k];
                let mut v = self.eval(*e, host)?;
                // Written without a decimal point: as the machine reads such a number, except in
                // the integer addresses (docs/dialects/fanuc.md).
                if call.arg_no_point[k] && !matches!(letter, b'M' | b'S' | b'T' | b'H' | b'D') {
                    v = v.map(|v| {
                        host.modal()
                            .value(&Word::literal(letter, v, false, span, 0))
                    });
                }
                locals[mapped[k] as usize] = v;
            }
            self.state.locals.push(locals);
        }
        self.enter(frame, pc, unit);
        Ok(Next::Go(entry))
    }

    /// Haas's `M97 P n L k`: the block N n of program `program`, called as a subprogram (its
    /// level counts with M98's; the same local variables).
    fn call_label<H: Host>(
        &mut self,
        pc: u32,
        call: &Call,
        label: Expr,
        program: u32,
        host: &H,
    ) -> Result<Next, Diagnostic> {
        let span = self.code.exprs.span(label);
        let n = self.eval(label, host)?;
        let Some(n) = n.filter(|v| *v >= 0.0 && v.fract() == 0.0 && *v <= 99_999.0) else {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                span,
                "M97's P is a sequence number, a whole number from 1 to 99999",
            ));
        };
        let count = self.call_count(call, host)?;
        if count == 0 {
            return Ok(Next::Go(pc + 1));
        }
        let entry = self.find_label(pc, n as u32, program, span)?;
        let depth = self
            .frames
            .iter()
            .filter(|f| f.kind == CallKind::M98)
            .count() as u32;
        if depth >= self.syntax.max_call_depth {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                format!(
                    "subprogram calls (M97, M98) nest at most {} levels deep",
                    self.syntax.max_call_depth
                ),
            ));
        }
        let mut frame = Frame::new(CallKind::M98, pc, entry, self.code.repeat_slots);
        frame.remaining = count - 1;
        self.enter(frame, pc, self.unit);
        Ok(Next::Go(entry))
    }

    /// A call's count (L; 1 without): a whole number from 0 to 9999.
    /// Sinumerik: `NAME(args) P n`, a PROC of this file called by name; its parameters are
    /// variables of its own, given the arguments' values (by value), 0 when not given.
    fn call_proc<H: Host>(
        &mut self,
        pc: u32,
        call: &Call,
        profile: bool,
        host: &H,
    ) -> Result<Next, Diagnostic> {
        let CallTarget::Name(id) = call.target else {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                call.span,
                "a call without a name",
            ));
        };
        let name = self.code.exprs.name(id).to_string();
        // A PROC of this file, else of a file the include directories hold (`NAME.SPF`): its
        // unit, first instruction and parameters (named in its own unit's code).
        let (unit, entry, params): (u32, u32, Vec<_>) = match self.code.subs.get(&id) {
            Some(&entry) => (
                self.unit,
                entry,
                self.code.params.get(&id).cloned().unwrap_or_default(),
            ),
            None => match self.external(&Wanted::Name(name.clone()), call.span) {
                Some(found) => {
                    let (unit, entry) = found?;
                    let callee = &self.units[unit as usize];
                    let params = callee
                        .exprs
                        .find(&name)
                        .and_then(|p| callee.params.get(&p).cloned())
                        .unwrap_or_default();
                    (unit, entry, params)
                }
                None => {
                    return Err(Diagnostic::error(
                        DiagCode::MissingWord,
                        call.span,
                        format!(
                            "{name} is not a subprogram of this file (alarm 14011, program not available)"
                        ),
                    )
                    .with_hint(format!(
                        "define it after the main program's end (PROC {name} … RET), or give the directory of {name}.SPF with --include"
                    )))
                }
            },
        };
        if call.args.len() > params.len() {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                format!(
                    "{name} takes {} parameters and is given {} (alarm 12340, number of parameters too high)",
                    params.len(),
                    call.args.len()
                ),
            ));
        }
        // The main program and 15 subprogram levels (the levels interrupts take not counted).
        if self.frames.len() >= self.syntax.max_call_depth as usize {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                format!(
                    "subprograms nest at most {} levels deep, the main program counted (alarm 14000)",
                    self.syntax.max_call_depth
                ),
            ));
        }
        let count = self.times(call, host, "P", "a subprogram runs")?;
        let mut frame = Frame::new(CallKind::Proc, pc, entry, self.code.repeat_slots);
        for (k, &param) in params.iter().enumerate() {
            let v = match call.args.get(k) {
                Some(&e) => self.eval(e, host)?.unwrap_or(0.0),
                None => 0.0,
            };
            frame.named.insert(param, v);
        }
        frame.remaining = count - 1;
        frame.profile = profile;
        self.enter(frame, pc, unit);
        Ok(Next::Go(entry))
    }

    /// Sinumerik's repeat count of a call or a section (`P n`, `P=n`; 1 without): a whole number
    /// from 1 to 9999, else an error naming `what` runs (written `word` then the value).
    fn times<H: Host>(
        &mut self,
        call: &Call,
        host: &H,
        word: &str,
        what: &str,
    ) -> Result<u64, Diagnostic> {
        let Some(p) = call.count else {
            return Ok(1);
        };
        let v = self.eval(p, host)?.unwrap_or(1.0);
        if !(1.0..=9999.0).contains(&v) || v.fract() != 0.0 {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                self.code.exprs.span(p),
                format!("{word}{v}: {what} a whole number of times, 1 to 9999"),
            ));
        }
        Ok(v as u64)
    }

    /// `REPEAT LABEL P=n` and its kin: the section runs `n` times (once without P), then the
    /// program goes on after the REPEAT block.
    fn repeat_section<H: Host>(
        &mut self,
        pc: u32,
        call: &Call,
        profile: bool,
        host: &H,
    ) -> Result<Next, Diagnostic> {
        let CallTarget::Section { first, end } = call.target else {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                call.span,
                "a repeat without its section",
            ));
        };
        let count = self.times(call, host, "P=", "a section repeats")?;
        if self.sections.len() >= MAX_SECTIONS {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                call.span,
                format!("sections repeat inside one another at most {MAX_SECTIONS} deep"),
            ));
        }
        self.sections.push(Section {
            call: pc,
            first,
            end,
            remaining: count - 1,
            depth: self.frames.len(),
            profile,
        });
        Ok(Next::Go(first))
    }

    /// Where the run goes at `pc`: on, or, at the end of the section being repeated, back to its
    /// start or after its REPEAT block.
    /// A contour's section that ends is told to the host (its call and its last instruction).
    fn section_end<H: Host>(&mut self, mut pc: u32, host: &mut H) -> R<u32, H::Error> {
        while let Some(s) = self.sections.last_mut() {
            if s.depth != self.frames.len() || s.end != pc {
                break;
            }
            if s.remaining > 0 {
                s.remaining -= 1;
                return Ok(s.first);
            }
            let (call, last, profile) = (s.call, s.end - 1, s.profile);
            pc = call + 1;
            self.sections.pop();
            if profile {
                host.profile_end(self.line(call), self.line(last))?;
            }
        }
        Ok(pc)
    }

    fn call_count<H: Host>(&mut self, call: &Call, host: &H) -> Result<u64, Diagnostic> {
        let Some(l) = call.count else {
            return Ok(1);
        };
        let v = self.eval(l, host)?.unwrap_or(1.0);
        if v < 0.0 || v.fract() != 0.0 || v > 9999.0 {
            return Err(Diagnostic::error(
                DiagCode::OutOfRange,
                self.code.exprs.span(l),
                format!("L{v}: the number of calls must be a whole number from 0 to 9999"),
            ));
        }
        Ok(v as u64)
    }

    fn ret<H: Host>(
        &mut self,
        pc: u32,
        value: Option<Expr>,
        to_label: Option<Expr>,
        host: &mut H,
    ) -> R<Next, H::Error> {
        let v = match value {
            Some(e) => Some(self.eval(e, host)?.unwrap_or(0.0)),
            None => None,
        };
        if self.frames.len() == 1 {
            // Only Fanuc's M99 gets here (LinuxCNC's return outside a subroutine is refused when
            // the program is compiled).
            return Ok(match to_label {
                Some(n) => Next::Go(self.goto(pc, n, 0, host)?),
                None => {
                    host.warn(
                        Diagnostic::warning(
                            DiagCode::Suspicious,
                            self.line(pc).whole(),
                            "M99 in the main program starts it again on the control: threadcut runs it once",
                        )
                        .with_hint("end the main program with M30 when it is not meant to repeat"),
                    );
                    Next::Stop
                }
            });
        }
        let frame = self.frames.last_mut().expect("a called frame");
        if frame.remaining > 0 {
            frame.remaining -= 1;
            let entry = frame.entry;
            let call = self.callers.last().copied().unwrap_or(0);
            self.last_loop = Some((call, self.line(pc).number));
            return Ok(Next::Go(entry));
        }
        let end = self.line(pc);
        let frame = self.frames.pop().expect("a called frame");
        self.callers.pop();
        self.calls.pop();
        self.unit = frame.unit;
        self.code = &self.units[frame.unit as usize];
        if let Some(saved) = frame.saved {
            self.state.params[1..31].copy_from_slice(&saved[..]);
        }
        if frame.kind == CallKind::G65 {
            self.state.locals.pop();
        }
        if self.code.lang == Lang::Ngc {
            self.state.value = v;
        }
        if frame.profile {
            host.profile_end(self.line(frame.call), end)?;
        }
        match to_label {
            Some(n) => {
                let program = self.program_of(frame.call);
                Ok(Next::Go(self.goto(frame.call, n, program, host)?))
            }
            None => Ok(Next::Go(frame.call + 1)),
        }
    }

    /// Runs `frame`, called at instruction `pc`, in unit `unit` (the calling one, or a file's).
    fn enter(&mut self, mut frame: Frame, pc: u32, unit: u32) {
        self.called += 1;
        let line = self.line(pc);
        self.callers.push(line.number);
        self.calls.push(line.whole());
        frame.unit = self.unit;
        if unit != self.unit {
            self.unit = unit;
            self.code = &self.units[unit as usize];
            frame.repeats = vec![0; self.code.repeat_slots as usize];
        }
        self.frames.push(frame);
    }

    /// A program the running text does not hold: where the call found it in another file (its
    /// unit and first instruction), or the error naming what was looked for.
    fn external(&self, wanted: &Wanted, span: Span) -> Option<Result<(u32, u32), Diagnostic>> {
        let found = self.external.get(wanted)?;
        Some(found.clone().map_err(|m| {
            let what = super::what(self.code.lang, wanted);
            let mut d = Diagnostic::error(
                DiagCode::MissingWord,
                span,
                match &m.problem {
                    Some(p) => format!("{what}: {p}"),
                    None => format!("{what} is not in the file nor in the include directories"),
                },
            );
            if !m.tried.is_empty() {
                d = d.with_hint(format!("looked for {}", m.tried.join(", ")));
            }
            d
        }))
    }

    /// The Fanuc program instruction `at` belongs to.
    fn program_of(&self, at: u32) -> u32 {
        self.code
            .programs
            .iter()
            .position(|p| p.first <= at && at < p.end)
            .unwrap_or(0) as u32
    }

    /// GSK's `G65 Hm P#i Q#j R#k`.
    fn macro_op<H: Host>(&mut self, pc: u32, op: &MacroOp, host: &mut H) -> R<Next, H::Error> {
        let value_of = |e: Option<Expr>, vm: &mut Self| match e {
            Some(e) => vm.eval(e, host),
            None => Ok(None),
        };
        let q = value_of(op.q, self)?;
        let r = value_of(op.r, self)?;
        let (j, k) = (q.unwrap_or(0.0), r.unwrap_or(0.0));
        if let Some(taken) = gsk_jump(op.h, j, k) {
            if !taken {
                return Ok(Next::Go(pc + 1));
            }
            let Some(p) = op.p else {
                return Err(Diagnostic::error(
                    DiagCode::MissingWord,
                    op.span,
                    "the jump needs P, the block's sequence number",
                )
                .into());
            };
            return Ok(Next::Go(self.goto(pc, p, op.program, host)?));
        }
        if op.h == 99 {
            let n = value_of(op.p, self)?.unwrap_or(0.0);
            return Err(Diagnostic::error(
                DiagCode::Conflict,
                op.span,
                format!("P/S alarm {} (G65 H99)", 500.0 + n),
            )
            .with_hint("the program raises this alarm itself")
            .into());
        }
        let Some(d) = op.dest else {
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                op.span,
                "the operation needs P#i, the variable it sets",
            )
            .into());
        };
        let n = self.eval(d, host)?;
        let n = whole(Lang::MacroB, n, op.span)?;
        // H26 reads the variable it sets.
        let i = if op.h == 26 {
            self.view(host.modal(), host.mill_position())
                .0
                .get(n, op.span)?
                .unwrap_or(0.0)
        } else {
            0.0
        };
        let value = gsk_value(op.h, i, q, j, k, op.span)?;
        self.store(n, value, op.span)?;
        Ok(Next::Go(pc + 1))
    }
}

/// Whether a GSK jump operation (H80–H86) jumps; `None` for the other operations.
fn gsk_jump(h: u32, j: f64, k: f64) -> Option<bool> {
    Some(match h {
        80 => true,
        81 => j == k,
        82 => j != k,
        83 => j > k,
        84 => j < k,
        85 => j >= k,
        86 => j <= k,
        _ => return None,
    })
}

/// The value GSK's operation `h` sets #i to (#i, #j and #k given; `q` is #j, possibly vacant).
fn gsk_value(
    h: u32,
    i: f64,
    q: Option<f64>,
    j: f64,
    k: f64,
    span: Span,
) -> Result<Option<f64>, Diagnostic> {
    let fail =
        |msg: &str| Diagnostic::error(DiagCode::OutOfRange, span, format!("{msg} (G65 H{h:02})"));
    let bits = |v: f64| v.round() as i64;
    let v = match h {
        1 => return Ok(q),
        2 => j + k,
        3 => j - k,
        4 => j * k,
        5 | 23 | 26 if k == 0.0 => return Err(fail("division by zero")),
        5 => j / k,
        11 => (bits(j) | bits(k)) as f64,
        12 => (bits(j) & bits(k)) as f64,
        13 => (bits(j) ^ bits(k)) as f64,
        21 if j < 0.0 => return Err(fail("square root of a negative number")),
        21 => j.sqrt(),
        22 => j.abs(),
        23 => j - (j / k).trunc() * k,
        24 => return super::expr::unary(Lang::MacroB, super::expr::Func::Bin, q, span),
        25 => return super::expr::unary(Lang::MacroB, super::expr::Func::Bcd, q, span),
        26 => i * j / k,
        27 => (j * j + k * k).sqrt(),
        31 => j * k.to_radians().sin(),
        32 => j * k.to_radians().cos(),
        33 => j * k.to_radians().tan(),
        34 => {
            let d = j.atan2(k).to_degrees();
            if d < 0.0 {
                d + 360.0
            } else {
                d
            }
        }
        _ => {
            return Err(Diagnostic::error(
                DiagCode::Unsupported,
                span,
                format!("G65 H{h:02} is not one of GSK's macro operations"),
            )
            .with_hint("GSK 980TDi: H01–H05, H11–H13, H21–H27, H31–H34, H80–H86, H99"))
        }
    };
    if !v.is_finite() {
        return Err(fail("calculated data overflow"));
    }
    Ok(Some(v))
}

/// What to run next.
/// A section of a Sinumerik program being repeated.
struct Section {
    /// The REPEAT block.
    call: u32,
    first: u32,
    /// The instruction after the section.
    end: u32,
    remaining: u64,
    /// The call level it runs in.
    depth: usize,
    /// It is a turning cycle's contour: its end is told to the host.
    profile: bool,
}

/// How deeply repeated sections nest (a bound on the run's memory).
const MAX_SECTIONS: usize = 64;

enum Next {
    Go(u32),
    Stop,
}

/// How many expression steps a run may take per block it may execute: ample for any real line,
/// and a bound on lines of megabytes run in a loop.
const STEPS_PER_BLOCK: u64 = 64;
