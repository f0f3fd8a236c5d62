//! One contact pair: a rigid tool against (a node set of) the blank, with the
//! per-point state laid out for the step loop, penalty normal forces, friction
//! through a [`PointIntegrator`], reactions on the tool and the pair's energies.

use plugins_api::{PointIntegrator, PointNeeds, PointState, ToolSurface, Vec3};
use std::time::Instant;

mod saved_state;

use crate::penalty::{PenaltySettings, nodal_stiffness};
use crate::stages::broad_phase::broad_phase;
use crate::stages::friction::{friction, no_friction};
use crate::stages::narrow_phase::narrow_phase;
use crate::stages::normal::{Normal, NormalSums};
use crate::stages::scatter::{Scatter, ScatterSums};
use crate::stages::{Batch, Candidates, LastProjection, PointsMut, Settings, ToolStep};
use crate::{BlankGeometry, BlankView, ContactError, ContactTiming, FrictionRecord};

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

/// The per-point state and results a step updates, as a [`PointsMut`]
/// borrowing the pair's arrays field by field (so that its other fields stay
/// free for the stages).
macro_rules! points_mut {
    ($pair:expr) => {
        PointsMut {
            status: &mut $pair.status,
            friction: &mut $pair.friction,
            pressure: &mut $pair.pressure,
            traction: &mut $pair.traction,
            tau_c: &mut $pair.tau_c,
            slip: &mut $pair.slip,
            n_old: &mut $pair.n_old,
            force: &mut $pair.force,
        }
    };
}

/// The law name of a frictionless pair ([`ContactPair::frictionless`]); a
/// scene asks for one with `contact.law = "frictionless"`.
pub const FRICTIONLESS: &str = "frictionless";

/// A rigid tool against the blank: state per blank node of the pair.
pub struct ContactPair {
    name: String,
    tool: usize,
    /// The law × formulation; `None`: a frictionless pair, whose steps run
    /// no friction stage (no return mapping, no stick springs).
    integrator: Option<Box<dyn PointIntegrator>>,
    /// What the step computes: the integrator's needs, and
    /// [`crate::RECORD_NEEDS`] while recording.
    needs: PointNeeds,
    /// The friction stage's record of the last step, when asked for
    /// ([`ContactPair::record_friction`]).
    record: Option<Box<FrictionRecord>>,
    settings: Settings,
    /// Blank node of each pair point.
    nodes: Vec<u32>,
    /// Penalty stiffness per pair point (N/mm).
    stiffness: Vec<f64>,
    /// Per pair point: the warm start and the `skip_far` record.
    last: LastProjection,
    /// Per pair point: the friction history, the normal of the last contact
    /// and the last contact force (N).
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
    /// Point steps of the friction law so far (touching points handed to the
    /// return mapping, all steps); 0 for a frictionless pair.
    pub friction_points: u64,
    /// Candidates answered from a flat region of the tool so far, without a
    /// projection ([`plugins_api::ToolSurface::flat_region`]).
    pub flat_answers: u64,
    /// Candidates answered from a curved region of the tool (a cylinder or
    /// torus patch) so far, without a projection
    /// ([`plugins_api::ToolSurface::curved_region`]).
    pub curved_answers: u64,
    /// Projections skipped so far because the node could not reach the tool
    /// ([`PairSpec::skip_far`]); nodes outside the bounding-box margin are not counted.
    pub skipped: u64,
    /// Seconds spent in the stages of this pair's steps so far (`press` and
    /// `geometry` stay 0: they belong to [`crate::ContactEffect`]).
    pub timing: ContactTiming,
    /// Scratch: the points to project this step and their answers.
    cand: Candidates,
    /// Scratch: the touching points gathered for friction.
    batch: Batch,
}

impl std::fmt::Debug for ContactPair {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactPair")
            .field("name", &self.name)
            .field("tool", &self.tool)
            .field("law", &self.friction_model().0)
            .field("formulation", &self.friction_model().1)
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
        Self::with_friction(spec, Some(integrator), geometry, x0)
    }

    /// A frictionless pair ([`FRICTIONLESS`]): normal contact only. Its steps
    /// compute no blank gradients and run no friction stage: no return
    /// mapping, no stick springs, no frictional energy.
    ///
    /// # Errors
    /// As [`ContactPair::new`].
    pub fn frictionless(
        spec: &PairSpec,
        geometry: &BlankGeometry,
        x0: &[Vec3],
    ) -> Result<Self, ContactError> {
        Self::with_friction(spec, None, geometry, x0)
    }

    fn with_friction(
        spec: &PairSpec,
        integrator: Option<Box<dyn PointIntegrator>>,
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
        let needs = law_needs(integrator.as_deref());
        Ok(Self {
            name: spec.name.clone(),
            tool: spec.tool,
            needs,
            record: None,
            integrator,
            settings: Settings {
                penalty: spec.penalty,
                search_margin: spec.search_margin,
                max_penetration: spec.max_penetration,
                skip_far: spec.skip_far,
            },
            nodes,
            stiffness,
            last: LastProjection::new(m),
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
            friction_points: 0,
            flat_answers: 0,
            curved_answers: 0,
            skipped: 0,
            timing: ContactTiming::default(),
            cand: Candidates::new(m),
            batch: Batch::with_capacity(m),
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

    /// What the pair's steps compute for its points: what its law and
    /// formulation read (friction-math §6), and [`crate::RECORD_NEEDS`]
    /// while it records its friction stage.
    pub fn needs(&self) -> PointNeeds {
        self.needs
    }

    /// Keep (`on`) or stop keeping a [`FrictionRecord`] of every step's
    /// friction stage. While recording the pair computes
    /// [`crate::RECORD_NEEDS`] too; its law and formulation read only what
    /// they declare, so the results do not change. A [`crate::ContactEffect`]
    /// must learn of the change to compute the blank's gradients: use
    /// [`crate::ContactEffect::record_friction`] on a pair it holds.
    pub fn record_friction(&mut self, on: bool) {
        let own = law_needs(self.integrator.as_deref());
        if on {
            self.needs = own | crate::RECORD_NEEDS;
            self.record.get_or_insert_with(Box::default);
        } else {
            self.needs = own;
            self.record = None;
        }
    }

    /// The friction stage of the last step, when recording
    /// ([`ContactPair::record_friction`]).
    pub fn friction_record(&self) -> Option<&FrictionRecord> {
        self.record.as_deref()
    }

    /// Blank node of each pair point.
    pub fn nodes(&self) -> &[u32] {
        &self.nodes
    }

    /// The law and formulation names (`frictionless`, `none` for a
    /// frictionless pair).
    pub fn friction_model(&self) -> (&str, &str) {
        match &self.integrator {
            Some(i) => (i.law_name(), i.formulation_name()),
            None => (FRICTIONLESS, "none"),
        }
    }

    /// Stick stiffness `k_T` of the law (MPa/mm); 0 for a frictionless pair.
    fn stick_stiffness(&self) -> f64 {
        self.integrator
            .as_ref()
            .map_or(0.0, |i| i.stick_stiffness())
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
        self.step_apart(tool, geometry, blank, dt)?;
        self.add_forces(forces);
        Ok(())
    }

    /// [`ContactPair::step`] but for adding the nodal forces, which stay with
    /// the pair until [`ContactPair::add_forces`]: pairs can then step at
    /// the same time (each touches only its own data) and add their forces
    /// one after the other, in the same order, so the same bits, as
    /// [`ContactPair::step`] one pair after the other.
    ///
    /// # Errors
    /// As [`ContactPair::step`].
    pub fn step_apart(
        &mut self,
        tool: &dyn ToolSurface,
        geometry: &BlankGeometry,
        blank: &BlankView<'_>,
        dt: f64,
    ) -> Result<(), ContactError> {
        let mut t = Instant::now();
        self.reaction = Reaction::default();
        self.clamped = false;
        self.penetration_max = 0.0;
        let at = ToolStep::new(tool, self.needs, dt);
        let (settings, needs, name) = (self.settings, self.needs, self.name.as_str());
        let k_t = self.stick_stiffness();
        let (nodes, stiffness) = (&self.nodes, &self.stiffness);
        let (last, cand, batch) = (&mut self.last, &mut self.cand, &mut self.batch);
        let mut points = points_mut!(self);

        // 1a. Broad phase: the candidates.
        self.skipped += broad_phase(&settings, &at, blank, nodes, last, &mut points, cand);
        lap(&mut t, &mut self.timing.broad_phase);
        // 1b. Narrow phase: project them.
        let warm = (&last.hint[..], &last.region[..]);
        narrow_phase(tool, &at, blank.x, nodes, warm, cand, name)?;
        let (projected, curved) = cand.near.iter().fold((0, 0), |(p, c), n| {
            (p + n.projected as u64, c + n.curved as u64)
        });
        self.projections += projected;
        self.curved_answers += curved;
        self.flat_answers += cand.near.len() as u64 - projected - curved;
        lap(&mut t, &mut self.timing.projection);
        // 1c. Normal: gap and pressure; gather the touching points.
        let normal = Normal {
            settings: &settings,
            tool: &at,
            needs,
            geometry,
            blank,
            dt,
        };
        let contact = normal.run(nodes, stiffness, cand, last, &mut points, batch);
        lap(&mut t, &mut self.timing.normal);
        // 2. Friction on the gathered points (a frictionless pair: none).
        match self.integrator.as_deref() {
            Some(integrator) => {
                friction(integrator, points.friction, nodes, batch, name)?;
                self.friction_points += batch.points.len() as u64;
            }
            None => no_friction(batch),
        }
        if let Some(r) = self.record.as_deref_mut() {
            r.capture(batch, points.friction);
        }
        lap(&mut t, &mut self.timing.friction);
        // 3. Scatter forces, reactions, energies.
        let scatter = Scatter {
            geometry,
            blank,
            tool: &at,
            dt,
            k_t,
        };
        let sums = scatter.run(nodes, batch, &mut points, contact.stored);
        self.finish(&contact, &sums);
        lap(&mut t, &mut self.timing.scatter);
        Ok(())
    }

    /// Add the nodal forces (N) of the touching points of the last
    /// [`ContactPair::step_apart`] to `forces`, in the points' order.
    pub fn add_forces(&self, forces: &mut [Vec3]) {
        for &k in &self.batch.points {
            let k = k as usize;
            forces[self.nodes[k] as usize] += self.force[k];
        }
    }

    /// Keep the step's sums: the tool's reaction, the deepest penetration,
    /// the clamp flag and the energies.
    fn finish(&mut self, contact: &NormalSums, sums: &ScatterSums) {
        self.reaction = Reaction {
            force: sums.force,
            moment: sums.moment,
            stiffness: contact.stiffness,
        };
        self.clamped = sums.clamped;
        self.penetration_max = contact.penetration_max;
        self.energy.friction += sums.friction;
        self.energy.blank_work += sums.blank_work;
        self.energy.tool_work += sums.tool_work;
        self.energy.stored = sums.stored;
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

    /// Mark the node of every point touching in the last step (the
    /// drawbeads' clamping test).
    pub(crate) fn mark_touching(&self, touching: &mut [bool]) {
        for &k in &self.batch.points {
            touching[self.nodes[k as usize] as usize] = true;
        }
    }

    /// Whether any point touched the tool in the last step.
    pub fn touching(&self) -> bool {
        !self.batch.points.is_empty()
    }

    /// Add the penalty plus stick stiffness (N/mm) of every point touching
    /// in the last step to its node's entry of `stiffness` (the springs of
    /// [`ContactPair::stable_dt`], for the limit of the effects on a node
    /// together, see `fem_core::nodal_limit`).
    pub fn add_nodal_stiffness(&self, area: &[f64], stiffness: &mut [f64]) {
        for (node, s) in self.touching_springs(area) {
            stiffness[node] += s;
        }
    }

    /// `(node, penalty + stick stiffness (N/mm))` of every point touching in
    /// the last step (those whose forces [`ContactPair::add_forces`] adds)
    /// with a positive spring.
    fn touching_springs<'a>(&'a self, area: &'a [f64]) -> impl Iterator<Item = (usize, f64)> + 'a {
        let k_t = self.stick_stiffness();
        self.batch
            .points
            .iter()
            .map(move |&k| {
                let node = self.nodes[k as usize] as usize;
                (node, self.stiffness[k as usize] + k_t * area[node])
            })
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
        self.batch.points.clear();
        let mut points = points_mut!(self);
        for k in 0..points.status.len() {
            points.open(k);
            points.force[k] = Vec3::zeros();
        }
        self.reaction = Reaction::default();
        self.penetration_max = 0.0;
        self.energy.stored = 0.0;
    }
}

/// What a pair's law and formulation read; nothing for a frictionless pair.
fn law_needs(integrator: Option<&dyn PointIntegrator>) -> PointNeeds {
    integrator.map_or(PointNeeds::NONE, PointIntegrator::needs)
}

/// Add the time since `start` to `stage` (s) and restart the clock.
fn lap(start: &mut Instant, stage: &mut f64) {
    let now = Instant::now();
    *stage += (now - *start).as_secs_f64();
    *start = now;
}
