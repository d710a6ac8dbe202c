//! The part as the program turns it, for the blank at each thread (issue 23): with the stock's
//! diameter given (`--stock-diameter`), every feed and arc move of the program and every move of
//! its turning cycles cut the bar ([`crate::part`]); at a thread, where the program has turned the
//! bar below the stock's diameter along the thread, the blank's surface is the turned diameter,
//! not the bar's. A fact from the program: the turned surface is measured, not assumed.
//!
//! Thread moves cut nothing here (the thread's teeth stay in the revolved section), and rapids cut
//! nothing. The tool is taken as a point on a turning tool's body (moves as programmed, G40).

use crate::gcode::{MotionMode, PlainMove};
use crate::part::{Body, Dim, Part, Stock, Tool};
use crate::threads::Thread;
use crate::toolpath::{Motion, MotionKind};
use crate::turning::TurningJob;
use crate::units::{Pos, Units};

/// How far beyond the stock's face the bar is taken to reach toward the chuck when its length is
/// not given (mm): longer than any lathe part, so that the bar's far end is never a surface.
const ASSUMED_LENGTH: f64 = 10_000.0;
/// Points along a thread at which its blank's surface is looked up.
const SAMPLES: usize = 16;

/// The part the program turns, once its units are known (the stock is given in them).
pub(super) struct Turned {
    stock_diameter: Option<f64>,
    stock_start: Option<f64>,
    part: Option<Part>,
    /// The part could not hold the stock (a refusal is `check`'s options' business, not this).
    failed: bool,
}

impl Turned {
    pub(super) fn new(stock_diameter: Option<f64>, stock_start: Option<f64>) -> Turned {
        Turned {
            stock_diameter,
            stock_start,
            part: None,
            failed: false,
        }
    }

    /// The part, made from the stock at the first move (in the program's `units` then).
    fn part(&mut self, units: Units, tolerance: f64) -> Option<&mut Part> {
        if self.part.is_none() && !self.failed {
            let d = self.stock_diameter?;
            let stock = Stock {
                diameter: Dim::given(units.to_mm(d)),
                face: Dim::given_or(self.stock_start.map(|z| units.to_mm(z)), 0.0),
                length: Dim::assumed(ASSUMED_LENGTH),
                bore: Dim::assumed(0.0),
            };
            match Part::new(&stock, tolerance) {
                Ok(p) => self.part = Some(p),
                Err(_) => self.failed = true,
            }
        }
        self.part.as_mut()
    }

    /// A plain block's move: a feed or an arc from a known start cuts the bar.
    pub(super) fn plain(&mut self, mv: &PlainMove, units: Units, tolerance: f64) {
        let Some(from) = mv.from.known() else {
            return;
        };
        let kind = match (mv.mode, mv.centre) {
            (MotionMode::Feed, _) => MotionKind::Feed,
            (MotionMode::ArcCw, Some(centre)) => MotionKind::Arc {
                centre,
                clockwise: true,
            },
            (MotionMode::ArcCcw, Some(centre)) => MotionKind::Arc {
                centre,
                clockwise: false,
            },
            (MotionMode::ArcCw | MotionMode::ArcCcw, None) => MotionKind::Feed,
            _ => return,
        };
        let m = Motion {
            kind,
            to: mv.to,
            pass: 0,
            line: 0,
        };
        self.cut(from, &m, units, tolerance);
    }

    /// A turning cycle's feed and arc moves cut the bar, from the cycle's start.
    pub(super) fn turning(&mut self, job: &TurningJob, tolerance: f64) {
        let Ok(path) = crate::turning::toolpath(job) else {
            return;
        };
        for (from, m) in path.segments() {
            if matches!(m.kind, MotionKind::Feed | MotionKind::Arc { .. }) {
                self.cut(from, m, job.units, tolerance);
            }
        }
    }

    fn cut(&mut self, from: Pos, m: &Motion, units: Units, tolerance: f64) {
        if let Some(part) = self.part(units, tolerance) {
            // A move the part refuses (beyond what it holds) leaves it as it was.
            let _ = part.cut(from, m, &Tool::point(Body::Turning));
        }
    }

    /// The stock's diameter at `t`, in its program's units, as the program turned it: the
    /// outermost material along the thread's crest line where that lies below the bar's diameter;
    /// `None` where the program did not turn the bar there (the bar's diameter stands) or the
    /// thread is internal.
    pub(super) fn diameter_at(&self, t: &Thread) -> Option<f64> {
        let part = self.part.as_ref()?;
        let g = &t.job.geometry;
        if g.side != crate::thread::Side::External {
            return None;
        }
        let bar = part.stock().diameter.value / 2.0;
        let outer = (0..=SAMPLES)
            .map(|i| {
                let k = i as f64 / SAMPLES as f64;
                g.crest_start.z + (g.crest_end.z - g.crest_start.z) * k
            })
            .filter_map(|z| part.radius_at(z).map(|r| r.outer))
            .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))))?;
        (outer < bar - part.tolerance()).then(|| t.job.units.from_mm(2.0 * outer))
    }
}
