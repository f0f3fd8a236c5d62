//! Point histories of the suite: a designed reference history over a curved tool, its
//! rigidly rotated copy (objectivity) and fixed-seed random histories.
//!
//! Every history carries plausible values of all optional point data (flow
//! stress 200–600 MPa, temperature 293 K, a small velocity gradient `L` with the
//! deformation gradient `F` integrated from it, a small tool rotation); the
//! driver blanks out what no component declared ([`super::driver::neutralise`]).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::kinematics::{cayley, skew};
use crate::{Mat3, StepInput, StepKinematics, Vec3};

/// Time step of the designed histories (s).
pub(super) const DT: f64 = 1e-3;
/// Temperature supplied to laws that need it (K).
pub(super) const TEMPERATURE: f64 = 293.0;
/// Flow stress of the single-point cases (MPa).
pub(super) const FLOW_STRESS: f64 = 400.0;
/// Number of steps of the reference history.
pub(super) const REFERENCE_STEPS: usize = 64;
/// Steps of the reference history with open contact (lift-off, then re-contact).
const OPEN_STEPS: [usize; 2] = [40, 41];

/// Slip increment of the reference history in units of the stick limit
/// `u* = τ_c(p_ref)/k_T`: loading, deep slip (up to 3000 u*), reversals
/// (negative: unloading into stick) and tiny increments.
const PATTERN: [f64; 16] = [
    0.3, 0.5, 2.0, 5.0, -0.2, 0.1, 30.0, 0.05, -1.5, 300.0, 0.4, 1.2, -0.05, 8.0, 0.02, 3000.0,
];

/// A unit basis `(a, b)` of the tangent plane of the unit normal `n`.
pub(super) fn tangent_basis(n: &Vec3) -> (Vec3, Vec3) {
    let helper = if n.x.abs() < 0.9 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let a = (helper - n * n.dot(&helper)).normalize();
    (a, n.cross(&a))
}

/// Outward normal of a sphere at polar angle `theta`, azimuth `phi`.
fn sphere_normal(theta: f64, phi: f64) -> Vec3 {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Normal of the reference path over a spherical tool after `k` steps.
fn reference_normal(k: usize) -> Vec3 {
    let s = k as f64;
    sphere_normal(0.3 + 0.004 * s, 0.2 + 0.01 * s)
}

/// A single step at a point with fixed normal `n`, carrying all optional data.
pub(super) fn single(p: f64, du: Vec3, n: Vec3) -> StepInput {
    let l = small_velocity_gradient();
    let mut kin = StepKinematics::simple(DT, n, n);
    kin.vel_grad = l;
    kin.f_new = cayley(&(DT * l));
    kin.tool_rotation = cayley(&(DT * skew(&Vec3::new(0.4, -0.2, 0.3))));
    StepInput {
        p,
        du,
        kin,
        flow_stress: FLOW_STRESS,
        temperature: TEMPERATURE,
    }
}

/// A fixed small velocity gradient (1/s) with non-zero spin and stretching.
fn small_velocity_gradient() -> Mat3 {
    Mat3::new(0.2, 0.1, -0.05, -0.3, -0.1, 0.15, 0.05, 0.25, -0.1)
}

/// The designed reference history: a point sliding over a sphere (normal turning
/// by about 0.01 rad per step), pressure oscillating around `p_ref` with one
/// lift-off, slip increments of [`PATTERN`] times `u_star` along a slowly turning
/// direction. With `rigid`, the blank does not deform (`L = 0`, `F = I`) and the
/// tool does not rotate: the base history of the objectivity check.
pub(super) fn reference(u_star: f64, p_ref: f64, rigid: bool) -> Vec<StepInput> {
    let l = if rigid {
        Mat3::zeros()
    } else {
        small_velocity_gradient()
    };
    let df = cayley(&(DT * l));
    let tool = if rigid {
        Mat3::identity()
    } else {
        cayley(&(DT * skew(&Vec3::new(0.4, -0.2, 0.3))))
    };
    let mut f = Mat3::identity();
    (0..REFERENCE_STEPS)
        .map(|k| {
            let s = k as f64;
            let n_old = reference_normal(k);
            let n_new = reference_normal(k + 1);
            let p = if OPEN_STEPS.contains(&k) {
                0.0
            } else {
                p_ref * (1.0 + 0.5 * (0.37 * s).sin())
            };
            let psi = 0.05 * s + 1.3 * (k / PATTERN.len()) as f64;
            let (a, b) = tangent_basis(&n_new);
            let du = (a * psi.cos() + b * psi.sin()) * (u_star * PATTERN[k % PATTERN.len()]);
            let f_new = df * f;
            let kin = StepKinematics {
                dt: DT,
                n_old,
                n_new,
                tool_rotation: tool,
                vel_grad: l,
                f_old: f,
                f_new,
            };
            f = f_new;
            StepInput {
                p,
                du,
                kin,
                flow_stress: FLOW_STRESS + 150.0 * (0.1 * s).sin(),
                temperature: TEMPERATURE,
            }
        })
        .collect()
}

/// Superpose on a rigid base history (`L = 0`, `F = I`, no tool rotation) the
/// rigid rotation `Q(t)` with `Q_0 = q0` and constant spin `spin` (rad/s), with
/// exact Cayley increments `Q_{n+1} = cayley(Δt Ω) Q_n`: `n' = Q n`,
/// `Δu' = Q_{n+1} Δu`, `tool_rotation' = ΔQ R_tool`, `F' = Q F`, `L' = Ω`
/// (so that `cayley(Δt L') = ΔQ`). Returns the rotated history and `Q_{n+1}` of
/// every step.
pub(super) fn superpose(base: &[StepInput], q0: Mat3, spin: Vec3) -> (Vec<StepInput>, Vec<Mat3>) {
    let w = skew(&spin);
    let mut q = q0;
    let mut rotated = Vec::with_capacity(base.len());
    let mut qs = Vec::with_capacity(base.len());
    for x in base {
        let dq = cayley(&(x.kin.dt * w));
        let q_new = dq * q;
        let mut y = *x;
        y.kin.n_old = q * x.kin.n_old;
        y.kin.n_new = q_new * x.kin.n_new;
        y.du = q_new * x.du;
        y.kin.tool_rotation = dq * x.kin.tool_rotation;
        y.kin.f_old = q * x.kin.f_old;
        y.kin.f_new = q_new * x.kin.f_new;
        y.kin.vel_grad = w;
        rotated.push(y);
        qs.push(q_new);
        q = q_new;
    }
    (rotated, qs)
}

/// A random history of `steps` steps from `seed`: pressure in [0, 500] MPa
/// with intermittent lift-off (1–3 steps of `p = 0`), jumps, occasional tiny
/// pressures (1e-12..1 MPa); slip increments of 1e-9..1 mm (log-uniform, 3 %
/// exactly zero) in a direction that mostly persists and sometimes jumps;
/// normals turning by up to ~0.017 rad per step; a small random `L` (entries
/// within ±0.55 1/s) with `F` integrated from it; a small tool spin; flow stress
/// drifting in 200–600 MPa.
pub(super) fn random(seed: u64, steps: usize) -> Vec<StepInput> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let two_pi = std::f64::consts::TAU;
    let z: f64 = rng.random_range(-1.0..1.0);
    let az: f64 = rng.random_range(0.0..two_pi);
    let mut n = Vec3::new(
        (1.0 - z * z).sqrt() * az.cos(),
        (1.0 - z * z).sqrt() * az.sin(),
        z,
    )
    .normalize();
    let tool_spin = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0));
    let tool = cayley(&(DT * skew(&tool_spin)));
    let l0 = Mat3::from_fn(|_, _| rng.random_range(-0.5..0.5));
    let mut f = Mat3::identity();
    let mut p_level: f64 = rng.random_range(0.0..500.0);
    let mut lift = 0_u32;
    let mut angle: f64 = rng.random_range(0.0..two_pi);
    let mut flow: f64 = rng.random_range(200.0..600.0);
    let mut out = Vec::with_capacity(steps);
    for _ in 0..steps {
        let turn = Vec3::from_fn(|_, _| rng.random_range(-0.01..0.01));
        let n_new = (cayley(&skew(&turn)) * n).normalize();
        let l = l0 + Mat3::from_fn(|_, _| rng.random_range(-0.05..0.05));
        let f_new = cayley(&(DT * l)) * f;
        let p = if lift > 0 {
            lift -= 1;
            0.0
        } else if rng.random_bool(0.06) {
            lift = rng.random_range(0..3);
            p_level = 0.0;
            0.0
        } else {
            if p_level == 0.0 || rng.random_bool(0.1) {
                p_level = rng.random_range(0.0..500.0);
            } else {
                p_level = (p_level * rng.random_range(-0.3_f64..0.3).exp()).min(500.0);
            }
            if rng.random_bool(0.03) {
                10f64.powf(rng.random_range(-12.0..0.0))
            } else {
                p_level
            }
        };
        let du = if rng.random_bool(0.03) {
            Vec3::zeros()
        } else {
            if rng.random_bool(0.3) {
                angle = rng.random_range(0.0..two_pi);
            } else {
                angle += rng.random_range(-0.1..0.1);
            }
            let (a, b) = tangent_basis(&n_new);
            (a * angle.cos() + b * angle.sin()) * 10f64.powf(rng.random_range(-9.0..0.0))
        };
        flow = (flow + rng.random_range(-2.0..2.0)).clamp(200.0, 600.0);
        let kin = StepKinematics {
            dt: DT,
            n_old: n,
            n_new,
            tool_rotation: tool,
            vel_grad: l,
            f_old: f,
            f_new,
        };
        out.push(StepInput {
            p,
            du,
            kin,
            flow_stress: flow,
            temperature: TEMPERATURE,
        });
        n = n_new;
        f = f_new;
    }
    out
}
