//! A machining centre's modal state and one block executed on it: the codes read in the order
//! the controls execute them (units, plane, modes, feed, spindle, tool, compensation, length
//! offset, work system, then the non-modal codes and the motion).

use crate::diag::{Code, Diagnostic, Span};
use crate::dialect::mill::{Alarms, MillLanguage};
use crate::gcode::{Line, Word};
use crate::mill::motion::{Comp, Feed, MillKind, MillMotion, Plane, Rotation, State, TapCycle, P3};
use crate::mill::profile::{Axes, MillReference};
use crate::units::Units;

pub(crate) type Result<T> = std::result::Result<T, Diagnostic>;

/// Where a block's moves and tapping events go.
pub(crate) trait Out {
    fn motion(&mut self, m: &MillMotion, work: u16) -> Result<()>;
    fn tap(&mut self, t: &TapCycle) -> Result<()>;
}

/// The motion mode in force (group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Motion {
    Rapid,
    Feed,
    Arc {
        clockwise: bool,
    },
    /// A canned cycle, its code ×10.
    Cycle(u16),
    /// G80 (or a cycle cancelled): axis words alone do not move.
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FeedMode {
    PerMinute,
    PerRev,
    InverseTime,
}

/// The state of a machining centre as a program leaves it.
pub(crate) struct Mill {
    pub lang: MillLanguage,
    pub reference: MillReference,
    pub units: Units,
    pub absolute: bool,
    pub plane: Plane,
    pub centre_absolute: bool,
    pub feed_mode: FeedMode,
    /// The F register (program units).
    pub f: Option<f64>,
    pub rpm: Option<f64>,
    pub rotation: Rotation,
    pub tool: Option<u32>,
    /// The tool named by T, loaded by M6.
    pub next_tool: Option<u32>,
    pub length_offset: Option<u32>,
    pub comp: Comp,
    /// The work coordinate system (×10: G54 = 540, G54.1 P7 = 5417 … as `540 + 1`, `P` kept
    /// apart in `work_p`).
    pub work: u16,
    pub work_p: u32,
    /// G52's local shift and G92's (mm), added to every programmed absolute coordinate.
    pub local: [f64; 3],
    pub g92: [f64; 3],
    /// Where the programmed point is, axis by axis (mm, work coordinates, shifts included).
    pub pos: [Option<f64>; 3],
    pub motion: Motion,
    /// The last of G0, G1, G2, G3 (the Fanuc family's group 01, in force again after G80).
    pub group1: Motion,
    pub cycle: CycleModal,
    /// M29 given: the next tapping cycle is rigid.
    pub m29: bool,
    /// The program has ended (M2, M30).
    pub ended: bool,
}

/// A G code ×10, if the value is one (G54.1 = 541).
pub(crate) fn g10(v: f64) -> Option<u16> {
    let t = (v * 10.0).round();
    ((v * 10.0 - t).abs() < 1e-6 && (0.0..10_000.0).contains(&t)).then_some(t as u16)
}

/// How a G code ×10 is written.
pub(crate) fn g_name(code: u16) -> String {
    if code.is_multiple_of(10) {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

pub(crate) const AXES: [u8; 3] = [b'X', b'Y', b'Z'];

impl Mill {
    pub fn new(lang: MillLanguage, reference: MillReference, units: Units) -> Mill {
        Mill {
            lang,
            reference,
            units,
            absolute: true,
            plane: Plane::Xy,
            centre_absolute: false,
            feed_mode: FeedMode::PerMinute,
            f: None,
            rpm: None,
            rotation: Rotation::Stopped,
            tool: None,
            next_tool: None,
            length_offset: None,
            comp: Comp::Off,
            work: 540,
            work_p: 0,
            local: [0.0; 3],
            g92: [0.0; 3],
            pos: [None; 3],
            motion: Motion::Rapid,
            group1: Motion::Rapid,
            cycle: CycleModal::new(lang.cycles.initial_level_at_power_on),
            m29: false,
            ended: false,
        }
    }

    /// A word's value in program units (a number without a decimal point is a least increment
    /// where the control reads it so).
    pub fn value(&self, w: &Word) -> f64 {
        if w.has_dot || self.lang.calculator {
            w.value
        } else {
            w.value * self.increment(self.units)
        }
    }

    /// The least input increment (program units): IS-B.
    pub fn increment(&self, units: Units) -> f64 {
        match units {
            Units::Mm => 0.001,
            Units::Inch => 0.0001,
        }
    }

    /// A length word in mm.
    pub fn mm(&self, w: &Word) -> f64 {
        self.units.to_mm(self.value(w))
    }

    /// The machine's state for a move now.
    pub fn state(&self) -> State {
        let f = self.f.map(|f| self.units.to_mm(f));
        State {
            feed: match (self.feed_mode, f) {
                (FeedMode::PerMinute, Some(f)) => Feed::PerMinute(f),
                (FeedMode::PerRev, Some(f)) => Feed::PerRev(f),
                _ => Feed::Unknown,
            },
            rpm: self.rpm,
            rotation: self.rotation,
            tool: self.tool,
            length_offset: self.length_offset,
            comp: self.comp,
            units: self.units,
        }
    }

    fn shift(&self, axis: usize) -> f64 {
        self.local[axis] + self.g92[axis]
    }

    /// The block's end point from its X Y Z words (mm, work coordinates), axis by axis: an axis
    /// not written stays where it is; an incremental word needs its axis known.
    pub fn end_point(&self, line: &Line) -> Result<[Option<f64>; 3]> {
        let mut to = self.pos;
        for (axis, letter) in AXES.iter().enumerate() {
            let Some(w) = line.word(*letter) else {
                continue;
            };
            let v = self.mm(w);
            to[axis] = Some(if self.absolute {
                v + self.shift(axis)
            } else {
                self.pos[axis].ok_or_else(|| unknown_axis(w, "an incremental move (G91)"))? + v
            });
        }
        Ok(to)
    }

    /// Executes one block.
    pub fn block(&mut self, line: &Line, out: &mut dyn Out) -> Result<()> {
        let codes = self.codes(line)?;
        self.modes(&codes);
        self.words(line)?;
        self.compensation(line, &codes)?;
        self.length_offset(line, &codes)?;
        self.work_system(line, &codes)?;
        if self.non_modal(line, &codes, out)? {
            return Ok(());
        }
        self.motion(line, &codes, out)
    }

    /// The block's G codes (×10, with their words), each one the control has.
    fn codes<'l>(&self, line: &'l Line) -> Result<Vec<(u16, &'l Word)>> {
        let mut codes = Vec::new();
        for w in line.words.iter().filter(|w| w.letter == b'G') {
            let Some(c) = g10(w.value).filter(|c| self.has(*c)) else {
                return Err(Diagnostic::error(
                    Code::UnknownCode,
                    w.span,
                    format!(
                        "G{} is not a code threadcut reads in a {} milling program",
                        w.value, self.lang.control
                    ),
                )
                .with_hint(format!("threadcut reads G0–G3, G4, G10, G17–G21, G28, G30, G40–G44, G49, G52–G59, G61, G64, G73, G74, G80–G86, G89, G90–G95, G98, G99 and the control's own tapping, work system and arc-centre codes; a lathe program is read with a lathe controller ({})", crate::machine::ProfileKind::Lathe.names().join(", "))));
            };
            codes.push((c, w));
        }
        Ok(codes)
    }

    fn has(&self, c: u16) -> bool {
        let common = matches!(
            c,
            0 | 10
                | 20
                | 30
                | 40
                | 100
                | 170
                | 180
                | 190
                | 200
                | 210
                | 280
                | 300
                | 400
                | 410
                | 420
                | 430
                | 440
                | 490
                | 520
                | 530
                | 540
                | 550
                | 560
                | 570
                | 580
                | 590
                | 730
                | 800..=890 | 900 | 910 | 920 | 930 | 940 | 950 | 980 | 990
        ) && c.is_multiple_of(10);
        common
            || (c == 740 || c == 760)
            || self.lang.cycles.taps.iter().any(|t| t.code == c)
            || (self.lang.g54_1 && c == 541)
            || (self.lang.g59_x && matches!(c, 591..=593))
            || (self.lang.centre_modes && matches!(c, 901 | 911))
            || (self.lang.g33_1 && c == 331)
            || (self.lang.dynamic_comp && matches!(c, 411 | 421))
            || self.lang.neutral.contains(&c)
            || self.lang.probes.contains(&c)
            || (self.lang.haas_work
                && (matches!(c, 1100..=1290) && c.is_multiple_of(10) || c == 1540))
    }

    /// Units, plane, distance, arc-centre and feed modes, the return level.
    fn modes(&mut self, codes: &[(u16, &Word)]) {
        for (c, _) in codes {
            match c {
                200 => self.units = Units::Inch,
                210 => self.units = Units::Mm,
                170 => self.plane = Plane::Xy,
                180 => self.plane = Plane::Zx,
                190 => self.plane = Plane::Yz,
                900 => self.absolute = true,
                910 => self.absolute = false,
                901 => self.centre_absolute = true,
                911 => self.centre_absolute = false,
                930 => self.feed_mode = FeedMode::InverseTime,
                940 => self.feed_mode = FeedMode::PerMinute,
                950 => self.feed_mode = FeedMode::PerRev,
                980 => self.cycle.initial = true,
                990 => self.cycle.initial = false,
                _ => {}
            }
        }
    }

    /// F, S, T and the M codes of the spindle and the tool change.
    fn words(&mut self, line: &Line) -> Result<()> {
        for w in line.words {
            match w.letter {
                b'F' => {
                    if w.value < 0.0 {
                        return Err(bad_word(w, "a feed must not be negative"));
                    }
                    // F is a rate: whole units without a decimal point on every control.
                    self.f = Some(w.value);
                }
                b'S' => {
                    if w.value < 0.0 {
                        return Err(bad_word(w, "a spindle speed must not be negative"));
                    }
                    self.rpm = Some(w.value);
                }
                b'T' => self.next_tool = Some(whole(w)?),
                _ => {}
            }
        }
        for w in line.words.iter().filter(|w| w.letter == b'M') {
            match whole(w)? {
                3 => self.rotation = Rotation::Cw,
                4 => self.rotation = Rotation::Ccw,
                5 | 19 => self.rotation = Rotation::Stopped,
                6 => self.tool = self.next_tool.or(self.tool),
                29 if self.lang.cycles.m29_rigid => self.m29 = true,
                // Calls and returns are the interpreter's; a control without a macro language
                // threadcut runs cannot have them passed over.
                97..=99 if self.lang.macros.is_none() => {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        w.span,
                        format!(
                            "M{} (a subprogram call or return) is not read on {}: threadcut runs no subprograms there",
                            w.value, self.lang.control
                        ),
                    )
                    .with_hint("expand the program's subprograms into the main program"))
                }
                2 | 30 => self.ended = true,
                _ => {}
            }
        }
        Ok(())
    }

    /// G40, G41, G42 (with D); compensation is not started or ended on an arc.
    fn compensation(&mut self, line: &Line, codes: &[(u16, &Word)]) -> Result<()> {
        let d = || match line.word(b'D') {
            Some(w) => whole(w).map(Some),
            None => Ok(None),
        };
        for (c, _) in codes {
            // (G41.1/G42.1's D is the tool's diameter, not a register.)
            let comp = match c {
                400 => Comp::Off,
                410 => Comp::Left { d: d()? },
                420 => Comp::Right { d: d()? },
                411 => Comp::Left { d: None },
                421 => Comp::Right { d: None },
                _ => continue,
            };
            let arc = codes.iter().find(|(m, _)| matches!(m, 20 | 30));
            let allowed = *c != 400 && self.lang.comp_start_on_arc;
            if let (Some((m, mw)), false) = (arc, allowed) {
                return Err(Diagnostic::error(
                    Code::Conflict,
                    mw.span,
                    format!(
                        "{}: {} on the arc's block ({})",
                        self.lang.alarms.comp_on_arc,
                        g_name(*c),
                        g_name(*m)
                    ),
                )
                .with_hint(
                    "start and end compensation on a straight move (G1, or G0) before the arc",
                ));
            }
            self.comp = comp;
        }
        Ok(())
    }

    /// G43/G44 H, G49.
    fn length_offset(&mut self, line: &Line, codes: &[(u16, &Word)]) -> Result<()> {
        for (c, w) in codes {
            match c {
                430 | 440 => {
                    let h = line.word(b'H').map(whole).transpose()?;
                    self.length_offset = h.or(self.tool).or(self.length_offset);
                    if h.is_none() && self.tool.is_none() {
                        return Err(Diagnostic::error(
                            Code::MissingWord,
                            w.span,
                            format!("{} without H: which tool length register?", g_name(*c)),
                        )
                        .with_hint("write the register, e.g. G43 H1"));
                    }
                }
                490 => self.length_offset = None,
                _ => {}
            }
        }
        Ok(())
    }

    /// G54–G59, G54.1 P, G59.1–G59.3: the positions in another system are not known (its
    /// offsets are the machine's).
    fn work_system(&mut self, line: &Line, codes: &[(u16, &Word)]) -> Result<()> {
        for (c, w) in codes {
            let haas = matches!(c, 1100..=1290 | 1540);
            if !matches!(c, 540 | 550 | 560 | 570 | 580 | 590 | 541 | 591..=593) && !haas {
                continue;
            }
            let p = if *c == 541 || *c == 1540 {
                let p = line
                    .word(b'P')
                    .ok_or_else(|| {
                        Diagnostic::error(
                            Code::MissingWord,
                            w.span,
                            format!(
                                "{} without P: which additional work coordinate system?",
                                g_name(*c)
                            ),
                        )
                        .with_hint(format!("write its number, e.g. {} P1", g_name(*c)))
                    })
                    .and_then(whole)?;
                if p == 0 || p > 300 {
                    return Err(bad_word(
                        w,
                        "G54.1 P takes 1 to 300 (alarm PS0030 past the systems the control has)",
                    ));
                }
                p
            } else {
                0
            };
            if (*c, p) != (self.work, self.work_p) {
                self.pos = [None; 3];
            }
            self.work = *c;
            self.work_p = p;
        }
        Ok(())
    }

    /// G4, G10, G28, G30, G52, G53, G92: true when the block's axis words were theirs.
    fn non_modal(
        &mut self,
        line: &Line,
        codes: &[(u16, &Word)],
        out: &mut dyn Out,
    ) -> Result<bool> {
        for (c, w) in codes {
            match c {
                40 => return Ok(true),
                // G10 sets offsets: those of the system in force may have changed.
                100 => {
                    self.pos = [None; 3];
                    return Ok(true);
                }
                280 | 300 => {
                    self.reference_return(line, *c, out)?;
                    return Ok(true);
                }
                520 => {
                    self.local_shift(line)?;
                    return Ok(true);
                }
                c if *c == 530 || self.lang.probes.contains(c) => {
                    for (axis, letter) in AXES.iter().enumerate() {
                        if line.word(*letter).is_some() {
                            self.pos[axis] = None;
                        }
                    }
                    return Ok(true);
                }
                920 => {
                    self.set_position(line, w)?;
                    return Ok(true);
                }
                _ => {}
            }
        }
        Ok(false)
    }

    /// G52: the local shift, absolute in the work system (an axis not written keeps its
    /// shift). LinuxCNC's G52 is its G92 offset set to the values.
    fn local_shift(&mut self, line: &Line) -> Result<()> {
        let linuxcnc = self.lang.g52_is_g92_offset;
        for (axis, letter) in AXES.iter().enumerate() {
            if let Some(w) = line.word(*letter) {
                if linuxcnc {
                    self.g92[axis] = self.mm(w);
                } else {
                    self.local[axis] = self.mm(w);
                }
            }
        }
        Ok(())
    }

    /// G92: the named axes' current position becomes the value written.
    fn set_position(&mut self, line: &Line, g: &Word) -> Result<()> {
        let mut any = false;
        for (axis, letter) in AXES.iter().enumerate() {
            if let Some(w) = line.word(*letter) {
                any = true;
                let at = self.pos[axis]
                    .ok_or_else(|| unknown_axis(w, "G92 (which sets the current position)"))?;
                self.g92[axis] = at - self.local[axis] - self.mm(w);
            }
        }
        if !any {
            return Err(Diagnostic::error(
                Code::MissingWord,
                g.span,
                "G92 without an axis word: which position is set?",
            ));
        }
        Ok(())
    }

    /// G28/G30: through the intermediate point to the reference point (the profile's, else the
    /// axes are not known after it).
    fn reference_return(&mut self, line: &Line, code: u16, out: &mut dyn Out) -> Result<()> {
        let named: Vec<usize> = (0..3).filter(|a| line.word(AXES[*a]).is_some()).collect();
        let axes: Vec<usize> = if named.is_empty() && self.lang.return_all_without_axes {
            vec![0, 1, 2]
        } else {
            named
        };
        // The intermediate point; in G91 from where the tool is, which need not be known (the
        // usual `G91 G28 Z0` at a program's start moves no further than the return itself).
        let mut mid = self.pos;
        for (axis, letter) in AXES.iter().enumerate() {
            if let Some(w) = line.word(*letter) {
                let v = self.mm(w);
                mid[axis] = if self.absolute {
                    Some(v + self.shift(axis))
                } else {
                    self.pos[axis].map(|p| p + v)
                };
            }
        }
        self.rapid_to(mid, line.number, out)?;
        let reference: Axes = if code == 280 {
            self.reference.g28
        } else {
            self.reference.g30
        };
        let mut to = self.pos;
        for a in axes {
            to[a] = [reference.x, reference.y, reference.z][a];
        }
        self.rapid_to(to, line.number, out)
    }

    /// A rapid to `to`, emitted when its end is known on every axis.
    pub fn rapid_to(&mut self, to: [Option<f64>; 3], line: u32, out: &mut dyn Out) -> Result<()> {
        self.straight(MillKind::Rapid, to, line, out)
    }

    /// A straight move of `kind` to `to`: emitted when the end is known on every axis (an axis
    /// whose start is not known starts at NaN), and the position kept axis by axis.
    pub fn straight(
        &mut self,
        kind: MillKind,
        to: [Option<f64>; 3],
        line: u32,
        out: &mut dyn Out,
    ) -> Result<()> {
        let from = self.pos;
        self.pos = to;
        let (Some(x), Some(y), Some(z)) = (to[0], to[1], to[2]) else {
            return Ok(());
        };
        if from == to {
            return Ok(());
        }
        let m = MillMotion {
            kind,
            from: from.map(|v| v.unwrap_or(f64::NAN)),
            to: [x, y, z],
            state: self.state(),
            line,
        };
        out.motion(&m, self.work)
    }

    /// A feed move needs a feed (LinuxCNC: "Cannot do G1 with zero feed rate"; Fanuc: PS0011).
    pub(crate) fn feed_needed(&self, line: &Line, g: Option<&Word>, arc: bool) -> Result<()> {
        if self.f.is_some_and(|f| f > 0.0) || self.feed_mode == FeedMode::InverseTime {
            return Ok(());
        }
        let span = g.map_or(line.span(), |w| w.span);
        let alarm = if arc {
            self.lang.alarms.zero_feed_arc
        } else {
            self.lang.alarms.zero_feed
        };
        Err(Diagnostic::error(
            Code::MissingWord,
            span,
            format!(
                "{}: a feed move without a feed rate",
                Alarms::with_code(alarm, "G1")
            ),
        )
        .with_hint("write F on this block or before it"))
    }
}

/// The canned cycles' modal values.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CycleModal {
    /// G98: return to the initial level (else G99: to R).
    pub initial: bool,
    /// R and Z as written (mm), Q (mm), P (seconds), kept while the cycle mode lasts.
    pub(crate) r: Option<f64>,
    pub(crate) z: Option<f64>,
    pub(crate) q: Option<f64>,
    pub(crate) p: Option<f64>,
    /// The initial level (mm, work coordinates): Z when the cycle mode began.
    pub(crate) level: Option<f64>,
}

impl CycleModal {
    pub fn new(initial: bool) -> CycleModal {
        CycleModal {
            initial,
            r: None,
            z: None,
            q: None,
            p: None,
            level: None,
        }
    }

    /// The cycle mode ends (G80, a motion code): its words are forgotten.
    pub fn end(&mut self) {
        *self = CycleModal::new(self.initial);
    }
}

pub(crate) fn whole(w: &Word) -> Result<u32> {
    if w.value < 0.0 || w.value.fract() != 0.0 || w.value > 1e9 {
        return Err(bad_word(w, "a whole number is expected"));
    }
    Ok(w.value as u32)
}

pub(crate) fn bad_word(w: &Word, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::OutOfRange,
        w.span,
        format!("{}{}: {what}", w.letter as char, w.value),
    )
}

pub(crate) fn unknown_axis(w: &Word, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::UnknownPosition,
        w.span,
        format!(
            "the tool's {} is not known here, and {what} needs it",
            w.letter as char
        ),
    )
    .with_hint("position the axis with an absolute move first (after power-on, G28 without a reference in the profile, G53, or a change of work coordinate system the position is not known)")
}

/// A point known on every axis.
pub(crate) fn known(p: [Option<f64>; 3]) -> Option<P3> {
    Some([p[0]?, p[1]?, p[2]?])
}

pub(crate) fn span_of(line: &Line, w: Option<&Word>) -> Span {
    w.map_or(line.span(), |w| w.span)
}
