//! Stock removal and finishing along an offset profile ([`Strategy::Offset`]): the contour is
//! first brought into a normal frame (passes along Z, the depth decreasing, the contour running
//! toward −Z), offset normal to itself by the remaining distance, and cut in layers `depth` apart
//! from the start point's side; each layer ends where it meets the offset contour, with a 45°
//! retract and a rapid back. Where the layers end the tool follows the offset contour; a pocket
//! (the contour climbing and diving again) is cut layer by layer when it is reached, or left for
//! a later cycle ([`Pockets`]).
//!
//! Lengths and tolerances are in the program's units (the strategy's tolerances are absolute: 10⁻⁶
//! for a point on a curve, 10⁻³ for a monotonic piece and a piece too short to keep, 10⁻² for
//! pieces that no longer meet after an offset), X a radius. The walk through the contour is bounded
//! by its input: a walk that makes no progress is an error, never a hang.
//!
//! docs/dialects/linuxcnc-turning.md describes it step by step.

use crate::diag::{Code, Diagnostic, Span};
use crate::toolpath::{Motion, MotionKind, Toolpath};
use crate::units::{Pos, Units};

use super::{Finish, FinishOffsets, Pockets, Rough, Shape, Strategy};

/// A point of the working plane: `z` along the axis, `x` the radius (a complex number z + i·x).
#[derive(Clone, Copy, Debug, PartialEq)]
struct P {
    z: f64,
    x: f64,
}

impl P {
    const fn new(z: f64, x: f64) -> P {
        P { z, x }
    }
    fn add(self, o: P) -> P {
        P::new(self.z + o.z, self.x + o.x)
    }
    fn sub(self, o: P) -> P {
        P::new(self.z - o.z, self.x - o.x)
    }
    fn mul(self, o: P) -> P {
        P::new(self.z * o.z - self.x * o.x, self.z * o.x + self.x * o.z)
    }
    fn div(self, o: P) -> P {
        let n = o.norm();
        P::new(
            (self.z * o.z + self.x * o.x) / n,
            (self.x * o.z - self.z * o.x) / n,
        )
    }
    fn times(self, k: f64) -> P {
        P::new(self.z * k, self.x * k)
    }
    fn conj(self) -> P {
        P::new(self.z, -self.x)
    }
    fn neg(self) -> P {
        P::new(-self.z, -self.x)
    }
    fn norm(self) -> f64 {
        self.z * self.z + self.x * self.x
    }
    fn abs(self) -> f64 {
        self.z.hypot(self.x)
    }
    /// The cross product `self × o` (the imaginary part of conj(self)·o).
    fn cross(self, o: P) -> f64 {
        self.z * o.x - self.x * o.z
    }
}

/// i·p: a quarter turn.
fn quarter(p: P) -> P {
    P::new(-p.x, p.z)
}

const TOL: f64 = 1e-6;
/// A walk through a contour takes at most this many steps per piece and layer.
const MAX_STEPS: usize = 1_000_000;

fn fail(msg: impl Into<String>) -> String {
    msg.into()
}

/// A piece of contour: a line, or an arc about `c` (`ccw`: G3 in the working frame).
#[derive(Clone, Copy, Debug)]
struct Piece {
    a: P,
    b: P,
    arc: Option<(P, bool)>,
}

impl Piece {
    fn map(&mut self, f: impl Fn(P) -> P, mirror: bool) {
        self.a = f(self.a);
        self.b = f(self.b);
        if let Some((c, ccw)) = self.arc {
            self.arc = Some((f(c), ccw != mirror));
        }
    }

    fn length(&self) -> f64 {
        match self.arc {
            None => self.a.sub(self.b).abs(),
            Some((c, _)) => self.a.sub(self.b).abs().min(self.a.sub(c).abs()),
        }
    }

    fn monotonic(&self) -> bool {
        let dz = self.b.z - self.a.z;
        match self.arc {
            None => dz <= 1e-3,
            Some((c, ccw)) => {
                let (entry, exit) = (self.a.x - c.x, self.b.x - c.x);
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }

    /// Moves the piece `d` to its left (a line) or changes an arc's radius by `d` (grows a G3).
    fn offset(&mut self, d: f64) {
        match self.arc {
            None => {
                let along = self.a.sub(self.b);
                let shift = quarter(along.times(d / along.abs()));
                self.a = self.a.add(shift);
                self.b = self.b.add(shift);
            }
            Some((c, ccw)) => {
                let r = self.a.sub(c).abs();
                let k = (r + if ccw { d } else { -d }) / r;
                self.a = self.a.sub(c).times(k).add(c);
                self.b = self.b.sub(c).times(k).add(c);
            }
        }
    }

    fn on_arc(&self, c: P, ccw: bool, p: P) -> bool {
        let (s, e) = (self.a.sub(c).cross(p.sub(c)), self.b.sub(c).cross(p.sub(c)));
        if ccw {
            s >= -TOL && e <= TOL
        } else {
            s <= TOL && e >= -TOL
        }
    }

    /// Where the piece crosses the layer at radius `x`: Z values, as many as there are.
    fn crossings(&self, x: f64) -> Vec<f64> {
        let mut out = Vec::new();
        match self.arc {
            None => {
                let (lo, hi) = (self.a.x.min(self.b.x), self.a.x.max(self.b.x));
                if lo > x + TOL || hi < x - TOL {
                    return out;
                }
                if (self.a.x - self.b.x).abs() < TOL {
                    out.extend([self.a.z, self.b.z]);
                } else {
                    out.push(
                        (x - self.a.x) / (self.b.x - self.a.x) * (self.b.z - self.a.z) + self.a.z,
                    );
                }
            }
            Some((c, ccw)) => {
                let r = self.a.sub(c).abs();
                let s = -(x - r - c.x) * (x + r - c.x);
                if s < -TOL {
                    return out;
                }
                let s = s.max(0.0).sqrt();
                for z in [c.z + s, c.z - s] {
                    if self.on_arc(c, ccw, P::new(z, x)) {
                        out.push(z);
                    }
                }
            }
        }
        out
    }
}

/// The moves made, in the working frame, turned back into the program's frame as they are made.
struct Out {
    frame: u8,
    at: P,
    moves: Vec<(MotionKind, P)>,
}

impl Out {
    /// A point of the working frame in the program's frame (the inverse of the frame's turns and
    /// mirrors: bit 4 a quarter turn, bit 2 X mirrored, bit 1 Z mirrored), and whether arcs
    /// change direction.
    fn world(&self, p: P) -> (P, bool) {
        match self.frame {
            0 => (p, false),
            1 => (p.conj().neg(), true),
            2 => (p.conj(), true),
            3 => (p.neg(), false),
            4 => (quarter(p), false),
            5 => (quarter(p).conj(), true),
            6 => (quarter(p).conj().neg(), true),
            _ => (quarter(p).neg(), false),
        }
    }

    fn straight(&mut self, rapid: bool, to: P) {
        let (w, _) = self.world(to);
        let kind = if rapid {
            MotionKind::Rapid
        } else {
            MotionKind::Feed
        };
        self.moves.push((kind, w));
        self.at = w;
    }

    fn feed(&mut self, to: P) {
        self.straight(false, to);
    }

    fn rapid(&mut self, to: P) {
        self.straight(true, to);
    }

    /// An arc; none when it would end where the tool is (within 10⁻⁴, the interpreter's test
    /// for equal positions).
    fn arc(&mut self, ccw: bool, c: P, to: P) {
        let (w, mirror) = self.world(to);
        let (wc, _) = self.world(c);
        if (w.z - self.at.z).abs() < 1e-4 && (w.x - self.at.x).abs() < 1e-4 {
            return;
        }
        self.moves.push((
            MotionKind::Arc {
                centre: Pos::new(wc.x, wc.z),
                clockwise: ccw == mirror,
            },
            w,
        ));
        self.at = w;
    }

    fn draw(&mut self, piece: &Piece) {
        match piece.arc {
            None => self.feed(piece.b),
            Some((c, ccw)) => self.arc(ccw, c, piece.b),
        }
    }
}

/// The contour as pieces in the working frame, with the frame.
#[derive(Clone, Debug)]
struct Path {
    pieces: Vec<Piece>,
    frame: u8,
}

impl Path {
    fn each(&mut self, f: impl Fn(P) -> P, mirror: bool) {
        for p in &mut self.pieces {
            p.map(&f, mirror);
        }
    }

    fn turn(&mut self) {
        self.each(|p| quarter(p).neg(), false);
        self.frame ^= 4;
    }

    /// Mirrors the contour so that it runs toward −Z with X decreasing overall.
    fn normalise(&mut self) {
        let (first, last) = (self.pieces[0].b, self.pieces[self.pieces.len() - 1].b);
        let d = first.sub(last);
        if d.x > 0.0 {
            self.each(P::conj, true);
            self.frame ^= 2;
        }
        if d.z < 0.0 {
            self.each(|p| p.conj().neg(), true);
            self.frame ^= 1;
        }
    }

    fn drop_short(&mut self) {
        self.pieces.retain(|p| p.length() >= 1e-3);
    }

    fn check_monotonic(&mut self) -> Result<(), String> {
        let first = &mut self.pieces[0];
        if first.b.z - first.a.z > 0.0 {
            first.a.z = first.b.z;
        }
        if self.pieces.iter().all(Piece::monotonic) {
            Ok(())
        } else {
            Err(fail("Not monotonic"))
        }
    }

    /// The contour without its lead-in moved `distance` away from the material (toward the
    /// start point's side), in steps no longer than half the shortest piece.
    fn offset(&mut self, distance: f64) -> Result<(), String> {
        if self.pieces.len() < 2 {
            return Ok(());
        }
        let lead = self.pieces[0];
        let last = self.pieces[self.pieces.len() - 1];
        let turn = lead.b.sub(lead.a).div(last.a.sub(lead.a));
        let distance = if turn.x < 0.0 { -distance } else { distance };
        self.pieces.remove(0);
        let mut done = 0.0;
        let mut steps = 0;
        while done != distance {
            steps += 1;
            if steps > 10_000 || self.pieces.is_empty() {
                return Err(fail("the profile cannot be offset by D"));
            }
            let mut step = self
                .pieces
                .iter()
                .map(|p| p.length() / 2.0)
                .fold(1e9, f64::min)
                .min((distance - done).abs());
            if distance < 0.0 {
                step = -step;
            }
            offset_step(&mut self.pieces, step, distance > 0.0)?;
            done += step;
        }
        for i in 0..self.pieces.len().saturating_sub(1) {
            let mid = self.pieces[i].b.add(self.pieces[i + 1].a).times(0.5);
            self.pieces[i].b = mid;
            self.pieces[i + 1].a = mid;
        }
        let mut lead = lead;
        if let Some(first) = self.pieces.first() {
            lead.b = first.a;
        }
        self.pieces.insert(0, lead);
        Ok(())
    }
}

/// One offset step: every piece moved, gaps bridged by arcs, neighbours trimmed to meet.
fn offset_step(pieces: &mut Vec<Piece>, step: f64, outward: bool) -> Result<(), String> {
    for p in pieces.iter_mut() {
        p.offset(step);
    }
    pieces.retain(|p| p.length() >= 1e-3);
    let mut i = 0;
    while i + 1 < pieces.len() {
        if pieces[i].b.z - pieces[i + 1].a.z > 1e-2 {
            let (mut s, mut e) = (pieces[i], pieces[i + 1]);
            s.offset(-step);
            e.offset(-step);
            let centre = s.b.add(e.a).times(0.5);
            let bridge = Piece {
                a: pieces[i].b,
                b: pieces[i + 1].a,
                arc: Some((centre, outward)),
            };
            pieces.insert(i + 1, bridge);
            i += 1;
        }
        i += 1;
    }
    let mut i = 0;
    let mut guard = 0;
    while i + 1 < pieces.len() {
        guard += 1;
        if guard > MAX_STEPS {
            return Err(fail("the profile cannot be offset by D"));
        }
        if !pieces[i].monotonic() && i > 0 {
            let drop = if pieces[i].length() < pieces[i - 1].length() {
                i
            } else {
                i - 1
            };
            pieces.remove(drop);
            i = 0;
            if pieces.len() < 2 {
                break;
            }
        }
        if pieces[i].length() < 1e-3 {
            pieces.remove(i);
            i = 0;
        } else {
            let (head, tail) = pieces.split_at_mut(i + 1);
            meet(&mut head[i], &mut tail[0])?;
        }
        i += 1;
    }
    Ok(())
}

/// Trims `p`'s end and `n`'s start to the point where they meet.
fn meet(p: &mut Piece, n: &mut Piece) -> Result<(), String> {
    let at = match (p.arc, n.arc) {
        (_, None) => {
            // n is a line: in its own frame (its end at 0, along the real axis).
            let unit = n.a.sub(n.b).conj().times(1.0 / n.a.sub(n.b).abs());
            let to_line = |q: P| q.sub(n.b).mul(unit);
            match p.arc {
                None => {
                    let (ps, pe) = (to_line(p.a), to_line(p.b));
                    if ps.x - pe.x == 0.0 {
                        return Err(fail("Cannot intersect parallel lines"));
                    }
                    let f = ps.x / (ps.x - pe.x);
                    ps.add(pe.sub(ps).times(f)).div(unit).add(n.b)
                }
                Some((c, _)) => {
                    if n.a.sub(p.b).abs() < TOL {
                        return Ok(());
                    }
                    circle_meets_line(to_line(p.b), to_line(c), unit, n.b, n.a)
                }
            }
        }
        (None, Some((c, _))) => {
            if n.a.sub(p.b).abs() < TOL {
                return Ok(());
            }
            let unit = p.a.sub(p.b).conj().times(1.0 / p.a.sub(p.b).abs());
            let to_line = |q: P| q.sub(p.b).mul(unit);
            circle_meets_line(to_line(n.b), to_line(c), unit, p.b, n.a)
        }
        (Some((pc, _)), Some((nc, _))) => {
            let a = n.a.sub(nc).abs();
            let b = p.a.sub(pc).abs();
            let c = nc.sub(pc).abs();
            let cos = (c * c + a * a - b * b) / 2.0 / a / c;
            let turn = P::new(cos, (1.0 - (cos * cos).min(1.0)).sqrt());
            turn.mul(pc.sub(nc)).times(a / c).add(nc)
        }
    };
    p.b = at;
    n.a = at;
    Ok(())
}

/// Where a circle (through `on`, about `c`, both in a line's frame) meets the line: of the two
/// points, the one nearer `near` (in the program's frame), turned back by `unit` and `origin`.
fn circle_meets_line(on: P, c: P, unit: P, origin: P, near: P) -> P {
    let b = c.sub(on).norm() - c.x * c.x;
    let b = if b < 0.0 { 0.0 } else { b.sqrt() };
    let s1 = P::new(c.z + b, 0.0).div(unit).add(origin);
    let s2 = P::new(c.z - b, 0.0).div(unit).add(origin);
    if near.sub(s1).abs() < near.sub(s2).abs() {
        s1
    } else {
        s2
    }
}

/// The pieces of `contour`'s moves in program units, the lead-in from `start` first.
fn pieces(start: Pos, contour: &super::Contour, units: Units) -> Vec<Piece> {
    let p = |q: Pos| P::new(units.from_mm(q.z), units.from_mm(q.x));
    let mut at = p(start);
    let mut lead = true;
    let mut out = Vec::new();
    for s in &contour.segments {
        let to = p(s.to);
        let arc = match s.shape {
            Shape::Line => None,
            Shape::Arc { centre, clockwise } => Some((p(centre), !clockwise)),
        };
        // The lead-in runs from the cycle's start, whatever the contour's own start.
        let a = if lead { p(start) } else { at };
        lead = false;
        out.push(Piece { a, b: to, arc });
        at = to;
    }
    out
}

fn toolpath(out: Out, start: Pos, units: Units, line: u32) -> Toolpath {
    Toolpath {
        start,
        motions: out
            .moves
            .into_iter()
            .map(|(kind, to)| Motion {
                kind: match kind {
                    MotionKind::Arc { centre, clockwise } => MotionKind::Arc {
                        centre: Pos::new(units.to_mm(centre.x), units.to_mm(centre.z)),
                        clockwise,
                    },
                    k => k,
                },
                to: Pos::new(units.to_mm(to.x), units.to_mm(to.z)),
                pass: 0,
                line,
            })
            .collect(),
    }
}

fn error(span: Span, msg: String) -> Diagnostic {
    Diagnostic::error(Code::Input, span, format!("G7X error: {msg}"))
}

/// Roughing along an offset profile (`rough.strategy` is [`Strategy::Offset`]): the moves from
/// the cycle's start (a rapid to it first), in millimetres.
pub fn rough(rough: &Rough, units: Units, span: Span) -> Result<Toolpath, Diagnostic> {
    let Strategy::Offset { distance, pockets } = rough.strategy else {
        return Err(error(span, "not an offset-profile roughing".into()));
    };
    let start = P::new(units.from_mm(rough.start.z), units.from_mm(rough.start.x));
    let mut out = Out {
        frame: 0,
        at: start,
        moves: vec![(MotionKind::Rapid, start)],
    };
    let mut path = Path {
        pieces: pieces(rough.start, &rough.contour, units),
        frame: 0,
    };
    if path.pieces.len() > 1 {
        let job = Layers {
            depth: units.from_mm(rough.depth).max(2.0 * TOL),
            retract: units.from_mm(rough.retract),
            shift: P::new(
                units.from_mm(rough.allowance_z),
                units.from_mm(rough.allowance_x),
            ),
            distance: units.from_mm(distance),
            pockets,
            turned: rough.along == super::Along::X,
        };
        job.run(&mut path, start, &mut out)
            .map_err(|m| error(span, m))?;
    }
    Ok(toolpath(out, rough.start, units, span.line))
}

/// The roughing cycle's numbers in program units.
struct Layers {
    depth: f64,
    retract: f64,
    shift: P,
    distance: f64,
    pockets: Pockets,
    turned: bool,
}

impl Layers {
    fn run(&self, path: &mut Path, start: P, out: &mut Out) -> Result<(), String> {
        path.pieces[0].a = start;
        if self.turned {
            path.turn();
        }
        path.normalise();
        path.drop_short();
        if path.pieces.is_empty() {
            return Ok(());
        }
        path.check_monotonic()?;
        path.offset(self.distance)?;
        let shift = self.shift;
        path.each(|p| p.add(shift), false);
        out.frame = path.frame;
        let begin = path.pieces[0].a;
        out.rapid(begin);
        let end = path.pieces[path.pieces.len() - 1].b;
        if end.x < begin.x {
            path.pieces.push(Piece {
                a: end,
                b: P::new(end.z, begin.x),
                arc: None,
            });
        }
        let mut walk = Walk {
            pieces: &path.pieces,
            depth: self.depth,
            escape: P::new(self.retract, self.retract),
            starts: vec![begin],
            steps: 0,
        };
        walk.pocket(self.pockets, begin, out)
    }
}

/// Walking the contour layer by layer.
struct Walk<'p> {
    pieces: &'p [Piece],
    depth: f64,
    escape: P,
    /// Where each pocket began (the first: the cycle's start).
    starts: Vec<P>,
    steps: usize,
}

/// How a piece is followed when a layer reaches it.
enum Dive {
    /// The piece does not go deeper here: the tool climbs from here on.
    Climbs,
    /// The tool followed (or stayed on) the piece.
    Followed,
}

impl Walk<'_> {
    fn tick(&mut self) -> Result<(), String> {
        self.steps += 1;
        if self.steps > MAX_STEPS.max(self.pieces.len() * 1000) {
            return Err(fail(
                "the roughing passes do not end (LinuxCNC loops here without end)",
            ));
        }
        Ok(())
    }

    fn pocket(&mut self, mode: Pockets, mut at: P, out: &mut Out) -> Result<(), String> {
        let mut i = 0;
        let mut after_first = false;
        'pocket: loop {
            let mut x = self.starts[self.starts.len() - 1].x;
            if mode == Pockets::AfterFirst && !after_first {
                while i < self.pieces.len() {
                    if let Dive::Climbs = dive(&self.pieces[i], &mut at, -1e9, out, i == 0)? {
                        break;
                    }
                    i += 1;
                }
                after_first = true;
            }
            while i < self.pieces.len() {
                self.tick()?;
                let mut guard = 0usize;
                while x - TOL > at.x {
                    x -= self.depth;
                    guard += 1;
                    if guard > MAX_STEPS {
                        return Err(fail("the cutting increment I is too small"));
                    }
                }
                if let Dive::Climbs = dive(&self.pieces[i], &mut at, x, out, i == 0)? {
                    if mode == Pockets::None {
                        for p in &self.pieces[i..] {
                            climb_only(p, &mut at, out);
                        }
                        return Ok(());
                    }
                    while i < self.pieces.len() {
                        if climb(&self.pieces[i], &mut at, out)? {
                            if after_first {
                                let last = self.starts[self.starts.len() - 1];
                                if at.x > last.x && self.starts.len() > 1 {
                                    self.starts.pop();
                                }
                                if self.starts.len() == 1 {
                                    self.starts.push(at);
                                }
                            }
                            continue 'pocket;
                        }
                        i += 1;
                    }
                    return Ok(());
                }
                if (at.x - x).abs() > TOL {
                    i += 1;
                    continue;
                }
                if let Some(next) = self.layer(i, &mut at, out) {
                    i = next;
                } else {
                    x -= self.depth;
                }
            }
            return Ok(());
        }
    }

    /// One layer from `at` along Z to the contour: the cut, the retract and the way back. The
    /// piece the walk goes on with when the layer starts on another piece's entry.
    fn layer(&self, i: usize, at: &mut P, out: &mut Out) -> Option<usize> {
        for (j, p) in self.pieces.iter().enumerate().skip(i) {
            let hits = p.crossings(at.x);
            let Some(&z) = (if j != i { hits.first() } else { hits.last() }) else {
                continue;
            };
            let distance = (z - at.z).abs();
            if z - TOL > at.z {
                continue;
            }
            if distance < TOL {
                if j == i {
                    continue;
                }
                if at.sub(p.a).abs() < TOL {
                    return Some(j);
                }
                return None;
            }
            let mut dest = P::new(z, at.x);
            out.feed(dest);
            let k = (distance / 2.0 / self.escape.z).min(1.0);
            let escape = self.escape.times(k);
            dest = dest.add(escape);
            out.rapid(dest);
            out.rapid(at.sub(escape.conj()));
            out.straight(i == 0, *at);
            return None;
        }
        // No piece crossed: the layer is done where it is (LinuxCNC would not end here).
        None
    }
}

/// Follows a piece downward to the layer at `x` (a line) or along its arc.
fn dive(piece: &Piece, at: &mut P, x: f64, out: &mut Out, fast: bool) -> Result<Dive, String> {
    match piece.arc {
        None => {
            if piece.a.x <= piece.b.x + TOL {
                return Ok(Dive::Climbs);
            }
            let to = if x < piece.b.x {
                piece.b
            } else {
                let Some(&z) = piece.crossings(x).first() else {
                    return Err(fail("x too large in straight dive"));
                };
                P::new(z, x)
            };
            out.straight(fast, to);
            *at = to;
            Ok(Dive::Followed)
        }
        Some((c, ccw)) => {
            if at.sub(piece.b).abs() < TOL || at.z - piece.b.z <= TOL {
                *at = piece.b;
                return Ok(Dive::Followed);
            }
            let mut hits = piece.crossings(x);
            if hits.is_empty() {
                hits = piece.crossings(x - TOL);
            }
            if ccw {
                if at.z - TOL > c.z {
                    return Ok(Dive::Climbs);
                }
                let to = match hits.last() {
                    Some(&z) if z <= c.z => P::new(z, x),
                    _ => piece.b,
                };
                out.arc(ccw, c, to);
                *at = to;
            } else {
                if at.z <= c.z {
                    return Ok(Dive::Climbs);
                }
                match hits.first() {
                    None => {
                        out.arc(ccw, c, piece.b);
                        *at = piece.b;
                    }
                    Some(&z) if z < c.z => {}
                    Some(&z) => {
                        let to = P::new(z, x);
                        out.arc(ccw, c, to);
                        *at = to;
                    }
                }
            }
            Ok(Dive::Followed)
        }
    }
}

/// The top of a G3 piece's circle, where a climb along it ends when the arc runs over it.
fn top_of(piece: &Piece, c: P) -> P {
    if piece.b.z < c.z {
        P::new(c.z, c.x + piece.a.sub(c).abs())
    } else {
        piece.b
    }
}

/// Follows a piece upward: `true` when it does not climb (a pocket begins).
fn climb(piece: &Piece, at: &mut P, out: &mut Out) -> Result<bool, String> {
    match piece.arc {
        None => {
            if piece.b.x + TOL < piece.a.x {
                return Ok(true);
            }
            if at.sub(piece.a).abs() > TOL {
                return Err(fail("How did we get here?"));
            }
            out.feed(piece.b);
            *at = piece.b;
            Ok(false)
        }
        Some((c, false)) => {
            if at.z > c.z {
                return Ok(true);
            }
            if at.sub(piece.b).abs() > 1e-3 {
                out.arc(false, c, piece.b);
            }
            *at = piece.b;
            Ok(false)
        }
        Some((c, true)) => {
            if at.z < c.z {
                return Ok(true);
            }
            let to = top_of(piece, c);
            if at.sub(to).abs() > 1e-3 {
                out.arc(true, c, to);
            }
            *at = to;
            Ok(true)
        }
    }
}

/// Follows the climbing parts of a piece only (pockets left): from where the layer meets it.
fn climb_only(piece: &Piece, at: &mut P, out: &mut Out) {
    let hits = piece.crossings(at.x);
    match piece.arc {
        None => {
            if piece.b.x < piece.a.x {
                return;
            }
            let Some(&z) = hits.first() else { return };
            at.z = z;
            out.feed(*at);
            out.feed(piece.b);
            *at = piece.b;
        }
        Some((c, false)) => {
            let Some(&z) = hits.last() else { return };
            if z > c.z {
                return;
            }
            at.z = z;
            out.feed(*at);
            if at.sub(piece.b).abs() > 1e-3 {
                out.arc(false, c, piece.b);
            }
            *at = piece.b;
        }
        Some((c, true)) => {
            let Some(&z) = hits.first() else { return };
            if z < c.z {
                return;
            }
            at.z = z;
            out.feed(*at);
            let to = top_of(piece, c);
            if at.sub(to).abs() > 1e-3 {
                out.arc(true, c, to);
            }
            *at = to;
        }
    }
}

/// Finishing along the offset profile (`finish.offsets`): each pass a rapid to the offset
/// contour's lead-in start and end, then along it; the distance of pass k (counted down from
/// `passes`) is (k−1)·(first−last)/passes + last.
pub fn finish(finish: &Finish, units: Units, span: Span) -> Result<Toolpath, Diagnostic> {
    let offsets = finish.offsets.unwrap_or(FinishOffsets {
        first: 0.0,
        last: 0.0,
        passes: 1.0,
    });
    let start = P::new(units.from_mm(finish.start.z), units.from_mm(finish.start.x));
    let mut out = Out {
        frame: 0,
        at: start,
        moves: vec![(MotionKind::Rapid, start)],
    };
    let mut path = Path {
        pieces: pieces(finish.start, &finish.contour, units),
        frame: 0,
    };
    if path.pieces.len() > 1 {
        finish_passes(&mut path, start, offsets, units, &mut out).map_err(|m| error(span, m))?;
    }
    Ok(toolpath(out, finish.start, units, span.line))
}

fn finish_passes(
    path: &mut Path,
    start: P,
    offsets: FinishOffsets,
    units: Units,
    out: &mut Out,
) -> Result<(), String> {
    path.pieces[0].a = start;
    // The frame: from the contour without its lead-in, turned when a piece of it is not
    // monotonic along Z.
    let mut probe = path.clone();
    probe.pieces.remove(0);
    probe.normalise();
    if !probe.pieces.iter().all(Piece::monotonic) {
        probe.turn();
        probe.normalise();
    }
    probe.check_monotonic()?;
    if probe.frame & 4 != 0 {
        path.turn();
    }
    path.normalise();
    path.drop_short();
    path.check_monotonic()?;
    out.frame = path.frame;
    let (first, last) = (units.from_mm(offsets.first), units.from_mm(offsets.last));
    let passes = offsets.passes;
    let count = passes.clamp(0.0, 10_000.0) as u32;
    for k in (1..=count).rev() {
        let distance = f64::from(k - 1) * (first - last) / passes + last;
        let mut pass = path.clone();
        pass.offset(distance)?;
        out.rapid(pass.pieces[0].a);
        out.rapid(pass.pieces[0].b);
        for p in &pass.pieces[1..] {
            out.draw(p);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::turning::{Along, Contour, Segment};

    fn line(x: f64, z: f64) -> Segment {
        Segment {
            to: Pos::new(x, z),
            shape: Shape::Line,
            line: 5,
        }
    }

    /// A shoulder: from (X10 Z2) radius down to X5 at Z0, along to Z−10, up to X10.
    fn shoulder() -> Contour {
        Contour {
            start: Pos::new(10.0, 2.0),
            segments: vec![line(5.0, 0.0), line(5.0, -10.0), line(10.0, -10.0)],
        }
    }

    fn moves(path: &Toolpath) -> Vec<(char, f64, f64)> {
        path.motions
            .iter()
            .map(|m| {
                let k = match m.kind {
                    MotionKind::Rapid => 'R',
                    MotionKind::Feed => 'F',
                    _ => 'A',
                };
                (k, m.to.x, m.to.z)
            })
            .collect()
    }

    fn same(got: &[(char, f64, f64)], want: &[(char, f64, f64)]) {
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert!(
                g.0 == w.0 && (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9,
                "{g:?} != {w:?} in {got:?}"
            );
        }
    }

    #[test]
    fn layers_end_on_the_contour_with_a_45_degree_retract() {
        let rough = Rough {
            along: Along::Z,
            start: Pos::new(10.0, 2.0),
            depth: 2.0,
            retract: 0.5,
            allowance_x: 0.0,
            allowance_z: 0.0,
            pockets: true,
            contour: shoulder(),
            strategy: Strategy::Offset {
                distance: 0.0,
                pockets: Pockets::All,
            },
            then_outline: None,
        };
        let path = rough_path(&rough);
        // Layers at X10, 8, 6 (2 apart from the start's X10); each meets the lead-in line
        // (X10 Z2 → X5 Z0: z = 2 − 2·(10 − x)/5, so 1.2 at X8 and 0.4 at X6), cuts to the
        // shoulder at Z−10, retracts 0.5 in X and Z and rapids back. The layer at X4 lies below
        // the contour's X5: the tool goes to X5 Z0 and follows the contour out.
        same(
            &moves(&path),
            &[
                ('R', 10.0, 2.0),
                ('R', 10.0, 2.0),
                ('R', 10.0, 2.0),
                ('F', 10.0, -10.0),
                ('R', 10.5, -9.5),
                ('R', 10.5, 1.5),
                ('R', 10.0, 2.0),
                ('R', 8.0, 1.2),
                ('F', 8.0, -10.0),
                ('R', 8.5, -9.5),
                ('R', 8.5, 0.7),
                ('R', 8.0, 1.2),
                ('R', 6.0, 0.4),
                ('F', 6.0, -10.0),
                ('R', 6.5, -9.5),
                ('R', 6.5, -0.1),
                ('R', 6.0, 0.4),
                ('R', 5.0, 0.0),
                ('F', 5.0, -10.0),
                ('F', 10.0, -10.0),
            ],
        );
    }

    fn rough_path(rough: &Rough) -> Toolpath {
        super::rough(rough, Units::Mm, Span::default()).unwrap()
    }

    #[test]
    fn finishing_follows_the_contour_once_from_a_rapid_to_its_first_point() {
        let f = Finish {
            start: Pos::new(10.0, 2.0),
            contour: shoulder(),
            offsets: None,
        };
        let path = finish(&f, Units::Mm, Span::default()).unwrap();
        same(
            &moves(&path),
            &[
                ('R', 10.0, 2.0),
                ('R', 10.0, 2.0),
                ('R', 5.0, 0.0),
                ('F', 5.0, -10.0),
                ('F', 10.0, -10.0),
            ],
        );
    }

    #[test]
    fn a_contour_that_turns_back_in_z_is_refused() {
        // Along Z the contour must not turn back toward the start: Z−10 then Z−4 does.
        let mut contour = shoulder();
        contour.segments.push(line(12.0, -4.0));
        let rough = Rough {
            along: Along::Z,
            start: Pos::new(10.0, 2.0),
            depth: 1.0,
            retract: 0.5,
            allowance_x: 0.0,
            allowance_z: 0.0,
            pockets: true,
            contour,
            strategy: Strategy::Offset {
                distance: 0.0,
                pockets: Pockets::All,
            },
            then_outline: None,
        };
        let e = super::rough(&rough, Units::Mm, Span::default()).unwrap_err();
        assert_eq!(e.message, "G7X error: Not monotonic");
    }
}
