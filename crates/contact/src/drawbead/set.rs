//! The drawbeads of a [`crate::ContactEffect`], with what they read from
//! the pairs (where each bead's tool touches the blank) and their nodal
//! stiffness.

use plugins_api::{ToolSurface, Vec3};

use super::{BeadEnergy, Drawbead};
use crate::{BlankGeometry, BlankView, ContactPair};

/// What the beads' step reads from the contact step.
pub(crate) struct BeadInputs<'a> {
    /// The pairs, after their step.
    pub pairs: &'a [ContactPair],
    /// Whether each pair is active in the press step.
    pub active: &'a [bool],
    /// The tools, at their poses.
    pub tools: &'a [Box<dyn ToolSurface>],
    /// The blank's quads.
    pub geometry: &'a BlankGeometry,
    /// The blank's nodal state.
    pub view: &'a BlankView<'a>,
    /// Time step (s).
    pub dt: f64,
}

/// The drawbeads and their scratch.
#[derive(Debug, Default)]
pub(crate) struct BeadSet {
    pub beads: Vec<Drawbead>,
    /// Per node: whether it touches a tool in the step.
    touching: Vec<bool>,
    /// Per node: the stick stiffness of the beads' crossings in the last step (N/mm).
    pub stiffness: Vec<f64>,
}

impl BeadSet {
    /// The beads over a blank of `nodes` nodes.
    pub fn new(beads: Vec<Drawbead>, nodes: usize) -> Self {
        let n = if beads.is_empty() { 0 } else { nodes };
        Self {
            beads,
            touching: vec![false; n],
            stiffness: vec![0.0; n],
        }
    }

    /// The beads' step, after the pairs': where the blank touches a tool
    /// (the active pairs' touching points), then each bead's
    /// forces on the nodes (`f`), its reaction on its tool (`reactions`)
    /// and its tool's work in the step (`tool_work`).
    pub fn step(
        &mut self,
        s: &BeadInputs<'_>,
        f: &mut [Vec3],
        reactions: &mut [Vec3],
        tool_work: &mut [f64],
    ) {
        self.touching.iter_mut().for_each(|t| *t = false);
        for (pair, &active) in s.pairs.iter().zip(s.active) {
            if active {
                pair.mark_touching(&mut self.touching);
            }
        }
        self.stiffness.iter_mut().for_each(|k| *k = 0.0);
        let quads = s.geometry.quads();
        for bead in &mut self.beads {
            let t = bead.tool();
            let before = bead.energy.tool_work;
            bead.step(
                s.tools[t].as_ref(),
                s.geometry,
                s.view,
                &self.touching,
                s.dt,
            );
            bead.add_forces(quads, f);
            bead.add_nodal_stiffness(quads, &mut self.stiffness);
            reactions[t] -= bead.resultant;
            tool_work[t] += bead.energy.tool_work - before;
        }
    }

    /// The beads' energies together (N·mm).
    pub fn energy(&self) -> BeadEnergy {
        let mut e = BeadEnergy::default();
        for b in &self.beads {
            e.dissipation += b.energy.dissipation;
            e.blank_work += b.energy.blank_work;
            e.tool_work += b.energy.tool_work;
            e.stored += b.energy.stored;
        }
        e
    }

    /// Whether a bead crossed clamped blank in the last step.
    pub fn engaged(&self) -> bool {
        self.beads.iter().any(Drawbead::engaged)
    }
}
