//! Stage 3, scatter: the contact forces `F = A (p n + t)` of the gathered
//! points onto their nodes, `−F` and its moment onto the tool, the step's
//! energies (friction, the work of blank and tool, the stick springs'
//! stored energy), and each point's results and history for the next step.
//! It also completes the work of the forces of points that opened this step.
//! All sums run in pair-point order on one thread.

use plugins_api::Vec3;

use super::{Batch, PointsMut, ToolStep};
use crate::{BlankGeometry, BlankView, PointStatus};

/// The scatter stage of one step: the step's data that every point reads.
pub(crate) struct Scatter<'a> {
    /// The blank's nodal geometry of this step (areas).
    pub geometry: &'a BlankGeometry,
    /// The blank's nodal state of this step (velocities).
    pub blank: &'a BlankView<'a>,
    /// The tool's placement and motion.
    pub tool: &'a ToolStep,
    /// Time step (s).
    pub dt: f64,
    /// The law's stick stiffness `k_T` (MPa/mm).
    pub k_t: f64,
}

/// What scatter sums over a pair's points in one step.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ScatterSums {
    /// Resultant force on the tool (N).
    pub force: Vec3,
    /// Resultant moment on the tool about its origin (N·mm).
    pub moment: Vec3,
    /// Frictional dissipation of the step `Σ ΔD A` (N·mm).
    pub friction: f64,
    /// Work of the contact forces on the blank in the step (N·mm).
    pub blank_work: f64,
    /// Work of the tool through the contact in the step (N·mm).
    pub tool_work: f64,
    /// Stored energy: seeded with the penalty springs', plus the stick springs' (N·mm).
    pub stored: f64,
    /// Whether any point hit the clamp of its law.
    pub clamped: bool,
}

impl Scatter<'_> {
    /// Scatter `batch` (points `k`, blank nodes `nodes[k]`) into `points`
    /// (each point's force `F` in `points.force`, which
    /// [`crate::ContactPair::add_forces`] adds to the nodes), then complete
    /// the work of the points that opened; `stored` seeds
    /// [`ScatterSums::stored`].
    pub fn run(
        &self,
        nodes: &[u32],
        batch: &Batch,
        points: &mut PointsMut<'_>,
        stored: f64,
    ) -> ScatterSums {
        let mut sums = ScatterSums {
            stored,
            ..ScatterSums::default()
        };
        self.touching(nodes, batch, points, &mut sums);
        self.released(nodes, points, &mut sums);
        sums
    }

    /// The gathered (touching) points, in batch order.
    fn touching(
        &self,
        nodes: &[u32],
        batch: &Batch,
        points: &mut PointsMut<'_>,
        sums: &mut ScatterSums,
    ) {
        let dt = self.dt;
        for (j, &k) in batch.points.iter().enumerate() {
            let k = k as usize;
            let i = nodes[k] as usize;
            let out = &batch.outputs[j];
            let area = self.geometry.area[i];
            let normal = batch.inputs[j].kin.n_new;
            let (arm, v_tool) = batch.touch[j];
            let p = batch.inputs[j].p;
            let f = (normal * p + out.t) * area;
            sums.force -= f;
            sums.moment -= arm.cross(&f);
            let f_mid = 0.5 * (f + points.force[k]);
            sums.blank_work += f_mid.dot(&(self.blank.v[i] * dt));
            sums.tool_work += f_mid.dot(&(v_tool * dt));
            sums.friction += out.dissipation * area;
            if self.k_t > 0.0 {
                sums.stored += 0.5 * out.t.norm_squared() * area / self.k_t;
            }
            points.friction[k] = batch.states[j];
            points.n_old[k] = normal;
            points.force[k] = f;
            points.pressure[k] = p;
            points.traction[k] = out.t;
            points.tau_c[k] = out.tau_c;
            points.slip[k] += out.dgamma;
            points.status[k] = if out.stick {
                PointStatus::Stick
            } else {
                PointStatus::Slip
            };
            sums.clamped |= out.clamped;
        }
    }

    /// Points that opened this step still complete the work of their last force.
    fn released(&self, nodes: &[u32], points: &mut PointsMut<'_>, sums: &mut ScatterSums) {
        let dt = self.dt;
        for (k, &node) in nodes.iter().enumerate() {
            if points.status[k] == PointStatus::Open && points.force[k] != Vec3::zeros() {
                let i = node as usize;
                let f_mid = 0.5 * points.force[k];
                sums.blank_work += f_mid.dot(&(self.blank.v[i] * dt));
                sums.tool_work += f_mid.dot(&(self.tool.velocity.linear * dt));
                points.force[k] = Vec3::zeros();
            }
        }
    }
}
