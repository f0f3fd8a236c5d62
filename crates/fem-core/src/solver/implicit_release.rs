//! The implicit springback: when the tools let go in a springback step of
//! method [`ReleaseMethod::Implicit`](crate::ReleaseMethod), the release is
//! solved statically (`crate::statics`) in place of the dynamic relaxation's
//! thousands of damped steps.
//!
//! The static problem is the model as the tools let go: every effect's
//! static form ([`Effect::static_form`](crate::Effect::static_form); contact
//! adds nothing once released), every constrained DOF of the explicit
//! solver held (the scene's conditions and the 3-2-1 constraints that remove
//! the free rigid-body modes), the nodal loads as they stand, and the
//! internal forces the tools held let go increment by increment
//! ([`StaticProblem::release_start_forces`]). The converged positions and
//! the effects' committed states ([`Effect::absorb_static`](crate::Effect::absorb_static))
//! become the explicit state, at rest; the explicit steps that follow only
//! confirm it (the step ends when its out-of-balance force is below the
//! tolerance of the force let go, as with the relaxation).
//!
//! Energy: the static release takes the model from one state of rest to
//! another. The nodal loads' work over the jump is booked as external work,
//! and what the stored energy lost plus that work (and the kinetic energy
//! left when the tools let go) as dissipated, like the relaxation's damping
//! work: the ledger stays closed. Each effect's tally follows the jump
//! (springs from their lengths, shells by the work of the static
//! increments, plastic dissipation included).

use super::Solver;
use crate::statics::{NewtonSettings, SolveReport, StaticProblem, StaticSolver};
use crate::{Dof, Dofs, FemError, StaticForm};

impl Solver {
    /// Solve the release statically and take the result as the explicit
    /// state (module docs). Called once the tools have let go and the
    /// 3-2-1 constraints are in place.
    ///
    /// # Errors
    /// [`FemError::ImplicitSpringback`]: an effect without a static form,
    /// or the solve failed (the model is then at its last converged
    /// increment, and the message carries the residual history).
    pub(super) fn release_implicitly(&mut self, dt: f64) -> Result<(SolveReport, f64), FemError> {
        let fail = |m: String| FemError::ImplicitSpringback(m);
        let mut problem = StaticProblem::new(&self.state.x)?;
        let mut forms = Vec::new();
        for (i, e) in self.effects.iter().enumerate() {
            match e.static_form().map_err(fail)? {
                StaticForm::Released => {}
                StaticForm::Tangent(t) => forms.push((i, problem.add_boxed_effect(t))),
            }
        }
        for c in &self.constraints {
            problem.fix(&[c.node], Dofs::of(&[Dof::ALL[usize::from(c.dof)]]))?;
        }
        for l in &self.loads {
            let p = l.value * self.amp_values[l.amplitude as usize];
            problem.add_load(&[l.node], Dof::ALL[usize::from(l.dof)], p)?;
        }
        problem.release_start_forces();
        let settings = release_settings();
        let mut statics = StaticSolver::new(problem, settings).map_err(|e| fail(e.to_string()))?;
        let released = statics.release_residual();
        self.book_half_step(dt);
        let before = self.internal_and_kinetic();
        let outcome = statics.solve();
        // The last converged increment, whatever the outcome.
        let load_work = self.take_positions(statics.positions());
        for (i, k) in forms {
            let solved = statics.effect_dyn(k).expect("added above");
            self.effects[i]
                .absorb_static(solved, &self.state.x)
                .map_err(fail)?;
        }
        let after = self.internal_and_kinetic();
        self.work.loads += load_work;
        self.work.damping_work -= before - after + load_work;
        let report = outcome.map_err(|e| fail(e.to_string()))?;
        Ok((report, released))
    }

    /// Book what the next step would have booked of the step just taken
    /// (`dt`, s) with the velocities the release stops: the second half of
    /// the loads' work and of the damping's (the leapfrog books each step's
    /// work half at its end and half at the next step's).
    fn book_half_step(&mut self, dt: f64) {
        let hb = 0.5 * (self.dt_prev + dt);
        // The loads' half with the current velocities, as the leapfrog
        // books it; the damping's half `½ c h̄ Σ m v²` is `c h̄` times the
        // kinetic energy.
        let (_, loads) = self.load_work_halves(hb);
        let c = self
            .relaxation
            .as_ref()
            .map_or(self.settings.damping, |r| r.c);
        self.work.loads += loads;
        self.work.damping_work -= c * hb * self.kinetic_energy();
    }

    /// Move the nodes to `x`, at rest; the work of the nodal loads over the
    /// move (mJ = N·mm).
    fn take_positions(&mut self, x: &[crate::Vec3]) -> f64 {
        let mut work = 0.0;
        for l in &self.loads {
            let (i, d) = (l.node as usize, usize::from(l.dof));
            if d < 3 {
                let p = l.value * self.amp_values[l.amplitude as usize];
                work += p * (x[i][d] - self.state.x[i][d]);
            }
        }
        self.state.x.copy_from_slice(x);
        self.state
            .v
            .iter_mut()
            .for_each(|v| *v = crate::Vec3::zeros());
        self.state
            .w
            .iter_mut()
            .for_each(|w| *w = crate::Vec3::zeros());
        work
    }

    /// The effects' internal and hourglass energy plus the nodes' kinetic
    /// energy `½ m v²` of their half-step velocities (mJ; the leapfrog's
    /// own kinetic energy differs from it by terms of order `Δt`, so the
    /// booking is exact for a model at rest when the tools let go, and
    /// close for one that barely moves, as a formed part).
    fn internal_and_kinetic(&self) -> f64 {
        let kinetic = self.kinetic_energy();
        let stored: f64 = self
            .effects
            .iter()
            .map(|e| {
                let t = e.energies();
                t.internal + t.hourglass
            })
            .sum();
        kinetic + stored
    }

    /// `½ Σ (m v² + I w²)` of the half-step velocities (mJ).
    fn kinetic_energy(&self) -> f64 {
        let st = &self.state;
        (0..st.len())
            .map(|i| {
                let (v, w) = (st.v[i].norm_squared(), st.w[i].norm_squared());
                0.5 * (st.mass[i] * v + st.inertia[i] * w)
            })
            .sum()
    }
}

/// The Newton settings of the implicit release: the documented defaults
/// but for three, each measured on the square cup (2,500 shells, 15,300
/// equations) and the U-channel (1,210 shells, 7,623 equations).
///
/// - **Full steps** (`line_search_steps = 0`): the first step of an
///   increment stretches the shells' fibres to second order and raises
///   `|R|` for one iteration, which a line search on `|R|` rejects and then
///   crawls (the U-channel: 12 increments, 170 iterations, 3 cut-backs and
///   14.5 s with it; 7, 49, none and 3.3 s without).
/// - **The symmetric part of the tangent, by Cholesky** (`symmetrize`): the
///   shells' co-rotational tangent is not symmetric, and an LU of it costs
///   about 7× a Cholesky of its symmetric part (the cup: 0.23 s against
///   0.03 s), while Newton on the symmetric part converges in about
///   twice the iterations (the cup: 71 against 31).
/// - **The factor kept while it contracts `|R|` by half or better**
///   (`reuse_contraction = 0.5`): a new tangent costs an assembly with
///   derivatives and a factorisation, about eight times an iteration with
///   the factor in hand.
///
/// Together: the cup's release in 10 increments, 122 iterations and 9
/// factorisations, 1.5 s against 9.1 s with LU factorised every
/// iteration; the U-channel's in 1.2 s against 2.7 s. Every variant
/// converges to the same tolerances; the solutions differ by the path of
/// the increments through the plastic points (the cup's largest
/// springback displacement by 3e-5 mm, 1e-4 of it).
pub(crate) fn release_settings() -> NewtonSettings {
    NewtonSettings {
        line_search_steps: 0,
        symmetrize: true,
        reuse_contraction: 0.5,
        ..NewtonSettings::default()
    }
}
