//! End-to-end smoke run of the NUMISHEET'93 square cup (benchmarks.md §1),
//! quarter model on a coarse mesh, assembled by hand from the engine, the BT
//! shells, the exact NURBS tools, the press and contact with AC friction: the
//! punch draws 5 mm while the blankholder presses with 4.9 kN (quarter of
//! 19.6 kN). Not a result check (the scene, `formsim run` and the converged
//! meshes come with issue 5): it asserts that the pieces work together —
//! the run finishes, stays finite, draws the blank down with the punch,
//! keeps the holder force on the flange and closes its energy balance.

use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec};
use fem_core::{
    Control, Press, PressStep, Solver, SolverSettings, StepEnd, ToolMotion, Vec3, rectangle,
};
use friction_laws::builtin;
use plugins_api::{Params, RigidPose, TangentMode, ToolSurface};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};
use std::path::Path;

#[test]
fn square_cup_quarter_coarse_draws_5_mm() {
    let t0 = 0.78;
    let n = 12;
    let mut mesh = rectangle(75.0, 75.0, n, n).unwrap();
    for p in &mut mesh.nodes {
        p.z = 0.5 * t0;
    }
    let nodes = mesh.nodes.clone();
    let quads = mesh.quads.clone();
    let nn = nodes.len();
    let mut solver = Solver::new(&mesh, SolverSettings::default()).unwrap();
    let steel = J2PlaneStress::new(
        2.06e5,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap();
    solver.add_effect(
        ShellSet::new(
            "blank",
            &nodes,
            &quads,
            Section::new(t0).unwrap(),
            BelytschkoTsay::default(),
            steel,
        )
        .unwrap(),
    );
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let tools = tools_nurbs::spec::load(&root.join("scenes/tools/square-cup-tools.toml")).unwrap();
    let names: Vec<String> = tools.iter().map(|t| t.name().to_string()).collect();
    let index = |name: &str| names.iter().position(|n| n == name).unwrap();
    let (punch, die, holder) = (index("punch"), index("die"), index("blankholder"));
    let poses: Vec<RigidPose> = tools.iter().map(|t| t.pose()).collect();
    let force_quarter = 4900.0;
    let holder_motion = ToolMotion::Force {
        direction: -Vec3::z(),
        force: force_quarter,
        amplitude: None,
        mass: 0.01,
        damping: 500.0,
    };
    let steps = vec![
        PressStep {
            name: "clamp".into(),
            end: StepEnd::Duration(1e-3),
            motions: vec![(holder, holder_motion.clone())],
            active_pairs: None,
        },
        PressStep {
            name: "draw".into(),
            end: StepEnd::Duration(5e-3),
            motions: vec![
                (holder, holder_motion),
                (
                    punch,
                    ToolMotion::Travel {
                        direction: -Vec3::z(),
                        distance: 5.0,
                        amplitude: None,
                    },
                ),
            ],
            active_pairs: None,
        },
    ];
    let press = Press::new(&names, &poses, steps).unwrap();
    let geometry = BlankGeometry::new(nn, &quads).unwrap();
    let bulk = 2.06e5 / (3.0 * (1.0 - 0.6));
    let mut pairs = Vec::new();
    for (tool, name) in [
        (punch, "punch-blank"),
        (die, "die-blank"),
        (holder, "holder-blank"),
    ] {
        let integ = builtin::integrator(
            "ac",
            &Params::new().with("mu", 0.144),
            "convective",
            TangentMode::None,
        )
        .unwrap();
        pairs.push(
            ContactPair::new(&PairSpec::new(name, tool, bulk), integ, &geometry, &nodes).unwrap(),
        );
    }
    let boxed: Vec<Box<dyn ToolSurface>> = tools
        .into_iter()
        .map(|t| Box::new(t) as Box<dyn ToolSurface>)
        .collect();
    let contact = ContactEffect::new(boxed, Some(press), pairs, geometry, vec![t0; nn]).unwrap();
    let cid = solver.add_effect(contact);
    solver.symmetry("x0", 0).unwrap();
    solver.symmetry("y0", 1).unwrap();
    solver.initialize().unwrap();
    let mut worst_balance: f64 = 0.0;
    let summary = solver
        .run_until(6e-3, &mut |_s: &Solver, r| {
            if r.time > 2e-3 {
                worst_balance = worst_balance.max(r.energy.balance_error);
            }
            Control::Continue
        })
        .unwrap();
    let c: &ContactEffect = solver.effect(cid).unwrap();
    let press = c.press().unwrap();
    let stroke = -press.displacement(punch).z;
    let punch_force = c.reactions()[punch].z;
    let holder_force = c.reactions()[holder].z;
    let state = solver.state();
    let centre_drop = -(state.x[0].z - state.x0[0].z);
    let e = solver.ledger();
    eprintln!(
        "steps {}, stroke {stroke:.3} mm, centre drop {centre_drop:.3} mm, punch force {punch_force:.1} N, \
         holder reaction {holder_force:.1} N, friction {:.1} mJ, internal {:.1} mJ, plastic {:.1} mJ, \
         tools' work {:.1} mJ, balance error {:.2e} (worst after clamping {worst_balance:.2e})",
        summary.steps, e.friction, e.internal, e.plastic, e.external_tools, e.balance_error
    );
    assert!((stroke - 5.0).abs() < 1e-9);
    // The blank centre is pushed down with the punch nose: it may not lag behind
    // by more than a penalty penetration (0.05 mm); in this fast run (5 mm in
    // 5 ms) it may run ahead of the decelerating punch (0.16 mm measured).
    assert!(
        centre_drop > 5.0 - 0.05 && centre_drop < 5.0 + 0.5,
        "the blank centre follows the punch: {centre_drop}"
    );
    assert!(
        punch_force > 0.0,
        "the blank resists the punch: {punch_force} N"
    );
    assert!(
        (holder_force - force_quarter).abs() < 0.05 * force_quarter,
        "holder reaction {holder_force} N"
    );
    assert!(e.friction > 0.0 && e.plastic > 0.0);
    assert!(worst_balance < 0.05, "energy balance error {worst_balance}");
}
