//! The machine-neutral threading model. Every controller's cycle lowers into a [`Job`]; everything a
//! user sees (expanded G-code, pass tables, plots, checks) is derived from it, so views cannot disagree.
//!
//! Conventions: lengths in millimetres, X as a radius, absolute positions. "Depth" is measured from
//! the crest line along the infeed direction.

pub mod area;
pub mod plan;
pub mod standard;

use serde::Serialize;

use crate::diag::Span;
use crate::units::{Pos, Units, Vec2};

pub use plan::{plan_passes, DepthLaw, Pass, PassKind, PassPlan};

/// Which way depth grows: an external thread is cut toward −X, an internal one toward +X. A face
/// thread (its long axis is X) is cut toward −Z (`FaceFront`, the usual face seen from the tailstock)
/// or toward +Z (`FaceBack`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    External,
    Internal,
    FaceFront,
    FaceBack,
}

impl Side {
    /// Unit vector in which depth grows.
    pub fn infeed(self) -> Vec2 {
        match self {
            Side::External => Vec2::new(-1.0, 0.0),
            Side::Internal => Vec2::new(1.0, 0.0),
            Side::FaceFront => Vec2::new(0.0, -1.0),
            Side::FaceBack => Vec2::new(0.0, 1.0),
        }
    }

    /// Whether the thread's long axis is X (a face thread) rather than Z.
    pub fn is_face(self) -> bool {
        matches!(self, Side::FaceFront | Side::FaceBack)
    }

    /// Unit vector of the thread's long axis (+Z for turned threads, +X for face threads): the
    /// direction of the lateral offsets of [`Infeed`] and of the shift between starts.
    pub fn lateral(self) -> Vec2 {
        if self.is_face() {
            Vec2::new(1.0, 0.0)
        } else {
            Vec2::new(0.0, 1.0)
        }
    }

    /// A vector's component along the long axis.
    pub fn along(self, v: Vec2) -> f64 {
        if self.is_face() {
            v.x
        } else {
            v.z
        }
    }

    /// Unit vector pointing away from the part (the way the tool retracts).
    pub fn outward(self) -> Vec2 {
        self.infeed().scale(-1.0)
    }

    /// The side of a cycle that starts at radius `start_x` and cuts toward radius `toward_x`:
    /// external when it cuts down, internal when it cuts up, `None` when it does not move at the
    /// program's resolution (`x_tol`, [`Resolution::x`](crate::units::Resolution::x)).
    pub fn of_cut(start_x: f64, toward_x: f64, x_tol: crate::units::Tolerance) -> Option<Side> {
        match x_tol.sign(start_x - toward_x) {
            1 => Some(Side::External),
            -1 => Some(Side::Internal),
            _ => None,
        }
    }
}

/// The thread's form on the part: the crest line (depth 0) from the thread's start to its end.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Geometry {
    /// Crest at the thread start: the reference point from which every depth is measured.
    pub crest_start: Pos,
    /// Crest at the thread end (the programmed length and taper).
    pub crest_end: Pos,
    /// Total thread depth (radial).
    pub depth: f64,
    pub side: Side,
}

impl Geometry {
    /// The displacement of one pass from its start to its programmed end.
    pub fn travel(&self) -> Vec2 {
        self.crest_end.minus(self.crest_start)
    }

    /// Radial taper over the thread: start X − end X (positive when the start is larger).
    pub fn taper(&self) -> f64 {
        self.crest_start.x - self.crest_end.x
    }
}

/// How far the spindle-synchronised axis travels per revolution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Lead {
    /// Lead (mm per revolution) along the long axis at the thread start.
    pub lead: f64,
    /// Change of lead per revolution (variable-lead threads); 0 for a constant lead.
    pub dlead: f64,
    /// Number of starts; each start is the same thread, lead/starts further along the axis.
    pub starts: u32,
    /// The spindle angle (degrees, 0 ≤ φ < 360, after the spindle's one-revolution signal) at
    /// which every synchronised run of the first start begins: Fanuc's and Haas's `Q` on G32/G92/
    /// G76, Sinumerik's `SF=` on G33 and CYCLE97's NSP. 0 where the program states none. Further
    /// starts begin where [`indexing`](Lead::indexing) puts them ([`start_phase`](Lead::start_phase)).
    pub phase_deg: f64,
    /// How the tool reaches the further starts.
    pub indexing: StartIndexing,
}

/// How a multi-start thread's further starts are reached. Both cut the same grooves: a start
/// lead/starts further along the axis is the same helix turned by 360°/starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StartIndexing {
    /// Each further start begins lead/starts further from the part along the axis, at the same
    /// spindle angle; every start is cut at one depth before the next depth (OmniTurn, GSK G92 L,
    /// APT MULTRD). A program that cuts each start as a cycle of its own with its own start angle
    /// (Fanuc/Haas `Q`) reads as one job per start, each with one start and its `phase_deg`.
    Shift,
    /// Each further start begins at the same point with the spindle angle advanced by
    /// 360°/starts; each start is cut to full depth, all its passes, before the next (Sinumerik
    /// CYCLE97 NUMT: "the whole motion sequence is repeated for each further thread turn").
    Angle,
}

impl Lead {
    pub const fn constant(lead: f64) -> Lead {
        Lead {
            lead,
            dlead: 0.0,
            starts: 1,
            phase_deg: 0.0,
            indexing: StartIndexing::Shift,
        }
    }

    /// The spindle angle (degrees, 0 ≤ a < 360) at which start `s` (0-based) begins.
    pub fn start_phase(&self, s: u32) -> f64 {
        let turn = match self.indexing {
            StartIndexing::Shift => 0.0,
            StartIndexing::Angle => 360.0 * f64::from(s) / f64::from(self.starts.max(1)),
        };
        (self.phase_deg + turn).rem_euclid(360.0)
    }

    /// Axial distance between adjacent starts.
    pub fn start_spacing(&self) -> f64 {
        self.lead / f64::from(self.starts.max(1))
    }
}

/// Which side of the tool cuts as the passes go deeper. Directions are along the thread's long axis
/// ([`Side::lateral`]): +Z for turned threads, +X for face threads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Flank {
    /// The tip rides down the left flank of the groove: the infeed point moves toward +Z.
    Left,
    /// The tip rides down the right flank: the infeed point moves toward −Z.
    Right,
    /// Straight in along the groove's axis.
    Centre,
}

impl Flank {
    /// Sign of the lateral (+Z) shift as depth grows.
    pub fn sign(self) -> f64 {
        match self {
            Flank::Left => 1.0,
            Flank::Right => -1.0,
            Flank::Centre => 0.0,
        }
    }
}

/// The infeed law: where each pass's infeed point sits along the thread axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "law", rename_all = "lowercase")]
pub enum Infeed {
    /// Every pass starts at the same axial position.
    Radial,
    /// Every pass on one flank: the lateral shift is depth·tan(angle) from the reference point.
    Flank { flank: Flank, angle_deg: f64 },
    /// Passes alternate between `first` and `second`, all inside one groove: `first` passes shift as
    /// in single-flank infeed; `second` passes are their mirror image about the groove's axis
    /// (`Centre`: on the axis). With `first` = `Centre` the odd passes stay on the plunge line and
    /// the even passes ride `second`'s flank (APT THREAD OPTION 2/4: "only offsets the tool on even
    /// numbered cuts").
    Alternating {
        first: Flank,
        second: Flank,
        angle_deg: f64,
    },
}

impl Infeed {
    /// The lateral (+Z) offset of a pass at depth `depth`, pass index `n` (1-based, rough passes),
    /// for a thread of total depth `total`.
    pub fn offset(&self, n: u32, depth: f64, total: f64) -> f64 {
        match *self {
            Infeed::Radial => 0.0,
            Infeed::Flank { flank, angle_deg } => flank.sign() * depth * tan_deg(angle_deg),
            Infeed::Alternating {
                first,
                second,
                angle_deg,
            } => {
                let single = first.sign() * depth * tan_deg(angle_deg);
                let axis = self.axis(total);
                if first == Flank::Centre {
                    return if n % 2 == 1 {
                        0.0
                    } else {
                        second.sign() * depth * tan_deg(angle_deg)
                    };
                }
                if n % 2 == 1 {
                    single
                } else {
                    match second {
                        Flank::Centre => axis,
                        _ => 2.0 * axis - single,
                    }
                }
            }
        }
    }
}

impl Infeed {
    /// The lateral offset of the groove's axis: where a full-depth pass on the axis would sit.
    pub fn axis(&self, total: f64) -> f64 {
        match *self {
            Infeed::Radial => 0.0,
            Infeed::Flank { flank, angle_deg }
            | Infeed::Alternating {
                first: flank,
                angle_deg,
                ..
            } => flank.sign() * total * tan_deg(angle_deg),
        }
    }
}

pub fn tan_deg(deg: f64) -> f64 {
    deg.to_radians().tan()
}

/// Where finishing passes sit along the axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FinishPosition {
    /// At the axial position of the last rough pass (GSK G78 §7 note 2, Fanuc G76).
    LastRough,
    /// On the groove's axis.
    Axis,
}

/// How each pass begins: straight at the infeed point, or screwed in along a synchronised ramp.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Entry {
    /// A rapid move straight to the infeed point.
    Direct,
    /// A rapid move to a point `outward` away from the part and `before` ahead of the infeed point
    /// along the thread, then a synchronised move into the infeed point.
    Ramp { outward: f64, before: f64 },
}

/// How each pass ends.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Exit {
    /// The thread move ends at the programmed end; the retract is a rapid move.
    Straight,
    /// A synchronised pull-out (tail-out, chamfer): it starts `start_before` ahead of the programmed
    /// end (0: at the end; negative: past it), runs `length` along the axis and rises `outward`.
    PullOut {
        start_before: f64,
        length: f64,
        outward: f64,
    },
    /// Every pass's thread move ends at the programmed end Z, whatever the pass's lateral offset (a
    /// flank infeed moves only where a pass starts), then the tool leaves for the retract X. That X
    /// keeps at least the clearance it has at the thread start when a taper climbs toward the end.
    /// `run_on` 0: a rapid straight out. `run_on` r > 0: a synchronised pull-out that travels r
    /// times its X travel beyond the end (OmniTurn G33 P: "it will travel beyond Z the same amount
    /// as it has to travel in X to reach the retraction position", r = 1).
    ToRetract { run_on: f64 },
    /// The same pull-out cut with linear (feed) interpolation, not synchronised: APT THREAD cuts
    /// chamfers outside 30–60° this way.
    FeedOut {
        start_before: f64,
        length: f64,
        outward: f64,
    },
}

/// Where the tool goes between passes and at the end.
///
/// For a face thread ([`Side::is_face`]) the roles swap: the tool retracts to `z` after each pass
/// and returns along X to `x`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Retract {
    /// Absolute X (radius) the tool retracts to after each pass.
    pub x: f64,
    /// Absolute Z the tool returns to before the next pass.
    pub z: f64,
}

/// How the tool travels between passes and where the cycle leaves it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ReturnPath {
    /// After each pass: rapid out to `retract.x`, rapid back along Z to `retract.z`; after the last
    /// pass, rapid to the job's start if not there (Fanuc G76/G92, GSK G78).
    Box,
    /// LinuxCNC G76 (`shared/reference/linuxcnc-g76.md` §1.4): each pass starts with a rapid to its
    /// own "back" point, `clearance` outward of the pass's cut X at the Z where the pass (or its entry
    /// ramp) begins, ends with a radial rapid out to that same X, and the next pass's back point is
    /// reached by a diagonal rapid. An entry ramp is preceded by a synchronised radial move from the
    /// back point to the ramp's start, at the ramp's rate along its path. After the last pass the tool
    /// rapids to `end` (always emitted, even when it is a zero-length move).
    Diagonal { clearance: f64, end: Pos },
    /// A cycle with a start point of its own, the retract point (Sinumerik CYCLE97: "approach of
    /// the starting point determined in the cycle … with G0"): the tool first rapids there from
    /// wherever it is (a move that is always made, even of zero length), every pass then runs as
    /// in [`Box`](ReturnPath::Box), and the tool stays at the retract point after the last pass.
    BoxAtRetract,
}

/// One threading cycle in machine-neutral terms.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Job {
    /// Source line of the block that completed the cycle.
    pub line: u32,
    #[serde(skip)]
    pub span: Span,
    pub controller: &'static str,
    /// The program's units at the cycle, for output.
    pub units: Units,
    /// Where the cycle starts and where it ends (GSK's point A).
    pub start: Pos,
    pub geometry: Geometry,
    pub lead: Lead,
    pub plan: PassPlan,
    pub infeed: Infeed,
    pub finish_at: FinishPosition,
    /// Included angle of the tool (degrees), for chip areas and plots.
    pub tool_angle_deg: f64,
    pub entry: Entry,
    pub exit: Exit,
    pub retract: Retract,
    pub return_path: ReturnPath,
}

impl Job {
    /// Where the tool is when the cycle is over.
    pub fn end_point(&self) -> Pos {
        match self.return_path {
            ReturnPath::Box => self.start,
            ReturnPath::Diagonal { end, .. } => end,
            ReturnPath::BoxAtRetract => Pos::new(self.retract.x, self.retract.z),
        }
    }

    /// The pass table: depths, increments, infeed points, chip areas.
    pub fn passes(&self) -> crate::diag::Result<Vec<Pass>> {
        plan_passes(self)
    }
}
