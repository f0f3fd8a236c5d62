//! The explicit-dynamics batch kernel behind [`PairedIntegrator::step_batch`]
//! under [`TangentMode::None`](super::TangentMode::None).
//!
//! It runs, point by point, the one return of [`step_into`] (the same
//! validation `input_ok`, the same trial and the same `conclude`, so its
//! results are the same bits), organised for the common case that nothing is
//! wrong:
//!
//! - The law's and formulation's properties (`needs`, `k_T`, work dependence,
//!   backward Euler) are read once per batch, not once per point.
//! - Failures are not worded here: anything unusual — open contact
//!   (`p = 0`), an input `input_ok` refuses, a non-finite transported history
//!   or a trial traction whose square norm overflows, a law answer out of
//!   contract, a failed backward-Euler solve — hands the point, its state
//!   untouched, to [`step_into`], which produces the documented answer or
//!   the error.
//!
//! [`PairedIntegrator::step_batch`]: super::PairedIntegrator

use super::{
    Pairing, PointState, StepInput, StepOutput, TangentMode, Trial, conclude, input_ok,
    nonfinite_bits, step_into,
};
use crate::{CriticalShear, FrictionError, FrictionLaw, KinematicFormulation};

/// A law's answer within its contract (`check_shear` accepts it): `τ_c` in
/// `[+0, ∞)` is its bit pattern below that of `+∞` (a `-0.0`, which the
/// contract allows, is left to the general path), the derivatives finite.
#[inline(always)]
fn shear_ok(cs: &CriticalShear) -> bool {
    cs.tau.to_bits() < f64::INFINITY.to_bits()
        && nonfinite_bits([cs.dtau_dp, cs.dtau_domega, cs.dtau_dspeed]) >> 63 == 0
}

/// Integrate every point of the batch without tangents; see the module docs.
///
/// # Errors
/// The first point's error (as [`step_into`]), the points before it updated.
pub(super) fn explicit_batch<L, F>(
    law: &L,
    formulation: &F,
    states: &mut [PointState],
    inputs: &[StepInput],
    outputs: &mut [StepOutput],
) -> Result<(), FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    let pairing = Pairing::new(law, formulation);
    for ((state, input), out) in states.iter_mut().zip(inputs).zip(outputs.iter_mut()) {
        if !explicit_point(&pairing, state, input, out) {
            general_point(law, formulation, state, input, out)?;
        }
    }
    Ok(())
}

/// A point the kernel hands over: [`step_into`], out of line.
#[cold]
#[inline(never)]
fn general_point<L, F>(
    law: &L,
    formulation: &F,
    state: &mut PointState,
    input: &StepInput,
    out: &mut StepOutput,
) -> Result<(), FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    step_into(law, formulation, TangentMode::None, state, input, out)
}

/// One point through the one return of [`step_into`] (its trial and
/// `conclude`); `false`, with the state untouched, hands it to
/// [`step_into`] itself.
#[inline(always)]
fn explicit_point<L, F>(
    pairing: &Pairing<'_, L, F>,
    state: &mut PointState,
    input: &StepInput,
    out: &mut StepOutput,
) -> bool
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    // `p > 0`: open contact (and every refused input) goes the general way.
    if !(input.p != 0.0 && input_ok(input, pairing.needs)) {
        return false;
    }
    let trial = Trial::new(pairing, state, input);
    // Finite only if `t*` is (a difference with an infinite or NaN operand is
    // not finite) and the square norm does not overflow.
    if !trial.norm2_tr.is_finite() {
        return false;
    }
    let cs = pairing.law.critical_shear(&trial.x);
    if !shear_ok(&cs) {
        return false;
    }
    conclude(pairing, TangentMode::None, state, input, &trial, cs, out)
        .map_err(discard)
        .is_ok()
}

/// Drop an error out of line: the general path words it again, and the hot
/// path keeps no drop of a `Result<(), FrictionError>` per point.
#[cold]
#[inline(never)]
fn discard(_: FrictionError) {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::{forward_direction, rotate_minimal};
    use crate::{DirectionInputs, StepKinematics};
    use crate::{PointNeeds, ShearInputs, Vec3};
    use rand::{Rng, SeedableRng};

    /// `τ_c = μ(ω) p` with `μ = max(0.15 - 2e-4 ω, 0.05)` (clamp reported), read
    /// through a trait object as a dynamically loaded plugin law would be.
    struct Softening;
    impl FrictionLaw for Softening {
        fn name(&self) -> &str {
            "softening"
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn needs(&self) -> PointNeeds {
            PointNeeds::SLIDING_VELOCITY
        }
        fn work_dependent(&self) -> bool {
            true
        }
        fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
            let mu = 0.15 - 2e-4 * x.omega;
            if mu < 0.05 {
                CriticalShear {
                    tau: 0.05 * x.p,
                    dtau_dp: 0.05,
                    clamped: true,
                    ..CriticalShear::default()
                }
            } else {
                CriticalShear {
                    tau: mu * x.p,
                    dtau_dp: mu,
                    dtau_domega: -2e-4 * x.p,
                    ..CriticalShear::default()
                }
            }
        }
    }

    /// Coulomb with `μ = 0.144`, except that it answers `τ_c = -0.0` (allowed)
    /// for `p > 90` and NaN (refused) for `p` in `(80, 80.5)`.
    struct Quirky;
    impl FrictionLaw for Quirky {
        fn name(&self) -> &str {
            "quirky"
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
            let tau = if x.p > 90.0 {
                -0.0
            } else if x.p > 80.0 && x.p < 80.5 {
                f64::NAN
            } else {
                0.144 * x.p
            };
            CriticalShear {
                tau,
                dtau_dp: 0.144,
                ..CriticalShear::default()
            }
        }
    }

    /// Minimal-rotation transport with the tool's rotation; forward slip
    /// direction (or backward Euler when `euler`).
    struct Carried {
        euler: bool,
    }
    impl KinematicFormulation for Carried {
        fn name(&self) -> &str {
            "carried"
        }
        fn needs(&self) -> PointNeeds {
            PointNeeds::TOOL_ROTATION
        }
        fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
            let r = &kin.tool_rotation;
            rotate_minimal(&(r * kin.n_old), &kin.n_new, &(r * t_old))
        }
        fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
            if self.euler {
                None
            } else {
                forward_direction(&x.t_star, &x.t_end, &x.kin.n_new)
            }
        }
        fn backward_euler(&self) -> bool {
            self.euler
        }
    }

    fn bits(o: &StepOutput, s: &PointState) -> Vec<u64> {
        let mut v: Vec<u64> =
            o.t.iter()
                .chain(o.slip.iter())
                .chain(o.dt_dp.iter())
                .chain(o.tangent.iter())
                .chain(s.t.iter())
                .map(|x| x.to_bits())
                .collect();
        v.extend([o.tau_c, o.dgamma, o.dissipation, s.p, s.omega].map(f64::to_bits));
        v.extend([o.open, o.stick, o.clamped].map(u64::from));
        v
    }

    /// Random steps over a slowly turning tool normal; 1 in 10 points open,
    /// 1 in 10 on a rotated tool.
    fn history(seed: u64, points: usize, steps: usize) -> Vec<Vec<StepInput>> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut normals = vec![Vec3::z(); points];
        (0..steps)
            .map(|_| {
                normals
                    .iter_mut()
                    .map(|n| {
                        let n_new = (*n
                            + Vec3::new(
                                rng.random_range(-0.01..0.01),
                                rng.random_range(-0.01..0.01),
                                0.0,
                            ))
                        .normalize();
                        let du = Vec3::new(
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1.0..1.0),
                            0.0,
                        ) * 10f64.powf(rng.random_range(-7.0..-3.0));
                        let mut kin = StepKinematics::simple(1e-6, *n, n_new);
                        if rng.random_bool(0.1) {
                            kin.tool_rotation = crate::kinematics::cayley(
                                &crate::kinematics::skew(&Vec3::new(1e-3, -2e-3, 5e-4)),
                            );
                        }
                        *n = n_new;
                        let p = if rng.random_bool(0.1) {
                            0.0
                        } else {
                            rng.random_range(0.0..100.0)
                        };
                        StepInput::new(p, du, kin)
                    })
                    .collect()
            })
            .collect()
    }

    /// Run `history` through the kernel and through `step` point by point;
    /// compare every bit, or the first error.
    fn compare<L, F>(law: &L, formulation: &F, seed: u64) -> (usize, usize)
    where
        L: FrictionLaw + ?Sized,
        F: KinematicFormulation + ?Sized,
    {
        let points = 64;
        let mut batch_states = vec![PointState::default(); points];
        let mut point_states = vec![PointState::default(); points];
        let mut outputs = vec![StepOutput::default(); points];
        let (mut slips, mut errors) = (0, 0);
        for inputs in history(seed, points, 60) {
            let got = explicit_batch(law, formulation, &mut batch_states, &inputs, &mut outputs);
            let mut first_error = None;
            for (i, input) in inputs.iter().enumerate() {
                match super::super::step(
                    law,
                    formulation,
                    TangentMode::None,
                    &mut point_states[i],
                    input,
                ) {
                    Ok(reference) => {
                        assert_eq!(
                            bits(&outputs[i], &batch_states[i]),
                            bits(&reference, &point_states[i]),
                            "point {i}"
                        );
                        slips += usize::from(!reference.stick && !reference.open);
                    }
                    Err(e) => {
                        first_error = Some(e);
                        break;
                    }
                }
            }
            match (got, first_error) {
                (Ok(()), None) => {}
                (Err(a), Some(b)) => {
                    // Compared as text: a NaN value makes `==` false.
                    assert_eq!(a.to_string(), b.to_string());
                    errors += 1;
                    // Carry on from equal states.
                    point_states.copy_from_slice(&batch_states);
                }
                (a, b) => panic!("batch {a:?}, reference {b:?}"),
            }
        }
        (slips, errors)
    }

    /// The kernel gives the bits of `step` for a work-dependent plugin-style law behind a
    /// trait object, backward-Euler and forward slip directions, open contact,
    /// rotating tools. Source: `step` itself; tolerance: none.
    #[test]
    fn kernel_equals_point_path_bitwise_for_work_dependent_trait_object_law() {
        let law: &dyn FrictionLaw = &Softening;
        for euler in [true, false] {
            let formulation = Carried { euler };
            let (slips, errors) = compare(law, &formulation, 1);
            assert!(slips > 500 && errors == 0, "{slips} slips, {errors} errors");
        }
    }

    /// A law answering `τ_c = -0.0` (allowed: handed to the general path) or
    /// NaN (refused): the batch gives the bits of `step`, and for NaN the same
    /// error as the first failing point of `step`.
    #[test]
    fn kernel_hands_negative_zero_and_nan_shear_to_the_general_path() {
        for euler in [true, false] {
            let (slips, errors) = compare(&Quirky, &Carried { euler }, 2);
            assert!(slips > 500 && errors > 0, "{slips} slips, {errors} errors");
        }
    }
}
