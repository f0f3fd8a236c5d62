//! `StaticSolver`: set-up (pattern, DOF numbering, symbolic analysis),
//! the state it holds and what it gives back.

use super::assembly::Sink;
use super::dof_map::DofMap;
use super::factor::Factorizer;
use super::{
    Assembly, NewtonSettings, Pattern, StaticProblem, StaticTangent, StaticTiming, StaticsError,
    SystemStats, TrialState,
};
use crate::{Dof, Mat3, Vec3};
use std::any::Any;
use std::time::Instant;

/// The static Newton solver: solves `F_int(u) = λ F_ext` (with prescribed
/// DOFs at `λ ū`) for `λ` from 0 to 1, see the [module docs](crate::statics).
///
/// Build it from a [`StaticProblem`] with [`StaticSolver::new`] (which
/// records the tangent's pattern and makes the symbolic factorisation),
/// then [`StaticSolver::solve`]. After an error the solver holds the last
/// converged increment.
pub struct StaticSolver {
    pub(super) settings: NewtonSettings,
    pub(super) effects: Vec<Box<dyn StaticTangent>>,
    pub(super) symmetric: bool,
    pub(super) x_start: Vec<Vec3>,
    pub(super) x_committed: Vec<Vec3>,
    pub(super) x: Vec<Vec3>,
    pub(super) rotation_committed: Vec<Mat3>,
    pub(super) dtheta: Vec<Vec3>,
    /// Load factor of the committed state.
    pub(super) lambda: f64,
    /// Load factor of the trial state.
    pub(super) lambda_trial: f64,
    /// Constrained global DOFs and their prescribed values at `λ = 1`.
    pub(super) constraints: Vec<(u32, f64)>,
    /// External loads at `λ = 1` per global DOF.
    pub(super) loads: Vec<f64>,
    pub(super) dofs: DofMap,
    pub(super) pattern: Pattern,
    /// `None` when every DOF is constrained or dropped.
    pub(super) factor: Option<Factorizer>,
    /// Internal forces at the trial state, per global DOF.
    pub(super) f_int: Vec<f64>,
    /// Internal forces at the committed state.
    pub(super) f_committed: Vec<f64>,
    /// Internal forces of the start state let go over the increments (a
    /// stress release), else zero: the balance sought at `λ` is
    /// `F_int = (1 − λ) f_start + λ F_ext`.
    pub(super) f_start: Vec<f64>,
    /// `‖F_start − F_ext‖` over the free translation and rotation DOFs: the
    /// force (N) and moment (N·mm) scale of a stress release, zero
    /// otherwise; a floor of the convergence references.
    pub(super) release_scale: [f64; 2],
    /// Tangent values on the pattern.
    pub(super) values: Vec<f64>,
    /// Residual on the equations.
    pub(super) r: Vec<f64>,
    /// Newton correction on the equations.
    pub(super) du: Vec<f64>,
    pub(super) x_base: Vec<Vec3>,
    pub(super) dtheta_base: Vec<Vec3>,
    /// Whether a tangent has been factorised (a singular first tangent is
    /// an error at once; a later one is cut back).
    pub(super) factored_once: bool,
    /// Whether the next iteration solves with the factor in hand
    /// ([`NewtonSettings::reuse_contraction`]): the values on the pattern
    /// are then still the ones it factorised.
    pub(super) keep_factor: bool,
    /// Whether this attempt factorises the exact tangent although
    /// [`NewtonSettings::symmetrize`] is set: the retry of an increment
    /// that the symmetric part failed.
    pub(super) exact_tangent: bool,
    pub(super) timing: StaticTiming,
    pub(super) stats: SystemStats,
}

impl StaticSolver {
    /// Set up the solve: validate `settings`, record every effect's tangent
    /// pattern at the start state, number the DOFs (dropping those no
    /// effect stiffens) and make the symbolic factorisation.
    ///
    /// # Errors
    /// Invalid settings, an effect failing at the start state or breaking
    /// the assembly contract, a load on a DOF no effect stiffens.
    pub fn new(problem: StaticProblem, settings: NewtonSettings) -> Result<Self, StaticsError> {
        let t = Instant::now();
        settings.validate()?;
        let StaticProblem {
            x_start,
            mut effects,
            prescribed,
            loads,
            release,
        } = problem;
        let n_dofs = 6 * x_start.len();
        let (entries, segments, f_at_start) = record_pattern(&mut effects, &x_start)?;
        let f_start = if release {
            f_at_start
        } else {
            vec![0.0; n_dofs]
        };
        let constrained: Vec<bool> = prescribed.iter().map(Option::is_some).collect();
        let dofs = DofMap::new(n_dofs, &entries, &constrained);
        check_held_loads(&loads, &dofs, &constrained)?;
        let pattern = Pattern::new(&entries, segments, &dofs);
        let factor = match dofs.len() {
            0 => None,
            _ => Some(
                Factorizer::new(&pattern, settings.pivot_tolerance)
                    .map_err(StaticsError::Factorisation)?,
            ),
        };
        let n = x_start.len();
        let n_eq = dofs.len();
        let stats = SystemStats {
            equations: n_eq,
            constrained: constrained.iter().filter(|&&c| c).count(),
            dropped: (0..n_dofs)
                .filter(|&g| !dofs.stiffened[g] && !constrained[g])
                .count(),
            matrix_nnz: pattern.nnz(),
            factor_nnz: factor.as_ref().map_or(0, Factorizer::factor_nnz),
            factor_bytes: factor.as_ref().map_or(0, Factorizer::factor_bytes),
            ..Default::default()
        };
        let mut solver = Self {
            settings,
            symmetric: effects.iter().all(|e| e.symmetric_tangent()),
            effects,
            x_committed: x_start.clone(),
            x: x_start.clone(),
            x_base: x_start.clone(),
            x_start,
            rotation_committed: vec![Mat3::identity(); n],
            dtheta: vec![Vec3::zeros(); n],
            dtheta_base: vec![Vec3::zeros(); n],
            lambda: 0.0,
            lambda_trial: 0.0,
            constraints: (0..n_dofs)
                .filter_map(|g| prescribed[g].map(|v| (g as u32, v)))
                .collect(),
            loads,
            values: vec![0.0; pattern.nnz()],
            exact_tangent: false,
            pattern,
            factor,
            f_int: vec![0.0; n_dofs],
            f_committed: vec![0.0; n_dofs],
            f_start,
            release_scale: [0.0; 2],
            r: vec![0.0; n_eq],
            du: vec![0.0; n_eq],
            dofs,
            factored_once: false,
            keep_factor: false,
            timing: StaticTiming::default(),
            stats,
        };
        solver.release_scale = solver.release_norms();
        solver.timing.symbolic = solver.factor.as_ref().map_or(0.0, |f| f.tally.symbolic);
        solver.timing.total = t.elapsed().as_secs_f64();
        Ok(solver)
    }

    /// Load factor of the converged state (0 before the first increment).
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// Positions of the converged state (mm).
    pub fn positions(&self) -> &[Vec3] {
        &self.x_committed
    }

    /// Displacement of `node` from the start of the solve (mm).
    pub fn displacement(&self, node: usize) -> Vec3 {
        self.x_committed[node] - self.x_start[node]
    }

    /// Rotation of `node` from the start of the solve to the converged state.
    pub fn rotation(&self, node: usize) -> Mat3 {
        self.rotation_committed[node]
    }

    /// Internal force (N or N·mm) of `dof` at `node` in the converged state.
    pub fn internal_force(&self, node: usize, dof: Dof) -> f64 {
        self.f_committed[6 * node + dof.index()]
    }

    /// `F_int − (1 − λ) F_start − λ F_ext` of `dof` at `node` in the
    /// converged state (`F_start` zero unless the solve is a stress
    /// release): on a
    /// constrained DOF the reaction, the force (N) or moment (N·mm) the
    /// constraint applies to the node; on a free DOF the residual.
    pub fn reaction(&self, node: usize, dof: Dof) -> f64 {
        let g = 6 * node + dof.index();
        self.f_committed[g] - self.target(g, self.lambda)
    }

    /// The force `(1 − λ) F_start + λ F_ext` the internal force of global
    /// DOF `g` balances at load factor `lambda`.
    pub(super) fn target(&self, g: usize, lambda: f64) -> f64 {
        (1.0 - lambda) * self.f_start[g] + lambda * self.loads[g]
    }

    /// The out-of-balance force a stress release lets go, `‖F_int(x_start)
    /// − F_ext‖` over the free translation DOFs (N); 0 unless the solve is a
    /// release ([`StaticProblem::release_start_forces`]).
    pub fn release_residual(&self) -> f64 {
        self.release_scale[0]
    }

    /// `‖F_start − F_ext‖` over the free translations and rotations (zero
    /// unless the solve is a stress release).
    fn release_norms(&self) -> [f64; 2] {
        if self.f_start.iter().all(|f| *f == 0.0) {
            return [0.0; 2];
        }
        let mut r2 = [0.0; 2];
        for (&g, &rotation) in self.dofs.global.iter().zip(&self.dofs.is_rotation) {
            let d = self.f_start[g as usize] - self.loads[g as usize];
            r2[usize::from(rotation)] += d * d;
        }
        r2.map(f64::sqrt)
    }

    /// The effect with index `index`, as the static solver holds it.
    pub fn effect_dyn(&self, index: usize) -> Option<&dyn StaticTangent> {
        self.effects.get(index).map(AsRef::as_ref)
    }

    /// The settings.
    pub fn settings(&self) -> &NewtonSettings {
        &self.settings
    }

    /// Seconds spent since set-up began, by task (errors included).
    pub fn timing(&self) -> StaticTiming {
        self.timing
    }

    /// Sizes of the linear systems and factorisations made so far.
    pub fn system(&self) -> SystemStats {
        let mut s = self.stats;
        if let Some(f) = &self.factor {
            (s.llt, s.ldlt, s.lu) = (f.tally.llt, f.tally.ldlt, f.tally.lu);
        }
        s
    }

    /// The effect with index `index` (as returned by
    /// [`StaticProblem::add_effect`]) as its concrete type.
    pub fn effect<E: StaticTangent>(&self, index: usize) -> Option<&E> {
        let e: &dyn Any = self.effects.get(index)?.as_ref();
        e.downcast_ref::<E>()
    }
}

/// Entries (row, column, value) recorded from every effect at the start
/// state, each effect's range among them, and the internal forces there.
type Recorded = (Vec<(u32, u32, f64)>, Vec<std::ops::Range<usize>>, Vec<f64>);

fn record_pattern(
    effects: &mut [Box<dyn StaticTangent>],
    x_start: &[Vec3],
) -> Result<Recorded, StaticsError> {
    let n = x_start.len();
    let (rotations, dtheta) = (vec![Mat3::identity(); n], vec![Vec3::zeros(); n]);
    let state = TrialState {
        x_start,
        x_committed: x_start,
        x: x_start,
        rotation_committed: &rotations,
        dtheta: &dtheta,
        lambda: 0.0,
    };
    let mut f = vec![0.0; 6 * n];
    let mut entries = Vec::new();
    let mut segments = Vec::with_capacity(effects.len());
    for effect in effects.iter_mut() {
        let start = entries.len();
        let mut out = Assembly::new(&mut f, Sink::Record(&mut entries));
        effect.internal_forces(&state, &mut out)?;
        out.finish().map_err(|message| StaticsError::Assembly {
            effect: effect.name().to_string(),
            message,
        })?;
        effect.revert();
        segments.push(start..entries.len());
    }
    Ok((entries, segments, f))
}

fn check_held_loads(
    loads: &[f64],
    dofs: &DofMap,
    constrained: &[bool],
) -> Result<(), StaticsError> {
    let unheld = |g: &usize| loads[*g] != 0.0 && !dofs.stiffened[*g] && !constrained[*g];
    let count = (0..loads.len()).filter(unheld).count();
    match (0..loads.len()).find(unheld) {
        None => Ok(()),
        Some(g) => Err(StaticsError::UnheldLoad {
            node: g / 6,
            dof: Dof::ALL[g % 6],
            value: loads[g],
            count,
        }),
    }
}
