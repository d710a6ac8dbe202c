//! Stock removal to a contour in layers (Fanuc's G71 along Z and G72 along X, type I and type
//! II, as GSK's and Haas's of the same family): cuts at heights Δd apart from the start point,
//! each ended by a 45° retract of e and a rapid back, then one pass along the contour shifted by
//! the finishing allowance, then back to the start. docs/dialects/turning-cycles.md gives the
//! manuals' sentences and the decisions.

use crate::diag::{Code, Diagnostic, Result};
use crate::toolpath::{Motion, MotionKind};
use crate::turning::contour::{at_line, open_ranges, pieces, Frame, Piece, P, TOL};
use crate::turning::{Along, Rough, Segment, Shape};
use crate::units::Vec2;

/// The most cutting layers one cycle may take (a depth of cut far too small for the contour
/// would otherwise make motion without end).
pub const MAX_LAYERS: usize = 100_000;

/// The moves of a stock removal, from its start point back to it: every roughing pass numbered
/// from 1, the pass along the contour last; each move tagged with the cycle's `line`.
pub fn moves(cycle: &Rough, line: u32) -> Result<Vec<Motion>> {
    check_words(cycle, line)?;
    let segs = &cycle.contour.segments;
    let first = first_block(cycle, line)?;
    let frame = frame(cycle, first, line)?;
    let shift = Vec2::new(cycle.allowance_x, cycle.allowance_z);
    // The first block (A → A′) brings the tool to the contour: its end is shifted, its start is
    // the cycle's start point.
    let all = pieces(frame, cycle.start, segs, shift)?;
    let profile = &all[1..];
    check_shape(cycle, frame, profile)?;
    let plan = Plan::new(cycle, frame, &all)?;
    let mut out = Out::new(frame, plan.start, line);
    plan.cut_layers(&mut out);
    plan.along_contour(&mut out);
    if let Some((x, z)) = cycle.then_outline {
        let finish = pieces(frame, cycle.start, segs, Vec2::new(x, z))?;
        plan.along(&mut out, &finish[1..]);
    }
    Ok(out.moves)
}

/// PS0062 and its kin: values no cycle can run with.
fn check_words(cycle: &Rough, line: u32) -> Result<()> {
    let bad = |what: &str| Diagnostic::error(Code::OutOfRange, at_line(line), what.to_string());
    if !cycle.depth.is_finite() || cycle.depth <= 0.0 {
        return Err(bad(&format!(
            "PS0062: the depth of cut Δd is {}: it must be greater than 0",
            cycle.depth
        )));
    }
    if !cycle.retract.is_finite() || cycle.retract < 0.0 {
        return Err(bad(&format!(
            "PS0062: the retract e is {}: it must be 0 or more",
            cycle.retract
        )));
    }
    if !cycle.allowance_x.is_finite() || !cycle.allowance_z.is_finite() || !cycle.start.is_finite()
    {
        return Err(Diagnostic::error(
            Code::BadNumber,
            at_line(line),
            "the cycle's start point or finishing allowance is not a finite number",
        ));
    }
    if cycle.contour.start.distance(cycle.start) > TOL.get() {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape does not start at the cycle's start point",
        ));
    }
    Ok(())
}

/// The shape's first block (ns), checked: a line (G00/G01), and for type I a move in the depth
/// axis only; then at least one block after it.
fn first_block(cycle: &Rough, line: u32) -> Result<&Segment> {
    let segs = &cycle.contour.segments;
    let Some(first) = segs.first() else {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape has no block",
        ));
    };
    if matches!(first.shape, Shape::Arc { .. }) {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(first.line),
            "PS0065: the first block of the finishing shape must be G00 or G01, not an arc",
        ));
    }
    let (cut_axis, moved) = match cycle.along {
        Along::Z => ("Z (W)", first.to.z - cycle.start.z),
        Along::X => ("X (U)", first.to.x - cycle.start.x),
    };
    if !cycle.pockets && !TOL.is_zero(moved) {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(first.line),
            format!(
                "PS0065: in type I the first block of the finishing shape moves in {cut_axis} by {moved:.4} mm: it may move only toward the part"
            ),
        )
        .with_hint("a shape with pockets is type II: give both axes in its first block"));
    }
    if segs.len() < 2 {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(first.line),
            "the finishing shape has only its first block: there is no contour to rough",
        ));
    }
    Ok(first)
}

/// The working frame: the infeed as the first block goes, the cut from the first block's end
/// toward the shape's end.
fn frame(cycle: &Rough, first: &Segment, line: u32) -> Result<Frame> {
    let end = cycle.contour.segments.last().map_or(first.to, |s| s.to);
    let (infeed, cut, depth_axis, cut_axis) = match cycle.along {
        Along::Z => (first.to.x - cycle.start.x, end.z - first.to.z, "X", "Z"),
        Along::X => (first.to.z - cycle.start.z, end.x - first.to.x, "Z", "X"),
    };
    if TOL.is_zero(infeed) {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(first.line),
            format!(
                "the first block of the finishing shape does not move in {depth_axis}: the cycle cannot tell which side the part is on"
            ),
        ));
    }
    if TOL.is_zero(cut) {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            format!("the finishing shape ends where it starts in {cut_axis}: nothing to cut along {cut_axis}"),
        ));
    }
    Ok(Frame {
        along: cycle.along,
        infeed: infeed.signum(),
        cut: cut.signum(),
    })
}

/// Monotonic shapes: along the cut axis always (PS0064 for Z, the plane's first axis; PS0329
/// for X, its second), along the depth axis too in type I.
fn check_shape(cycle: &Rough, frame: Frame, profile: &[Piece]) -> Result<()> {
    let alarm = |axis: Along| match axis {
        Along::Z => ("PS0064", "Z"),
        Along::X => ("PS0329", "X"),
    };
    let depth_axis = match frame.along {
        Along::Z => Along::X,
        Along::X => Along::Z,
    };
    for p in profile {
        if !p.rises_in_t() {
            let (code, axis) = alarm(frame.along);
            return Err(Diagnostic::error(
                Code::Geometry,
                at_line(p.seg.line),
                format!("{code}: the finishing shape does not change monotonically in {axis}: this block turns back"),
            ));
        }
        if !cycle.pockets && !p.rises_in_h() {
            let (code, axis) = alarm(depth_axis);
            return Err(Diagnostic::error(
                Code::Geometry,
                at_line(p.seg.line),
                format!("{code}: in type I the finishing shape must change monotonically in {axis}: this block goes back into the part"),
            )
            .with_hint("a shape with pockets needs type II"));
        }
    }
    Ok(())
}

/// The layers of one cycle: their heights and where each runs through material.
struct Plan<'a> {
    start: P,
    depth: f64,
    retract: f64,
    /// The shape after its first block, shifted by the allowance.
    profile: &'a [Piece],
    /// Layer k (from 1) at height start.h − k·Δd; `ranges[k − 1]` where it cuts, in order.
    ranges: Vec<Vec<(f64, f64)>>,
    /// The cut stops where the shape first reaches the start point's height (nothing beyond a
    /// shoulder higher than the start can be reached) or at the shape's end.
    t_end: f64,
}

impl<'a> Plan<'a> {
    fn new(cycle: &Rough, frame: Frame, all: &'a [Piece]) -> Result<Plan<'a>> {
        let start = frame.to(cycle.start);
        let profile = &all[1..];
        let last = profile.last().map_or(start.t, |p| p.to.t);
        let t_end = open_ranges(profile, start.h, start.t, last)
            .first()
            .filter(|r| r.0 <= start.t + TOL.get())
            .map_or(start.t, |r| r.1);
        let lowest = profile
            .iter()
            .map(Piece::lowest)
            .fold(f64::INFINITY, f64::min);
        // Layers strictly above the lowest point: k·Δd < start.h − lowest.
        let room = start.h - lowest - TOL.get();
        let layers = if room > 0.0 {
            (room / cycle.depth).ceil() - 1.0
        } else {
            0.0
        };
        if layers > MAX_LAYERS as f64 {
            return Err(Diagnostic::error(
                Code::TooManyPasses,
                at_line(profile[0].seg.line),
                format!(
                    "a depth of cut of {} mm takes {layers} layers down to the finishing shape: more than {MAX_LAYERS}",
                    cycle.depth
                ),
            ));
        }
        let ranges = (1..=layers as usize)
            .map(|k| open_ranges(profile, start.h - k as f64 * cycle.depth, start.t, t_end))
            .collect();
        Ok(Plan {
            start,
            depth: cycle.depth,
            retract: cycle.retract,
            profile,
            ranges,
            t_end,
        })
    }

    fn height(&self, layer: usize) -> f64 {
        self.start.h - layer as f64 * self.depth
    }

    /// Every layer's cuts, one region at a time: a cut, then the cuts below it in order along
    /// the cut (each pocket roughed to its bottom before the next), depth first.
    fn cut_layers(&self, out: &mut Out) {
        // (layer, range) still to cut, and the layers above the tool's region (the chain).
        let mut todo: Vec<(usize, (f64, f64))> = Vec::new();
        if let Some(top) = self.ranges.first() {
            todo.extend(top.iter().rev().map(|&r| (1, r)));
        }
        let mut chain: Vec<(usize, (f64, f64))> = Vec::new();
        while let Some((layer, (a, b))) = todo.pop() {
            while chain.last().is_some_and(|c| c.0 >= layer) {
                chain.pop();
            }
            out.pass += 1;
            let h = self.height(layer);
            out.travel(self.clear_height(&chain), a);
            let air = a <= self.start.t + TOL.get();
            out.go(
                P::new(a, h),
                if air {
                    MotionKind::Rapid
                } else {
                    MotionKind::Feed
                },
            );
            out.go(P::new(b, h), MotionKind::Feed);
            // The 45° retract: e up and e back, not behind the cut's own start.
            let back = (b - self.retract).max(a);
            out.go(P::new(back, h + self.retract), MotionKind::Rapid);
            chain.push((layer, (a, b)));
            if let Some(below) = self.ranges.get(layer) {
                let mid = |r: &(f64, f64)| (r.0 + r.1) / 2.0;
                let from = below.partition_point(|r| mid(r) < a);
                let to = below.partition_point(|r| mid(r) <= b);
                todo.extend(below[from..to].iter().rev().map(|&r| (layer + 1, r)));
            }
        }
    }

    /// The height the tool travels at to reach a cut whose region is the last of `chain`: the
    /// retract height of the layer above (everything above it over that region is cut), or the
    /// start's height for the first layer.
    fn clear_height(&self, chain: &[(usize, (f64, f64))]) -> f64 {
        chain
            .last()
            .map_or(self.start.h, |c| self.height(c.0) + self.retract)
    }

    /// The pass along the shape shifted by the allowance, then back to the start point.
    fn along_contour(&self, out: &mut Out) {
        self.along(out, self.profile);
    }

    /// A pass along `profile` (the shape after its first block, shifted), reached at rapid over
    /// the material the layers left, then back to the start point.
    fn along(&self, out: &mut Out, profile: &[Piece]) {
        out.pass += 1;
        let first = profile[0].from;
        let clear = self.clear_between(out.at.t, first.t);
        out.travel(clear, first.t);
        out.go(first, MotionKind::Rapid);
        for p in profile {
            out.follow(p);
        }
        out.go(self.start, MotionKind::Rapid);
    }

    /// The height at which the tool may travel from `t1` to `t2`: the retract height of the
    /// deepest layer one of whose cuts spans both (the layers nest, so the search stops at the
    /// first that does not), or the start's height.
    fn clear_between(&self, t1: f64, t2: f64) -> f64 {
        let lo = t1.min(t2).clamp(self.start.t, self.t_end);
        let hi = t1.max(t2).clamp(self.start.t, self.t_end);
        let spans = |rs: &Vec<(f64, f64)>| {
            rs.iter()
                .any(|r| r.0 <= lo + TOL.get() && hi <= r.1 + TOL.get())
        };
        let deepest = self.ranges.iter().take_while(|rs| spans(rs)).count();
        if deepest == 0 {
            self.start.h
        } else {
            self.height(deepest) + self.retract
        }
    }
}

/// The moves being written, in the working frame.
struct Out {
    frame: Frame,
    at: P,
    pass: u32,
    line: u32,
    moves: Vec<Motion>,
}

impl Out {
    fn new(frame: Frame, start: P, line: u32) -> Out {
        Out {
            frame,
            at: start,
            pass: 0,
            line,
            moves: Vec::new(),
        }
    }

    /// A straight move to `p`, left out when the tool is there already.
    fn go(&mut self, p: P, kind: MotionKind) {
        if TOL.eq(p.t, self.at.t) && TOL.eq(p.h, self.at.h) {
            return;
        }
        self.moves.push(Motion {
            kind,
            to: self.frame.from(p),
            pass: self.pass,
            line: self.line,
        });
        self.at = p;
    }

    /// Up to `height` (if below it), then along t to `t`, at rapid.
    fn travel(&mut self, height: f64, t: f64) {
        if self.at.h < height - TOL.get() {
            self.go(P::new(self.at.t, height), MotionKind::Rapid);
        }
        self.go(P::new(t, self.at.h), MotionKind::Rapid);
    }

    /// Along a piece of the shape.
    fn follow(&mut self, p: &Piece) {
        self.moves.push(p.motion(self.pass, self.line));
        self.at = p.to;
    }
}

#[cfg(test)]
#[path = "rough_tests.rs"]
mod tests;
