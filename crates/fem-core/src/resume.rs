//! A solver's state at the end of a step, taken out of one run and put into
//! another (forming in stages): [`Solver::save_resume`](crate::Solver::save_resume)
//! and [`Solver::resume`](crate::Solver::resume).
//!
//! What it holds is what the next central-difference step reads: the nodes
//! (positions, half-step velocities, masses with any mass scaling), the
//! forces `f_n`, the last and next time steps, the rigid-body state of every
//! tool of the press and each effect's own state ([`StateArrays`], saved by
//! [`Effect::save_state`](crate::Effect::save_state)) and the time reached,
//! from which the next run's time (and its press programme) goes on. The
//! step count, energies and prescribed displacements count from the start
//! of each run.

use crate::{EnergyLedger, Forces, NodalState, ToolLoad, Vec3};
use plugins_api::{RigidPose, RigidVelocity};

/// An effect's state as named arrays of numbers (integers stored exactly as
/// `f64`, below 2⁵³), in the order the effect pushed them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StateArrays {
    entries: Vec<(String, Vec<f64>)>,
}

impl StateArrays {
    /// Arrays read back in their saved order.
    pub fn from_entries(entries: Vec<(String, Vec<f64>)>) -> Self {
        Self { entries }
    }

    /// Append the array `key`.
    pub fn push(&mut self, key: &str, values: Vec<f64>) {
        self.entries.push((key.to_string(), values));
    }

    /// Every array, in order.
    pub fn entries(&self) -> &[(String, Vec<f64>)] {
        &self.entries
    }

    /// The array `key` (`None` when absent).
    pub fn find(&self, key: &str) -> Option<&[f64]> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_slice())
    }

    /// The array `key`, which must hold `len` numbers.
    ///
    /// # Errors
    /// The array is absent or of another length (one line naming both).
    pub fn get(&self, key: &str, len: usize) -> Result<&[f64], String> {
        let v = self
            .find(key)
            .ok_or_else(|| format!("the saved state has no `{key}`"))?;
        if v.len() != len {
            return Err(format!(
                "`{key}` holds {} values in the saved state, {len} here",
                v.len()
            ));
        }
        Ok(v)
    }
}

/// Vectors flattened to `[x, y, z, x, y, z, …]`.
pub fn flatten(v: &[Vec3]) -> Vec<f64> {
    v.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// The inverse of [`flatten`] into `out` (lengths checked by the caller).
pub fn unflatten(flat: &[f64], out: &mut [Vec3]) {
    for (p, c) in out.iter_mut().zip(flat.chunks_exact(3)) {
        *p = Vec3::new(c[0], c[1], c[2]);
    }
}

/// One rigid tool of the press as a run left it.
#[derive(Debug, Clone, PartialEq)]
pub struct ToolResume {
    /// The tool's name.
    pub name: String,
    /// Its pose at the start of the first run (force control measures its
    /// compression from there).
    pub initial: RigidPose,
    /// Its pose at the end (mm).
    pub pose: RigidPose,
    /// Its mid-step velocity in the last step.
    pub velocity: RigidVelocity,
    /// Mid-step speed of force-controlled travel (mm/s; 0 otherwise).
    pub free_speed: f64,
    /// Force applied to a force-controlled tool in the last step (N).
    pub applied: Option<f64>,
    /// The last reaction along a force-controlled tool's direction (N).
    pub last_reaction: Option<f64>,
    /// What the blank did to the tool in the last step.
    pub load: ToolLoad,
}

/// The state the next step of a run reads, to continue in another run.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverResume {
    /// The nodes: reference and current positions, velocities at the last
    /// half step, masses and inertias (mass scaling included).
    pub nodes: NodalState,
    /// Forces and moments at the end of the last step, `f_n`.
    pub forces: Forces,
    /// The time reached (s): the next run continues from it.
    pub time: f64,
    /// The last time step taken, `Δt_{n-1/2}` (s).
    pub dt_prev: f64,
    /// The time step the next step takes, `Δt_{n+1/2}` (s).
    pub dt_next: f64,
    /// The smallest time step allowed before a collapse is reported (s).
    pub dt_floor: f64,
    /// Mass without mass scaling (tonne).
    pub physical_mass: f64,
    /// Mass added by mass scaling so far (tonne).
    pub added_mass: f64,
    /// The press's tools (empty without a press).
    pub tools: Vec<ToolResume>,
    /// Each effect's state, by effect name.
    pub effects: Vec<(String, StateArrays)>,
    /// The energy ledger when the state was saved (the runs before
    /// included): a continued run carries it on.
    pub ledger: EnergyLedger,
}
