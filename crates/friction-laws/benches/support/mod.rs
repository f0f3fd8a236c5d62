//! Inputs shared by the `point_updates` benchmark and the `profile_points`
//! example (included by path), so that both measure the same work.

use plugins_api::kinematics::cayley;
use plugins_api::{Mat3, StepInput, StepKinematics, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `points` random step inputs (fixed seed): a mix of stick and slip,
/// curved-tool normals, blank spin and deformation, a fixed tool.
pub fn inputs(points: usize) -> Vec<StepInput> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..points)
        .map(|_| {
            let tilt = Vec3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                1.0,
            )
            .normalize();
            let n_old = tilt;
            let n_new = (tilt
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
            let tangential = dir - n_new * n_new.dot(&dir);
            // Slip increments from 1e-6 to 1e-3 mm: small ones stick, large ones slip.
            let du = tangential.normalize() * 10f64.powf(rng.random_range(-6.0..-3.0));
            let dt = 1e-6;
            let l = Mat3::from_fn(|_, _| rng.random_range(-50.0..50.0));
            let f_old = Mat3::identity() + Mat3::from_fn(|_, _| rng.random_range(-0.05..0.05));
            let kin = StepKinematics {
                dt,
                n_old,
                n_new,
                tool_rotation: Mat3::identity(),
                vel_grad: l,
                f_old,
                f_new: cayley(&(l * dt)) * f_old,
            };
            let mut input = StepInput::new(rng.random_range(1.0..100.0), du, kin);
            input.flow_stress = rng.random_range(250.0..450.0);
            input
        })
        .collect()
}
