//! The machine's state at each pass of a thread: whether the spindle turns and which way, which
//! tool cuts, in which coordinate system — read from each block's codes through the controller's
//! own meanings ([`crate::dialect::lexicon`]), and judged where a thread is cut.
//!
//! Codes act in the order ISO 6983-1 gives them (and LinuxCNC's order of execution keeps): a
//! tool selection or change, `M3`/`M4`, a work offset act before the block's motion; `M5`, `M19`,
//! `M0`/`M1` and the end of the program after it. So a pass written on the block that stops the
//! spindle is cut before it stops.
//!
//! | finding | severity |
//! | --- | --- |
//! | a pass cut after `M5`, `M19` or the end of the program with no `M3`/`M4` since | error E017 |
//! | … after `M0` on a control whose manual says `M0` stops the spindle | error E017 |
//! | … after `M0` where the machine builder decides (most stop it), or after `M1` | warning W010 |
//! | the spindle's direction reversed between passes of one thread | error E017 |
//! | another tool between passes of one thread | error E017 |
//! | the same tool restated (another offset, the same number) between passes | warning W010 |
//!
//! Passes of one thread are the passes [`crate::threads`] joins, and a later thread over the same
//! groove in the same coordinate system with nothing cut between (`Groove::same`). Decisions and
//! their sources: `docs/simulation.md`, "The machine's state at each thread".

use crate::diag::{Code as DiagCode, Diagnostic, Span};
use crate::dialect::lexicon::{Code, Function, Meanings, PauseSpindle, ToolForm};
use crate::gcode::reader::g_code;
use crate::gcode::Line;
use crate::threads::{Groove, Thread};

use super::spindle::Spindle;

/// The spindle's direction of rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Cw,
    Ccw,
}

/// Why the spindle is not turning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Halt {
    /// `M5`.
    Stop,
    /// `M19`: stopped at an angle and held.
    Orient,
    /// `M2`/`M30`: the end of the program stops the spindle.
    End,
    /// `M0` on a control whose manual says it stops the spindle.
    Pause,
    /// `M0` where the machine builder decides, or `M1` (with the optional stop switch on): the
    /// spindle stops on the assumption named in the finding.
    PauseAssumed { optional: bool },
}

/// A code as the program wrote it, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    pub code: Code,
    pub line: u32,
}

impl Mark {
    fn text(self) -> String {
        if self.line == 0 {
            self.code.text()
        } else {
            format!("{} at line {}", self.code.text(), self.line)
        }
    }
}

/// Whether the spindle turns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Turning {
    /// Nothing in the program has started or stopped it yet (a fragment: not judged).
    Unknown,
    On {
        dir: Direction,
        by: Mark,
    },
    Off {
        why: Halt,
        by: Mark,
    },
}

/// The tool in the spindle's turret, as the program selected it.
#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    /// The tool's number (a Fanuc-format `T0303` is tool 3 with offset 3).
    pub number: u64,
    /// The word as written (`T0303`).
    pub word: String,
    pub line: u32,
    /// How many tool changes came before this one.
    pub serial: u32,
}

/// The machine's state at a pass.
#[derive(Clone, Debug)]
pub struct State {
    pub spindle: Spindle,
    pub turning: Turning,
    pub tool: Option<Tool>,
    /// How many changes of the coordinate system (a work offset, a set position) came before.
    pub frame: u32,
    /// Where the pass (or the cycle) is written.
    pub at: Span,
}

/// Reads the machine's state block by block through a controller's meanings.
pub struct Reader {
    /// The M codes that change the state, with their functions.
    m_codes: Vec<(u16, Function)>,
    /// The G codes that change the coordinate system (×10).
    frames: Vec<u16>,
    tool_form: ToolForm,
    pause: PauseSpindle,
    set_position: u16,
    state: State,
    /// A tool selected and not yet changed to (`T1` before `M6`).
    prepared: Option<Tool>,
    changes: u32,
}

impl Reader {
    /// A reader for a controller with these meanings; `set_position` is its set-position code
    /// (×10; its S is the speed clamp).
    pub fn new(meanings: &Meanings, set_position: u16) -> Reader {
        let m_codes = meanings
            .entries()
            .filter_map(|&(c, f)| match c {
                Code::M(m) if affects(f) => Some((m, f)),
                _ => None,
            })
            .collect();
        let frames = meanings
            .entries()
            .filter_map(|&(c, f)| match (c, f) {
                (Code::G(g), Function::WorkOffset(_) | Function::SetPosition) => Some(g),
                _ => None,
            })
            .collect();
        Reader {
            m_codes,
            frames,
            tool_form: meanings.tool,
            pause: meanings.pause_spindle,
            set_position,
            state: State {
                spindle: Spindle::default(),
                turning: Turning::Unknown,
                tool: None,
                frame: 0,
                at: Span::default(),
            },
            prepared: None,
            changes: 0,
        }
    }

    /// The state now, for a pass written at `at`.
    pub fn now(&self, at: Span) -> State {
        State {
            at,
            ..self.state.clone()
        }
    }

    /// What a block does before its motion: S, G96/G97, the tool, `M3`/`M4`, the coordinate
    /// system.
    pub fn before(&mut self, line: &Line) {
        self.state.spindle.read(line, self.set_position);
        let mut m = false;
        for w in line.words {
            match w.letter {
                b'T' => self.tool_word(line, w),
                b'G' => {
                    if let Some(c) = g_code(w.value).filter(|&c| c > 30 && self.frames.contains(&c))
                    {
                        // `G50 S` is the speed clamp, not a new position.
                        let axes = line.word(b'X').is_some() || line.word(b'Z').is_some();
                        if axes || c != self.set_position {
                            self.state.frame += 1;
                        }
                    }
                }
                b'M' => m = true,
                _ => {}
            }
        }
        if m {
            self.m_words(line, true);
        }
    }

    /// What a block does after its motion: `M5`, `M19`, `M0`/`M1`, the end of the program.
    pub fn after(&mut self, line: &Line) {
        if line.words.iter().any(|w| w.letter == b'M') {
            self.m_words(line, false);
        }
    }

    /// The spindle set by APT's SPINDL (`None`: SPINDL/OFF).
    pub fn apt_spindle(&mut self, s: Option<(f64, bool)>) {
        self.state.spindle.s = s.map(|(rpm, _)| rpm);
        self.state.spindle.css = false;
        self.state.turning = match s {
            Some((_, cw)) => Turning::On {
                dir: if cw { Direction::Cw } else { Direction::Ccw },
                by: Mark {
                    code: Code::Keyword(if cw {
                        "SPINDL/…,CLW"
                    } else {
                        "SPINDL/…,CCLW"
                    }),
                    line: 0,
                },
            },
            None => Turning::Off {
                why: Halt::Stop,
                by: Mark {
                    code: Code::Keyword("SPINDL/OFF"),
                    line: 0,
                },
            },
        };
    }

    fn tool_word(&mut self, line: &Line, w: &crate::gcode::Word) {
        if w.value < 0.0 || w.value.fract() != 0.0 || w.value > 1e12 {
            return;
        }
        let v = w.value as u64;
        let number = match self.tool_form {
            ToolForm::Combined { digits } => v / 10u64.pow(digits),
            ToolForm::Single | ToolForm::ToolAndEdge | ToolForm::ChangeAndOffset => v,
        };
        let tool = Tool {
            number,
            word: format!("T{}", String::from_utf8_lossy(w.raw(line.text))),
            line: line.number,
            serial: 0,
        };
        if self.tool_form == ToolForm::ChangeAndOffset {
            // `T` only prepares the tool; `M6` changes to it.
            self.prepared = Some(tool);
        } else {
            self.change_to(tool);
        }
    }

    fn change_to(&mut self, mut tool: Tool) {
        self.changes += 1;
        tool.serial = self.changes;
        self.state.tool = Some(tool);
    }

    /// The block's M codes that act `before` its motion, or after it.
    fn m_words(&mut self, line: &Line, before: bool) {
        // Another spindle (LinuxCNC's `$1`): not the one the thread is cut with.
        if line.word(b'$').is_some_and(|d| d.value != 0.0) {
            return;
        }
        for w in line.words.iter().filter(|w| w.letter == b'M') {
            if w.value < 0.0 || w.value.fract() != 0.0 || w.value > 9999.0 {
                continue;
            }
            let m = w.value as u16;
            let Some(&(_, f)) = self.m_codes.iter().find(|(c, _)| *c == m) else {
                continue;
            };
            let by = Mark {
                code: Code::M(m),
                line: line.number,
            };
            if before {
                self.start(f, by);
            } else {
                self.stop(f, by);
            }
        }
    }

    fn start(&mut self, f: Function, by: Mark) {
        match f {
            Function::SpindleCw => {
                self.state.turning = Turning::On {
                    dir: Direction::Cw,
                    by,
                }
            }
            Function::SpindleCcw => {
                self.state.turning = Turning::On {
                    dir: Direction::Ccw,
                    by,
                }
            }
            Function::ToolChange => {
                if let Some(t) = self.prepared.clone() {
                    self.change_to(t);
                }
            }
            _ => {}
        }
    }

    fn stop(&mut self, f: Function, by: Mark) {
        let why = match (f, self.pause) {
            (Function::SpindleStop, _) => Halt::Stop,
            (Function::SpindleOrient, _) => Halt::Orient,
            (Function::End | Function::EndRewind, _) => Halt::End,
            (Function::Stop | Function::OptionalStop, PauseSpindle::Keeps) => return,
            (Function::Stop, PauseSpindle::Stops) => Halt::Pause,
            (Function::Stop, PauseSpindle::BuilderDecides) => {
                Halt::PauseAssumed { optional: false }
            }
            (Function::OptionalStop, _) => Halt::PauseAssumed { optional: true },
            _ => return,
        };
        self.state.turning = Turning::Off { why, by };
    }
}

/// The functions the state follows.
fn affects(f: Function) -> bool {
    matches!(
        f,
        Function::SpindleCw
            | Function::SpindleCcw
            | Function::SpindleStop
            | Function::SpindleOrient
            | Function::Stop
            | Function::OptionalStop
            | Function::End
            | Function::EndRewind
            | Function::ToolChange
    )
}

/// The last thread judged: its groove and the state at its last pass, so that a thread over the
/// same groove right after it is judged as its further passes.
pub struct Last {
    groove: Groove,
    state: State,
}

/// The words that restart the spindle, for messages (`M3 or M4`, `SPINDL`).
pub struct Restart(pub String);

impl Restart {
    pub fn of(meanings: &Meanings) -> Restart {
        let cw = meanings.code(Function::SpindleCw).map(Code::text);
        let ccw = meanings.code(Function::SpindleCcw).map(Code::text);
        Restart(match (cw, ccw) {
            (Some(a), Some(b)) => format!("{a} or {b}"),
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => "a spindle start".into(),
        })
    }
}

/// Judges the machine's state at each pass of `thread` (`states`: one per pass group, as the
/// collector gives them) and against the thread before it, if it cut the same groove.
pub fn judge(
    thread: &Thread,
    states: &[State],
    last: &mut Option<Last>,
    restart: &Restart,
    found: &mut Vec<Diagnostic>,
) {
    if let Some(d) = stopped(states, restart) {
        found.push(d);
    }
    let before = last
        .take()
        .filter(|l| thread.first_groove().is_some_and(|g| l.groove.same(&g)))
        .map(|l| l.state);
    let mut prev = before
        .as_ref()
        .filter(|b| states.first().is_some_and(|s| s.frame == b.frame));
    let mut reported = (false, false);
    for s in states {
        if let Some(p) = prev {
            let across = before.as_ref().is_some_and(|b| std::ptr::eq(b, p));
            if !reported.0 {
                if let Some(d) = reversed(p, s, across) {
                    found.push(d);
                    reported.0 = true;
                }
            }
            if !reported.1 {
                if let Some(d) = tool_changed(p, s, across) {
                    found.push(d);
                    reported.1 = true;
                }
            }
        }
        prev = Some(s);
    }
    if let (Some(groove), Some(state)) = (thread.last_groove(), states.last()) {
        *last = Some(Last {
            groove,
            state: state.clone(),
        });
    }
}

/// The first pass cut with the spindle stopped.
fn stopped(states: &[State], restart: &Restart) -> Option<Diagnostic> {
    let (i, s, why, by) = states
        .iter()
        .enumerate()
        .find_map(|(i, s)| match s.turning {
            Turning::Off { why, by } => Some((i, s, why, by)),
            _ => None,
        })?;
    let what = if i == 0 {
        "the thread is cut with the spindle stopped".to_string()
    } else {
        format!(
            "the passes from line {} on are cut with the spindle stopped",
            s.at.line
        )
    };
    let code = by.text();
    let cause = match why {
        Halt::Stop => format!("{code} stops it"),
        Halt::Orient => {
            format!("{code} orients it (the spindle stops at an angle and is held there)")
        }
        Halt::End => format!("{code} ends the program, which stops it"),
        Halt::Pause => format!("{code} stops the program, which on this control stops the spindle"),
        Halt::PauseAssumed { optional: false } => format!(
            "{code} stops the program; assuming it stops the spindle too, as most machine \
             builders' ladders do"
        ),
        Halt::PauseAssumed { optional: true } => format!(
            "{code} stops the program when the optional stop switch is on; assuming it is on and \
             the stop stops the spindle, as most machine builders' ladders do"
        ),
    };
    let message = format!("{what}: {cause}, and no {} restarts it", restart.0);
    let hint = format!("start the spindle ({} with S) before the thread", restart.0);
    Some(
        match why {
            Halt::PauseAssumed { .. } => {
                Diagnostic::warning(DiagCode::MachineStateAssumed, s.at, message)
            }
            _ => Diagnostic::error(DiagCode::MachineState, s.at, message),
        }
        .with_hint(hint),
    )
}

/// Where the passes of one thread run: the words of a message.
fn between(across: bool) -> &'static str {
    if across {
        "between this thread and the one just before it over the same groove"
    } else {
        "between passes of one thread"
    }
}

/// The spindle turning the other way at `s` than at `p`.
fn reversed(p: &State, s: &State, across: bool) -> Option<Diagnostic> {
    let (Turning::On { dir: a, by: was }, Turning::On { dir: b, by: now }) = (p.turning, s.turning)
    else {
        return None;
    };
    (a != b).then(|| {
        Diagnostic::error(
            DiagCode::MachineState,
            s.at,
            format!(
                "the spindle turns the other way {}: {} reverses {}, so these passes cut a \
                 thread of the other hand and do not fall in the groove",
                between(across),
                now.text(),
                was.text()
            ),
        )
        .with_hint("cut every pass of a thread with the spindle turning one way")
    })
}

/// A tool change at `s` since `p`.
fn tool_changed(p: &State, s: &State, across: bool) -> Option<Diagnostic> {
    let (Some(a), Some(b)) = (&p.tool, &s.tool) else {
        return None;
    };
    if a.serial == b.serial {
        return None;
    }
    Some(if a.number == b.number {
        Diagnostic::warning(
            DiagCode::MachineStateAssumed,
            s.at,
            format!(
                "the tool is selected again {}: {} at line {} after {} at line {}; assuming the \
                 offset it applies may differ along the thread, the passes may not fall in one \
                 groove",
                between(across),
                b.word,
                b.line,
                a.word,
                a.line
            ),
        )
        .with_hint("select the tool once, before the thread's first pass")
    } else {
        Diagnostic::error(
            DiagCode::MachineState,
            s.at,
            format!(
                "the tool changes {}: {} at line {} replaces {} at line {}; another tool's \
                 offset puts its point elsewhere, so its passes do not fall in the groove",
                between(across),
                b.word,
                b.line,
                a.word,
                a.line
            ),
        )
        .with_hint("cut every pass of a thread with one tool")
    })
}
