//! The explicit solver: set-up (masses, mass scaling, initial forces), the central-difference step, run loop and output hook.
//!
//! # One step (`t_n → t_{n+1}`), stage by stage
//!
//! [`Solver::step`] runs six named stages in this order; the numbers are the
//! ones every document uses. With `Δt = Δt_{n+1/2}` (chosen at the end of the
//! previous step) and `Δt̄ = (Δt_{n-1/2} + Δt_{n+1/2})/2`:
//!
//! 1. **Integrate** (`update_nodes`: one pass over the nodes in fixed
//!    chunks, in parallel on large models with the same bits on any number
//!    of threads, then the constrained nodes):
//!    `a_n = M⁻¹ f_n`; `v_{n+1/2} = [(1 − c Δt̄/2) v_{n-1/2} + Δt̄ a_n] / (1 + c Δt̄/2)`
//!    (`c` the dynamic-relaxation damping, 0 by default; the same for `w`
//!    with the scalar inertia); constrained DOFs overwrite their velocity
//!    (fixed → 0, prescribed velocity → `value · A(t_{n+1/2})`, prescribed
//!    displacement → `(value · A(t_{n+1}) − u_n)/Δt`, so the displacement is
//!    met exactly); `x_{n+1} = x_n + Δt v_{n+1/2}`.
//! 2. **Ledger** (`book_energy`): the energies at `t_n` (see
//!    [`crate::energy`]); `t_{n+1} = t_n + Δt`.
//! 3. **Press** (`move_press`, [`crate::press`]): the rigid tools move to
//!    `t_{n+1}`, force-controlled ones reading what the effects did to them
//!    in the last step ([`Effect::tool_loads`]). The effects read the press
//!    through [`StepContext::press`].
//! 4. **Element forces** and 5. **contact forces** (`compute_forces`): zero,
//!    add nodal loads `value · A(t_{n+1})`, then each effect, every writer of
//!    a shared nodal field before its readers (see [`crate::fields`]): a
//!    reader sees the field at `t_{n+1}`, as its writer computed it in this
//!    same step. In formsim the writers are the blank's shells (stage 4) and
//!    the reader is contact (stage 5).
//! 6. **Time step** (`next_dt`): `Δt_{n+3/2} = min(safety × stable dt, dt_max)`,
//!    the stable dt the smallest of the effects' own and of the effects on
//!    one node together ([`crate::nodal_limit`]), with mass scaling if
//!    configured; a collapse stops the run with an error. A fixed step
//!    (`fixed_dt`) is checked against the stable dt instead, and the run
//!    stops when it is above.
//!
//! Nodes with zero mass (zero inertia) do not move (do not rotate): they are
//! counted in [`SetupReport::massless_nodes`].

use crate::fields::{Declared, effect_order};
use crate::nodal_limit::NodalLimit;
use crate::relaxation::{Relaxation, SpringbackReport};
use crate::selective_mass::SelectiveMass;

mod implicit_release;
pub(crate) mod node_chunks;
mod resume_state;
use crate::{
    Amplitude, BoundaryCondition, Dof, Dofs, Effect, EnergyLedger, EnergyTally, FemError, Forces,
    MassScaling, Mesh, MotionKind, NodalField, NodalLoad, NodalState, Press, SelectiveStats,
    SharedFields, SolverSettings, StableDt, StepContext, StepEnd, ToolLoad, Vec3,
};
use std::any::Any;
use std::collections::BTreeMap;
use std::time::Instant;

/// During a run, mass scaling brings elements whose step fell below the
/// target up to `target × (1 + MASS_SCALING_HEADROOM)`: a 2 % headroom that
/// spares a full mass-scaling pass at every step of a forming run, where
/// elements shrink a little each step (set-up scales to the target exactly).
pub const MASS_SCALING_HEADROOM: f64 = 0.02;

/// The most conjugate-gradient iterations a selective mass solve takes; a
/// solve stopped here is counted in [`SelectiveStats::unconverged`].
pub const SELECTIVE_MAX_ITERATIONS: u32 = 200;

/// Handle of an effect added to a [`Solver`] (its index, in order of addition).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct EffectId(pub usize);

/// The effect and element that limit the time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DtLimit {
    /// Index of the effect (see [`Solver::effect_name`]); for a combined
    /// limit, the effect whose own limit is the smallest.
    pub effect: usize,
    /// Its stable time step (without safety factor) and limiting element.
    pub stable: StableDt,
    /// `true` when the limit is that of the effects on one node together
    /// ([`crate::nodal_limit`]); `stable.element` is then the node.
    pub combined: bool,
}

/// What [`Solver::initialize`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetupReport {
    /// Translational mass from the effects and point masses (tonne).
    pub physical_mass: f64,
    /// Mass added by mass scaling at set-up (tonne).
    pub added_mass: f64,
    /// `100 × added_mass / physical_mass` (%).
    pub added_mass_percent: f64,
    /// The first time step `Δt_{1/2}` (s), safety factor included.
    pub dt_initial: f64,
    /// What limits it (`None` when only `dt_max` does).
    pub limit: Option<DtLimit>,
    /// Nodes without translational mass (they do not move).
    pub massless_nodes: usize,
}

/// What one step did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// Step number `n + 1` of the state now held.
    pub step: u64,
    /// Time of the state now held, `t_{n+1}` (s).
    pub time: f64,
    /// Time step just taken, `Δt_{n+1/2}` (s).
    pub dt: f64,
    /// Time step the next step will take, `Δt_{n+3/2}` (s).
    pub dt_next: f64,
    /// What limits `dt_next` (`None` when only `dt_max` does).
    pub limit: Option<DtLimit>,
    /// Cumulative mass added by mass scaling so far (tonne).
    pub added_mass: f64,
    /// Energies at `t_n` (`energy.time`), one step behind `time`.
    pub energy: EnergyLedger,
}

/// Wall-clock seconds a [`Solver`] spent in its steps, by stage, summed over
/// every [`Solver::step`] since set-up ([`Solver::initialize`] is not
/// counted). Read with [`Solver::timing`].
///
/// The stages are timed with [`std::time::Instant`] at their boundaries
/// only (about ten readings of the clock per step, whatever the model's
/// size), so timing costs well under a microsecond per step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepTiming {
    /// Whole calls of [`Solver::step`] (s).
    pub total: f64,
    /// Stages 1–2: velocities, constraints, positions and the energy ledger (s).
    pub integration: f64,
    /// Stage 3: the press moving the rigid tools to `t_{n+1}` (s).
    pub press: f64,
    /// Stages 4–5 outside the effects: zeroing the forces, nodal loads, the
    /// finiteness check of the summed forces (s).
    pub assembly: f64,
    /// Stage 6: the effects' stable time steps and mass scaling during the run (s).
    pub time_step: f64,
    /// Stage 1's mass solve of selective mass scaling (s; part of `integration`).
    pub selective_mass: f64,
    /// Handing a step called from outside rayon's pool back to its caller
    /// (s); the hand-over into the pool is part of `integration`.
    pub handover: f64,
    /// Each effect's [`Effect::add_forces`], by effect index (order of
    /// addition, see [`Solver::effect_name`]) (s).
    pub effects: Vec<f64>,
}

impl StepTiming {
    /// The engine's own seconds: `integration + assembly + time_step +
    /// handover` (everything of the step but the press and the effects'
    /// forces).
    pub fn engine(&self) -> f64 {
        self.integration + self.assembly + self.time_step + self.handover
    }

    /// Zero every sum (no allocation).
    fn reset(&mut self) {
        self.total = 0.0;
        self.integration = 0.0;
        self.press = 0.0;
        self.assembly = 0.0;
        self.time_step = 0.0;
        self.selective_mass = 0.0;
        self.handover = 0.0;
        self.effects.iter_mut().for_each(|s| *s = 0.0);
    }
}

/// Returned by the run-loop callback.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on.
    Continue,
    /// Stop after this step.
    Stop,
}

/// How a [`Solver::run_until`] ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSummary {
    /// Steps taken by this call.
    pub steps: u64,
    /// Whether the callback asked to stop before `t_end`.
    pub stopped_by_callback: bool,
    /// Report of the last step taken (`None` if none was).
    pub last: Option<StepReport>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum ConstraintKind {
    Fixed,
    /// Index into `Solver::motions`.
    Prescribed(u32),
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Constraint {
    node: u32,
    dof: u8,
    kind: ConstraintKind,
}

#[derive(Debug, Clone, PartialEq)]
struct Motion {
    kind: MotionKind,
    value: f64,
    amplitude: u32,
    /// Displacement (rotation) reached so far (mm or rad).
    done: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct LoadEntry {
    node: u32,
    dof: u8,
    value: f64,
    amplitude: u32,
}

/// Running sums of the work terms, split at the step boundaries (see `energy`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct WorkSums {
    mass_scaling: f64,
    loads: f64,
    loads_pending: f64,
    prescribed: f64,
    prescribed_pending: f64,
    damping_work: f64,
    damping_pending: f64,
    /// The step-change term of `integration` (see [`Solver::step_change_sums`]).
    step_change: f64,
    step_change_pending: f64,
    /// The work of `ΔM a`, the selective mass's inertia force.
    added_inertia: f64,
    added_inertia_pending: f64,
}

/// Energy sums of one nodal update (index 0: translations, 1: rotations).
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    /// Product form `½ m v_{n-1/2}·v_{n+1/2}`.
    ke_prod: [f64; 2],
    /// Mid-step form `½ m |v̄_n|²`.
    ke_mid: [f64; 2],
    damp_cur: f64,
    damp_pend: f64,
    presc_cur: f64,
    presc_pend: f64,
}

impl Sums {
    /// Replace a constrained DOF's free contribution (velocity `vfree`) by the
    /// constrained one (`vn`) and add the reaction's work; `f` is the nodal force.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn constrained(
        &mut self,
        m: f64,
        vo: f64,
        vfree: f64,
        vn: f64,
        f: f64,
        r: usize,
        c: f64,
        hb: f64,
    ) -> f64 {
        if m > 0.0 {
            self.ke_prod[r] += 0.5 * m * vo * (vn - vfree);
            self.ke_mid[r] += 0.125 * m * ((vo + vn).powi(2) - (vo + vfree).powi(2));
            if c > 0.0 {
                let dh = -0.5 * c * m * hb * (vo + vfree);
                self.damp_cur -= 0.5 * dh * vo;
                self.damp_pend -= 0.5 * dh * vfree;
            }
        }
        let hr = m * (vn - vo) - hb * f;
        self.presc_cur += 0.5 * hr * vo;
        self.presc_pend += 0.5 * hr * vn;
        hr / hb
    }
}

/// The constants of one step `t_n → t_{n+1}` (see the module docs).
#[derive(Clone, Copy)]
struct StepConstants {
    /// `Δt = Δt_{n+1/2}`.
    dt: f64,
    /// `t_n`.
    t_n: f64,
    /// `Δt̄ = (Δt_{n-1/2} + Δt_{n+1/2})/2`.
    hb: f64,
    /// The damping `c`.
    c: f64,
    /// `1 − c Δt̄/2`.
    d1: f64,
    /// `1 / (1 + c Δt̄/2)`.
    d2: f64,
    /// `t_{n+1/2}`.
    t_half: f64,
    /// `t_{n+1}` (the landing time when the step lands on one).
    t_next: f64,
}

/// The free DOFs' energy sums of one nodal update, before their factors
/// (index 0: translations, 1: rotations): `Σ m vo·vn`, `Σ m |vo+vn|²` and the
/// damping halves `Σ m (vo+vn)·vo`, `Σ m (vo+vn)·vn`.
#[derive(Clone, Copy, Default)]
struct FreeSums {
    product: [f64; 2],
    sum2: [f64; 2],
    damp_cur: f64,
    damp_pend: f64,
}

impl FreeSums {
    /// The free update of one DOF triple of mass (inertia) `m > 0`, velocity
    /// `vo` and force `f` into `v`, summed under `r`.
    #[inline(always)]
    fn update(&mut self, r: usize, m: f64, v: &mut Vec3, vo: Vec3, f: &Vec3, k: &StepConstants) {
        let u = velocity_step(vo, f, k.hb / m, k.d1, k.d2);
        *v = u.v;
        self.product[r] += m * u.product;
        self.sum2[r] += m * u.sum2;
        if k.c > 0.0 {
            self.damp_cur += m * u.sum_old;
            self.damp_pend += m * u.sum_new;
        }
    }

    /// Add another chunk's sums to these (term by term).
    #[inline]
    fn merge(&mut self, o: &FreeSums) {
        for r in 0..2 {
            self.product[r] += o.product[r];
            self.sum2[r] += o.sum2[r];
        }
        self.damp_cur += o.damp_cur;
        self.damp_pend += o.damp_pend;
    }

    /// Add the free sums to `sums`: ½ m vo·vn, ⅛ m |vo+vn|², and the damping
    /// work halves ½ Δt̄ D·v with Δt̄ D = −½ c m Δt̄ (vo + vn).
    #[inline(always)]
    fn add_to(&self, sums: &mut Sums, c: f64, hb: f64) {
        sums.ke_prod[0] += 0.5 * self.product[0];
        sums.ke_prod[1] += 0.5 * self.product[1];
        sums.ke_mid[0] += 0.125 * self.sum2[0];
        sums.ke_mid[1] += 0.125 * self.sum2[1];
        sums.damp_cur += -0.25 * c * hb * self.damp_cur;
        sums.damp_pend += -0.25 * c * hb * self.damp_pend;
    }
}

/// One node's values before its constraints are applied.
struct Node {
    m: f64,
    j: f64,
    vo: Vec3,
    wo: Vec3,
    f: Vec3,
    mt: Vec3,
}

/// Apply the constraints of node `i` (starting at `k` in the node-sorted
/// list) to its velocities; returns the index after its last constraint.
#[allow(clippy::too_many_arguments)]
#[cold]
#[inline(never)]
fn apply_constraints(
    i: usize,
    mut k: usize,
    node: &Node,
    v: &mut Vec3,
    w: &mut Vec3,
    constraints: &[Constraint],
    reactions: &mut [f64],
    motions: &mut [Motion],
    amplitudes: &[Amplitude],
    (t_half, t_next, dt, c, hb): (f64, f64, f64, f64, f64),
    sums: &mut Sums,
) -> usize {
    while let Some(con) = constraints.get(k).filter(|con| con.node as usize == i) {
        k += 1;
        let axis = (con.dof % 3) as usize;
        let rot = con.dof >= 3;
        let (m, vo, vfree, f) = if rot {
            (node.j, node.wo[axis], w[axis], node.mt[axis])
        } else {
            (node.m, node.vo[axis], v[axis], node.f[axis])
        };
        let vn = match con.kind {
            ConstraintKind::Fixed => 0.0,
            ConstraintKind::Prescribed(p) => {
                let mo = &mut motions[p as usize];
                let a = &amplitudes[mo.amplitude as usize];
                let vn = match mo.kind {
                    MotionKind::Velocity => mo.value * a.value(t_half),
                    MotionKind::Displacement => (mo.value * a.value(t_next) - mo.done) / dt,
                };
                mo.done += vn * dt;
                vn
            }
        };
        if rot {
            w[axis] = vn;
        } else {
            v[axis] = vn;
        }
        reactions[k - 1] = sums.constrained(m, vo, vfree, vn, f, rot as usize, c, hb);
    }
    k
}

/// The explicit solver: nodal state, effects, boundary conditions, loads and settings.
///
/// Build with [`Solver::new`], add effects ([`Solver::add_effect`]),
/// boundary conditions and loads, optionally [`Solver::initialize`] (else the
/// first step does it), then [`Solver::step`] or [`Solver::run_until`]. After
/// an error the solver still holds the state computed so far.
pub struct Solver {
    settings: SolverSettings,
    state: NodalState,
    forces: Forces,
    v_old: Vec<Vec3>,
    w_old: Vec<Vec3>,
    /// Each node chunk's energy sums of the last update (see `node_chunks`).
    chunk_sums: Vec<FreeSums>,
    scratch_mass: Vec<f64>,
    scratch_inertia: Vec<f64>,
    /// The effects' stiffness summed per node (the combined step limit).
    nodal: NodalLimit,
    node_sets: BTreeMap<String, Vec<u32>>,
    effects: Vec<Box<dyn Effect>>,
    /// The order of the effects' `add_forces` (indices into `effects`):
    /// writers of shared fields before their readers, fixed at set-up.
    order: Vec<usize>,
    /// The nodal fields effects share, allocated at set-up.
    fields: SharedFields,
    /// The press that moves the rigid tools, if any (its own stage).
    press: Option<Press>,
    /// What the effects did to each tool of the press in the last force
    /// computation, summed (read by the press in the next step).
    tool_loads: Vec<ToolLoad>,
    point_masses: Vec<(u32, f64, f64)>,
    constraints: Vec<Constraint>,
    /// Reaction (N or N·mm) of each constraint at the ledger time `t_n`.
    reactions: Vec<f64>,
    /// Per node, bit `Dof::index` set when that DOF is constrained.
    constrained: Vec<u8>,
    /// Per node, bit set when that DOF is fixed.
    fixed: Vec<u8>,
    motions: Vec<Motion>,
    loads: Vec<LoadEntry>,
    amplitudes: Vec<Amplitude>,
    amp_values: Vec<f64>,
    time: f64,
    step: u64,
    dt_prev: f64,
    dt_next: f64,
    dt_floor: f64,
    limit: Option<DtLimit>,
    initialized: bool,
    setup: Option<SetupReport>,
    tally: EnergyTally,
    work: WorkSums,
    total0: f64,
    /// The ledger of the runs before, when this one continues a saved state.
    carried: Option<EnergyLedger>,
    ledger: EnergyLedger,
    physical_mass: f64,
    added_mass: f64,
    land_at: Option<f64>,
    /// Seconds spent per stage of the steps.
    timing: StepTiming,
    /// The running springback step's dynamic relaxation, if any.
    relaxation: Option<Relaxation>,
    /// What the last springback step did.
    springback: Option<SpringbackReport>,
    /// Selective mass scaling's blocks and mass solve, when the run scales so.
    selective: Option<SelectiveMass>,
}

impl Solver {
    /// A solver at rest in the mesh's configuration (the mesh is validated).
    pub fn new(mesh: &Mesh, settings: SolverSettings) -> Result<Self, FemError> {
        mesh.validate()?;
        Self::from_nodes(&mesh.nodes, mesh.node_sets.clone(), settings)
    }

    /// A solver over bare nodes and node sets (no quads; e.g. spring models).
    pub fn from_nodes(
        nodes: &[Vec3],
        node_sets: BTreeMap<String, Vec<u32>>,
        settings: SolverSettings,
    ) -> Result<Self, FemError> {
        settings.validate()?;
        for (i, p) in nodes.iter().enumerate() {
            for (axis, value) in ["x", "y", "z"].into_iter().zip(p.iter()) {
                if !value.is_finite() {
                    return Err(FemError::NonFiniteCoordinate {
                        node: i,
                        axis,
                        value: *value,
                    });
                }
            }
        }
        for (name, set) in &node_sets {
            if let Some(&i) = set.iter().find(|&&i| i as usize >= nodes.len()) {
                return Err(FemError::SetOutOfRange {
                    kind: "node set",
                    name: name.clone(),
                    index: i as u64,
                    len: nodes.len(),
                });
            }
        }
        let n = nodes.len();
        Ok(Self {
            settings,
            state: NodalState::at_rest(nodes),
            forces: Forces::zeros(n),
            v_old: vec![Vec3::zeros(); n],
            w_old: vec![Vec3::zeros(); n],
            chunk_sums: vec![FreeSums::default(); node_chunks::chunks(n)],
            scratch_mass: vec![0.0; n],
            scratch_inertia: vec![0.0; n],
            nodal: NodalLimit::new(n),
            node_sets,
            effects: Vec::new(),
            order: Vec::new(),
            fields: SharedFields::default(),
            press: None,
            tool_loads: Vec::new(),
            point_masses: Vec::new(),
            constraints: Vec::new(),
            reactions: Vec::new(),
            constrained: vec![0; n],
            fixed: vec![0; n],
            motions: Vec::new(),
            loads: Vec::new(),
            amplitudes: Vec::new(),
            amp_values: Vec::new(),
            time: 0.0,
            step: 0,
            dt_prev: 0.0,
            dt_next: 0.0,
            dt_floor: 0.0,
            limit: None,
            initialized: false,
            setup: None,
            tally: EnergyTally::default(),
            work: WorkSums::default(),
            total0: 0.0,
            carried: None,
            ledger: EnergyLedger::default(),
            physical_mass: 0.0,
            added_mass: 0.0,
            land_at: None,
            timing: StepTiming::default(),
            relaxation: None,
            springback: None,
            selective: None,
        })
    }

    // ----- building ---------------------------------------------------------

    /// Add an effect. Effects are called in the order they were added, but
    /// for shared fields: at set-up each writer is moved before its readers
    /// ([`Effect::writes`], [`Effect::reads`]). An effect added after set-up
    /// runs last and shares no field.
    pub fn add_effect<E: Effect>(&mut self, effect: E) -> EffectId {
        self.add_boxed_effect(Box::new(effect))
    }

    /// Give the solver the press that moves the rigid tools: its stage runs
    /// in every step before the effects' forces, and the effects read it
    /// through [`StepContext::press`].
    ///
    /// # Errors
    /// Called after set-up.
    pub fn set_press(&mut self, press: Press) -> Result<(), FemError> {
        self.require_not_initialized("set the press")?;
        self.tool_loads = vec![ToolLoad::default(); press.tool_names().len()];
        self.press = Some(press);
        Ok(())
    }

    /// The press, if any, as of the last step.
    pub fn press(&self) -> Option<&Press> {
        self.press.as_ref()
    }

    /// What the effects did to each tool of the press in the last step,
    /// summed over the effects (index: tool).
    pub fn tool_loads(&self) -> &[ToolLoad] {
        &self.tool_loads
    }

    /// Add a boxed effect.
    pub fn add_boxed_effect(&mut self, effect: Box<dyn Effect>) -> EffectId {
        self.effects.push(effect);
        self.timing.effects.push(0.0);
        self.order.push(self.effects.len() - 1);
        EffectId(self.effects.len() - 1)
    }

    /// The effect `id` as its concrete type (`None` if it is another type).
    pub fn effect<E: Effect>(&self, id: EffectId) -> Option<&E> {
        let e: &dyn Any = self.effects.get(id.0)?.as_ref();
        e.downcast_ref::<E>()
    }

    /// The effect `id` as its concrete type, mutable.
    pub fn effect_mut<E: Effect>(&mut self, id: EffectId) -> Option<&mut E> {
        let e: &mut dyn Any = self.effects.get_mut(id.0)?.as_mut();
        e.downcast_mut::<E>()
    }

    /// Name of the effect with index `index`.
    pub fn effect_name(&self, index: usize) -> &str {
        self.effects.get(index).map_or("?", |e| e.name())
    }

    /// Add a point mass (tonne) and rotational inertia (tonne·mm²) to every node of `set`.
    pub fn add_point_mass(&mut self, set: &str, mass: f64, inertia: f64) -> Result<(), FemError> {
        for (field, value, unit) in [("mass", mass, "tonne"), ("inertia", inertia, "tonne·mm²")] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(FemError::InvalidParameter {
                    field: format!("point mass on `{set}`: {field}"),
                    value,
                    unit,
                    range: "finite and >= 0",
                });
            }
        }
        let nodes = self.set(set)?.to_vec();
        self.point_masses
            .extend(nodes.into_iter().map(|i| (i, mass, inertia)));
        Ok(())
    }

    /// Set the initial velocity (mm/s) of every node of `set` (before the first step).
    pub fn set_initial_velocity(&mut self, set: &str, v: Vec3) -> Result<(), FemError> {
        self.require_not_initialized("set_initial_velocity")?;
        let nodes = self.set(set)?.to_vec();
        for i in nodes {
            self.state.v[i as usize] = v;
        }
        Ok(())
    }

    /// Add a boundary condition (before the first step).
    pub fn add_boundary_condition(&mut self, bc: &BoundaryCondition) -> Result<(), FemError> {
        self.require_not_initialized("add_boundary_condition")?;
        match bc {
            BoundaryCondition::Fixed { set, dofs } => self.fix(set, *dofs),
            BoundaryCondition::Symmetry { set, axis } => self.symmetry(set, *axis),
            BoundaryCondition::Prescribed {
                set,
                dof,
                kind,
                value,
                amplitude,
            } => self.prescribe(set, *dof, *kind, *value, amplitude.clone()),
        }
    }

    /// Fix `dofs` (zero velocity) of every node of `set`.
    pub fn fix(&mut self, set: &str, dofs: Dofs) -> Result<(), FemError> {
        self.require_not_initialized("fix")?;
        let nodes = self.set(set)?.to_vec();
        for node in nodes {
            for dof in Dof::ALL.into_iter().filter(|d| dofs.contains(*d)) {
                self.add_constraint(node, dof, ConstraintKind::Fixed)?;
            }
        }
        Ok(())
    }

    /// A symmetry plane through the nodes of `set` with normal along global
    /// `axis` (0 = x, 1 = y, 2 = z): fixes the normal translation and the two
    /// in-plane rotations (plane `x = const`: `ux`, `ry`, `rz`).
    pub fn symmetry(&mut self, set: &str, axis: usize) -> Result<(), FemError> {
        if axis > 2 {
            return Err(FemError::InvalidParameter {
                field: format!("symmetry plane on `{set}`: axis"),
                value: axis as f64,
                unit: "-",
                range: "0 (x), 1 (y) or 2 (z)",
            });
        }
        self.fix(set, Dofs::symmetry(axis))
    }

    /// Prescribe the motion of `dof` of every node of `set`: velocity or
    /// displacement `value · A(t)`.
    pub fn prescribe(
        &mut self,
        set: &str,
        dof: Dof,
        kind: MotionKind,
        value: f64,
        amplitude: Amplitude,
    ) -> Result<(), FemError> {
        self.require_not_initialized("prescribe")?;
        if !value.is_finite() {
            return Err(FemError::InvalidParameter {
                field: format!("prescribed {} on `{set}`", dof.name()),
                value,
                unit: if dof.is_rotation() {
                    "rad or rad/s"
                } else {
                    "mm or mm/s"
                },
                range: "finite",
            });
        }
        let nodes = self.set(set)?.to_vec();
        let amp = self.add_amplitude(amplitude)?;
        for node in nodes {
            self.motions.push(Motion {
                kind,
                value,
                amplitude: amp,
                done: 0.0,
            });
            let m = (self.motions.len() - 1) as u32;
            self.add_constraint(node, dof, ConstraintKind::Prescribed(m))?;
        }
        Ok(())
    }

    /// Add a nodal load (force or moment per node, fixed global direction).
    pub fn add_load(&mut self, load: &NodalLoad) -> Result<(), FemError> {
        self.require_not_initialized("add_load")?;
        if !load.value.is_finite() {
            return Err(FemError::InvalidParameter {
                field: format!("load {} on `{}`", load.dof.name(), load.set),
                value: load.value,
                unit: if load.dof.is_rotation() { "N·mm" } else { "N" },
                range: "finite",
            });
        }
        let nodes = self.set(&load.set)?.to_vec();
        let amp = self.add_amplitude(load.amplitude.clone())?;
        self.loads.extend(nodes.into_iter().map(|node| LoadEntry {
            node,
            dof: load.dof as u8,
            value: load.value,
            amplitude: amp,
        }));
        Ok(())
    }

    fn add_amplitude(&mut self, a: Amplitude) -> Result<u32, FemError> {
        a.validate()?;
        if let Some(k) = self.amplitudes.iter().position(|b| *b == a) {
            return Ok(k as u32);
        }
        self.amplitudes.push(a);
        self.amp_values.push(0.0);
        Ok((self.amplitudes.len() - 1) as u32)
    }

    fn add_constraint(
        &mut self,
        node: u32,
        dof: Dof,
        kind: ConstraintKind,
    ) -> Result<(), FemError> {
        let d = dof as u8;
        let bit = 1u8 << d;
        let fixed = matches!(kind, ConstraintKind::Fixed);
        let (c, f) = (
            &mut self.constrained[node as usize],
            &mut self.fixed[node as usize],
        );
        if *c & bit != 0 {
            return if fixed && *f & bit != 0 {
                Ok(())
            } else {
                Err(FemError::InvalidSetup(format!(
                    "node {node}: DOF {} is constrained twice (fixed/prescribed conflict)",
                    dof.name()
                )))
            };
        }
        *c |= bit;
        if fixed {
            *f |= bit;
        }
        self.constraints.push(Constraint { node, dof: d, kind });
        Ok(())
    }

    fn set(&self, name: &str) -> Result<&[u32], FemError> {
        self.node_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| FemError::UnknownSet {
                kind: "node set",
                name: name.to_string(),
                known: self
                    .node_sets
                    .keys()
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    fn require_not_initialized(&self, what: &str) -> Result<(), FemError> {
        if self.initialized {
            Err(FemError::InvalidSetup(format!(
                "`{what}` must be called before the first step (the solver is already initialized)"
            )))
        } else {
            Ok(())
        }
    }

    // ----- access -----------------------------------------------------------

    /// The nodal state (`x` at [`Solver::time`], `v`/`w` half a step behind).
    pub fn state(&self) -> &NodalState {
        &self.state
    }

    /// Mutable nodal state, e.g. to set initial positions or velocities before the first step.
    pub fn state_mut(&mut self) -> &mut NodalState {
        &mut self.state
    }

    /// Forces and moments at [`Solver::time`] (loads + effects, before constraints).
    pub fn forces(&self) -> &Forces {
        &self.forces
    }

    /// Time of the state (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
    }

    /// The time step the next step will take (s); 0 before initialization.
    pub fn dt_next(&self) -> f64 {
        self.dt_next
    }

    /// The nodal fields shared between effects: only those one effect
    /// writes and another reads are allocated (and computed).
    pub fn shared_fields(&self) -> &SharedFields {
        &self.fields
    }

    /// The latest energy ledger (at `t_n`, one step behind the state).
    pub fn ledger(&self) -> &EnergyLedger {
        &self.ledger
    }

    /// Sum of the reactions at the constrained DOFs of the nodes of `set`:
    /// (force (N), moment (N·mm)) at the ledger time `t_n` (one step behind
    /// the state). The reaction is the force the constraint applies to the
    /// node, `m Δv/Δt̄ − f` per DOF; free DOFs contribute nothing.
    pub fn reaction(&self, set: &str) -> Result<(Vec3, Vec3), FemError> {
        let nodes = self.set(set)?;
        let (mut f, mut m) = (Vec3::zeros(), Vec3::zeros());
        for &node in nodes {
            let k0 = self.constraints.partition_point(|c| c.node < node);
            for (c, r) in self.constraints[k0..].iter().zip(&self.reactions[k0..]) {
                if c.node != node {
                    break;
                }
                if c.dof < 3 {
                    f[c.dof as usize] += r;
                } else {
                    m[(c.dof - 3) as usize] += r;
                }
            }
        }
        Ok((f, m))
    }

    /// The shared nodal field `field` (one value per node) as its writer left
    /// it in the last force computation; `None` when no effect both writes
    /// and reads it (then it is not computed).
    pub fn field(&self, field: NodalField) -> Option<&[f64]> {
        self.fields.get(field)
    }

    /// The shared vector field `field`, as [`Solver::field`].
    pub fn field_vec3(&self, field: NodalField) -> Option<&[Vec3]> {
        self.fields.get_vec3(field)
    }

    /// The order in which the effects compute their forces (indices in order
    /// of addition, see [`Solver::effect_name`]); fixed at set-up.
    pub fn effect_order(&self) -> &[usize] {
        &self.order
    }

    /// Wall-clock seconds spent in the steps so far, by stage and by effect.
    pub fn timing(&self) -> &StepTiming {
        &self.timing
    }

    /// Set-up report (`None` before initialization).
    pub fn setup_report(&self) -> Option<&SetupReport> {
        self.setup.as_ref()
    }

    /// Mass added by mass scaling so far (tonne), and in % of the physical mass.
    pub fn added_mass(&self) -> (f64, f64) {
        (
            self.added_mass,
            100.0 * self.added_mass / self.physical_mass.max(f64::MIN_POSITIVE),
        )
    }

    /// The settings.
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    // ----- set-up -----------------------------------------------------------

    /// Masses, mass scaling, forces at `t = 0` and the first time step.
    /// Called by the first [`Solver::step`] if not called before; calling it
    /// again does nothing.
    pub fn initialize(&mut self) -> Result<SetupReport, FemError> {
        if let Some(s) = self.setup {
            return Ok(s);
        }
        let _span = tracing::debug_span!("set-up", nodes = self.state.len()).entered();
        self.initialized = true;
        self.share_fields()?;
        self.constraints.sort_by_key(|c| (c.node, c.dof));
        self.reactions = vec![0.0; self.constraints.len()];
        self.lump_masses()?;
        self.physical_mass = self.state.mass.iter().sum();
        self.start_selective();
        if let Some(target) = self.settings.mass_scaling_dt {
            self.added_mass += self.scale_mass(target);
        }
        let added_setup = self.added_mass;
        let massless_nodes = self.state.mass.iter().filter(|&&m| m == 0.0).count();
        self.initial_constrained_velocities();
        self.compute_forces(0.0, 0.0, 0)?;
        let (dt, limit) = self.first_dt()?;
        self.solve_selective();
        self.half_step_back(dt);
        let report = SetupReport {
            physical_mass: self.physical_mass,
            added_mass: added_setup,
            added_mass_percent: 100.0 * added_setup / self.physical_mass.max(f64::MIN_POSITIVE),
            dt_initial: dt,
            limit,
            massless_nodes,
        };
        tracing::debug!(
            physical_mass_tonne = report.physical_mass,
            added_mass_percent = report.added_mass_percent,
            dt_initial = report.dt_initial,
            massless_nodes = report.massless_nodes,
            "set-up"
        );
        // The forces at t = 0 are set-up, not a step.
        self.timing.reset();
        self.setup = Some(report);
        Ok(report)
    }

    /// Lumped masses and inertias: the effects' (given the state with its
    /// masses zeroed), then the point masses; each checked finite and `>= 0`.
    fn lump_masses(&mut self) -> Result<(), FemError> {
        self.state.mass.iter_mut().for_each(|m| *m = 0.0);
        self.state.inertia.iter_mut().for_each(|m| *m = 0.0);
        {
            let (state, mass, inertia) = (
                &self.state,
                &mut self.scratch_mass,
                &mut self.scratch_inertia,
            );
            mass.iter_mut().for_each(|m| *m = 0.0);
            inertia.iter_mut().for_each(|m| *m = 0.0);
            for e in &self.effects {
                e.add_lumped_mass(state, mass, inertia);
            }
        }
        std::mem::swap(&mut self.state.mass, &mut self.scratch_mass);
        std::mem::swap(&mut self.state.inertia, &mut self.scratch_inertia);
        for &(i, m, j) in &self.point_masses {
            self.state.mass[i as usize] += m;
            self.state.inertia[i as usize] += j;
        }
        for (i, (&m, &j)) in self.state.mass.iter().zip(&self.state.inertia).enumerate() {
            if !(m.is_finite() && m >= 0.0) {
                return Err(mass_error(i, "mass (tonne)", m));
            }
            if !(j.is_finite() && j >= 0.0) {
                return Err(mass_error(i, "rotational inertia (tonne·mm²)", j));
            }
        }
        Ok(())
    }

    /// The constrained DOFs' velocities at `t = 0` (amplitudes evaluated at 0).
    fn initial_constrained_velocities(&mut self) {
        self.eval_amplitudes(0.0);
        for c in &self.constraints {
            let v = match c.kind {
                ConstraintKind::Fixed => 0.0,
                ConstraintKind::Prescribed(k) => {
                    let m = &self.motions[k as usize];
                    let a = &self.amplitudes[m.amplitude as usize];
                    match m.kind {
                        MotionKind::Velocity => m.value * a.value(0.0),
                        MotionKind::Displacement => m.value * a.rate(0.0),
                    }
                }
            };
            set_dof(&mut self.state.v, &mut self.state.w, c.node, c.dof, v);
        }
    }

    /// The first step from the forces at `t = 0`, with its floor and limit;
    /// a collapse error for a step not finite and `> 0`.
    fn first_dt(&mut self) -> Result<(f64, Option<DtLimit>), FemError> {
        let (dt, limit) = self.next_dt()?;
        if !(dt.is_finite() && dt > 0.0) {
            self.dt_floor = 0.0;
            return Err(self.collapse(dt, limit));
        }
        self.dt_next = dt;
        self.dt_floor = self.settings.dt_floor_ratio * dt;
        self.dt_prev = dt;
        self.limit = limit;
        Ok((dt, limit))
    }

    /// The velocities half the first step `dt` back, `v_{-1/2}`, from the forces at `t = 0`.
    fn half_step_back(&mut self, dt: f64) {
        let n = self.state.len();
        let g = self
            .selective
            .as_ref()
            .filter(|s| s.is_active())
            .map(|s| &s.g);
        let f = |i: usize| g.map_or(self.forces.f[i], |g| self.forces.f[i] - g[i].t);
        let mt = |i: usize| g.map_or(self.forces.m[i], |g| self.forces.m[i] - g[i].r);
        // Virtual v_{-1/2} = v_0 − Δt_{1/2}/2 · a_0 for the free DOFs, so that
        // every step, the first included, uses Δt̄ = (Δt_{n-1/2} + Δt_{n+1/2})/2.
        for i in 0..n {
            let (m, j) = (self.state.mass[i], self.state.inertia[i]);
            if m > 0.0 {
                self.state.v[i] -= f(i) * (0.5 * dt / m);
            }
            if j > 0.0 {
                self.state.w[i] -= mt(i) * (0.5 * dt / j);
            }
        }
        // Constrained DOFs keep their prescribed initial velocity.
        for c in &self.constraints {
            let i = c.node as usize;
            let (m, j) = (self.state.mass[i], self.state.inertia[i]);
            let axis = (c.dof % 3) as usize;
            if c.dof < 3 && m > 0.0 {
                self.state.v[i][axis] += f(i)[axis] * (0.5 * dt / m);
            } else if c.dof >= 3 && j > 0.0 {
                self.state.w[i][axis] += mt(i)[axis] * (0.5 * dt / j);
            }
        }
    }

    /// With selective mass scaling: its solver part, with the constrained
    /// translations held at zero acceleration (set-up only).
    fn start_selective(&mut self) {
        let MassScaling::Selective { tolerance } = self.settings.mass_scaling else {
            return;
        };
        let mut s = SelectiveMass::new(self.state.len(), tolerance, SELECTIVE_MAX_ITERATIONS);
        for c in &self.constraints {
            s.hold(c.node as usize, c.dof);
        }
        self.selective = Some(s);
    }

    /// With selective mass scaling: solve `(M + ΔM) a = f` at `t_n` and
    /// leave `ΔM a` in the selective part's `g`.
    fn solve_selective(&mut self) {
        if let Some(s) = self.selective.as_mut().filter(|s| s.is_active()) {
            let st = &self.state;
            s.solve(
                &st.x,
                (&st.mass, &st.inertia),
                (&self.forces.f, &self.forces.m),
            );
        }
    }

    /// The selective part when it has blocks (`None` otherwise).
    fn active_selective(&self) -> Option<&SelectiveMass> {
        self.selective.as_ref().filter(|s| s.is_active())
    }

    /// Stage 1 with selective mass scaling: the mass solve, and its inertia
    /// force `ΔM a` taken off the forces and moments (timed).
    fn subtract_added_inertia(&mut self) {
        if self.active_selective().is_none() {
            return;
        }
        let mark = Instant::now();
        self.solve_selective();
        if let Some(s) = &self.selective {
            let fm = self.forces.f.iter_mut().zip(self.forces.m.iter_mut());
            for ((f, m), g) in fm.zip(&s.g) {
                *f -= g.t;
                *m -= g.r;
            }
        }
        self.timing.selective_mass += mark.elapsed().as_secs_f64();
    }

    /// What selective mass scaling did so far (`None` when the run does not
    /// scale selectively).
    pub fn selective_stats(&self) -> Option<SelectiveStats> {
        self.selective.as_ref().map(|s| s.stats)
    }

    /// Order the effects so that each shared field's writer runs before its
    /// readers, and allocate the fields (set-up only).
    fn share_fields(&mut self) -> Result<(), FemError> {
        let declared: Vec<Declared<'_>> = self
            .effects
            .iter()
            .map(|e| Declared {
                name: e.name(),
                writes: e.writes(),
                reads: e.reads(),
            })
            .collect();
        let order = effect_order(&declared)?;
        let fields = SharedFields::new(self.state.len(), &declared)?;
        self.order = order;
        self.fields = fields;
        Ok(())
    }

    /// Ask every effect to add mass so that its stable dt is `>= target / safety`,
    /// then every node so that the effects on it together allow it
    /// ([`crate::nodal_limit`]); returns the added mass.
    fn scale_mass(&mut self, target: f64) -> f64 {
        let goal = target / self.settings.safety_factor;
        self.scratch_mass.copy_from_slice(&self.state.mass);
        self.scratch_inertia.copy_from_slice(&self.state.inertia);
        let mut added = 0.0;
        let mut blocks = self.selective.as_mut().map(|s| s.blocks_mut());
        for e in &mut self.effects {
            let selective = blocks
                .as_deref_mut()
                .is_some_and(|b| e.selective_mass(&self.state, goal, b));
            if !selective {
                added += e.scale_mass(
                    &self.state,
                    goal,
                    &mut self.scratch_mass,
                    &mut self.scratch_inertia,
                );
            }
        }
        if let Some(s) = &mut self.selective {
            s.blocks_changed();
        }
        added += self
            .nodal
            .scale_mass(&self.effects, &self.state, goal, &mut self.scratch_mass);
        std::mem::swap(&mut self.state.mass, &mut self.scratch_mass);
        std::mem::swap(&mut self.state.inertia, &mut self.scratch_inertia);
        added
    }

    fn eval_amplitudes(&mut self, t: f64) {
        for (v, a) in self.amp_values.iter_mut().zip(&self.amplitudes) {
            *v = a.value(t);
        }
    }

    /// The press stage: move the tools to `time` (`dt > 0`), reading what the
    /// effects did to them in the last step.
    fn move_press(&mut self, time: f64, dt: f64) -> Result<(), FemError> {
        if let Some(press) = &mut self.press
            && dt > 0.0
        {
            let started = Instant::now();
            press.advance(time, dt, &self.tool_loads)?;
            self.timing.press += started.elapsed().as_secs_f64();
        }
        Ok(())
    }

    /// Start or end the dynamic relaxation of a springback step as the press
    /// enters or leaves one; during one, keep the forces at `t_n`.
    fn follow_release(&mut self) -> Result<(), FemError> {
        let releasing = self.press.as_ref().is_some_and(Press::releasing);
        match (releasing, self.relaxation.is_some()) {
            (true, false) => self.start_release()?,
            (false, true) => {
                self.springback = self.relaxation.take().map(|r| r.report);
            }
            _ => {}
        }
        if let Some(r) = &mut self.relaxation {
            r.keep_forces(&self.forces.f, &self.forces.m);
        }
        Ok(())
    }

    /// The tools let go: fix the DOFs that remove the free rigid-body modes
    /// (their velocities to zero) and start the relaxation.
    fn start_release(&mut self) -> Result<(), FemError> {
        let Some(StepEnd::Settled {
            tolerance, method, ..
        }) = self.press.as_ref().map(|p| p.steps()[p.current_step()].end)
        else {
            return Ok(());
        };
        let springback = |e: FemError| FemError::InvalidSetup(format!("springback: {e}"));
        let free =
            crate::rigid_modes::free_modes(&self.state.x, &self.constrained).map_err(springback)?;
        let fixed = crate::rigid_modes::three_two_one(&self.state.x, &self.constrained, None)
            .map_err(springback)?;
        for &(node, dof) in &fixed {
            self.add_constraint(node, dof, ConstraintKind::Fixed)?;
            let (i, a) = (node as usize, dof.axis());
            if dof.is_rotation() {
                self.state.w[i][a] = 0.0;
            } else {
                self.state.v[i][a] = 0.0;
            }
        }
        // Sort the constraints with their reactions (the new ones at 0).
        let reactions = self.reactions.iter().copied().chain(std::iter::repeat(0.0));
        let mut paired: Vec<(Constraint, f64)> =
            self.constraints.iter().copied().zip(reactions).collect();
        paired.sort_by_key(|(c, _)| (c.node, c.dof));
        (self.constraints, self.reactions) = paired.into_iter().unzip();
        if let Some(s) = &mut self.selective {
            for c in &self.constraints {
                s.hold(c.node as usize, c.dof);
            }
        }
        self.relaxation = Some(Relaxation::new(
            tolerance,
            self.time,
            &self.state.x,
            (free, fixed),
        ));
        if let Some(r) = &mut self.relaxation {
            r.implicit_pending = method == crate::ReleaseMethod::Implicit;
        }
        Ok(())
    }

    /// After the forces of a springback step: the damping of the next step,
    /// and the press told when the blank is at rest.
    fn relax(&mut self, dt: f64) {
        let Some(r) = &mut self.relaxation else {
            return;
        };
        let st = &self.state;
        let settled = r.update(
            (&st.v, &st.w),
            (&st.mass, &st.inertia),
            (&self.forces.f, &self.forces.m),
            &self.constrained,
            dt,
        );
        if settled && let Some(p) = &mut self.press {
            p.mark_settled();
        }
    }

    /// What the last springback step did (its report is complete once the
    /// press has left it), or the running one's so far.
    pub fn springback(&self) -> Option<&SpringbackReport> {
        self.relaxation
            .as_ref()
            .map(|r| &r.report)
            .or(self.springback.as_ref())
    }

    /// What the effects did to the press's tools in this step, summed.
    fn gather_tool_loads(&mut self) {
        self.tool_loads
            .iter_mut()
            .for_each(|l| *l = ToolLoad::default());
        for e in &self.effects {
            for (sum, l) in self.tool_loads.iter_mut().zip(e.tool_loads()) {
                sum.force += l.force;
                sum.stiffness += l.stiffness;
            }
        }
    }

    /// Zero the accumulators, add the loads at `time` and every effect's forces.
    fn compute_forces(&mut self, time: f64, dt: f64, step: u64) -> Result<(), FemError> {
        let started = Instant::now();
        node_chunks::zero_forces(&mut self.forces);
        self.eval_amplitudes(time);
        for l in &self.loads {
            let p = l.value * self.amp_values[l.amplitude as usize];
            let axis = (l.dof % 3) as usize;
            if l.dof < 3 {
                self.forces.f[l.node as usize][axis] += p;
            } else {
                self.forces.m[l.node as usize][axis] += p;
            }
        }
        let ctx = StepContext {
            time,
            dt,
            step,
            press: self.press.as_ref(),
        };
        let mut tally = EnergyTally::default();
        let mut mark = Instant::now();
        self.timing.assembly += (mark - started).as_secs_f64();
        for &k in &self.order {
            let e = &mut self.effects[k];
            let mut fields = self.fields.access(k);
            e.add_forces(&ctx, &self.state, &mut self.forces, &mut fields)?;
            let now = Instant::now();
            self.timing.effects[k] += (now - mark).as_secs_f64();
            mark = now;
            tally.add(&e.energies());
        }
        self.tally = tally;
        self.gather_tool_loads();
        if !node_chunks::forces_finite(&self.forces) {
            let bad = |v: &Vec3| !(v.x.is_finite() && v.y.is_finite() && v.z.is_finite());
            if let Some(i) = self.forces.f.iter().position(bad) {
                return Err(FemError::NonFiniteState {
                    node: i,
                    field: "force (N)",
                    time,
                    step,
                });
            }
            if let Some(i) = self.forces.m.iter().position(bad) {
                return Err(FemError::NonFiniteState {
                    node: i,
                    field: "moment (N·mm)",
                    time,
                    step,
                });
            }
        }
        self.timing.assembly += mark.elapsed().as_secs_f64();
        Ok(())
    }

    /// The smallest stable dt over the effects and over the nodes they
    /// share (see [`crate::nodal_limit`]).
    fn stable_dt(&mut self) -> Option<DtLimit> {
        let mut best: Option<DtLimit> = None;
        for (k, e) in self.effects.iter().enumerate() {
            if let Some(s) = e.stable_dt(&self.state) {
                // NaN compares false: a NaN dt replaces anything so that it is reported.
                if best.is_none_or(|b| s.dt.is_nan() || s.dt < b.stable.dt) {
                    best = Some(DtLimit {
                        effect: k,
                        stable: s,
                        combined: false,
                    });
                }
            }
        }
        if let Some(b) = best
            && !b.stable.dt.is_nan()
            && let Some(c) = self.nodal.stable_dt(&self.effects, &self.state)
            && (c.dt.is_nan() || c.dt < b.stable.dt)
        {
            best = Some(DtLimit {
                effect: b.effect,
                stable: c,
                combined: true,
            });
        }
        best
    }

    /// Who limits the step: the effect's name (for a combined limit, the
    /// effects on the node with their stiffness, `name s N/mm + …`), the
    /// element (or node) and the cause; `dt_max` when the setting does.
    fn limit_source(&mut self, limit: Option<DtLimit>) -> (String, usize, &'static str) {
        match limit {
            Some(l) if l.combined => {
                let who = self
                    .nodal
                    .contributors(&self.effects, &self.state, l.stable.element);
                (who, l.stable.element, l.stable.what)
            }
            Some(l) => (
                self.effect_name(l.effect).to_string(),
                l.stable.element,
                l.stable.what,
            ),
            None => ("dt_max".to_string(), 0, "settings"),
        }
    }

    /// Where `limit` sits, in words: `element E of `effect` (what)`, or
    /// `node N (effect s N/mm + … together)` for a combined limit.
    fn describe_limit(&mut self, limit: DtLimit) -> String {
        let (who, element, what) = self.limit_source(Some(limit));
        if limit.combined {
            format!("node {element} ({who}, together)")
        } else {
            format!("element {element} of `{who}` ({what})")
        }
    }

    /// The collapse error for a step `dt` below the floor, with its limit.
    fn collapse(&mut self, dt: f64, limit: Option<DtLimit>) -> FemError {
        let (effect, element, what) = self.limit_source(limit);
        FemError::TimeStepCollapse {
            time: self.time,
            step: self.step,
            dt,
            floor: self.dt_floor,
            effect,
            element,
            what,
        }
    }

    /// Next time step (safety, dt_max, mass scaling), before the collapse check.
    fn next_dt(&mut self) -> Result<(f64, Option<DtLimit>), FemError> {
        if let Some(fixed) = self.settings.fixed_dt {
            let limit = self.stable_dt();
            if let Some(l) = limit
                && (l.stable.dt.is_nan() || l.stable.dt < fixed)
            {
                return Err(FemError::StepAboveStableLimit {
                    time: self.time,
                    step: self.step,
                    dt: fixed,
                    stable: l.stable.dt,
                    location: self.describe_limit(l),
                });
            }
            return Ok((fixed, limit));
        }
        let sf = self.settings.safety_factor;
        let mut limit = self.stable_dt();
        let mut dt = limit.map_or(f64::INFINITY, |l| sf * l.stable.dt);
        if dt.is_nan() {
            return Ok((dt, limit));
        }
        if let Some(target) = self.settings.mass_scaling_dt
            && dt < target * (1.0 - 1e-9)
            && self.initialized
            && self.setup.is_some()
        {
            // Scale to a little above the target, so that elements shrinking
            // slowly during forming do not trigger a full pass every step.
            let added = self.scale_mass(target * (1.0 + MASS_SCALING_HEADROOM));
            self.added_mass += added;
            tracing::debug!(
                time = self.time,
                step = self.step,
                added_tonne = added,
                added_total_tonne = self.added_mass,
                "mass scaling during the run"
            );
            // Mass added to moving nodes changes the kinetic energy by
            // ½ Δm |v_{n+1/2}|² (exact for the product form): book it as work.
            let st = &self.state;
            let mut e = 0.0;
            for i in 0..st.len() {
                e += 0.5 * (st.mass[i] - self.scratch_mass[i]) * st.v[i].norm_squared();
                e += 0.5 * (st.inertia[i] - self.scratch_inertia[i]) * st.w[i].norm_squared();
            }
            self.work.mass_scaling += e;
            limit = self.stable_dt();
            dt = limit.map_or(f64::INFINITY, |l| sf * l.stable.dt);
        }
        if let Some(target) = self.settings.mass_scaling_dt {
            dt = dt.min(target);
        }
        if let Some(m) = self.settings.dt_max
            && dt > m
        {
            dt = m;
            limit = None;
        }
        if dt == f64::INFINITY {
            return Err(FemError::InvalidSetup(
                "no effect imposes a stable time step: set `dt_max` or `mass_scaling_dt`".into(),
            ));
        }
        Ok((dt, limit))
    }

    /// The step-change halves of the step just updated, `(cur, pending)`.
    ///
    /// The effects book the work of their forces with the trapezoidal rule
    /// over each step, `½ (F_{k-1} + F_k)·v_{k-1/2} Δt_{k-1/2}`; central
    /// difference changes the product-form kinetic energy by the rule the
    /// ledger applies to loads, `½ v_{k-1/2}·(Δt̄_k F_k + Δt̄_{k-1} F_{k-1})`.
    /// The two differ only where the step changes: with
    /// `δ_k = Δt_{k+1/2} − Δt_{k-1/2}`, by `¼ δ_k F_k·v_{k-1/2}` over the
    /// step ending at `t_k` and `−¼ δ_k F_k·v_{k+1/2}` over the next (`F` the
    /// effects' forces and moments, loads excluded). Exact, and zero at a
    /// constant step; large only where the step jumps under large forces
    /// (a node landing on a tool shortens the step it limits).
    fn step_change_sums(&self, delta: f64) -> (f64, f64) {
        let st = &self.state;
        let (mut cur, mut pend) = (0.0, 0.0);
        for i in 0..st.len() {
            let (f, m) = (&self.forces.f[i], &self.forces.m[i]);
            if st.mass[i] > 0.0 {
                cur += f.dot(&self.v_old[i]);
                pend += f.dot(&st.v[i]);
            }
            if st.inertia[i] > 0.0 {
                cur += m.dot(&self.w_old[i]);
                pend += m.dot(&st.w[i]);
            }
        }
        if let Some(s) = self.active_selective() {
            // The force array holds f − ΔM a: the inertia force is booked
            // with the ledger's rule, like the loads, so it is put back.
            for (i, g) in s.g.iter().enumerate() {
                if st.mass[i] > 0.0 {
                    cur += g.t.dot(&self.v_old[i]);
                    pend += g.t.dot(&st.v[i]);
                }
                if st.inertia[i] > 0.0 {
                    cur += g.r.dot(&self.w_old[i]);
                    pend += g.r.dot(&st.w[i]);
                }
            }
        }
        for l in &self.loads {
            let p = l.value * self.amp_values[l.amplitude as usize];
            let (i, axis) = (l.node as usize, (l.dof % 3) as usize);
            let (moving, vo, vn) = if l.dof >= 3 {
                (st.inertia[i] > 0.0, self.w_old[i][axis], st.w[i][axis])
            } else {
                (st.mass[i] > 0.0, self.v_old[i][axis], st.v[i][axis])
            };
            if moving {
                cur -= p * vo;
                pend -= p * vn;
            }
        }
        (0.25 * delta * cur, -0.25 * delta * pend)
    }

    // ----- stepping ---------------------------------------------------------

    /// Advance one step `t_n → t_{n+1}` (initializing first if needed).
    /// Its wall-clock time goes to [`Solver::timing`].
    ///
    /// With more than one rayon thread, a step called from outside rayon's
    /// pool runs on it, handed over once: the parallel parts inside (the
    /// elements, the contact pairs, the nodes) then split their work among
    /// the pool's threads without each handing it over and waiting on its
    /// own. A caller stepping many times saves even that by calling from
    /// inside the pool (`ThreadPool::install`, as the batch executors run
    /// each job). On one thread nothing is handed over.
    pub fn step(&mut self) -> Result<StepReport, FemError> {
        self.initialize()?;
        let started = Instant::now();
        let report = if rayon::current_num_threads() > 1 && rayon::current_thread_index().is_none()
        {
            let (report, done) = rayon::scope(|_| (self.advance(started), Instant::now()));
            // The hand-back from the pool (the hand-over in is in stage 1).
            self.timing.handover += done.elapsed().as_secs_f64();
            report
        } else {
            self.advance(started)
        };
        self.timing.total += started.elapsed().as_secs_f64();
        report
    }

    /// The step of [`Solver::step`] once initialized; `started` is when it began.
    fn advance(&mut self, started: Instant) -> Result<StepReport, FemError> {
        let first = self.step == 0;
        let k = self.step_constants();
        let dt = k.dt;

        // 1. Integrate: velocities, constraints and positions, one pass (with
        // selective mass scaling, on the force f − ΔM a).
        self.subtract_added_inertia();
        let sums = self.update_nodes(k);
        // 2. Ledger: the energies at t_n.
        let ledger = self.book_energy(first, k, sums);
        self.time = k.t_next;
        self.land_at = None;
        self.step += 1;
        self.dt_prev = dt;
        self.timing.integration += started.elapsed().as_secs_f64();

        // 3. Press: the tools at t_{n+1} (a springback step lets go of the
        // blank and relaxes it).
        self.move_press(self.time, dt)?;
        self.follow_release()?;
        // 4.–5. Forces at t_{n+1}: loads, then each effect, writers of a
        // shared field before its readers (the blank's shells, then contact).
        self.compute_forces(self.time, dt, self.step)?;
        if self.relaxation.as_ref().is_some_and(|r| r.implicit_pending) {
            // An implicit springback: the release solved statically from
            // this state, then the forces where it put the blank.
            let (report, released) = self.release_implicitly(dt)?;
            if let Some(r) = &mut self.relaxation {
                r.preset(released, report);
            }
            self.compute_forces(self.time, dt, self.step)?;
        }
        self.relax(dt);
        // 6. Time step: the next stable step, with mass scaling.
        let mark = Instant::now();
        let (dt_next, limit) = self.next_dt()?;
        self.timing.time_step += mark.elapsed().as_secs_f64();
        self.limit = limit;
        if !dt_next.is_finite() || dt_next < self.dt_floor {
            return Err(self.collapse(dt_next, limit));
        }
        self.dt_next = dt_next;
        Ok(StepReport {
            step: self.step,
            time: self.time,
            dt,
            dt_next,
            limit,
            added_mass: self.added_mass,
            energy: ledger,
        })
    }

    /// The constants of the step `t_n → t_{n+1}` about to be taken.
    #[inline(always)]
    fn step_constants(&self) -> StepConstants {
        let dt = self.dt_next;
        let t_n = self.time;
        let hb = 0.5 * (self.dt_prev + dt);
        let c = self
            .relaxation
            .as_ref()
            .map_or(self.settings.damping, |r| r.c);
        let (d1, d2) = (1.0 - 0.5 * c * hb, 1.0 / (1.0 + 0.5 * c * hb));
        StepConstants {
            dt,
            t_n,
            hb,
            c,
            d1,
            d2,
            t_half: t_n + 0.5 * dt,
            t_next: self.land_at.unwrap_or(t_n + dt),
        }
    }

    /// Step 1.: the free update of every DOF and the positions of the
    /// unconstrained nodes in one pass over the nodes (in fixed chunks, in
    /// parallel on large models: `node_chunks`), then the constrained nodes
    /// (constraints sorted by node) overwrite their DOFs and move; returns
    /// the step's energy sums (the same bits on any number of threads).
    #[inline(always)]
    fn update_nodes(&mut self, k: StepConstants) -> Sums {
        // The constrained nodes' corrections go to `sums` on the cold path.
        let mut sums = Sums::default();
        let Self {
            state: st,
            forces,
            v_old,
            w_old,
            chunk_sums,
            constraints,
            reactions,
            constrained,
            motions,
            amplitudes,
            ..
        } = self;
        let free =
            node_chunks::free_update(st, forces, (v_old, w_old), constrained, chunk_sums, &k);
        let mut kc = 0;
        while let Some(con) = constraints.get(kc) {
            let i = con.node as usize;
            let node = Node {
                m: st.mass[i],
                j: st.inertia[i],
                vo: v_old[i],
                wo: w_old[i],
                f: forces.f[i],
                mt: forces.m[i],
            };
            let times = (k.t_half, k.t_next, k.dt, k.c, k.hb);
            kc = apply_constraints(
                i,
                kc,
                &node,
                &mut st.v[i],
                &mut st.w[i],
                constraints,
                reactions,
                motions,
                amplitudes,
                times,
                &mut sums,
            );
            let v = st.v[i];
            let x = &mut st.x[i];
            x.x += v.x * k.dt;
            x.y += v.y * k.dt;
            x.z += v.z * k.dt;
        }
        free.add_to(&mut sums, k.c, k.hb);
        sums
    }

    /// Step 3.: the load work, the step-change term and the running work
    /// sums over the step, and the energy ledger at `t_n` (kept and returned).
    #[inline]
    fn book_energy(&mut self, first: bool, k: StepConstants, sums: Sums) -> EnergyLedger {
        let (loads_cur, loads_pend) = self.load_work_halves(k.hb);
        let (inertia_cur, inertia_pend) = self.added_inertia_halves(k.hb);
        let (sc_cur, sc_pend) = if k.dt != self.dt_prev {
            self.step_change_sums(k.dt - self.dt_prev)
        } else {
            (0.0, 0.0)
        };
        let w = &mut self.work;
        if first {
            *w = WorkSums::default();
        } else {
            // (mass_scaling is booked directly when mass is added.)
            w.loads += w.loads_pending + loads_cur;
            w.prescribed += w.prescribed_pending + sums.presc_cur;
            w.damping_work += w.damping_pending + sums.damp_cur;
            w.step_change -= w.step_change_pending + sc_cur;
            w.added_inertia += w.added_inertia_pending + inertia_cur;
        }
        w.added_inertia_pending = inertia_pend;
        w.step_change_pending = sc_pend;
        w.loads_pending = loads_pend;
        w.prescribed_pending = sums.presc_pend;
        w.damping_pending = sums.damp_pend;
        let (ke_prod, ke_mid) = (sums.ke_prod, sums.ke_mid);
        let mut ledger = EnergyLedger {
            time: k.t_n,
            kinetic: ke_mid[0] + ke_mid[1],
            kinetic_rotational: ke_mid[1],
            kinetic_added: w.added_inertia,
            integration: (ke_prod[0] + ke_prod[1]) - (ke_mid[0] + ke_mid[1]) + w.step_change,
            internal: self.tally.internal,
            hourglass: self.tally.hourglass,
            plastic: self.tally.plastic,
            contact: self.tally.contact,
            friction: self.tally.friction,
            bead: self.tally.bead,
            damping: -w.damping_work,
            external_loads: w.loads,
            external_prescribed: w.prescribed,
            external_mass_scaling: w.mass_scaling,
            external_tools: self.tally.external,
            ..Default::default()
        };
        if first {
            self.total0 = ledger.total();
        }
        ledger.close(self.total0);
        if let Some(before) = &self.carried {
            ledger.carry(before);
        }
        self.ledger = ledger;
        ledger
    }

    /// The work halves of the selective mass's inertia force `ΔM a` over
    /// the step, by the loads' rule (zero without selective scaling).
    #[inline]
    fn added_inertia_halves(&self, hb: f64) -> (f64, f64) {
        let Some(s) = self.active_selective() else {
            return (0.0, 0.0);
        };
        let (mut cur, mut pend) = (0.0, 0.0);
        let st = &self.state;
        for (i, g) in s.g.iter().enumerate() {
            cur += g.t.dot(&self.v_old[i]) + g.r.dot(&self.w_old[i]);
            pend += g.t.dot(&st.v[i]) + g.r.dot(&st.w[i]);
        }
        (0.5 * hb * cur, 0.5 * hb * pend)
    }

    /// The loads' work halves over the step, `½ Δt̄ p·v` at `v_{n-1/2}` and
    /// at `v_{n+1/2}` (`hb` = `Δt̄`).
    #[inline]
    fn load_work_halves(&self, hb: f64) -> (f64, f64) {
        let mut loads_cur = 0.0;
        let mut loads_pend = 0.0;
        for l in &self.loads {
            let p = l.value * self.amp_values[l.amplitude as usize];
            let (i, axis) = (l.node as usize, (l.dof % 3) as usize);
            let (vo, vn) = if l.dof >= 3 {
                (self.w_old[i][axis], self.state.w[i][axis])
            } else {
                (self.v_old[i][axis], self.state.v[i][axis])
            };
            loads_cur += 0.5 * hb * p * vo;
            loads_pend += 0.5 * hb * p * vn;
        }
        (loads_cur, loads_pend)
    }

    /// One step towards `t_end`, as [`Solver::run_until`] takes it: over the
    /// last (at most) 32 steps before `t_end` the steps are shortened evenly
    /// to land on it exactly. A caller stepping with this until
    /// `time() >= t_end` takes the very steps `run_until(t_end, …)` takes.
    ///
    /// # Errors
    /// `t_end` not finite or not after the current time; the step's errors.
    pub fn step_toward(&mut self, t_end: f64) -> Result<StepReport, FemError> {
        self.initialize()?;
        if !(t_end.is_finite() && t_end > self.time) {
            return Err(FemError::InvalidParameter {
                field: "t_end".into(),
                value: t_end,
                unit: "s",
                range: "finite and after the current time",
            });
        }
        self.land_on(t_end);
        self.step()
    }

    /// Land on `t_end`: over the last (at most) 32 steps, use equal steps
    /// remaining / N, so that Δt changes by at most ~3 % once (a sudden
    /// change of Δt disturbs the energy balance; see `energy`).
    fn land_on(&mut self, t_end: f64) {
        let remaining = t_end - self.time;
        if self.dt_next * 32.0 >= remaining {
            let steps = (remaining / self.dt_next * (1.0 - 1e-12)).ceil().max(1.0);
            self.dt_next = remaining / steps;
            if steps == 1.0 {
                self.land_at = Some(t_end);
            }
        }
    }

    /// Step until `t_end` (the last steps are shortened evenly to land on it
    /// exactly, see [`Solver::step_toward`]; prefer one call with output in
    /// the callback over many short calls),
    /// calling `callback` after every step; stops early when it returns
    /// [`Control::Stop`]. On error the solver keeps the state computed so far.
    pub fn run_until<F>(&mut self, t_end: f64, callback: &mut F) -> Result<RunSummary, FemError>
    where
        F: FnMut(&Solver, &StepReport) -> Control,
    {
        if !t_end.is_finite() {
            return Err(FemError::InvalidParameter {
                field: "t_end".into(),
                value: t_end,
                unit: "s",
                range: "finite",
            });
        }
        self.initialize()?;
        let mut summary = RunSummary {
            steps: 0,
            stopped_by_callback: false,
            last: None,
        };
        while self.time < t_end {
            let report = self.step_toward(t_end)?;
            summary.steps += 1;
            summary.last = Some(report);
            if callback(self, &report) == Control::Stop {
                summary.stopped_by_callback = true;
                break;
            }
        }
        Ok(summary)
    }
}

fn mass_error(node: usize, field: &str, value: f64) -> FemError {
    FemError::InvalidParameter {
        field: format!("node {node}: lumped {field}"),
        value,
        unit: "-",
        range: "finite and >= 0",
    }
}

fn set_dof(v: &mut [Vec3], w: &mut [Vec3], node: u32, dof: u8, value: f64) {
    let axis = (dof % 3) as usize;
    if dof < 3 {
        v[node as usize][axis] = value;
    } else {
        w[node as usize][axis] = value;
    }
}

/// One damped central-difference velocity update of a translational or
/// rotational DOF triple, `v_new = (v_old d1 + f g) d2`, with the per-unit-mass
/// sums the ledger needs (`s = v_old + v_new`).
#[derive(Clone, Copy)]
struct VelocityStep {
    /// The new velocity.
    v: Vec3,
    /// `v_old · v_new`.
    product: f64,
    /// `|s|²`.
    sum2: f64,
    /// `s · v_old`.
    sum_old: f64,
    /// `s · v_new`.
    sum_new: f64,
}

#[inline(always)]
fn velocity_step(vo: Vec3, f: &Vec3, g: f64, d1: f64, d2: f64) -> VelocityStep {
    let vn = Vec3::new(
        (vo.x * d1 + f.x * g) * d2,
        (vo.y * d1 + f.y * g) * d2,
        (vo.z * d1 + f.z * g) * d2,
    );
    let s = (vo.x + vn.x, vo.y + vn.y, vo.z + vn.z);
    VelocityStep {
        v: vn,
        product: vo.x * vn.x + vo.y * vn.y + vo.z * vn.z,
        sum2: s.0 * s.0 + s.1 * s.1 + s.2 * s.2,
        sum_old: s.0 * vo.x + s.1 * vo.y + s.2 * vo.z,
        sum_new: s.0 * vn.x + s.1 * vn.y + s.2 * vn.z,
    }
}
