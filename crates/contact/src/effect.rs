//! Contact as an engine effect (stage 5 of the explicit step,
//! docs/architecture.md §3): the tools, placed where the press stage put
//! them, the pairs, and the blank's nodal thickness and flow stress that the
//! pairs read (from the shared fields the shells write).

use fem_core::{
    Effect, EnergyTally, FemError, FieldAccess, Forces, NodalField, NodalState, Press, StableDt,
    StepContext, ToolLoad,
};
use plugins_api::{PointNeeds, ToolSurface, Vec3};

mod saved_state;

use rayon::prelude::*;
use std::time::Instant;

use crate::drawbead::{BeadInputs, BeadSet};
use crate::tool_log::{ToolSample, ToolStepLog, record};
use crate::{
    BeadEnergy, BlankGeometry, BlankView, ContactEnergy, ContactPair, ContactTiming, Drawbead,
    DrawbeadSpec,
};

/// Tools and contact pairs over one blank, as a [`fem_core::Effect`].
///
/// Per step: the tools take the poses the press stage gave them for
/// `t_{n+1}` ([`StepContext::press`]; tools without a press stay where they
/// are); the blank's nodal geometry is updated for what the active pairs
/// read; each pair active in the current press step adds its forces; the
/// reactions are summed per tool ([`Effect::tool_loads`]: force-controlled
/// tools read them in the next press stage).
///
/// The blank's nodal thickness and outer-fibre flow stress are `fem-core`
/// shared fields: contact reads [`NodalField::THICKNESS`] and, when a pair's
/// law declares [`PointNeeds::FLOW_STRESS`], [`NodalField::FLOW_STRESS_TOP`]
/// and [`NodalField::FLOW_STRESS_BOTTOM`] ([`Effect::reads`]). The solver
/// runs their writer (the blank's shells) first in every step, so the gap
/// at `t_{n+1}` is measured with the thickness at `t_{n+1}` that the shells
/// just computed from this step's deformation. The pairs borrow the fields
/// for the step; with no effect writing them (a rigid block on springs,
/// say) they read the initial thickness given to [`ContactEffect::new`]
/// ([`ContactEffect::initial_thickness`]) and zero flow stress.
///
/// The blank's nodal areas and normals come the same way when a writer gives
/// them ([`NodalField::AREA`], [`NodalField::NORMAL`]: the shells compute
/// them from the element frames of their own step), so the quad geometry is
/// computed once per step; without a writer contact computes them itself
/// ([`BlankGeometry::update`]). Contact keeps the areas (the time step and
/// mass scaling read them between steps) and the unit normals.
///
/// At the initial force computation (`Δt = 0`) contact adds nothing: a scene
/// starts with its tools clear of the blank or just touching it.
///
/// With more than one rayon thread and a blank of more than
/// [`BlankGeometry::PARALLEL_MIN_QUADS`] quads or a pair of more than
/// [`ContactPair::PARALLEL_MIN_CANDIDATES`] nodes, the step runs on a thread
/// of rayon's pool and its large loops (nodal areas, projections, friction)
/// in parallel; the results are the same bits on any number of threads.
pub struct ContactEffect {
    tools: Vec<Box<dyn ToolSurface>>,
    pairs: Vec<ContactPair>,
    geometry: BlankGeometry,
    needs: PointNeeds,
    /// Initial nodal thickness (mm), read when no effect writes the field.
    thickness: Vec<f64>,
    /// Zero top and bottom flow stress (MPa), read when a law needs it and
    /// no effect writes the fields.
    flow_stress: Option<(Vec<f64>, Vec<f64>)>,
    reactions: Vec<Vec3>,
    /// What the blank did to each tool in the last step (force control reads it).
    loads: Vec<ToolLoad>,
    /// Accumulated energies of pairs, including those of earlier press steps.
    energy: ContactEnergy,
    /// Whether the blank or a pair is large enough for parallel loops (a
    /// small model is not worth the hand-over to the pool every step).
    parallel: bool,
    /// What each tool did, press step by press step.
    tool_log: Vec<Vec<ToolStepLog>>,
    /// Work of each tool through contact in the current explicit step (N·mm).
    tool_work_step: Vec<f64>,
    /// Per pair, scratch of a step: whether it is active in the press step,
    /// its energies before the step, and the error it met.
    active: Vec<bool>,
    before: Vec<ContactEnergy>,
    outcome: Vec<Option<crate::ContactError>>,
    /// Seconds spent moving the tools and updating the nodal geometry (the
    /// pairs keep their own stages).
    timing: ContactTiming,
    /// The drawbeads ([`ContactEffect::with_drawbeads`]).
    beads: BeadSet,
}

impl std::fmt::Debug for ContactEffect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactEffect")
            .field(
                "tools",
                &self
                    .tools
                    .iter()
                    .map(|t| t.name().to_string())
                    .collect::<Vec<_>>(),
            )
            .field("pairs", &self.pairs)
            .finish()
    }
}

impl ContactEffect {
    /// Contact of `pairs` against `tools` over the blank `geometry` of initial
    /// thickness `thickness` (mm, per node). The solver's press, if any,
    /// moves the tools (tool `i` is the press's tool `i`).
    ///
    /// # Errors
    /// A pair referring to a missing tool; a thickness list of the wrong length.
    pub fn new(
        tools: Vec<Box<dyn ToolSurface>>,
        pairs: Vec<ContactPair>,
        geometry: BlankGeometry,
        thickness: Vec<f64>,
    ) -> Result<Self, crate::ContactError> {
        for p in &pairs {
            if p.tool() >= tools.len() {
                return Err(crate::ContactError::NoSuchTool {
                    pair: p.name().into(),
                    tool: p.tool(),
                    count: tools.len(),
                });
            }
        }
        if thickness.len() != geometry.node_count() {
            return Err(crate::ContactError::Mesh(format!(
                "{} nodal thicknesses for {} nodes",
                thickness.len(),
                geometry.node_count()
            )));
        }
        let needs = pairs.iter().fold(PointNeeds::NONE, |a, p| a | p.needs());
        let n = geometry.node_count();
        let flow_stress = needs
            .contains(PointNeeds::FLOW_STRESS)
            .then(|| (vec![0.0; n], vec![0.0; n]));
        let parallel = geometry.quads().len() > BlankGeometry::PARALLEL_MIN_QUADS
            || pairs
                .iter()
                .any(|p| p.nodes().len() > ContactPair::PARALLEL_MIN_CANDIDATES);
        let m = pairs.len();
        Ok(Self {
            parallel,
            active: vec![false; m],
            before: vec![ContactEnergy::default(); m],
            outcome: (0..m).map(|_| None).collect(),
            tool_log: vec![Vec::new(); tools.len()],
            tool_work_step: vec![0.0; tools.len()],
            reactions: vec![Vec3::zeros(); tools.len()],
            loads: vec![ToolLoad::default(); tools.len()],
            tools,
            pairs,
            geometry,
            needs,
            thickness,
            flow_stress,
            energy: ContactEnergy::default(),
            timing: ContactTiming::default(),
            beads: BeadSet::default(),
        })
    }

    /// Add drawbeads ([`Drawbead`], docs/drawbeads.md): each acts where it
    /// crosses blank touching its tool, through that tool's pairs. Their
    /// points are given in the global frame at the tools' current poses
    /// (the scene's frame, at set-up) and are fixed to the tool from then on.
    ///
    /// # Errors
    /// A bead on a missing tool, or a bead [`Drawbead::new`] refuses.
    pub fn with_drawbeads(mut self, specs: Vec<DrawbeadSpec>) -> Result<Self, crate::ContactError> {
        let quads = self.geometry.quads().len();
        let mut beads = Vec::new();
        for mut spec in specs {
            let Some(tool) = self.tools.get(spec.tool) else {
                return Err(crate::ContactError::NoSuchTool {
                    pair: format!("drawbead {}", spec.name),
                    tool: spec.tool,
                    count: self.tools.len(),
                });
            };
            let pose = tool.pose();
            spec.points.iter_mut().for_each(|p| *p = pose.to_local(p));
            beads.push(Drawbead::new(spec, quads)?);
        }
        self.beads = BeadSet::new(beads, self.geometry.node_count());
        Ok(self)
    }

    /// The drawbeads.
    pub fn drawbeads(&self) -> &[Drawbead] {
        &self.beads.beads
    }

    /// The drawbeads' energies together (N·mm).
    pub fn bead_energy(&self) -> BeadEnergy {
        self.beads.energy()
    }

    /// What the pairs read, united (friction-math §6).
    pub fn needs(&self) -> PointNeeds {
        self.needs
    }

    /// Make pair `pair` keep (`on`) or stop keeping a record of its friction
    /// stage ([`ContactPair::record_friction`]), and compute the blank's
    /// gradients the record needs.
    ///
    /// # Errors
    /// No pair of that index.
    pub fn record_friction(&mut self, pair: usize, on: bool) -> Result<(), crate::ContactError> {
        let count = self.pairs.len();
        let p = self.pairs.get_mut(pair).ok_or_else(|| {
            crate::ContactError::Mesh(format!(
                "record_friction: no contact pair {pair} (the effect has {count})"
            ))
        })?;
        p.record_friction(on);
        self.needs = self
            .pairs
            .iter()
            .fold(PointNeeds::NONE, |a, p| a | p.needs());
        Ok(())
    }

    /// The initial nodal thickness (mm) given to [`ContactEffect::new`]: what
    /// the pairs read when no effect writes [`NodalField::THICKNESS`] (the
    /// solver's [`fem_core::Solver::field`] holds it when one does).
    pub fn initial_thickness(&self) -> &[f64] {
        &self.thickness
    }

    /// The tools.
    pub fn tools(&self) -> &[Box<dyn ToolSurface>] {
        &self.tools
    }

    /// The pairs.
    pub fn pairs(&self) -> &[ContactPair] {
        &self.pairs
    }

    /// The blank's nodal geometry as of the last step.
    pub fn geometry(&self) -> &BlankGeometry {
        &self.geometry
    }

    /// Force the blank exerted on each tool in the last step (N).
    pub fn reactions(&self) -> &[Vec3] {
        &self.reactions
    }

    /// What each tool did, press step by press step (index: tool).
    pub fn tool_log(&self) -> &[Vec<ToolStepLog>] {
        &self.tool_log
    }

    /// Energies of all pairs together (N·mm).
    pub fn energy(&self) -> ContactEnergy {
        let mut e = self.energy;
        e.stored = self.pairs.iter().map(|p| p.energy.stored).sum();
        e
    }

    /// Seconds spent per stage of the contact steps so far: placing the tools
    /// and the nodal geometry, and every pair's stages summed. What the stages leave
    /// out of the whole [`Effect::add_forces`] (copying the shared fields,
    /// summing the energies, logging the tools, handing the step to rayon's
    /// pool) is small; the solver times the whole call
    /// ([`fem_core::Solver::timing`]).
    pub fn timing(&self) -> ContactTiming {
        let mut t = self.timing;
        for p in &self.pairs {
            t.add(&p.timing);
        }
        t
    }

    /// One contact step (`ctx.dt > 0`): tools, nodal geometry, every pair.
    fn step(
        &mut self,
        ctx: &StepContext<'_>,
        state: &NodalState,
        forces: &mut Forces,
        fields: &FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let t_start = Instant::now();
        if let Some(press) = ctx.press {
            for (i, tool) in self.tools.iter_mut().enumerate() {
                tool.set_pose(press.pose(i), press.velocity(i));
            }
        }
        let flow_stress = self.flow_stress.as_ref().map(|(top, bottom)| {
            match (
                fields.read(NodalField::FLOW_STRESS_TOP),
                fields.read(NodalField::FLOW_STRESS_BOTTOM),
            ) {
                (Some(t), Some(b)) => (t, b),
                _ => (top.as_slice(), bottom.as_slice()),
            }
        });
        let view = BlankView {
            x0: &state.x0,
            x: &state.x,
            v: &state.v,
            mass: &state.mass,
            thickness: fields
                .read(NodalField::THICKNESS)
                .unwrap_or(&self.thickness),
            flow_stress,
        };
        self.geometry.update(&view, ctx.dt, self.needs);
        self.timing.geometry += t_start.elapsed().as_secs_f64();
        self.reactions.iter_mut().for_each(|r| *r = Vec3::zeros());
        self.loads.iter_mut().for_each(|l| *l = ToolLoad::default());
        let mut friction = 0.0;
        let mut tool_work = 0.0;
        let mut blank_work = 0.0;
        self.tool_work_step.iter_mut().for_each(|w| *w = 0.0);
        for (k, (active, energy)) in self.active.iter_mut().zip(&mut self.before).enumerate() {
            *active = ctx.press.is_none_or(|p| p.pair_active(k));
            *energy = self.pairs[k].energy;
        }
        step_pairs(
            PairsStep {
                tools: &self.tools,
                geometry: &self.geometry,
                view: &view,
                dt: ctx.dt,
                parallel: self.parallel,
            },
            &mut self.pairs,
            &self.active,
            &mut self.outcome,
        )?;
        for (k, pair) in self.pairs.iter_mut().enumerate() {
            let (active, before) = (self.active[k], self.before[k]);
            if active {
                pair.add_forces(&mut forces.f);
                self.reactions[pair.tool()] += pair.reaction.force;
                let load = &mut self.loads[pair.tool()];
                load.stiffness += pair.reaction.stiffness;
            } else {
                pair.release();
            }
            friction += pair.energy.friction - before.friction;
            tool_work += pair.energy.tool_work - before.tool_work;
            self.tool_work_step[pair.tool()] += pair.energy.tool_work - before.tool_work;
            blank_work += pair.energy.blank_work - before.blank_work;
        }
        self.energy.friction += friction;
        self.energy.tool_work += tool_work;
        self.energy.blank_work += blank_work;
        if !self.beads.beads.is_empty() {
            let inputs = BeadInputs {
                pairs: &self.pairs,
                active: &self.active,
                tools: &self.tools,
                geometry: &self.geometry,
                view: &view,
                dt: ctx.dt,
            };
            self.beads.step(
                &inputs,
                &mut forces.f,
                &mut self.reactions,
                &mut self.tool_work_step,
            );
        }
        for (load, r) in self.loads.iter_mut().zip(&self.reactions) {
            load.force = *r;
        }
        self.log_tools(ctx.dt, ctx.press);
        Ok(())
    }

    /// Sample what each tool did in this explicit step.
    fn log_tools(&mut self, dt: f64, press: Option<&Press>) {
        for (i, log) in self.tool_log.iter_mut().enumerate() {
            let direction = press
                .and_then(|p| p.direction(i).or_else(|| p.first_direction(i)))
                .unwrap_or(-Vec3::z());
            let sample = ToolSample {
                step: press.map_or(0, |p| p.current_step()),
                dt,
                direction,
                force: -self.reactions[i],
                applied: press.and_then(|p| p.applied_force(i)),
                displacement: press.map_or_else(Vec3::zeros, |p| p.displacement(i)),
                step_start: press.map_or_else(Vec3::zeros, |p| p.step_start_displacement(i)),
                work: self.tool_work_step[i],
                momentum: press.and_then(|p| p.momentum(i)),
            };
            record(log, &sample);
        }
    }
}

/// Copy `field` into `dst` when another effect writes it.
/// What every pair of a step reads.
struct PairsStep<'a> {
    tools: &'a [Box<dyn ToolSurface>],
    geometry: &'a BlankGeometry,
    view: &'a BlankView<'a>,
    dt: f64,
    /// Whether the blank is large enough for parallel loops.
    parallel: bool,
}

/// Step the `active` pairs ([`ContactPair::step_apart`]): at the same time
/// on rayon's pool when the blank is large enough for parallel loops and
/// more than one pair is active (each pair reads the shared tools, blank and
/// geometry and writes only its own data), else one after the other. The
/// first error in pair order is returned, whatever the threads did;
/// `outcome` is per-pair scratch.
fn step_pairs(
    s: PairsStep<'_>,
    pairs: &mut [ContactPair],
    active: &[bool],
    outcome: &mut [Option<crate::ContactError>],
) -> Result<(), FemError> {
    let one = |pair: &mut ContactPair, active: bool| {
        if active {
            let tool = s.tools[pair.tool()].as_ref();
            pair.step_apart(tool, s.geometry, s.view, s.dt)
        } else {
            Ok(())
        }
    };
    outcome.iter_mut().for_each(|o| *o = None);
    let busy = active.iter().filter(|a| **a).count();
    if s.parallel && busy > 1 && rayon::current_num_threads() > 1 {
        outcome
            .par_iter_mut()
            .zip(pairs.par_iter_mut())
            .zip(active.par_iter())
            .for_each(|((o, pair), &active)| *o = one(pair, active).err());
    } else {
        for ((o, pair), &active) in outcome.iter_mut().zip(pairs).zip(active) {
            *o = one(pair, active).err();
            if o.is_some() {
                break;
            }
        }
    }
    match outcome.iter_mut().find_map(Option::take) {
        Some(e) => Err(FemError::Effect {
            effect: "contact".into(),
            message: e.to_string(),
        }),
        None => Ok(()),
    }
}

/// What contact reads without and with a law that needs the flow stress.
const READS_THICKNESS: [NodalField; 3] =
    [NodalField::THICKNESS, NodalField::AREA, NodalField::NORMAL];
const READS_ALL: [NodalField; 5] = [
    NodalField::THICKNESS,
    NodalField::AREA,
    NodalField::NORMAL,
    NodalField::FLOW_STRESS_TOP,
    NodalField::FLOW_STRESS_BOTTOM,
];

impl Effect for ContactEffect {
    fn name(&self) -> &str {
        "contact"
    }

    /// Every pair's per-point state (friction history, warm starts) and the
    /// blank's deformation gradients.
    fn save_state(&self, out: &mut fem_core::StateArrays) {
        self.save_arrays(out);
    }

    /// The saved state, pairs matched by name (a dropped pair's state
    /// noted). Drawbeads keep no saved state: each starts with its
    /// restraining springs unloaded, and a note says so.
    fn restore_state(
        &mut self,
        saved: &fem_core::StateArrays,
        notes: &mut Vec<String>,
    ) -> Result<(), String> {
        self.restore_arrays(saved, notes)?;
        if !self.drawbeads().is_empty() {
            notes.push(
                "drawbeads start with their restraining springs unloaded (a state file does not carry them)"
                    .into(),
            );
        }
        Ok(())
    }

    /// The nodal thickness, and the outer-fibre flow stress when a pair's
    /// law declares [`PointNeeds::FLOW_STRESS`].
    fn reads(&self) -> &[NodalField] {
        if self.flow_stress.is_some() {
            &READS_ALL
        } else {
            &READS_THICKNESS
        }
    }

    fn add_forces(
        &mut self,
        ctx: &StepContext<'_>,
        state: &NodalState,
        forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        // The areas also serve the time step and mass scaling, from set-up on.
        if let (Some(area), Some(normal)) = (
            fields.read(NodalField::AREA),
            fields.read_vec3(NodalField::NORMAL),
        ) {
            self.geometry.set_nodal(area, normal);
        }
        if ctx.dt <= 0.0 {
            return Ok(());
        }
        let fields = &*fields;
        if self.parallel
            && rayon::current_num_threads() > 1
            && rayon::current_thread_index().is_none()
        {
            // Run the whole step on a pool thread: its parallel loops then
            // start at once on that thread (the others join when they wake),
            // instead of the caller waking the pool and waiting for each loop.
            rayon::scope(|_| self.step(ctx, state, forces, fields))
        } else {
            self.step(ctx, state, forces, fields)
        }
    }

    fn scale_mass(
        &mut self,
        _state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        _inertia: &mut [f64],
    ) -> f64 {
        self.pairs
            .iter()
            .map(|p| p.scale_mass(target_dt, mass, &self.geometry.area))
            .sum()
    }

    fn stiffens_nodes(&self) -> bool {
        self.pairs.iter().any(ContactPair::touching) || self.beads.engaged()
    }

    /// The penalty and stick springs of the touching points, summed over
    /// the pairs (a flange node between die and holder gets both), and the
    /// drawbeads' stick springs.
    fn nodal_stiffness(&self, _state: &NodalState, stiffness: &mut [f64]) {
        for p in &self.pairs {
            p.add_nodal_stiffness(&self.geometry.area, stiffness);
        }
        for (s, b) in stiffness.iter_mut().zip(&self.beads.stiffness) {
            *s += b;
        }
    }

    /// The pairs' springs, and the drawbeads' stick springs alone
    /// (`2 √(m / s)` per node; they are soft beside the penalty springs).
    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        let pairs = self
            .pairs
            .iter()
            .filter_map(|p| p.stable_dt(&state.mass, &self.geometry.area))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(dt, node)| StableDt {
                dt,
                element: node,
                what: "contact springs (penalty + stick) at a blank node (element = node index)",
            });
        let beads = self
            .beads
            .stiffness
            .iter()
            .zip(&state.mass)
            .enumerate()
            .filter(|(_, (s, _))| **s > 0.0)
            .map(|(i, (s, m))| (2.0 * (m / s).sqrt(), i))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(dt, node)| StableDt {
                dt,
                element: node,
                what: "drawbead stick springs at a blank node (element = node index)",
            });
        match (pairs, beads) {
            (Some(p), Some(b)) => Some(if b.dt < p.dt { b } else { p }),
            (p, b) => p.or(b),
        }
    }

    /// The force and contact stiffness of the blank on each tool in the
    /// last step.
    fn tool_loads(&self) -> &[ToolLoad] {
        &self.loads
    }

    /// The pairs' energies and the drawbeads': their dissipation is `bead`,
    /// the rest of what their tools put in and the blank did not receive
    /// (the stick springs' energy) joins `contact`.
    fn energies(&self) -> EnergyTally {
        let e = self.energy();
        let b = self.bead_energy();
        EnergyTally {
            contact: e.contact() + (b.tool_work - b.blank_work - b.dissipation),
            friction: e.friction,
            bead: b.dissipation,
            external: e.tool_work + b.tool_work,
            ..EnergyTally::default()
        }
    }

    /// Contact has no static form: a static solve comes after the tools
    /// have let go (a springback step ends every pair), and then it adds
    /// nothing.
    fn static_form(&self) -> Result<fem_core::StaticForm, String> {
        Ok(fem_core::StaticForm::Released)
    }
}
