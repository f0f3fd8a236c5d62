//! Dynamic relaxation of a springback step: the blank let go by the tools
//! comes to rest at its static springback shape under adaptive viscous
//! damping.
//!
//! When the press enters a springback step ([`crate::StepEnd::Settled`]) the
//! solver fixes a minimal set of translational DOFs that removes the blank's
//! free rigid-body modes (the 3-2-1 rule of [`crate::rigid_modes`], the
//! scene's symmetry conditions kept) and damps every node with the
//! mass-proportional coefficient `c = 2 ω`, where `ω² = Δxᵀ K Δx / Δxᵀ M Δx`
//! is the Rayleigh quotient of the step's own motion, with
//! `K Δx ≈ −(f_{n+1} − f_n)` (Underwood's adaptive dynamic relaxation:
//! P. Underwood, "Dynamic relaxation", in Belytschko & Hughes (eds.),
//! *Computational Methods for Transient Analysis*, 1983, ch. 5). Critical
//! damping of the mode that dominates the motion makes it decay in about one
//! of its periods; the coefficient is capped at `c Δt = 1`. The damping
//! work goes to the energy ledger's damping term like any damping.
//!
//! The step ends when the out-of-balance force of the free DOFs (the
//! translational forces, Euclidean norm) has fallen to `tolerance` times its
//! value in the first step after the tools let go.

use crate::rigid_modes::{RigidMode, remove_rigid_motion};
use crate::{Dof, Vec3};

/// The state of a running springback step.
#[derive(Debug, Clone)]
pub(crate) struct Relaxation {
    /// Damping coefficient of the step about to be taken (1/s).
    pub(crate) c: f64,
    /// Out-of-balance force when the tools let go (N); 0 until measured.
    pub(crate) f_ref: f64,
    /// Residual ratio at which the blank is at rest.
    pub(crate) tolerance: f64,
    /// Forces and moments at `t_n`, for the Rayleigh quotient.
    pub(crate) f_prev: Vec<Vec3>,
    /// See `f_prev`.
    pub(crate) m_prev: Vec<Vec3>,
    /// What the step reports.
    pub(crate) report: SpringbackReport,
    /// An implicit springback whose static solve is still to come (once
    /// the forces of the step the tools let go in are known).
    pub(crate) implicit_pending: bool,
}

/// What a springback step did: the constraints it added, its cost and how
/// far it came to rest.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpringbackReport {
    /// The rigid-body modes the scene's own conditions left free when the
    /// tools let go.
    pub free_modes: Vec<RigidMode>,
    /// The DOFs it fixed to remove them (node, DOF).
    pub fixed: Vec<(u32, Dof)>,
    /// Nodal positions when the tools let go (mm).
    pub x_release: Vec<Vec3>,
    /// Time when the tools let go (s).
    pub t_release: f64,
    /// Explicit steps taken in the springback step.
    pub steps: u64,
    /// Out-of-balance force when the tools let go (N).
    pub residual_start: f64,
    /// Out-of-balance force at the end (N).
    pub residual: f64,
    /// The last damping coefficient (1/s): `c/2` estimates the circular
    /// frequency of the mode that came to rest last.
    pub damping: f64,
    /// Whether the residual reached the tolerance (else the step ran to its
    /// maximum duration).
    pub settled: bool,
    /// The static solve of an implicit springback
    /// ([`crate::ReleaseMethod::Implicit`]), before the explicit steps that
    /// confirm its rest.
    pub implicit: Option<crate::statics::SolveReport>,
}

impl SpringbackReport {
    /// The springback displacement at the positions `x` (mm): the motion
    /// since the tools let go less its least-squares fit by the free modes,
    /// so that it does not depend on the DOFs fixed to remove them.
    pub fn displacement(&self, x: &[Vec3]) -> Vec<Vec3> {
        let mut d: Vec<Vec3> = x.iter().zip(&self.x_release).map(|(a, b)| a - b).collect();
        // The modes and positions were checked when the tools let go; a field
        // that cannot be fitted (non-finite) is left as it is.
        let _ = remove_rigid_motion(&self.x_release, &mut d, &self.free_modes);
        d
    }
}

impl Relaxation {
    /// A relaxation starting at `time` from the positions `x`, with the
    /// free modes `free_modes` removed by the constraints `fixed`.
    pub(crate) fn new(
        tolerance: f64,
        time: f64,
        x: &[Vec3],
        (free_modes, fixed): (Vec<RigidMode>, Vec<(u32, Dof)>),
    ) -> Self {
        let n = x.len();
        Self {
            c: 0.0,
            f_ref: 0.0,
            tolerance,
            f_prev: vec![Vec3::zeros(); n],
            m_prev: vec![Vec3::zeros(); n],
            report: SpringbackReport {
                free_modes,
                fixed,
                x_release: x.to_vec(),
                t_release: time,
                ..SpringbackReport::default()
            },
            implicit_pending: false,
        }
    }

    /// After an implicit release: the out-of-balance force let go (N), the
    /// reference of the rest tolerance, and the static solve's report.
    pub(crate) fn preset(&mut self, released: f64, implicit: crate::statics::SolveReport) {
        self.f_ref = released;
        self.report.residual_start = released;
        self.report.implicit = Some(implicit);
        self.implicit_pending = false;
    }

    /// Keep the forces at `t_n` before the solver computes those at `t_{n+1}`.
    pub(crate) fn keep_forces(&mut self, f: &[Vec3], m: &[Vec3]) {
        self.f_prev.copy_from_slice(f);
        self.m_prev.copy_from_slice(m);
    }

    /// After the forces at `t_{n+1}`: the damping for the next step from the
    /// Rayleigh quotient of the step's motion (`v`, `w` over `dt`), and
    /// whether the blank is at rest. `constrained` masks the DOFs whose
    /// force is a reaction, not a residual.
    pub(crate) fn update(
        &mut self,
        motion: (&[Vec3], &[Vec3]),
        inertia: (&[f64], &[f64]),
        forces: (&[Vec3], &[Vec3]),
        constrained: &[u8],
        dt: f64,
    ) -> bool {
        let ((v, w), (mass, rot), (f, m)) = (motion, inertia, forces);
        let (mut num, mut den, mut r2) = (0.0, 0.0, 0.0);
        for i in 0..v.len() {
            let free = |d: usize| constrained[i] & (1 << d) == 0;
            let (dx, dth) = (v[i] * dt, w[i] * dt);
            num -= dx.dot(&(f[i] - self.f_prev[i])) + dth.dot(&(m[i] - self.m_prev[i]));
            den += mass[i] * dx.norm_squared() + rot[i] * dth.norm_squared();
            for (d, fd) in f[i].iter().enumerate() {
                if free(d) {
                    r2 += fd * fd;
                }
            }
        }
        if den > 0.0 && num > 0.0 {
            self.c = (2.0 * (num / den).sqrt()).min(1.0 / dt);
        }
        let residual = r2.sqrt();
        self.report.steps += 1;
        self.report.residual = residual;
        self.report.damping = self.c;
        if self.f_ref == 0.0 {
            self.f_ref = residual;
            self.report.residual_start = residual;
        }
        let settled = self.report.steps >= 10 && residual <= self.tolerance * self.f_ref;
        self.report.settled = settled;
        settled
    }
}
