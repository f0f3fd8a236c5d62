//! Stage 1c, the normal stage: from each candidate's projection, the gap of
//! the blank face on the tool's side, the penalty pressure, the relative
//! slip of the step and the kinematics the friction model declared it reads
//! (friction-math §1, §6). It owns the contact/no-contact decision, the
//! renewal of the points' [`LastProjection`] and the gathering of the
//! touching points into the friction [`Batch`].

use plugins_api::{PointNeeds, StepInput, StepKinematics, Vec3};

use super::{Batch, Candidates, LastProjection, Near, PointsMut, Settings, ToolStep};
use crate::{BlankGeometry, BlankView, PointStatus};

/// The normal stage of one step: the step's data that every point reads.
pub(crate) struct Normal<'a> {
    /// The pair's enforcement settings.
    pub settings: &'a Settings,
    /// The tool's placement and motion.
    pub tool: &'a ToolStep,
    /// What the pair's law and formulation read.
    pub needs: PointNeeds,
    /// The blank's nodal geometry of this step.
    pub geometry: &'a BlankGeometry,
    /// The blank's nodal state of this step.
    pub blank: &'a BlankView<'a>,
    /// Time step (s).
    pub dt: f64,
}

/// Sums the normal stage takes over the touching points, in pair-point order.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct NormalSums {
    /// Energy stored in the penalty springs, `Σ ½ k g²` (N·mm).
    pub stored: f64,
    /// Deepest penetration `−g` (mm; 0 when none touch).
    pub penetration_max: f64,
    /// Summed penalty stiffness (N/mm).
    pub stiffness: f64,
}

/// A candidate found touching.
struct Touch {
    /// Gap `g < 0` of the blank face (mm).
    gap: f64,
    /// Normal force (N), damped when asked.
    f_n: f64,
    /// Contact point about the tool origin (mm).
    arm: Vec3,
    /// The tool's velocity at the contact point (mm/s).
    v_tool: Vec3,
    /// Blank velocity relative to the tool (mm/s).
    v_rel: Vec3,
}

impl Normal<'_> {
    /// Run the stage over `cand` (points `k`, blank nodes `nodes[k]`, penalty
    /// stiffness `stiffness[k]`): renew `last` for every candidate, gather
    /// the touching ones into `batch` (cleared first) in candidate order, and
    /// open the others in `points`.
    pub fn run(
        &self,
        nodes: &[u32],
        stiffness: &[f64],
        cand: &Candidates,
        last: &mut LastProjection,
        points: &mut PointsMut<'_>,
        batch: &mut Batch,
    ) -> NormalSums {
        batch.clear();
        let mut sums = NormalSums::default();
        for (&k, pr) in cand.points.iter().zip(&cand.near) {
            let k = k as usize;
            let i = nodes[k] as usize;
            self.remember(k, i, pr, last);
            let Some(touch) = self.touch(i, pr, stiffness[k]) else {
                points.open(k);
                continue;
            };
            sums.stored += 0.5 * stiffness[k] * touch.gap * touch.gap;
            sums.penetration_max = sums.penetration_max.max(-touch.gap);
            sums.stiffness += stiffness[k];
            let n_old = if points.status[k] == PointStatus::Open {
                pr.normal
            } else {
                points.n_old[k]
            };
            batch.inputs.push(self.input(i, n_old, pr.normal, &touch));
            batch.touch.push((touch.arm, touch.v_tool));
            batch.points.push(k as u32);
        }
        sums
    }

    /// Keep the warm start of point `k` (node `i`) and, with `skip_far`, its
    /// distance and position in the tool's frame.
    #[inline]
    fn remember(&self, k: usize, i: usize, pr: &Near, last: &mut LastProjection) {
        last.hint[k] = Some(pr.hint);
        if self.settings.skip_far {
            last.dist[k] = pr.distance.abs();
            last.local[k] = self.tool.local(&self.blank.x[i]);
        }
    }

    /// Node `i` with projection `pr` and penalty stiffness `k_n`: its contact,
    /// or `None` when open (a gap, a penetration deeper than `max_penetration`
    /// thicknesses, or no area).
    #[inline]
    fn touch(&self, i: usize, pr: &Near, k_n: f64) -> Option<Touch> {
        let blank = self.blank;
        let half = 0.5 * blank.thickness[i];
        let gap = pr.distance - half;
        if gap >= 0.0 || -gap > self.settings.max_penetration * blank.thickness[i] {
            return None;
        }
        let area = self.geometry.area[i];
        if area.is_nan() || area <= 0.0 {
            return None;
        }
        let arm = blank.x[i] - pr.normal * half - self.tool.origin;
        let v_tool = self.tool.velocity.linear + self.tool.velocity.angular.cross(&arm);
        let v_rel = blank.v[i] - v_tool;
        let mut f_n = k_n * (-gap);
        let damping = self.settings.penalty.damping;
        if damping > 0.0 {
            let c = 2.0 * damping * (k_n * blank.mass[i]).sqrt();
            // Approaching velocity is -v_rel·n > 0; damping resists it, never pulls.
            f_n = (f_n - c * v_rel.dot(&pr.normal)).max(0.0);
        }
        Some(Touch {
            gap,
            f_n,
            arm,
            v_tool,
            v_rel,
        })
    }

    /// The return mapping's input at node `i`: pressure, slip increment and
    /// the kinematics and flow stress the law and formulation declared.
    #[inline]
    fn input(&self, i: usize, n_old: Vec3, n_new: Vec3, touch: &Touch) -> StepInput {
        let g = self.geometry;
        let mut kin = StepKinematics::simple(self.dt, n_old, n_new);
        kin.tool_rotation = self.tool.rotation;
        if self.needs.contains(PointNeeds::SPIN)
            || self.needs.contains(PointNeeds::VELOCITY_GRADIENT)
        {
            kin.vel_grad = g.vel_grad[i];
        }
        if self.needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
            kin.f_old = g.f_old[i];
            kin.f_new = g.f_new[i];
        }
        let mut input = StepInput::new(touch.f_n / g.area[i], touch.v_rel * self.dt, kin);
        if self.needs.contains(PointNeeds::FLOW_STRESS)
            && let Some((top, bottom)) = self.blank.flow_stress
        {
            // The tool normal points towards the blank: a tool on the +n_blank
            // side has n_tool·n_blank < 0 and touches the top fibre.
            input.flow_stress = if n_new.dot(&g.normal[i]) < 0.0 {
                top[i]
            } else {
                bottom[i]
            };
        }
        input
    }
}
