//! Block on a plane (docs/benchmarks.md §3): a stiff four-node block pressed on a
//! rigid plane by `N`, pulled by a slowly ramped tangential force `T`, starts to
//! slip when `T = μ N`. Run through the explicit engine (fem-core) with the
//! contact effect, for every formulation.

mod common;
use common::Plane;
use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec, PointStatus};
use fem_core::{Amplitude, Control, Dof, NodalLoad, Solver, SolverSettings, Spring, Springs};
use friction_laws::builtin;
use plugins_api::{Params, RigidPose, RigidVelocity, TangentMode, ToolSurface, Vec3};
use std::collections::BTreeMap;

/// Returns (T at the first step where every point slips, μ N).
fn slip_force(law: &str, params: Params, formulation: &str, mu: f64) -> (f64, f64) {
    let side = 10.0;
    let thickness = 1.0;
    let z = 0.5 * thickness;
    let nodes = vec![
        Vec3::new(0.0, 0.0, z),
        Vec3::new(side, 0.0, z),
        Vec3::new(side, side, z),
        Vec3::new(0.0, side, z),
    ];
    let mut sets = BTreeMap::new();
    sets.insert("all".to_string(), vec![0, 1, 2, 3]);
    let mut solver = Solver::from_nodes(&nodes, sets, SolverSettings::default()).unwrap();
    solver.add_point_mass("all", 1e-3, 0.0).unwrap();
    let pairs_ab = [(0, 1), (1, 2), (2, 3), (3, 0), (0, 2), (1, 3)];
    let springs = pairs_ab
        .iter()
        .map(|&(a, b)| Spring {
            a,
            b,
            k: 1e5,
            length0: (nodes[a as usize] - nodes[b as usize]).norm(),
        })
        .collect();
    solver.add_effect(Springs::new("block", 4, springs).unwrap());
    let quads = [[0u32, 1, 2, 3]];
    let geometry = BlankGeometry::new(4, &quads).unwrap();
    let integ = builtin::integrator(law, &params, formulation, TangentMode::None).unwrap();
    let pair = ContactPair::new(
        &PairSpec::new("plane-block", 0, 1.7e5),
        integ,
        &geometry,
        &nodes,
    )
    .unwrap();
    let plane: Box<dyn ToolSurface> = Box::new(Plane {
        pose: RigidPose::default(),
        vel: RigidVelocity::default(),
    });
    let contact =
        ContactEffect::new(vec![plane], vec![pair], geometry, vec![thickness; 4]).unwrap();
    let id = solver.add_effect(contact);
    let n_total = 1000.0;
    solver
        .add_load(&NodalLoad {
            set: "all".into(),
            dof: Dof::Uz,
            value: -n_total / 4.0,
            amplitude: Amplitude::SmoothStep { t0: 0.0, t1: 0.01 },
        })
        .unwrap();
    // T ramps from 0 at t = 0.02 s to 2 μN at t = 0.12 s.
    let (t0, t1, t_max) = (0.02, 0.12, 2.0 * mu * n_total);
    solver
        .add_load(&NodalLoad {
            set: "all".into(),
            dof: Dof::Ux,
            value: t_max / 4.0,
            amplitude: Amplitude::Linear { t0, t1 },
        })
        .unwrap();
    solver.initialize().unwrap();
    let mut slip_at = None;
    solver
        .run_until(t1, &mut |s: &Solver, r| {
            let c: &ContactEffect = s.effect(id).unwrap();
            let all_slip = c.pairs()[0]
                .status
                .iter()
                .all(|st| *st == PointStatus::Slip);
            if all_slip && slip_at.is_none() {
                slip_at = Some(r.time);
            }
            Control::Continue
        })
        .unwrap();
    let t = slip_at.expect("the block slipped");
    // The energy balance of the run (fem-core's ledger), after sliding on to
    // T = 2 μN, closes: loads' work = kinetic + springs + contact + friction.
    let e = solver.ledger();
    assert!(e.friction > 0.0 && e.balance_error.is_finite());
    assert!(
        e.balance_error < 0.01,
        "{formulation}: balance error {}",
        e.balance_error
    );
    (t_max * (t - t0) / (t1 - t0), mu * n_total)
}

/// Block on a plane, Amontons–Coulomb μ = 0.144: slip starts at `T = μ N`
/// (docs/benchmarks.md §3; tolerance 1 %).
#[test]
fn block_on_plane_slips_at_mu_n() {
    for formulation in ["convective", "jaumann", "lagrangian", "updated-lagrangian"] {
        let (t, mu_n) = slip_force("ac", Params::new().with("mu", 0.144), formulation, 0.144);
        let err = (t - mu_n).abs() / mu_n;
        eprintln!(
            "{formulation}: T_slip = {t:.3} N, mu N = {mu_n:.3} N, error {:.3} %",
            100.0 * err
        );
        assert!(
            err < 0.01,
            "{formulation}: T_slip = {t} N vs mu N = {mu_n} N"
        );
    }
}
