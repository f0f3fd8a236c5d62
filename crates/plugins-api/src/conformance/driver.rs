//! Guarded calls into the law and formulation under test: panics and errors become readable failures.

use std::fmt;
use std::panic::{AssertUnwindSafe, catch_unwind};

use crate::kinematics::tangent_part;
use crate::return_mapping::{check_shear, explained, step};
use crate::{
    CriticalShear, FrictionError, FrictionLaw, KinematicFormulation, Mat3, PointNeeds, PointState,
    ShearInputs, StepInput, StepOutput, TangentMode,
};

/// Why a call into the law under test did not give a usable answer.
#[derive(Clone, Debug)]
pub(super) enum Failure {
    /// The return mapping (or the law through it) returned an error.
    Error(FrictionError),
    /// The law or formulation panicked; the panic message.
    Panic(String),
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Error(e) => write!(f, "error: {e}"),
            Self::Panic(m) => write!(f, "panicked: {m}"),
        }
    }
}

/// Run `f`, turning a panic into its message.
pub(super) fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        if let Some(s) = payload.downcast_ref::<&str>() {
            (*s).to_string()
        } else if let Some(s) = payload.downcast_ref::<String>() {
            s.clone()
        } else {
            "(panic payload is not a string)".to_string()
        }
    })
}

/// Put the engine's neutral values into every field that no active component
/// declared it reads (friction-math §6), as the engine does.
pub(super) fn neutralise(input: &mut StepInput, needs: PointNeeds) {
    if !needs.contains(PointNeeds::FLOW_STRESS) {
        input.flow_stress = f64::NAN;
    }
    if !needs.contains(PointNeeds::TEMPERATURE) {
        input.temperature = f64::NAN;
    }
    if !(needs.contains(PointNeeds::SPIN) || needs.contains(PointNeeds::VELOCITY_GRADIENT)) {
        input.kin.vel_grad = Mat3::zeros();
    }
    if !needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
        input.kin.f_old = Mat3::identity();
        input.kin.f_new = Mat3::identity();
    }
    if !needs.contains(PointNeeds::TOOL_ROTATION) {
        input.kin.tool_rotation = Mat3::identity();
    }
}

/// A law and a formulation, driven through the shared return mapping with the
/// consistent tangent, every call guarded.
#[derive(Clone, Copy)]
pub(super) struct Driver<'a> {
    /// The law under test.
    pub law: &'a dyn FrictionLaw,
    /// The formulation.
    pub form: &'a dyn KinematicFormulation,
    /// Union of what both read.
    pub needs: PointNeeds,
}

impl<'a> Driver<'a> {
    /// Pair a law with a formulation (`law_needs` fetched once, guarded, by the caller).
    pub fn new(
        law: &'a dyn FrictionLaw,
        law_needs: PointNeeds,
        form: &'a dyn KinematicFormulation,
    ) -> Self {
        Self {
            law,
            form,
            needs: law_needs.union(form.needs()),
        }
    }

    /// The input as the engine would pass it: undeclared data neutral.
    pub fn prepare(&self, input: &StepInput) -> StepInput {
        let mut x = *input;
        neutralise(&mut x, self.needs);
        x
    }

    /// One step of the return mapping; `input` is used as given (see [`Driver::prepare`]).
    pub fn step(&self, state: &mut PointState, input: &StepInput) -> Result<StepOutput, Failure> {
        match guarded(|| step(self.law, self.form, TangentMode::Consistent, state, input)) {
            Ok(Ok(out)) => Ok(out),
            Ok(Err(e)) => Err(Failure::Error(e)),
            Err(m) => Err(Failure::Panic(m)),
        }
    }

    /// `τ_c` of the law at the data of `input` and work `omega`, evaluated
    /// directly (not through the return mapping); non-finite or negative values
    /// are failures.
    pub fn critical_shear(&self, input: &StepInput, omega: f64) -> Result<CriticalShear, Failure> {
        let speed = if self.needs.contains(PointNeeds::SLIDING_VELOCITY) {
            let n = input.kin.n_new.normalize();
            tangent_part(&n, &input.du).norm() / input.kin.dt
        } else {
            f64::NAN
        };
        let x = ShearInputs {
            p: input.p,
            omega,
            sliding_speed: speed,
            flow_stress: input.flow_stress,
            temperature: input.temperature,
        };
        let cs = guarded(|| self.law.critical_shear(&x)).map_err(Failure::Panic)?;
        let name = || guarded(|| self.law.name().to_string()).unwrap_or_else(|_| "law".to_string());
        check_shear(cs, input.p, name)
            .map_err(|e| Failure::Error(guarded(|| explained(self.law, e.clone())).unwrap_or(e)))
    }
}

/// Whether every number of a step's output and the state after it is finite.
pub(super) fn all_finite(out: &StepOutput, state: &PointState) -> bool {
    out.t.iter().all(|v| v.is_finite())
        && out.tau_c.is_finite()
        && out.dgamma.is_finite()
        && out.slip.iter().all(|v| v.is_finite())
        && out.dissipation.is_finite()
        && out.tangent.iter().all(|v| v.is_finite())
        && out.dt_dp.iter().all(|v| v.is_finite())
        && state.t.iter().all(|v| v.is_finite())
        && state.p.is_finite()
        && state.omega.is_finite()
}

/// Every number of an output and state as bits, for bitwise comparisons.
pub(super) fn fingerprint(out: &StepOutput, state: &PointState, into: &mut Vec<u64>) {
    into.extend(out.t.iter().map(|v| v.to_bits()));
    into.extend([out.tau_c, out.dgamma, out.dissipation].map(f64::to_bits));
    into.extend([
        u64::from(out.open),
        u64::from(out.stick),
        u64::from(out.clamped),
    ]);
    into.extend(out.slip.iter().map(|v| v.to_bits()));
    into.extend(out.tangent.iter().map(|v| v.to_bits()));
    into.extend(out.dt_dp.iter().map(|v| v.to_bits()));
    into.extend(state.t.iter().map(|v| v.to_bits()));
    into.extend([state.p, state.omega].map(f64::to_bits));
}

/// Bits of a state, for "unchanged" comparisons.
pub(super) fn state_bits(state: &PointState) -> [u64; 5] {
    [state.t.x, state.t.y, state.t.z, state.p, state.omega].map(f64::to_bits)
}
