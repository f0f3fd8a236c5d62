//! The kinematic-formulation trait: history transport and slip direction (friction-math §4).

use crate::{Mat3, PointNeeds, Vec3};

/// Kinematics of one contact point over one step `n → n+1`.
///
/// Fields not declared by any active component ([`PointNeeds`]) hold neutral
/// values (identity matrices, zero vectors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepKinematics {
    /// Time step `Δt` (s), `> 0`.
    pub dt: f64,
    /// Unit tool normal at step `n` (towards the blank).
    pub n_old: Vec3,
    /// Unit tool normal at step `n+1`.
    pub n_new: Vec3,
    /// Rigid rotation of the tool over the step ([`PointNeeds::TOOL_ROTATION`]).
    pub tool_rotation: Mat3,
    /// Blank velocity gradient `L` at mid-step (1/s); its skew part is the spin
    /// `W` ([`PointNeeds::SPIN`] or [`PointNeeds::VELOCITY_GRADIENT`]).
    pub vel_grad: Mat3,
    /// Total deformation gradient of the blank at `n` ([`PointNeeds::DEFORMATION_GRADIENT`]).
    pub f_old: Mat3,
    /// Total deformation gradient of the blank at `n+1`.
    pub f_new: Mat3,
}

impl StepKinematics {
    /// A step over a fixed flat-or-curved tool with no blank deformation data.
    #[must_use]
    pub fn simple(dt: f64, n_old: Vec3, n_new: Vec3) -> Self {
        Self {
            dt,
            n_old,
            n_new,
            tool_rotation: Mat3::identity(),
            vel_grad: Mat3::zeros(),
            f_old: Mat3::identity(),
            f_new: Mat3::identity(),
        }
    }

    /// The blank spin `W = (L - Lᵀ)/2`.
    #[must_use]
    pub fn spin(&self) -> Mat3 {
        0.5 * (self.vel_grad - self.vel_grad.transpose())
    }
}

/// What a formulation sees when it chooses the slip direction `d` of a slipping step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionInputs<'a> {
    /// Step kinematics.
    pub kin: &'a StepKinematics,
    /// History traction `t_n` (tangent to `n_old`), MPa.
    pub t_old: Vec3,
    /// Pressure at step `n`, MPa.
    pub p_old: f64,
    /// History traction carried into step `n+1` by this formulation's
    /// transport and projected onto the new tangent plane: `t*` (MPa).
    pub t_star: Vec3,
    /// Trial traction `t_tr = t* - k_T Δu_T` (tangent to `n_new`), MPa; non-zero.
    pub t_trial: Vec3,
    /// End-of-step traction of the radial return with the start-of-step
    /// critical shear stress, `τ_c(p_{n+1}, ω_n) φ_tr` (MPa): the traction the
    /// step is heading to, without its `Δγ`-dependent correction.
    pub t_end: Vec3,
    /// Pressure at step `n+1`, MPa.
    pub p_new: f64,
}

/// A kinematic formulation (friction-math §4): decides (a) how the history
/// traction is carried into the new frame and (b) the slip direction.
pub trait KinematicFormulation: Send + Sync {
    /// Name as typed in scenes (`convective`, `jaumann`, …).
    fn name(&self) -> &str;

    /// Point data the formulation reads (§6).
    fn needs(&self) -> PointNeeds;

    /// (a) Carry `t_old` (tangent at `n_old`) into step `n+1`. The caller
    /// re-projects the result onto the tangent plane of `n_new`.
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3;

    /// (b) Unit slip direction `d` for `Δu_sl = -Δγ d`; `None` means backward
    /// Euler, `d = φ_tr`. The return mapping also falls back to `φ_tr` when the
    /// returned direction is not finite or lies 90° or more from `φ_tr`
    /// (reversal within one step), so that `ΔD ≥ 0` always.
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3>;

    /// Whether [`slip_direction`](Self::slip_direction) always returns `None`
    /// (backward Euler, `d = φ_tr`). Lets the return mapping take its
    /// branch-free path; the default `false` is always safe.
    fn backward_euler(&self) -> bool {
        false
    }
}

impl<T: KinematicFormulation + ?Sized> KinematicFormulation for Box<T> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn needs(&self) -> PointNeeds {
        (**self).needs()
    }
    #[inline]
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        (**self).transport(t_old, kin)
    }
    #[inline]
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        (**self).slip_direction(x)
    }
    fn backward_euler(&self) -> bool {
        (**self).backward_euler()
    }
}
