//! One contact pair: a rigid tool against (a node set of) the blank, with the
//! per-point state laid out for the step loop, penalty normal forces, friction
//! through a [`PointIntegrator`], reactions on the tool and the pair's energies.

use plugins_api::kinematics::cayley_rotate;
use plugins_api::{
    Mat3, PointIntegrator, PointNeeds, PointState, Projection, ProjectionHint, StepInput,
    StepKinematics, StepOutput, ToolSurface, Vec3,
};
use rayon::prelude::*;
use std::time::Instant;

use crate::penalty::{PenaltySettings, nodal_stiffness};
use crate::{BlankGeometry, BlankView, ContactError, ContactTiming};

/// What a contact pair is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct PairSpec {
    /// Pair name (for messages and outputs), e.g. `punch-blank`.
    pub name: String,
    /// Index of the tool in the tool list handed to [`ContactPair::step`]'s caller.
    pub tool: usize,
    /// Blank nodes that may touch this tool; `None`: all nodes.
    pub nodes: Option<Vec<u32>>,
    /// Normal enforcement.
    pub penalty: PenaltySettings,
    /// Bulk modulus of the blank material (MPa), for the penalty stiffness.
    pub bulk_modulus: f64,
    /// Nodes farther than this from the tool's bounding box (beyond half the
    /// thickness) are not projected (mm); default 1.
    pub search_margin: f64,
    /// Penetrations deeper than this many blank thicknesses are taken as a node
    /// on the far side of a thin tool feature, not as contact (-); default 3.
    pub max_penetration: f64,
    /// Skip the projection of open nodes that provably cannot reach the tool
    /// (default `true`). A node projected and found open keeps its distance
    /// from the tool and its position in the tool's frame; in later steps it
    /// is projected again only once its travel relative to the tool could have
    /// brought it within reach (half its thickness, or `max_penetration`
    /// thicknesses less half on the far side, plus `search_margin`). Touching
    /// nodes are projected every step. `false` projects every node within the
    /// bounding-box margin every step (for comparison and checks).
    pub skip_far: bool,
}

impl PairSpec {
    /// A pair with default enforcement settings.
    pub fn new(name: &str, tool: usize, bulk_modulus: f64) -> Self {
        Self {
            name: name.into(),
            tool,
            nodes: None,
            penalty: PenaltySettings::default(),
            bulk_modulus,
            search_margin: 1.0,
            max_penetration: 3.0,
            skip_far: true,
        }
    }
}

/// Candidate nodes per parallel task.
const PARALLEL_CHUNK: usize = 64;

/// Whether `n` points are worth a parallel loop: more than
/// [`ContactPair::PARALLEL_MIN_CANDIDATES`] and more than one rayon thread
/// (on one thread, handing the loop to the pool's worker only costs a
/// wake-up and the data's trip to another core).
fn parallel(n: usize) -> bool {
    n > ContactPair::PARALLEL_MIN_CANDIDATES && rayon::current_num_threads() > 1
}

/// Contact points per parallel friction task.
const FRICTION_CHUNK: usize = 256;

/// Slack (mm) added to the reach of a skipped node, above the rounding of the
/// local coordinates and of the projection's distance.
const SKIP_TOL: f64 = 1e-9;

/// What step 1 keeps of a projection.
#[derive(Clone, Copy, Debug)]
struct Near {
    normal: Vec3,
    distance: f64,
    hint: ProjectionHint,
}

impl Near {
    const NONE: Near = Near {
        normal: Vec3::new(0.0, 0.0, 0.0),
        distance: f64::NAN,
        hint: ProjectionHint {
            patch: 0,
            u: f64::NAN,
            v: f64::NAN,
        },
    };

    fn of(pr: &Projection) -> Self {
        Self {
            normal: pr.normal,
            distance: pr.distance,
            hint: pr.hint(),
        }
    }
}

/// State of a contact point after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PointStatus {
    /// Not touching.
    #[default]
    Open,
    /// Touching and sticking.
    Stick,
    /// Touching and slipping.
    Slip,
}

/// Force and moment that the blank exerts on a tool (N, N·mm about the tool origin).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Reaction {
    /// Resultant force on the tool (N).
    pub force: Vec3,
    /// Resultant moment on the tool about its pose origin (N·mm).
    pub moment: Vec3,
    /// Sum of the normal penalty stiffnesses of the touching points (N/mm):
    /// the stiffness of the support the tool rests on.
    pub stiffness: f64,
}

/// Cumulative energies of a pair (N·mm = mJ).
///
/// With `W_b` the work of the contact forces on the blank and `W_t` the work
/// the moving tool does through the contact, `W_t − W_b = friction + stored`:
/// what the tool puts in and the blank does not receive is dissipated by
/// friction or stored in the penalty and stick springs. [`ContactEnergy::contact`]
/// is that remainder (`W_t − W_b − friction`), which should stay close to
/// [`ContactEnergy::stored`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ContactEnergy {
    /// Frictional dissipation `Σ ΔD A` (≥ 0).
    pub friction: f64,
    /// Work done by the tool on the blank through this pair (`W_t`).
    pub tool_work: f64,
    /// Work of the contact forces on the blank (`W_b`).
    pub blank_work: f64,
    /// Energy currently stored in the penalty (`½ k δ²`) and stick (`½ |t|² A / k_T`) springs.
    pub stored: f64,
}

impl ContactEnergy {
    /// The interface energy net of friction, `W_t − W_b − friction`.
    pub fn contact(&self) -> f64 {
        self.tool_work - self.blank_work - self.friction
    }
}

/// A rigid tool against the blank: state per blank node of the pair.
pub struct ContactPair {
    name: String,
    tool: usize,
    integrator: Box<dyn PointIntegrator>,
    needs: PointNeeds,
    penalty: PenaltySettings,
    search_margin: f64,
    max_penetration: f64,
    skip_far: bool,
    /// Blank node of each pair point.
    nodes: Vec<u32>,
    /// Penalty stiffness per pair point (N/mm).
    stiffness: Vec<f64>,
    hint: Vec<Option<ProjectionHint>>,
    friction: Vec<PointState>,
    n_old: Vec<Vec3>,
    force: Vec<Vec3>,
    /// Contact pressure per pair point (MPa), after the last step.
    pub pressure: Vec<f64>,
    /// Friction traction on the blank per pair point (MPa).
    pub traction: Vec<Vec3>,
    /// Critical shear stress `τ_c` per pair point after the last step (MPa); 0 when open.
    pub tau_c: Vec<f64>,
    /// Accumulated slip length `Σ Δγ` per pair point (mm).
    pub slip: Vec<f64>,
    /// Open / stick / slip per pair point.
    pub status: Vec<PointStatus>,
    /// Reaction on the tool after the last step.
    pub reaction: Reaction,
    /// Cumulative energies.
    pub energy: ContactEnergy,
    /// Whether any point hit the clamp of its law during the last step.
    pub clamped: bool,
    /// Deepest penetration `−g` of the points touching in the last step (mm;
    /// 0 when none touch): the face of the blank (mid-surface ± half the
    /// current thickness) inside the tool. With the penalty `p A = k (−g)` it
    /// is the largest `F_N / k`; the hard cases compare it with the thickness.
    pub penetration_max: f64,
    /// Projections on the tool so far (all steps).
    pub projections: u64,
    /// Projections skipped so far because the node could not reach the tool
    /// ([`PairSpec::skip_far`]); nodes outside the bounding-box margin are not counted.
    pub skipped: u64,
    /// Seconds spent in the stages of this pair's steps so far (`press` and
    /// `geometry` stay 0: they belong to [`crate::ContactEffect`]).
    pub timing: ContactTiming,
    /// Per pair point: the unsigned distance from the tool at its last
    /// projection (mm; `-∞` before the first) and its position then, in the
    /// tool's local frame (mm).
    far_dist: Vec<f64>,
    far_local: Vec<Vec3>,
    /// Scratch: the points to project this step and their answers.
    cand: Vec<u32>,
    near: Vec<Near>,
    // Scratch for the gathered friction batch (capacity = node count; no allocation per step).
    active: Vec<u32>,
    /// Per gathered point: lever arm of the contact point about the tool origin
    /// (mm) and the tool's velocity there (mm/s).
    touch: Vec<(Vec3, Vec3)>,
    inputs: Vec<StepInput>,
    states: Vec<PointState>,
    outputs: Vec<StepOutput>,
}

impl std::fmt::Debug for ContactPair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactPair")
            .field("name", &self.name)
            .field("tool", &self.tool)
            .field("law", &self.integrator.law_name())
            .field("formulation", &self.integrator.formulation_name())
            .field("points", &self.nodes.len())
            .finish()
    }
}

impl ContactPair {
    /// A pair with more candidate nodes than this in a step projects them in
    /// parallel (rayon's current pool, when it has more than one thread), in
    /// chunks of 64; with more touching points than this it runs their
    /// friction in parallel chunks of 256. Each point's answer lands in its
    /// own slot and the sums are taken afterwards in node order, so the
    /// results do not depend on the number of threads.
    pub const PARALLEL_MIN_CANDIDATES: usize = 512;

    /// Build a pair over the blank `geometry` with initial positions `x0`.
    ///
    /// # Errors
    /// Out-of-range settings or node indices.
    pub fn new(
        spec: &PairSpec,
        integrator: Box<dyn PointIntegrator>,
        geometry: &BlankGeometry,
        x0: &[Vec3],
    ) -> Result<Self, ContactError> {
        let n = geometry.node_count();
        let nodes: Vec<u32> = match &spec.nodes {
            Some(list) => {
                if let Some(&bad) = list.iter().find(|&&i| i as usize >= n) {
                    return Err(ContactError::Mesh(format!(
                        "contact pair `{}` lists node {bad}, but the blank has {n} nodes",
                        spec.name
                    )));
                }
                list.clone()
            }
            None => (0..n as u32).collect(),
        };
        for (field, value, unit, ok, range) in [
            (
                "search_margin",
                spec.search_margin,
                "mm",
                spec.search_margin.is_finite() && spec.search_margin >= 0.0,
                ">= 0 (mm)",
            ),
            (
                "max_penetration",
                spec.max_penetration,
                "-",
                spec.max_penetration.is_finite() && spec.max_penetration > 0.0,
                "> 0 (blank thicknesses)",
            ),
        ] {
            if !ok {
                return Err(ContactError::OutOfRange {
                    pair: spec.name.clone(),
                    field,
                    value,
                    unit,
                    range,
                });
            }
        }
        let all = nodal_stiffness(geometry, x0, spec.bulk_modulus, &spec.penalty, &spec.name)?;
        let stiffness = nodes.iter().map(|&i| all[i as usize]).collect();
        let m = nodes.len();
        let needs = integrator.needs();
        Ok(Self {
            name: spec.name.clone(),
            tool: spec.tool,
            needs,
            integrator,
            penalty: spec.penalty,
            search_margin: spec.search_margin,
            max_penetration: spec.max_penetration,
            skip_far: spec.skip_far,
            nodes,
            stiffness,
            hint: vec![None; m],
            friction: vec![PointState::default(); m],
            n_old: vec![Vec3::zeros(); m],
            force: vec![Vec3::zeros(); m],
            pressure: vec![0.0; m],
            traction: vec![Vec3::zeros(); m],
            tau_c: vec![0.0; m],
            slip: vec![0.0; m],
            status: vec![PointStatus::Open; m],
            reaction: Reaction::default(),
            energy: ContactEnergy::default(),
            clamped: false,
            penetration_max: 0.0,
            projections: 0,
            skipped: 0,
            timing: ContactTiming::default(),
            far_dist: vec![f64::NEG_INFINITY; m],
            far_local: vec![Vec3::zeros(); m],
            cand: Vec::with_capacity(m),
            near: Vec::with_capacity(m),
            active: Vec::with_capacity(m),
            touch: Vec::with_capacity(m),
            inputs: Vec::with_capacity(m),
            states: Vec::with_capacity(m),
            outputs: Vec::with_capacity(m),
        })
    }

    /// Pair name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Index of the pair's tool.
    pub fn tool(&self) -> usize {
        self.tool
    }

    /// What the pair's law and formulation read (friction-math §6).
    pub fn needs(&self) -> PointNeeds {
        self.needs
    }

    /// Blank node of each pair point.
    pub fn nodes(&self) -> &[u32] {
        &self.nodes
    }

    /// The law and formulation names.
    pub fn friction_model(&self) -> (&str, &str) {
        (
            self.integrator.law_name(),
            self.integrator.formulation_name(),
        )
    }

    /// Frictional work density `ω` (N/mm) per pair point.
    pub fn omega(&self, point: usize) -> f64 {
        self.friction[point].omega
    }

    /// One explicit step: project the pair's nodes on `tool`, compute penalty
    /// pressures, slip increments and friction tractions, add the nodal forces
    /// to `forces` (N), and update reactions and energies. `geometry` must have
    /// been updated for this step with at least [`ContactPair::needs`].
    ///
    /// # Errors
    /// A non-finite node position; the friction model refusing a point.
    pub fn step(
        &mut self,
        tool: &dyn ToolSurface,
        geometry: &BlankGeometry,
        blank: &BlankView<'_>,
        dt: f64,
        forces: &mut [Vec3],
    ) -> Result<(), ContactError> {
        let t_start = Instant::now();
        let bbox = tool.bounding_box();
        let pose = tool.pose();
        let origin = pose.translation;
        let to_local = pose.rotation.transpose();
        let tool_vel = tool.velocity();
        let tool_rotation = if self.needs.contains(PointNeeds::TOOL_ROTATION) {
            // The rigid rotation of the step (Hughes–Winget / Cayley of Δt ω).
            let a = tool_vel.angular * (0.5 * dt);
            Mat3::from_columns(&[
                cayley_rotate(&a, &Vec3::x()),
                cayley_rotate(&a, &Vec3::y()),
                cayley_rotate(&a, &Vec3::z()),
            ])
        } else {
            Mat3::identity()
        };
        let want_l = self.needs.contains(PointNeeds::SPIN)
            || self.needs.contains(PointNeeds::VELOCITY_GRADIENT);
        let want_f = self.needs.contains(PointNeeds::DEFORMATION_GRADIENT);
        let want_flow = self.needs.contains(PointNeeds::FLOW_STRESS);

        self.active.clear();
        self.touch.clear();
        self.inputs.clear();
        self.reaction = Reaction::default();
        self.clamped = false;
        self.penetration_max = 0.0;
        let mut stored = 0.0;
        let k_t = self.integrator.stick_stiffness();

        // 1a. Candidates: inside the bounding-box margin, and not provably out
        //     of reach since their last projection (`skip_far`).
        self.cand.clear();
        for k in 0..self.nodes.len() {
            let i = self.nodes[k] as usize;
            let x = blank.x[i];
            let half = 0.5 * blank.thickness[i];
            if bbox.distance(&x) > half + self.search_margin {
                self.open(k);
                continue;
            }
            if self.skip_far && self.status[k] == PointStatus::Open {
                // The distance from a rigidly moving surface is 1-Lipschitz in
                // the point's position in the surface's own frame, so
                // |d_now| ≥ |d_then| − |x_local,now − x_local,then|.
                let moved = (to_local * (x - origin) - self.far_local[k]).norm();
                let reach = half.max(self.max_penetration * blank.thickness[i] - half);
                if self.far_dist[k] - moved > reach + self.search_margin + SKIP_TOL {
                    self.skipped += 1;
                    continue;
                }
            }
            self.cand.push(k as u32);
        }
        let t_broad = Instant::now();
        self.timing.broad_phase += (t_broad - t_start).as_secs_f64();

        // 1b. Project the candidates (in parallel for many: each answer lands
        //     in its own slot, so the result does not depend on the threads).
        self.project_candidates(tool, blank.x)?;
        self.projections += self.cand.len() as u64;
        let t_projection = Instant::now();
        self.timing.projection += (t_projection - t_broad).as_secs_f64();

        // 1c. Gap and pressure, in node order; gather the touching points.
        for j in 0..self.cand.len() {
            let k = self.cand[j] as usize;
            let i = self.nodes[k] as usize;
            let x = blank.x[i];
            let half = 0.5 * blank.thickness[i];
            let pr = self.near[j];
            self.hint[k] = Some(pr.hint);
            if self.skip_far {
                self.far_dist[k] = pr.distance.abs();
                self.far_local[k] = to_local * (x - origin);
            }
            let gap = pr.distance - half;
            if gap >= 0.0 || -gap > self.max_penetration * blank.thickness[i] {
                self.open(k);
                continue;
            }
            let area = geometry.area[i];
            if area.is_nan() || area <= 0.0 {
                self.open(k);
                continue;
            }
            let n_new = pr.normal;
            let arm = x - n_new * half - origin;
            let v_tool = tool_vel.linear + tool_vel.angular.cross(&arm);
            let v_rel = blank.v[i] - v_tool;
            let mut f_n = self.stiffness[k] * (-gap);
            if self.penalty.damping > 0.0 {
                let c = 2.0 * self.penalty.damping * (self.stiffness[k] * blank.mass[i]).sqrt();
                // Approaching velocity is -v_rel·n > 0; damping resists it, never pulls.
                f_n = (f_n - c * v_rel.dot(&n_new)).max(0.0);
            }
            stored += 0.5 * self.stiffness[k] * gap * gap;
            self.penetration_max = self.penetration_max.max(-gap);
            self.reaction.stiffness += self.stiffness[k];
            let n_old = if self.status[k] == PointStatus::Open {
                n_new
            } else {
                self.n_old[k]
            };
            let mut kin = StepKinematics::simple(dt, n_old, n_new);
            kin.tool_rotation = tool_rotation;
            if want_l {
                kin.vel_grad = geometry.vel_grad[i];
            }
            if want_f {
                kin.f_old = geometry.f_old[i];
                kin.f_new = geometry.f_new[i];
            }
            let mut input = StepInput::new(f_n / area, v_rel * dt, kin);
            if want_flow && let Some((top, bottom)) = blank.flow_stress {
                // The tool normal points towards the blank: a tool on the +n_blank
                // side has n_tool·n_blank < 0 and touches the top fibre.
                input.flow_stress = if n_new.dot(&geometry.normal[i]) < 0.0 {
                    top[i]
                } else {
                    bottom[i]
                };
            }
            self.touch.push((arm, v_tool));
            self.active.push(k as u32);
            self.inputs.push(input);
        }
        let t_normal = Instant::now();
        self.timing.normal += (t_normal - t_projection).as_secs_f64();

        // 2. Friction for the gathered points: one batch, or chunks in
        //    parallel for many (the points are independent, each lands in its
        //    own slot).
        self.states.clear();
        self.states
            .extend(self.active.iter().map(|&k| self.friction[k as usize]));
        self.outputs.clear();
        self.outputs
            .resize(self.active.len(), StepOutput::default());
        let integrator = self.integrator.as_ref();
        let done = if parallel(self.active.len()) {
            self.states
                .par_chunks_mut(FRICTION_CHUNK)
                .zip(self.inputs.par_chunks(FRICTION_CHUNK))
                .zip(self.outputs.par_chunks_mut(FRICTION_CHUNK))
                .try_for_each(|((s, i), o)| integrator.step_batch(s, i, o))
        } else {
            integrator.step_batch(&mut self.states, &self.inputs, &mut self.outputs)
        };
        if let Err(batch) = done {
            // Name the first point refused, with its own error: re-run point by point.
            let mut first = (0, batch);
            for (j, &k) in self.active.iter().enumerate() {
                let mut s = self.friction[k as usize];
                if let Err(e) = integrator.step(&mut s, &self.inputs[j]) {
                    first = (self.nodes[k as usize] as usize, e);
                    break;
                }
            }
            return Err(ContactError::Friction {
                pair: self.name.clone(),
                node: first.0,
                source: Box::new(first.1),
            });
        }

        let t_friction = Instant::now();
        self.timing.friction += (t_friction - t_normal).as_secs_f64();

        // 3. Scatter forces, reactions, energies.
        let mut friction = 0.0;
        let mut blank_work = 0.0;
        let mut tool_work = 0.0;
        for (j, &k) in self.active.iter().enumerate() {
            let k = k as usize;
            let i = self.nodes[k] as usize;
            let out = &self.outputs[j];
            let area = geometry.area[i];
            let normal = self.inputs[j].kin.n_new;
            let (arm, v_tool) = self.touch[j];
            let p = self.inputs[j].p;
            let f = (normal * p + out.t) * area;
            forces[i] += f;
            self.reaction.force -= f;
            self.reaction.moment -= arm.cross(&f);
            let f_mid = 0.5 * (f + self.force[k]);
            blank_work += f_mid.dot(&(blank.v[i] * dt));
            tool_work += f_mid.dot(&(v_tool * dt));
            friction += out.dissipation * area;
            if k_t > 0.0 {
                stored += 0.5 * out.t.norm_squared() * area / k_t;
            }
            self.friction[k] = self.states[j];
            self.n_old[k] = normal;
            self.force[k] = f;
            self.pressure[k] = p;
            self.traction[k] = out.t;
            self.tau_c[k] = out.tau_c;
            self.slip[k] += out.dgamma;
            self.status[k] = if out.stick {
                PointStatus::Stick
            } else {
                PointStatus::Slip
            };
            self.clamped |= out.clamped;
        }
        // Points that opened this step still complete the work of their last force.
        for k in 0..self.nodes.len() {
            if self.status[k] == PointStatus::Open && self.force[k] != Vec3::zeros() {
                let i = self.nodes[k] as usize;
                let f_mid = 0.5 * self.force[k];
                blank_work += f_mid.dot(&(blank.v[i] * dt));
                tool_work += f_mid.dot(&(tool_vel.linear * dt));
                self.force[k] = Vec3::zeros();
            }
        }
        self.energy.friction += friction;
        self.energy.blank_work += blank_work;
        self.energy.tool_work += tool_work;
        self.energy.stored = stored;
        self.timing.scatter += t_friction.elapsed().as_secs_f64();
        Ok(())
    }

    /// Project the nodes of `self.cand` on `tool` into `self.near` (same
    /// order), in parallel chunks when there are more than
    /// [`ContactPair::PARALLEL_MIN_CANDIDATES`]. A failure names the first
    /// failing node in candidate order, whatever the threads did.
    fn project_candidates(
        &mut self,
        tool: &dyn ToolSurface,
        x: &[Vec3],
    ) -> Result<(), ContactError> {
        let (nodes, hint, cand, near) = (&self.nodes, &self.hint, &self.cand, &mut self.near);
        near.clear();
        near.resize(cand.len(), Near::NONE);
        let one = |k: u32| tool.project(&x[nodes[k as usize] as usize], hint[k as usize]);
        if parallel(cand.len()) {
            let done: Result<(), ()> = near
                .par_chunks_mut(PARALLEL_CHUNK)
                .zip(cand.par_chunks(PARALLEL_CHUNK))
                .try_for_each(|(out, ks)| {
                    for (o, &k) in out.iter_mut().zip(ks) {
                        *o = Near::of(&one(k).map_err(|_| ())?);
                    }
                    Ok(())
                });
            if done.is_ok() {
                return Ok(());
            }
        }
        for (o, &k) in near.iter_mut().zip(cand.iter()) {
            let pr = one(k).map_err(|source| ContactError::Tool {
                pair: self.name.clone(),
                node: nodes[k as usize] as usize,
                source: Box::new(source),
            })?;
            *o = Near::of(&pr);
        }
        Ok(())
    }

    /// The stable time step of the contact springs of the touching points:
    /// `2 √(m / (k_N + k_T A))` per node (central difference on a mass between
    /// the penalty and the stick spring, the two added as if in one direction),
    /// with the node that limits it. `None` when nothing touches.
    pub fn stable_dt(&self, mass: &[f64], area: &[f64]) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for (i, stiff) in self.touching_springs(area) {
            if mass[i] > 0.0 {
                let dt = 2.0 * (mass[i] / stiff).sqrt();
                if best.is_none_or(|(b, _)| dt < b) {
                    best = Some((dt, i));
                }
            }
        }
        best
    }

    /// Fixed-step mass scaling of this pair's springs: add translational mass
    /// to every touching node whose contact time step `2 √(m / k)`, with `k`
    /// the penalty plus stick stiffness as in [`ContactPair::stable_dt`],
    /// falls below `target_dt` (s). Returns the added mass (tonne).
    pub fn scale_mass(&self, target_dt: f64, mass: &mut [f64], area: &[f64]) -> f64 {
        let mut added = 0.0;
        for (i, stiff) in self.touching_springs(area) {
            let need = stiff * 0.25 * target_dt * target_dt;
            if mass[i] > 0.0 && need > mass[i] {
                added += need - mass[i];
                mass[i] = need;
            }
        }
        added
    }

    /// `(node, penalty + stick stiffness (N/mm))` of every touching point with a positive spring.
    fn touching_springs<'a>(&'a self, area: &'a [f64]) -> impl Iterator<Item = (usize, f64)> + 'a {
        let k_t = self.integrator.stick_stiffness();
        self.nodes
            .iter()
            .zip(&self.stiffness)
            .zip(&self.status)
            .filter(|(_, status)| **status != PointStatus::Open)
            .map(move |((&node, &k_n), _)| (node as usize, k_n + k_t * area[node as usize]))
            .filter(|&(_, stiff)| stiff > 0.0)
    }

    /// Contact area (mm², the nodal areas of the points touching) and the
    /// area-weighted mean pressure over it (MPa), from the last step.
    pub fn area_and_mean_pressure(&self, area: &[f64]) -> (f64, f64) {
        let (mut a, mut pa) = (0.0, 0.0);
        for (k, &node) in self.nodes.iter().enumerate() {
            if self.status[k] != PointStatus::Open {
                let ak = area[node as usize];
                a += ak;
                pa += self.pressure[k] * ak;
            }
        }
        (a, if a > 0.0 { pa / a } else { 0.0 })
    }

    /// Open every point (the pair is inactive in the current press step).
    pub fn release(&mut self) {
        for k in 0..self.nodes.len() {
            self.open(k);
            self.force[k] = Vec3::zeros();
        }
        self.reaction = Reaction::default();
        self.penetration_max = 0.0;
        self.energy.stored = 0.0;
    }

    /// Mark pair point `k` open: no pressure, no traction, history cleared.
    fn open(&mut self, k: usize) {
        if self.status[k] != PointStatus::Open {
            self.status[k] = PointStatus::Open;
            self.friction[k] = PointState::default();
            self.pressure[k] = 0.0;
            self.traction[k] = Vec3::zeros();
            self.tau_c[k] = 0.0;
        }
    }
}
