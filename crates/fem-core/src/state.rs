//! Nodal state (positions, velocities, lumped masses), force accumulators and the step context.
//!
//! Laid out as structures of arrays: each loop (element gather, nodal update)
//! reads only the arrays it needs, contiguously.

use crate::Vec3;

/// The state of every node, indexed by the mesh's 0-based node index.
///
/// Between steps and while effects compute forces, `x` holds the positions at
/// `t_{n+1}` and `v`, `w` the velocities at the half step `t_{n+1/2}` (central
/// difference). Before the first step, after
/// [`Solver::initialize`](crate::Solver::initialize), `v` and `w` hold the
/// virtual half-step velocities `v_{-1/2} = v_0 - Δt_{1/2}/2 · a_0`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NodalState {
    /// Initial (reference) positions (mm).
    pub x0: Vec<Vec3>,
    /// Current positions (mm).
    pub x: Vec<Vec3>,
    /// Translational velocities (mm/s).
    pub v: Vec<Vec3>,
    /// Angular velocities in the global frame (rad/s).
    pub w: Vec<Vec3>,
    /// Lumped translational mass (tonne), mass scaling included.
    pub mass: Vec<f64>,
    /// Lumped rotational inertia (tonne·mm²), one scalar per node, mass scaling included.
    pub inertia: Vec<f64>,
}

impl NodalState {
    /// A state at rest in the configuration `x0`, with zero masses.
    pub fn at_rest(x0: &[Vec3]) -> Self {
        let n = x0.len();
        Self {
            x0: x0.to_vec(),
            x: x0.to_vec(),
            v: vec![Vec3::zeros(); n],
            w: vec![Vec3::zeros(); n],
            mass: vec![0.0; n],
            inertia: vec![0.0; n],
        }
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Displacement of node `i` from its reference position (mm).
    pub fn displacement(&self, i: usize) -> Vec3 {
        self.x[i] - self.x0[i]
    }
}

/// Nodal force (N) and moment (N·mm) accumulators in the global frame.
///
/// The engine zeroes them at the start of each force computation, adds the
/// nodal loads, then every effect *adds* its contribution as the force acting
/// on the nodes (an element adds `-f_int`). An effect that assembles in
/// parallel may keep per-element buffers and scatter them here; the engine
/// reads the arrays only after every effect has returned.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Forces {
    /// Forces on the nodes (N).
    pub f: Vec<Vec3>,
    /// Moments on the nodes (N·mm).
    pub m: Vec<Vec3>,
}

impl Forces {
    /// Zeroed accumulators for `n` nodes.
    pub fn zeros(n: usize) -> Self {
        Self {
            f: vec![Vec3::zeros(); n],
            m: vec![Vec3::zeros(); n],
        }
    }

    /// Set every force and moment to zero (no allocation).
    pub fn clear(&mut self) {
        self.f.iter_mut().for_each(|f| *f = Vec3::zeros());
        self.m.iter_mut().for_each(|m| *m = Vec3::zeros());
    }
}

/// Where the integration stands when forces are asked for.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepContext<'a> {
    /// Time `t_{n+1}` of the configuration whose forces are computed (s).
    pub time: f64,
    /// Time step `Δt_{n+1/2} = t_{n+1} - t_n` (s); 0 for the initial force
    /// computation at `t = 0`.
    pub dt: f64,
    /// Step number `n + 1` (0 for the initial force computation).
    pub step: u64,
    /// The press, already moved to `time` by the press stage (`None`
    /// without one): the tools' poses and velocities, the current press step
    /// and the pairs it activates.
    pub press: Option<&'a crate::Press>,
}
