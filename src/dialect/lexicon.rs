//! What a controller's codes and words mean, machine-neutral: each dialect states its own
//! [`Lexicon`] ([`crate::dialect::Dialect::lexicon`]), and conversion reads a block through the
//! source's lexicon into [`Function`]s and writes them back through the target's. The converter
//! itself names no controller.
//!
//! A lexicon lists only what threadcut knows a code to mean on that controller (its manual, or
//! ISO 6983-1 where the controller's list is not public and the dialect's page says so). A
//! function a target's lexicon does not have is a refusal naming the target, never a guess.

use crate::gcode::modal::Reference;
use crate::gcode::Conventions;
use crate::units::Units;

/// A code as written: `G21`, `M30`, or a word of its own (`DIAMON`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Code {
    /// ×10: `G33.1` is 331.
    G(u16),
    M(u16),
    Keyword(&'static str),
}

impl Code {
    /// The code as a program writes it.
    pub fn text(self) -> String {
        match self {
            Code::G(c) => crate::gcode::modal::g_name(c),
            Code::M(c) => format!("M{c}"),
            Code::Keyword(k) => k.to_string(),
        }
    }
}

/// The working plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Plane {
    Xy,
    Zx,
    Yz,
}

/// What a code does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    Rapid,
    Feed,
    ArcCw,
    ArcCcw,
    /// The single synchronised move (`G32`, `G33`).
    Thread,
    Dwell,
    Units(Units),
    Absolute,
    Incremental,
    /// X words are diameters.
    Diameter,
    /// X words are radii.
    Radius,
    FeedPerMinute,
    FeedPerRevolution,
    /// S is a surface speed (m/min, ft/min).
    SurfaceSpeed,
    /// S is the spindle speed in rpm.
    Rpm,
    Plane(Plane),
    CompensationOff,
    CompensationLeft,
    CompensationRight,
    /// A work coordinate system: 1 for `G54` … 6 for `G59`.
    WorkOffset(u8),
    /// The block's X and Z become the current position's coordinates (`G50`, `G92`).
    SetPosition,
    /// The block restates the current coordinates and must equal them (OmniTurn's `G92` after
    /// `G35`/`G36`): no effect on motion.
    RestatePosition,
    /// The block's S is the largest spindle speed (`G50 S`, `G92 S` in G-code systems B and C).
    SpindleLimit,
    /// The named axes return to the reference point.
    ReferenceReturn,
    SpindleCw,
    SpindleCcw,
    SpindleStop,
    /// The spindle stops at an angle and is held there (`M19`, ISO 6983-1's oriented spindle
    /// stop): it does not turn again before `M3`/`M4`.
    SpindleOrient,
    CoolantOn,
    MistOn,
    CoolantOff,
    /// End of program (`M2`).
    End,
    /// End of program and rewind (`M30`).
    EndRewind,
    Stop,
    OptionalStop,
    /// The prepared tool goes to the spindle (`M6`).
    ToolChange,
    /// The tool's offset is applied (LinuxCNC's `G43`, with `H` or the tool's own).
    ToolOffset,
    /// The tool's offset is cancelled (`G49`).
    ToolOffsetOff,
    /// A code that changes only how this controller reads its own threading cycles (Haas's
    /// `M23`/`M24` chamfer, OmniTurn's `G35`/`G36` coarse leads): its effect is in the cycles'
    /// jobs, which conversion writes whole.
    CycleSetting,
}

impl Function {
    /// What the function does, in the words of messages.
    pub fn describe(self) -> String {
        match self {
            Function::Rapid => "rapid move".into(),
            Function::Feed => "feed move".into(),
            Function::ArcCw => "clockwise arc".into(),
            Function::ArcCcw => "counter-clockwise arc".into(),
            Function::Thread => "synchronised thread move".into(),
            Function::Dwell => "dwell".into(),
            Function::Units(u) => format!("{} input", u.name()),
            Function::Absolute => "absolute distances".into(),
            Function::Incremental => "incremental distances".into(),
            Function::Diameter => "X on diameter".into(),
            Function::Radius => "X on radius".into(),
            Function::FeedPerMinute => "feed per minute".into(),
            Function::FeedPerRevolution => "feed per revolution".into(),
            Function::SurfaceSpeed => "constant surface speed".into(),
            Function::Rpm => "spindle speed in rpm".into(),
            Function::Plane(Plane::Xy) => "XY plane".into(),
            Function::Plane(Plane::Zx) => "ZX plane".into(),
            Function::Plane(Plane::Yz) => "YZ plane".into(),
            Function::CompensationOff => "tool nose radius compensation off".into(),
            Function::CompensationLeft => "tool nose radius compensation left".into(),
            Function::CompensationRight => "tool nose radius compensation right".into(),
            Function::WorkOffset(n) => format!("work coordinate system {n} (G{})", 53 + n),
            Function::SetPosition => "setting the current position's coordinates".into(),
            Function::RestatePosition => "restating the current coordinates".into(),
            Function::SpindleLimit => "spindle speed limit".into(),
            Function::ReferenceReturn => "return to the reference point".into(),
            Function::SpindleCw => "spindle on clockwise".into(),
            Function::SpindleCcw => "spindle on counter-clockwise".into(),
            Function::SpindleStop => "spindle stop".into(),
            Function::SpindleOrient => "spindle orientation".into(),
            Function::CoolantOn => "coolant on".into(),
            Function::MistOn => "mist coolant on".into(),
            Function::CoolantOff => "coolant off".into(),
            Function::End => "end of program".into(),
            Function::EndRewind => "end of program with rewind".into(),
            Function::Stop => "program stop".into(),
            Function::OptionalStop => "optional stop".into(),
            Function::ToolChange => "tool change".into(),
            Function::ToolOffset => "tool offset".into(),
            Function::ToolOffsetOff => "tool offset cancel".into(),
            Function::CycleSetting => "a setting of this controller's threading cycles".into(),
        }
    }

    /// A function that cancels a state which a target without the state's codes cannot be in:
    /// dropped there rather than refused (`G40` where no compensation exists, `G97` where S is
    /// always rpm, `G49`).
    pub fn cancelled_family(self) -> Option<&'static [Function]> {
        match self {
            Function::CompensationOff => {
                Some(&[Function::CompensationLeft, Function::CompensationRight])
            }
            Function::Rpm => Some(&[Function::SurfaceSpeed]),
            Function::ToolOffsetOff => Some(&[Function::ToolOffset]),
            _ => None,
        }
    }

    /// The motion a code selects, if it selects one.
    pub fn is_motion(self) -> bool {
        matches!(
            self,
            Function::Rapid
                | Function::Feed
                | Function::ArcCw
                | Function::ArcCcw
                | Function::Thread
        )
    }
}

/// How a block selects a tool and its offset.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolForm {
    /// `T` followed by the tool number and `digits` digits of offset number (`T0101`, `T505`):
    /// Fanuc and its copies, Allen-Bradley's T-word format 2.
    Combined { digits: u32 },
    /// `T4`: the tool, with its own offset (OmniTurn).
    Single,
    /// `T7 D1`: the tool and its cutting edge (Sinumerik); `T="NAME"` names the tool.
    ToolAndEdge,
    /// `T1 M6 G43 [H2]`: the tool is prepared with T, changed with `M6`, its offset applied with
    /// `G43` (LinuxCNC).
    ChangeAndOffset,
}

/// How a block writes a dwell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DwellForm {
    /// `G4 X1.5` or `U1.5` (seconds) or `P1500` (milliseconds, no decimal point): Fanuc, GSK.
    XSecondsOrPMilliseconds,
    /// `G4 P1.5`: seconds (LinuxCNC).
    PSeconds,
    /// `G4 P1.5` in seconds with a decimal point, `P1500` in milliseconds without (Haas).
    PSecondsOrMilliseconds,
    /// `G4 F1.5`: seconds (Sinumerik).
    FSeconds,
}

/// How a block states the largest spindle speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitForm {
    /// A code with `S` (`G50 S2000`, `G92 S2000`): the entry of [`Function::SpindleLimit`].
    Code,
    /// `NAME=value` (Sinumerik's `LIMS=2000`).
    Setting(&'static str),
    /// A word on the constant-surface-speed block (LinuxCNC's `G96 S… D2000`).
    OnSurfaceSpeed(u8),
}

/// What a program stop (`M0`, and `M1` with the optional stop switch on) does to the spindle,
/// as the controller's manual says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PauseSpindle {
    /// The manual says the stop stops the spindle (Haas: "M00 … stops the axes, spindle").
    Stops,
    /// The manual leaves it to the machine builder (the M code goes to the ladder, which on most
    /// machines stops the spindle): Fanuc-format controls, Sinumerik.
    BuilderDecides,
    /// The program pauses and the spindle keeps turning (LinuxCNC: its interpreter stops the
    /// spindle at the end of a program, not at `M0`/`M1`).
    Keeps,
}

/// How a block returns axes straight to the reference point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReturnForm {
    /// The return code with incremental zero words (`G28 U0. W0.`): the intermediate point is
    /// where the tool is.
    IncrementalWords { x: u8, z: u8 },
    /// The return code in incremental mode, then absolute mode again (`G91 G28 X0. Z0.` /
    /// `G90`): LinuxCNC, whose U/W are no incremental words.
    IncrementalMode,
    /// The return code with machine-axis words whose values are ignored (`G74 X1=0 Z1=0`).
    MachineAxes { x: &'static str, z: &'static str },
}

/// What a controller's codes and words mean, besides what its reader's [`Conventions`](crate::gcode::Conventions) state
/// already ([`Meanings`] joins the two).
#[derive(Debug)]
pub struct Lexicon {
    /// Every code with its function, in groups (a list shared by several controllers, then each
    /// controller's own). A code may appear with two functions told apart by the block's words
    /// (`G50 X Z` sets the position, `G50 S` the spindle limit). The reference return, the work
    /// coordinate systems and the code that sets the position are not listed: they are the
    /// dialect's [`Conventions`](crate::gcode::Conventions) (its `positions` and `set_position`), stated once for reading
    /// and converting alike.
    pub codes: &'static [&'static [(Code, Function)]],
    pub tool: ToolForm,
    pub dwell: Option<DwellForm>,
    pub spindle_limit: Option<LimitForm>,
    pub reference: Option<ReturnForm>,
    /// The code that sets the position ([`Conventions::set_position`](crate::gcode::Conventions::set_position)) only restates the
    /// coordinates the tool has, which it must equal (OmniTurn's `G92` after `G35`/`G36`): no
    /// effect on motion, and no code to set the position with.
    pub restates_position: bool,
    /// `O…` numbers the program (Fanuc family); elsewhere O is program flow or nothing.
    pub program_number: bool,
    /// `N…` sequence numbers.
    pub sequence_numbers: bool,
    /// `%` lines delimit the program.
    pub delimiters: bool,
    /// The feed mode at power-on: [`Function::FeedPerMinute`] or [`Function::FeedPerRevolution`].
    pub power_on_feed: Function,
    /// The letters of the thread move that carry its lead and start angle (`F Q`, `K`, `F E`):
    /// the move itself carries them through conversion.
    pub thread_words: &'static [u8],
    /// `NAME=` settings that state the thread move's start angle (Sinumerik's `SF=`).
    pub thread_settings: &'static [&'static str],
    /// The only units the controller is programmed in, where it has one (OmniTurn: inch).
    pub only_units: Option<Units>,
    /// What a program stop does to the spindle.
    pub pause_spindle: PauseSpindle,
}

/// A controller's meanings for conversion: its [`Lexicon`], with the codes its reader's
/// [`Conventions`](crate::gcode::Conventions) state — the return to the (first) reference point
/// ([`PositionCodes::returns`](crate::gcode::modal::PositionCodes)), the work coordinate systems
/// G54–G59 among its `work_systems`, the code that sets (or restates) the position
/// ([`Conventions::set_position`](crate::gcode::Conventions::set_position)) — and whether a return without axis words returns every axis
/// (`PositionCodes::all_without_axes`). So each of these is one statement per dialect, which the
/// modal reader and conversion both read.
#[derive(Debug)]
pub struct Meanings {
    lexicon: &'static Lexicon,
    /// The codes the conventions give a function, after the lexicon's own.
    positions: Vec<(Code, Function)>,
    /// A return code without axis words returns every axis (LinuxCNC, Haas); otherwise none.
    pub return_all_without_axes: bool,
}

impl Meanings {
    /// The meanings of the codes of a controller whose lexicon is `lexicon` and whose reader's
    /// conventions are `conv` ([`crate::dialect::Dialect::meanings`]).
    pub fn new(lexicon: &'static Lexicon, conv: &Conventions) -> Meanings {
        let p = &conv.positions;
        let mut positions = Vec::new();
        if let Some(&(c, _)) = p.returns.iter().find(|(_, r)| *r == Reference::First) {
            positions.push((Code::G(c), Function::ReferenceReturn));
        }
        for n in 1..=6u8 {
            let c = 530 + 10 * u16::from(n);
            if p.work_systems.contains(&c) {
                positions.push((Code::G(c), Function::WorkOffset(n)));
            }
        }
        if conv.set_position != 0 {
            positions.push((
                Code::G(conv.set_position),
                if lexicon.restates_position {
                    Function::RestatePosition
                } else {
                    Function::SetPosition
                },
            ));
        }
        Meanings {
            lexicon,
            positions,
            return_all_without_axes: p.all_without_axes,
        }
    }

    /// Every code with its function: the lexicon's, then the conventions'.
    pub fn entries(&self) -> impl Iterator<Item = &(Code, Function)> {
        self.lexicon
            .codes
            .iter()
            .flat_map(|g| g.iter())
            .chain(self.positions.iter())
    }

    /// The functions of a code, in the order listed.
    pub fn functions(&self, code: Code) -> impl Iterator<Item = Function> + '_ {
        self.entries()
            .filter(move |(c, _)| *c == code)
            .map(|(_, f)| *f)
    }

    /// The code that writes `f`, if the controller has one.
    pub fn code(&self, f: Function) -> Option<Code> {
        self.entries().find(|(_, g)| *g == f).map(|(c, _)| *c)
    }

    /// Whether the controller has a code for `f`.
    pub fn has(&self, f: Function) -> bool {
        self.code(f).is_some()
    }

    /// Whether a program can be written in `units`.
    pub fn has_units(&self, units: Units) -> bool {
        match self.lexicon.only_units {
            Some(only) => only == units,
            None => self.has(Function::Units(units)),
        }
    }
}

/// The lexicon's forms and flags (`tool`, `dwell`, `thread_words` …).
impl std::ops::Deref for Meanings {
    type Target = Lexicon;
    fn deref(&self) -> &Lexicon {
        self.lexicon
    }
}

/// One item of a line in a controller's own syntax ([`crate::dialect::Dialect::terms`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Term {
    /// An address word (`G33`, `X-10.5`), or an address given a number (`X=12`).
    Word(crate::gcode::Word),
    /// An address given the value of a parameter (`X=R1`): present, its value not known here.
    Assigned { letter: u8, span: crate::diag::Span },
    /// A word of its own (`DIAMON`).
    Keyword {
        name: String,
        span: crate::diag::Span,
    },
    /// The tool named rather than numbered (`T="THREAD_EXT"`).
    ToolName {
        name: String,
        span: crate::diag::Span,
    },
    /// `NAME=value`: a setting (`LIMS=2500`, `SF=90`) or a variable declared earlier; `value` when
    /// it is written as a number.
    Setting {
        name: String,
        value: Option<f64>,
        span: crate::diag::Span,
    },
    /// A machine axis (`X1=0`), as the reference return takes them.
    MachineAxis {
        name: String,
        span: crate::diag::Span,
    },
    /// Values set for later blocks (`R1=1.5`, `DEF REAL LEAD=3`), and the names it declares: the
    /// converted blocks carry the values, so the line becomes a comment.
    Data { declares: Vec<String> },
    /// The program's name line (a file header such as `%_N_NAME_MPF`): a comment, written first in
    /// a converted program, as a program number is.
    ProgramName,
    /// A call that changes nothing threadcut follows (`MSG("…")`): a comment.
    Passive { span: crate::diag::Span },
    /// A call, keyword or setting conversion has no meaning for.
    Unknown {
        what: String,
        span: crate::diag::Span,
    },
}

/// `M0` … `M30` as ISO 6983-1 assigns them, which every lathe control threadcut knows keeps (the
/// dialects' pages say where this is the manual's list and where it is assumed).
pub const ISO_M: &[(Code, Function)] = &[
    (Code::M(0), Function::Stop),
    (Code::M(1), Function::OptionalStop),
    (Code::M(2), Function::End),
    (Code::M(3), Function::SpindleCw),
    (Code::M(4), Function::SpindleCcw),
    (Code::M(5), Function::SpindleStop),
    (Code::M(8), Function::CoolantOn),
    (Code::M(9), Function::CoolantOff),
    (Code::M(30), Function::EndRewind),
];

/// `M19`, the oriented spindle stop of ISO 6983-1, on the controls whose manual (or whose
/// builders' common list) has it (the dialects' pages say which).
pub const ORIENT: &[(Code, Function)] = &[(Code::M(19), Function::SpindleOrient)];

/// `G0`–`G3`.
pub const MOTION: &[(Code, Function)] = &[
    (Code::G(0), Function::Rapid),
    (Code::G(10), Function::Feed),
    (Code::G(20), Function::ArcCw),
    (Code::G(30), Function::ArcCcw),
];

/// `G4`, the dwell (its time word is the lexicon's [`DwellForm`]).
pub const DWELL: &[(Code, Function)] = &[(Code::G(40), Function::Dwell)];

/// `G17`–`G19`: the same on every control that has them.
pub const PLANES: &[(Code, Function)] = &[
    (Code::G(170), Function::Plane(Plane::Xy)),
    (Code::G(180), Function::Plane(Plane::Zx)),
    (Code::G(190), Function::Plane(Plane::Yz)),
];

/// Tool nose radius compensation.
pub const COMPENSATION: &[(Code, Function)] = &[
    (Code::G(400), Function::CompensationOff),
    (Code::G(410), Function::CompensationLeft),
    (Code::G(420), Function::CompensationRight),
];

/// Constant surface speed and rpm.
pub const SPINDLE_MODES: &[(Code, Function)] = &[
    (Code::G(960), Function::SurfaceSpeed),
    (Code::G(970), Function::Rpm),
];

/// `G20` inch, `G21` mm.
pub const G20_G21: &[(Code, Function)] = &[
    (Code::G(200), Function::Units(Units::Inch)),
    (Code::G(210), Function::Units(Units::Mm)),
];

/// `G90` absolute, `G91` incremental.
pub const G90_G91: &[(Code, Function)] = &[
    (Code::G(900), Function::Absolute),
    (Code::G(910), Function::Incremental),
];

/// `G94` per minute, `G95` per revolution.
pub const G94_G95: &[(Code, Function)] = &[
    (Code::G(940), Function::FeedPerMinute),
    (Code::G(950), Function::FeedPerRevolution),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_controllers_lexicon_agrees_with_its_vocabulary() {
        // Every G code a lexicon gives a meaning is a code the controller's reader accepts, and
        // the thread move of a lexicon is its conventions' (so that what is written reads back).
        for (name, _) in crate::machine::BUILT_IN {
            let m = crate::machine::Machine::built_in(name).unwrap();
            let d = crate::dialect::open(&m).unwrap();
            let lex = d.meanings();
            for (code, f) in lex.entries() {
                if let Code::G(c) = code {
                    assert!(
                        d.vocabulary().get(*c).is_some(),
                        "{name}: {} ({f:?}) is not in its vocabulary",
                        code.text()
                    );
                }
            }
            if let Some(Code::G(c)) = lex.code(Function::Thread) {
                assert_eq!(c, d.conventions().thread_move, "{name}");
            }
            assert!(
                lex.has_units(m.units),
                "{name}: its power-on units have a code"
            );
            assert!(matches!(
                lex.power_on_feed,
                Function::FeedPerMinute | Function::FeedPerRevolution
            ));
            assert!(lex.has(lex.power_on_feed), "{name}");
        }
    }
}

/// A machine setting a native cycle reads from the control rather than from its block (Haas's
/// Setting 86 for G76's finishing pass): the converted program relies on the machine holding the
/// value threadcut verified its motion with.
#[derive(Clone, Debug, PartialEq)]
pub struct Setting {
    /// `Setting 86`.
    pub name: &'static str,
    /// `thread finish allowance`.
    pub what: &'static str,
    /// The value, with its unit (`0.002 in`, `45 deg`), in ASCII: it goes into a comment.
    pub value: String,
    pub known: Known,
}

/// Where a setting's value comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known {
    /// The target profile states the machine's value.
    Stated,
    /// Not stated; the control's factory default, which its manual gives.
    FactoryDefault,
    /// Not stated, and no manual sentence gives its default: threadcut's assumed value. A
    /// conversion writes no native cycle that relies on it.
    Assumed,
}

impl Setting {
    /// `Setting 86, thread finish allowance: 0.002 in`, with where the value comes from when the
    /// profile does not state it (no parentheses: it goes into a comment).
    pub fn describe(&self) -> String {
        let from = match self.known {
            Known::Stated => "",
            Known::FactoryDefault => ", the factory default, not stated in the target profile",
            Known::Assumed => ", assumed, not stated in the target profile",
        };
        format!("{}, {}: {}{from}", self.name, self.what, self.value)
    }
}
