//! Stock removal in even layers, each layer's corner cleaned along the contour, and finishing
//! along the contour, from a start point the cycle works out itself (Sinumerik's CYCLE95 on a
//! contour without relief cuts). In the working frame of [`contour`](super::contour) the passes
//! run toward +t and the infeed lowers h: the contour shifted by the allowances must rise (never
//! fall) along t. docs/dialects/sinumerik.md ("CYCLE95") gives the sentences and decisions.

use crate::diag::{Code, Diagnostic, Result};
use crate::toolpath::{Motion, MotionKind};
use crate::turning::contour::{at_line, pieces, Frame, Piece, P, TOL};
use crate::turning::{Along, Contour, Removal, Segment, Shape};
use crate::units::{Pos, Vec2};

/// The most layers one cycle may take (a depth of cut far too small for the contour would
/// otherwise make motion without end).
pub const MAX_LAYERS: usize = 100_000;

/// Bisection steps that put a crossing on an arc within far less than [`TOL`].
const BISECTIONS: usize = 60;

/// The moves of the cycle, from the tool's position at the call back to the cycle's start
/// point; roughing layers are passes 1…n, the finishing pass the next.
pub fn moves(cycle: &Removal, line: u32) -> Result<Vec<Motion>> {
    check_values(cycle, line)?;
    let frame = frame(cycle);
    let ordered = oriented(frame, &cycle.contour, line)?;
    let shift = allowance_shift(cycle, frame);
    let profile = pieces(frame, ordered.start.plus(shift), &ordered.segments, shift)?;
    check_shape(&profile)?;
    let start = start_in_frame(cycle, &profile);
    let mut out = Out {
        frame,
        at: frame.to(cycle.from),
        pass: 0,
        line,
        moves: Vec::new(),
    };
    // "The cycle starting point is … approached with G0 in both axes at the same time": the
    // first pass's first move.
    out.pass = 1;
    out.go(start, MotionKind::Rapid);
    out.pass = 0;
    if cycle.rough {
        rough(cycle, &profile, start, &mut out)?;
    }
    if cycle.finish {
        // Finishing after roughing runs as the roughing did; alone, as the contour is written.
        let written = if cycle.rough {
            ordered
        } else {
            cycle.contour.clone()
        };
        let path = pieces(frame, written.start, &written.segments, Vec2::new(0.0, 0.0))?;
        finish(&path, start, &mut out);
    }
    Ok(out.moves)
}

/// The cycle's start point (absolute mm, X radius): the contour's extent with the allowances,
/// and the lift-off beyond it in both axes.
pub fn start_point(cycle: &Removal) -> Result<Pos> {
    let frame = frame(cycle);
    let ordered = oriented(frame, &cycle.contour, 0)?;
    let shift = allowance_shift(cycle, frame);
    let profile = pieces(frame, ordered.start.plus(shift), &ordered.segments, shift)?;
    Ok(frame.from(start_in_frame(cycle, &profile)))
}

/// Values no cycle can run with.
fn check_values(cycle: &Removal, line: u32) -> Result<()> {
    let bad = |what: String| Err(Diagnostic::error(Code::OutOfRange, at_line(line), what));
    if !cycle.depth.is_finite() || (cycle.rough && cycle.depth <= 0.0) {
        return bad(format!(
            "the depth of cut is {}: it must be greater than 0",
            cycle.depth
        ));
    }
    if !(cycle.lift.is_finite() && cycle.lift > 0.0) {
        return bad(format!(
            "the lift-off is {}: it must be greater than 0",
            cycle.lift
        ));
    }
    let allowances = [cycle.allowance_x, cycle.allowance_z, cycle.allowance];
    if allowances.iter().any(|a| !a.is_finite() || *a < 0.0) || !cycle.from.is_finite() {
        return bad("a finishing allowance is negative or not a number".into());
    }
    if cycle.contour.segments.is_empty() {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the contour has no block after its first point",
        ));
    }
    if cycle.allowance > 0.0 {
        normal_allowance_on_axis_lines(&cycle.contour)?;
    }
    Ok(())
}

/// The allowance along the contour is a shift by it in both axes only where every piece is a
/// line along an axis (each edge then moves by it along its normal, and the corners where two
/// meet move by it in both axes); on a taper or an arc it would be an offset the model does not
/// make.
fn normal_allowance_on_axis_lines(contour: &Contour) -> Result<()> {
    let mut from = contour.start;
    for s in &contour.segments {
        let along_axis = TOL.eq(s.to.x, from.x) || TOL.eq(s.to.z, from.z);
        if matches!(s.shape, Shape::Arc { .. }) || !along_axis {
            return Err(Diagnostic::error(
                Code::Unsupported,
                at_line(s.line),
                "a finishing allowance along the contour on a taper or an arc: threadcut does not offset a stock removal's contour normal to itself",
            )
            .with_hint("give the allowance on each axis instead"));
        }
        from = s.to;
    }
    Ok(())
}

/// The working frame: longitudinal passes toward −Z (infeed toward the axis outside, away from
/// it in a bore); facing passes toward the axis outside and away from it in a bore, the infeed
/// toward −Z.
fn frame(cycle: &Removal) -> Frame {
    let (infeed, cut) = match (cycle.along, cycle.internal) {
        (Along::Z, false) => (-1.0, -1.0),
        (Along::Z, true) => (1.0, -1.0),
        (Along::X, false) => (-1.0, -1.0),
        (Along::X, true) => (-1.0, 1.0),
    };
    Frame {
        along: cycle.along,
        infeed,
        cut,
    }
}

/// The allowances as one displacement away from the part: up in the frame by the allowance on
/// the depth axis, back along the cut by the one on the cut axis.
fn allowance_shift(cycle: &Removal, frame: Frame) -> Vec2 {
    let (on_x, on_z) = (
        cycle.allowance_x + cycle.allowance,
        cycle.allowance_z + cycle.allowance,
    );
    let (up, back) = match cycle.along {
        Along::Z => (on_x, on_z),
        Along::X => (on_z, on_x),
    };
    let d = frame.from(P::new(-back, up));
    Vec2::new(d.x, d.z)
}

/// The contour in the order the passes run (t rising from its first point to its last): as
/// written, or reversed when it is written from the other end.
fn oriented(frame: Frame, contour: &Contour, line: u32) -> Result<Contour> {
    let last = contour.segments.last().map_or(contour.start, |s| s.to);
    let (a, b) = (frame.to(contour.start), frame.to(last));
    if TOL.eq(a.t, b.t) {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(contour.segments.first().map_or(line, |s| s.line)),
            "the contour ends where it starts along the cutting axis: there is nothing to cut along it",
        ));
    }
    if a.t < b.t {
        return Ok(contour.clone());
    }
    let mut points = vec![contour.start];
    points.extend(contour.segments.iter().map(|s| s.to));
    let segments = contour
        .segments
        .iter()
        .enumerate()
        .rev()
        .map(|(i, s)| Segment {
            to: points[i],
            shape: match s.shape {
                Shape::Line => Shape::Line,
                Shape::Arc { centre, clockwise } => Shape::Arc {
                    centre,
                    clockwise: !clockwise,
                },
            },
            line: s.line,
        })
        .collect();
    Ok(Contour {
        start: last,
        segments,
    })
}

/// A contour the cycle cuts: along the cut it never turns back, and it never falls back into
/// the part (a relief cut, which is not modelled).
fn check_shape(profile: &[Piece]) -> Result<()> {
    for p in profile {
        if !p.rises_in_t() {
            return Err(Diagnostic::error(
                Code::Geometry,
                at_line(p.seg.line),
                "the contour turns back along the cutting axis in this block: the stock removal cannot cut it",
            ));
        }
        if !p.rises_in_h() {
            return Err(Diagnostic::error(
                Code::Unsupported,
                at_line(p.seg.line),
                "this block goes back into the part (a relief cut element): threadcut does not simulate the relief cuts of a stock removal",
            )
            .with_hint("rough the contour without its relief cuts, and program the relief cut as a cycle or moves of its own"));
        }
    }
    Ok(())
}

/// The start point in the frame: before the contour's first point and above its highest, each
/// by the lift-off.
fn start_in_frame(cycle: &Removal, profile: &[Piece]) -> P {
    let t0 = profile.first().map_or(0.0, |p| p.from.t);
    let top = highest(profile);
    P::new(t0 - cycle.lift, top + cycle.lift)
}

fn highest(profile: &[Piece]) -> f64 {
    profile
        .iter()
        .map(|p| p.to.h.max(p.from.h))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The layers: the depth from the contour's highest point to its lowest divided into equal
/// cuts no deeper than `depth`; each cut fed from the start's t to where the contour rises
/// above it, then along the contour up to the height of the cut before, a lift-off in both axes,
/// back along t at rapid. Last, back to the start point.
fn rough(cycle: &Removal, profile: &[Piece], start: P, out: &mut Out) -> Result<()> {
    let top = highest(profile);
    let low = profile
        .iter()
        .map(Piece::lowest)
        .fold(f64::INFINITY, f64::min);
    let total = top - low;
    let count = if total > TOL.get() {
        (total / cycle.depth - TOL.get() / cycle.depth)
            .ceil()
            .max(1.0)
    } else {
        0.0
    };
    if count > MAX_LAYERS as f64 {
        return Err(Diagnostic::error(
            Code::TooManyPasses,
            at_line(out.line),
            format!(
                "a depth of cut of {} mm takes {count} layers down to the contour: more than {MAX_LAYERS}",
                cycle.depth
            ),
        ));
    }
    let step = if count > 0.0 { total / count } else { 0.0 };
    for k in 1..=count as usize {
        out.pass += 1;
        let (above, h) = (top - (k - 1) as f64 * step, top - k as f64 * step);
        let h = if k == count as usize { low } else { h };
        out.go(P::new(start.t, h), MotionKind::Rapid);
        let (i, end) = last_at_or_below(profile, h);
        out.go(end, MotionKind::Feed);
        let (j, up) = first_at_or_above(profile, above, i);
        out.follow(profile, (i, end), (j, up));
        out.go(
            P::new(up.t - cycle.lift, up.h + cycle.lift),
            MotionKind::Rapid,
        );
        out.go(P::new(start.t, out.at.h), MotionKind::Rapid);
    }
    out.go(start, MotionKind::Rapid);
    Ok(())
}

/// The finishing pass: down to the contour's first height at the start's t (G0), along the cut
/// axis to the contour's first point and along the contour (G1/G2/G3), back to the start (G0).
fn finish(path: &[Piece], start: P, out: &mut Out) {
    out.pass += 1;
    let first = path[0].from;
    out.go(P::new(start.t, first.h), MotionKind::Rapid);
    out.go(first, MotionKind::Feed);
    for p in path {
        out.push_piece(p);
    }
    out.go(start, MotionKind::Rapid);
}

/// The last point of the contour at or below `level` (the contour rises along t): where a cut
/// at that height ends. (Piece index, point.)
fn last_at_or_below(profile: &[Piece], level: f64) -> (usize, P) {
    for (i, p) in profile.iter().enumerate() {
        if p.to.h > level + TOL.get() {
            if p.from.h > level + TOL.get() {
                return (i, p.from);
            }
            return (i, crossing(p, level));
        }
    }
    let last = profile.len() - 1;
    (last, profile[last].to)
}

/// The first point of the contour from piece `from` on at or above `level`.
fn first_at_or_above(profile: &[Piece], level: f64, from: usize) -> (usize, P) {
    for (i, p) in profile.iter().enumerate().skip(from) {
        if p.to.h >= level - TOL.get() {
            if p.from.h >= level - TOL.get() {
                return (i, p.from);
            }
            return (i, crossing(p, level));
        }
    }
    let last = profile.len() - 1;
    (last, profile[last].to)
}

/// Where a piece that rises through `level` meets it.
fn crossing(p: &Piece, level: f64) -> P {
    let Some(a) = p.arc else {
        if TOL.eq(p.to.h, p.from.h) {
            return p.from;
        }
        let u = (level - p.from.h) / (p.to.h - p.from.h);
        return P::new(p.from.t + u * (p.to.t - p.from.t), level);
    };
    let at = |u: f64| {
        let angle = a.from_angle + u * a.sweep;
        P::new(
            a.centre.t + a.radius * angle.cos(),
            a.centre.h + a.radius * angle.sin(),
        )
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..BISECTIONS {
        let mid = (lo + hi) / 2.0;
        if at(mid).h < level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    P::new(at(hi).t, level)
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
    /// A straight move to `p`, left out when the tool is there already.
    fn go(&mut self, p: P, kind: MotionKind) {
        if TOL.eq(p.t, self.at.t) && TOL.eq(p.h, self.at.h) {
            return;
        }
        self.push(p, kind);
    }

    fn push(&mut self, p: P, kind: MotionKind) {
        self.moves.push(Motion {
            kind,
            to: self.frame.from(p),
            pass: self.pass,
            line: self.line,
        });
        self.at = p;
    }

    /// Along a whole piece.
    fn push_piece(&mut self, p: &Piece) {
        self.moves.push(p.motion(self.pass, self.line));
        self.at = p.to;
    }

    /// Along piece `p` (its own kind of move) to the point `to` on it.
    fn along(&mut self, p: &Piece, to: P) {
        if TOL.eq(to.t, self.at.t) && TOL.eq(to.h, self.at.h) {
            return;
        }
        let kind = match p.seg.shape {
            Shape::Line => MotionKind::Feed,
            Shape::Arc { centre, clockwise } => MotionKind::Arc { centre, clockwise },
        };
        self.push(to, kind);
    }

    /// Along the contour from point `a` on piece `a.0` to point `b` on piece `b.0`.
    fn follow(&mut self, profile: &[Piece], a: (usize, P), b: (usize, P)) {
        self.at = a.1;
        for (i, p) in profile.iter().enumerate().take(b.0 + 1).skip(a.0) {
            let to = if i == b.0 { b.1 } else { p.to };
            self.along(p, to);
        }
    }
}

#[cfg(test)]
#[path = "removal_tests.rs"]
mod tests;
