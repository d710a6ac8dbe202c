//! Modal state of a lathe program and the plain moves (G0/G1/G2/G3/thread) between cycles.
//!
//! Each dialect states its conventions (which G code threads, whether U/W are incremental words,
//! whether G90/G91 select the distance mode); the bookkeeping itself is shared.

use super::lexer::{is_plain_motion, Syntax, Word};
use super::reader::{g_code, Line};
use crate::diag::{Code, Diagnostic, Result, Span};
use crate::machine::{AxisPoint, Machine};
use crate::units::{lead_from_tpi, Pos, Resolution, Units};

/// What a dialect's plain blocks mean. Codes are G numbers ×10.
#[derive(Clone, Debug)]
pub struct Conventions {
    /// `U`/`W` are incremental X/Z (Fanuc system A, GSK).
    pub uw_incremental: bool,
    /// `G90`/`G91` select absolute/incremental distance (false where G90 is a turning cycle).
    pub g90_g91_distance: bool,
    /// X words are diameters.
    pub diameter_x: bool,
    /// The single-pass synchronised move (`G32` on Fanuc/GSK, `G33` on LinuxCNC).
    pub thread_move: u16,
    /// The word that carries threads per inch on the thread move (GSK/Fanuc: `I`; none: 0).
    pub tpi_letter: u8,
    /// The word that carries the lead on the thread move (`F` on Fanuc/GSK, `K` on LinuxCNC's G33).
    pub lead_letter: u8,
    /// The lead word is the travel per revolution along the move's path (LinuxCNC's G33 K), not
    /// along its longer axis; `apply` converts it, so every `PlainMove::lead` is the model's.
    pub lead_along_path: bool,
    /// Sets the current position without motion (`G50` on GSK/Fanuc A, `G92` elsewhere; 0: none).
    pub set_position: u16,
    /// G codes that run a canned cycle and leave the tool where it started.
    pub canned_cycles: &'static [u16],
    /// Motion codes the control has and threadcut does not follow (hole-machining canned
    /// cycles, rigid tapping, probing, splines), each with what it is: a block with one is
    /// refused at its word, since the moves after it would be read from the wrong place and its
    /// own moves would be missing. A code's entry also covers its fractional variants (`G38.2`
    /// under `G38`), as [`Vocabulary::get`] does.
    pub unmodelled: &'static [(u16, &'static str)],
    /// The G codes (×10) that select inch and millimetre input: [`G20_G21`] nearly everywhere,
    /// `G70`/`G71` in Fanuc's G-code system C (where G20 and G21 are turning cycles).
    pub units_codes: [u16; 2],
    /// G codes that send axes where the program's coordinates do not say (reference returns,
    /// machine coordinates, another work coordinate system).
    pub positions: PositionCodes,
    /// How the controller writes its lines (bare letters, blanks, comments, lines in its own
    /// syntax): the one place a dialect states it; the reader lexes every line with it.
    pub syntax: Syntax,
}

/// What the motion code `code` (×10) is, when threadcut does not follow it on this control: the
/// code's own entry, else its whole number's (`G38.2` under `G38`).
fn unmodelled(conv: &Conventions, code: u16) -> Option<&'static str> {
    let find = |c: u16| {
        conv.unmodelled
            .iter()
            .find(|(u, _)| *u == c)
            .map(|(_, w)| *w)
    };
    find(code).or_else(|| find(code / 10 * 10))
}

/// The refusal of a motion code threadcut does not follow ([`Conventions::unmodelled`]).
#[cold]
fn not_followed(w: &Word, code: u16, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::Unsupported,
        w.span,
        format!(
            "{} ({what}) is a motion threadcut does not follow yet: its moves would be missing and the moves after it read from the wrong place",
            g_name(code)
        ),
    )
    .with_hint("the program is read up to this block; check or draw the part before it, or the threading part of the program without it (docs/simulation.md, \"Motions not followed\")")
}

/// A reference point of the machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reference {
    /// The first reference point (`G28`; Sinumerik's `G74`).
    First = 0,
    /// The second reference point (`G30`).
    Second = 1,
}

/// The G codes (×10) after which an axis's position is known only from the machine profile, or
/// not at all. Each dialect lists its own (`docs/dialects/README.md`, "Reference returns"); the
/// bookkeeping is [`Modal`]'s. Only blocks with a G code that [`Modal`] does not otherwise know
/// look here: plain moves never do.
#[derive(Clone, Copy, Debug)]
pub struct PositionCodes {
    /// Returns to a reference point through an intermediate point (`G28`, `G30`, Sinumerik's
    /// `G74`): the named axes end at the reference point, which the profile's `[reference]` table
    /// may state.
    pub returns: &'static [(u16, Reference)],
    /// A return without axis words returns every axis (LinuxCNC, Haas); where false it returns
    /// none (Fanuc and its family: "only the axes commanded return").
    pub all_without_axes: bool,
    /// Store the current position as a reference point (LinuxCNC's `G28.1`, `G30.1`).
    pub stores: &'static [(u16, Reference)],
    /// Moves whose named axes end where the program's coordinates do not say: in machine
    /// coordinates (`G53`, Sinumerik's `G153`), or at a point no profile states (Fanuc's floating
    /// reference `G30.1`, Sinumerik's fixed points `G75`).
    pub machine_moves: &'static [u16],
    /// A return from the reference point (`G29`; 0: none): absolute words are its end point;
    /// incremental words count from the intermediate point, which is not tracked.
    pub from_reference: u16,
    /// Work coordinate systems (`G54`…): selecting another one than the one in force moves the
    /// program's coordinates by an offset this reader does not know.
    pub work_systems: &'static [u16],
    /// The work coordinate system in force at power-on (`G54`; Sinumerik's `G500`).
    pub power_on_work_system: u16,
    /// Codes that change the coordinate offsets by amounts this reader does not track (`G10`,
    /// `G52`, Fanuc's workpiece coordinate preset, LinuxCNC's `G92.1`–`G92.3`, Sinumerik's
    /// programmable offsets `G58`/`G59`): every axis becomes unknown, and the block's axis words
    /// are no move.
    pub offset_changes: &'static [u16],
    /// Codes whose axis words are data, not a move: the position stays (Sinumerik's working-area
    /// limits `G25`/`G26`).
    pub not_moves: &'static [u16],
}

/// G54–G59 (×10): the work coordinate systems of Fanuc's lathe G code list, in every G-code system.
const G54_G59: &[u16] = &[540, 550, 560, 570, 580, 590];

/// G54–G59, G59.1–G59.3 (×10): LinuxCNC's nine coordinate systems.
const G54_G59_3: &[u16] = &[540, 550, 560, 570, 580, 590, 591, 592, 593];

/// G28 and G30 (P2, the default of G30's P): the first and second reference points.
const G28_G30: &[(u16, Reference)] = &[(280, Reference::First), (300, Reference::Second)];

impl PositionCodes {
    /// Fanuc's lathe G code list in G-code system A, and the controls that follow it (GSK,
    /// Allen-Bradley, OmniTurn): G28, G30 (P2, its default), G29, G53, G30.1 (the floating
    /// reference point, which no profile states), G54–G59; G10 (data setting: work offsets
    /// among them), G52 (a local coordinate system) and G50.3 (the workpiece coordinate system
    /// preset) change offsets by amounts not kept. The other G-code systems renumber only the
    /// preset (`fanuc_family::GCodes::positions`).
    pub const FANUC: PositionCodes = PositionCodes {
        returns: G28_G30,
        all_without_axes: false,
        stores: &[],
        machine_moves: &[530, 301],
        from_reference: 290,
        work_systems: G54_G59,
        power_on_work_system: 540,
        offset_changes: &[100, 520, 503],
        not_moves: &[],
    };

    /// LinuxCNC: G28/G30 (every axis without axis words), G28.1/G30.1, G53, G54–G59.3; G10
    /// (offsets and tool data), G52 and G92.1–G92.3 change offsets by amounts not kept.
    pub const LINUXCNC: PositionCodes = PositionCodes {
        returns: G28_G30,
        all_without_axes: true,
        stores: &[(281, Reference::First), (301, Reference::Second)],
        machine_moves: &[530],
        from_reference: 0,
        work_systems: G54_G59_3,
        power_on_work_system: 540,
        offset_changes: &[100, 520, 921, 922, 923],
        not_moves: &[],
    };

    /// What `code` does to the position, if anything.
    fn classify(&self, code: u16) -> Option<Special> {
        if let Some(&(_, r)) = self.returns.iter().find(|(c, _)| *c == code) {
            Some(Special::Return(r))
        } else if let Some(&(_, r)) = self.stores.iter().find(|(c, _)| *c == code) {
            Some(Special::Store(r))
        } else if self.machine_moves.contains(&code) {
            Some(Special::MachineMove)
        } else if code == self.from_reference && code != 0 {
            Some(Special::FromReference)
        } else if self.work_systems.contains(&code) {
            Some(Special::WorkSystem(code))
        } else if self.offset_changes.contains(&code) {
            Some(Special::OffsetChange)
        } else if self.not_moves.contains(&code) {
            Some(Special::NotAMove)
        } else {
            None
        }
    }
}

/// A block that puts axes where the program's coordinates do not say.
#[derive(Clone, Copy, Debug)]
enum Special {
    Return(Reference),
    Store(Reference),
    MachineMove,
    FromReference,
    WorkSystem(u16),
    OffsetChange,
    NotAMove,
}

/// Where the tool is, axis by axis (mm, X as a radius, absolute): each axis is known or not on its
/// own. Both are unknown at power-on; an axis becomes known when a block names it with an absolute
/// value, and unknown again after a reference return the profile does not place, a move in machine
/// coordinates, or a change of coordinate system.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Position {
    pub x: Option<f64>,
    pub z: Option<f64>,
}

impl Position {
    /// Neither axis known.
    pub const UNKNOWN: Position = Position { x: None, z: None };

    /// Both axes known, at `p`.
    pub const fn at(p: Pos) -> Position {
        Position {
            x: Some(p.x),
            z: Some(p.z),
        }
    }

    /// The point, when both axes are known.
    #[inline(always)]
    pub fn known(self) -> Option<Pos> {
        match (self.x, self.z) {
            (Some(x), Some(z)) => Some(Pos::new(x, z)),
            _ => None,
        }
    }

    /// The axes that are not known, as the program names them (`"X"`, `"Z"`).
    pub fn unknown_axes(self) -> &'static [&'static str] {
        match (self.x.is_some(), self.z.is_some()) {
            (true, true) => &[],
            (false, true) => &["X"],
            (true, false) => &["Z"],
            (false, false) => &["X", "Z"],
        }
    }
}

/// `G20` inch, `G21` millimetre input.
pub const G20_G21: [u16; 2] = [200, 210];

/// One G code a controller has, as its vocabulary lists it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GCode {
    /// The code ×10 (`G33.1` is 331). A code with no fraction also stands for its fractional
    /// variants (`G5` for `G5.1`), so that a controller's list need not name every one.
    pub code: u16,
    /// The letters its blocks take, where the code means different things on different
    /// controllers (a threading cycle's words); `None`: not stated (every letter).
    pub words: Option<&'static [u8]>,
    /// The code cuts a thread (a synchronised move or a threading cycle).
    pub threads: bool,
}

impl GCode {
    /// A code whose words are not stated.
    pub const fn plain(code: u16) -> GCode {
        GCode {
            code,
            words: None,
            threads: false,
        }
    }

    /// A threading code with the letters its blocks take.
    pub const fn thread(code: u16, words: &'static [u8]) -> GCode {
        GCode {
            code,
            words: Some(words),
            threads: true,
        }
    }

    /// Whether a block of these letters (`G` and `N` aside) fits the code's words.
    pub fn takes(&self, letters: &[u8]) -> bool {
        self.words.is_none_or(|words| {
            letters
                .iter()
                .all(|l| matches!(l, b'G' | b'N') || words.contains(l))
        })
    }
}

/// The G codes a controller has: its dialect states them ([`crate::dialect::Dialect::vocabulary`])
/// and the modal reader refuses every other code with the controller's alarm.
pub struct Vocabulary {
    /// The controller's name, as profiles and messages write it.
    pub controller: &'static str,
    /// The controller's alarm for a G code it does not have (its number and wording).
    pub alarm: &'static str,
    pub g_codes: &'static [GCode],
    /// Fractional codes the controller does not have although [`g_codes`](Self::g_codes) has
    /// their whole number: the numbers its other G-code systems give a function (Fanuc's
    /// workpiece coordinate preset is `G92.1` in systems B and C, where `G92` is system A's
    /// threading cycle; `G50.3` in A, where `G50` is B's and C's polygon turning). Without them a
    /// code would be a preset in one system and pass as nothing in another.
    pub foreign: &'static [u16],
    /// A hint naming the controllers that have a code (with a block of these letters), added to
    /// the alarm; the dialects' module supplies it, since only it knows the other controllers.
    pub others: fn(code: u16, letters: &[u8], except: &Vocabulary) -> Option<String>,
}

impl std::fmt::Debug for Vocabulary {
    /// The controller's name: the list itself is static data.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Vocabulary({})", self.controller)
    }
}

impl Vocabulary {
    /// The entry of a code: the code itself, else (for `G5.1`) its whole number unless the code
    /// is [`foreign`](Self::foreign). The list is
    /// sorted by code (a test keeps every dialect's so).
    pub fn get(&self, code: u16) -> Option<&GCode> {
        let find = |c: u16| {
            self.g_codes
                .binary_search_by_key(&c, |g| g.code)
                .ok()
                .map(|i| &self.g_codes[i])
        };
        find(code).or_else(|| {
            if self.foreign.contains(&code) {
                None
            } else {
                find(code / 10 * 10)
            }
        })
    }

    /// The alarm for the G word `w` of `line`, whose code this controller does not have.
    #[cold]
    pub fn unknown(&self, w: &Word, code: u16, line: &Line) -> Diagnostic {
        let letters: Vec<u8> = line.words.iter().map(|w| w.letter).collect();
        let d = Diagnostic::error(
            Code::UnknownCode,
            w.span,
            format!(
                "{}: {} is not a G code of {}",
                self.alarm,
                g_name(code),
                self.controller
            ),
        );
        match (self.others)(code, &letters, self) {
            Some(hint) => d.with_hint(hint),
            None => d,
        }
    }

    /// The codes that cut threads, as `G32, G76, G92`.
    pub fn thread_codes(&self) -> String {
        self.g_codes
            .iter()
            .filter(|g| g.threads)
            .map(|g| g_name(g.code))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A G code ×10 as written: `G78`, `G33.1`.
pub fn g_name(code: u16) -> String {
    if code.is_multiple_of(10) {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MotionMode {
    Rapid,
    Feed,
    ArcCw,
    ArcCcw,
    Thread,
    /// A canned cycle is modal: its X/Z words do not move the tool's resting point.
    Cycle,
}

/// A plain move decoded from one block, in millimetres and radius. A block is a move when it
/// ends at a known point; where the tool was before it may be unknown on either axis (the first
/// `G0 X.. Z..` of a program, a move after a reference return).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlainMove {
    pub mode: MotionMode,
    /// Where the move starts, as far as it is known.
    pub from: Position,
    pub to: Pos,
    /// Lead in mm per revolution, for thread moves.
    pub lead: Option<f64>,
    /// Spindle angle (degrees) at which a thread move begins when it starts a chain of thread
    /// moves; 0 unless a dialect states one (Sinumerik `SF=`).
    pub phase_deg: f64,
    /// The centre of a G2/G3 arc (mm, X a radius), from its I/K or R words
    /// ([`Modal::arc_centre`]); `None` for other moves, and for an arc whose centre its words do
    /// not give (no I, K or R; R with the end point on the start point or out of its reach; a
    /// start not known).
    pub centre: Option<Pos>,
}

#[derive(Clone, Debug)]
pub struct Modal {
    pub units: Units,
    pub absolute: bool,
    pub diameter_x: bool,
    /// Where the tool is, axis by axis (see [`Position`]).
    pub position: Position,
    pub motion: MotionMode,
    /// The last thread lead programmed (mm/rev), kept apart from the feed rate on purpose.
    pub lead: Option<f64>,
    /// The F register as last written (program units), threads and feeds alike: after an expanded
    /// cycle the output must leave it as the original program would.
    pub f_word: Option<f64>,
    /// What a number without a decimal point is worth in mm and in inch programs.
    pub no_point: [f64; 2],
    /// The least input increment in mm and in inch programs (program units): the program's
    /// [`resolution`](Modal::resolution).
    pub increment: [f64; 2],
    /// Where the first and second reference returns leave the tool ([`Reference`]): from the
    /// profile's `[reference]` table, or stored by the program (LinuxCNC's `G28.1`).
    pub references: [Position; 2],
    /// The work coordinate system in force (×10; G54 at power-on).
    pub work_system: u16,
    /// The G codes the controller has; `None`: every code is accepted (a reader that only reads
    /// back text threadcut wrote).
    pub vocabulary: Option<&'static Vocabulary>,
    /// An arc's I/K are the centre itself, not its distance from the start (LinuxCNC's G90.1,
    /// which its dialect tracks; false at power-on and on every other control).
    pub arc_centre_absolute: bool,
    /// A threading cycle whose pass table does not depend on its start point may start where the
    /// tool's position is not known ([`Modal::assume_start`]; `passes` for a cycle shown without
    /// the lines before it). False: such a cycle is refused, as the control would have no start.
    pub start_unstated: bool,
    /// The axes (X, Z) of the current cycle's start point that were not known and were taken at
    /// [`UNSTATED_START`]: what depends on them is not known. Cleared after the cycle's event.
    pub assumed: [bool; 2],
}

/// Where a cycle's start is taken on an axis whose position is not known, when the run allows it
/// ([`Modal::start_unstated`]), in mm, X a radius: far outside any lathe's part, so that the side
/// reads as external (the start X above the thread's X) and the start Z lies before the thread's
/// end on the usual side (a thread cut toward −Z). Nothing placed from it is ever reported: the
/// columns that depend on it are not known.
pub const UNSTATED_START: Pos = Pos {
    x: 10_000.0,
    z: 10_000.0,
};

impl Modal {
    /// `no_point`: the worth of a number written without a decimal point, in mm and in inch
    /// programs (1.0 for "calculator" input, the least increment otherwise).
    /// The program's resolution is IS-B's (0.001 mm, 0.0001 inch) and no reference point is known:
    /// [`for_machine`](Modal::for_machine) takes both from a machine profile.
    pub fn new(conv: &Conventions, units: Units, no_point: [f64; 2]) -> Modal {
        Modal {
            units,
            absolute: true,
            diameter_x: conv.diameter_x,
            position: Position::UNKNOWN,
            motion: MotionMode::Rapid,
            lead: None,
            f_word: None,
            no_point,
            increment: [0.001, 0.0001],
            references: [Position::UNKNOWN; 2],
            work_system: conv.positions.power_on_work_system,
            vocabulary: None,
            arc_centre_absolute: false,
            start_unstated: false,
            assumed: [false; 2],
        }
    }

    /// Whether `other` is this very state, every number to the bit (−0 is not 0): a run from
    /// either reads every later line the same. (Every field is named here, so that a field added
    /// to the state cannot be left out of the comparison.)
    pub fn same(&self, other: &Modal) -> bool {
        let Modal {
            units,
            absolute,
            diameter_x,
            position,
            motion,
            lead,
            f_word,
            no_point,
            increment,
            references,
            work_system,
            vocabulary,
            arc_centre_absolute,
            start_unstated,
            assumed,
        } = self;
        fn num(a: f64, b: f64) -> bool {
            a.to_bits() == b.to_bits()
        }
        fn opt(a: Option<f64>, b: Option<f64>) -> bool {
            match (a, b) {
                (Some(a), Some(b)) => num(a, b),
                (a, b) => a.is_none() && b.is_none(),
            }
        }
        fn at(a: &Position, b: &Position) -> bool {
            opt(a.x, b.x) && opt(a.z, b.z)
        }
        *units == other.units
            && *absolute == other.absolute
            && *diameter_x == other.diameter_x
            && at(position, &other.position)
            && *motion == other.motion
            && opt(*lead, other.lead)
            && opt(*f_word, other.f_word)
            && no_point
                .iter()
                .zip(&other.no_point)
                .all(|(a, b)| num(*a, *b))
            && increment
                .iter()
                .zip(&other.increment)
                .all(|(a, b)| num(*a, *b))
            && references
                .iter()
                .zip(&other.references)
                .all(|(a, b)| at(a, b))
            && *work_system == other.work_system
            && match (vocabulary, other.vocabulary) {
                (Some(a), Some(b)) => std::ptr::eq(*a, b),
                (a, b) => a.is_none() && b.is_none(),
            }
            && *arc_centre_absolute == other.arc_centre_absolute
            && *start_unstated == other.start_unstated
            && *assumed == other.assumed
    }

    /// The tool placed at (`x`, `z`) as the program writes them at power-on (its units, X on
    /// diameter where the control's X is), before the program's first line (`--start X,Z`).
    pub fn place(&mut self, x: f64, z: f64) {
        self.position = Position::at(Pos::new(self.x_to_mm(x), self.units.to_mm(z)));
    }

    /// Where a cycle starts whose pass table does not depend on its start point: the tool's
    /// position, its unknown axes taken at [`UNSTATED_START`] and marked [`assumed`](Modal::assumed)
    /// when the run allows it (`None` otherwise, and the cycle is refused).
    pub fn start_or_unstated(&mut self) -> Option<Pos> {
        let p = self.position;
        self.assumed = [p.x.is_none(), p.z.is_none()];
        if let Some(known) = p.known() {
            return Some(known);
        }
        if !self.start_unstated {
            self.assumed = [false; 2];
            return None;
        }
        Some(Pos::new(
            p.x.unwrap_or(UNSTATED_START.x),
            p.z.unwrap_or(UNSTATED_START.z),
        ))
    }

    /// After a cycle: the tool at `end`, except on an axis whose start was not known (the cycle
    /// returns there).
    pub fn cycle_ended(&mut self, end: Pos) {
        self.position = Position::at(end);
        if self.assumed[0] {
            self.position.x = None;
        }
        if self.assumed[1] {
            self.position.z = None;
        }
    }

    /// The modal state at power-on of `machine`: its units, decimal-point convention, resolution
    /// and reference points.
    pub fn for_machine(conv: &Conventions, machine: &Machine) -> Modal {
        let mut m = Modal::new(
            conv,
            machine.units,
            [
                machine.no_point_scale(Units::Mm),
                machine.no_point_scale(Units::Inch),
            ],
        );
        m.increment = [
            machine.resolution(Units::Mm),
            machine.resolution(Units::Inch),
        ];
        if let Some(r) = &machine.reference {
            // Stated as the program writes at power-on: the profile's units and X convention.
            let at = |p: AxisPoint| Position {
                x: p.x.map(|x| m.x_to_mm(x)),
                z: p.z.map(|z| m.units.to_mm(z)),
            };
            m.references = [at(r.g28), at(r.g30)];
        }
        m
    }

    /// The program's resolution as it stands (units and X convention may change mid-program).
    pub fn resolution(&self) -> Resolution {
        Resolution::new(
            self.increment[(self.units == Units::Inch) as usize],
            self.units,
            self.diameter_x,
        )
    }

    /// A word's value in program units, applying the decimal-point convention.
    pub fn value(&self, w: &Word) -> f64 {
        if w.has_dot {
            w.value
        } else {
            w.value
                * match self.units {
                    Units::Mm => self.no_point[0],
                    Units::Inch => self.no_point[1],
                }
        }
    }

    /// A length word in mm.
    pub fn length_mm(&self, w: &Word) -> f64 {
        self.units.to_mm(self.value(w))
    }

    /// An X value as written, in mm radius.
    pub fn x_to_mm(&self, written: f64) -> f64 {
        let r = if self.diameter_x {
            written / 2.0
        } else {
            written
        };
        self.units.to_mm(r)
    }

    /// An X value in mm radius, as this program would write it.
    pub fn x_from_mm(&self, radius_mm: f64) -> f64 {
        let v = self.units.from_mm(radius_mm);
        if self.diameter_x {
            v * 2.0
        } else {
            v
        }
    }

    /// The end point named by X/U and Z/W words, relative to `from`. Absent words keep `from`.
    pub fn target(&self, conv: &Conventions, line: &Line, from: Pos) -> Result<Pos> {
        let mut to = from;
        let (mut x_seen, mut z_seen) = (None::<&Word>, None::<&Word>);
        for w in line.words {
            let (axis_seen, incremental) = match w.letter {
                b'X' => (&mut x_seen, !self.absolute),
                b'Z' => (&mut z_seen, !self.absolute),
                b'U' if conv.uw_incremental => (&mut x_seen, true),
                b'W' if conv.uw_incremental => (&mut z_seen, true),
                _ => continue,
            };
            if let Some(first) = axis_seen.replace(w) {
                return Err(axis_twice(first, w));
            }
            let is_x = matches!(w.letter, b'X' | b'U');
            if incremental && self.assumed[usize::from(!is_x)] {
                return Err(Diagnostic::error(
                    Code::UnknownPosition,
                    w.span,
                    format!(
                        "{} counts from the cycle's start point, and the tool's {} is not known here",
                        w.letter as char,
                        if is_x { "X" } else { "Z" }
                    ),
                )
                .with_hint("write the end point in absolute coordinates, or give the start point (--start X,Z)"));
            }
            let v = if is_x {
                self.x_to_mm(self.value(w))
            } else {
                self.length_mm(w)
            };
            match (is_x, incremental) {
                (true, false) => to.x = v,
                (true, true) => to.x = from.x + v,
                (false, false) => to.z = v,
                (false, true) => to.z = from.z + v,
            }
            if !to.is_finite() {
                return Err(Diagnostic::error(
                    Code::BadNumber,
                    w.span,
                    "this value puts the tool beyond any representable position",
                ));
            }
        }
        Ok(to)
    }

    /// Applies a block that is not a threading cycle: modal codes, then any motion.
    #[inline(always)]
    pub fn apply(&mut self, conv: &Conventions, line: &Line) -> Result<Option<PlainMove>> {
        self.apply_block::<true>(conv, line)
    }

    /// [`apply`](Self::apply) for a caller that only needs the state after the block (`expand`
    /// copying plain lines): the same state and the same errors; a plain arc's centre, which has
    /// neither, is not computed (`None` in the move).
    #[inline(always)]
    pub fn advance(&mut self, conv: &Conventions, line: &Line) -> Result<Option<PlainMove>> {
        self.apply_block::<false>(conv, line)
    }

    #[inline(always)]
    fn apply_block<const CENTRE: bool>(
        &mut self,
        conv: &Conventions,
        line: &Line,
    ) -> Result<Option<PlainMove>> {
        // Most blocks are a plain move: no G code but G0–G3, no letter written twice, from a known
        // position. Their words are found through the lexer's index, without a look at each word
        // (measured: a quarter of the pass-through time went to that look, docs/performance.md).
        // Every other block goes through its words the general way, in `apply_words`.
        if line.summary.other_g() || !line.letters_unique() {
            return self.apply_words(conv, line);
        }
        if let Some(g) = line.unique_word(b'G') {
            // The summary promises G0–G3.
            self.motion = plain_motion(g);
        }
        let plain_motion = matches!(
            self.motion,
            MotionMode::Rapid | MotionMode::Feed | MotionMode::ArcCw | MotionMode::ArcCcw
        );
        let (x, z) = (line.unique_word(b'X'), line.unique_word(b'Z'));
        let (x, z, named_twice) = if conv.uw_incremental {
            let (u, w) = (line.unique_word(b'U'), line.unique_word(b'W'));
            (
                x.or(u),
                z.or(w),
                (x.is_some() && u.is_some()) || (z.is_some() && w.is_some()),
            )
        } else {
            (x, z, false)
        };
        let (Some(fx), Some(fz), true, false) =
            (self.position.x, self.position.z, plain_motion, named_twice)
        else {
            // (G0–G3 applied above are applied again there, in their place: the same result.)
            return self.apply_words(conv, line);
        };
        let from = Pos::new(fx, fz);
        if let Some(f) = line.unique_word(b'F') {
            self.f_word = Some(self.value(f));
        }
        if x.is_none() && z.is_none() {
            return Ok(None);
        }
        let to = self.end_point(x, z, from);
        self.position = Position::at(to);
        Ok(Some(PlainMove {
            mode: self.motion,
            from: Position::at(from),
            to,
            lead: None,
            phase_deg: 0.0,
            centre: if CENTRE {
                self.arc_centre(line, from, to)
            } else {
                None
            },
        }))
    }

    /// [`apply`](Self::apply) word by word: modal codes in the order written, then any motion.
    #[inline(never)]
    fn apply_words(&mut self, conv: &Conventions, line: &Line) -> Result<Option<PlainMove>> {
        let mut dwell = false;
        let mut set_position = false;
        let mut special = None;
        let mut work_system = None;
        let mut store = None;
        let mut f_word = None;
        // One pass over the words: the axis words are remembered here, so that the end point is
        // computed without a second scan (`axes` gives exactly what `target` would).
        let mut axes = AxisWords::default();
        // Written as a few two-way branches rather than a `match` on the letter and on the code:
        // multi-way jumps on data that changes from word to word mispredict far more often.
        let axis_letters = if conv.uw_incremental { 4 } else { 2 };
        for w in line.words {
            let axis = AXES[w.letter as usize & 0x7f];
            if axis != 0 && axis <= axis_letters {
                if axis & 1 == 1 {
                    axes.see_x(w);
                } else {
                    axes.see_z(w);
                }
            } else if w.letter == b'G' {
                // Most G words are G0–G3: no need for `g_code`'s rounding.
                if is_plain_motion(w.value, w.has_dot) {
                    self.motion = plain_motion(w);
                    continue;
                }
                let Some(code) = g_code(w.value) else {
                    return Err(bad_g(w));
                };
                if code <= 30 && code % 10 == 0 {
                    self.motion = PLAIN_MOTION[usize::from(code / 10)];
                } else {
                    match code {
                        40 => dwell = true,
                        c if c == conv.units_codes[0] => self.units = Units::Inch,
                        c if c == conv.units_codes[1] => self.units = Units::Mm,
                        900 if conv.g90_g91_distance => self.absolute = true,
                        910 if conv.g90_g91_distance => self.absolute = false,
                        c if c == conv.thread_move => self.motion = MotionMode::Thread,
                        c if c == conv.set_position && c != 0 => set_position = true,
                        c if conv.canned_cycles.contains(&c) => self.motion = MotionMode::Cycle,
                        c if unmodelled(conv, c).is_some() => {
                            return Err(not_followed(w, c, unmodelled(conv, c).unwrap_or("")));
                        }
                        c => {
                            if let Some(v) = self.vocabulary {
                                if v.get(c).is_none() {
                                    return Err(v.unknown(w, c, line));
                                }
                            }
                            match conv.positions.classify(c) {
                                Some(Special::WorkSystem(code)) => work_system = Some(code),
                                Some(Special::Store(r)) => store = Some(r),
                                Some(s) => special = Some(s),
                                None => {}
                            }
                        }
                    }
                }
            } else if w.letter == b'F' {
                f_word = Some(w);
            }
        }
        if self.motion == MotionMode::Thread {
            self.read_lead(conv, line.words)?;
        }
        if let Some(f) = f_word {
            self.f_word = Some(self.value(f));
        }
        // A change of coordinate system and a stored reference point take effect before the
        // block's motion (`G55 G0 X20 Z5` moves in G55's coordinates).
        if let Some(code) = work_system {
            if code != self.work_system {
                self.work_system = code;
                self.position = Position::UNKNOWN;
            }
        }
        if let Some(r) = store {
            self.references[r as usize] = self.position;
        }
        if let Some(special) = special {
            self.apply_special(conv, special, &axes)?;
            return Ok(None);
        }
        if dwell || (axes.x.is_none() && axes.z.is_none()) {
            return Ok(None);
        }
        if set_position {
            self.position = self.end_of(&axes, self.position)?;
            return Ok(None);
        }
        if self.motion == MotionMode::Cycle {
            return Ok(None);
        }
        let from = self.position;
        let end = self.end_of(&axes, from)?;
        self.position = end;
        // A block that ends where the program cannot say is no move to report.
        let Some(to) = end.known() else {
            return Ok(None);
        };
        let lead = if self.motion == MotionMode::Thread {
            let Some(lead) = self.lead else {
                return Err(no_lead(line.span()));
            };
            Some(if conv.lead_along_path {
                // The lead along the path needs the path: where the move starts on each axis
                // it moves along.
                let Some(start) = self.path_start(from, to, &axes) else {
                    return Err(thread_from_unknown(line.span(), from));
                };
                crate::post::long_axis_lead(lead, to.minus(start))
            } else {
                lead
            })
        } else {
            None
        };
        let centre = from.known().and_then(|f| self.arc_centre(line, f, to));
        Ok(Some(PlainMove {
            mode: self.motion,
            from,
            to,
            lead,
            phase_deg: 0.0,
            centre,
        }))
    }

    /// The centre of the arc from `from` to `to` that `line` describes in the motion mode in
    /// force (mm, X a radius); `None` when the mode is not G2/G3 or the words give no centre.
    ///
    /// * R (it takes precedence over I/K, as on Fanuc's controls: "If I, J, K, and R addresses are
    ///   specified simultaneously, the arc specified by address R takes precedence"): the centre
    ///   on the side of the chord that gives the shorter arc for R > 0, the longer for R < 0
    ///   (RS274/NGC's rule, which LinuxCNC's `arc_data_r` follows). A half chord longer than |R|
    ///   by at most the program's resolution puts the centre on the chord's midpoint; further
    ///   out, or an end on the start, there is no centre.
    /// * I/K: the distance from the start to the centre, I a radius whatever the X convention
    ///   (Fanuc's lathe controls and LinuxCNC's `arc_data_ijk`, G7 or not); the centre itself
    ///   under [`arc_centre_absolute`](Modal::arc_centre_absolute) (LinuxCNC's G90.1).
    ///
    /// The arc runs clockwise for G2 as seen with Z to the right and X up (the ZX plane seen from
    /// +Y, ISO 6983's G18).
    pub fn arc_centre(&self, line: &Line, from: Pos, to: Pos) -> Option<Pos> {
        let clockwise = match self.motion {
            MotionMode::ArcCw => true,
            MotionMode::ArcCcw => false,
            _ => return None,
        };
        if let Some(r) = line.word(b'R') {
            let r = self.length_mm(r);
            return centre_from_radius(from, to, r, clockwise, self.resolution().increment_mm());
        }
        let (i, k) = (line.word(b'I'), line.word(b'K'));
        if i.is_none() && k.is_none() {
            return None;
        }
        let offset = |w: Option<&Word>| w.map_or(0.0, |w| self.length_mm(w));
        let centre = if self.arc_centre_absolute {
            Pos::new(offset(i), offset(k))
        } else {
            Pos::new(from.x + offset(i), from.z + offset(k))
        };
        centre.is_finite().then_some(centre)
    }

    /// Where a move to `to` starts, when the start is known on every axis the move runs along:
    /// an axis the block does not name does not move, whether its position is known or not
    /// (it is known here: `to` is).
    fn path_start(&self, from: Position, to: Pos, axes: &AxisWords) -> Option<Pos> {
        let x = if axes.x.is_some() { from.x? } else { to.x };
        let z = if axes.z.is_some() { from.z? } else { to.z };
        Some(Pos::new(x, z))
    }

    /// A block of [`PositionCodes`]: reference returns, machine coordinates, coordinate systems.
    fn apply_special(
        &mut self,
        conv: &Conventions,
        special: Special,
        axes: &AxisWords,
    ) -> Result<()> {
        if let Some(second) = axes.conflict {
            return Err(axis_twice(axes.first_on_axis_of(second), second));
        }
        let named = (axes.x.is_some(), axes.z.is_some());
        match special {
            Special::Return(r) => {
                // The named axes (or every axis, where a bare return returns all) go through the
                // intermediate point to the reference point.
                let (x, z) = if named == (false, false) && conv.positions.all_without_axes {
                    (true, true)
                } else {
                    named
                };
                let at = self.references[r as usize];
                if x {
                    self.position.x = at.x;
                }
                if z {
                    self.position.z = at.z;
                }
            }
            Special::MachineMove => {
                if named.0 {
                    self.position.x = None;
                }
                if named.1 {
                    self.position.z = None;
                }
            }
            Special::FromReference => {
                // Absolute words are the end point; incremental ones count from the intermediate
                // point, which this reader does not keep.
                let end = self.end_of(axes, Position::UNKNOWN)?;
                if named.0 {
                    self.position.x = end.x;
                }
                if named.1 {
                    self.position.z = end.z;
                }
            }
            Special::OffsetChange => self.position = Position::UNKNOWN,
            Special::NotAMove => {}
            // Taken before the block's motion, in `apply_words`.
            Special::WorkSystem(_) | Special::Store(_) => {}
        }
        Ok(())
    }

    /// The end of a block's axis words from `from`, axis by axis: an absolute word makes its axis
    /// known, an incremental one keeps it as known as it was, an axis not named stays as it is.
    fn end_of(&self, axes: &AxisWords, from: Position) -> Result<Position> {
        if let Some(second) = axes.conflict {
            return Err(axis_twice(axes.first_on_axis_of(second), second));
        }
        let mut to = from;
        if let Some(w) = axes.x {
            let v = self.x_to_mm(self.value(w));
            to.x = if w.letter == b'U' || !self.absolute {
                from.x.map(|x| x + v)
            } else {
                Some(v)
            };
        }
        if let Some(w) = axes.z {
            let v = self.length_mm(w);
            to.z = if w.letter == b'W' || !self.absolute {
                from.z.map(|z| z + v)
            } else {
                Some(v)
            };
        }
        Ok(to)
    }

    /// The end point named by one X (or U) and one Z (or W) word, either or both absent.
    #[inline(always)]
    fn end_point(&self, x: Option<&Word>, z: Option<&Word>, from: Pos) -> Pos {
        let mut to = from;
        if let Some(w) = x {
            let v = self.x_to_mm(self.value(w));
            to.x = if w.letter == b'U' || !self.absolute {
                from.x + v
            } else {
                v
            };
        }
        if let Some(w) = z {
            let v = self.length_mm(w);
            to.z = if w.letter == b'W' || !self.absolute {
                from.z + v
            } else {
                v
            };
        }
        to
    }

    /// Reads F (lead in program units per revolution) or the dialect's TPI word into the modal lead.
    pub fn read_lead(&mut self, conv: &Conventions, words: &[Word]) -> Result<()> {
        let word = |letter| words.iter().find(|w: &&Word| w.letter == letter);
        let f = word(conv.lead_letter);
        let tpi = (conv.tpi_letter != 0)
            .then(|| word(conv.tpi_letter))
            .flatten();
        match (f, tpi) {
            (Some(f), Some(i)) => Err(Diagnostic::error(
                Code::Conflict,
                i.span,
                "F (lead) and I (threads per inch) in one block",
            )
            .with_hint(format!(
                "keep one of them; {}{} was also given",
                conv.lead_letter as char, f.value
            ))),
            (Some(f), None) => {
                // A lead below the program's resolution is no lead.
                if !self.resolution().length().gt(self.length_mm(f), 0.0) {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        f.span,
                        format!(
                            "{}{} lead must be positive",
                            conv.lead_letter as char, f.value
                        ),
                    ));
                }
                self.lead = Some(self.length_mm(f));
                Ok(())
            }
            (None, Some(i)) => {
                if i.value <= 0.0 {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        i.span,
                        format!("I{} threads per inch must be positive", i.value),
                    ));
                }
                self.lead = Some(lead_from_tpi(i.value));
                Ok(())
            }
            (None, None) => Ok(()),
        }
    }
}

/// Axis letters for [`Modal::apply`]: odd for X, even for Z; U and W (3, 4) only count where they
/// are incremental words.
const AXES: [u8; 128] = {
    let mut t = [0; 128];
    t[b'X' as usize] = 1;
    t[b'Z' as usize] = 2;
    t[b'U' as usize] = 3;
    t[b'W' as usize] = 4;
    t
};

/// The motion of a `G0`–`G3` word ([`is_plain_motion`]): its whole number 0–3 is in the low bits
/// of the value plus 2^52 (no rounding and no conversion to an integer).
#[inline(always)]
fn plain_motion(g: &Word) -> MotionMode {
    const TWO_POW_52: f64 = 4_503_599_627_370_496.0;
    PLAIN_MOTION[(g.value + TWO_POW_52).to_bits() as usize & 3]
}

/// The centre of an arc of radius `r` (mm; negative: the longer arc) from `from` to `to`,
/// clockwise (G2) or not, in the ZX plane with Z as the first axis ([`Modal::arc_centre`]). A
/// half chord longer than |r| by at most `slack` (mm) puts the centre on the chord's midpoint.
pub fn centre_from_radius(from: Pos, to: Pos, r: f64, clockwise: bool, slack: f64) -> Option<Pos> {
    let (dz, dx) = (to.z - from.z, to.x - from.x);
    let d = dz.hypot(dx);
    if d.is_nan() || d <= 0.0 || !r.is_finite() || r == 0.0 {
        return None;
    }
    let half = d / 2.0;
    let excess = half - r.abs();
    if excess > slack {
        return None;
    }
    let h = if excess >= 0.0 {
        0.0
    } else {
        (r * r - half * half).sqrt()
    };
    // Seen with Z to the right and X up, the centre of a clockwise arc shorter than a half
    // circle lies right of the chord: the chord's direction (dz, dx) turned a quarter clockwise,
    // (dx, −dz); a counter-clockwise or a longer arc's lies left.
    let side = if clockwise == (r > 0.0) { 1.0 } else { -1.0 };
    let k = side * h / d;
    Some(Pos::new(
        (from.x + to.x) / 2.0 - k * dz,
        (from.z + to.z) / 2.0 + k * dx,
    ))
}

/// G0, G1, G2, G3.
const PLAIN_MOTION: [MotionMode; 4] = [
    MotionMode::Rapid,
    MotionMode::Feed,
    MotionMode::ArcCw,
    MotionMode::ArcCcw,
];

/// The X/U and Z/W words of a block, in one pass: the first of each axis and the first word that
/// names an axis already named (the error [`Modal::target`] reports).
#[derive(Default)]
struct AxisWords<'w> {
    x: Option<&'w Word>,
    z: Option<&'w Word>,
    conflict: Option<&'w Word>,
}

impl<'w> AxisWords<'w> {
    #[inline(always)]
    fn see_x(&mut self, w: &'w Word) {
        if self.x.is_some() {
            self.conflict.get_or_insert(w);
        } else {
            self.x = Some(w);
        }
    }

    #[inline(always)]
    fn see_z(&mut self, w: &'w Word) {
        if self.z.is_some() {
            self.conflict.get_or_insert(w);
        } else {
            self.z = Some(w);
        }
    }

    fn first_on_axis_of(&self, w: &'w Word) -> &'w Word {
        let first = if matches!(w.letter, b'X' | b'U') {
            self.x
        } else {
            self.z
        };
        first.unwrap_or(w)
    }
}

#[cold]
fn no_lead(line: Span) -> Diagnostic {
    Diagnostic::error(Code::MissingWord, line, "thread move without a lead")
        .with_hint("program F (lead) on the first thread move")
}

#[cold]
fn thread_from_unknown(line: Span, from: Position) -> Diagnostic {
    Diagnostic::error(
        Code::UnknownPosition,
        line,
        format!(
            "the thread move's lead is along its path, and the tool's {} before it is not known here",
            from.unknown_axes().join(" and ")
        ),
    )
    .with_hint("position the tool with G0 X.. Z.. before the thread move")
}

#[cold]
fn axis_twice(first: &Word, second: &Word) -> Diagnostic {
    Diagnostic::error(
        Code::Conflict,
        second.span,
        format!(
            "{} and {} in one block name the same axis twice",
            first.letter as char, second.letter as char
        ),
    )
}

#[cold]
fn bad_g(w: &Word) -> Diagnostic {
    Diagnostic::error(
        Code::Syntax,
        w.span,
        format!("G{} is not a G code", w.value),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gcode::Reader;

    fn conv() -> Conventions {
        Conventions {
            uw_incremental: true,
            g90_g91_distance: false,
            diameter_x: true,
            thread_move: 320,
            tpi_letter: b'I',
            lead_letter: b'F',
            lead_along_path: false,
            set_position: 500,
            canned_cycles: &[900, 920, 940, 710, 720, 730, 700, 760, 780],
            unmodelled: &[(830, "peck drilling cycle")],
            units_codes: G20_G21,
            positions: PositionCodes::FANUC,
            syntax: Syntax::default(),
        }
    }

    fn run(src: &str) -> (Modal, Vec<PlainMove>) {
        let c = conv();
        let mut m = Modal::new(&c, Units::Mm, [1.0, 1.0]);
        let mut r = Reader::new(src.as_bytes());
        let mut moves = vec![];
        while let Some(l) = r.next_line() {
            let l = l.unwrap();
            if let Some(mv) = m.apply(&c, &l).unwrap() {
                moves.push(mv);
            }
        }
        (m, moves)
    }

    #[test]
    fn diameter_x_and_incremental_uw() {
        let (m, moves) = run("G0 X80 Z10\nG1 U-10 W-5\nG32 Z-20 F2\n");
        assert_eq!(m.position, Position::at(Pos::new(35.0, -20.0)));
        // The first positioning starts nowhere known and ends at a known point: it is a move.
        assert_eq!(moves.len(), 3);
        assert_eq!(
            (moves[0].from, moves[0].to),
            (Position::UNKNOWN, Pos::new(40.0, 10.0))
        );
        assert_eq!(moves[1].to, Pos::new(35.0, 5.0));
        assert_eq!(
            (moves[2].mode, moves[2].lead),
            (MotionMode::Thread, Some(2.0))
        );
    }

    #[test]
    fn inch_and_tpi() {
        let (m, moves) = run("G20\nG0 X2 Z1\nG32 Z0 I8\n");
        assert_eq!(m.position, Position::at(Pos::new(25.4, 0.0)));
        assert_eq!(moves[1].lead, Some(3.175));
    }

    #[test]
    fn dwell_cycles_and_home_do_not_move() {
        let (m, _) = run("G0 X50 Z5\nG04 X2\nG90 X40 Z-20 F0.2\nX38\n");
        assert_eq!(m.position, Position::at(Pos::new(25.0, 5.0)));
        let (m, _) = run("G0 X50 Z5\nG28 U0 W0\n");
        assert_eq!(m.position, Position::UNKNOWN);
    }

    #[test]
    fn one_pass_end_point_is_target() {
        // `apply` picks the axis words out in its own pass; `target` is the reference.
        let c = conv();
        let mut plain = conv();
        plain.uw_incremental = false;
        for conv in [c, plain] {
            for text in [
                "G1 X30 Z-2",
                "G1 U-3 W-0.5",
                "G2 Z-4.5 U1 R2",
                "G3 X21.5",
                "W2.25",
                "G0 U7 Z1 F0.2",
            ] {
                let mut m = Modal::new(&conv, Units::Mm, [1.0, 1.0]);
                let src = format!("G0 X50 Z5\n{text}\n");
                let mut r = Reader::new(src.as_bytes());
                m.apply(&conv, &r.next_line().unwrap().unwrap()).unwrap();
                let line = r.next_line().unwrap().unwrap();
                let from = m.position.known().unwrap();
                let want = m.target(&conv, &line, from).unwrap();
                let mv = m.apply(&conv, &line).unwrap();
                assert_eq!(m.position, Position::at(want), "{text}");
                let names_axis = line.words.iter().any(|w| {
                    matches!(w.letter, b'X' | b'Z')
                        || (conv.uw_incremental && matches!(w.letter, b'U' | b'W'))
                });
                let got = mv.map(|mv| (mv.from.known().unwrap(), mv.to));
                assert_eq!(got, names_axis.then_some((from, want)), "{text}");
            }
        }
        // U and W are not axis words where they are not incremental: only Z moves.
        let mut m = Modal::new(&plain_conv(), Units::Mm, [1.0, 1.0]);
        let mut r = Reader::new(&b"G0 X50 Z5\nG1 U5 Z2\n"[..]);
        m.apply(&plain_conv(), &r.next_line().unwrap().unwrap())
            .unwrap();
        m.apply(&plain_conv(), &r.next_line().unwrap().unwrap())
            .unwrap();
        assert_eq!(m.position, Position::at(Pos::new(25.0, 2.0)));
    }

    #[test]
    fn units_codes_are_the_dialects() {
        // Fanuc's G-code system C: G70/G71 select inch/mm; G20 is a turning cycle there.
        let c = Conventions {
            units_codes: [700, 710],
            canned_cycles: &[200, 210, 240],
            ..conv()
        };
        let mut m = Modal::new(&c, Units::Mm, [1.0, 1.0]);
        let mut r = Reader::new(&b"G70\nG20 X1 Z1\nG71\nG21\n"[..]);
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        assert_eq!(m.units, Units::Inch);
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        assert_eq!((m.units, m.motion), (Units::Inch, MotionMode::Cycle));
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        assert_eq!(m.units, Units::Mm);
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        assert_eq!(m.units, Units::Mm, "G21 is no units code in system C");
    }

    fn plain_conv() -> Conventions {
        Conventions {
            uw_incremental: false,
            ..conv()
        }
    }

    #[test]
    fn z_and_w_together_is_an_error_at_the_second() {
        let c = conv();
        let mut m = Modal::new(&c, Units::Mm, [1.0, 1.0]);
        let mut r = Reader::new(&b"G0 X1 Z1\nG1 W3 X2 Z4 U1\n"[..]);
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        let line = r.next_line().unwrap().unwrap();
        let want = m.target(&c, &line, Pos::default()).unwrap_err();
        let e = m.apply(&c, &line).unwrap_err();
        assert_eq!(e, want);
        // Z4 (column 10) is the first word to name an axis already named, by W3.
        assert_eq!((e.code, e.span.column), (Code::Conflict, 10));
        assert!(e.message.starts_with("W and Z"), "{}", e.message);
    }

    #[test]
    fn x_and_u_together_is_an_error() {
        let c = conv();
        let mut m = Modal::new(&c, Units::Mm, [1.0, 1.0]);
        let mut r = Reader::new(&b"G0 X1 Z1\nG0 X2 U3\n"[..]);
        m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap();
        let e = m.apply(&c, &r.next_line().unwrap().unwrap()).unwrap_err();
        assert_eq!((e.code, e.span.line, e.span.column), (Code::Conflict, 2, 7));
    }

    proptest::proptest! {
        /// `apply` finds a plain move's words through the lexer's index and hands every other block
        /// to `apply_words`, which goes through the words in order: both give the same result and
        /// leave the same state, block after block, errors included.
        #[test]
        fn apply_is_apply_words(
            lines in proptest::collection::vec(
                proptest::collection::vec(
                    proptest::sample::select(vec![
                        "G0", "G1", "G01", "G2", "G3", "G4", "G04", "G20", "G21", "G28", "G32",
                        "G50", "G90", "G91", "G1.5", "G1.0", "G29", "G30", "G53", "G54", "G55",
                        "G10", "X10", "X-2.5", "X7", "Z3", "Z-1.25",
                        "Z.5", "U-0.4", "U2", "W2", "W-0.75", "F0.2", "F1.5", "I8", "N10",
                        "T0101", "M08", "R2.5",
                    ]),
                    0..6,
                ),
                1..12,
            ),
            start_known in proptest::bool::ANY,
            uw in proptest::bool::ANY,
        ) {
            let c = if uw { conv() } else { plain_conv() };
            let mut text = String::from(if start_known { "G0 X50 Z5\n" } else { "\n" });
            for words in &lines {
                text.push_str(&words.join(" "));
                text.push('\n');
            }
            let mut fast = Modal::new(&c, Units::Mm, [1.0, 0.0001]);
            let mut general = fast.clone();
            let mut r = Reader::new(text.as_bytes());
            while let Some(line) = r.next_line() {
                let line = line.unwrap();
                let (a, b) = (fast.apply(&c, &line), general.apply_words(&c, &line));
                proptest::prop_assert_eq!(format!("{a:?}"), format!("{b:?}"), "{:?}", line.text);
                proptest::prop_assert_eq!(format!("{fast:?}"), format!("{general:?}"));
            }
        }
    }
}
