//! The friction-law trait: a critical shear stress `τ_c(p, ω, ctx)` and its derivatives.

use crate::{FrictionError, ParamSpec, PointNeeds};

/// Everything a law may read at a point when it evaluates `τ_c`.
///
/// Quantities that no active component declared in [`FrictionLaw::needs`] are
/// not computed by the engine and hold `f64::NAN`; a law must not read them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShearInputs {
    /// Contact pressure `p ≥ 0` (MPa).
    pub p: f64,
    /// Frictional work density `ω ≥ 0` (N/mm = MPa·mm), the running sum of `ΔD`.
    pub omega: f64,
    /// Sliding speed `|Δu_T|/Δt` (mm/s), if [`PointNeeds::SLIDING_VELOCITY`].
    pub sliding_speed: f64,
    /// Blank flow stress at the point (MPa), if [`PointNeeds::FLOW_STRESS`].
    pub flow_stress: f64,
    /// Temperature (K), if [`PointNeeds::TEMPERATURE`].
    pub temperature: f64,
}

/// `τ_c` and its partial derivatives at one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CriticalShear {
    /// Critical shear stress `τ_c ≥ 0` (MPa).
    pub tau: f64,
    /// `∂τ_c/∂p` (-).
    pub dtau_dp: f64,
    /// `∂τ_c/∂ω` (1/mm). Must be 0 unless [`FrictionLaw::work_dependent`].
    pub dtau_domega: f64,
    /// `∂τ_c/∂|v|` (MPa·s/mm). Must be 0 unless the law needs the sliding velocity.
    pub dtau_dspeed: f64,
    /// Whether a lower clamp of the law is active (e.g. WH's `μ_min`): reported
    /// to the user, never silent.
    pub clamped: bool,
}

/// An isotropic friction law (docs/friction-math.md §3): slip function
/// `Φ = |t| - τ_c(p, ω, ctx)`; the return mapping is shared (§2).
///
/// Implementations are plain structs holding their parameters; they are
/// immutable during a run (per-point state lives in the engine).
pub trait FrictionLaw: Send + Sync {
    /// Name as typed in scenes (`ac`, `wvs`, …).
    fn name(&self) -> &str;

    /// Tangential stiffness in stick `k_T` (MPa/mm), a regularisation.
    fn stick_stiffness(&self) -> f64;

    /// Point data the law reads beyond `p` and `ω` (§6).
    fn needs(&self) -> PointNeeds {
        PointNeeds::NONE
    }

    /// Whether `τ_c` depends on the frictional work `ω`; if so the return
    /// mapping solves the backward-Euler equation of §3 (WH) by a bracketed
    /// Newton iteration instead of the closed-form radial return.
    fn work_dependent(&self) -> bool {
        false
    }

    /// `τ_c` and its derivatives. Must be finite and `τ_c ≥ 0` for every
    /// `p ≥ 0`, `ω ≥ 0` and finite declared inputs.
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear;

    /// Why the last [`Self::critical_shear`] call of this law on the calling
    /// thread gave no valid answer, when the law knows better than its numbers
    /// (a plugin that panicked: [`FrictionError::PluginPanicked`]); taken, so a
    /// second call returns `None`. The return mapping reports it instead of a
    /// non-finite result. Laws that compute their answer themselves keep the
    /// default, `None`.
    fn take_failure(&self) -> Option<FrictionError> {
        None
    }
}

impl<T: FrictionLaw + ?Sized> FrictionLaw for Box<T> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn stick_stiffness(&self) -> f64 {
        (**self).stick_stiffness()
    }
    fn needs(&self) -> PointNeeds {
        (**self).needs()
    }
    fn work_dependent(&self) -> bool {
        (**self).work_dependent()
    }
    #[inline]
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        (**self).critical_shear(x)
    }
    fn take_failure(&self) -> Option<FrictionError> {
        (**self).take_failure()
    }
}

/// Static description of a law, for registries, the CLI and plugin tables.
#[derive(Clone, Copy, Debug)]
pub struct LawDescription {
    /// Name as typed in scenes.
    pub name: &'static str,
    /// One-line summary with the formula.
    pub summary: &'static str,
    /// Parameter schema, in the order the builder receives the values.
    pub params: &'static [ParamSpec],
}
