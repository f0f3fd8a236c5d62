//! The explicit batch path (`PointIntegrator::step_batch` without tangents)
//! against the point-by-point reference (`PointIntegrator::step`, i.e.
//! `plugins_api::return_mapping::step`) for every built-in law × formulation.
//!
//! Source of the expected values: the reference path itself, run on the same
//! inputs and states. Tolerance: none — the batch kernel performs the same
//! floating-point operations, so every output field and every state must be
//! equal bit for bit (checked on `f64::to_bits`).

use friction_laws::builtin::{self, FORMULATION_NAMES, LAW_NAMES};
use plugins_api::kinematics::{cayley, skew};
use plugins_api::{
    FrictionError, Mat3, PointIntegrator, PointState, StepInput, StepKinematics, StepOutput,
    TangentMode, Vec3,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Every bit of an output, in a fixed order.
fn output_bits(o: &StepOutput) -> Vec<u64> {
    let mut bits: Vec<u64> =
        o.t.iter()
            .chain(o.slip.iter())
            .chain(o.dt_dp.iter())
            .chain(o.tangent.iter())
            .map(|x| x.to_bits())
            .collect();
    bits.extend([o.tau_c, o.dgamma, o.dissipation].map(f64::to_bits));
    bits.extend([o.open, o.stick, o.clamped].map(u64::from));
    bits
}

/// Every bit of a state.
fn state_bits(s: &PointState) -> [u64; 5] {
    [s.t.x, s.t.y, s.t.z, s.p, s.omega].map(f64::to_bits)
}

/// A random step at one point: curved, sometimes rotating tool; stick and
/// slip; spin and deformation; and, now and then, the cases the batch kernel
/// hands to the general path (open contact, normals at the edge of the unit
/// tolerance, a slip increment so large that `|t_tr|²` overflows).
fn random_input(rng: &mut ChaCha8Rng, n_old: Vec3) -> StepInput {
    let n_new = (n_old
        + Vec3::new(
            rng.random_range(-1e-3..1e-3),
            rng.random_range(-1e-3..1e-3),
            0.0,
        ))
    .normalize();
    let dir = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    let mut du = (dir - n_new * n_new.dot(&dir)) * 10f64.powf(rng.random_range(-6.5..-3.0));
    let dt = 1e-6;
    let l = Mat3::from_fn(|_, _| rng.random_range(-50.0..50.0));
    let f_old = Mat3::identity() + Mat3::from_fn(|_, _| rng.random_range(-0.05..0.05));
    let mut kin = StepKinematics {
        dt,
        n_old,
        n_new,
        tool_rotation: Mat3::identity(),
        vel_grad: l,
        f_old,
        f_new: cayley(&(l * dt)) * f_old,
    };
    let mut p = rng.random_range(1.0..100.0);
    match rng.random_range(0..40) {
        0 => p = 0.0,
        1 => {
            // A rotating tool (the normals rotate with it).
            let r = cayley(&skew(&Vec3::new(
                rng.random_range(-1e-3..1e-3),
                rng.random_range(-1e-3..1e-3),
                rng.random_range(-1e-3..1e-3),
            )));
            kin.tool_rotation = r;
            kin.n_new = r * n_old;
        }
        // |n| = 1 + 9.9e-7: accepted by the input check, refused by the
        // kernel's tighter fast test.
        2 => kin.n_new *= 1.0 + 9.9e-7,
        // |t_tr|² overflows: the general path's answer for huge slip.
        3 => du *= 1e300,
        _ => {}
    }
    let mut input = StepInput::new(p, du, kin);
    input.flow_stress = rng.random_range(250.0..450.0);
    input
}

fn integrator(law: &str, formulation: &str) -> Box<dyn PointIntegrator> {
    builtin::integrator(
        law,
        &builtin::benchmark_params(law),
        formulation,
        TangentMode::None,
    )
    .expect("benchmark parameters are valid")
}

/// Run `steps` steps at `points` points through both paths; assert equal bits.
fn compare(law: &str, formulation: &str, points: usize, steps: usize, seed: u64) {
    let integrator = integrator(law, formulation);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut normals: Vec<Vec3> = (0..points)
        .map(|_| {
            Vec3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                1.0,
            )
            .normalize()
        })
        .collect();
    let mut batch_states = vec![PointState::default(); points];
    let mut point_states = vec![PointState::default(); points];
    let mut outputs = vec![StepOutput::default(); points];
    let (mut sticks, mut slips, mut opens) = (0, 0, 0);
    for step in 0..steps {
        let inputs: Vec<StepInput> = normals.iter().map(|&n| random_input(&mut rng, n)).collect();
        integrator
            .step_batch(&mut batch_states, &inputs, &mut outputs)
            .expect("no input of this history is invalid");
        for (i, input) in inputs.iter().enumerate() {
            let reference = integrator
                .step(&mut point_states[i], input)
                .expect("the reference accepts what the batch accepted");
            assert_eq!(
                output_bits(&outputs[i]),
                output_bits(&reference),
                "{law}/{formulation}, step {step}, point {i}: output"
            );
            assert_eq!(
                state_bits(&batch_states[i]),
                state_bits(&point_states[i]),
                "{law}/{formulation}, step {step}, point {i}: state"
            );
            if input.du.norm() > 1e100 {
                // Outside the documented domain (|Δu_T| ≤ 1e6 mm, friction-math
                // §2 edge cases): both paths agree, but the point's work is then
                // infinite; start it afresh so that later steps stay in range.
                batch_states[i] = PointState::default();
                point_states[i] = PointState::default();
            }
            sticks += usize::from(reference.stick);
            opens += usize::from(reference.open);
            slips += usize::from(!reference.stick && !reference.open);
        }
        normals = inputs
            .iter()
            .map(|input| input.kin.n_new.normalize())
            .collect();
    }
    // The history must exercise every branch.
    let total = points * steps;
    assert!(
        sticks > total / 20 && slips > total / 20 && opens > 0,
        "{law}/{formulation}: {sticks} sticks, {slips} slips, {opens} opens"
    );
}

/// friction-math §2 through both paths: every pairing, 200 points × 30 steps
/// with stick, slip, lift-off, rotating tools and the fallback cases; equal bits.
#[test]
fn batch_path_equals_point_path_bitwise_for_every_pairing() {
    for (k, law) in LAW_NAMES.iter().enumerate() {
        for (j, formulation) in FORMULATION_NAMES.iter().enumerate() {
            compare(law, formulation, 200, 30, (10 * k + j) as u64);
        }
    }
}

/// Makes one input invalid.
type Spoil = fn(&mut StepInput);

/// An invalid input in the middle of a batch: the batch returns the error that
/// the point-by-point path gives for that point, the points before it are
/// updated as by the reference, and the failing point's state is unchanged.
#[test]
fn batch_error_is_the_first_bad_points_error_with_earlier_points_updated() {
    for law in LAW_NAMES {
        for formulation in FORMULATION_NAMES {
            let integrator = integrator(law, formulation);
            let mut rng = ChaCha8Rng::seed_from_u64(99);
            // Closed contact everywhere, so that the bad point is the only error.
            let inputs: Vec<StepInput> = (0..16)
                .map(|_| {
                    let mut input = random_input(&mut rng, Vec3::z());
                    input.p = input.p.max(1.0);
                    input.kin.n_new = input.kin.n_new.normalize();
                    input
                })
                .collect();
            let bad = 9;
            let cases: [(&str, Spoil); 4] = [
                ("du", |i| i.du.y = f64::NAN),
                ("p", |i| i.p = -1.0),
                ("n", |i| i.kin.n_new *= 1.1),
                ("dt", |i| i.kin.dt = f64::INFINITY),
            ];
            for (field, spoil) in cases {
                let mut spoilt = inputs.clone();
                spoil(&mut spoilt[bad]);
                let mut batch_states = vec![PointState::default(); inputs.len()];
                let mut outputs = vec![StepOutput::default(); inputs.len()];
                let err = integrator
                    .step_batch(&mut batch_states, &spoilt, &mut outputs)
                    .expect_err("a spoilt input is refused");
                let mut reference = vec![PointState::default(); inputs.len()];
                let mut expected: Option<FrictionError> = None;
                for (s, input) in reference.iter_mut().zip(&spoilt) {
                    if let Err(e) = integrator.step(s, input) {
                        expected = Some(e);
                        break;
                    }
                }
                // Compared as text: a NaN value makes `==` false.
                assert_eq!(
                    Some(err.to_string()),
                    expected.map(|e| e.to_string()),
                    "{law}/{formulation}: {field}"
                );
                assert!(
                    err.to_string()
                        .contains(&format!("invalid point input `{field}`")),
                    "{err}"
                );
                for i in 0..=bad {
                    assert_eq!(
                        state_bits(&batch_states[i]),
                        state_bits(&reference[i]),
                        "{law}/{formulation}: {field}, point {i}"
                    );
                }
                assert_eq!(batch_states[bad], PointState::default());
            }
        }
    }
}
