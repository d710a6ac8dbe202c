//! What the front ends compile a program into: flat instructions with jumps (one evaluator loop
//! for every construct of both languages), blocks whose words may hold expressions, and the
//! tables calls and jumps look things up in. Where each instruction came from is kept beside the
//! instructions, not in them.

use std::collections::HashMap;

use crate::diag::{Diagnostic, Span};

use super::expr::{Expr, Exprs, Lang};
use super::text::Text;

/// One instruction.
#[derive(Clone, Debug)]
pub enum Inst {
    /// The instruction's line is a plain block: lexed when it runs and executed as the run loop
    /// executes any line.
    Plain,
    /// A block with computed words and/or parameter settings: `blocks[i]`.
    Block(u32),
    Jump(u32),
    /// Jumps when the condition is false (if, while).
    JumpUnless {
        cond: Expr,
        target: u32,
    },
    /// Jumps when the condition is true (LinuxCNC's do … while).
    JumpIf {
        cond: Expr,
        target: u32,
    },
    /// Fanuc `GOTO n`: the sequence number is looked up when it runs, in program `program`.
    Goto {
        target: Expr,
        program: u32,
    },
    /// Fanuc `IF [c] GOTO n`.
    IfGoto {
        cond: Expr,
        target: Expr,
        program: u32,
    },
    /// A LinuxCNC `repeat [n]`: sets the loop's count (slot `slot` of the frame).
    RepeatStart {
        count: Expr,
        slot: u32,
    },
    /// The top of a repeat loop: leaves it (to `exit`) when the count is spent.
    RepeatTest {
        slot: u32,
        exit: u32,
    },
    /// A call: `calls[i]`.
    Call(u32),
    /// LinuxCNC `endsub`/`return` (with its optional value), Fanuc `M99`.
    Return {
        value: Option<Expr>,
        to_label: Option<Expr>,
    },
    /// The program ends (M2, M30, the closing `%`).
    End,
    /// The start of another program (Fanuc `O1000` after the main program): the program running
    /// into it has ended; a subprogram must have returned before it.
    NextProgram,
    /// GSK's `G65 Hm P#i Q#j R#k` operation: `ops[i]`.
    MacroOp(u32),
    /// A line that cannot run: its error, raised when it is reached.
    Fail(u32),
    /// Does nothing (a `do`, a label of its own).
    Nop,
}

/// A word of a block: a number as written, or an expression.
#[derive(Clone, Debug)]
pub enum WordValue {
    /// As the lexer would give it: the value, whether written with a decimal point, and where the
    /// number starts after the letter.
    Lit {
        value: f64,
        has_dot: bool,
        skip: u32,
    },
    Expr(Expr),
}

#[derive(Clone, Debug)]
pub struct BlockWord {
    pub letter: u8,
    pub value: WordValue,
    /// The letter and what follows it, as written.
    pub span: Span,
}

/// Where a parameter setting writes.
#[derive(Clone, Debug)]
pub enum Target {
    /// `#n`, `#[…]`: the number's expression.
    Number(Expr),
    /// LinuxCNC `#<name>` (index into the program's names); Sinumerik, a variable declared
    /// before.
    Named(u32),
    /// Sinumerik `DEF … NAME=…`: declares the name in the running program (its frame).
    Declare(u32),
}

#[derive(Clone, Debug)]
pub struct Assign {
    pub target: Target,
    pub value: Expr,
    pub span: Span,
}

/// A block of words (and, in LinuxCNC, parameter settings that take effect after the line's values
/// are read).
#[derive(Clone, Debug, Default)]
pub struct Block {
    pub words: Vec<BlockWord>,
    pub assigns: Vec<Assign>,
    pub block_delete: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CallKind {
    /// LinuxCNC `o… call [args]`: #1–#30 are the arguments, restored on return.
    OWord,
    /// Fanuc `M98 P…`: a subprogram; the same local variables.
    M98,
    /// Fanuc `G65 P… args`: a macro; a new level of local variables #1–#33.
    G65,
    /// Sinumerik: a subprogram (`PROC NAME(params)`) called by name; its parameters and DEF
    /// variables are its own.
    Proc,
    /// Sinumerik's `REPEAT`/`REPEATB` with labels: a section of the same program run again,
    /// with the same variables.
    Section,
}

#[derive(Clone, Debug)]
pub enum CallTarget {
    /// A LinuxCNC subroutine by name (`o<name>`, or the number as text).
    Name(u32),
    /// A LinuxCNC subroutine whose number is computed (`o[#1] call`).
    Number(Expr),
    /// A Fanuc program number (P), and for M98's packed form whether the count is packed in it.
    Program { number: Expr, packed: bool },
    /// A sequence number in Fanuc-style program `program` (Haas's local subprogram, `M97 P…`).
    Label { label: Expr, program: u32 },
    /// A section of the program: its first instruction and the one after its last.
    Section { first: u32, end: u32 },
}

#[derive(Clone, Debug)]
pub struct Call {
    pub kind: CallKind,
    pub target: CallTarget,
    /// LinuxCNC: `[a] [b] …`; G65: the argument words (letter, value).
    pub args: Vec<Expr>,
    pub arg_letters: Vec<(u8, Span)>,
    /// G65: which arguments were written as numbers without a decimal point.
    pub arg_no_point: Vec<bool>,
    /// How many times (L).
    pub count: Option<Expr>,
    /// The call word (for errors).
    pub span: Span,
}

/// GSK's `G65 Hm P#i Q#j R#k` operation.
#[derive(Clone, Debug)]
pub struct MacroOp {
    pub h: u32,
    /// The variable written (P#i), for operations that write one.
    pub dest: Option<Expr>,
    /// P as a sequence number (jumps), Q and R as values.
    pub p: Option<Expr>,
    pub q: Option<Expr>,
    pub r: Option<Expr>,
    pub span: Span,
    pub program: u32,
}

/// A Fanuc program held in the text: the main program (number 0 when it has none) or a
/// subprogram after it.
#[derive(Clone, Debug)]
pub struct ProgramInfo {
    pub number: Option<u32>,
    /// First and one-past-last instruction.
    pub first: u32,
    pub end: u32,
    /// Sequence number → its instructions, in order.
    pub labels: HashMap<u32, Vec<u32>>,
}

/// A compiled program.
pub struct Code {
    pub lang: Lang,
    pub text: Text,
    pub exprs: Exprs,
    pub insts: Vec<Inst>,
    /// The text line (index) of each instruction.
    pub inst_line: Vec<u32>,
    /// The first instruction of each text line.
    pub line_inst: Vec<u32>,
    pub blocks: Vec<Block>,
    pub calls: Vec<Call>,
    /// The calls that read a turning cycle's contour (Sinumerik's CYCLE95 NPP): their subprogram
    /// or section is the cycle's profile, and its end is told to the host.
    pub profiles: Vec<u32>,
    pub ops: Vec<MacroOp>,
    pub failures: Vec<Diagnostic>,
    /// LinuxCNC subroutines, Sinumerik PROCs: name → first instruction of the body.
    pub subs: HashMap<u32, u32>,
    /// Sinumerik PROCs: name → the names of their parameters, in order.
    pub params: HashMap<u32, Vec<u32>>,
    /// Fanuc programs; `programs[0]` is the main program.
    pub programs: Vec<ProgramInfo>,
    /// How many repeat slots a frame needs.
    pub repeat_slots: u32,
    /// How the dialect writes its lines (bare letters, LinuxCNC's blanks and nested comments):
    /// plain lines are lexed as the streamed run lexes them.
    pub lexer: crate::gcode::Syntax,
}

impl Code {
    pub fn new(lang: Lang, text: Text, lexer: crate::gcode::Syntax) -> Code {
        let lines = text.len();
        Code {
            lang,
            text,
            exprs: Exprs::default(),
            insts: Vec::new(),
            inst_line: Vec::new(),
            line_inst: Vec::with_capacity(lines),
            blocks: Vec::new(),
            calls: Vec::new(),
            profiles: Vec::new(),
            ops: Vec::new(),
            failures: Vec::new(),
            subs: HashMap::new(),
            params: HashMap::new(),
            programs: Vec::new(),
            repeat_slots: 0,
            lexer,
        }
    }

    /// Appends an instruction for text line `line`; returns its index.
    pub fn emit(&mut self, line: usize, inst: Inst) -> u32 {
        let at = self.insts.len() as u32;
        self.insts.push(inst);
        self.inst_line.push(line as u32);
        at
    }

    /// The index the next instruction will have.
    pub fn here(&self) -> u32 {
        self.insts.len() as u32
    }

    /// Marks the start of text line `line`'s instructions (call before emitting them).
    pub fn start_line(&mut self, line: usize) {
        debug_assert_eq!(self.line_inst.len(), line);
        self.line_inst.push(self.here());
    }

    pub fn fail(&mut self, line: usize, d: Diagnostic) -> u32 {
        let i = self.failures.len() as u32;
        self.failures.push(d);
        self.emit(line, Inst::Fail(i))
    }

    /// Replaces instruction `at` by a failure (a construct found open or broken later).
    pub fn fail_at(&mut self, at: u32, d: Diagnostic) {
        let i = self.failures.len() as u32;
        self.failures.push(d);
        self.insts[at as usize] = Inst::Fail(i);
    }

    /// Sets the target of the jump at `at`.
    pub fn patch(&mut self, at: u32, to: u32) {
        match &mut self.insts[at as usize] {
            Inst::Jump(t)
            | Inst::JumpUnless { target: t, .. }
            | Inst::JumpIf { target: t, .. }
            | Inst::RepeatTest { exit: t, .. } => *t = to,
            _ => {}
        }
    }

    /// The text line number of instruction `at`.
    pub fn line_number(&self, at: u32) -> u32 {
        self.text.line(self.inst_line[at as usize] as usize).number
    }
}
