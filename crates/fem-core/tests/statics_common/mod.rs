//! The von Mises (two-bar) truss shared by the static solver's tests, with
//! its closed-form load–deflection curve.
#![allow(dead_code)]

use fem_core::statics::{NewtonSettings, StaticProblem, StaticSolver};
use fem_core::{Dof, Dofs, Spring, Springs, Vec3};

/// Half-span (mm).
pub const A: f64 = 100.0;
/// Rise of the apex (mm): shallow, `h/a = 0.1`.
pub const H: f64 = 10.0;
/// Spring stiffness (N/mm).
pub const K: f64 = 1000.0;
/// The apex node (supports 0 and 1).
pub const APEX: usize = 2;

/// Free length of each spring, `L0 = √(a² + h²)` (mm).
pub fn l0() -> f64 {
    A.hypot(H)
}

/// Downward apex load (N) that holds the apex at deflection `w` (mm,
/// downward): with `s = h − w` and `L = √(a² + s²)`, vertical equilibrium
/// of the apex under two axial springs of force `k (L − L0)` gives
/// `P(w) = 2 k (L0 − L) s / L` (positive down, compression for `0 < w < 2h`).
pub fn load(w: f64) -> f64 {
    let s = H - w;
    let l = A.hypot(s);
    2.0 * K * (l0() - l) * s / l
}

/// The limit point `(w, P)`: `dP/ds = 0` gives `L0 a² = L³`, so
/// `L = (L0 a²)^(1/3)` and `s = √(L² − a²)`.
pub fn limit() -> (f64, f64) {
    let l = (l0() * A * A).cbrt();
    let w = H - (l * l - A * A).sqrt();
    (w, load(w))
}

/// The deflection `w` in `[0, w_limit]` with `P(w) = p` (bisection to
/// round-off; `P` rises monotonically on that branch).
pub fn deflection(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, limit().0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if load(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The truss as a problem: supports 0 `(−a, 0, 0)` and 1 `(a, 0, 0)`
/// clamped, apex 2 `(0, 0, h)` held out of plane (`uy`); its rotations no
/// effect stiffens, so they are dropped.
pub fn truss() -> StaticProblem {
    let nodes = [
        Vec3::new(-A, 0.0, 0.0),
        Vec3::new(A, 0.0, 0.0),
        Vec3::new(0.0, 0.0, H),
    ];
    let springs = vec![
        Spring {
            a: 0,
            b: 2,
            k: K,
            length0: l0(),
        },
        Spring {
            a: 1,
            b: 2,
            k: K,
            length0: l0(),
        },
    ];
    let mut p = StaticProblem::new(&nodes).unwrap();
    p.add_effect(Springs::new("truss", 3, springs).unwrap());
    p.fix(&[0, 1], Dofs::ALL).unwrap();
    p.fix(&[APEX as u32], Dofs::of(&[Dof::Uy])).unwrap();
    p
}

/// The truss with each bar split at its middle into two springs of
/// stiffness `2k` and free length `L0/2` (nodes 3 and 4, free in the plane).
/// In equilibrium each middle node sits on its bar's chord, so the bar acts
/// as one spring of stiffness `k` and free length `L0` and the closed form
/// holds unchanged; but a compressed chord with a free middle node is
/// unstable sideways (negative geometric stiffness `4T/L`), so the tangent
/// is indefinite on the snap-through and the solver needs `LDLᵀ`.
pub fn truss_with_midpoints() -> StaticProblem {
    let apex = Vec3::new(0.0, 0.0, H);
    let nodes = [
        Vec3::new(-A, 0.0, 0.0),
        Vec3::new(A, 0.0, 0.0),
        apex,
        (Vec3::new(-A, 0.0, 0.0) + apex) * 0.5,
        (Vec3::new(A, 0.0, 0.0) + apex) * 0.5,
    ];
    let half = |a, b| Spring {
        a,
        b,
        k: 2.0 * K,
        length0: 0.5 * l0(),
    };
    let springs = vec![half(0, 3), half(3, 2), half(1, 4), half(4, 2)];
    let mut p = StaticProblem::new(&nodes).unwrap();
    p.add_effect(Springs::new("truss", 5, springs).unwrap());
    p.fix(&[0, 1], Dofs::ALL).unwrap();
    p.fix(&[2, 3, 4], Dofs::of(&[Dof::Uy])).unwrap();
    p
}

/// The truss under the downward apex load `p` (N) at `λ = 1`.
pub fn truss_under_load(p: f64, settings: NewtonSettings) -> StaticSolver {
    let mut problem = truss();
    problem.add_load(&[APEX as u32], Dof::Uz, -p).unwrap();
    StaticSolver::new(problem, settings).unwrap()
}
