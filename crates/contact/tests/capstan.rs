//! Capstan (benchmarks.md §3): a thin strip wrapped over a fixed rigid cylinder
//! through θ = π/2, one end held by a constant force, the other pulled slowly;
//! steady sliding gives `T_pull / T_hold = e^{μθ}` (Euler–Eytelwein). Shell strip
//! (Belytschko–Tsay, elastic), exact NURBS cylinder, contact with AC friction,
//! through the explicit engine.

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec};
use fem_core::{Amplitude, Control, Dof, Dofs, MotionKind, NodalLoad, Solver, SolverSettings};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, ToolSurface, Vec3};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};
use std::collections::BTreeMap;
use tools_nurbs::builders::primitives::cylinder;
use tools_nurbs::builders::{Facing, Placement};

const R: f64 = 20.0;
const T: f64 = 0.1;
const WIDTH: f64 = 4.0;
const TAIL: f64 = 20.0;
const H: f64 = 1.0;

/// Nodes, quads and node sets of the strip.
type Strip = (Vec<Vec3>, Vec<[u32; 4]>, BTreeMap<String, Vec<u32>>);

/// Nodes and quads of the strip: a horizontal tail on top of the drum (pull end
/// at x = TAIL), a quarter arc over the drum, a vertical tail (hold end at z = -TAIL).
fn strip() -> Strip {
    let rm = R + 0.5 * T;
    let mut centre = Vec::new();
    let n1 = (TAIL / H).round() as usize;
    for i in 0..=n1 {
        centre.push((TAIL - i as f64 * TAIL / n1 as f64, rm));
    }
    let na = (rm * std::f64::consts::FRAC_PI_2 / H).ceil() as usize;
    for j in 1..=na {
        let a = std::f64::consts::FRAC_PI_2 * (1.0 + j as f64 / na as f64);
        centre.push((rm * a.cos(), rm * a.sin()));
    }
    for k in 1..=n1 {
        centre.push((-rm, -(k as f64) * TAIL / n1 as f64));
    }
    let ys = [-0.5 * WIDTH, 0.0, 0.5 * WIDTH];
    let mut nodes = Vec::new();
    for &(x, z) in &centre {
        for &y in &ys {
            nodes.push(Vec3::new(x, y, z));
        }
    }
    let m = centre.len();
    let mut quads = Vec::new();
    for i in 0..m - 1 {
        for j in 0..2 {
            let a = (3 * i + j) as u32;
            quads.push([a, a + 3, a + 4, a + 1]);
        }
    }
    let mut sets = BTreeMap::new();
    sets.insert("pull".to_string(), vec![0, 1, 2]);
    let last = 3 * (m as u32 - 1);
    sets.insert("hold".to_string(), vec![last, last + 1, last + 2]);
    sets.insert(
        "centre".to_string(),
        (0..m as u32).map(|i| 3 * i + 1).collect(),
    );
    (nodes, quads, sets)
}

/// Returns the steady tension ratio `T_pull / T_hold`.
fn tension_ratio(formulation: &str, mu: f64) -> f64 {
    let (nodes, quads, sets) = strip();
    let n = nodes.len();
    let mut solver = Solver::from_nodes(&nodes, sets, SolverSettings::default()).unwrap();
    let material = J2PlaneStress::new(
        2.06e5,
        0.3,
        7.85e-9,
        Hardening::swift(1e30, 1.0, 0.0).unwrap(),
    )
    .unwrap();
    let shells = ShellSet::new(
        "strip",
        &nodes,
        &quads,
        Section::new(T).unwrap(),
        BelytschkoTsay::default(),
        material,
    )
    .unwrap();
    solver.add_effect(shells);
    let drum = cylinder(
        "drum",
        R,
        3.0 * WIDTH,
        0.0,
        200.0,
        &Placement {
            origin: Vec3::zeros(),
            facing: Facing::Up,
        },
    )
    .unwrap();
    // Sanity: the drum is the cylinder of radius R about y.
    let top = drum.project(&Vec3::new(0.0, 0.0, R + 1.0), None).unwrap();
    assert!((top.distance - 1.0).abs() < 1e-9 && (top.normal - Vec3::z()).norm() < 1e-9);
    let geometry = BlankGeometry::new(n, &quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", mu),
        formulation,
        TangentMode::None,
    )
    .unwrap();
    let bulk = 2.06e5 / (3.0 * (1.0 - 0.6));
    let pair = ContactPair::new(
        &PairSpec::new("drum-strip", 0, bulk),
        integ,
        &geometry,
        &nodes,
    )
    .unwrap();
    let tools: Vec<Box<dyn ToolSurface>> = vec![Box::new(drum)];
    solver.add_effect(ContactEffect::new(tools, None, vec![pair], geometry, vec![T; n]).unwrap());
    // Keep the strip in its plane: the centre line holds uy (the width may contract).
    solver.fix("centre", Dofs::of(&[Dof::Uy])).unwrap();
    let t_hold = 200.0;
    let ramp = 2e-3;
    solver
        .add_load(&NodalLoad {
            set: "hold".into(),
            dof: Dof::Uz,
            value: -t_hold / 3.0,
            amplitude: Amplitude::SmoothStep { t0: 0.0, t1: ramp },
        })
        .unwrap();
    // The pull end holds its height and is drawn along +x at 1 m/s after the hold force is up.
    solver.fix("pull", Dofs::of(&[Dof::Uz])).unwrap();
    let speed = 1000.0;
    solver
        .prescribe(
            "pull",
            Dof::Ux,
            MotionKind::Velocity,
            speed,
            Amplitude::SmoothStep {
                t0: ramp,
                t1: 2.0 * ramp,
            },
        )
        .unwrap();
    solver.initialize().unwrap();
    let t_end = 6.0 * ramp;
    let mut samples = Vec::new();
    solver
        .run_until(t_end, &mut |s: &Solver, r| {
            if r.time > 4.0 * ramp {
                let (f, _) = s.reaction("pull").unwrap();
                samples.push(f.x.abs());
            }
            Control::Continue
        })
        .unwrap();
    let mean = samples.iter().sum::<f64>() / samples.len() as f64;
    let e = solver.ledger();
    assert!(
        e.balance_error.is_finite() && e.friction > 0.0,
        "{formulation}: {e:?}"
    );
    mean / t_hold
}

/// Euler–Eytelwein: `T_pull/T_hold = e^{μθ}`, θ = π/2, μ = 0.144 (benchmarks.md
/// §3; issue 5's tolerance 2 %), for the convective and Jaumann formulations.
#[test]
fn capstan_matches_euler_eytelwein() {
    let mu = 0.144;
    let exact = (mu * std::f64::consts::FRAC_PI_2).exp();
    for formulation in ["convective", "jaumann"] {
        let ratio = tension_ratio(formulation, mu);
        let err = (ratio - exact).abs() / exact;
        eprintln!(
            "capstan {formulation}: ratio {ratio:.4}, e^(mu theta) = {exact:.4}, error {:.2} %",
            100.0 * err
        );
        assert!(err < 0.02, "{formulation}: ratio {ratio} vs {exact}");
    }
}
