//! The contact step of one pair as a pipeline of five named stages: 5b–5f of
//! stage 5 (contact forces) of the explicit step (docs/architecture.md §3),
//! after 5a, where [`crate::ContactEffect`] places the tools and updates the
//! blank's nodal geometry.
//!
//! [`crate::ContactPair::step`] runs them in this order, timing each into the
//! pair's [`crate::ContactTiming`]:
//!
//! | stage | module | reads | writes |
//! |---|---|---|---|
//! | 5b broad phase | [`broad_phase`] | node positions, thickness, the tool's box, [`LastProjection`] | [`Candidates::points`]; opens points beyond the box margin |
//! | 5c narrow phase | [`narrow_phase`] | the candidates, [`LastProjection::hint`] | [`Candidates::near`] (one projection per candidate) |
//! | 5d normal | [`normal`] | the projections, nodal geometry, velocities, masses | [`LastProjection`], the [`Batch`] of touching points (pressure, slip increment, kinematics); opens the rest |
//! | 5e friction | [`friction`] | the [`Batch`] and the points' friction history | the batch's new states and outputs |
//! | 5f scatter | [`scatter`] | the [`Batch`] | nodal forces, the tool's reaction, energies, the per-point results and history |
//!
//! Every stage writes each point's answer into that point's own slot and
//! every sum (forces, reactions, energies) is taken in pair-point order by
//! one thread, so the results are the same bits on any number of threads.
//! The per-point arrays live on the pair; the stages borrow them through
//! [`PointsMut`] (what a step updates per point), [`LastProjection`] (what the
//! last projection left), [`Candidates`] and [`Batch`] (the step's scratch).

pub(crate) mod broad_phase;
pub(crate) mod friction;
pub(crate) mod narrow_phase;
pub(crate) mod normal;
pub(crate) mod scatter;

use plugins_api::kinematics::cayley_rotate;
use plugins_api::{
    Aabb, Mat3, PointNeeds, PointState, ProjectionHint, RigidVelocity, StepInput, StepOutput,
    ToolRegion, ToolSurface, Vec3,
};

use crate::PointStatus;
use crate::penalty::PenaltySettings;

pub(crate) use narrow_phase::Near;

/// Candidate nodes per parallel task.
pub(crate) const PARALLEL_CHUNK: usize = 64;

/// Contact points per parallel friction task.
pub(crate) const FRICTION_CHUNK: usize = 256;

/// Whether `n` points are worth a parallel loop: more than
/// [`crate::ContactPair::PARALLEL_MIN_CANDIDATES`] and more than one rayon
/// thread (on one thread, handing the loop to the pool's worker only costs a
/// wake-up and the data's trip to another core).
pub(crate) fn parallel(n: usize) -> bool {
    n > crate::ContactPair::PARALLEL_MIN_CANDIDATES && rayon::current_num_threads() > 1
}

/// A pair's enforcement settings (from its [`crate::PairSpec`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Settings {
    /// Normal enforcement.
    pub penalty: PenaltySettings,
    /// Reach beyond half the thickness from the tool's box and surface (mm).
    pub search_margin: f64,
    /// Deepest penetration taken as contact, in blank thicknesses (-).
    pub max_penetration: f64,
    /// Skip open nodes that provably cannot reach the tool.
    pub skip_far: bool,
}

/// Where the tool is in this step and how it moves.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ToolStep {
    /// The tool's bounding box (global frame).
    pub bbox: Aabb,
    /// The tool's pose origin (mm).
    pub origin: Vec3,
    /// Global → tool frame rotation (the pose's rotation transposed).
    pub to_local: Mat3,
    /// Tool → global frame rotation (the pose's rotation).
    pub to_global: Mat3,
    /// The tool's rigid velocity.
    pub velocity: RigidVelocity,
    /// The rigid rotation of the step when the law reads it, else the identity.
    pub rotation: Mat3,
}

impl ToolStep {
    /// The tool's placement for a step of `dt` (s); the step's rotation is
    /// computed only when `needs` asks for [`PointNeeds::TOOL_ROTATION`].
    pub fn new(tool: &dyn ToolSurface, needs: PointNeeds, dt: f64) -> Self {
        let pose = tool.pose();
        let velocity = tool.velocity();
        let rotation = if needs.contains(PointNeeds::TOOL_ROTATION) {
            // The rigid rotation of the step (Hughes–Winget / Cayley of Δt ω).
            let a = velocity.angular * (0.5 * dt);
            Mat3::from_columns(&[
                cayley_rotate(&a, &Vec3::x()),
                cayley_rotate(&a, &Vec3::y()),
                cayley_rotate(&a, &Vec3::z()),
            ])
        } else {
            Mat3::identity()
        };
        Self {
            bbox: tool.bounding_box(),
            origin: pose.translation,
            to_local: pose.rotation.transpose(),
            to_global: pose.rotation,
            velocity,
            rotation,
        }
    }

    /// A global position in the tool's own frame (mm).
    #[inline]
    pub fn local(&self, x: &Vec3) -> Vec3 {
        self.to_local * (x - self.origin)
    }
}

/// The per-point state and results a step updates, borrowed from the pair
/// (one slot per pair point).
pub(crate) struct PointsMut<'a> {
    /// Open / stick / slip.
    pub status: &'a mut [PointStatus],
    /// Friction history.
    pub friction: &'a mut [PointState],
    /// Contact pressure (MPa).
    pub pressure: &'a mut [f64],
    /// Friction traction on the blank (MPa).
    pub traction: &'a mut [Vec3],
    /// Critical shear stress (MPa).
    pub tau_c: &'a mut [f64],
    /// Accumulated slip length (mm).
    pub slip: &'a mut [f64],
    /// Tool normal of the point's last contact.
    pub n_old: &'a mut [Vec3],
    /// Contact force on the node in the last step (N), for the work sums.
    pub force: &'a mut [Vec3],
}

impl PointsMut<'_> {
    /// Mark point `k` open: no pressure, no traction, history cleared.
    #[inline]
    pub fn open(&mut self, k: usize) {
        if self.status[k] != PointStatus::Open {
            self.status[k] = PointStatus::Open;
            self.friction[k] = PointState::default();
            self.pressure[k] = 0.0;
            self.traction[k] = Vec3::zeros();
            self.tau_c[k] = 0.0;
        }
    }
}

/// Per pair point, what its last projection left: the warm start of the
/// next one and the record that `skip_far` bounds the motion from.
#[derive(Clone, Debug)]
pub(crate) struct LastProjection {
    /// Warm start on the tool; `None` before the first projection.
    pub hint: Vec<Option<ProjectionHint>>,
    /// The tool's flat or curved region around the last answer, if any
    /// ([`ToolSurface::region`]).
    pub region: Vec<Option<ToolRegion>>,
    /// Unsigned distance from the tool (mm; `-∞` before the first).
    pub dist: Vec<f64>,
    /// Position in the tool's local frame then (mm).
    pub local: Vec<Vec3>,
}

impl LastProjection {
    /// No projection yet for `m` points.
    pub fn new(m: usize) -> Self {
        Self {
            hint: vec![None; m],
            region: vec![None; m],
            dist: vec![f64::NEG_INFINITY; m],
            local: vec![Vec3::zeros(); m],
        }
    }
}

/// The step's candidates (scratch, reused from step to step).
#[derive(Clone, Debug, Default)]
pub(crate) struct Candidates {
    /// Pair points to project, in pair-point order (5b).
    pub points: Vec<u32>,
    /// Their projections, same order (5c).
    pub near: Vec<Near>,
    /// The region the tool gave around each new projection, same order as
    /// `near`; read only where `near[j].projected` (a point a region
    /// answered keeps the region it has). Apart from [`Near`] so that a
    /// region's answer does not move a region's bytes; as long as the
    /// pair's points, so that it never grows in a step.
    pub regions: Vec<Option<ToolRegion>>,
}

impl Candidates {
    /// Scratch for a pair of `m` points.
    pub fn new(m: usize) -> Self {
        Self {
            points: Vec::with_capacity(m),
            near: Vec::with_capacity(m),
            regions: vec![None; m],
        }
    }
}

/// The touching points gathered for friction (scratch, reused from step to
/// step; capacity the pair's point count, so no allocation per step).
#[derive(Clone, Debug, Default)]
pub(crate) struct Batch {
    /// Pair point of each gathered point, in pair-point order.
    pub points: Vec<u32>,
    /// Lever arm of the contact point about the tool origin (mm) and the
    /// tool's velocity there (mm/s).
    pub touch: Vec<(Vec3, Vec3)>,
    /// The return mapping's input per point.
    pub inputs: Vec<StepInput>,
    /// Friction history per point (in: before the step; out: after).
    pub states: Vec<PointState>,
    /// The return mapping's output per point.
    pub outputs: Vec<StepOutput>,
}

impl Batch {
    /// An empty batch with room for `m` points.
    pub fn with_capacity(m: usize) -> Self {
        Self {
            points: Vec::with_capacity(m),
            touch: Vec::with_capacity(m),
            inputs: Vec::with_capacity(m),
            states: Vec::with_capacity(m),
            outputs: Vec::with_capacity(m),
        }
    }

    /// Empty the batch, keeping its capacity. The inputs are kept: the
    /// normal stage overwrites in each slot only what the law and formulation
    /// read, and truncates them to the points it gathered.
    pub fn clear(&mut self) {
        self.points.clear();
        self.touch.clear();
        self.states.clear();
        self.outputs.clear();
    }
}
