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

use crate::solver::node_chunks::{NODE_CHUNK, parallel};
use crate::{Effect, NodalState, StableDt};
use rayon::prelude::*;

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
        let n = state.mass.len().min(self.stiffness.len());
        let (mass, stiffness) = (&state.mass[..n], &self.stiffness[..n]);
        if parallel(n) {
            mass.par_chunks(NODE_CHUNK)
                .zip(stiffness.par_chunks(NODE_CHUNK))
                .enumerate()
                .map(|(c, (m, s))| smallest(m, s, c * NODE_CHUNK))
                .reduce(|| None, pick)
        } else {
            smallest(mass, stiffness, 0)
        }
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

/// The smallest combined step over nodes `start..` of masses `mass` and
/// summed stiffness `stiffness`: the first node's of equal ones, the last
/// NaN if any (so that it is reported).
fn smallest(mass: &[f64], stiffness: &[f64], start: usize) -> Option<StableDt> {
    let mut best: Option<StableDt> = None;
    for (i, (&m, &s)) in mass.iter().zip(stiffness).enumerate() {
        if m > 0.0 && s > 0.0 {
            let dt = 2.0 * (m / s).sqrt();
            if best.is_none_or(|b| dt.is_nan() || dt < b.dt) {
                best = Some(StableDt {
                    dt,
                    element: start + i,
                    what: COMBINED_WHAT,
                });
            }
        }
    }
    best
}

/// Of two chunks' answers, the one [`smallest`] over both would give: the
/// later node's NaN, else the smaller step, the earlier node's at a tie.
/// It depends on the nodes alone, not on which chunk comes first, so the
/// chunks may be combined in any order.
fn pick(a: Option<StableDt>, b: Option<StableDt>) -> Option<StableDt> {
    match (a, b) {
        (Some(a), Some(b)) => {
            let (first, last) = if a.element <= b.element {
                (a, b)
            } else {
                (b, a)
            };
            Some(if last.dt.is_nan() || last.dt < first.dt {
                last
            } else {
                first
            })
        }
        (x, None) | (None, x) => x,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chunks combined in any order give what one pass over all nodes gives:
    /// ties (the first node), a NaN step (`∞/∞`: the last), nodes without
    /// mass or stiffness.
    #[test]
    fn chunks_combine_to_the_single_pass() {
        let n = 40;
        let inf = f64::INFINITY;
        // (node, mass, stiffness) changed from 1, 1; the node expected.
        type Case<'a> = (&'a [(usize, f64, f64)], usize);
        let cases: [Case<'_>; 4] = [
            (&[], 0),
            (&[(7, 0.25, 1.0), (29, 0.25, 1.0), (33, 1.0, 4.0)], 7),
            (
                &[
                    (7, 0.25, 1.0),
                    (12, inf, inf),
                    (31, inf, inf),
                    (35, 0.01, 1.0),
                ],
                31,
            ),
            (&[(3, 0.0, 1.0), (21, 0.5, 1.0)], 21),
        ];
        for (changes, expect) in cases {
            let (mut mass, mut stiffness) = (vec![1.0; n], vec![1.0; n]);
            mass[9] = 0.0;
            stiffness[15] = 0.0;
            for &(i, m, s) in changes {
                (mass[i], stiffness[i]) = (m, s);
            }
            let whole = smallest(&mass, &stiffness, 0).unwrap();
            assert_eq!(whole.element, expect);
            for chunk in [1, 3, 8, 40] {
                let parts: Vec<_> = mass
                    .chunks(chunk)
                    .zip(stiffness.chunks(chunk))
                    .enumerate()
                    .map(|(c, (m, s))| smallest(m, s, c * chunk))
                    .collect();
                for order in [false, true] {
                    let mut it: Vec<_> = parts.clone();
                    if order {
                        it.reverse();
                    }
                    let got = it.into_iter().fold(None, pick).unwrap();
                    assert_eq!(
                        got.element, whole.element,
                        "chunk {chunk}, reversed {order}"
                    );
                    assert_eq!(got.dt.to_bits(), whole.dt.to_bits());
                }
            }
        }
    }
}
