//! GSK 980TDi-class lathe controls: the enhanced multiple thread-cutting cycle G78 (seed 001; the
//! English text is `shared/reference/gsk-g78-english.md`, whose section numbers are cited below).
//!
//! ```text
//! G78 P(m)(r)(a) Q(Δdmin) R(d) D_ L_ E_ ;            first block: settings, no motion
//! G78 X(U) Z(W) R(i) P(k) Q(Δd) J_ K_ F(I) ;          second block: the cycle
//! ```
//! Every decision on an ambiguity of the seed is a row of `docs/dialects/gsk-g78.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::{GCodeSystem, GskParameters, IncrementSystem, Machine};
use crate::post::Format;
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, ReturnPath, Side, StartIndexing,
};
use crate::units::{Pos, Resolution, Tolerance, Units};

use super::fanuc_family::{self, FanucFamily, Flavour, GCodes, ThreadParameters};
use super::{g, only_words, Dialect, Read};
use crate::dialect::lexicon::{self, Code as C, Function as F, Lexicon};

/// The G codes of a GSK 980TDi-class lathe control (its manual's G code table: docs/dialects/gsk-g78.md,
/// "Vocabulary"). G33 is GSK's Z-axis tapping cycle, not a thread move; G32 threads, and G76, G78 and
/// G92 are the threading cycles. A fractional code (G6.2, G7.3, G12.1) is known by its whole number.
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "gsk980",
    alarm: "GSK alarm (illegal G code)",
    g_codes: &[
        g(0),
        g(10),
        g(20),
        g(30),
        g(40),
        g(50),
        g(60),
        g(70),
        g(100),
        g(110),
        g(120),
        g(130),
        g(170),
        g(180),
        g(190),
        g(200),
        g(210),
        g(220),
        g(230),
        g(260),
        g(270),
        g(280),
        g(290),
        g(300),
        g(310),
        GCode::thread(320, b"XZUWFIJKLQ"),
        GCode {
            code: 330,
            words: Some(b"ZWFIL"),
            threads: false,
        },
        g(340),
        g(360),
        g(370),
        g(400),
        g(410),
        g(420),
        g(500),
        g(510),
        g(520),
        g(530),
        g(540),
        g(550),
        g(560),
        g(570),
        g(580),
        g(590),
        g(650),
        g(660),
        g(670),
        g(700),
        g(710),
        g(720),
        g(730),
        g(740),
        g(750),
        GCode::thread(760, b"XZUWRPQFI"),
        GCode::thread(780, b"XZUWRPQJKFIDLE"),
        g(800),
        g(830),
        g(840),
        g(850),
        g(860),
        g(870),
        g(880),
        g(890),
        g(900),
        GCode::thread(920, b"XZUWRFIJKL"),
        g(940),
        g(960),
        g(970),
        g(980),
        g(990),
    ],
    foreign: &[],
    others: super::others_with,
};

const G78: u16 = 780;

/// Values of the first block, in force for every later second block until the next first block
/// (as on Fanuc's G76, whose first block rewrites the parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Settings {
    finish_passes: u32,
    infeed_mode: u8,
    tool_angle: f64,
    min_cut_mm: f64,
    finish_allowance_mm: f64,
    depth_mode: u8,
    starts: u32,
    lead_in_mm: f64,
}

impl Settings {
    /// Parameters 5140–5145 stand in for the first block's missing words (§3).
    fn from_parameters(p: &GskParameters) -> Settings {
        Settings {
            finish_passes: u32::from(p.p5142),
            infeed_mode: p.p5144,
            tool_angle: f64::from(p.p5143),
            min_cut_mm: p.p5140,
            finish_allowance_mm: p.p5141,
            depth_mode: p.p5145,
            starts: 1,
            lead_in_mm: 0.0,
        }
    }
}

/// What a GSK 980TDi's codes mean: Fanuc's system A (GSK copies it: `docs/dialects/gsk-g78.md`,
/// "Vocabulary"), with feed per minute (G98) at power-on and the thread move's lead as F or
/// threads per inch as I (`docs/translation.md`).
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        lexicon::G20_G21,
        &[
            (C::G(320), F::Thread),
            (C::G(500), F::SpindleLimit),
            (C::G(980), F::FeedPerMinute),
            (C::G(990), F::FeedPerRevolution),
        ],
        lexicon::COMPENSATION,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
    ],
    power_on_feed: F::FeedPerMinute,
    thread_words: b"FI",
    ..fanuc_family::FANUC_LEXICON
};

pub struct Gsk {
    conv: Conventions,
    machine: Machine,
    params: GskParameters,
    settings: Settings,
    /// J and K are modal (§3): the last values written, in mm.
    tail_j: Option<f64>,
    tail_k: Option<f64>,
    /// G76 and G92 are the Fanuc family's, shared with `--controller fanuc`.
    family: FanucFamily,
}

/// The built-in parameter values when a profile has no `[gsk]` table.
pub fn default_parameters() -> GskParameters {
    Machine::built_in("gsk980")
        .and_then(|m| m.gsk)
        .expect("the gsk980 profile has a [gsk] table")
}

impl Gsk {
    pub fn new(machine: &Machine) -> Gsk {
        let params = machine.gsk.clone().unwrap_or_else(default_parameters);
        Gsk {
            conv: Conventions {
                uw_incremental: true,
                g90_g91_distance: false,
                diameter_x: machine.diameter_x,
                thread_move: 320,
                tpi_letter: b'I',
                lead_letter: b'F',
                lead_along_path: false,
                set_position: 500,
                canned_cycles: &[700, 710, 720, 730, 740, 750, 760, 780, 900, 920, 940],
                // GSK 980TDi: G83 end-face and G87 side deep-hole drilling, G84/G88 rigid
                // tapping, G85/G89 boring.
                unmodelled: &[
                    (830, "end-face deep-hole drilling cycle"),
                    (840, "end-face rigid tapping cycle"),
                    (850, "end-face boring cycle"),
                    (860, "boring cycle"),
                    (870, "side deep-hole drilling cycle"),
                    (880, "side rigid tapping cycle"),
                    (890, "side boring cycle"),
                ],
                units_codes: crate::gcode::modal::G20_G21,
                positions: crate::gcode::modal::PositionCodes::FANUC,
                syntax: crate::gcode::lexer::Syntax::default(),
            },
            machine: machine.clone(),
            settings: Settings::from_parameters(&params),
            family: FanucFamily::new(
                Flavour {
                    gsk_g92_words: true,
                    // GSK's G92 cuts further starts with L, not by a start angle.
                    start_angle: false,
                    turning_fst_first: true,
                    ..Flavour::fanuc("gsk980", |_| &VOCABULARY)
                },
                ThreadParameters::fanuc(
                    params.p5130,
                    params.p5131,
                    params.p5140,
                    params.p5141,
                    params.p5142,
                    params.p5143,
                ),
                GCodes::of(GCodeSystem::A),
                machine,
            ),
            params,
            tail_j: None,
            tail_k: None,
        }
    }

    /// The seed's address table (§4): the allowed range of a word in the active units.
    fn range(&self, class: RangeClass, units: Units) -> (f64, f64) {
        let isc = self.machine.increment_system == IncrementSystem::Isc;
        let inch = units == Units::Inch;
        let max = match (isc, inch) {
            (false, false) => 999999.999,
            (false, true) => 99999.9999,
            (true, false) => 99999.9999,
            (true, true) => 9999.99999,
        };
        match class {
            RangeClass::Length => (0.0, max),
            RangeClass::Positive => (self.machine.resolution(units), max),
            RangeClass::Signed => (-max, max),
            RangeClass::Lead if inch => (0.00001, 9.99),
            RangeClass::Lead => (0.0001, 9999.0),
            RangeClass::Tpi if inch => (0.0001, 100.0),
            RangeClass::Tpi => (0.0001, 254.0),
        }
    }

    /// A word's value in program units, checked against its range.
    fn checked(&self, modal: &Modal, w: &Word, name: &str, class: RangeClass) -> Result<f64> {
        let v = modal.value(w);
        let (lo, hi) = self.range(class, modal.units);
        if v < lo || v > hi {
            return Err(out_of_range(
                w.span,
                name,
                v,
                lo,
                hi,
                modal.units,
                self.machine.increment_system,
            ));
        }
        Ok(v)
    }

    fn read_first(&mut self, line: &Line, modal: &Modal) -> Result<()> {
        only_words(
            line,
            b"GNPQRDLE",
            "the first G78 block",
            "P(m)(r)(a) Q(Δdmin) R(d) D L E",
        )?;
        let mut s = Settings::from_parameters(&self.params);
        if let Some(p) = line.word(b'P') {
            let (m, r, a) = unpack_p(line, p)?;
            s.finish_passes = m;
            s.infeed_mode = r;
            s.tool_angle = f64::from(a);
        }
        if let Some(q) = line.word(b'Q') {
            s.min_cut_mm =
                modal
                    .units
                    .to_mm(self.checked(modal, q, "Q(Δdmin)", RangeClass::Length)?);
        }
        if let Some(r) = line.word(b'R') {
            s.finish_allowance_mm =
                modal
                    .units
                    .to_mm(self.checked(modal, r, "R(d)", RangeClass::Length)?);
        }
        if let Some(d) = line.word(b'D') {
            s.depth_mode = small_integer(d, "D (depth mode)", 0, 1)? as u8;
        }
        if let Some(l) = line.word(b'L') {
            s.starts = small_integer(l, "L (number of starts)", 1, 99)?;
        }
        if let Some(e) = line.word(b'E') {
            s.lead_in_mm =
                modal
                    .units
                    .to_mm(self.checked(modal, e, "E (lead-in)", RangeClass::Length)?);
        }
        self.settings = s;
        Ok(())
    }

    fn read_second(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        g78: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        only_words(
            line,
            b"GNXZUWRPQJKFI",
            "the second G78 block",
            "X(U) Z(W) R(i) P(k) Q(Δd) J K F(I)",
        )?;
        let units = modal.units;
        let mm = |v: f64| units.to_mm(v);
        let taper = match line.word(b'R') {
            Some(r) => mm(self.checked(modal, r, "R(i)", RangeClass::Signed)?),
            None => 0.0,
        };
        let height = match line.word(b'P') {
            Some(p) => mm(self.checked(modal, p, "P(k)", RangeClass::Positive)?),
            None => {
                return Err(alarm_missing(
                    g78,
                    "P(k)",
                    "the thread height (total depth of cut, radius)",
                ))
            }
        };
        let first = match line.word(b'Q') {
            Some(q) => mm(self.checked(modal, q, "Q(Δd)", RangeClass::Positive)?),
            None => {
                return Err(alarm_missing(
                    g78,
                    "Q(Δd)",
                    "the depth of the first cut (radius)",
                ))
            }
        };
        let j = line
            .word(b'J')
            .map(|w| self.checked(modal, w, "J (tail-out, short axis)", RangeClass::Length))
            .transpose()?;
        let k = line
            .word(b'K')
            .map(|w| self.checked(modal, w, "K (tail-out, long axis)", RangeClass::Length))
            .transpose()?;
        if let Some(f) = line.word(b'F') {
            self.checked(modal, f, "F (lead)", RangeClass::Lead)?;
        }
        if let Some(i) = line.word(b'I') {
            self.checked(modal, i, "I (threads per inch)", RangeClass::Tpi)?;
        }
        modal.read_lead(&self.conv, line.words)?;
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        let lead = modal.lead.ok_or_else(|| {
            Diagnostic::error(
                Code::MissingWord,
                g78,
                "G78 has no lead: F (lead) or I (threads per inch) is missing",
            )
            .with_hint("F and I are modal: write one on this block or on an earlier thread block")
        })?;
        if line.word(b'X').or(line.word(b'U')).is_none()
            || line.word(b'Z').or(line.word(b'W')).is_none()
        {
            return Err(Diagnostic::error(
                Code::MissingWord,
                g78,
                "G78 needs the thread end point: X (or U) and Z (or W)",
            ));
        }
        let a = super::start_point_unstated(
            modal,
            g78,
            "G78",
            "position the tool with G00 X.. Z.. before the cycle (its start point A)",
        )?;
        let end = modal.target(&self.conv, line, a)?;
        // §12: J and K are modal; the tail-out falls back to parameters 5130/5131 when neither was given.
        if j.is_some() || k.is_some() {
            self.tail_j = j.map(mm).or(self.tail_j);
            self.tail_k = k.map(mm).or(self.tail_k);
        }
        let s = self.settings;
        lower(
            &LoweringInput {
                span: g78,
                line: line.number,
                units,
                a,
                end,
                taper,
                height,
                first,
                lead,
                settings: s,
                tail: self.tail(lead, modal.resolution().length()),
                x_word: |x| modal.x_from_mm(x),
                resolution: modal.resolution(),
            },
            warnings,
        )
    }

    /// The tail-out (J, K) in mm, following the 980TDi rules for omitted words: K alone means J = K,
    /// J alone means K = J, J = 0 means none; neither ever written: parameter 5130 (amount in 0.1
    /// lead) at the angle of parameter 5131 (0 = 45°).
    fn tail(&self, lead: f64, tol: Tolerance) -> Option<(f64, f64)> {
        let (j, k) = match (self.tail_j, self.tail_k) {
            (None, None) => {
                let k = f64::from(self.params.p5130) * 0.1 * lead;
                let angle = if self.params.p5131 == 0 {
                    45.0
                } else {
                    f64::from(self.params.p5131)
                };
                (k * tan_deg(angle), k)
            }
            (Some(j), None) => (j, j),
            (None, Some(k)) => (k, k),
            (Some(j), Some(k)) if tol.is_zero(k) => (j, j),
            (Some(j), Some(k)) => (j, k),
        };
        (tol.gt(j, 0.0) && tol.gt(k, 0.0)).then_some((j, k))
    }
}

#[derive(Clone, Copy)]
enum RangeClass {
    /// 0 ~ max: Q(Δdmin), R(d), E, J, K.
    Length,
    /// least increment ~ max: P(k), Q(Δd).
    Positive,
    /// ±max: R(i).
    Signed,
    Lead,
    Tpi,
}

struct LoweringInput<F: Fn(f64) -> f64> {
    span: Span,
    line: u32,
    units: Units,
    a: Pos,
    end: Pos,
    taper: f64,
    height: f64,
    first: f64,
    lead: f64,
    settings: Settings,
    tail: Option<(f64, f64)>,
    /// How the program writes an X radius, for messages.
    x_word: F,
    /// The program's resolution, for every comparison of the values above.
    resolution: Resolution,
}

/// Lowers a validated G78 into the shared model: points A, B, C, D of §12 and the formulas of §7–§8.
fn lower<F: Fn(f64) -> f64>(
    input: &LoweringInput<F>,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Job> {
    let i = input;
    let s = i.settings;
    let geometry_error = |msg: String| Diagnostic::error(Code::Geometry, i.span, msg);
    // C: the thread start on the root line, i (radius) from D's X, at A's Z (§12).
    let c = Pos::new(i.end.x + i.taper, i.a.z);
    let travel_z = i.end.z - i.a.z;
    let length = i.resolution.length();
    if length.is_zero(travel_z) {
        return Err(geometry_error(
            "the thread end Z equals the start point's Z: the thread has no length".into(),
        ));
    }
    if length.gt(i.taper.abs(), travel_z.abs()) {
        return Err(geometry_error(format!(
            "the taper R(i) changes X by more than the thread's Z length ({} > {} mm, radius): G78 cuts along Z and cannot cut a face-like thread",
            i.taper.abs(),
            travel_z.abs()
        ))
        .with_hint("G78 cannot machine face threads (§1)"));
    }
    let (side, crest_start) = g78_crest_start(i, c)?;
    let crest_end = Pos::new(crest_start.x - i.taper, i.end.z);
    if !length.lt(s.finish_allowance_mm, i.height) {
        return Err(geometry_error(format!(
            "the finishing allowance R(d) {} is not smaller than the thread height P(k) {}",
            i.units.from_mm(s.finish_allowance_mm),
            i.units.from_mm(i.height)
        )));
    }
    let exit = g78_exit(i, travel_z)?;
    super::lead_warning(
        i.lead,
        travel_z,
        i.units,
        length,
        i.span,
        "check F: a lead written without its decimal point?",
        warnings,
    );
    Ok(Job {
        line: i.line,
        span: i.span,
        controller: "gsk980",
        units: i.units,
        start: i.a,
        geometry: Geometry {
            crest_start,
            crest_end,
            depth: i.height,
            side,
        },
        lead: Lead {
            starts: s.starts,
            ..Lead::constant(i.lead)
        },
        plan: PassPlan {
            law: g78_depth_law(&s, i.first),
            finish_allowance: s.finish_allowance_mm,
            finish_passes: s.finish_passes,
        },
        infeed: g78_infeed(&s),
        finish_at: FinishPosition::LastRough,
        tool_angle_deg: s.tool_angle,
        entry: if length.gt(s.lead_in_mm, 0.0) {
            Entry::Ramp {
                outward: s.lead_in_mm,
                before: 0.0,
            }
        } else {
            Entry::Direct
        },
        exit,
        retract: Retract { x: i.a.x, z: i.a.z },
        return_path: ReturnPath::Box,
    })
}

/// The side and the crest at the thread's start: the start point A above C cuts an external
/// thread, below C an internal one (§8), and A must not lie inside the thread.
fn g78_crest_start<F: Fn(f64) -> f64>(i: &LoweringInput<F>, c: Pos) -> Result<(Side, Pos)> {
    let geometry_error = |msg: String| Diagnostic::error(Code::Geometry, i.span, msg);
    let x_tol = i.resolution.x();
    // The infeed direction follows from the start point (§8): above C an external thread, cut toward
    // −X ("negative-direction infeed"); below C an internal one.
    let side = match x_tol.sign(i.a.x - c.x) {
        1 => Side::External,
        -1 => Side::Internal,
        _ => return Err(geometry_error(
            "the start point's X equals the thread's start on the root line: cannot tell an external from an internal thread".into(),
        )),
    };
    let crest_start = c.plus(side.outward().scale(i.height));
    // A start point within the resolution of the crest is on the crest (`G00 X40` before a crest
    // computed at X40.001).
    let beyond_crest = (i.a.x - crest_start.x) * side.outward().x;
    if x_tol.lt(beyond_crest, 0.0) {
        return Err(geometry_error(format!(
            "the start point X{} lies inside the thread (the crest is at X{}): the return along Z between passes would cut through it",
            crate::post::number((i.x_word)(i.a.x), 4, false),
            crate::post::number((i.x_word)(crest_start.x), 4, false)
        ))
        .with_hint("start the cycle from a point clear of the crest"));
    }
    Ok((side, crest_start))
}

/// The exit: straight without a tail-out, else a pull-out over K by J; K must be shorter than
/// the thread.
fn g78_exit<F: Fn(f64) -> f64>(i: &LoweringInput<F>, travel_z: f64) -> Result<Exit> {
    Ok(match i.tail {
        None => Exit::Straight,
        Some((j, k)) => {
            if !i.resolution.length().lt(k, travel_z.abs()) {
                return Err(Diagnostic::error(
                    Code::Geometry,
                    i.span,
                    format!(
                        "the tail-out K {} is not shorter than the thread ({} along Z)",
                        i.units.from_mm(k),
                        i.units.show(travel_z.abs())
                    ),
                ));
            }
            Exit::PullOut {
                start_before: k,
                length: k,
                outward: j,
            }
        }
    })
}

/// The infeed from the first block's mode m (§7): 0 radial, 1 left flank, 2 right flank, 3
/// right flank and centre alternating, otherwise both flanks alternating; at half the tool angle.
fn g78_infeed(s: &Settings) -> Infeed {
    let half = s.tool_angle / 2.0;
    match s.infeed_mode {
        0 => Infeed::Radial,
        1 => Infeed::Flank {
            flank: Flank::Left,
            angle_deg: half,
        },
        2 => Infeed::Flank {
            flank: Flank::Right,
            angle_deg: half,
        },
        3 => Infeed::Alternating {
            first: Flank::Right,
            second: Flank::Centre,
            angle_deg: half,
        },
        _ => Infeed::Alternating {
            first: Flank::Left,
            second: Flank::Right,
            angle_deg: half,
        },
    }
}

/// The depth law from the first block's depth mode: 0 equal steps of the first cut, otherwise
/// constant area (degression 2) with the smallest cut Q(Δdmin).
fn g78_depth_law(s: &Settings, first: f64) -> DepthLaw {
    if s.depth_mode == 0 {
        DepthLaw::Power {
            first,
            degression: 1.0,
            min_step: 0.0,
        }
    } else {
        DepthLaw::Power {
            first,
            degression: 2.0,
            min_step: s.min_cut_mm,
        }
    }
}

impl Dialect for Gsk {
    /// G78, G76 and G92 R(i): the radius at the cycle's start minus at its end (GSK980TDc §3.21,
    /// docs/dialects/gsk-g78.md).
    fn taper_word(&self) -> Option<super::TaperWord> {
        Some(super::TaperWord {
            cycles: "G78 / G76 / G92 R(i)",
            letter: 'R',
            start_minus_end: true,
            radius: true,
        })
    }
    fn name(&self) -> &'static str {
        "gsk980"
    }

    /// G78 blocks, the family's (G76, G92) and blocks with an E word (G78's lead-in, an exponent
    /// to refuse elsewhere).
    #[inline(always)]
    fn prefilter(&self, line: &Line) -> bool {
        self.family.prefilter(line, 0, |line| line.has_g(G78))
    }

    fn at_rest(&self) -> bool {
        // The family's prefilter depends on nothing else of its state (its letters and codes
        // are the machine's).
        !self.family.in_progress()
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

    fn end_of_input(&mut self) -> Result<()> {
        self.family.end_of_input()
    }

    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        if let Some(read) = self.family.read(&self.conv, line, modal, warnings)? {
            return Ok(read);
        }
        let Some(g78) = line
            .words
            .iter()
            .find(|w| w.letter == b'G' && crate::gcode::reader::g_code(w.value) == Some(G78))
        else {
            // E is G78's lead-in; on a thread move it may be a lead; nowhere else.
            if !self.family.threads(&self.conv, line, modal) {
                super::refuse_exponent(line)?;
            }
            return Ok(Read::Plain);
        };
        super::alone_in_block(line, g78.span, "G78", &[])?;
        let second = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        if second {
            let job = self.read_second(line, modal, g78.span, warnings)?;
            Ok(Read::Cycle(Box::new(job)))
        } else {
            self.read_first(line, modal)?;
            Ok(Read::Settings)
        }
    }

    fn program_files(
        &self,
        wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        fanuc_family::program_files(wanted)
    }

    fn macros(&self) -> Option<crate::interp::Syntax> {
        // GSK 980TDi: G65 is its macro operation `G65 Hm P#i Q#j R#k`, M98 packs the count in P
        // (`M98 P00031000`), subprograms nest four levels (docs/dialects/gsk-g78.md).
        Some(crate::interp::Syntax {
            max_macro_depth: 0,
            g65_operations: true,
            m98_l_word: false,
            ..crate::interp::Syntax::MACRO_B
        })
    }

    fn format(&self) -> Format {
        Format::lathe(&self.machine, "G32", 'F')
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        self.native_candidates(job).remove(0)
    }

    /// G78 first, with every choice of its open words; then G92 and G76 (the reason given when
    /// none reads back is G78's).
    fn native_candidates(&self, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
        let f = &self.family;
        let mut out = g78_candidates(&self.machine, job);
        out.push(fanuc_family::native_g92(
            &self.machine,
            &f.codes,
            &f.flavour,
            job,
        ));
        out.extend(fanuc_family::g76_candidates(
            &self.machine,
            &f.codes,
            &f.params,
            job,
        ));
        out
    }
}

/// The two G78 blocks that may express `job`, one per choice of the infeed mode r and tool angle a
/// that gives the job's infeed (the read-back check decides): a radial infeed is r = 0 with the
/// job's tool angle, or any r with a = 0; a flank at θ is a = 2θ; the checks mirror what [`lower`]
/// builds.
fn g78_candidates(machine: &Machine, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
    match g78_choices(job) {
        Ok(choices) => choices
            .into_iter()
            .map(|(r, a)| g78_text(machine, job, r, a))
            .collect(),
        Err(why) => vec![Err(why)],
    }
}

/// The (r, a) pairs whose infeed is the job's, or the property G78 cannot express.
fn g78_choices(job: &Job) -> std::result::Result<Vec<(u32, u32)>, String> {
    let g = &job.geometry;
    if g.side.is_face() {
        return Err("G78 cuts along Z and cannot cut a face thread".into());
    }
    if g.crest_start.z != job.start.z
        || job.retract
            != (Retract {
                x: job.start.x,
                z: job.start.z,
            })
    {
        return Err(
            "G78 starts and ends each pass at its start point, its passes moving away from its Z as they go deeper, and this job does not".into(),
        );
    }
    if job.lead.dlead != 0.0 {
        return Err("G78 cuts constant leads only".into());
    }
    if job.lead.phase_deg != 0.0 {
        return Err("G78 has no start angle".into());
    }
    if job.lead.starts > 1 && job.lead.indexing != StartIndexing::Shift {
        return Err(
            "G78's L reaches further starts by a shift along Z, and this job reaches them by the spindle angle, each start whole"
                .into(),
        );
    }
    if !(1..=99).contains(&job.lead.starts) || !(1..=99).contains(&job.plan.finish_passes) {
        return Err("G78 allows 1 to 99 starts and 1 to 99 finishing passes".into());
    }
    if !matches!(
        job.plan.law,
        DepthLaw::Power { degression, .. } if degression == 2.0
    ) && !matches!(
        job.plan.law,
        DepthLaw::Power { degression, min_step, .. } if degression == 1.0 && min_step == 0.0
    ) {
        return Err("G78 knows the √n law with a minimum cut and the constant step only".into());
    }
    let whole_angle = |half: f64| {
        let a = 2.0 * half;
        ((a - a.round()).abs() < 1e-9 && (0.0..=99.0).contains(&a.round()))
            .then(|| a.round() as u32)
    };
    let flank = |angle_deg: f64| {
        whole_angle(angle_deg).ok_or_else(|| {
            format!(
                "G78 infeeds along a flank at half its tool angle a, a whole number 0 to 99, and this job at {}°",
                crate::post::number(angle_deg, 4, false)
            )
        })
    };
    let last_rough = job.plan.finish_allowance == 0.0 || job.finish_at == FinishPosition::LastRough;
    let choices = match job.infeed {
        Infeed::Radial => {
            let tool = job.tool_angle_deg;
            let named = (tool.fract() == 0.0 && (0.0..=99.0).contains(&tool)).then_some(tool as u32);
            let mut v: Vec<(u32, u32)> = named.into_iter().map(|a| (0, a)).collect();
            if named != Some(0) {
                v.push((0, 0));
            }
            v
        }
        _ if !last_rough => {
            return Err("G78 cuts its finishing passes at the last rough pass's Z, and this job on the groove's axis".into())
        }
        Infeed::Flank {
            flank: Flank::Left,
            angle_deg,
        } => vec![(1, flank(angle_deg)?)],
        Infeed::Flank {
            flank: Flank::Right,
            angle_deg,
        } => vec![(2, flank(angle_deg)?)],
        Infeed::Alternating {
            first: Flank::Right,
            second: Flank::Centre,
            angle_deg,
        } => vec![(3, flank(angle_deg)?)],
        Infeed::Alternating {
            first: Flank::Left,
            second: Flank::Right,
            angle_deg,
        } => vec![(4, flank(angle_deg)?)],
        _ => {
            return Err(
                "G78 infeeds along the centre line, one flank, right and centre or left and right alternately, and this job otherwise".into(),
            )
        }
    };
    Ok(choices)
}

/// The two blocks with infeed mode `r` and tool angle `a`.
fn g78_text(
    machine: &Machine,
    job: &Job,
    r: u32,
    a: u32,
) -> std::result::Result<Vec<String>, String> {
    let g = &job.geometry;
    let (first, depth_mode, min_cut) = match job.plan.law {
        DepthLaw::Power {
            first,
            degression: 2.0,
            min_step,
        } => (first, 1, min_step),
        DepthLaw::Power { first, .. } => (first, 0, 0.0),
        _ => {
            return Err("G78 knows the √n law with a minimum cut and the constant step only".into())
        }
    };
    let lead_in = match job.entry {
        Entry::Direct => None,
        Entry::Ramp {
            outward,
            before: 0.0,
        } => Some(outward),
        Entry::Ramp { .. } => return Err("G78's lead-in E is a radial screw-in".into()),
    };
    let tail = match job.exit {
        Exit::Straight => (0.0, 0.0),
        Exit::PullOut {
            start_before,
            length,
            outward,
        } if start_before == length => (outward, length),
        Exit::PullOut { .. } | Exit::ToRetract { .. } => {
            return Err("G78's tail-out ends at the thread's end".into())
        }
        Exit::FeedOut { .. } => return Err("G78's tail-out is a threaded move".into()),
    };
    let u = job.units;
    let nd = machine.decimals(u);
    let num = |mm: f64| crate::post::number(u.from_mm(mm), nd, false);
    let lead = crate::post::number(
        u.from_mm(job.lead.lead),
        if u == Units::Inch { 5 } else { 4 },
        false,
    );
    let root_end = g.crest_end.plus(g.side.infeed().scale(g.depth));
    let x_end = if machine.diameter_x {
        root_end.x * 2.0
    } else {
        root_end.x
    };
    let mut first_block = format!(
        "G78 P{:02}{r:02}{a:02} Q{} R{} D{depth_mode}",
        job.plan.finish_passes,
        num(min_cut),
        num(job.plan.finish_allowance)
    );
    if job.lead.starts > 1 {
        first_block.push_str(&format!(" L{}", job.lead.starts));
    }
    if let Some(e) = lead_in {
        first_block.push_str(&format!(" E{}", num(e)));
    }
    let mut second = format!(
        "G78 X{} Z{}",
        crate::post::number(u.from_mm(x_end), nd, false),
        num(root_end.z)
    );
    if g.taper() != 0.0 {
        second.push_str(&format!(" R{}", num(g.taper())));
    }
    second.push_str(&format!(
        " P{} Q{} J{} K{} F{lead}",
        num(g.depth),
        num(first),
        num(tail.0),
        num(tail.1)
    ));
    Ok(vec![first_block, second])
}

/// P(m)(r)(a): three two-digit fields (§2, the example's `P020545`). Leading zeros may be omitted.
fn unpack_p(line: &Line, p: &Word) -> Result<(u32, u8, u8)> {
    let packed = super::packed_p(
        line,
        p,
        "G78",
        "P020060 is 2 finishing passes, infeed mode 0, a 60° tool",
    )?;
    let [m, r, a] = packed.fields;
    if !(1..=99).contains(&m) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            packed.span(0),
            format!("P(m)={m:02}: the number of finishing passes must be 01 to 99"),
        ));
    }
    if r > 4 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            packed.span(1),
            format!("P(r)={r:02}: the infeed mode must be 0 to 4 (0 centre line, 1 left flank, 2 right flank, 3 right/centre, 4 left/right)"),
        )
        .with_hint("the seed's own example writes P020545; threadcut refuses r = 05 rather than guess (docs/dialects/gsk-g78.md)"));
    }
    Ok((m, r as u8, a as u8))
}

fn small_integer(w: &Word, name: &str, lo: u32, hi: u32) -> Result<u32> {
    if w.value.fract() != 0.0 || w.value < f64::from(lo) || w.value > f64::from(hi) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            w.span,
            format!(
                "{name}={} is out of range: allowed {lo} to {hi}, a whole number",
                w.value
            ),
        ));
    }
    Ok(w.value as u32)
}

fn alarm_missing(span: Span, word: &str, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("G78 alarm: {word} is missing; it gives {what}"),
    )
    .with_hint(format!(
        "{word} has no default: the controller raises an alarm without it (§3)"
    ))
}

fn out_of_range(
    span: Span,
    name: &str,
    v: f64,
    lo: f64,
    hi: f64,
    units: Units,
    system: IncrementSystem,
) -> Diagnostic {
    let system = match system {
        IncrementSystem::Isb => "ISB",
        IncrementSystem::Isc => "ISC",
    };
    Diagnostic::error(
        Code::OutOfRange,
        span,
        format!(
            "{name}={v} is out of range: G78 allows {lo} to {hi} ({system}, {})",
            units.name()
        ),
    )
}
