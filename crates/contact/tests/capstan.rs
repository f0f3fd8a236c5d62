//! Capstan (docs/benchmarks.md §3): a thin strip wrapped over a fixed rigid cylinder
//! through θ = π/2, one end held by a constant force, the other pulled slowly;
//! steady sliding gives `T_pull / T_hold = e^{μθ}` (Euler–Eytelwein). Shell strip
//! (Belytschko–Tsay, elastic), exact NURBS cylinder, contact with AC friction,
//! through the explicit engine.

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec};
use fem_core::{
    Amplitude, Control, Dof, Dofs, MotionKind, NodalLoad, Solver, SolverSettings, wrapped_strip,
};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, ToolSurface, Vec3};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};
use tools_nurbs::builders::primitives::cylinder;
use tools_nurbs::builders::{Facing, Placement};

const R: f64 = 20.0;
const T: f64 = 0.1;
const WIDTH: f64 = 4.0;
const TAIL: f64 = 20.0;
const H: f64 = 1.0;

/// Returns the steady tension ratio `T_pull / T_hold`.
fn tension_ratio(formulation: &str, mu: f64) -> f64 {
    let mesh = wrapped_strip(R + 0.5 * T, WIDTH, TAIL, std::f64::consts::FRAC_PI_2, H).unwrap();
    let (nodes, quads) = (mesh.nodes.clone(), mesh.quads.clone());
    let n = nodes.len();
    let mut solver = Solver::new(&mesh, SolverSettings::default()).unwrap();
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
    solver.add_effect(ContactEffect::new(tools, vec![pair], geometry, vec![T; n]).unwrap());
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

/// Euler–Eytelwein: `T_pull/T_hold = e^{μθ}`, θ = π/2, μ = 0.144 (docs/benchmarks.md
/// §3; tolerance 2 %), for the convective and Jaumann formulations.
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
