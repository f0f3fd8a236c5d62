//! The stable time step of the effects acting on the same nodes together.
//!
//! Each effect bounds its own step ([`Effect::stable_dt`]). Where two act on
//! one node (the blank's shells and a contact spring that holds the node,
//! two contact pairs clamping a flange), the node's highest frequency is
//! that of their summed stiffness: with `s_i` the stiffness an effect puts
//! on node `i` ([`Effect::nodal_stiffness`]),
//!
//! ```text
//! ω_i² ≤ Σ_effects s_i / m_i,    Δt_i = 2 / ω_i = 2 √(m_i / Σ s_i)
//! ```
//!
//! (the largest eigenvalue of `M⁻¹(K₁ + K₂)` is at most the sum of theirs).
//! Taking the smaller of the effects' own steps instead lets a sticking
//! node's stick spring and the membrane drive each other unstable at up to
//! `√2` times the step they tolerate together.

use crate::{Effect, NodalState, StableDt};

/// What the combined limit reports as its cause (its `element` is a node).
pub const COMBINED_WHAT: &str =
    "the effects on one node together, 2 √(m / Σ stiffness) (element = node index)";

/// Scratch space for the combined nodal limit (one stiffness per node).
#[derive(Debug, Default)]
pub(crate) struct NodalLimit {
    stiffness: Vec<f64>,
}

impl NodalLimit {
    pub(crate) fn new(nodes: usize) -> Self {
        Self {
            stiffness: vec![0.0; nodes],
        }
    }

    /// Sum the nodal stiffness of every effect, if two or more stiffen nodes
    /// now; `false` (and nothing summed) otherwise.
    fn gather(&mut self, effects: &[Box<dyn Effect>], state: &NodalState) -> bool {
        if effects.iter().filter(|e| e.stiffens_nodes()).count() < 2 {
            return false;
        }
        self.stiffness.iter_mut().for_each(|s| *s = 0.0);
        for e in effects.iter().filter(|e| e.stiffens_nodes()) {
            e.nodal_stiffness(state, &mut self.stiffness);
        }
        true
    }

    /// The smallest combined step `2 √(m_i / Σ s_i)` over the nodes of
    /// positive mass, and the node; `None` when fewer than two effects
    /// stiffen nodes.
    pub(crate) fn stable_dt(
        &mut self,
        effects: &[Box<dyn Effect>],
        state: &NodalState,
    ) -> Option<StableDt> {
        if !self.gather(effects, state) {
            return None;
        }
        let mut best: Option<StableDt> = None;
        for (i, (&m, &s)) in state.mass.iter().zip(&self.stiffness).enumerate() {
            if m > 0.0 && s > 0.0 {
                let dt = 2.0 * (m / s).sqrt();
                if best.is_none_or(|b| dt.is_nan() || dt < b.dt) {
                    best = Some(StableDt {
                        dt,
                        element: i,
                        what: COMBINED_WHAT,
                    });
                }
            }
        }
        best
    }

    /// Fixed-step mass scaling for the combination: raise the translational
    /// mass of every moving node to `Σ s_i (goal/2)²` where it is below, so
    /// that its combined step is at least `goal` (s). `mass` holds the masses
    /// after the effects' own scaling; returns the mass added (tonne).
    pub(crate) fn scale_mass(
        &mut self,
        effects: &[Box<dyn Effect>],
        state: &NodalState,
        goal: f64,
        mass: &mut [f64],
    ) -> f64 {
        if !self.gather(effects, state) {
            return 0.0;
        }
        let q = 0.25 * goal * goal;
        let mut added = 0.0;
        for (m, &s) in mass.iter_mut().zip(&self.stiffness) {
            let need = s * q;
            // Massless nodes do not move: they stay massless.
            if *m > 0.0 && need > *m {
                added += need - *m;
                *m = need;
            }
        }
        added
    }

    /// The effects that put stiffness on `node`, with their share (N/mm),
    /// as `name 1.2e5 N/mm + …` (for messages; not on the hot path).
    pub(crate) fn contributors(
        &mut self,
        effects: &[Box<dyn Effect>],
        state: &NodalState,
        node: usize,
    ) -> String {
        let mut parts = Vec::new();
        for e in effects.iter().filter(|e| e.stiffens_nodes()) {
            self.stiffness.iter_mut().for_each(|s| *s = 0.0);
            e.nodal_stiffness(state, &mut self.stiffness);
            if let Some(&s) = self.stiffness.get(node)
                && s > 0.0
            {
                parts.push(format!("{} {s:.3e} N/mm", e.name()));
            }
        }
        parts.join(" + ")
    }
}
