//! The G-code systems A, B and C of a Fanuc-format lathe control: the threading codes' numbers
//! ([`GCodes`]), the G code list a member's vocabulary is made of ([`g_codes`]) and what the codes
//! mean in each system ([`lexicon`]).

use crate::dialect::lexicon::{
    self, Code as G, DwellForm, Function, Lexicon, LimitForm, PauseSpindle, ReturnForm, ToolForm,
};
use crate::gcode::modal::GCode;
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, PositionCodes, Syntax};
use crate::machine::{GCodeSystem, Machine};
use crate::units::Units;

/// No code in this G-code system.
const NONE: u16 = u16::MAX;

/// The G code list of a Fanuc 0i/30i lathe control: one row per function, its number (×10) in
/// G-code systems A, B and C (the operator's manual's G code list; `docs/dialects/fanuc.md`,
/// "Vocabulary"). A fractional code (G7.1, G12.1, G50.3, G92.1) is known by its whole number, but
/// for the other systems' preset ([`GCodes::foreign`]).
const G_CODE_LIST: &[[u16; 3]] = &[
    // The same number in every system.
    [0, 0, 0],
    [10, 10, 10],
    [20, 20, 20],
    [30, 30, 30],
    [40, 40, 40],
    [50, 50, 50],
    [70, 70, 70],
    [80, 80, 80],
    [90, 90, 90],
    [100, 100, 100],
    [110, 110, 110],
    [120, 120, 120],
    [130, 130, 130],
    [170, 170, 170],
    [180, 180, 180],
    [190, 190, 190],
    [220, 220, 220],
    [230, 230, 230],
    [250, 250, 250],
    [260, 260, 260],
    [270, 270, 270],
    [280, 280, 280],
    [290, 290, 290],
    [300, 300, 300],
    [310, 310, 310],
    [340, 340, 340],
    [350, 350, 350],
    [360, 360, 360],
    [370, 370, 370],
    [380, 380, 380],
    [390, 390, 390],
    [400, 400, 400],
    [410, 410, 410],
    [420, 420, 420],
    [430, 430, 430],
    [440, 440, 440],
    [490, 490, 490],
    // G50.2/G51.2 polygon turning (and system A's G50, below).
    [500, 500, 500],
    [510, 510, 510],
    [520, 520, 520],
    [530, 530, 530],
    [540, 540, 540],
    [550, 550, 550],
    [560, 560, 560],
    [570, 570, 570],
    [580, 580, 580],
    [590, 590, 590],
    [610, 610, 610],
    [620, 620, 620],
    [630, 630, 630],
    [640, 640, 640],
    [650, 650, 650],
    [660, 660, 660],
    [670, 670, 670],
    [680, 680, 680],
    [690, 690, 690],
    [800, 800, 800],
    [810, 810, 810],
    [820, 820, 820],
    [830, 830, 830],
    [840, 840, 840],
    [850, 850, 850],
    [860, 860, 860],
    [870, 870, 870],
    [880, 880, 880],
    [890, 890, 890],
    [960, 960, 960],
    [970, 970, 970],
    [1070, 1070, 1070],
    [1120, 1120, 1120],
    [1130, 1130, 1130],
    [2500, 2500, 2500],
    [2510, 2510, 2510],
    // Inch and millimetre input.
    [200, 200, 700],
    [210, 210, 710],
    // The thread move.
    [320, 330, 330],
    // Coordinate system setting (G50.3 / G92.1: workpiece coordinate system preset).
    [500, 920, 920],
    // The multiple repetitive cycles: finishing, stock removal in turning and in facing, pattern
    // repeating, end-face peck drilling, grooving, the multiple threading cycle.
    [700, 700, 720],
    [710, 710, 730],
    [720, 720, 740],
    [730, 730, 750],
    [740, 740, 760],
    [750, 750, 770],
    [760, 760, 780],
    // The single-pass cycles: turning, threading, facing.
    [900, 770, 200],
    [920, 780, 210],
    [940, 790, 240],
    // Feed per minute and per revolution.
    [980, 940, 940],
    [990, 950, 950],
    // Absolute and incremental programming, canned-cycle return to the initial or the R level.
    [NONE, 900, 900],
    [NONE, 910, 910],
    [NONE, 980, 980],
    [NONE, 990, 990],
];

/// The G numbers (×10) of one of Fanuc's G-code systems that the threading code needs (the lathe
/// manuals' G code list; `docs/dialects/fanuc.md` has the table and its sources).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GCodes {
    pub system: GCodeSystem,
    /// The synchronised move: G32 (A), G33 (B, C).
    pub thread_move: u16,
    /// The single-pass threading cycle: G92 (A), G78 (B), G21 (C).
    pub single: u16,
    /// The multiple threading cycle: G76 (A, B), G78 (C).
    pub multiple: u16,
    /// Sets the coordinates: G50 (A), G92 (B, C).
    pub set_position: u16,
    /// Inch and millimetre input: G20/G21 (A, B), G70/G71 (C).
    pub units: [u16; 2],
    /// G90/G91 select absolute or incremental distance (B, C); in A, G90 is a turning cycle.
    pub g90_g91: bool,
    /// The cycles that leave the tool where they began (turning and multiple repetitive cycles).
    pub canned: &'static [u16],
    /// The codes that end a modal single-pass cycle: group 01 and the other turning cycles.
    pub ends_single: &'static [u16],
    /// The codes that change coordinate offsets by amounts the program does not state: G10
    /// (data setting), G52 (local coordinate system) and the workpiece coordinate system preset,
    /// G50.3 (A) or G92.1 (B, C). The reference returns (G28, G30, G29, G30.1), G53 and G54–G59
    /// are the same in every system.
    pub offset_changes: &'static [u16],
    /// The other systems' fractional codes whose whole number this system has for another
    /// function: the preset of the other systems (`Vocabulary::foreign`).
    pub foreign: &'static [u16],
    /// The turning cycles' numbers.
    pub turning: TurningCodes,
}

/// The G numbers (×10) of the turning cycles in one G-code system (the G code list, rows
/// "multiple repetitive cycles" and "single-pass cycles": `G_CODE_LIST`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TurningCodes {
    /// Finishing: G70 (A, B), G72 (C).
    pub finish: u16,
    /// Stock removal in turning: G71 (A, B), G73 (C).
    pub rough_z: u16,
    /// Stock removal in facing: G72 (A, B), G74 (C).
    pub rough_x: u16,
    /// Pattern repeating: G73 (A, B), G75 (C).
    pub pattern: u16,
    /// End-face peck drilling: G74 (A, B), G76 (C).
    pub peck_z: u16,
    /// Outer/inner diameter grooving: G75 (A, B), G77 (C).
    pub peck_x: u16,
    /// The turning box cycle: G90 (A), G77 (B), G20 (C).
    pub box_z: u16,
    /// The facing box cycle: G94 (A), G79 (B), G24 (C).
    pub box_x: u16,
}

impl TurningCodes {
    /// Every code, for a quick test of a block.
    pub const fn all(&self) -> [u16; 8] {
        [
            self.finish,
            self.rough_z,
            self.rough_x,
            self.pattern,
            self.peck_z,
            self.peck_x,
            self.box_z,
            self.box_x,
        ]
    }
}

/// System A's and B's multiple repetitive cycles.
const TURNING_AB: TurningCodes = TurningCodes {
    finish: 700,
    rough_z: 710,
    rough_x: 720,
    pattern: 730,
    peck_z: 740,
    peck_x: 750,
    box_z: 900,
    box_x: 940,
};

impl GCodes {
    /// Whether `line` has a G code of one of the system's cycles: its threading cycles
    /// (`multiple`, `single`) or its turning cycles. Each G word's code is taken once (most lines
    /// that get here have one G word and no cycle); none of these codes is G0–G3, so a line whose
    /// summary has no other G code has none of them (`cycle_codes_are_not_plain_motion`).
    #[inline]
    pub fn has_cycle(&self, line: &Line) -> bool {
        if !line.summary.other_g() {
            return false;
        }
        let turning = self.turning.all();
        line.words.iter().any(|w| {
            w.letter == b'G'
                && g_code(w.value)
                    .is_some_and(|c| c == self.multiple || c == self.single || turning.contains(&c))
        })
    }

    /// The table of `system`.
    pub const fn of(system: GCodeSystem) -> GCodes {
        match system {
            GCodeSystem::A => GCodes {
                system,
                thread_move: 320,
                single: 920,
                multiple: 760,
                set_position: 500,
                units: [200, 210],
                g90_g91: false,
                canned: &[700, 710, 720, 730, 740, 750, 760, 900, 920, 940],
                ends_single: &[
                    0, 10, 20, 30, 320, 330, 340, 700, 710, 720, 730, 740, 750, 760, 780, 900, 940,
                ],
                offset_changes: &[100, 520, 503],
                foreign: &[921],
                turning: TURNING_AB,
            },
            GCodeSystem::B => GCodes {
                system,
                thread_move: 330,
                single: 780,
                multiple: 760,
                set_position: 920,
                units: [200, 210],
                g90_g91: true,
                canned: &[700, 710, 720, 730, 740, 750, 760, 770, 780, 790],
                ends_single: &[
                    0, 10, 20, 30, 330, 340, 700, 710, 720, 730, 740, 750, 760, 770, 790,
                ],
                offset_changes: &[100, 520, 921],
                foreign: &[503],
                turning: TurningCodes {
                    box_z: 770,
                    box_x: 790,
                    ..TURNING_AB
                },
            },
            GCodeSystem::C => GCodes {
                system,
                thread_move: 330,
                single: 210,
                multiple: 780,
                set_position: 920,
                units: [700, 710],
                g90_g91: true,
                canned: &[200, 210, 240, 720, 730, 740, 750, 760, 770, 780],
                ends_single: &[
                    0, 10, 20, 30, 330, 340, 200, 240, 720, 730, 740, 750, 760, 770, 780,
                ],
                offset_changes: &[100, 520, 921],
                foreign: &[503],
                turning: TurningCodes {
                    finish: 720,
                    rough_z: 730,
                    rough_x: 740,
                    pattern: 750,
                    peck_z: 760,
                    peck_x: 770,
                    box_z: 200,
                    box_x: 240,
                },
            },
        }
    }

    /// The modal reader's conventions of a Fanuc-family lathe in this system: U/W incremental
    /// (in B and C as well: see `docs/dialects/fanuc.md`), the lead in F.
    pub fn conventions(&self, machine: &Machine) -> Conventions {
        Conventions {
            uw_incremental: true,
            g90_g91_distance: self.g90_g91,
            diameter_x: machine.diameter_x,
            thread_move: self.thread_move,
            // E on G32 is TPI on some series and a precise lead on others: not read.
            tpi_letter: 0,
            lead_letter: b'F',
            lead_along_path: false,
            set_position: self.set_position,
            canned_cycles: self.canned,
            unmodelled: HOLE_CYCLES,
            units_codes: self.units,
            positions: self.positions(),
            syntax: Syntax::default(),
        }
    }

    /// The codes after which the position is known only from the profile, or not at all
    /// (`docs/dialects/README.md`): Fanuc's system-A list ([`PositionCodes::FANUC`]) with this
    /// system's offset-changing codes.
    pub const fn positions(&self) -> PositionCodes {
        PositionCodes {
            offset_changes: self.offset_changes,
            ..PositionCodes::FANUC
        }
    }

    /// The synchronised move as it is written (`G32`, `G33`).
    pub fn thread_move_name(&self) -> &'static str {
        if self.thread_move == 320 {
            "G32"
        } else {
            "G33"
        }
    }
}

/// The letters the threading codes of a member of the family take (the hint of an alarm names the
/// controllers whose code fits a block's words).
pub struct ThreadWords {
    pub thread_move: &'static [u8],
    pub single: &'static [u8],
    pub multiple: &'static [u8],
}

/// The G codes of a Fanuc-format control in `system`, sorted, the threading codes with `words`:
/// the rows of [`G_CODE_LIST`] in that system's column, the threading codes where [`GCodes`] puts
/// them (one table for the three systems, so that they cannot disagree).
pub const fn g_codes(system: GCodeSystem, words: &ThreadWords) -> [GCode; G_CODE_LIST.len()] {
    let codes = GCodes::of(system);
    let column = match system {
        GCodeSystem::A => 0,
        GCodeSystem::B => 1,
        GCodeSystem::C => 2,
    };
    let mut out = [GCode::plain(0); G_CODE_LIST.len()];
    let mut i = 0;
    while i < G_CODE_LIST.len() {
        let code = G_CODE_LIST[i][column];
        out[i] = if code == NONE {
            // A row the system does not have: G0 again (the list stays sorted).
            GCode::plain(0)
        } else if code == codes.thread_move {
            GCode::thread(code, words.thread_move)
        } else if code == codes.single {
            GCode::thread(code, words.single)
        } else if code == codes.multiple {
            GCode::thread(code, words.multiple)
        } else {
            GCode::plain(code)
        };
        i += 1;
    }
    // Sorted by code (insertion sort: a short list, at compile time).
    let mut i = 1;
    while i < out.len() {
        let mut j = i;
        while j > 0 && out[j - 1].code > out[j].code {
            let t = out[j - 1];
            out[j - 1] = out[j];
            out[j] = t;
            j -= 1;
        }
        i += 1;
    }
    out
}

/// `G76`, `G78`, `G21`: a code's name.
pub(super) fn g_name(code: u16) -> String {
    format!("G{}", code / 10)
}

/// What the codes of a Fanuc-format lathe control mean in G-code system A (the operator's
/// manual's G code list, `docs/dialects/fanuc.md`, "Vocabulary"; `docs/translation.md`): G32
/// threads, G50 sets the position or (with S) the spindle limit, G98/G99 select the feed mode, U/W
/// are the incremental words. Shared by `fanuc` and `fanuc15`.
pub static LEXICON_A: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        lexicon::G20_G21,
        &[
            (G::G(320), Function::Thread),
            (G::G(500), Function::SpindleLimit),
            (G::G(980), Function::FeedPerMinute),
            (G::G(990), Function::FeedPerRevolution),
        ],
        lexicon::COMPENSATION,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
    ],
    ..FANUC_LEXICON
};

/// … in G-code system B: G33 threads, G92 sets the position or the spindle limit, G90/G91 select
/// the distance mode, G94/G95 the feed mode (G98/G99 are canned-cycle return levels).
pub static LEXICON_B: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        lexicon::G20_G21,
        SYSTEM_B_C,
        lexicon::COMPENSATION,
        lexicon::G90_G91,
        lexicon::G94_G95,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
    ],
    ..FANUC_LEXICON
};

/// … in G-code system C: as B, with G70/G71 for inch and mm (G20 and G21 are cycles there).
pub static LEXICON_C: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        &[
            (G::G(700), Function::Units(Units::Inch)),
            (G::G(710), Function::Units(Units::Mm)),
        ],
        SYSTEM_B_C,
        lexicon::COMPENSATION,
        lexicon::G90_G91,
        lexicon::G94_G95,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
    ],
    ..FANUC_LEXICON
};

/// The codes systems B and C share that differ from A's.
const SYSTEM_B_C: &[(G, Function)] = &[
    (G::G(330), Function::Thread),
    (G::G(920), Function::SpindleLimit),
];

/// What every Fanuc-format control's blocks share: `T0101` (tool and offset, two digits each),
/// `G4 X(s)`/`P(ms)`, the spindle limit as a code with S, `G28 U0 W0` (only the axes named
/// return), `O` program numbers, `%` delimiters, feed per revolution at power-on (parameter
/// 3402's lathe default), the thread move's `F` lead and `Q` start angle.
pub const FANUC_LEXICON: Lexicon = Lexicon {
    codes: &[],
    tool: ToolForm::Combined { digits: 2 },
    dwell: Some(DwellForm::XSecondsOrPMilliseconds),
    spindle_limit: Some(LimitForm::Code),
    reference: Some(ReturnForm::IncrementalWords { x: b'U', z: b'W' }),
    restates_position: false,
    program_number: true,
    sequence_numbers: true,
    delimiters: true,
    power_on_feed: Function::FeedPerRevolution,
    thread_words: b"FQ",
    thread_settings: &[],
    only_units: None,
    pause_spindle: PauseSpindle::BuilderDecides,
};

/// The lexicon of a Fanuc-format control in `system`.
pub fn lexicon(system: GCodeSystem) -> &'static Lexicon {
    match system {
        GCodeSystem::A => &LEXICON_A,
        GCodeSystem::B => &LEXICON_B,
        GCodeSystem::C => &LEXICON_C,
    }
}

/// The hole-machining canned cycles of Fanuc's lathe controls (the same numbers in systems A, B
/// and C; Haas's lathe the same, G81 drilling to G89 boring): threadcut does not follow them
/// ([`Conventions::unmodelled`]). G80, which cancels them, is no motion.
pub const HOLE_CYCLES: &[(u16, &str)] = &[
    (810, "drilling cycle"),
    (820, "drilling cycle with dwell"),
    (830, "peck drilling cycle"),
    (840, "tapping cycle"),
    (850, "boring cycle"),
    (860, "boring cycle"),
    (870, "side drilling cycle"),
    (880, "side tapping cycle"),
    (890, "boring cycle with dwell"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_codes_are_not_plain_motion() {
        // `GCodes::has_cycle` trusts the lexer's summary, which leaves G0–G3 out.
        for system in [GCodeSystem::A, GCodeSystem::B, GCodeSystem::C] {
            let codes = GCodes::of(system);
            let mut all = codes.turning.all().to_vec();
            all.extend([codes.multiple, codes.single]);
            for c in all {
                assert!(c % 10 != 0 || c > 30, "{system:?}: G{}", c / 10);
            }
        }
    }
}
