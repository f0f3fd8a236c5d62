//! One contact pair: a rigid tool against (a node set of) the blank, with the
//! per-point state laid out for the step loop, penalty normal forces, friction
//! through a [`PointIntegrator`], reactions on the tool and the pair's energies.

use plugins_api::kinematics::cayley_rotate;
use plugins_api::{
    Mat3, PointIntegrator, PointNeeds, PointState, ProjectionHint, StepInput, StepKinematics,
    StepOutput, ToolSurface, Vec3,
};

use crate::penalty::{PenaltySettings, nodal_stiffness};
use crate::{BlankGeometry, BlankView, ContactError};

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
        let bbox = tool.bounding_box();
        let origin = tool.pose().translation;
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
        let mut stored = 0.0;
        let k_t = self.integrator.stick_stiffness();

        // 1. Projection, gap and pressure; gather the touching points.
        for k in 0..self.nodes.len() {
            let i = self.nodes[k] as usize;
            let x = blank.x[i];
            let half = 0.5 * blank.thickness[i];
            if bbox.distance(&x) > half + self.search_margin {
                self.open(k);
                continue;
            }
            let pr = tool
                .project(&x, self.hint[k])
                .map_err(|source| ContactError::Tool {
                    pair: self.name.clone(),
                    node: i,
                    source: Box::new(source),
                })?;
            self.hint[k] = Some(pr.hint());
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

        // 2. Friction for the gathered points, in one batch.
        self.states.clear();
        self.states
            .extend(self.active.iter().map(|&k| self.friction[k as usize]));
        self.outputs.clear();
        self.outputs
            .resize(self.active.len(), StepOutput::default());
        if let Err(source) =
            self.integrator
                .step_batch(&mut self.states, &self.inputs, &mut self.outputs)
        {
            // Name the first point the batch refused: re-run point by point.
            let mut node = 0;
            for (j, &k) in self.active.iter().enumerate() {
                let mut s = self.friction[k as usize];
                if self.integrator.step(&mut s, &self.inputs[j]).is_err() {
                    node = self.nodes[k as usize] as usize;
                    break;
                }
            }
            return Err(ContactError::Friction {
                pair: self.name.clone(),
                node,
                source: Box::new(source),
            });
        }

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
        Ok(())
    }

    /// The stable time step of the contact springs of the touching points:
    /// `2 √(m / (k_N + k_T A))` per node (central difference on a mass between
    /// the penalty and the stick spring, the two added as if in one direction),
    /// with the node that limits it. `None` when nothing touches.
    pub fn stable_dt(&self, mass: &[f64], area: &[f64]) -> Option<(f64, usize)> {
        let k_t = self.integrator.stick_stiffness();
        let mut best: Option<(f64, usize)> = None;
        for (k, &node) in self.nodes.iter().enumerate() {
            if self.status[k] == PointStatus::Open {
                continue;
            }
            let i = node as usize;
            let stiff = self.stiffness[k] + k_t * area[i];
            if stiff > 0.0 && mass[i] > 0.0 {
                let dt = 2.0 * (mass[i] / stiff).sqrt();
                if best.is_none_or(|(b, _)| dt < b) {
                    best = Some((dt, i));
                }
            }
        }
        best
    }

    /// Open every point (the pair is inactive in the current press step).
    pub fn release(&mut self) {
        for k in 0..self.nodes.len() {
            self.open(k);
            self.force[k] = Vec3::zeros();
        }
        self.reaction = Reaction::default();
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
