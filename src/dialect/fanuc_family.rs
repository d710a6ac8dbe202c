//! The Fanuc family's threading cycles, shared by every controller that copies them (Fanuc 0i/30i in
//! G-code systems A, B and C, Fanuc's FS15 program format, Haas, GSK 980TDi): the single-pass box
//! cycle G92 and the multiple-pass cycle G76 (`shared/reference/threading-notes.md` §c.1, §c.3, §e).
//! G numbers are system A's; [`GCodes`] gives the others (G78/G21 for G92, G78 for G76 in C).
//!
//! ```text
//! G92 X(U) Z(W) [R(i)] F(L) [Q] ;                  one pass; modal: a following `X..` repeats it
//! G76 P(m)(r)(a) Q(Δdmin) R(d) ;                   first block: rewrites parameters 5142/5130/5143, 5140, 5141
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L) ;             second block: the cycle
//! G76 X(U) Z(W) I K D F A P Q ;                    or in one block (FS15 format, Haas: `super::one_block`)
//! ```
//! P(k), Q(Δd) and Q(Δdmin) are counts of least input increments, written without a decimal point,
//! whatever the machine's decimal-point setting. Q on G32/G92 (and the one-block G76) shifts the
//! thread's start angle, in 0.001°. Each member's words are its own dialect's ([`Flavour`]); each
//! decision is a row of `docs/dialects/fanuc.md` (or `haas.md`).

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::lexicon::{
    self, Code as G, DwellForm, Function, Lexicon, LimitForm, ReturnForm, ToolForm,
};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{
    Conventions, Line, Modal, MotionMode, PositionCodes, Syntax, Word, WordSummary,
};
use crate::machine::{FanucParameters, GCodeSystem, Machine};
use crate::post::{AngleUnit, StartAngleWord};
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, ReturnPath, Side, StartIndexing,
};
use crate::units::{Pos, Tolerance, Units};

use super::{one_block, only_words, Read};

/// Tool-tip angles the first G76 block accepts (Fanuc: 80, 60, 55, 30, 29 and 0 degrees).
pub const TOOL_ANGLES: [u32; 6] = [80, 60, 55, 30, 29, 0];

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
}

impl GCodes {
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
fn g_name(code: u16) -> String {
    format!("G{}", code / 10)
}

/// Parameters of the threading cycles. The first G76 block rewrites them, as on the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadParameters {
    /// The pull-out's length in leads (Fanuc 5130 ÷ 10, Haas Setting 95); 0: none.
    pub chamfer_leads: f64,
    /// Its angle from the Z axis, degrees (Fanuc 5131, 0 read as 45; Haas Setting 96).
    pub chamfer_angle_deg: f64,
    /// 5140: Δdmin (mm, radius).
    pub min_cut_mm: f64,
    /// 5141: d (mm, radius).
    pub allowance_mm: f64,
    /// 5142: m.
    pub finish_passes: u32,
    /// 5143: a (degrees); the one-block G76's tool angle when the block has no A.
    pub tool_angle: u32,
}

impl ThreadParameters {
    /// Fanuc's parameters 5130, 5131, 5140–5143 (GSK numbers them the same).
    pub fn fanuc(
        p5130: u8,
        p5131: u8,
        p5140: f64,
        p5141: f64,
        p5142: u8,
        p5143: u8,
    ) -> ThreadParameters {
        ThreadParameters {
            chamfer_leads: f64::from(p5130) * 0.1,
            chamfer_angle_deg: if p5131 == 0 { 45.0 } else { f64::from(p5131) },
            min_cut_mm: p5140,
            allowance_mm: p5141,
            finish_passes: u32::from(p5142),
            tool_angle: u32::from(p5143),
        }
    }

    /// A Fanuc profile's `[fanuc]` table.
    pub fn of_fanuc(p: &FanucParameters) -> ThreadParameters {
        ThreadParameters::fanuc(p.p5130, p.p5131, p.p5140, p.p5141, p.p5142, p.p5143)
    }
}

/// The multiple threading cycle's form.
#[derive(Clone, Copy, Debug)]
pub enum G76Form {
    /// Fanuc 0i/30i standard format, GSK: `G76 P(m)(r)(a) Q(Δdmin) R(d)` then `G76 X Z R P Q F`.
    TwoBlock,
    /// FS15 format, Haas: `G76 X Z I K D F A P Q` in these words.
    OneBlock(one_block::G76Words),
}

/// What a member of the family adds to the common words, and how its manuals name things.
#[derive(Clone, Copy, Debug)]
pub struct Flavour {
    /// The controller's name on jobs.
    pub controller: &'static str,
    /// GSK's G92 words: J/K (tail-out, short and long axis) and L (starts).
    pub gsk_g92_words: bool,
    /// The single-pass cycle's taper word: `R` (Fanuc standard format), `I` (FS15 format, Haas).
    pub taper_letter: u8,
    /// `Q` on the thread move and the single-pass cycle shifts the thread's start angle.
    pub start_angle: bool,
    /// Haas's `F(E)`: E is the lead as F is; elsewhere E is refused.
    pub e_is_lead: bool,
    pub g76: G76Form,
    /// What messages call the setting of the pull-out, e.g. "the chamfer (parameter 5130)".
    pub chamfer_name: &'static str,
    /// … and of the finishing allowance, e.g. "the finishing allowance d".
    pub allowance_name: &'static str,
    /// The controller's G codes in a G-code system (the modal reader's alarm for any other code,
    /// and the alarm on a block of another control's form).
    pub vocabulary: fn(GCodeSystem) -> &'static Vocabulary,
}

impl Flavour {
    /// Fanuc's standard program format (and GSK's G76/G92).
    pub const fn fanuc(controller: &'static str) -> Flavour {
        Flavour {
            controller,
            gsk_g92_words: false,
            taper_letter: b'R',
            start_angle: true,
            e_is_lead: false,
            g76: G76Form::TwoBlock,
            chamfer_name: "the chamfer (parameter 5130)",
            allowance_name: "the finishing allowance d",
            vocabulary: super::fanuc::vocabulary,
        }
    }
}

/// The modal state of G92: the values a following block without a G code repeats.
#[derive(Clone, Copy, Debug)]
struct G92Modal {
    end_z: f64,
    taper: f64,
    /// The start angle of the last pass (not repeated: Q is not modal), and its line.
    phase_deg: f64,
    phase_line: u32,
}

/// The shared reader. A dialect offers it every line first.
pub struct FanucFamily {
    pub flavour: Flavour,
    pub params: ThreadParameters,
    pub codes: GCodes,
    /// The controller's G codes in its G-code system (the flavour's, for `codes.system`).
    pub vocabulary: &'static Vocabulary,
    /// Haas's M23/M24: the pull-out of G76/G92 is cut (M23, the default) or not (M24).
    pub chamfer_on: bool,
    /// Least input increment in mm and in inch (for P(k), Q(Δd), Q(Δdmin)).
    increment: [f64; 2],
    g92: Option<G92Modal>,
    /// The start angle of the synchronised run in progress, from the `Q` of its first plain
    /// thread move, while it is not 0: the moves that continue the run carry it.
    run_phase: Option<f64>,
    /// The letters whose words make any line the family's business (a [`WordSummary`] mask).
    letters: u32,
}

impl FanucFamily {
    /// The taper word of the member's cycles: `R` in Fanuc's standard format (the two-block G76 and
    /// G92), `I` in the FS15 format and on Haas (the one-block G76 and G92), a radius, X at the
    /// cycle's start minus X at its end either way.
    pub fn taper_word(&self) -> super::TaperWord {
        let r = self.flavour.taper_letter == b'R';
        let cycles = match (self.codes.system, r) {
            (GCodeSystem::A, true) => "G76 (second block) / G92 R(i)",
            (GCodeSystem::A, false) => "G76 / G92 I(i)",
            (GCodeSystem::B, true) => "G76 (second block) / G78 R(i)",
            (GCodeSystem::B, false) => "G76 / G78 I(i)",
            (GCodeSystem::C, true) => "G78 (second block) / G21 R(i)",
            (GCodeSystem::C, false) => "G78 / G21 I(i)",
        };
        super::TaperWord {
            cycles,
            letter: self.flavour.taper_letter as char,
            start_minus_end: true,
            radius: true,
        }
    }

    pub fn new(
        flavour: Flavour,
        params: ThreadParameters,
        codes: GCodes,
        machine: &Machine,
    ) -> FanucFamily {
        FanucFamily {
            flavour,
            params,
            codes,
            vocabulary: (flavour.vocabulary)(codes.system),
            chamfer_on: true,
            increment: [
                machine.resolution(Units::Mm),
                machine.resolution(Units::Inch),
            ],
            g92: None,
            run_phase: None,
            // E: a lead or an exponent to refuse; Q: a start angle.
            letters: WordSummary::letter_mask(if flavour.start_angle { b"EQ" } else { b"E" }),
        }
    }

    /// Whether the family reads even a line of plain words: while a single-pass cycle is modal (a
    /// block of axis words repeats it) or a run of thread moves begun with a start angle goes on.
    #[inline(always)]
    pub fn in_progress(&self) -> bool {
        self.g92.is_some() | self.run_phase.is_some()
    }

    /// Whether a member's `read` may act on `line`: the family's blocks ([`wants`](Self::wants)),
    /// a block with an E word (a lead where the member reads one, refused as an exponent
    /// elsewhere), and the member's own blocks (`own_block`), which have a G code other than
    /// G0–G3 or one of the member's `own_letters` (a [`WordSummary`] mask). Most lines have no G
    /// code but G0–G3 and none of these letters: one test of the summary answers for them
    /// (docs/performance.md, "Reader after issue 13").
    #[inline(always)]
    pub fn prefilter(
        &self,
        line: &Line,
        own_letters: u32,
        own_block: impl FnOnce(&Line) -> bool,
    ) -> bool {
        if !line.summary.other_g_or_any(self.letters | own_letters) {
            return self.in_progress();
        }
        self.prefilter_words(line, own_block)
    }

    /// [`prefilter`](Self::prefilter) for the lines the summary's one test does not answer: kept
    /// out of line, so that the test itself is inlined into the run loop.
    #[inline(never)]
    fn prefilter_words(&self, line: &Line, own_block: impl FnOnce(&Line) -> bool) -> bool {
        self.wants(line) || line.summary.has_letter(b'E') || own_block(line)
    }

    /// Whether [`read`](Self::read) may act on `line`: a G76 or G92 block, any block while a G92
    /// is modal (a block of axis words repeats it; a motion code cancels it), a block with a `Q`
    /// where Q is a start angle (a thread move's Q), and any block while a run of thread moves
    /// begun with a start angle goes on.
    #[inline]
    pub fn wants(&self, line: &Line) -> bool {
        self.g92.is_some()
            || self.run_phase.is_some()
            || line.has_g(self.codes.multiple)
            || line.has_g(self.codes.single)
            || (self.flavour.start_angle && line.summary.has_letter(b'Q'))
    }

    /// The pull-out of a pass for lead `lead` (mm), as the parameters (and M23/M24) give it.
    fn chamfer(&self, lead: f64, tol: Tolerance) -> Exit {
        let p = &self.params;
        let length = p.chamfer_leads * lead;
        if !self.chamfer_on || !tol.gt(length, 0.0) {
            return Exit::Straight;
        }
        Exit::PullOut {
            start_before: length,
            length,
            outward: length * tan_deg(p.chamfer_angle_deg),
        }
    }

    /// The parameters as the one-block G76 takes them.
    pub fn one_block_setup(&self) -> one_block::Setup {
        let p = &self.params;
        one_block::Setup {
            controller: self.flavour.controller,
            allowance: p.allowance_mm,
            allowance_name: self.flavour.allowance_name,
            min_cut: p.min_cut_mm,
            finish_passes: p.finish_passes,
            tool_angle: f64::from(p.tool_angle),
            pull_out: self.chamfer_on.then_some(one_block::PullOut {
                leads: p.chamfer_leads,
                angle_deg: p.chamfer_angle_deg,
            }),
            pull_out_name: self.flavour.chamfer_name,
        }
    }

    /// Whether `line` is a thread move (the dialect's thread-move code on it, or a block of axis
    /// words under a modal thread move), where an E word may be a lead.
    pub fn threads(&self, conv: &Conventions, line: &Line, modal: &Modal) -> bool {
        line.has_g(conv.thread_move)
            || (modal.motion == crate::gcode::MotionMode::Thread
                && !line.words.iter().any(|w| w.letter == b'G'))
    }

    /// Reads `line` if it is a G76 or G92 block (or a block repeating a modal G92); `None` otherwise.
    pub fn read(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Read>> {
        let codes = self.codes;
        // No allocation: this runs on every line offered.
        let gs = || {
            line.words
                .iter()
                .filter(|w| w.letter == b'G')
                .map(|w| (w, g_code(w.value)))
        };
        let cycle = gs()
            .find(|(_, c)| *c == Some(codes.multiple) || *c == Some(codes.single))
            .map(|(w, c)| (w, c.expect("matched")));
        let Some((gword, code)) = cycle else {
            if gs().any(|(_, c)| c.is_some_and(|c| codes.ends_single.contains(&c))) {
                self.g92 = None;
            }
            // A repeat is a block of axis words alone: any G code (a dwell `G4 X1.`, `G50 X..`) makes
            // the block something else.
            let moves = gs().next().is_none()
                && line
                    .words
                    .iter()
                    .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
            return match self.g92 {
                Some(m) if moves => {
                    let job = self.read_g92(conv, line, modal, line.span(), Some(m), warnings)?;
                    Ok(Some(Read::Cycle(Box::new(job))))
                }
                _ => self.thread_move(conv, line, modal),
            };
        };
        self.run_phase = None;
        let name = g_name(code);
        // In systems B and C a G90/G91 may share the cycle's block: it applies to the block's own
        // words (and stays in force), as on the modal reader's blocks.
        let distance: &[u16] = if codes.g90_g91 { &[900, 910] } else { &[] };
        super::alone_in_block(line, gword.span, &name, distance)?;
        for (_, c) in gs() {
            match c {
                Some(900) if codes.g90_g91 => modal.absolute = true,
                Some(910) if codes.g90_g91 => modal.absolute = false,
                _ => {}
            }
        }
        let second = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        if code == codes.single {
            if !second {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    gword.span,
                    format!("{name} needs the thread end point: X (or U) and Z (or W)"),
                )
                .with_hint(format!(
                    "this dialect reads {name} as the thread-cutting cycle (G-code system {:?})",
                    codes.system
                )));
            }
            let job = self.read_g92(conv, line, modal, gword.span, None, warnings)?;
            return Ok(Some(Read::Cycle(Box::new(job))));
        }
        self.g92 = None;
        if let G76Form::OneBlock(words) = self.flavour.g76 {
            let setup = self.one_block_setup();
            let job = one_block::read_g76(
                conv, line, modal, gword.span, &name, &words, &setup, warnings,
            )?;
            return Ok(Some(Read::Cycle(Box::new(job))));
        }
        one_block_words_on_two_block(line, self.vocabulary, code, &name)?;
        if second {
            let job = self.read_g76_second(conv, line, modal, gword.span, warnings)?;
            Ok(Some(Read::Cycle(Box::new(job))))
        } else {
            self.read_g76_first(line, modal)?;
            Ok(Some(Read::Settings))
        }
    }

    /// Ends a modal single-pass cycle (a dialect that reads a block itself calls this).
    pub fn end_single(&mut self) {
        self.g92 = None;
    }

    /// A plain block's start angle. `Q` on a thread move (`G32 … Q`, or a block of axis words while
    /// the thread move is modal) begins a run of thread moves at that angle: the move carries it
    /// ([`PlainMove::phase_deg`](crate::gcode::PlainMove::phase_deg)), and so do the thread moves
    /// that continue the run without a Q (only a run's first move waits for the one-revolution
    /// signal), until a move of another kind. `None`: the modal reader applies the block as it is.
    fn thread_move(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
    ) -> Result<Option<Read>> {
        let q = self.thread_move_start_angle(line, modal)?;
        if q.is_none() && self.run_phase.is_none() {
            return Ok(None);
        }
        let mut mv = modal.apply(conv, line)?;
        match mv.as_mut() {
            Some(m) if m.mode == MotionMode::Thread => {
                let phase = q.or(self.run_phase).unwrap_or(0.0);
                m.phase_deg = phase;
                self.run_phase = (phase != 0.0).then_some(phase);
            }
            // A block that does not move while G32 stays modal (M8) leaves the run as it is.
            None if modal.motion == MotionMode::Thread => {}
            _ => self.run_phase = None,
        }
        Ok(Some(Read::Applied(mv)))
    }

    /// `Q` on a thread move, checked: its start angle in degrees.
    fn thread_move_start_angle(&self, line: &Line, modal: &Modal) -> Result<Option<f64>> {
        if !self.flavour.start_angle {
            return Ok(None);
        }
        let Some(q) = line.word(b'Q') else {
            return Ok(None);
        };
        let no_g = !line.words.iter().any(|w| w.letter == b'G');
        if line.has_g(self.codes.thread_move) || (no_g && modal.motion == MotionMode::Thread) {
            return start_angle(q).map(Some);
        }
        Ok(None)
    }

    fn multiple_name(&self) -> String {
        g_name(self.codes.multiple)
    }

    /// A count of least input increments, written without a decimal point, in mm.
    fn increments(&self, modal: &Modal, w: &Word, name: &str, what: &str) -> Result<f64> {
        // A computed value (`Q#1`) is the count itself; it must be a whole number.
        if (w.has_dot && !w.is_computed()) || w.value.fract() != 0.0 {
            return Err(Diagnostic::error(
                Code::Syntax,
                w.span,
                format!("{name} is written without a decimal point, in least input increments"),
            )
            .with_hint(if modal.units == Units::Inch {
                format!(
                    "{what}: write 0.05 inch as {} on this machine",
                    (0.05 / self.increment[1]).round()
                )
            } else {
                format!(
                    "{what}: write 1.2 mm as {} on this machine",
                    (1.2 / self.increment[0]).round()
                )
            }));
        }
        if w.value < 0.0 {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                w.span,
                format!("{name}={} must not be negative", w.value),
            ));
        }
        let inc = self.increment[(modal.units == Units::Inch) as usize];
        Ok(modal.units.to_mm(w.value * inc))
    }

    fn read_g76_first(&mut self, line: &Line, modal: &Modal) -> Result<()> {
        let name = self.multiple_name();
        only_words(
            line,
            b"GNPQR",
            &format!("the first {name} block"),
            "P(m)(r)(a) Q(Δdmin) R(d)",
        )?;
        let mut p = self.params;
        if let Some(w) = line.word(b'P') {
            let (m, r, a) = unpack_p(line, w, &name)?;
            p.finish_passes = m;
            p.chamfer_leads = f64::from(r) * 0.1;
            p.tool_angle = a;
        }
        if let Some(q) = line.word(b'Q') {
            p.min_cut_mm =
                self.increments(modal, q, "Q(Δdmin)", "the minimum depth of cut (radius)")?;
        }
        if let Some(r) = line.word(b'R') {
            let v = modal.length_mm(r);
            if v < 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    r.span,
                    format!(
                        "R(d)={} is negative: the finishing allowance is a radial stock",
                        r.value
                    ),
                ));
            }
            p.allowance_mm = v;
        }
        self.params = p;
        Ok(())
    }

    fn read_g76_second(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        g76: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let name = self.multiple_name();
        let letters: &[u8] = if conv.tpi_letter == b'I' {
            b"GNXZUWRPQFIE"
        } else {
            b"GNXZUWRPQFE"
        };
        only_words(
            line,
            letters,
            &format!("the second {name} block"),
            "X(U) Z(W) R(i) P(k) Q(Δd) F(L)",
        )?;
        let height = match line.word(b'P') {
            Some(w) => self.increments(modal, w, "P(k)", "the thread height (radius)")?,
            None => {
                return Err(alarm_missing(
                    g76,
                    &name,
                    "P(k)",
                    "the thread height (radius)",
                ))
            }
        };
        let first = match line.word(b'Q') {
            Some(w) => self.increments(modal, w, "Q(Δd)", "the depth of the first cut (radius)")?,
            None => {
                return Err(alarm_missing(
                    g76,
                    &name,
                    "Q(Δd)",
                    "the depth of the first cut (radius)",
                ))
            }
        };
        let res = modal.resolution();
        let (x_tol, length) = (res.x(), res.length());
        for (w, v, word) in [
            (line.word(b'P'), height, "P(k)"),
            (line.word(b'Q'), first, "Q(Δd)"),
        ] {
            if !length.gt(v, 0.0) {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.map_or(g76, |w| w.span),
                    format!("{name} alarm (PS0062): {word} must be greater than 0"),
                ));
            }
        }
        let taper = line.word(b'R').map_or(0.0, |r| modal.length_mm(r));
        let lead = self.lead(conv, line, modal, g76, &name)?;
        let (a, end) = self.endpoints(conv, line, modal, g76, &name)?;
        let p = self.params;
        if !length.lt(p.allowance_mm, height) {
            return Err(Diagnostic::error(
                Code::Geometry,
                g76,
                format!(
                    "the finishing allowance d {} is not smaller than the thread height P(k) {}",
                    modal.units.from_mm(p.allowance_mm),
                    modal.units.from_mm(height)
                ),
            ));
        }
        // C: the root at the thread start (X of the end point plus the taper, Z of the start point).
        let c = Pos::new(end.x + taper, a.z);
        let side = side_of(a, c, x_tol, g76)?;
        let travel_z = end.z - a.z;
        if length.is_zero(travel_z) {
            return Err(geometry(
                g76,
                "the thread end Z equals the start point's Z: the thread has no length",
            ));
        }
        if length.gt(taper.abs(), travel_z.abs()) {
            return Err(geometry(
                g76,
                format!(
                    "the taper R(i) changes X by more than the thread's Z length ({} > {} mm, radius)",
                    taper.abs(),
                    travel_z.abs()
                ),
            ));
        }
        let crest_c = c.plus(side.outward().scale(height));
        // A start point within the resolution of the crest is on the crest.
        if x_tol.lt((a.x - crest_c.x) * side.outward().x, 0.0) {
            return Err(geometry(
                g76,
                "the start point lies inside the thread (between crest and root): the return along Z would cut through it",
            )
            .with_hint("start the cycle from a point clear of the crest"));
        }
        let half = f64::from(p.tool_angle) / 2.0;
        // Single-edge infeed: deeper passes move in the cutting direction along the flank at a/2, so
        // the leading edge cuts and the trailing edge follows the groove; the full-depth pass runs
        // from the start point's Z to the programmed end Z.
        let flank = if travel_z < 0.0 {
            Flank::Right
        } else {
            Flank::Left
        };
        let infeed = if p.tool_angle == 0 {
            Infeed::Radial
        } else {
            Infeed::Flank {
                flank,
                angle_deg: half,
            }
        };
        let full_offset = infeed.axis(height);
        let crest_start = Pos::new(crest_c.x, a.z - full_offset);
        let crest_end = Pos::new(crest_c.x - taper, end.z - full_offset);
        let exit = self.chamfer(lead, length);
        self.check_exit(&exit, travel_z, modal.units, length, g76)?;
        super::lead_warning(
            lead,
            travel_z,
            modal.units,
            length,
            g76,
            "check F",
            warnings,
        );
        Ok(Job {
            line: line.number,
            span: g76,
            controller: self.flavour.controller,
            units: modal.units,
            start: a,
            geometry: Geometry {
                crest_start,
                crest_end,
                depth: height,
                side,
            },
            lead: Lead::constant(lead),
            plan: PassPlan {
                law: DepthLaw::Power {
                    first,
                    degression: 2.0,
                    min_step: p.min_cut_mm,
                },
                finish_allowance: p.allowance_mm,
                finish_passes: p.finish_passes,
            },
            infeed,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: f64::from(p.tool_angle),
            entry: Entry::Direct,
            exit,
            retract: Retract { x: a.x, z: a.z },
            return_path: ReturnPath::Box,
        })
    }

    fn read_g92(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        repeat: Option<G92Modal>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let f = self.flavour;
        let name = g_name(self.codes.single);
        let (letters, format) = self.g92_words(conv);
        only_words(line, &letters, &format!("a {name} block"), &format)?;
        let lead = self.lead(conv, line, modal, span, &name)?;
        let a = start_point(modal, span, &name)?;
        let mut end = modal.target(conv, line, a)?;
        let has_z = line.word(b'Z').or(line.word(b'W')).is_some();
        let has_x = line.word(b'X').or(line.word(b'U')).is_some();
        match repeat {
            Some(m) if !has_z => end.z = m.end_z,
            _ if !has_z || !has_x => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    format!("{name} needs the thread end point: X (or U) and Z (or W)"),
                ))
            }
            _ => {}
        }
        let taper = match line.word(f.taper_letter) {
            Some(r) => modal.length_mm(r),
            None => repeat.map_or(0.0, |m| m.taper),
        };
        let phase_deg = self.g92_start_angle(line, span, repeat, warnings)?;
        self.g92 = Some(G92Modal {
            end_z: end.z,
            taper,
            phase_deg,
            phase_line: line.number,
        });
        let res = modal.resolution();
        let (x_tol, length) = (res.x(), res.length());
        let travel_z = end.z - a.z;
        if length.is_zero(travel_z) {
            return Err(geometry(
                span,
                "the thread end Z equals the start point's Z: the thread has no length",
            ));
        }
        // The cut starts at the end X plus the taper; the pull-out rises toward the start point's X.
        let cut_start = Pos::new(end.x + taper, a.z);
        let side = side_of(a, end, x_tol, span)?;
        if !x_tol.gt((a.x - cut_start.x) * side.outward().x, 0.0) {
            let t = f.taper_letter as char;
            return Err(geometry(
                span,
                format!(
                    "{t}(i) {} puts the thread's start beyond the start point's X: when {t}'s sign differs from U's, |{t}| must not exceed |U/2|",
                    modal.units.from_mm(taper)
                ),
            ));
        }
        let (exit, starts) = if f.gsk_g92_words {
            self.gsk_tail(line, modal, lead)?
        } else {
            (self.chamfer(lead, length), 1)
        };
        self.check_exit(&exit, travel_z, modal.units, length, span)?;
        super::lead_warning(
            lead,
            travel_z,
            modal.units,
            length,
            span,
            "check F",
            warnings,
        );
        Ok(Job {
            line: line.number,
            span,
            controller: f.controller,
            units: modal.units,
            start: a,
            geometry: Geometry {
                crest_start: cut_start,
                crest_end: Pos::new(end.x, end.z),
                depth: 0.0,
                side,
            },
            lead: Lead {
                starts,
                phase_deg,
                ..Lead::constant(lead)
            },
            plan: PassPlan {
                law: DepthLaw::Explicit { depths: vec![] },
                finish_allowance: 0.0,
                finish_passes: 1,
            },
            infeed: Infeed::Radial,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: f64::from(self.params.tool_angle),
            entry: Entry::Direct,
            exit,
            retract: Retract { x: a.x, z: a.z },
            return_path: ReturnPath::Box,
        })
    }

    /// The single-pass cycle's words on this controller (E is read only to refuse it with its own
    /// message, except where it is the lead), and the hint that lists them.
    fn g92_words(&self, conv: &Conventions) -> (Vec<u8>, String) {
        let f = self.flavour;
        let mut letters: Vec<u8> = b"GNXZUWFE".to_vec();
        letters.push(f.taper_letter);
        let mut format = format!("X(U) Z(W) {}(i) F(L)", f.taper_letter as char);
        if conv.tpi_letter != 0 {
            letters.push(conv.tpi_letter);
        }
        if f.gsk_g92_words {
            letters.extend_from_slice(b"JKL");
            format.push_str(" or I(threads per inch), J K L");
        }
        if f.start_angle {
            letters.push(b'Q');
            format.push_str(" Q(start angle)");
        }
        (letters, format)
    }

    /// The pass's start angle: its own Q, else 0 — Q is not modal, and a repeat without one after
    /// a pass that had one draws a warning (the usual slip on a second start).
    fn g92_start_angle(
        &self,
        line: &Line,
        span: Span,
        repeat: Option<G92Modal>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<f64> {
        if let Some(q) = line.word(b'Q').filter(|_| self.flavour.start_angle) {
            return start_angle(q);
        }
        if let Some(m) = repeat.filter(|m| m.phase_deg != 0.0) {
            warnings.push(
                Diagnostic::warning(
                    Code::Suspicious,
                    span,
                    format!(
                        "this pass starts at 0°: the start angle Q{} of line {} is not modal",
                        crate::post::start_angle_count(m.phase_deg),
                        m.phase_line
                    ),
                )
                .with_hint("repeat Q on every pass of a start other than the first"),
            );
        }
        Ok(0.0)
    }

    /// GSK's G92 tail-out J (short axis) and K (long axis) in the block's own words, and L starts
    /// (threading-notes §c.1–c.2): J alone means K = J, K alone means J = K, J = 0 means none;
    /// neither: parameters 5130/5131.
    fn gsk_tail(&self, line: &Line, modal: &Modal, lead: f64) -> Result<(Exit, u32)> {
        let j = line.word(b'J').map(|w| modal.length_mm(w));
        let k = line.word(b'K').map(|w| modal.length_mm(w));
        for w in [line.word(b'J'), line.word(b'K')].into_iter().flatten() {
            if w.value < 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.span,
                    format!(
                        "{}{} is negative: the tail-out is unsigned",
                        w.letter as char, w.value
                    ),
                ));
            }
        }
        let length = modal.resolution().length();
        let exit = match (j, k) {
            (None, None) => self.chamfer(lead, length),
            (Some(j), None) => pull_out(j, j, length),
            (Some(j), Some(k)) if length.is_zero(k) => pull_out(j, j, length),
            (None, Some(k)) => pull_out(k, k, length),
            (Some(j), Some(k)) => pull_out(j, k, length),
        };
        let starts = match line.word(b'L') {
            None => 1,
            Some(l) if l.value.fract() == 0.0 && (1.0..=99.0).contains(&l.value) => l.value as u32,
            Some(l) => {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    l.span,
                    format!(
                        "L{} is out of range: the number of starts is 1 to 99",
                        l.value
                    ),
                ))
            }
        };
        Ok((exit, starts))
    }

    /// The cycle's lead: F (or a TPI word), modal from an earlier thread block; Haas's E as F.
    fn lead(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        cycle: &str,
    ) -> Result<f64> {
        if let Some(e) = line.word(b'E') {
            if !self.flavour.e_is_lead {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    e.span,
                    format!(
                        "E on {cycle} means threads per inch or a precise lead depending on the series"
                    ),
                )
                .with_hint("write the lead with F"));
            }
            if let Some(f) = line.word(b'F') {
                let later = if e.span.start > f.span.start { e } else { f };
                return Err(Diagnostic::error(
                    Code::Conflict,
                    later.span,
                    format!("F and E in one {cycle} block: the lead is given by either F or E"),
                ));
            }
            let lead = one_block::positive(modal, e, "the lead")?;
            modal.lead = Some(lead);
            return Ok(lead);
        }
        modal.read_lead(conv, line.words)?;
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        modal.lead.ok_or_else(|| {
            Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{cycle} has no lead: F is missing"),
            )
            .with_hint("F is modal: write it on this block or on an earlier thread block")
        })
    }

    fn endpoints(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &Modal,
        span: Span,
        cycle: &str,
    ) -> Result<(Pos, Pos)> {
        if line.word(b'X').or(line.word(b'U')).is_none()
            || line.word(b'Z').or(line.word(b'W')).is_none()
        {
            return Err(Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{cycle} needs the thread end point: X (or U) and Z (or W)"),
            ));
        }
        let a = start_point(modal, span, cycle)?;
        Ok((a, modal.target(conv, line, a)?))
    }

    fn check_exit(
        &self,
        exit: &Exit,
        travel_z: f64,
        units: Units,
        tol: Tolerance,
        span: Span,
    ) -> Result<()> {
        if let Exit::PullOut { length, .. } = *exit {
            if !tol.lt(length, travel_z.abs()) {
                return Err(geometry(
                    span,
                    format!(
                        "{} {} is not shorter than the thread ({} along Z)",
                        self.flavour.chamfer_name,
                        units.from_mm(length),
                        units.from_mm(travel_z.abs())
                    ),
                )
                .with_hint(format!("lower {}", self.flavour.chamfer_name)));
            }
        }
        Ok(())
    }
}

/// `Q` on a plain thread move (`G32 … Q180000`): the start angle of the run it begins, in 0.001°
/// without a decimal point, for its own block only (not modal).
pub const START_ANGLE_Q: StartAngleWord = StartAngleWord {
    name: "Q",
    unit: AngleUnit::Millidegrees,
    modal: false,
};

/// `Q`, the thread's start angle: a count of 0.001° without a decimal point, 0 to 360000 (Fanuc:
/// "Angle for shifting the threading start angle (Increment: 0.001 degrees, Valid setting range: 0
/// to 360 degrees)"; Haas: "Thread Start Angle (Do not use a decimal point)"). In degrees, below 360.
pub(crate) fn start_angle(q: &Word) -> Result<f64> {
    if q.has_dot || q.value.fract() != 0.0 {
        return Err(Diagnostic::error(
            Code::Syntax,
            q.span,
            "Q (the thread's start angle) is written in 0.001° without a decimal point",
        )
        .with_hint("Q180000 is 180°; a decimal point is not allowed"));
    }
    if !(0.0..=360_000.0).contains(&q.value) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            q.span,
            format!(
                "Q{}: the start angle is 0 to 360000 (0.001°: 0 to 360°)",
                q.value
            ),
        ));
    }
    Ok((q.value / 1000.0) % 360.0)
}

/// A one-block G76's words (K thread height, D first cut, A tool angle: Fanuc's FS15 program
/// format, Haas) on a two-block control: the control's alarm at the word, the form it reads, and
/// the built-in controllers whose vocabulary has the code with the block's words
/// ([`super::others_with`]: every controller that declares a one-block G76 is named).
fn one_block_words_on_two_block(
    line: &Line,
    vocabulary: &Vocabulary,
    code: u16,
    name: &str,
) -> Result<()> {
    match line
        .words
        .iter()
        .find(|w| matches!(w.letter, b'K' | b'D' | b'A'))
    {
        Some(w) => Err(super::foreign_form(
            line,
            w.span,
            code,
            vocabulary,
            format!(
                "{} is a word of the one-block {name} (X Z I K D F A P Q: Fanuc's FS15 program format, Haas), and {} reads {name} in two blocks",
                w.letter as char, vocabulary.controller
            ),
            &format!("{name} P(m)(r)(a) Q(Δdmin) R(d), then {name} X(U) Z(W) R(i) P(k) Q(Δd) F(L)"),
        )),
        None => Ok(()),
    }
}

fn pull_out(j: f64, k: f64, length: Tolerance) -> Exit {
    if length.gt(j, 0.0) && length.gt(k, 0.0) {
        Exit::PullOut {
            start_before: k,
            length: k,
            outward: j,
        }
    } else {
        Exit::Straight
    }
}

fn start_point(modal: &Modal, span: Span, cycle: &str) -> Result<Pos> {
    super::start_point(
        modal,
        span,
        cycle,
        "position the tool with G00 X.. Z.. before the cycle",
    )
}

/// External when the start point is above `reference` (cut toward −X), internal when below; the
/// same X at the program's resolution cannot tell.
fn side_of(a: Pos, reference: Pos, x_tol: Tolerance, span: Span) -> Result<Side> {
    match x_tol.sign(a.x - reference.x) {
        1 => Ok(Side::External),
        -1 => Ok(Side::Internal),
        _ => Err(geometry(
            span,
            "the start point's X equals the thread's X: cannot tell an external from an internal thread",
        )),
    }
}

fn geometry(span: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(Code::Geometry, span, msg)
}

/// P(m)(r)(a): three two-digit fields, leading zeros may be omitted (`P21060` is m 02, r 10, a 60).
fn unpack_p(line: &Line, p: &Word, name: &str) -> Result<(u32, u32, u32)> {
    let packed = super::packed_p(
        line,
        p,
        name,
        "P021060 is 2 finishing passes, a chamfer of 1.0 lead, a 60° tool",
    )?;
    let [m, r, a] = packed.fields;
    if !(1..=99).contains(&m) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            p.span,
            format!("P(m)={m:02}: the number of finishing passes must be 01 to 99"),
        ));
    }
    if !TOOL_ANGLES.contains(&a) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            p.span,
            format!("P(a)={a:02}: the tool-tip angle must be 80, 60, 55, 30, 29 or 00"),
        ));
    }
    Ok((m, r, a))
}

fn alarm_missing(span: Span, name: &str, word: &str, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("{name} alarm (PS0062): {word} is missing; it gives {what}"),
    )
    .with_hint(format!("{word} has no default on the second {name} block"))
}

/// The two G76 blocks (G78 in system C) that may express `job`, one per choice of the words the
/// job leaves open (the read-back check decides): the tool angle `a` is chosen for the infeed the
/// job makes, not copied from the tool the job names for its chip areas — a radial infeed is `a`
/// 0 whatever the tool, a single-flank infeed at θ is the angle 2θ of the list. `params` are the
/// target's (the chamfer's angle is its parameter 5131, which no block rewrites).
pub fn g76_candidates(
    machine: &Machine,
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    match g76_words(codes, params, job) {
        Ok((angles, r)) => angles
            .into_iter()
            .map(|a| Ok(g76_text(machine, codes, job, a, r)))
            .collect(),
        Err(why) => vec![Err(why)],
    }
}

/// The first of [`g76_candidates`].
pub fn native_g76(
    machine: &Machine,
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> std::result::Result<Vec<String>, String> {
    g76_candidates(machine, codes, params, job).remove(0)
}

/// The tool angles whose infeed is the job's, and the chamfer's r; or the property of the job the
/// cycle cannot express.
fn g76_words(
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> std::result::Result<(Vec<u32>, u32), String> {
    let name = g_name(codes.multiple);
    let g = &job.geometry;
    if g.side.is_face() {
        return Err(format!("{name} threads along Z, and this is a face thread"));
    }
    if job.lead.phase_deg != 0.0
        || (job.lead.starts > 1 && job.lead.indexing == StartIndexing::Angle)
    {
        return Err(format!(
            "the two-block {name} has no start angle: its Q is the first depth"
        ));
    }
    if job.return_path != ReturnPath::Box
        || job.retract
            != (Retract {
                x: job.start.x,
                z: job.start.z,
            })
    {
        return Err(
            format!("{name} retracts to the start point's X and returns to its Z after every pass, and this job does not"),
        );
    }
    if job.entry != Entry::Direct {
        return Err(format!("{name} has no entry ramp"));
    }
    if job.lead.dlead != 0.0 || job.lead.starts != 1 {
        return Err(format!("{name} cuts one start of a constant lead"));
    }
    if !(1..=99).contains(&job.plan.finish_passes) {
        return Err(format!(
            "{name} cuts 1 to 99 finishing passes, and this job cuts {}",
            crate::text::count(
                job.plan.finish_passes as usize,
                "finishing pass",
                "finishing passes"
            )
        ));
    }
    if !matches!(job.plan.law, DepthLaw::Power { degression, .. } if degression == 2.0) {
        return Err(format!(
            "{name} cuts the constant-area law d·√n (each cut at least Δdmin), and this job's depths follow another law"
        ));
    }
    let lead = job.lead.lead;
    let r = match job.exit {
        Exit::Straight => 0,
        Exit::PullOut {
            start_before,
            length,
            outward,
        } if start_before == length => {
            let tenths = length / (0.1 * lead);
            if (tenths - tenths.round()).abs() > 1e-6 || tenths.round() > 99.0 {
                return Err(format!(
                    "{name}'s chamfer is a whole number of tenths of a lead, 0 to 99, and this job's pull-out is {} leads long",
                    crate::post::number(length / lead, 4, false)
                ));
            }
            let angle = tan_deg(params.chamfer_angle_deg);
            if (outward - length * angle).abs() > 1e-6 {
                return Err(format!(
                    "{name}'s chamfer runs at parameter 5131's angle ({}° from Z), and this job's pull-out at {}°",
                    params.chamfer_angle_deg,
                    crate::post::number(outward.atan2(length).to_degrees(), 3, false)
                ));
            }
            tenths.round() as u32
        }
        Exit::PullOut { .. } | Exit::ToRetract { .. } | Exit::FeedOut { .. } => {
            return Err(format!(
                "{name}'s chamfer is a synchronised pull-out ending at the thread's end, and this job's exit is not"
            ))
        }
    };
    let leading = if g.side.along(g.travel()) < 0.0 {
        Flank::Right
    } else {
        Flank::Left
    };
    let angles: Vec<u32> = match job.infeed {
        Infeed::Radial => vec![0],
        Infeed::Flank { flank, angle_deg } if flank == leading => {
            let fits: Vec<u32> = TOOL_ANGLES
                .iter()
                .copied()
                .filter(|&a| (f64::from(a) / 2.0 - angle_deg).abs() < 1e-9)
                .collect();
            if fits.is_empty() {
                return Err(format!(
                    "{name} infeeds along the flank at half its tool angle a (80, 60, 55, 30, 29 or 0), and this job at {}°",
                    crate::post::number(angle_deg, 4, false)
                ));
            }
            if job.plan.finish_allowance > 0.0 && job.finish_at == FinishPosition::LastRough {
                return Err(format!(
                    "{name} cuts its finishing passes at the full-depth flank position, and this job at the last rough pass's"
                ));
            }
            fits
        }
        Infeed::Flank { .. } => {
            return Err(format!(
                "{name} infeeds along the leading flank (the tool moves toward the thread's end as it goes deeper), and this job along the trailing one"
            ))
        }
        Infeed::Alternating { .. } => {
            return Err(format!(
                "the two-block {name} infeeds along one flank, and this job alternates between flanks"
            ))
        }
    };
    Ok((angles, r))
}

/// The two blocks with tool angle `angle` and chamfer `r`.
fn g76_text(machine: &Machine, codes: &GCodes, job: &Job, angle: u32, r: u32) -> Vec<String> {
    let name = g_name(codes.multiple);
    let g = &job.geometry;
    let (first, min_cut) = match job.plan.law {
        DepthLaw::Power {
            first, min_step, ..
        } => (first, min_step),
        _ => (0.0, 0.0),
    };
    let u = job.units;
    let inc = machine.resolution(u);
    let count = |mm: f64| format!("{}", (u.from_mm(mm) / inc).round() as i64);
    let nd = machine.decimals(u);
    let num = |mm: f64| crate::post::number(u.from_mm(mm), nd, false);
    // The full-depth pass runs from the start Z to the programmed end.
    let full_offset = job.infeed.axis(g.depth);
    let root_end = Pos::new(
        g.crest_end.x + g.side.infeed().x * g.depth,
        g.crest_end.z + full_offset,
    );
    let x_end = if machine.diameter_x {
        root_end.x * 2.0
    } else {
        root_end.x
    };
    let mut second = format!(
        "{name} X{} Z{}",
        crate::post::number(u.from_mm(x_end), nd, false),
        num(root_end.z)
    );
    if g.taper() != 0.0 {
        second.push_str(&format!(" R{}", num(g.taper())));
    }
    second.push_str(&format!(
        " P{} Q{} F{}",
        count(g.depth),
        count(first),
        crate::post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        )
    ));
    vec![
        format!(
            "{name} P{:02}{r:02}{angle:02} Q{} R{}",
            job.plan.finish_passes,
            count(min_cut),
            num(job.plan.finish_allowance)
        ),
        second,
    ]
}

/// The candidates of a control with a single-pass and a multiple-pass cycle, the one that fits the
/// job's number of passes first (so that its reason is the one given when none reads back).
pub fn single_or_multiple(
    single: std::result::Result<Vec<String>, String>,
    multiple: Vec<std::result::Result<Vec<String>, String>>,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    if is_single_pass(job) {
        std::iter::once(single).chain(multiple).collect()
    } else {
        multiple
            .into_iter()
            .chain(std::iter::once(single))
            .collect()
    }
}

/// One pass at the crest line: what a single-pass cycle (G92) cuts.
pub fn is_single_pass(job: &Job) -> bool {
    job.geometry.depth == 0.0
        && job.plan.finish_passes == 1
        && matches!(&job.plan.law, DepthLaw::Explicit { depths } if depths.is_empty())
}

/// The G92 block (G78 in system B, G21 in C) that expresses a single-pass `job`, when G92 can.
/// GSK writes the pull-out as J (short axis) and K (long axis) on the block (`gsk_g92_words`);
/// the others take it from their parameters. The taper and start-angle words are the flavour's.
pub fn native_g92(
    machine: &Machine,
    codes: &GCodes,
    flavour: &Flavour,
    job: &Job,
) -> std::result::Result<Vec<String>, String> {
    let name = g_name(codes.single);
    let tail_words = flavour.gsk_g92_words;
    let g = &job.geometry;
    if !is_single_pass(job) {
        return Err(format!(
            "{name} cuts one pass, and this job cuts {}",
            crate::text::count(job.passes().map_or(0, |p| p.len()), "pass", "passes")
        ));
    }
    if job.return_path != ReturnPath::Box || job.entry != Entry::Direct || job.lead.dlead != 0.0 {
        return Err(format!("{name} has no entry ramp or variable lead"));
    }
    let u = job.units;
    let nd = machine.decimals(u);
    let num = |mm: f64| crate::post::number(u.from_mm(mm), nd, false);
    let x = if machine.diameter_x {
        g.crest_end.x * 2.0
    } else {
        g.crest_end.x
    };
    let mut block = format!(
        "{name} X{} Z{}",
        crate::post::number(u.from_mm(x), nd, false),
        num(g.crest_end.z)
    );
    if g.taper() != 0.0 {
        block.push_str(&format!(
            " {}{}",
            flavour.taper_letter as char,
            num(g.taper())
        ));
    }
    if tail_words {
        match job.exit {
            Exit::Straight => block.push_str(" J0"),
            Exit::PullOut {
                start_before,
                length,
                outward,
            } if start_before == length => {
                block.push_str(&format!(" J{} K{}", num(outward), num(length)))
            }
            Exit::PullOut { .. } | Exit::ToRetract { .. } | Exit::FeedOut { .. } => {
                return Err(format!(
                    "{name}'s tail-out is synchronised and ends at the thread's end"
                ))
            }
        }
        if job.lead.starts > 1 {
            if job.lead.indexing != StartIndexing::Shift {
                return Err(format!(
                    "{name}'s L reaches further starts by a shift along Z, and this job reaches them by the spindle angle, each start whole"
                ));
            }
            block.push_str(&format!(" L{}", job.lead.starts));
        }
    } else if job.lead.starts != 1 {
        return Err(format!("{name} cuts one start (a start angle Q shifts it)"));
    }
    if job.lead.phase_deg != 0.0 && !flavour.start_angle {
        return Err(format!("{name} has no start angle on this controller"));
    }
    block.push_str(&format!(
        " F{}",
        crate::post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        )
    ));
    if job.lead.phase_deg != 0.0 {
        block.push_str(&format!(
            " Q{}",
            crate::post::start_angle_count(job.lead.phase_deg)
        ));
    }
    Ok(vec![block])
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
};

/// The lexicon of a Fanuc-format control in `system`.
pub fn lexicon(system: GCodeSystem) -> &'static Lexicon {
    match system {
        GCodeSystem::A => &LEXICON_A,
        GCodeSystem::B => &LEXICON_B,
        GCodeSystem::C => &LEXICON_C,
    }
}
