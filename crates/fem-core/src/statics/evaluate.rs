//! Evaluating a trial state: the effects' internal forces (and tangent)
//! into the solver's buffers, the residual on the equations and its norms.

use super::assembly::Sink;
use super::dof_map::split_norms;
use super::{Assembly, StaticSolver, StaticsError};
use crate::Dof;
use std::time::Instant;

/// Residual norms of a trial state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Eval {
    /// `‖R‖₂` over the equations (N and N·mm together): the line search's merit.
    pub merit: f64,
    /// `‖R‖₂` over the translation equations (N).
    pub r_t: f64,
    /// `‖R‖₂` over the rotation equations (N·mm).
    pub r_r: f64,
    /// Force reference over translations (N): `max(‖λ F_ext‖, ‖F_int −
    /// (1 − λ) F_start‖, ‖F_start − F_ext‖)`, the last the force a stress
    /// release lets go (zero otherwise).
    pub ref_t: f64,
    /// Moment reference over rotations (N·mm).
    pub ref_r: f64,
}

/// Why an increment attempt failed.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Failure {
    /// Stop the solve: a contract broken or a singular first tangent.
    Hard(StaticsError),
    /// Cut the increment back, for this reason.
    Soft(String),
}

impl StaticSolver {
    /// Evaluate the trial state in `x`, `dtheta`, `lambda_trial`: internal
    /// forces, residual `r` and, when `tangent`, the tangent values.
    pub(super) fn evaluate(&mut self, tangent: bool) -> Result<Eval, Failure> {
        let t = Instant::now();
        let result = self.assemble(tangent).and_then(|()| self.residual(tangent));
        self.timing.assembly += t.elapsed().as_secs_f64();
        result
    }

    fn assemble(&mut self, tangent: bool) -> Result<(), Failure> {
        self.f_int.iter_mut().for_each(|f| *f = 0.0);
        if tangent {
            self.values.iter_mut().for_each(|v| *v = 0.0);
        }
        let state = super::TrialState {
            x_start: &self.x_start,
            x_committed: &self.x_committed,
            x: &self.x,
            rotation_committed: &self.rotation_committed,
            dtheta: &self.dtheta,
            lambda: self.lambda_trial,
        };
        for (e, effect) in self.effects.iter_mut().enumerate() {
            let sink = if tangent {
                let seg = self.pattern.segments[e].clone();
                Sink::Scatter {
                    keys: &self.pattern.keys[seg.clone()],
                    slots: &self.pattern.slots[seg],
                    values: &mut self.values,
                    next: 0,
                }
            } else {
                Sink::Off
            };
            let mut out = Assembly::new(&mut self.f_int, sink);
            effect
                .internal_forces(&state, &mut out)
                .map_err(|e| Failure::Soft(e.to_string()))?;
            out.finish().map_err(|message| {
                Failure::Hard(StaticsError::Assembly {
                    effect: effect.name().to_string(),
                    message,
                })
            })?;
        }
        Ok(())
    }

    fn residual(&mut self, tangent: bool) -> Result<Eval, Failure> {
        let lambda = self.lambda_trial;
        for (i, &g) in self.dofs.global.iter().enumerate() {
            self.r[i] = self.f_int[g as usize] - self.target(g as usize, lambda);
        }
        if let Some(i) = self.r.iter().position(|r| !r.is_finite()) {
            let (node, dof) = self.dofs.node_dof(i);
            return Err(Failure::Soft(format!(
                "the residual of node {node} {} is not finite",
                dof.name()
            )));
        }
        if tangent && let Some(p) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(Failure::Soft(format!("tangent entry {p} is not finite")));
        }
        let (r_t, r_r) = split_norms(&self.r, &self.dofs.is_rotation);
        let (mut ext, mut int) = ([0.0; 2], [0.0; 2]);
        for (g, &f) in self.f_int.iter().enumerate() {
            let k = usize::from(Dof::ALL[g % 6].is_rotation());
            // The internal force net of the held forces still to let go (a
            // stress release), against the loads applied so far.
            let net = f - (1.0 - lambda) * self.f_start[g];
            let l = lambda * self.loads[g];
            int[k] += net * net;
            ext[k] += l * l;
        }
        let scale = self.release_scale;
        let reference = |k: usize| ext[k].sqrt().max(int[k].sqrt()).max(scale[k]);
        Ok(Eval {
            merit: r_t.hypot(r_r),
            r_t,
            r_r,
            ref_t: reference(0),
            ref_r: reference(1),
        })
    }
}
