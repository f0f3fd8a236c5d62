//! Membrane and bending patch tests on the MacNeal–Harder distorted 5-element patch, both elements.
//!
//! Source: MacNeal & Harder, "A proposed standard set of problems to test
//! finite element accuracy", Finite Elem. Anal. Des. 1 (1985) 3–20, test 1
//! (patch 0.24 × 0.12, interior nodes (0.04, 0.02), (0.18, 0.03),
//! (0.16, 0.08), (0.08, 0.08); E = 1e6, ν = 0.25, t = 0.001).
//! Check (explicit form): impose the exact linear field (membrane) or the
//! exact constant-curvature field (bending: w quadratic, Kirchhoff
//! rotations) as nodal velocities over one step from the reference
//! configuration; every element must carry the exact constant stress or
//! moment (tolerance 1e-6 relative) and the interior nodes' residual
//! forces and moments must vanish (1e-9 of the largest nodal force).

mod common;
use common::*;
use fem_core::Vec3;
use shell_elements::{
    BelytschkoTsay, FullyIntegrated, Section, ShellFormulation, ShellSet, corotational_basis,
};

const E: f64 = 1.0e6;
const NU: f64 = 0.25;
const T: f64 = 0.001;

fn patch() -> (Vec<Vec3>, Vec<[u32; 4]>) {
    let p = |x, y| Vec3::new(x, y, 0.0);
    let nodes = vec![
        p(0.0, 0.0),
        p(0.24, 0.0),
        p(0.24, 0.12),
        p(0.0, 0.12),
        p(0.04, 0.02),
        p(0.18, 0.03),
        p(0.16, 0.08),
        p(0.08, 0.08),
    ];
    let quads = vec![
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
        [4, 5, 6, 7],
    ];
    (nodes, quads)
}

const INTERIOR: [usize; 4] = [4, 5, 6, 7];

fn element_basis(nodes: &[Vec3], q: [u32; 4]) -> [[f64; 3]; 3] {
    corotational_basis(&q.map(|n| {
        let p = nodes[n as usize];
        [p.x, p.y, p.z]
    }))
}

fn membrane_patch<F: ShellFormulation>(form: F) {
    let (nodes, quads) = patch();
    let mut set = ShellSet::new(
        "patch",
        &nodes,
        &quads,
        Section::new(T).unwrap(),
        form,
        elastic(E, NU, 1e-9),
    )
    .unwrap();
    let dt = 1e-6;
    // u = 1e-3 (x + y/2), v = 1e-3 (y + x/2) as a velocity field over dt.
    let v: Vec<Vec3> = nodes
        .iter()
        .map(|p| Vec3::new(1e-3 * (p.x + 0.5 * p.y), 1e-3 * (p.y + 0.5 * p.x), 0.0))
        .collect();
    let w = vec![Vec3::zeros(); nodes.len()];
    let f = one_step(&mut set, &nodes, &v, &w, dt);
    let c = E / (1.0 - NU * NU);
    let (exx, eyy, gxy) = (1e-3 * dt, 1e-3 * dt, 1e-3 * dt);
    let exact = [
        c * (exx + NU * eyy),
        c * (eyy + NU * exx),
        E / (2.0 * (1.0 + NU)) * gxy,
    ];
    let scale = exact[0].abs();
    for (e, q) in quads.iter().enumerate() {
        let r = element_basis(&nodes, *q);
        for p in 0..F::IN_PLANE_POINTS {
            for k in 0..5 {
                let s = to_global_xy(set.stress(e, p, k), r[0], r[1]);
                for c in 0..3 {
                    assert!(
                        (s[c] - exact[c]).abs() <= 1e-6 * scale,
                        "{}: element {e} point {p}/{k} σ[{c}] = {} vs {}",
                        F::NAME,
                        s[c],
                        exact[c]
                    );
                }
            }
        }
    }
    let fmax = f.f.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for &n in &INTERIOR {
        assert!(
            f.f[n].norm() <= 1e-9 * fmax,
            "{}: interior node {n} residual {:?} (max {fmax})",
            F::NAME,
            f.f[n]
        );
        assert!(
            f.m[n].norm() <= 1e-9 * fmax,
            "{}: interior node {n} moment {:?}",
            F::NAME,
            f.m[n]
        );
    }
}

fn bending_patch<F: ShellFormulation>(form: F) {
    let (nodes, quads) = patch();
    let mut set = ShellSet::new(
        "patch",
        &nodes,
        &quads,
        Section::new(T).unwrap(),
        form,
        elastic(E, NU, 1e-9),
    )
    .unwrap();
    let dt = 1e-6;
    // w = 1e-3 (x² + xy + y²)/2, θx = ∂w/∂y, θy = −∂w/∂x (rates over dt).
    let v: Vec<Vec3> = nodes
        .iter()
        .map(|p| Vec3::new(0.0, 0.0, 0.5e-3 * (p.x * p.x + p.x * p.y + p.y * p.y)))
        .collect();
    let w: Vec<Vec3> = nodes
        .iter()
        .map(|p| Vec3::new(1e-3 * (p.y + 0.5 * p.x), -1e-3 * (p.x + 0.5 * p.y), 0.0))
        .collect();
    let f = one_step(&mut set, &nodes, &v, &w, dt);
    // κ = (∂θy/∂x, −∂θx/∂y, ∂θy/∂y − ∂θx/∂x) = −1e-3 (1, 1, 1) per unit time.
    let d = E * T.powi(3) / (12.0 * (1.0 - NU * NU));
    let k = -1e-3 * dt;
    let exact = [d * (k + NU * k), d * (k + NU * k), d * (1.0 - NU) / 2.0 * k];
    let scale = exact[0].abs();
    let fmax =
        f.f.iter()
            .chain(f.m.iter())
            .map(|v| v.norm())
            .fold(0.0, f64::max);
    for (e, q) in quads.iter().enumerate() {
        let r = element_basis(&nodes, *q);
        let (_, m) = set.resultants(e);
        let m = to_global_xy(m, r[0], r[1]);
        for c in 0..3 {
            assert!(
                (m[c] - exact[c]).abs() <= 1e-6 * scale,
                "{}: element {e} M[{c}] = {} vs {}",
                F::NAME,
                m[c],
                exact[c]
            );
        }
        for p in 0..F::IN_PLANE_POINTS {
            let ts = set.transverse_shear(e, p);
            assert!(
                ts[0].abs().max(ts[1].abs()) * T <= 1e-6 * scale / 0.12,
                "{}: element {e} shear {ts:?}",
                F::NAME
            );
        }
    }
    for &n in &INTERIOR {
        assert!(
            f.f[n].norm() <= 1e-9 * fmax,
            "{}: interior node {n} force {:?} (max {fmax})",
            F::NAME,
            f.f[n]
        );
        assert!(
            f.m[n].norm() <= 1e-9 * fmax,
            "{}: interior node {n} moment {:?} (max {fmax})",
            F::NAME,
            f.m[n]
        );
    }
}

#[test]
fn macneal_harder_membrane_patch_belytschko_tsay() {
    membrane_patch(BelytschkoTsay::default());
}

#[test]
fn macneal_harder_membrane_patch_fully_integrated() {
    membrane_patch(FullyIntegrated::default());
}

#[test]
fn macneal_harder_bending_patch_belytschko_tsay() {
    bending_patch(BelytschkoTsay::default());
}

#[test]
fn macneal_harder_bending_patch_fully_integrated() {
    bending_patch(FullyIntegrated::default());
}

/// The original BT shear (node-averaged rotations at the centre) does not
/// pass the bending patch on this distorted mesh; recorded, not required.
#[test]
fn original_bt_shear_fails_the_distorted_bending_patch() {
    let (nodes, quads) = patch();
    let form = BelytschkoTsay {
        shear_projection: false,
        ..Default::default()
    };
    let mut set = ShellSet::new(
        "patch",
        &nodes,
        &quads,
        Section::new(T).unwrap(),
        form,
        elastic(E, NU, 1e-9),
    )
    .unwrap();
    let v: Vec<Vec3> = nodes
        .iter()
        .map(|p| Vec3::new(0.0, 0.0, 0.5e-3 * (p.x * p.x + p.x * p.y + p.y * p.y)))
        .collect();
    let w: Vec<Vec3> = nodes
        .iter()
        .map(|p| Vec3::new(1e-3 * (p.y + 0.5 * p.x), -1e-3 * (p.x + 0.5 * p.y), 0.0))
        .collect();
    let f = one_step(&mut set, &nodes, &v, &w, 1e-6);
    let fmax =
        f.f.iter()
            .chain(f.m.iter())
            .map(|v| v.norm())
            .fold(0.0, f64::max);
    let worst = INTERIOR
        .iter()
        .map(|&n| f.f[n].norm().max(f.m[n].norm()))
        .fold(0.0, f64::max);
    assert!(worst > 1e-6 * fmax, "unexpectedly passes: {worst} / {fmax}");
}
