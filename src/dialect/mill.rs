//! What a machining centre's control reads: the facts the milling reader (`millprog`) needs about
//! each milling profile's language, stated here so that the reader names no controller.
//!
//! Decisions and their manual sentences: docs/milling.md, "Reading milling programs".

use crate::gcode::lexer::Syntax as Lexer;
use crate::interp::library::{FileNames, Wanted};
use crate::interp::Syntax;

/// How the radii to an arc's start and end may differ before the control's alarm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RadiusCheck {
    /// The Fanuc family: PS0020 past this many least input increments (parameter 3410 is the
    /// machine's; the start, end and centre words are each rounded to the increment, so a
    /// correct arc differs by up to about two, as on the lathe side).
    Increments(f64),
    /// LinuxCNC's `CENTER_ARC_RADIUS_TOLERANCE` rule (2·√2·0.01 mm or 2·√2·0.001 inch, or more
    /// within 0.1 % of the radius, never 100 tolerances), with its message.
    LinuxCnc,
}

/// A control's alarms as it words them (LinuxCNC's as rs274 prints them, checked by
/// `tests/linuxcnc_reference_mill.rs`; the Fanuc family's with the alarm's number where a manual
/// read names it).
#[derive(Clone, Copy, Debug)]
pub struct Alarms {
    /// The radii to an arc's start and end differ.
    pub radius: &'static str,
    /// Compensation started or cancelled on an arc.
    pub comp_on_arc: &'static str,
    /// A straight feed move, and an arc, with no feed rate.
    pub zero_feed: &'static str,
    pub zero_feed_arc: &'static str,
    /// An arc with neither its centre nor R.
    pub no_centre: &'static str,
    /// R shorter than half the chord.
    pub r_too_small: &'static str,
    /// An R arc that ends where it starts.
    pub r_full_circle: &'static str,
    /// A canned cycle without R, without Z, a peck cycle without Q (`{code}`, `{g}`: its G code,
    /// [`Alarms::with_code`]).
    pub cycle_no_r: &'static str,
    pub cycle_no_z: &'static str,
    pub cycle_no_q: &'static str,
    /// LinuxCNC's arc P below 1.
    pub turns: &'static str,
    /// A dwelling cycle (G82, G86, G89) without P, where the control requires it (LinuxCNC).
    pub cycle_no_p: Option<&'static str>,
    /// A tapping cycle with the spindle stopped, or turning against the tap (`{dir}`: the way it
    /// turns), where the control checks it (LinuxCNC).
    pub tap_spindle_stopped: Option<&'static str>,
    pub tap_spindle_reversed: Option<&'static str>,
}

const FANUC_ALARMS: Alarms = Alarms {
    radius: "alarm PS0020 (over tolerance of radius)",
    comp_on_arc: "alarm PS0034 (no circular interpolation allowed in the start-up or cancel block)",
    zero_feed: "alarm PS0011 (feed zero)",
    zero_feed_arc: "alarm PS0011 (feed zero)",
    no_centre: "an arc without its centre or R",
    r_too_small: "alarm PS0020 (over tolerance of radius): R is shorter than half the chord",
    r_full_circle: "an arc by R ends where it starts: a full circle needs I J K",
    cycle_no_r: "{code} without R: where does the feed start (the R level)?",
    cycle_no_z: "{code} without Z: how deep is the hole?",
    cycle_no_q: "{code} without Q: how deep is each peck?",
    turns: "P on an arc",
    cycle_no_p: None,
    tap_spindle_stopped: None,
    tap_spindle_reversed: None,
};

// (Haas's and Centroid's alarm numbers are not stated: no page read names them.)
const PLAIN_ALARMS: Alarms = Alarms {
    radius: "the arc's end radius differs from its start radius",
    comp_on_arc: "compensation is not started or cancelled on an arc",
    zero_feed: "no feed rate is programmed",
    zero_feed_arc: "no feed rate is programmed",
    r_too_small: "R is shorter than half the chord",
    ..FANUC_ALARMS
};

const LINUXCNC_ALARMS: Alarms = Alarms {
    radius: "Radius to end of arc differs from radius to start",
    comp_on_arc:
        "The move just after exiting cutter compensation mode must be straight, not an arc",
    zero_feed: "Cannot do {g} with zero feed rate",
    zero_feed_arc: "Cannot make arc with zero feed rate",
    no_centre: "R i j k words all missing for arc",
    r_too_small: "Arc radius too small to reach end point",
    r_full_circle: "Current point same as end point of arc",
    cycle_no_r: "R clearance plane unspecified in cycle",
    cycle_no_z: "Z value unspecified in xy plane canned cycle",
    cycle_no_q: "Q word missing with {g}",
    turns: "P value should be 1 or greater with G2 or G3",
    cycle_no_p: Some("Dwell time p word missing with {g}"),
    tap_spindle_stopped: Some("Spindle not turning in {code}"),
    tap_spindle_reversed: Some("Spindle turning {dir} in {code}"),
};

/// A tapping cycle's code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TapCode {
    /// The G code ×10 (G84 = 840, G84.2 = 842).
    pub code: u16,
    /// Cuts going in with the spindle reversed (M4): a left-hand tap.
    pub left: bool,
    /// Rigid without M29 (Fanuc's G84.2/G84.3, LinuxCNC's spindle-synchronised G84/G74 are
    /// not: LinuxCNC's G84 is a floating tap's cycle).
    pub rigid: bool,
}

/// The hole-machining (canned) cycles a control has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cycles {
    /// The letter of the repeat count (Fanuc `K`; Haas, Centroid and LinuxCNC `L`).
    pub repeat: u8,
    /// G73's retract after each peck (mm): Fanuc's parameter 5114, Haas's Setting 22,
    /// LinuxCNC's fixed 0.010 inch.
    pub g73_retract_mm: f64,
    /// G83's clearance above the previous peck's depth (mm): Fanuc's parameter 5115, Haas's
    /// Setting 22, LinuxCNC's 0.010 inch.
    pub g83_clearance_mm: f64,
    /// The tapping codes.
    pub taps: &'static [TapCode],
    /// `M29 S…` before a tapping cycle makes it rigid (Fanuc, Haas).
    pub m29_rigid: bool,
    /// Without G98/G99 stated, the cycle returns to the initial level (Fanuc, Haas: G98 at
    /// power-on) rather than to R (LinuxCNC: rs274's retract mode at power-on is the R plane).
    pub initial_level_at_power_on: bool,
    /// LinuxCNC's moves (measured with rs274): each hole is positioned at the higher of the
    /// current Z and the return level, G89 and the tapping cycles feed out to the return level; otherwise (Fanuc) positioned at the current Z, out to R, then a rapid.
    pub linuxcnc_moves: bool,
}

/// A milling control's language.
#[derive(Clone, Copy, Debug)]
pub struct MillLanguage {
    /// The control's name in messages.
    pub control: &'static str,
    pub lexer: Lexer,
    /// Its macro language, if threadcut runs it.
    pub macros: Option<Syntax>,
    /// A number without a decimal point is a whole program unit (else a least increment).
    pub calculator: bool,
    pub radius: RadiusCheck,
    /// The control's alarms, as it words them.
    pub alarms: Alarms,
    /// Cutter compensation may start on an arc (LinuxCNC: an entry arc larger than the tool's
    /// radius, which threadcut does not know); it never ends on one.
    pub comp_start_on_arc: bool,
    /// G52 sets the G92 offset to its values (LinuxCNC: "G52 … shares G92's offset"); else a
    /// local shift of its own (Fanuc family: the local coordinate system).
    pub g52_is_g92_offset: bool,
    /// The block that ends a program threadcut writes.
    pub program_end: &'static str,
    /// G2/G3 take `P`, the number of turns (LinuxCNC).
    pub arc_turns: bool,
    /// G90.1/G91.1 choose absolute or incremental arc centres (LinuxCNC; incremental at
    /// power-on).
    pub centre_modes: bool,
    /// A reference return without axis words returns every axis (Haas, LinuxCNC).
    pub return_all_without_axes: bool,
    /// `G54.1 P n` (Fanuc, Haas): the additional work coordinate systems.
    pub g54_1: bool,
    /// `G59.1`–`G59.3` (LinuxCNC).
    pub g59_x: bool,
    /// `G33.1` rigid tapping (LinuxCNC).
    pub g33_1: bool,
    /// Codes (×10) that change nothing the reader models (exact stop, look-ahead and contour
    /// control modes, and the cancel codes of polar coordinates, scaling, mirroring and
    /// rotation, whose active codes are refused): read and passed over.
    pub neutral: &'static [u16],
    /// Skip and probe moves (×10): they end where a signal comes, so the named axes are not
    /// known after them.
    pub probes: &'static [u16],
    /// Haas's further work offsets: G110–G129 and `G154 P1`–`P99`.
    pub haas_work: bool,
    /// G41.1/G42.1 with the tool's diameter in D (LinuxCNC's dynamic compensation).
    pub dynamic_comp: bool,
    /// G80 is a motion code (LinuxCNC's modal group 1: "G0 G80" is two codes of one group, and
    /// axis words after G80 do not move); else it only cancels the canned cycle and the group-01
    /// code in force before it (G0, G1, G2, G3) moves again (the Fanuc family: "canned cycles
    /// are cancelled by G80 or a group 01 G code").
    pub g80_in_motion_group: bool,
    pub cycles: Cycles,
    /// The files a call of a program the text does not hold may read.
    pub program_files: fn(&Wanted) -> FileNames,
}

const INCH: f64 = 25.4;

const FANUC_TAPS: &[TapCode] = &[
    TapCode {
        code: 840,
        left: false,
        rigid: false,
    },
    TapCode {
        code: 740,
        left: true,
        rigid: false,
    },
    // Fanuc's FS15-format rigid tapping (G84.2 right hand, G84.3 left hand).
    TapCode {
        code: 842,
        left: false,
        rigid: true,
    },
    TapCode {
        code: 843,
        left: true,
        rigid: true,
    },
];

// Haas taps rigidly without M29 (RECALLED from Haas's mill manual, G84: the spindle and Z are
// synchronised; docs/milling.md).
const HAAS_TAPS: &[TapCode] = &[
    TapCode {
        code: 840,
        left: false,
        rigid: true,
    },
    TapCode {
        code: 740,
        left: true,
        rigid: true,
    },
];

const LINUXCNC_TAPS: &[TapCode] = &[
    TapCode {
        code: 840,
        left: false,
        rigid: false,
    },
    TapCode {
        code: 740,
        left: true,
        rigid: false,
    },
];

fn fanuc_files(w: &Wanted) -> FileNames {
    super::fanuc_family::program_files(w)
}

fn ngc_files(w: &Wanted) -> FileNames {
    match w {
        Wanted::Name(name) => FileNames {
            names: vec![format!("{name}.ngc")],
            any_case: false,
        },
        Wanted::Number(_) => FileNames::default(),
    }
}

fn no_files(_: &Wanted) -> FileNames {
    FileNames::default()
}

impl Alarms {
    /// An alarm with its code filled in: `{code}` as written (`G83`), `{g}` in lower case
    /// (`g83`, as rs274 prints it).
    pub fn with_code(text: &str, code: &str) -> String {
        text.replace("{code}", code)
            .replace("{g}", &code.to_lowercase())
    }
}

/// The language a milling profile names (`language` in its TOML), if threadcut knows it.
pub fn language(name: &str) -> Option<MillLanguage> {
    let fanuc = MillLanguage {
        control: "Fanuc",
        lexer: Lexer::default(),
        macros: Some(Syntax::MACRO_B),
        calculator: false,
        radius: RadiusCheck::Increments(2.0),
        alarms: FANUC_ALARMS,
        comp_start_on_arc: false,
        g52_is_g92_offset: false,
        program_end: "M30",
        arc_turns: false,
        centre_modes: false,
        return_all_without_axes: false,
        g54_1: true,
        g59_x: false,
        g33_1: false,
        // G5.1 (AI contour control), G8 (look-ahead), G9, G15, G50, G50.1, G61, G61.1, G62,
        // G63, G64, G69, G13.1.
        neutral: &[51, 80, 90, 131, 150, 500, 501, 610, 611, 620, 630, 640, 690],
        probes: &[310],
        haas_work: false,
        dynamic_comp: false,
        g80_in_motion_group: false,
        cycles: Cycles {
            repeat: b'K',
            // Parameters 5114 and 5115 are the machine's; threadcut takes 0.1 mm for both
            // (docs/milling.md, "Reading milling programs": assumed).
            g73_retract_mm: 0.1,
            g83_clearance_mm: 0.1,
            taps: FANUC_TAPS,
            m29_rigid: true,
            initial_level_at_power_on: true,
            linuxcnc_moves: false,
        },
        program_files: fanuc_files,
    };
    Some(match name {
        "fanuc" => fanuc,
        "haas" => MillLanguage {
            control: "Haas",
            macros: Some(Syntax {
                m97_local_calls: true,
                m99_p_jumps: true,
                wide_commons: true,
                ..Syntax::MACRO_B
            }),
            // Haas: a number without a decimal point is a whole unit, as on its lathe.
            calculator: true,
            alarms: PLAIN_ALARMS,
            return_all_without_axes: true,
            // G9, G15, G50, G50.1, G61, G64, G69, G103 (look-ahead), G187 (smoothness).
            neutral: &[90, 150, 500, 501, 610, 640, 690, 1030, 1870],
            haas_work: true,
            cycles: Cycles {
                // Setting 22, Can Cycle Delta Z: 0.05 in at the factory.
                // RECALLED: Haas's canned cycles count holes in L ("L: number of holes if
                // G91 is used").
                repeat: b'L',
                g73_retract_mm: 0.05 * INCH,
                g83_clearance_mm: 0.05 * INCH,
                taps: HAAS_TAPS,
                ..fanuc.cycles
            },
            ..fanuc
        },
        "linuxcnc" => MillLanguage {
            control: "LinuxCNC",
            lexer: Lexer {
                blanks_anywhere: true,
                nested_comment_error: true,
                ..Lexer::default()
            },
            macros: Some(Syntax::O_WORDS),
            calculator: true,
            radius: RadiusCheck::LinuxCnc,
            alarms: LINUXCNC_ALARMS,
            comp_start_on_arc: true,
            g52_is_g92_offset: true,
            program_end: "M2",
            arc_turns: true,
            centre_modes: true,
            return_all_without_axes: true,
            g54_1: false,
            g59_x: true,
            g33_1: true,
            // G15 (polar off), G61, G61.1, G64 (G5.1 is a spline on LinuxCNC: refused).
            neutral: &[150, 610, 611, 640],
            probes: &[382, 383, 384, 385],
            haas_work: false,
            dynamic_comp: true,
            g80_in_motion_group: true,
            cycles: Cycles {
                repeat: b'L',
                g73_retract_mm: 0.010 * INCH,
                g83_clearance_mm: 0.010 * INCH,
                taps: LINUXCNC_TAPS,
                m29_rigid: false,
                initial_level_at_power_on: false,
                linuxcnc_moves: true,
            },
            program_files: ngc_files,
        },
        "centroid" => MillLanguage {
            control: "Centroid",
            // CNC12's macro language is not Custom Macro B: threadcut reads plain blocks only.
            macros: None,
            calculator: true,
            alarms: PLAIN_ALARMS,
            return_all_without_axes: true,
            g54_1: false,
            // G15, G50, G61, G64, G69.
            neutral: &[150, 500, 610, 640, 690],
            program_files: no_files,
            cycles: Cycles {
                repeat: b'L',
                taps: LINUXCNC_TAPS,
                m29_rigid: false,
                ..fanuc.cycles
            },
            ..fanuc
        },
        _ => return None,
    })
}
