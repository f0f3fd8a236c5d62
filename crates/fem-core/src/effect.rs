//! The `Effect` trait: anything that adds nodal forces (element families, contact, springs), with its masses, time step and energies.

use crate::{
    FemError, FieldAccess, Forces, MassBlocks, NodalField, NodalState, StepContext, ToolLoad,
};
use std::any::Any;

/// The stable time step an effect imposes, and which of its elements limits it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StableDt {
    /// Stable time step without safety factor (s).
    pub dt: f64,
    /// Index of the limiting element within the effect.
    pub element: usize,
    /// What limits it (e.g. `element length / wave speed`, `negative area`).
    pub what: &'static str,
}

/// Cumulative energies an effect accounts for (mJ = N·mm).
///
/// `internal` excludes `hourglass` and includes plastic work; `plastic` is the
/// dissipated part of `internal`, reported separately and never added twice.
/// `contact` is stored (penalty) energy; `friction` is dissipated energy;
/// `bead` is energy dissipated by drawbeads' restraint;
/// `external` is work done on the model by agents the effect owns (rigid
/// tools moved by the press, pushing the blank through contact).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyTally {
    /// Internal (strain) energy, elastic + plastic, hourglass excluded (mJ).
    pub internal: f64,
    /// Hourglass-control energy (mJ).
    pub hourglass: f64,
    /// Plastic dissipation, included in `internal` (mJ).
    pub plastic: f64,
    /// Contact (penalty) energy (mJ).
    pub contact: f64,
    /// Frictional dissipation (mJ).
    pub friction: f64,
    /// Drawbead dissipation (mJ).
    pub bead: f64,
    /// Work done on the model by the effect's external agents (mJ).
    pub external: f64,
}

impl EnergyTally {
    /// Component-wise sum.
    pub fn add(&mut self, o: &EnergyTally) {
        self.internal += o.internal;
        self.hourglass += o.hourglass;
        self.plastic += o.plastic;
        self.contact += o.contact;
        self.friction += o.friction;
        self.bead += o.bead;
        self.external += o.external;
    }
}

/// What an effect is in a static solve (the implicit springback step).
pub enum StaticForm {
    /// It adds nothing once the tools have let go (contact).
    Released,
    /// Its static form, built from its current state; handed back to
    /// [`Effect::absorb_static`] after the solve.
    Tangent(Box<dyn crate::statics::StaticTangent>),
}

/// A contribution to the nodal forces: an element family, a contact pair, a spring set.
///
/// The solver calls, per step and per effect, [`Effect::add_forces`] once and
/// then [`Effect::stable_dt`] once with the same state; an effect may compute
/// its stable time step inside `add_forces` and return the cached value.
/// Effects are called one after the other: in the order they were added,
/// except that an effect writing a shared field ([`Effect::writes`]) runs
/// before the effects reading it ([`Effect::reads`]) — see [`crate::fields`].
/// `Any` lets [`Solver::effect`](crate::Solver::effect) hand an effect back
/// as its concrete type (to read element results after a run).
pub trait Effect: Any + Send {
    /// Name used in reports and errors (e.g. `bt-shell`).
    fn name(&self) -> &str;

    /// Called once before the run: add lumped masses (tonne) and rotational
    /// inertias (tonne·mm²) computed from `state.x0`.
    fn add_lumped_mass(&self, state: &NodalState, mass: &mut [f64], inertia: &mut [f64]) {
        let _ = (state, mass, inertia);
    }

    /// The stable time step of this effect (without safety factor) and which
    /// element limits it, for the configuration in `state` (masses included);
    /// `None` if it imposes none.
    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        let _ = state;
        None
    }

    /// Fixed-time-step mass scaling: add mass/inertia so that every element's
    /// stable time step (without safety factor) is `>= target_dt`; return the
    /// added translational mass (tonne). `mass`/`inertia` hold the current
    /// lumped values (the solver swaps them in afterwards; `state.mass` still
    /// holds the old ones during the call). Called at set-up, after
    /// [`Effect::add_lumped_mass`] and before the first
    /// [`Effect::add_forces`], and during the run (after `add_forces`)
    /// whenever `safety × stable dt` falls below the target.
    fn scale_mass(
        &mut self,
        state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        inertia: &mut [f64],
    ) -> f64 {
        let _ = (state, target_dt, mass, inertia);
        0.0
    }

    /// Selective mass scaling ([`crate::selective_mass`]): raise the added
    /// inertia of the relative motion of this effect's elements so that each
    /// element's stable step (without safety factor) is `>= target_dt`, and
    /// push every element that carries added inertia (all of them, not only
    /// those raised now) into `blocks`, with its lumped share per node.
    /// Called whenever conventional scaling would be, when the run scales
    /// selectively. Returns `false` when the effect cannot scale selectively
    /// (the default): the solver then calls [`Effect::scale_mass`] instead.
    fn selective_mass(
        &mut self,
        state: &NodalState,
        target_dt: f64,
        blocks: &mut MassBlocks,
    ) -> bool {
        let _ = (state, target_dt, blocks);
        false
    }

    /// Whether [`Effect::nodal_stiffness`] adds anything at the moment
    /// (asked at every step, so it must be cheap): the solver combines the
    /// effects' stiffness on shared nodes only when two or more do.
    fn stiffens_nodes(&self) -> bool {
        false
    }

    /// Add, per node, the stiffness `s_i` (N/mm) that bounds this effect's
    /// highest translational frequency at the node for its own stable step:
    /// `2 √(m_i / s_i)` is the step it would allow the node alone (`m_i` the
    /// nodal mass, which `s_i` must not depend on). The solver sums the
    /// effects' `s_i` on every node, so that a node held by shells and a
    /// contact spring together gets the step stable for both (the highest
    /// frequency of a sum of stiffnesses is at most the sum of theirs).
    /// The default adds nothing.
    fn nodal_stiffness(&self, state: &NodalState, stiffness: &mut [f64]) {
        let _ = (state, stiffness);
    }

    /// The shared nodal fields this effect writes in [`Effect::add_forces`]
    /// (asked once, at set-up). One effect at most writes a given field.
    fn writes(&self) -> &[NodalField] {
        &[]
    }

    /// The shared nodal fields this effect reads in [`Effect::add_forces`]
    /// (asked once, at set-up); their writers run before it in every step.
    fn reads(&self) -> &[NodalField] {
        &[]
    }

    /// Add forces/moments for the configuration in `state` (`x` at `t_{n+1}`,
    /// `v`/`w` at `t_{n+1/2}`), as forces acting on the nodes; update internal
    /// state (stresses) and energies. `ctx.press` is the press at `t_{n+1}`. `fields` holds the shared nodal fields:
    /// those this effect reads were written in this same call of the solver
    /// (at `t_{n+1}`) by effects that ran before it; those it writes, it
    /// writes for the configuration in `state`.
    fn add_forces(
        &mut self,
        ctx: &StepContext<'_>,
        state: &NodalState,
        forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError>;

    /// What this effect did to each rigid tool of the press in its last
    /// [`Effect::add_forces`] (index: tool, as in [`crate::Press`]). The
    /// solver sums them over the effects and hands them to the press stage
    /// of the next step, where force-controlled tools read them. The default
    /// touches no tool.
    fn tool_loads(&self) -> &[ToolLoad] {
        &[]
    }

    /// Cumulative energies this effect accounts for, at the configuration of
    /// the last `add_forces` call (mJ).
    fn energies(&self) -> EnergyTally {
        EnergyTally::default()
    }

    /// The effect in a static solve, from its current state (the implicit
    /// springback, when the tools have let go). The default is an error
    /// naming the effect: an effect whose forces matter must give one.
    ///
    /// # Errors
    /// The effect has no static form (one line naming it).
    fn static_form(&self) -> Result<StaticForm, String> {
        Err(format!("{} has no static form", self.name()))
    }

    /// Push this effect's state (what its next [`Effect::add_forces`] reads:
    /// stresses, histories, per-point contact state, …) to `out`, to continue
    /// in another run ([`crate::resume`]). The default saves nothing.
    fn save_state(&self, out: &mut crate::StateArrays) {
        let _ = out;
    }

    /// Take back a state [`Effect::save_state`] gave, before the first step;
    /// push to `notes` one line per part of it this effect drops (e.g. a
    /// contact pair no longer there). The default takes nothing.
    ///
    /// # Errors
    /// The state does not fit this effect (one line naming what differs).
    fn restore_state(
        &mut self,
        saved: &crate::StateArrays,
        notes: &mut Vec<String>,
    ) -> Result<(), String> {
        let _ = (saved, notes);
        Ok(())
    }

    /// Take back the state of a static solve: `solved` is the static form
    /// [`Effect::static_form`] gave, after the solve (its committed state,
    /// the last converged increment), and `x` the nodes' positions there
    /// (mm). The default takes nothing.
    ///
    /// # Errors
    /// `solved` is not this effect's static form.
    fn absorb_static(
        &mut self,
        solved: &dyn crate::statics::StaticTangent,
        x: &[crate::Vec3],
    ) -> Result<(), String> {
        let _ = (solved, x);
        Ok(())
    }
}
