//! Siemens Sinumerik 828D/840D turning: the thread-cutting cycle CYCLE97, `G33 Z… K… SF=…` as the
//! synchronised move (with the start angle SF), DIAMON/DIAMOF/DIAM90, G70/G71/G700/G710, and the
//! parts of Sinumerik's own block syntax that programs around a thread are written in: `;`
//! comments, R parameters and DEF variables set to numbers, `NAME=value` words, calls.
//!
//! Lines of address words only are read by the shared lexer as on every controller; a line in
//! Sinumerik's own syntax is handed over unread ([`Syntax::hand_over_unread`]) and read here
//! ([`block`]). Every decision is a row of `docs/dialects/sinumerik.md`.

mod block;
mod cycle95;
mod cycle97;

use std::collections::HashMap;

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::lexicon::{
    self, Code as C, DwellForm, Function as F, Lexicon, LimitForm, ReturnForm, Term, ToolForm,
};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{
    Conventions, Line, Modal, MotionMode, Position, PositionCodes, Reference, Syntax, Word,
    WordSummary,
};
use crate::machine::Machine;
use crate::post::{AngleUnit, Format, StartAngleWord};
use crate::units::Units;

use super::{Dialect, Read};
use block::{Item, Operand};

const G33: u16 = 330;

/// Words that change nothing threadcut follows: technology and look-ahead settings.
const PASSIVE_KEYWORDS: &[&str] = &[
    "STOPRE",
    "SOFT",
    "BRISK",
    "DRIVE",
    "FFWON",
    "FFWOF",
    "CFC",
    "CFTCP",
    "CFIN",
    "DIAMCYCOF",
    "SPCON",
    "SPCOF",
    "RET",
    "ORIWKS",
    "ORIMKS",
    "CUT2D",
    "CUT2DF",
    "COMPOF",
    "FNORM",
    "TRAFOOF",
];

/// `NAME=value` settings that change nothing threadcut follows (spindle speed limit, spindle
/// positioning, the fixed point of a G75, the smoothing distances of G641, which round the
/// corners between moves and leave the moves' end points and a G33 chain's thread as written).
const PASSIVE_SETTINGS: &[&str] = &[
    "LIMS", "SPOS", "SPOSA", "SETMS", "ACC", "OVR", "FP", "ADIS", "ADISPOS",
];

/// Calls that change nothing threadcut follows: messages, the simulation's blank, the master
/// spindle.
/// Sinumerik's turning cycles that remove material threadcut does not simulate (grooving,
/// undercuts). (CYCLE95, stock removal, is read: `cycle95`.)
const TURNING_CALLS: &[&str] = &["CYCLE93", "CYCLE94", "CYCLE96"];

const PASSIVE_CALLS: &[&str] = &["MSG", "WORKPIECE", "SETMS", "SETPIECE", "SPOS", "SUPD"];

/// Program flow: threadcut reads a program from top to bottom and cannot follow these.
const FLOW: &[&str] = &[
    "GOTO", "GOTOF", "GOTOB", "GOTOC", "IF", "ELSE", "ENDIF", "WHILE", "ENDWHILE", "REPEAT",
    "REPEATB", "UNTIL", "LOOP", "ENDLOOP", "FOR", "ENDFOR", "CASE", "CALL", "PCALL", "MCALL",
    "PROC", "EXTERN",
];

/// Frames: they move every later coordinate in a way threadcut does not follow.
const FRAMES: &[&str] = &[
    "TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR", "RPL",
];

/// `SF=` on G33: the start angle in degrees (0.0001°, as CYCLE97's NSP), kept by the control
/// (setting data 42000 THREAD_START_ANGLE) until the next `SF=`.
const SF: StartAngleWord = StartAngleWord {
    name: "SF=",
    unit: AngleUnit::Degrees { decimals: 4 },
    modal: true,
};

/// Sinumerik's lines: `;` comments (`(` belongs to calls), and lines in its own syntax handed
/// over unread for [`block`] to read.
pub const SYNTAX: Syntax = Syntax {
    parens_not_comments: true,
    hand_over_unread: true,
    bare: b"",
    blanks_anywhere: false,
    nested_comment_error: false,
};

/// Sinumerik's G codes for where the tool is (`docs/dialects/sinumerik.md`, "Where the tool
/// is"): `G74` approaches the reference point with the axes it names (the profile's
/// `[reference] g28`); `G75` approaches a fixed point (machine data no profile states) and
/// `G53`/`G153` move in machine coordinates: the named axes become unknown. The settable work
/// offsets are `G500` (none: in force at power-on), `G54`–`G57` and `G505`–`G599`; `G25`/`G26`
/// with axis words set the working-area limits and move nothing. (The programmable offsets
/// `G58`/`G59` are frames, refused as TRANS is.)
pub const POSITIONS: PositionCodes = PositionCodes {
    returns: &[(740, Reference::First)],
    all_without_axes: false,
    stores: &[],
    machine_moves: &[530, 1530, 750],
    from_reference: 0,
    work_systems: &WORK_SYSTEMS,
    power_on_work_system: 5000,
    offset_changes: &[],
    not_moves: &[250, 260],
};

/// G500, G54–G57, G505–G599 (×10).
const WORK_SYSTEMS: [u16; 100] = {
    let first = [5000, 540, 550, 560, 570];
    let mut t = [0u16; 100];
    let mut i = 0;
    while i < 100 {
        t[i] = if i < 5 {
            first[i]
        } else {
            5050 + 10 * (i as u16 - 5)
        };
        i += 1;
    }
    t
};

/// What a block does to where the tool is, beyond its words.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Leaves {
    /// Its words say it all.
    Known,
    /// `SUPA`: the block's positions are in machine coordinates; the axes it names are unknown
    /// after it (as after `G53`).
    NamedAxesUnknown,
    /// Another cycle's call: where it leaves the tool is not known.
    AllUnknown,
}

/// Sinumerik's G functions in Siemens mode, as ranges of whole numbers (the Fundamentals manual's
/// list of G functions: `docs/dialects/sinumerik.md`, "Vocabulary"). Generous where threadcut's
/// knowledge of the list may be partial: every code G0–G99 but the ISO/Fanuc codes a Siemens-mode
/// program never has — G20/G21 (inch and metric are G70/G71, G700/G710), G32 (the thread move is
/// G33), G76, G78 (the thread cycle is CYCLE97, a call, not a G code) — and the functions above G99:
/// G110–G112, G140–G143, G147/G148, G153, G247/G248, G290/G291, G331/G332, G335/G336, G340/G341,
/// G347/G348, G450/G451, G460–G462, G500, G505–G599, G601–G603, G621, G641–G645, G700, G710, the
/// OEM codes G810–G829, G931, G942, G952, G961/G962, G971–G973.
const RANGES: &[(u16, u16)] = &[
    (0, 19),
    (22, 31),
    (33, 75),
    (77, 77),
    (79, 99),
    (110, 112),
    (140, 143),
    (147, 148),
    (153, 153),
    (247, 248),
    (290, 291),
    (331, 332),
    (335, 336),
    (340, 341),
    (347, 348),
    (450, 451),
    (460, 462),
    (500, 500),
    (505, 599),
    (601, 603),
    (621, 621),
    (641, 645),
    (700, 700),
    (710, 710),
    (810, 829),
    (931, 931),
    (942, 942),
    (952, 952),
    (961, 962),
    (971, 973),
];

/// What Sinumerik's codes and keywords mean (the Fundamentals manual, `docs/dialects/sinumerik.md`,
/// `docs/translation.md`): G70/G71 (G700/G710) units, DIAMON/DIAMOF (DIAM90: diameter under
/// G90, where conversion writes), `G4 F` in seconds, G74 to the reference point with machine-axis
/// words, `LIMS=` the spindle limit, `T… D…` tool and cutting edge, G33 K (I) with `SF=`, G54–G57
/// (G58/G59 are frames), feed per minute (G94) as delivered, no `%` delimiters or O numbers.
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        &[
            (C::G(700), F::Units(Units::Inch)),
            (C::G(710), F::Units(Units::Mm)),
            (C::G(7000), F::Units(Units::Inch)),
            (C::G(7100), F::Units(Units::Mm)),
            (C::G(330), F::Thread),
            (C::Keyword("DIAMON"), F::Diameter),
            (C::Keyword("DIAMOF"), F::Radius),
            (C::Keyword("DIAM90"), F::Diameter),
        ],
        lexicon::COMPENSATION,
        lexicon::G90_G91,
        lexicon::G94_G95,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
    ],
    tool: ToolForm::ToolAndEdge,
    dwell: Some(DwellForm::FSeconds),
    spindle_limit: Some(LimitForm::Setting("LIMS")),
    reference: Some(ReturnForm::MachineAxes { x: "X1", z: "Z1" }),
    restates_position: false,
    program_number: false,
    sequence_numbers: true,
    delimiters: false,
    power_on_feed: F::FeedPerMinute,
    thread_words: b"KI",
    thread_settings: &["SF"],
    only_units: None,
    pause_spindle: lexicon::PauseSpindle::BuilderDecides,
};

/// Sinumerik's G functions; G33 with its words `X Z I K` (SF= is a named word).
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "sinumerik",
    alarm: "alarm 12470 (G function unknown)",
    g_codes: &super::ranges::<{ super::count(RANGES) }>(RANGES, &[GCode::thread(G33, b"XZIK")]),
    foreign: &[],
    others: super::others_with,
};

pub struct Sinumerik {
    conv: Conventions,
    machine: Machine,
    /// The start angle of a G33 block that begins a thread (setting data 42000
    /// THREAD_START_ANGLE, which `SF=` writes): 0 at power-on.
    sf: f64,
    /// DIAM90: X on diameter under G90, on radius under G91.
    diam90: bool,
    /// The X convention to put back on the next line: CYCLE97 under DIAM90 and G91 is expanded
    /// under G90, where X is a diameter.
    restore_diameter: Option<bool>,
    /// Whether a tool offset (a cutting edge D) is active: D0 deselects it, D1… and a tool
    /// change select one. Unknown at the start of a program: taken as active.
    offset_active: bool,
    /// R parameters set in this program.
    r: HashMap<u32, f64>,
    /// Variables declared with DEF in this program.
    vars: HashMap<String, f64>,
    /// A CYCLE95 whose contour the interpreter is about to run (or runs) as its profile.
    cycle95: Option<cycle95::Pending>,
    /// The last block was a CYCLE95: the program's next instruction reads its contour.
    profile_next: bool,
}

impl Sinumerik {
    pub fn new(machine: &Machine) -> Sinumerik {
        Sinumerik {
            conv: Conventions {
                uw_incremental: false,
                g90_g91_distance: true,
                diameter_x: machine.diameter_x,
                thread_move: G33,
                tpi_letter: 0,
                // K: the pitch along Z; I (along X) is read here, for moves steeper than 45°.
                lead_letter: b'K',
                lead_along_path: false,
                set_position: 0,
                canned_cycles: &[],
                unmodelled: &[],
                // G70/G71; G700/G710 (feeds too) are read here.
                units_codes: [700, 710],
                positions: POSITIONS,
                syntax: SYNTAX,
            },
            machine: machine.clone(),
            sf: 0.0,
            diam90: false,
            restore_diameter: None,
            offset_active: true,
            r: HashMap::new(),
            vars: HashMap::new(),
            cycle95: None,
            profile_next: false,
        }
    }

    /// The value of an operand: a number, or a parameter set earlier in the program.
    fn value(&self, op: &Operand) -> Result<f64> {
        match op {
            Operand::Number { value, .. } => Ok(*value),
            Operand::R { n, negative, span } => match self.r.get(n) {
                Some(v) => Ok(if *negative { -v } else { *v }),
                None => Err(Diagnostic::error(
                    Code::Unsupported,
                    *span,
                    format!(
                        "R{n} is not set earlier in this program: its value lives on the control"
                    ),
                )
                .with_hint(format!(
                    "set it before it is used, e.g. `R{n}=1.5`, or write the number"
                ))),
            },
            Operand::Name {
                name,
                negative,
                span,
            } => match self.vars.get(name) {
                Some(v) => Ok(if *negative { -v } else { *v }),
                None => Err(Diagnostic::error(
                    Code::Unsupported,
                    *span,
                    format!("{name} is not a variable declared earlier in this program"),
                )
                .with_hint(
                    "declare it with `DEF REAL NAME=value` before it is used, or write the number",
                )),
            },
            Operand::Text { span, .. } => Err(Diagnostic::error(
                Code::Syntax,
                *span,
                "a string where a number was expected",
            )),
        }
    }

    /// A line of address words: the state this dialect keeps, then the modal reader. `words` are
    /// the line's own or, for a line in Sinumerik's syntax, the address words found in it.
    fn read_words(&mut self, line: &Line, modal: &mut Modal, leaves: Leaves) -> Result<Read> {
        let mut absolute = modal.absolute;
        let mut thread = false;
        for w in line.words {
            match w.letter {
                b'D' => self.offset_active = w.value != 0.0,
                // A tool change selects the tool's first cutting edge (machine data 20270).
                b'T' => self.offset_active = w.value != 0.0,
                b'L' => {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        w.span,
                        format!("L{}: threadcut does not follow subprogram calls", w.value),
                    )
                    .with_hint("expand the subprogram into the program"))
                }
                b'G' => match g_code(w.value) {
                    Some(700 | 7000) => modal.units = Units::Inch,
                    Some(710 | 7100) => modal.units = Units::Mm,
                    Some(900) => absolute = true,
                    Some(910) => absolute = false,
                    Some(G33) => thread = true,
                    // The programmable zero offsets: frames, as TRANS and ATRANS ("G58 replaces
                    // the absolute translation component of the programmable zero offset").
                    Some(c @ (580 | 590)) => {
                        return Err(frame_refused(&format!("G{}", c / 10), w.span))
                    }
                    // G291 switches to the ISO dialect: the words after it are Fanuc's.
                    Some(2910) => {
                        return Err(Diagnostic::error(
                            Code::Unsupported,
                            w.span,
                            "G291: threadcut reads Sinumerik programs in Siemens mode (G290), not in the ISO dialect",
                        )
                        .with_hint("a program written in the ISO dialect is a Fanuc program: read it with --controller fanuc"))
                    }
                    Some(c @ (340 | 350 | 630 | 3310 | 3320)) => {
                        return Err(Diagnostic::error(
                            Code::Unsupported,
                            w.span,
                            format!(
                                "G{}: threadcut does not read Sinumerik's {} on this controller",
                                f64::from(c) / 10.0,
                                if c < 400 {
                                    "variable-lead threads (G34/G35)"
                                } else {
                                    "tapping moves (G63/G331/G332)"
                                }
                            ),
                        )
                        .with_hint("threadcut reads G33 and CYCLE97"))
                    }
                    _ => {}
                },
                _ => {}
            }
        }
        if self.diam90 {
            modal.diameter_x = absolute;
        }
        let steep = if thread || modal.motion == MotionMode::Thread {
            self.steep_lead(line, modal)?
        } else {
            false
        };
        if !(thread || steep || leaves != Leaves::Known) {
            // (G74/G75 and the work offsets are the shared modal reader's: `POSITIONS`.)
            return Ok(Read::Plain);
        }
        let mut mv = modal.apply(&self.conv, line)?;
        if let Some(m) = mv.as_mut().filter(|m| m.mode == MotionMode::Thread) {
            m.phase_deg = self.sf;
        }
        match leaves {
            Leaves::Known => {}
            Leaves::NamedAxesUnknown => {
                // As G53: the named axes end in machine coordinates, and the block is no move in
                // the program's.
                if line.word(b'X').is_some() {
                    modal.position.x = None;
                }
                if line.word(b'Z').is_some() {
                    modal.position.z = None;
                }
                mv = None;
            }
            Leaves::AllUnknown => modal.position = Position::UNKNOWN,
        }
        Ok(Read::Applied(mv))
    }

    /// `G33 … I…`: the pitch along X of a thread steeper than 45°, read into the modal lead.
    fn steep_lead(&self, line: &Line, modal: &mut Modal) -> Result<bool> {
        let Some(i) = line.word(b'I') else {
            return Ok(false);
        };
        if let Some(k) = line.word(b'K') {
            return Err(Diagnostic::error(
                Code::Conflict,
                i.span,
                "I and K in one G33 block",
            )
            .with_hint(format!(
                "K is the pitch along Z, I along X: keep the one of the axis that travels further (K{} was also given)",
                k.value
            )));
        }
        if !modal.resolution().length().gt(modal.length_mm(i), 0.0) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                i.span,
                format!("I{} lead must be positive", i.value),
            ));
        }
        modal.lead = Some(modal.length_mm(i));
        Ok(true)
    }

    /// A line in Sinumerik's own syntax.
    fn read_block(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        let items = block::parse(line.text, line.number, line.offset)?;
        let mut words: Vec<Word> = Vec::new();
        let mut cycle = None;
        let mut stock = None;
        let mut leaves = Leaves::Known;
        let mut machine_axis = None;
        for item in items {
            match item {
                Item::Word(w) => words.push(w),
                Item::Assign { name, span, value } => {
                    if let Some(w) = self.assign(&name, span, &value, &mut machine_axis)? {
                        words.push(w);
                    }
                }
                Item::Keyword { name, span } => {
                    if self.keyword(&name, span, modal)? {
                        leaves = leaves.max(Leaves::NamedAxesUnknown);
                    }
                }
                Item::Call {
                    name,
                    span,
                    args,
                    arg_spans,
                } => match name.as_str() {
                    "CYCLE97" => cycle = Some(self.cycle97_call(span, &args, &arg_spans)?),
                    "CYCLE95" => stock = Some(self.cycle95_call(span, &args, &arg_spans)?),
                    "CYCLE99" => return Err(Diagnostic::error(
                        Code::Unsupported,
                        span,
                        "CYCLE99 (thread turning from the ShopTurn/programGUIDE forms) is not read by threadcut",
                    )
                    .with_hint("the public descriptions of its parameter list found for threadcut disagree on the order of its parameters; program the thread with CYCLE97 or G33 blocks")),
                    // Another cycle (stock removal, grooving, drilling): it passes through, and
                    // threadcut does not know where it leaves the tool. A turning cycle's
                    // material is then missing from the part `check` simulates: said once per call.
                    n if n.starts_with("CYCLE") => {
                        leaves = Leaves::AllUnknown;
                        if TURNING_CALLS.contains(&n) {
                            warnings.push(Diagnostic::warning(
                                Code::Suspicious,
                                span,
                                format!("{n} is not simulated by threadcut: the material it removes is not in the part `check` follows, and where it leaves the tool is not known"),
                            ).with_hint("the blank at a thread after it is the bar given (--stock-diameter) or the thread's crest; docs/dialects/sinumerik.md, \"Turning cycles not simulated\""));
                        }
                    }
                    n if PASSIVE_CALLS.contains(&n) => {}
                    n => return Err(Diagnostic::error(
                        Code::Unsupported,
                        span,
                        format!("{n}(…) is not a call threadcut reads on Sinumerik"),
                    )
                    .with_hint("threadcut reads CYCLE97, passes other CYCLE… calls and MSG/WORKPIECE through, and does not follow subprograms")),
                },
                Item::Def { kind, vars } => {
                    for (name, span, value) in vars {
                        let v = match &value {
                            Some(op) => self.value(op)?,
                            None => 0.0,
                        };
                        if kind == "INT" && v.fract() != 0.0 {
                            return Err(Diagnostic::error(
                                Code::OutOfRange,
                                value.map_or(span, |op| op.span()),
                                format!("{name} is an INT and {v} is not a whole number"),
                            ));
                        }
                        self.vars.insert(name, v);
                    }
                }
                // A jump label marks a block; the jumps to it are refused.
                Item::Header | Item::Label => {}
            }
        }
        let mut index = [0; 32];
        let own = line.with_words(&words, &mut index);
        if let Some(span) = machine_axis {
            if !(own.has_g(740) || own.has_g(750)) {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    span,
                    "a machine axis word outside G74/G75: threadcut does not follow machine coordinates",
                ));
            }
        }
        if let Some(call) = cycle {
            if let Some(w) = own.words.iter().find(|w| w.letter != b'N') {
                return Err(Diagnostic::error(
                    Code::Conflict,
                    w.span,
                    format!(
                        "{}{} shares a block with CYCLE97",
                        w.letter as char, w.value
                    ),
                )
                .with_hint("write CYCLE97 in a block of its own"));
            }
            return self.cycle97(&call, &own, modal, warnings);
        }
        if let Some(call) = stock {
            return self.cycle95(&call, &own, modal);
        }
        let mv = match self.read_words(&own, modal, leaves)? {
            Read::Plain => modal.apply(&self.conv, &own)?,
            Read::Applied(mv) => mv,
            read => return Ok(read),
        };
        Ok(Read::Own { mv, words })
    }

    /// `NAME=value`: a parameter, a setting, or an address given by an operand (`X=R1`), which
    /// comes back as a word.
    fn assign(
        &mut self,
        name: &str,
        span: Span,
        value: &Operand,
        machine_axis: &mut Option<Span>,
    ) -> Result<Option<Word>> {
        let letter = name.as_bytes()[0];
        let digits = &name[1..];
        let indexed = !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
        if let (b'T', Operand::Text { .. }) = (letter, value) {
            // A tool by name: its first cutting edge is selected.
            if name.len() == 1 {
                self.offset_active = true;
                return Ok(None);
            }
        }
        match (letter, indexed) {
            (b'R', true) => {
                let v = self.value(value)?;
                let n = digits.parse::<u32>().map_err(|_| {
                    Diagnostic::error(
                        Code::OutOfRange,
                        span,
                        format!("{name} is not an R parameter"),
                    )
                })?;
                self.r.insert(n, v);
                return Ok(None);
            }
            // Spindle speeds and auxiliary functions of a numbered spindle (`S1=500`, `M1=3`).
            (b'S' | b'M' | b'H', true) => {
                self.value(value)?;
                return Ok(None);
            }
            (b'T', true) => {
                self.offset_active = self.value(value)? != 0.0;
                return Ok(None);
            }
            (_, true) => {
                // A machine axis (`X1=0` with G74/G75): X and Z come back as the axes the block
                // names (their values mean nothing there); others are not followed.
                self.value(value)?;
                machine_axis.get_or_insert(span);
                return Ok(matches!(letter, b'X' | b'Z').then(|| Word::assigned(letter, 0.0, span)));
            }
            _ => {}
        }
        if self.vars.contains_key(name) {
            let v = self.value(value)?;
            self.vars.insert(name.to_string(), v);
            return Ok(None);
        }
        if name.len() == 1 {
            let v = self.value(value)?;
            return Ok(Some(Word::assigned(letter, v, span)));
        }
        match name {
            "SF" => {
                let v = self.value(value)?;
                if !(0.0..360.0).contains(&v) {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        value.span(),
                        format!("SF={v}: the start angle is 0 to 359.9999 degrees"),
                    ));
                }
                self.sf = v;
                Ok(None)
            }
            n if PASSIVE_SETTINGS.contains(&n) => {
                self.value(value)?;
                Ok(None)
            }
            n => Err(Diagnostic::error(
                Code::Unsupported,
                span,
                format!("{n}= is not a setting threadcut reads on Sinumerik"),
            )
            .with_hint(
                "threadcut reads R parameters (R1=…), variables declared with DEF, SF=, LIMS= and addresses given a value (X=R1); others, such as the contour's CHF=/RND=, change motion it does not follow",
            )),
        }
    }

    /// A keyword; `true` when threadcut no longer knows where the tool is after the block.
    fn keyword(&mut self, name: &str, span: Span, modal: &mut Modal) -> Result<bool> {
        match name {
            "DIAMON" => {
                self.diam90 = false;
                modal.diameter_x = true;
            }
            "DIAMOF" => {
                self.diam90 = false;
                modal.diameter_x = false;
            }
            "DIAM90" => {
                self.diam90 = true;
                modal.diameter_x = modal.absolute;
            }
            // The block's positions are in machine coordinates.
            "SUPA" => return Ok(true),
            n if PASSIVE_KEYWORDS.contains(&n) => {}
            n if FLOW.contains(&n) => {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    span,
                    format!("{n}: threadcut does not follow this program flow"),
                )
                .with_hint("threadcut follows labels and GOTOF/GOTOB/GOTO/GOTOC, IF/ELSE/ENDIF, WHILE, FOR, LOOP, REPEAT/UNTIL and the PROCs of the same file (docs/dialects/sinumerik.md, \"Program flow\"); not CASE, MCALL, PCALL or REPEAT with labels"))
            }
            n if FRAMES.contains(&n) => return Err(frame_refused(n, span)),
            n => {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    span,
                    format!("{n} is not a word threadcut reads on Sinumerik"),
                )
                .with_hint("a name alone calls a subprogram: threadcut follows the PROCs of the same file, and this program defines no PROC of this name"))
            }
        }
        Ok(false)
    }

    /// The values of a CYCLE97 call's parameters.
    fn cycle97_call(
        &self,
        name: Span,
        args: &[Option<Operand>],
        spans: &[Span],
    ) -> Result<cycle97::Call> {
        if args.len() > cycle97::NAMES.len() {
            return Err(Diagnostic::error(
                Code::Syntax,
                spans[cycle97::NAMES.len()],
                format!(
                    "CYCLE97 takes {} parameters ({}), and this call has {}",
                    cycle97::NAMES.len(),
                    cycle97::NAMES.join(", "),
                    args.len()
                ),
            ));
        }
        let mut values = [None; 17];
        for (i, (arg, span)) in args.iter().zip(spans).enumerate() {
            if let Some(op) = arg {
                values[i] = Some((self.value(op)?, *span));
            }
        }
        Ok(cycle97::Call { name, args: values })
    }

    /// The values of a CYCLE95 call's numeric parameters (NPP, the contour's name, is the
    /// interpreter's: it runs the contour as the cycle's profile).
    fn cycle95_call(
        &self,
        name: Span,
        args: &[Option<Operand>],
        spans: &[Span],
    ) -> Result<cycle95::Call> {
        if args.len() > cycle95::NAMES.len() {
            return Err(Diagnostic::error(
                Code::Syntax,
                spans[cycle95::NAMES.len()],
                format!(
                    "CYCLE95 takes {} parameters ({}), and this call has {}",
                    cycle95::NAMES.len(),
                    cycle95::NAMES.join(", "),
                    args.len()
                ),
            ));
        }
        if !matches!(args.first(), Some(Some(Operand::Text { .. }))) {
            return Err(Diagnostic::error(
                Code::MissingWord,
                spans.first().copied().unwrap_or(name),
                "CYCLE95: NPP, the contour, is text: the subprogram's name (\"NAME\") or two labels of this program (\"START:END\")",
            ));
        }
        let mut values = [None; 12];
        for (i, (arg, span)) in args.iter().zip(spans).enumerate().skip(1) {
            if let Some(op) = arg {
                values[i] = Some((self.value(op)?, *span));
            }
        }
        Ok(cycle95::Call { name, args: values })
    }

    /// A CYCLE95 block: alone in its block, its contour read next.
    fn cycle95(&mut self, call: &cycle95::Call, own: &Line, modal: &Modal) -> Result<Read> {
        if let Some(w) = own.words.iter().find(|w| w.letter != b'N') {
            return Err(Diagnostic::error(
                Code::Conflict,
                w.span,
                format!(
                    "{}{} shares a block with CYCLE95",
                    w.letter as char, w.value
                ),
            )
            .with_hint("write CYCLE95 in a block of its own"));
        }
        self.cycle95 = Some(cycle95::read(call, own, modal)?);
        self.profile_next = true;
        // The block reads the contour the interpreter runs next (no move of its own); the cycle
        // is complete at the contour's end.
        Ok(Read::Applied(None))
    }

    /// A block of CYCLE95's contour: read as any block is, its move added to the contour.
    fn contour_block(&mut self, line: &Line, modal: &mut Modal) -> Result<()> {
        let mut warnings = Vec::new();
        let read = self.read(line, modal, &mut warnings)?;
        let mv = match read {
            Read::Plain => modal.apply(&self.conv, line)?,
            Read::Applied(mv) | Read::Own { mv, .. } => mv,
            Read::Settings => None,
            _ => {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    line.span(),
                    "a cycle inside CYCLE95's contour",
                ))
            }
        };
        match self.cycle95.as_mut() {
            Some(p) => p.block(line, mv),
            None => Ok(()),
        }
    }

    fn cycle97(
        &mut self,
        call: &cycle97::Call,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        let state = cycle97::State {
            offset_active: self.offset_active,
        };
        let job = cycle97::lower(call, line, modal, &state, warnings)?;
        // The cycle's last thread turn leaves its start angle in the setting data, as the
        // expansion (which writes SF on every pass) does.
        self.sf = job.lead.start_phase(job.lead.starts - 1);
        if self.diam90 && !modal.absolute {
            // Expanded under G90, where DIAM90 reads X as a diameter; radius again after.
            modal.diameter_x = true;
            self.restore_diameter = Some(false);
        }
        Ok(Read::Cycle(Box::new(job)))
    }
}

/// A frame (TRANS, ATRANS, G58, G59, …) is refused at its word.
#[cold]
fn frame_refused(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(
        Code::Unsupported,
        span,
        format!("{name}: threadcut does not follow frames, which move every later position"),
    )
    .with_hint("write the positions in the workpiece coordinates the frame gives")
}

/// The terms of a block in Sinumerik's syntax ([`Dialect::terms`]).
fn own_terms(items: Vec<Item>) -> Vec<Term> {
    let number = |op: &Operand| match op {
        Operand::Number { value, .. } => Some(*value),
        _ => None,
    };
    items
        .into_iter()
        .map(|item| match item {
            Item::Word(w) => Term::Word(w),
            Item::Assign { name, span, value } => {
                let letter = name.as_bytes()[0];
                let indexed = name.len() > 1 && name[1..].bytes().all(|b| b.is_ascii_digit());
                match (&value, name.len(), indexed) {
                    (Operand::Text { text, .. }, 1, _) if letter == b'T' => Term::ToolName {
                        name: text.clone(),
                        span,
                    },
                    (_, 1, _) => match number(&value) {
                        Some(v) => Term::Word(Word::assigned(letter, v, span)),
                        None => Term::Assigned { letter, span },
                    },
                    (_, _, true) if letter == b'R' => Term::Data {
                        declares: Vec::new(),
                    },
                    (_, _, true) if matches!(letter, b'X' | b'Z') => {
                        Term::MachineAxis { name, span }
                    }
                    (_, _, true) => Term::Unknown {
                        what: format!("{name}= (an address of a numbered spindle or axis)"),
                        span,
                    },
                    _ => Term::Setting {
                        value: number(&value),
                        name,
                        span,
                    },
                }
            }
            Item::Keyword { name, span } => Term::Keyword { name, span },
            Item::Call { name, span, .. } if PASSIVE_CALLS.contains(&name.as_str()) => {
                Term::Passive { span }
            }
            Item::Call { name, span, .. } => Term::Unknown {
                what: format!("{name}(…)"),
                span,
            },
            Item::Def { vars, .. } => Term::Data {
                declares: vars.into_iter().map(|(n, _, _)| n).collect(),
            },
            Item::Header => Term::ProgramName,
            Item::Label => Term::Data {
                declares: Vec::new(),
            },
        })
        .collect()
}

impl Dialect for Sinumerik {
    fn name(&self) -> &'static str {
        "sinumerik"
    }

    fn conventions(&self) -> &Conventions {
        &self.conv
    }

    fn vocabulary(&self) -> &'static Vocabulary {
        &VOCABULARY
    }

    fn lexicon(&self) -> &'static Lexicon {
        &LEXICON
    }

    /// Lines in Sinumerik's own syntax, G codes other than G0–G3, and the letters `read` looks at
    /// (D and T: the tool offset; L: a subprogram call; E: an exponent to refuse), in one test of
    /// the word summary; and the line after a CYCLE97 expanded under DIAM90 and G91.
    #[inline]
    fn prefilter(&self, line: &Line) -> bool {
        const LETTERS: u32 = WordSummary::letter_mask(b"DTLE");
        line.shape.unread || line.summary.other_g_or_any(LETTERS) || self.restore_diameter.is_some()
    }

    fn at_rest(&self) -> bool {
        self.restore_diameter.is_none()
    }

    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        if let Some(d) = self.restore_diameter.take() {
            modal.diameter_x = d;
        }
        if line.shape.unread {
            self.read_block(line, modal, warnings)
        } else {
            // Sinumerik writes an exponent as `EX` (`1.5EX3`); an E glued to a number is none.
            super::refuse_exponent(line)?;
            self.read_words(line, modal, Leaves::Known)
        }
    }

    fn profile_follows(&mut self) -> bool {
        std::mem::take(&mut self.profile_next)
    }

    fn profile_block(&mut self, line: &Line, modal: &mut Modal) -> Result<()> {
        self.contour_block(line, modal)
    }

    fn profile_end(&mut self, modal: &mut Modal, end: Span) -> Result<Read> {
        match self.cycle95.take() {
            Some(p) => Ok(Read::Turning(Some(Box::new(p.finish(modal, end)?)))),
            None => Ok(Read::Settings),
        }
    }

    /// CYCLE97 takes a taper as the thread's crest diameters at SPL and FPL (S2, S5: "DM1 thread
    /// diameter at the starting point", "DM2 … at the end point"; inside, the tap hole's), the
    /// run-in APP before SPL on the same cone (docs/dialects/sinumerik.md, "Taper threads").
    /// A subprogram called by name from another file: `NAME.SPF` (a subprogram), then
    /// `NAME.MPF` (a main program called as a subprogram), then `NAME` bare, in any case — the
    /// names the control's program memory gives (`_N_NAME_SPF`) as DNC software and the
    /// control's own USB/network drives store them (docs/dialects/sinumerik.md, "Programs in
    /// other files").
    fn program_files(
        &self,
        wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        use crate::interp::library::{FileNames, Wanted};
        match wanted {
            Wanted::Name(name) => FileNames {
                names: vec![format!("{name}.SPF"), format!("{name}.MPF"), name.clone()],
                any_case: true,
            },
            Wanted::Number(_) => FileNames::default(),
        }
    }

    fn macros(&self) -> Option<crate::interp::Syntax> {
        // Program flow, R parameters and DEF variables in expressions, PROC subprograms of the
        // same file (docs/dialects/sinumerik.md, "Program flow"): the main program and 15
        // subprogram levels.
        Some(crate::interp::Syntax {
            lang: crate::interp::Lang::Sinumerik,
            max_call_depth: 16,
            max_macro_depth: 0,
            g65_operations: false,
            m98_l_word: false,
            m97_local_calls: false,
            m99_p_jumps: false,
            wide_commons: false,
            plain_names: &[
                PASSIVE_KEYWORDS,
                PASSIVE_CALLS,
                TURNING_CALLS,
                FRAMES,
                &[
                    "DIAMON", "DIAMOF", "DIAM90", "SUPA", "CYCLE95", "CYCLE97", "CYCLE99",
                ],
            ],
            profile_calls: &["CYCLE95"],
        })
    }

    fn parameters(&self) -> Vec<(String, f64)> {
        let r = self.r.iter().map(|(n, v)| (format!("R{n}"), *v));
        r.chain(self.vars.iter().map(|(k, v)| (k.clone(), *v)))
            .collect()
    }

    fn set_parameter(&mut self, name: &str, value: f64) {
        match name.strip_prefix('R').and_then(|n| n.parse::<u32>().ok()) {
            Some(n) => {
                self.r.insert(n, value);
            }
            None => {
                self.vars.insert(name.to_string(), value);
            }
        }
    }

    fn cycle_taper(&self) -> Option<super::CycleTaper> {
        Some(super::CycleTaper::Diameters(super::TaperDiameters {
            cycles: "CYCLE97 DM1/DM2",
            at_start: "DM1",
            start_point: "SPL",
            at_end: "DM2",
            end_point: "FPL",
            run_in: "APP",
        }))
    }

    fn emit_native(&self, job: &crate::thread::Job) -> std::result::Result<Vec<String>, String> {
        self.native_candidates(job).remove(0)
    }

    /// Sinumerik's own syntax as conversion's terms: address words (an address given a number is
    /// a word), keywords, `T="NAME"`, settings (`LIMS=`, `SF=`, a DEF variable), machine axes
    /// (`X1=0`), R parameters and DEF lines as data (the converted blocks carry their values),
    /// passive calls (MSG) and the program header. What threadcut reads only to refuse (frames,
    /// program flow) is unknown to conversion as well.
    fn terms(&self, line: &Line) -> Option<Result<Vec<Term>>> {
        Some(block::parse(line.text, line.number, line.offset).map(own_terms))
    }

    /// CYCLE97 with the NRC the job's law makes (`cycle97::native`).
    fn native_candidates(
        &self,
        job: &crate::thread::Job,
    ) -> Vec<std::result::Result<Vec<String>, String>> {
        cycle97::native(&self.machine, job)
    }

    fn format(&self) -> Format {
        Format {
            steep_lead_letter: Some('I'),
            start_angle: Some(SF),
            ..Format::lathe(&self.machine, "G33", 'K')
        }
    }
}
