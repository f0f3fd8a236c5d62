//! Shared helpers of the shell verification tests: materials, meshes, one-shot force evaluation.
#![allow(dead_code)]

use fem_core::{Effect, Forces, NodalState, StepContext, Vec3};
use shell_elements::{Hardening, J2PlaneStress, Material, ShellFormulation, ShellSet};

/// Elastic material (flow stress 1e30 MPa).
pub fn elastic(e: f64, nu: f64, rho: f64) -> J2PlaneStress {
    J2PlaneStress::new(e, nu, rho, Hardening::swift(1e30, 1.0, 0.0).unwrap()).unwrap()
}

/// Evaluate the forces of one step of `dt` with nodal velocities `v`, `w`
/// read in the reference configuration: the classic explicit patch check.
/// The elements read their rates in the step's midpoint configuration, so
/// the step runs from `x0 − ½Δt v` to `x0 + ½Δt v`.
pub fn one_step<E: ShellFormulation, M: Material>(
    set: &mut ShellSet<E, M>,
    x0: &[Vec3],
    v: &[Vec3],
    w: &[Vec3],
    dt: f64,
) -> Forces {
    let mut st = NodalState::at_rest(x0);
    for (x, u) in st.x.iter_mut().zip(v) {
        *x += 0.5 * dt * u;
    }
    st.v = v.to_vec();
    st.w = w.to_vec();
    let mut f = Forces::zeros(x0.len());
    let ctx = StepContext {
        time: dt,
        dt,
        step: 1,
        press: None,
    };
    set.add_forces(&ctx, &st, &mut f, &mut fem_core::FieldAccess::none())
        .unwrap();
    f
}

/// Rotate a local `[xx, yy, xy]` tensor with the in-plane basis rows `e1`, `e2` to global x-y.
pub fn to_global_xy(s: [f64; 3], e1: [f64; 3], e2: [f64; 3]) -> [f64; 3] {
    // σ_g = Rᵀ σ_l R with R rows e1, e2 (x-y parts).
    let r = [[e1[0], e1[1]], [e2[0], e2[1]]];
    let l = [[s[0], s[2]], [s[2], s[1]]];
    let mut g = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            for a in 0..2 {
                for b in 0..2 {
                    g[i][j] += r[a][i] * l[a][b] * r[b][j];
                }
            }
        }
    }
    [g[0][0], g[1][1], g[0][1]]
}
