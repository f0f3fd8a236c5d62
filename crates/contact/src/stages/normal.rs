//! Stage 1c, the normal stage: from each candidate's projection, the gap of
//! the blank face on the tool's side, the penalty pressure, the relative
//! slip of the step and the kinematics the friction model declared it reads
//! (friction-math §1, §6). It owns the contact/no-contact decision, the
//! renewal of the points' [`LastProjection`] and the gathering of the
//! touching points into the friction [`Batch`].

use plugins_api::{PointNeeds, StepInput, StepKinematics, ToolRegion, Vec3};

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
    /// the touching ones into `batch` (emptied first; its input slots are
    /// reused, see [`Normal::fill`]) in candidate order, and open the others
    /// in `points`.
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
        let candidates = cand.points.iter().zip(&cand.near).zip(&cand.regions);
        for ((&k, pr), region) in candidates {
            let k = k as usize;
            let i = nodes[k] as usize;
            self.remember(k, i, pr, region, last);
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
            let j = batch.points.len();
            if j == batch.inputs.len() {
                batch.inputs.push(self.blank_input());
            }
            self.fill(&mut batch.inputs[j], i, n_old, pr.normal, &touch);
            batch.touch.push((touch.arm, touch.v_tool));
            batch.points.push(k as u32);
        }
        batch.inputs.truncate(batch.points.len());
        sums
    }

    /// Keep the warm start of point `k` (node `i`), the `region` of a new
    /// projection and, with `skip_far`, its distance and position in the
    /// tool's frame.
    #[inline]
    fn remember(
        &self,
        k: usize,
        i: usize,
        pr: &Near,
        region: &Option<ToolRegion>,
        last: &mut LastProjection,
    ) {
        last.hint[k] = Some(pr.hint);
        if pr.projected {
            last.region[k] = *region;
        }
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
        // The tool's material point under the node moves at the rigid
        // velocity of the step's midpoint, where the node's velocity is read:
        // with the arm at t_{n+1} a turning tool would drift each point by
        // ½Δt²ω²r a step, and the stick springs would ratchet it up.
        let lin = self.tool.velocity.linear;
        let arm_mid = arm - (blank.v[i] - lin) * (0.5 * self.dt);
        let v_tool = lin + self.tool.velocity.angular.cross(&arm_mid);
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

    /// A slot for a new point in the batch: every field the law and
    /// formulation do not read at its value in a default [`StepInput`].
    fn blank_input(&self) -> StepInput {
        let n = Vec3::z();
        StepInput::new(0.0, Vec3::zeros(), StepKinematics::simple(self.dt, n, n))
    }

    /// Write the return mapping's input at node `i` into `slot`: pressure,
    /// slip increment and normals, and the kinematics and flow stress the
    /// law and formulation declared. Fields not declared are left as they
    /// are: at their default since the slot was made (they are never written).
    #[inline]
    fn fill(&self, slot: &mut StepInput, i: usize, n_old: Vec3, n_new: Vec3, touch: &Touch) {
        let g = self.geometry;
        let needs = self.needs;
        slot.p = touch.f_n / g.area[i];
        slot.du = touch.v_rel * self.dt;
        let kin = &mut slot.kin;
        kin.dt = self.dt;
        kin.n_old = n_old;
        kin.n_new = n_new;
        if needs.contains(PointNeeds::TOOL_ROTATION) {
            kin.tool_rotation = self.tool.rotation;
        }
        if needs.contains(PointNeeds::SPIN) || needs.contains(PointNeeds::VELOCITY_GRADIENT) {
            kin.vel_grad = g.vel_grad[i];
        }
        if needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
            kin.f_old = g.f_old[i];
            kin.f_new = g.f_new[i];
        }
        if needs.contains(PointNeeds::FLOW_STRESS) {
            // The tool normal points towards the blank: a tool on the +n_blank
            // side has n_tool·n_blank < 0 and touches the top fibre.
            slot.flow_stress = match self.blank.flow_stress {
                Some((top, _)) if n_new.dot(&g.normal[i]) < 0.0 => top[i],
                Some((_, bottom)) => bottom[i],
                None => f64::NAN,
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::penalty::PenaltySettings;
    use plugins_api::{Aabb, Mat3, PointState, ProjectionHint, RigidVelocity};

    /// The input as the step built it before the stages: a whole
    /// [`StepInput`] per point, undeclared fields at their defaults.
    fn reference(n: &Normal<'_>, i: usize, n_old: Vec3, n_new: Vec3, t: &Touch) -> StepInput {
        let g = n.geometry;
        let mut kin = StepKinematics::simple(n.dt, n_old, n_new);
        kin.tool_rotation = n.tool.rotation;
        if n.needs.contains(PointNeeds::VELOCITY_GRADIENT) {
            kin.vel_grad = g.vel_grad[i];
        }
        if n.needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
            kin.f_old = g.f_old[i];
            kin.f_new = g.f_new[i];
        }
        let mut input = StepInput::new(t.f_n / g.area[i], t.v_rel * n.dt, kin);
        if n.needs.contains(PointNeeds::FLOW_STRESS)
            && let Some((top, bottom)) = n.blank.flow_stress
        {
            input.flow_stress = if n_new.dot(&g.normal[i]) < 0.0 {
                top[i]
            } else {
                bottom[i]
            };
        }
        input
    }

    /// Reused batch slots hold, after every step, exactly the input a fresh
    /// one would (bit for bit, NaN included), whatever touched before:
    /// declared fields renewed, the others at their defaults.
    #[test]
    fn reused_slots_equal_fresh_inputs() {
        let all = PointNeeds::VELOCITY_GRADIENT
            .union(PointNeeds::DEFORMATION_GRADIENT)
            .union(PointNeeds::FLOW_STRESS)
            .union(PointNeeds::TOOL_ROTATION);
        for needs in [PointNeeds::NONE, PointNeeds::TOOL_ROTATION, all] {
            check_reuse(needs);
        }
    }

    /// A tool moving and turning, as `ToolStep::new` makes it: the step's
    /// rotation is the identity unless declared.
    fn tool_step(needs: PointNeeds) -> ToolStep {
        let turn = Mat3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        ToolStep {
            bbox: Aabb {
                min: Vec3::repeat(-9.0),
                max: Vec3::repeat(9.0),
            },
            origin: Vec3::new(0.1, 0.2, -1.0),
            to_local: Mat3::identity(),
            to_global: Mat3::identity(),
            velocity: RigidVelocity {
                linear: Vec3::new(3.0, 0.0, -1.0),
                angular: Vec3::new(0.0, 0.5, 0.0),
            },
            rotation: if needs.contains(PointNeeds::TOOL_ROTATION) {
                turn
            } else {
                Mat3::identity()
            },
        }
    }

    /// The blank's positions and velocities at step `s`.
    fn blank_state(x0: &[Vec3], s: f64) -> [Vec<Vec3>; 2] {
        let x = x0
            .iter()
            .enumerate()
            .map(|(i, p)| p + Vec3::new(0.0, 0.0, 0.01 * (s + i as f64).sin()))
            .collect();
        let v = (0..x0.len())
            .map(|i| Vec3::new(1.0 + s, -(i as f64), 0.5))
            .collect();
        [x, v]
    }

    /// Every point a candidate, the ones in `touch` within half the unit
    /// thickness of the tool; the normal faces up, or down when `down`.
    fn candidates(m: usize, touch: &[usize], s: f64, down: bool) -> Candidates {
        let sign = if down { -1.0 } else { 1.0 };
        let near = |k: usize| Near {
            normal: Vec3::new(0.0, 0.1 * s, sign).normalize(),
            distance: if touch.contains(&k) {
                0.45 - 0.01 * k as f64
            } else {
                0.7
            },
            hint: ProjectionHint {
                patch: 0,
                u: 0.0,
                v: 0.0,
            },
            projected: true,
            curved: false,
        };
        Candidates {
            points: (0..m as u32).collect(),
            near: (0..m).map(near).collect(),
            regions: vec![None; m],
        }
    }

    /// The per-point arrays of a pair of `m` points, all open.
    struct Arrays {
        status: Vec<PointStatus>,
        friction: Vec<PointState>,
        pressure: Vec<f64>,
        traction: Vec<Vec3>,
        tau_c: Vec<f64>,
        slip: Vec<f64>,
        n_old: Vec<Vec3>,
        force: Vec<Vec3>,
    }

    impl Arrays {
        fn new(m: usize) -> Self {
            Self {
                status: vec![PointStatus::Open; m],
                friction: vec![PointState::default(); m],
                pressure: vec![0.0; m],
                traction: vec![Vec3::zeros(); m],
                tau_c: vec![0.0; m],
                slip: vec![0.0; m],
                n_old: (0..m)
                    .map(|k| Vec3::new(0.01 * k as f64, 0.0, 1.0).normalize())
                    .collect(),
                force: vec![Vec3::zeros(); m],
            }
        }

        fn points(&mut self) -> PointsMut<'_> {
            PointsMut {
                status: &mut self.status,
                friction: &mut self.friction,
                pressure: &mut self.pressure,
                traction: &mut self.traction,
                tau_c: &mut self.tau_c,
                slip: &mut self.slip,
                n_old: &mut self.n_old,
                force: &mut self.force,
            }
        }
    }

    /// Three steps of a 2 × 2-quad blank with the needs `needs`: all nine
    /// points touch, then two (which stuck before), then all again; after
    /// each, every batch input is compared with [`reference`].
    fn check_reuse(needs: PointNeeds) {
        let mesh = fem_core::rectangle(2.0, 2.0, 2, 2).unwrap();
        let m = mesh.nodes.len();
        let mut geometry = BlankGeometry::new(m, &mesh.quads).unwrap();
        let settings = Settings {
            penalty: PenaltySettings::default(),
            search_margin: 1.0,
            max_penetration: 3.0,
            skip_far: true,
        };
        let tool = tool_step(needs);
        let nodes: Vec<u32> = (0..m as u32).collect();
        let stiffness: Vec<f64> = (0..m).map(|k| 100.0 + k as f64).collect();
        let (mass, thickness) = (vec![1e-6; m], vec![1.0; m]);
        let mut arrays = Arrays::new(m);
        let mut last = LastProjection::new(m);
        let mut batch = Batch::with_capacity(m);
        let all: Vec<usize> = (0..m).collect();
        for (step, touch) in [&all[..], &[2, 7], &all[..]].into_iter().enumerate() {
            let s = step as f64;
            let [x, v] = blank_state(&mesh.nodes, s);
            let top: Vec<f64> = (0..m).map(|i| 300.0 + i as f64 + s).collect();
            let bottom: Vec<f64> = (0..m).map(|i| 200.0 + i as f64 + s).collect();
            let blank = BlankView {
                x0: &mesh.nodes,
                x: &x,
                v: &v,
                mass: &mass,
                thickness: &thickness,
                flow_stress: Some((&top, &bottom)),
            };
            geometry.update(&blank, 1e-6, needs);
            let cand = candidates(m, touch, s, step == 1);
            let normal = Normal {
                settings: &settings,
                tool: &tool,
                needs,
                geometry: &geometry,
                blank: &blank,
                dt: 1e-6,
            };
            let mut points = arrays.points();
            normal.run(
                &nodes,
                &stiffness,
                &cand,
                &mut last,
                &mut points,
                &mut batch,
            );
            assert_eq!(batch.points.len(), touch.len());
            assert_eq!(batch.inputs.len(), touch.len());
            for (j, &k) in batch.points.iter().enumerate() {
                let k = k as usize;
                let pr = &cand.near[k];
                let t = normal.touch(k, pr, stiffness[k]).unwrap();
                let n_prev = if arrays.status[k] == PointStatus::Open {
                    pr.normal
                } else {
                    arrays.n_old[k]
                };
                let want = reference(&normal, k, n_prev, pr.normal, &t);
                assert_eq!(
                    format!("{:?}", batch.inputs[j]),
                    format!("{want:?}"),
                    "step {step}, point {k}, needs {needs:?}"
                );
            }
            // The next step sees these points stick.
            for &k in touch {
                arrays.status[k] = PointStatus::Stick;
            }
        }
    }
}
