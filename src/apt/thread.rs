//! THREAD/ON … THREAD/OFF (seed 000): its parameters, their checks, and the lowering into the
//! shared [`Job`]. Every decision on an ambiguity of the seed is a row of
//! `docs/dialects/apt-thread.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, Side,
};
use crate::units::{Pos, Units, Vec2};

use super::reader::{Arg, Statement};

/// "A total of 200 cuts may be programmed per thread cycle."
pub const MAX_CUTS: u32 = 200;

/// DEPTH verifies `c·s + finish` to within half a unit of the fourth decimal (CL units): CL files
/// print four or more decimals, so a rounding of the printed values never fails the check.
pub const VERIFY_TOLERANCE: f64 = 0.5e-4;

/// Leads beyond this (mm per revolution) are refused as typing errors.
pub const MAX_LEAD_MM: f64 = 1000.0;

/// The default tool nose angle (TLANGL).
pub const DEFAULT_TOOL_ANGLE: f64 = 60.0;

/// A lead and its starts, in millimetres, as PITCH or THREAD/ON set them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pitch {
    /// Lead per spindle revolution (mm).
    pub lead: f64,
    pub starts: u32,
    /// Change of lead per revolution (mm), signed: INCR positive, DECR negative.
    pub dlead: f64,
}

/// A value with the span of the keyword that introduced it.
#[derive(Clone, Copy, Debug)]
pub struct At<T> {
    pub value: T,
    pub span: Span,
}

/// The CUTS specification: a count, or `n,step` couplets.
#[derive(Clone, Debug)]
pub struct Cuts {
    pub span: Span,
    pub count: u32,
    /// `(n, step)` in CL units; empty when only the count was given.
    pub couplets: Vec<(u32, f64)>,
}

/// The parameters of THREAD/ON, as written (CL units, degrees).
#[derive(Clone, Debug, Default)]
pub struct ThreadOn {
    pub span: Span,
    pub line: u32,
    pub depth: Option<At<f64>>,
    pub cuts: Option<Cuts>,
    pub step: Option<At<f64>>,
    pub fincut: Option<At<(u32, f64)>>,
    pub cutang: Option<At<f64>>,
    pub tlangl: Option<At<f64>>,
    pub option: Option<At<u8>>,
    pub atangl: Option<At<(f64, Option<f64>)>>,
    pub chamfr: Option<At<(f64, Option<f64>)>>,
    pub ret: Option<At<Option<f64>>>,
    pub pitch: PitchWords,
}

/// The pitch words shared by PITCH and THREAD/ON.
#[derive(Clone, Copy, Debug, Default)]
pub struct PitchWords {
    /// Lead in mm and the span of its word.
    pub lead: Option<At<f64>>,
    pub starts: Option<At<u32>>,
    /// Signed change of lead per revolution, mm.
    pub dlead: Option<At<f64>>,
}

impl PitchWords {
    /// Applies these words over `base` (the modal PITCH), or fails when no lead is known.
    pub fn over(&self, base: Option<Pitch>, span: Span) -> Result<Pitch> {
        let lead = match (self.lead, base) {
            (Some(l), _) => l.value,
            (None, Some(b)) => b.lead,
            (None, None) => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    "no pitch is known: the thread needs a PITCH statement before it or TPI/IPR/MMPR/PERREV on THREAD/ON",
                ))
            }
        };
        if !(lead.is_finite() && lead <= MAX_LEAD_MM) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                self.lead.map_or(span, |l| l.span),
                format!("a lead of {lead} mm per revolution is beyond {MAX_LEAD_MM} mm"),
            ));
        }
        Ok(Pitch {
            lead,
            starts: self
                .starts
                .map(|s| s.value)
                .or(base.map(|b| b.starts))
                .unwrap_or(1),
            dlead: self
                .dlead
                .map(|d| d.value)
                .or(base.map(|b| b.dlead))
                .unwrap_or(0.0),
        })
    }
}

/// Reads the arguments as a sequence of keywords with their numbers.
pub struct Args<'a> {
    args: &'a [Arg],
    i: usize,
}

impl<'a> Args<'a> {
    pub fn new(args: &'a [Arg]) -> Args<'a> {
        Args { args, i: 0 }
    }

    pub fn take(&mut self) -> Option<&'a Arg> {
        let a = self.args.get(self.i);
        self.i += a.is_some() as usize;
        a
    }

    pub fn peek(&self) -> Option<&'a Arg> {
        self.args.get(self.i)
    }

    /// The next argument, which must be a number.
    pub fn number(&mut self, after: &Arg, what: &str) -> Result<f64> {
        match self.peek().and_then(Arg::number) {
            Some(v) => {
                self.i += 1;
                Ok(v)
            }
            None => Err(Diagnostic::error(
                Code::MissingWord,
                self.peek().map_or(after.span, |a| a.span),
                format!(
                    "{} needs {what} here",
                    after.word().unwrap_or("the keyword")
                ),
            )),
        }
    }

    /// The next argument if it is a number.
    pub fn optional(&mut self) -> Option<f64> {
        let v = self.peek().and_then(Arg::number)?;
        self.i += 1;
        Some(v)
    }
}

fn whole(v: f64, span: Span, what: &str, lo: u32, hi: u32) -> Result<u32> {
    if v.fract() != 0.0 || v < f64::from(lo) || v > f64::from(hi) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            format!("{what} {v} is out of range: a whole number {lo} to {hi} is expected"),
        ));
    }
    Ok(v as u32)
}

fn positive(v: f64, span: Span, what: &str) -> Result<f64> {
    if v <= 0.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            format!("{what} {v} must be a positive number"),
        ));
    }
    Ok(v)
}

fn duplicate(span: Span, word: &str) -> Diagnostic {
    Diagnostic::error(
        Code::Conflict,
        span,
        format!("{word} is given twice in one statement"),
    )
}

/// Reads one pitch word (`TPI`, `IPR`, `MMPR`, `PERREV`, `MULTRD`, `INCR`, `DECR`) and its value.
/// Returns false when `key` is not one of them.
pub fn pitch_word(
    key: &Arg,
    word: &str,
    args: &mut Args,
    units: Units,
    into: &mut PitchWords,
) -> Result<bool> {
    let span = key.span;
    match word {
        "TPI" | "IPR" | "MMPR" | "PERREV" => {
            if into.lead.is_some() {
                return Err(duplicate(span, "the pitch"));
            }
            let v = positive(args.number(key, "the pitch")?, span, word)?;
            let lead = match word {
                "TPI" => crate::units::lead_from_tpi(v),
                "IPR" => Units::Inch.to_mm(v),
                "MMPR" => v,
                _ => units.to_mm(v),
            };
            into.lead = Some(At { value: lead, span });
        }
        "MULTRD" => {
            if into.starts.is_some() {
                return Err(duplicate(span, "MULTRD"));
            }
            let v = args.number(key, "the number of starts")?;
            let n = whole(v, span, "MULTRD", 1, 999)?;
            into.starts = Some(At { value: n, span });
        }
        "INCR" | "DECR" => {
            if into.dlead.is_some() {
                return Err(duplicate(span, "INCR/DECR"));
            }
            let v = args.number(key, "the change of lead per revolution")?;
            if v < 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    span,
                    format!(
                        "{word} {v}: the change of lead is written positive; DECR makes it shrink"
                    ),
                ));
            }
            let sign = if word == "INCR" { 1.0 } else { -1.0 };
            into.dlead = Some(At {
                value: sign * units.to_mm(v),
                span,
            });
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// Parses `THREAD/ON, …`.
pub fn parse_on(st: &Statement, units: Units) -> Result<ThreadOn> {
    let mut t = ThreadOn {
        span: st.major_span,
        line: st.line,
        ..ThreadOn::default()
    };
    let mut args = Args::new(&st.args);
    args.take(); // ON, checked by the caller
    while let Some(key) = args.take() {
        let word = keyword(key)?;
        if !on_word(key, word, &mut args, &mut t)?
            && !pitch_word(key, word, &mut args, units, &mut t.pitch)?
        {
            return Err(Diagnostic::error(
                Code::Unsupported,
                key.span,
                format!("{word} is not a THREAD/ON parameter"),
            )
            .with_hint("the parameters are DEPTH CUTS STEP FINCUT CUTANG TLANGL OPTION ATANGL CHAMFR RETURN TPI IPR MMPR PERREV MULTRD INCR DECR"));
        }
    }
    Ok(t)
}

/// The keyword a THREAD/ON parameter starts with; a number in its place is a syntax error.
fn keyword(key: &Arg) -> Result<&str> {
    key.word().ok_or_else(|| {
        Diagnostic::error(
            Code::Syntax,
            key.span,
            format!(
                "a THREAD/ON parameter keyword is expected here, not the number {}",
                key.number().unwrap_or_default()
            ),
        )
    })
}

/// Sets a parameter read once, or refuses it when the statement gives it twice.
fn once<T>(field: &mut Option<At<T>>, value: T, span: Span, word: &str) -> Result<()> {
    if field.is_some() {
        return Err(duplicate(span, word));
    }
    *field = Some(At { value, span });
    Ok(())
}

/// Reads one THREAD/ON parameter other than the pitch words into `t`, its values checked.
/// Returns false when `word` is not one of them.
fn on_word(key: &Arg, word: &str, args: &mut Args, t: &mut ThreadOn) -> Result<bool> {
    let span = key.span;
    match word {
        "ON" => return Err(duplicate(span, "ON")),
        "DEPTH" => {
            let d = positive(args.number(key, "the thread depth")?, span, "DEPTH")?;
            once(&mut t.depth, d, span, word)?
        }
        "CUTS" => {
            if t.cuts.is_some() {
                return Err(duplicate(span, word));
            }
            t.cuts = Some(cuts(key, args)?);
        }
        "STEP" => {
            let s = positive(args.number(key, "the in-feed of a pass")?, span, "STEP")?;
            once(&mut t.step, s, span, word)?
        }
        "FINCUT" => once(&mut t.fincut, fincut(key, args)?, span, word)?,
        "CUTANG" => once(&mut t.cutang, cutang(key, args)?, span, word)?,
        "TLANGL" => once(&mut t.tlangl, tlangl(key, args)?, span, word)?,
        "OPTION" => {
            let n = args.number(key, "the in-feed pattern 0 to 4")?;
            let n = whole(n, span, "OPTION", 0, 4)? as u8;
            once(&mut t.option, n, span, word)?
        }
        "ATANGL" => once(&mut t.atangl, atangl(key, args)?, span, word)?,
        "CHAMFR" => once(&mut t.chamfr, chamfr(key, args)?, span, word)?,
        "RETURN" => once(&mut t.ret, return_height(key, args)?, span, word)?,
        _ => return Ok(false),
    }
    Ok(true)
}

/// CUTS: the count of rough cuts, or `n,step` couplets that must come in whole pairs.
fn cuts(key: &Arg, args: &mut Args) -> Result<Cuts> {
    let span = key.span;
    let mut numbers = Vec::new();
    numbers.push((args.number(key, "the number of cuts")?, span));
    while let Some(a) = args.peek().filter(|a| a.number().is_some()) {
        numbers.push((a.number().unwrap_or_default(), a.span));
        args.take();
    }
    let count = whole(numbers[0].0, numbers[0].1, "CUTS", 1, u32::MAX)?;
    let mut couplets = Vec::new();
    if numbers.len() > 1 {
        if numbers.len() % 2 == 1 {
            let last = numbers[numbers.len() - 1].1;
            return Err(Diagnostic::error(
                Code::Syntax,
                last,
                "CUTS couplets come as n,step pairs: this count has no step",
            ));
        }
        for pair in numbers.chunks(2) {
            let n = whole(pair[0].0, pair[0].1, "CUTS count", 1, u32::MAX)?;
            let s = positive(pair[1].0, pair[1].1, "the CUTS step")?;
            couplets.push((n, s));
        }
    }
    Ok(Cuts {
        span,
        count,
        couplets,
    })
}

/// FINCUT: the number of finish cuts (0 to the cut limit) and a non-negative allowance.
fn fincut(key: &Arg, args: &mut Args) -> Result<(u32, f64)> {
    let span = key.span;
    let c = args.number(key, "the number of finish cuts")?;
    let c = whole(c, span, "FINCUT count", 0, MAX_CUTS)?;
    let d = args.optional().unwrap_or(0.0);
    if d < 0.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            format!("FINCUT allowance {d} must not be negative"),
        ));
    }
    Ok((c, d))
}

/// CUTANG: the plunge angle, within a full turn either way.
fn cutang(key: &Arg, args: &mut Args) -> Result<f64> {
    let a = args.number(key, "the plunge angle")?;
    if !(-360.0..=360.0).contains(&a) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            key.span,
            format!("CUTANG {a} is out of range: -360 to 360 degrees"),
        ));
    }
    Ok(a)
}

/// TLANGL: the tool nose angle, strictly between 0 and 180 degrees.
fn tlangl(key: &Arg, args: &mut Args) -> Result<f64> {
    let a = args.number(key, "the tool nose angle")?;
    if !(a > 0.0 && a < 180.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            key.span,
            format!("TLANGL {a} is out of range: more than 0 and less than 180 degrees"),
        ));
    }
    Ok(a)
}

/// ATANGL: the pull-out angle (-80 to 80 degrees) and an optional non-negative height.
fn atangl(key: &Arg, args: &mut Args) -> Result<(f64, Option<f64>)> {
    let span = key.span;
    let a = args.number(key, "the pull-out angle")?;
    if !(-80.0..=80.0).contains(&a) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            format!("ATANGL {a} is out of range: -80 to 80 degrees"),
        ));
    }
    let h = args.optional();
    if let Some(h) = h.filter(|h| *h < 0.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            format!("the ATANGL height {h} must not be negative"),
        ));
    }
    Ok((a, h))
}

/// CHAMFR: the chamfer length and an optional angle of 10 to 80 degrees (`0,0` switches it off).
fn chamfr(key: &Arg, args: &mut Args) -> Result<(f64, Option<f64>)> {
    let l = args.number(key, "the chamfer length")?;
    let a = args.optional();
    if let Some(a) = a {
        let off = l == 0.0 && a == 0.0;
        if !off && !(10.0..=80.0).contains(&a) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                key.span,
                format!("the CHAMFR angle {a} is out of range: 10 to 80 degrees"),
            ));
        }
    }
    Ok((l, a))
}

/// RETURN: an optional non-negative height to retract to between passes.
fn return_height(key: &Arg, args: &mut Args) -> Result<Option<f64>> {
    let h = args.optional();
    if let Some(h) = h.filter(|h| *h < 0.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            key.span,
            format!("the RETURN height {h} must not be negative"),
        ));
    }
    Ok(h)
}

/// The rough depths (cumulative, perpendicular, CL units), the total depth and the finish plan.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthPlan {
    pub rough: Vec<f64>,
    /// The same rough depths as a power law `d_n = first·n^(1/degression)` when they are one
    /// (constant steps, constant depth, constant cross-section): native cycles can express those.
    pub power: Option<(f64, f64)>,
    /// The depth the finish passes reach (the thread's depth as cut).
    pub total: f64,
    pub finish_allowance: f64,
    pub finish_passes: u32,
}

/// The seed's table of permitted DEPTH / CUTS / STEP combinations, with FINCUT.
pub fn depth_plan(t: &ThreadOn) -> Result<DepthPlan> {
    let (finish_passes, dist) = t.fincut.map_or((0, 0.0), |f| f.value);
    let option = t.option.map_or(0, |o| o.value);
    let fincut_span = t.fincut.map_or(t.span, |f| f.span);
    let explicit: Option<Vec<(u32, f64)>> = match (&t.cuts, t.step) {
        (Some(c), Some(s)) if !c.couplets.is_empty() => {
            return Err(Diagnostic::error(
                Code::Conflict,
                s.span,
                "STEP conflicts with the n,step couplets of CUTS",
            ))
        }
        // [DEPTH,d,] CUTS,c,STEP,s — constant step.
        (Some(c), Some(s)) => Some(vec![(c.count, s.value)]),
        // [DEPTH,d,] CUTS,c,s[,n,s…]
        (Some(c), None) if !c.couplets.is_empty() => Some(c.couplets.clone()),
        _ => None,
    };
    let mut power = None;
    let (rough, total) = if let Some(couplets) = explicit {
        if let [(_, s)] = couplets[..] {
            power = Some((s, 1.0));
        }
        let span = t.cuts.as_ref().map_or(t.span, |c| c.span);
        let n: u64 = couplets.iter().map(|&(n, _)| u64::from(n)).sum();
        count_check(n + u64::from(finish_passes), span)?;
        let mut rough = Vec::with_capacity(n as usize);
        let mut d = 0.0;
        for &(n, s) in &couplets {
            for _ in 0..n {
                d += s;
                rough.push(d);
            }
        }
        let total = d + dist;
        if let Some(depth) = t.depth {
            if (depth.value - total).abs() > VERIFY_TOLERANCE {
                return Err(Diagnostic::error(
                    Code::Conflict,
                    depth.span,
                    format!(
                        "DEPTH {} does not match the cuts: c·s + finish = {} + {} = {}",
                        depth.value,
                        fmt(d),
                        fmt(dist),
                        fmt(total)
                    ),
                )
                .with_hint("with stepping values DEPTH only verifies them: correct DEPTH, the steps or the FINCUT allowance"));
            }
        }
        (rough, total)
    } else {
        match (&t.cuts, t.step, t.depth) {
            (_, Some(s), None) => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    s.span,
                    "STEP needs DEPTH,depth or CUTS,n",
                ))
            }
            (Some(c), None, None) if c.count == 1 => {
                // CUTS,1: a single pass at the thread contour.
                if dist > 0.0 {
                    return Err(Diagnostic::error(
                        Code::Conflict,
                        fincut_span,
                        "CUTS,1 without DEPTH cuts at the contour: there is no depth for a finish allowance",
                    ));
                }
                count_check(1 + u64::from(finish_passes), c.span)?;
                (vec![0.0], 0.0)
            }
            (Some(c), None, None) => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    c.span,
                    format!("CUTS,{} gives no steps: DEPTH must be specified", c.count),
                ))
            }
            (None, None, None) => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    t.span,
                    "THREAD/ON needs the thread depth: DEPTH, CUTS or both",
                ))
            }
            (cuts, step, Some(depth)) => {
                let d = depth.value;
                if dist >= d {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        fincut_span,
                        format!("the FINCUT allowance {dist} is not smaller than DEPTH {d}"),
                    ));
                }
                let rough_to = d - dist;
                let rough = match (cuts, step) {
                    (Some(c), _) => {
                        count_check(u64::from(c.count) + u64::from(finish_passes), c.span)?;
                        let cf = f64::from(c.count);
                        power = match option {
                            0 => None,
                            1 | 2 => Some((rough_to / cf.sqrt(), 2.0)),
                            _ => Some((rough_to / cf, 1.0)),
                        };
                        by_count(option, c.count, rough_to)
                    }
                    (None, Some(s)) => {
                        power = match option {
                            0 => None,
                            1 | 2 => Some((s.value, 2.0)),
                            _ => Some((s.value, 1.0)),
                        };
                        by_first_step(option, s.value, rough_to, finish_passes, s.span)?
                    }
                    (None, None) => {
                        power = Some((rough_to, 1.0));
                        vec![rough_to]
                    }
                };
                (rough, d)
            }
        }
    };
    if dist > 0.0 && dist >= total {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            fincut_span,
            format!("the FINCUT allowance {dist} is not smaller than the depth {total}"),
        ));
    }
    // FINCUT,0,dist: "will cut the thread to depth-dist".
    let (total, finish_allowance) = if finish_passes == 0 {
        (total - dist, 0.0)
    } else {
        (total, dist)
    };
    Ok(DepthPlan {
        rough,
        power,
        total,
        finish_allowance,
        finish_passes,
    })
}

fn fmt(v: f64) -> String {
    crate::post::number(v, 6, false)
}

fn count_check(n: u64, span: Span) -> Result<()> {
    if n > u64::from(MAX_CUTS) {
        return Err(Diagnostic::error(
            Code::TooManyPasses,
            span,
            format!("{n} cuts are programmed: at most {MAX_CUTS} cuts per thread cycle (finish cuts included)"),
        ));
    }
    Ok(())
}

/// `c` cuts over `depth` by the OPTION law.
fn by_count(option: u8, c: u32, depth: f64) -> Vec<f64> {
    let cf = f64::from(c);
    (1..=c)
        .map(|n| {
            let n = f64::from(n);
            if n == cf {
                return depth;
            }
            match option {
                // Steps c, c−1, …, 1 (× 2·depth/(c(c+1))): decremented by a constant amount.
                0 => depth * n * (2.0 * cf - n + 1.0) / (cf * (cf + 1.0)),
                // Constant cross-section: d_n = D·√(n/c).
                1 | 2 => depth * (n / cf).sqrt(),
                // Constant depth: d_n = D·n/c.
                _ => depth * n / cf,
            }
        })
        .collect()
}

/// First step `s`, then the OPTION law, until `depth` (the last pass clipped to it).
fn by_first_step(option: u8, s: f64, depth: f64, finish: u32, span: Span) -> Result<Vec<f64>> {
    // Option 0: N = ⌈2D/s − 1⌉ steps s, s − s/N, …: their sum s(N+1)/2 reaches D.
    let n_zero = ((2.0 * depth / s - 1.0) - 1e-9).ceil().max(1.0);
    let mut out = Vec::new();
    for n in 1..=u64::from(MAX_CUTS) + 1 {
        if n as usize + finish as usize > MAX_CUTS as usize {
            return Err(Diagnostic::error(
                Code::TooManyPasses,
                span,
                format!("STEP {s} over the depth {depth} needs more than {MAX_CUTS} cuts per thread cycle (finish cuts included)"),
            ));
        }
        let k = n as f64;
        let d = match option {
            0 => s * k - s / n_zero * k * (k - 1.0) / 2.0,
            1 | 2 => s * k.sqrt(),
            _ => s * k,
        };
        if d >= depth - 1e-9 * depth.max(1.0) || (option == 0 && k >= n_zero) {
            out.push(depth);
            return Ok(out);
        }
        out.push(d);
    }
    Ok(out) // not reached: the count check above ends the loop
}

/// The contour: the GOTOs between THREAD/ON and THREAD/OFF, in mm.
pub struct Contour {
    pub initial: Pos,
    pub start: At<Pos>,
    pub end: At<Pos>,
    pub chamfer: Option<At<Pos>>,
}

/// Lowers a THREAD/ON … THREAD/OFF block into the shared model.
pub fn lower(t: &ThreadOn, c: &Contour, pitch: Pitch, units: Units, off: Span) -> Result<Job> {
    let l = Lowering::new(t, c, pitch, units)?;
    let plunge = l.plunge()?;
    let side = plunge.side;
    let tool_angle = t.tlangl.map_or(DEFAULT_TOOL_ANGLE, |a| a.value);
    let long = side.along(l.travel);
    let infeed = l.infeed(&plunge, tool_angle / 2.0, long)?;
    let plan = depth_plan(t)?;
    // Depth is the perpendicular distance from the thread line reached along the plunge line; the
    // model measures depth along the depth axis: D = d·cos φ / sin(angle(u, line)).
    let scale = plunge.along_n / plunge.cross;
    let mm = |v: f64| units.to_mm(v) * scale;
    l.check_initial_clear(side)?;
    l.check_starts()?;
    let thread_pitch = pitch.lead / f64::from(pitch.starts.max(1));
    let full_height = thread_pitch / (2.0 * tan_deg(30.0));
    let exit = exit(t, c, side, l.travel, full_height, units)?;
    l.check_exit(exit, long, thread_pitch)?;
    let level = l.return_level(side, full_height)?;
    let first = plan.rough.first().map_or(0.0, |&d| mm(d));
    let level = l.exit_level(level, side, exit, first);
    Ok(Job {
        line: off.line,
        span: t.span,
        controller: "apt",
        units,
        start: c.initial,
        geometry: Geometry {
            crest_start: c.start.value,
            crest_end: c.end.value,
            depth: mm(plan.total),
            side,
        },
        lead: Lead {
            dlead: pitch.dlead,
            starts: pitch.starts,
            ..Lead::constant(pitch.lead)
        },
        plan: pass_plan(&plan, mm),
        infeed,
        // Finish passes go straight to full depth from the last rough pass: they clean both flanks.
        finish_at: FinishPosition::LastRough,
        tool_angle_deg: tool_angle,
        entry: Entry::Direct,
        exit,
        retract: l.retract(side, level),
        return_path: crate::thread::ReturnPath::Box,
    })
}

/// A contour that cannot be threaded as programmed.
fn geometry_error(span: Span, msg: String) -> Diagnostic {
    Diagnostic::error(Code::Geometry, span, msg)
}

/// A THREAD/ON block and its contour, as the steps of the lowering share them (mm).
struct Lowering<'a> {
    t: &'a ThreadOn,
    c: &'a Contour,
    pitch: Pitch,
    units: Units,
    /// From the thread start to its end.
    travel: Vec2,
    /// The contour's long axis is X.
    face: bool,
}

/// The plunge line (CUTANG) and what it decides about the thread.
struct Plunge {
    /// Degrees from +X toward +Z.
    angle: f64,
    side: Side,
    /// The plunge direction across the in-feed (u·l) and along it (u·n = cos φ > 0).
    lateral: f64,
    along_n: f64,
    /// The sine of the angle between the plunge line and the thread line.
    cross: f64,
}

impl<'a> Lowering<'a> {
    /// Decides turn or face from the contour; a thread without length is refused.
    fn new(t: &'a ThreadOn, c: &'a Contour, pitch: Pitch, units: Units) -> Result<Lowering<'a>> {
        let travel = c.end.value.minus(c.start.value);
        if travel.length() == 0.0 {
            return Err(geometry_error(
                c.end.span,
                "the thread end point equals its start point".into(),
            ));
        }
        Ok(Lowering {
            t,
            c,
            pitch,
            units,
            travel,
            // The contour decides turn (long axis Z) or face (long axis X); 45° counts as turn.
            face: travel.x.abs() > travel.z.abs(),
        })
    }

    /// CUTANG: the plunge direction, measured from +X toward +Z in the CL XZ plane. Without it,
    /// straight in from the initial point's side of the thread start.
    fn plunge_angle(&self) -> Result<(f64, Span)> {
        let (t, face) = (self.t, self.face);
        if let Some(a) = t.cutang {
            return Ok((a.value, a.span));
        }
        let (p0, s) = (self.c.initial, self.c.start.value);
        let toward = if face { s.z - p0.z } else { s.x - p0.x };
        if toward == 0.0 {
            return Err(Diagnostic::error(
                Code::Geometry,
                t.span,
                format!(
                    "the initial point lies on the thread start's {} level: the default CUTANG cannot tell the in-feed direction",
                    if face { "Z" } else { "X" }
                ),
            )
            .with_hint("start from a point clear of the thread, or give CUTANG"));
        }
        let a = match (face, toward < 0.0) {
            (false, true) => 180.0,
            (false, false) => 0.0,
            (true, true) => 270.0,
            (true, false) => 90.0,
        };
        Ok((a, t.span))
    }

    /// The plunge line and the side of the thread it cuts: it must lie more than 10° off the
    /// thread line and move along the depth axis.
    fn plunge(&self) -> Result<Plunge> {
        let (angle, angle_span) = self.plunge_angle()?;
        let face = self.face;
        let u = Vec2::new(angle.to_radians().cos(), angle.to_radians().sin());
        let line = self.travel.scale(1.0 / self.travel.length());
        let cross = (u.x * line.z - u.z * line.x).abs();
        if cross <= 10f64.to_radians().sin() + 1e-12 {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                angle_span,
                format!(
                    "CUTANG {angle} lies within 10° of the line through the thread start and end points: the thread cycle aborts"
                ),
            )
            .with_hint("the plunge line must be more than 10° off the thread line"));
        }
        let depth_component = if face { u.z } else { u.x };
        if depth_component.abs() < 1e-12 {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                angle_span,
                format!(
                    "CUTANG {angle} runs along {}: a {} thread's in-feed must move along {}",
                    if face { "X" } else { "Z" },
                    if face { "face" } else { "turn" },
                    if face { "Z" } else { "X" }
                ),
            ));
        }
        let side = match (face, depth_component < 0.0) {
            (false, true) => Side::External,
            (false, false) => Side::Internal,
            (true, true) => Side::FaceFront,
            (true, false) => Side::FaceBack,
        };
        let n = side.infeed();
        let l = side.lateral();
        Ok(Plunge {
            angle,
            side,
            lateral: u.x * l.x + u.z * l.z,
            along_n: u.x * n.x + u.z * n.z,
            cross,
        })
    }

    /// The in-feed by OPTION: an oblique plunge line allows OPTION 0 only (along the line);
    /// otherwise radial, down one flank, or alternating, with flank offsets toward the start.
    fn infeed(&self, p: &Plunge, half: f64, long: f64) -> Result<Infeed> {
        let t = self.t;
        let option = t.option.map_or(0, |o| o.value);
        // Flank offsets point back toward the start, so that no pass runs past the programmed end.
        let back = if long > 0.0 {
            Flank::Right
        } else {
            Flank::Left
        };
        let oblique = p.lateral.abs() > 1e-12;
        Ok(match option {
            0 if !oblique => Infeed::Radial,
            0 => Infeed::Flank {
                flank: if p.lateral > 0.0 {
                    Flank::Left
                } else {
                    Flank::Right
                },
                angle_deg: (p.lateral.abs() / p.along_n).atan().to_degrees(),
            },
            _ if oblique => {
                return Err(Diagnostic::error(
                    Code::Conflict,
                    t.option.map_or(t.span, |o| o.span),
                    format!(
                        "OPTION {option} works when CUTANG is parallel to a major datum; CUTANG {} is not",
                        p.angle
                    ),
                )
                .with_hint("use OPTION 0 for an oblique plunge line, or a CUTANG divisible by 90°"))
            }
            1 | 3 => Infeed::Flank {
                flank: back,
                angle_deg: half,
            },
            _ => Infeed::Alternating {
                first: Flank::Centre,
                second: back,
                angle_deg: half,
            },
        })
    }

    /// The initial point must lie clear of the crest, or the return between passes cuts the part.
    fn check_initial_clear(&self, side: Side) -> Result<()> {
        let (p0, s) = (self.c.initial, self.c.start.value);
        let outward = side.outward();
        let clear = |p: Pos| p.minus(s).x * outward.x + p.minus(s).z * outward.z;
        if clear(p0) < 0.0 {
            return Err(geometry_error(
                self.t.span,
                "the initial point lies on the in-feed side of the thread start: the return between passes would cut through the thread".into(),
            )
            .with_hint("position the tool clear of the thread before THREAD/ON"));
        }
        Ok(())
    }

    /// A variable lead and several starts exclude each other.
    fn check_starts(&self) -> Result<()> {
        let (t, pitch) = (self.t, self.pitch);
        if pitch.starts > 1 && pitch.dlead != 0.0 {
            return Err(Diagnostic::error(
                Code::Conflict,
                t.pitch
                    .starts
                    .map(|a| a.span)
                    .or(t.pitch.dlead.map(|a| a.span))
                    .unwrap_or(t.span),
                "a variable-lead thread (INCR/DECR) with several starts (MULTRD) is not supported: the starts would not be copies of one another shifted along the axis",
            ));
        }
        Ok(())
    }

    /// The chamfer must start within the thread, and a shrinking lead (DECR) must stay positive
    /// to the end of the pull-out.
    fn check_exit(&self, exit: Exit, long: f64, thread_pitch: f64) -> Result<()> {
        let (t, pitch) = (self.t, self.pitch);
        if let Exit::PullOut { start_before, .. } | Exit::FeedOut { start_before, .. } = exit {
            if start_before >= long.abs() {
                return Err(geometry_error(
                    t.chamfr.map_or(t.span, |c| c.span),
                    "the chamfer starts before the thread start".into(),
                ));
            }
        }
        // Variable lead: the lead must stay positive to the end of the thread.
        if pitch.dlead < 0.0 {
            let extra = match exit {
                Exit::PullOut { length, .. } => length.max(0.0),
                _ => 0.0,
            };
            let reach = long.abs() + extra + thread_pitch;
            if pitch.lead * pitch.lead + 2.0 * pitch.dlead * reach <= 0.0 {
                return Err(geometry_error(
                    t.pitch.dlead.map_or(t.span, |d| d.span),
                    format!(
                        "DECR {} brings the lead to zero before the thread's end ({} mm)",
                        self.units.from_mm(-pitch.dlead),
                        reach
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The level the tool retracts to between passes, along the depth axis (outward positive):
    /// RETURN's height over the crest, the initial point's level, or a full thread height.
    fn return_level(&self, side: Side, full_height: f64) -> Result<f64> {
        let (t, p0) = (self.t, self.c.initial);
        let outward = side.outward();
        let outermost = [self.c.start.value, self.c.end.value]
            .into_iter()
            .map(|p| p.x * outward.x + p.z * outward.z)
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(match t.ret {
            Some(At { value: None, .. }) => {
                // RETURN without a height: the initial point's X (turn) or Z (face).
                let lv = p0.x * outward.x + p0.z * outward.z;
                if lv < outermost {
                    return Err(geometry_error(
                        t.ret.map_or(t.span, |r| r.span),
                        "RETURN retracts to the initial point's level, which lies inside the thread"
                            .into(),
                    ));
                }
                lv
            }
            Some(At { value: Some(h), .. }) => outermost + self.units.to_mm(h),
            None => outermost + full_height,
        })
    }

    /// The retract never moves toward the part: it starts at least as high as the end of the
    /// shallowest pass's pull-out (`first`: that pass's depth, mm).
    fn exit_level(&self, level: f64, side: Side, exit: Exit, first: f64) -> f64 {
        let outward = side.outward();
        let crest_end = self.c.end.value;
        match exit {
            Exit::PullOut {
                start_before,
                length,
                outward: up,
            }
            | Exit::FeedOut {
                start_before,
                length,
                outward: up,
            } => {
                let long = side.along(self.travel);
                let along = self.travel.scale(1.0 / long.abs());
                let rise = along.x * outward.x + along.z * outward.z;
                let end = crest_end.x * outward.x
                    + crest_end.z * outward.z
                    + rise * (length - start_before)
                    + up
                    - first;
                level.max(end)
            }
            Exit::Straight | Exit::ToRetract { .. } => level,
        }
    }

    /// The retract point: the level on the depth axis, the thread start on the long axis.
    fn retract(&self, side: Side, level: f64) -> Retract {
        let outward = side.outward();
        let s = self.c.start.value;
        let signed_level = level * (outward.x + outward.z);
        if self.face {
            Retract {
                x: s.x,
                z: signed_level,
            }
        } else {
            Retract {
                x: signed_level,
                z: s.z,
            }
        }
    }
}

/// The pass plan in mm along the depth axis: a power law where the rough depths follow one,
/// otherwise the depths themselves.
fn pass_plan(plan: &DepthPlan, mm: impl Fn(f64) -> f64) -> PassPlan {
    PassPlan {
        law: match plan.power {
            Some((first, degression)) => DepthLaw::Power {
                first: mm(first),
                degression,
                min_step: 0.0,
            },
            None => DepthLaw::Explicit {
                depths: plan.rough.iter().map(|&d| mm(d)).collect(),
            },
        },
        finish_allowance: mm(plan.finish_allowance),
        finish_passes: plan.finish_passes,
    }
}

/// A pull-out that rises `up` while running `length` along the long axis (negative: back toward
/// the start) is threaded when its angle from the thread axis lies in 30–60°, otherwise linear.
fn pull_out(start_before: f64, length: f64, up: f64) -> Exit {
    let angle = up.atan2(length).to_degrees();
    if (30.0 - 1e-9..=60.0 + 1e-9).contains(&angle) {
        Exit::PullOut {
            start_before,
            length,
            outward: up,
        }
    } else {
        Exit::FeedOut {
            start_before,
            length,
            outward: up,
        }
    }
}

fn exit(
    t: &ThreadOn,
    c: &Contour,
    side: Side,
    travel: Vec2,
    full_height: f64,
    units: Units,
) -> Result<Exit> {
    let methods = [
        c.chamfer.map(|g| g.span),
        t.atangl.map(|a| a.span),
        t.chamfr.map(|a| a.span),
    ];
    let given: Vec<Span> = methods.iter().flatten().copied().collect();
    if given.len() > 1 {
        return Err(Diagnostic::error(
            Code::Conflict,
            given[1],
            "the chamfer is defined twice: use one of a third GOTO, ATANGL or CHAMFR",
        ));
    }
    let long = side.along(travel);
    let forward = long.signum();
    let outward = side.outward();
    if let Some(end) = c.chamfer {
        let delta = end.value.minus(c.end.value);
        let length = side.along(delta) * forward;
        let along = travel.scale(1.0 / long.abs());
        let rest = Vec2::new(delta.x - along.x * length, delta.z - along.z * length);
        let up = rest.x * outward.x + rest.z * outward.z;
        if up <= 0.0 {
            return Err(Diagnostic::error(
                Code::Geometry,
                end.span,
                "the end of chamfer does not lie above the thread end: the pull-out must move away from the part",
            ));
        }
        return Ok(pull_out(0.0, length, up));
    }
    if let Some(a) = t.atangl {
        let (angle, height) = a.value;
        let h = height.map_or(full_height, |h| units.to_mm(h));
        if h == 0.0 || (angle == 0.0 && height.is_none()) {
            // ATANGL,0 / ATANGL,0,0 / a zero height: the default pull-out (the retract).
            return Ok(Exit::Straight);
        }
        // The angle is measured off the depth axis (X for turning, Z for facing); positive leans
        // forward along the cut.
        return Ok(pull_out(0.0, h * tan_deg(angle), h));
    }
    if let Some(ch) = t.chamfr {
        let (length, angle) = ch.value;
        if length == 0.0 {
            return Ok(Exit::Straight);
        }
        let angle = angle.unwrap_or(45.0);
        let l = units.to_mm(length.abs());
        // The chamfer angle is measured from the thread axis.
        let up = l * tan_deg(angle);
        let start_before = if length < 0.0 { l } else { 0.0 };
        return Ok(pull_out(start_before, l, up));
    }
    Ok(Exit::Straight)
}
