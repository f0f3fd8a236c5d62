//! Incremental objectivity: a finite rigid rotation, step after step, leaves
//! an element unstrained (both elements, flat and warped, with and without
//! the warping correction).
//!
//! Source: Hughes & Winget, "Finite rotation effects in numerical
//! integration of rate constitutive equations arising in large-deformation
//! analysis", IJNME 15 (1980) 1862–1867: strain increments read in the
//! midpoint configuration `x_{n+1/2}` are exactly zero for a rigid rotation
//! of any size, because the step's velocity `(x_{n+1} − x_n)/Δt` is then a
//! rigid spin of `x_{n+1/2}` at the rate `2 tan(θ/2)/Δt` (the Cayley
//! transform of the step's rotation by `θ`). Read in the end configuration
//! `x_{n+1}`, a fibre is strained by `θ²/2` per step instead.
//!
//! Check: rotate an element by 90° about a general axis in 30 equal steps
//! (3° each), nodes moved exactly (`x_{n+1} = R x_n`), rotation rates the
//! Cayley rate; every stress, force and moment must stay at round-off:
//! tolerance 1e-9 of E (stress) and of E t (forces, 1 mm lever). With the
//! end configuration the stress would reach about E θ²/2 × 30 = 4e-2 E.

mod common;
use common::elastic;
use shell_elements::{
    BelytschkoTsay, ElementResult, ElementState, FullyIntegrated, Material, Section,
    ShellFormulation, V3,
};

const E: f64 = 206_000.0;
const T: f64 = 0.8;

/// A distorted quad lifted out of its plane by `zh` at alternate corners.
fn quad(zh: f64) -> [V3; 4] {
    [
        [0.0, 0.0, zh],
        [1.2, 0.1, -zh],
        [1.0, 0.9, zh],
        [0.2, 1.1, -zh],
    ]
}

/// Rotation by `theta` about the unit `axis` (Rodrigues).
fn rotate(p: V3, axis: V3, theta: f64) -> V3 {
    let (s, c) = theta.sin_cos();
    let d = axis[0] * p[0] + axis[1] * p[1] + axis[2] * p[2];
    let x = [
        axis[1] * p[2] - axis[2] * p[1],
        axis[2] * p[0] - axis[0] * p[2],
        axis[0] * p[1] - axis[1] * p[0],
    ];
    std::array::from_fn(|k| p[k] * c + x[k] * s + axis[k] * d * (1.0 - c))
}

/// Largest stress over `E` and largest nodal load over `E t` seen while
/// `form` turns `quad(zh)` by 90° about `axis` in `steps` steps of `dt`.
fn spin<F: ShellFormulation>(form: &F, zh: f64, axis: V3, steps: usize) -> (f64, f64) {
    let mat = elastic(E, 0.3, 7.85e-9);
    let sec = Section::new(T).unwrap();
    let n = sec.rule.n * F::IN_PLANE_POINTS;
    let mut t = T;
    let mut stress = vec![[0.0; 3]; n];
    let mut history = vec![mat.initial_history(); n];
    let mut shear = vec![[0.0; 2]; F::IN_PLANE_POINTS];
    let mut hourglass = vec![0.0; F::HOURGLASS_VARS];
    let mut drilling = [0.0; 4];
    let dt = 1e-6;
    let theta = std::f64::consts::FRAC_PI_2 / steps as f64;
    let rate = 2.0 * (0.5 * theta).tan() / dt;
    let w = [axis.map(|a| a * rate); 4];
    let mut x = quad(zh);
    let (mut s_max, mut f_max) = (0.0f64, 0.0f64);
    for _ in 0..steps {
        let next = x.map(|p| rotate(p, axis, theta));
        let v: [V3; 4] =
            std::array::from_fn(|i| std::array::from_fn(|k| (next[i][k] - x[i][k]) / dt));
        let r: ElementResult = form.compute(
            &mat,
            &sec,
            &next,
            &v,
            &w,
            dt,
            ElementState {
                thickness: &mut t,
                stress: &mut stress,
                history: &mut history,
                shear: &mut shear,
                hourglass: &mut hourglass,
                drilling: &mut drilling,
            },
        );
        x = next;
        let s = stress
            .iter()
            .flatten()
            .chain(shear.iter().flatten())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let f =
            r.f.iter()
                .chain(r.m.iter())
                .flatten()
                .fold(0.0f64, |m, v| m.max(v.abs()));
        s_max = s_max.max(s / E);
        f_max = f_max.max(f / (E * T));
    }
    (s_max, f_max)
}

#[test]
fn finite_rigid_rotation_steps_leave_both_elements_unstrained() {
    let axes: [V3; 3] = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.48, -0.6, 0.64]];
    for zh in [0.0, 0.05] {
        for wc in [false, true] {
            for axis in axes {
                let bt = BelytschkoTsay {
                    warping_correction: wc,
                    ..Default::default()
                };
                let fi = FullyIntegrated {
                    warping_correction: wc,
                    ..Default::default()
                };
                for (name, (s, f)) in [
                    ("BT", spin(&bt, zh, axis, 30)),
                    ("FI", spin(&fi, zh, axis, 30)),
                ] {
                    assert!(
                        s < 1e-9 && f < 1e-9,
                        "{name}, warping correction {wc}, z_h = {zh}, axis {axis:?}: \
                         stress/E {s:.2e}, load/(E t) {f:.2e}"
                    );
                }
            }
        }
    }
}
