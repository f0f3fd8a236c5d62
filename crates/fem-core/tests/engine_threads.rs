//! The engine's node update on one thread and on two: the same bits.
//!
//! A spring lattice of 3,721 nodes (above the size from which the nodes are
//! updated in parallel chunks) with damping, fixed, symmetric and prescribed
//! DOFs, a nodal moment and a non-uniform start, two effects sharing the
//! nodes (the combined nodal step limit), stepped in a local rayon
//! pool of one thread and in one of two: positions, velocities, rotations,
//! reactions and every term of the energy ledger must agree to the bit.

use fem_core::{
    Amplitude, Dof, Dofs, EnergyLedger, MotionKind, NodalLoad, Solver, SolverSettings, Spring,
    Springs, Vec3, rectangle,
};

/// Quads per side of the lattice: (60 + 1)² = 3,721 nodes.
const DIVISIONS: usize = 60;

/// The lattice: springs along the quads' edges and diagonals of varying
/// stiffness, varying point masses, every kind of constraint, a moment.
fn lattice() -> Solver {
    let mesh = rectangle(60.0, 60.0, DIVISIONS, DIVISIONS).unwrap();
    // Edges and diagonals in two effects: their step is the combined one.
    let (mut springs, mut diagonals) = (Vec::new(), Vec::new());
    for (e, q) in mesh.quads.iter().enumerate() {
        for (a, b) in [(0, 1), (1, 2), (0, 2)] {
            let list = if b == 2 && a == 0 {
                &mut diagonals
            } else {
                &mut springs
            };
            list.push(Spring {
                a: q[a],
                b: q[b],
                k: 50.0 + (e % 7) as f64 * 10.0,
                length0: (mesh.nodes[q[a] as usize] - mesh.nodes[q[b] as usize]).norm(),
            });
        }
    }
    let n = mesh.nodes.len();
    let mut sets = mesh.node_sets.clone();
    sets.insert("odd".into(), (1..n as u32).step_by(3).collect());
    // The edge x = 60 but its corner on the fixed edge y = 0.
    let pulled = mesh.node_sets["x1"][1..].to_vec();
    sets.insert("pulled".into(), pulled);
    let settings = SolverSettings {
        damping: 40.0,
        ..Default::default()
    };
    let mut s = Solver::from_nodes(&mesh.nodes, sets, settings).unwrap();
    s.add_effect(Springs::new("lattice", n, springs).unwrap());
    s.add_effect(Springs::new("diagonals", n, diagonals).unwrap());
    s.add_point_mass("all", 1e-6, 1e-6).unwrap();
    s.add_point_mass("odd", 2.5e-6, 0.5e-6).unwrap();
    s.symmetry("x0", 0).unwrap();
    s.fix("y0", Dofs::ALL).unwrap();
    s.prescribe(
        "pulled",
        Dof::Ux,
        MotionKind::Velocity,
        200.0,
        Amplitude::SmoothStep { t0: 0.0, t1: 1e-4 },
    )
    .unwrap();
    s.add_load(&NodalLoad {
        set: "y1".into(),
        dof: Dof::Rz,
        value: 1e-3,
        amplitude: Amplitude::SmoothStep { t0: 0.0, t1: 1e-4 },
    })
    .unwrap();
    for (i, v) in s.state_mut().v.iter_mut().enumerate() {
        let t = i as f64;
        *v = Vec3::new((0.7 * t).sin(), (1.3 * t).cos(), 0.5 * (0.3 * t).sin());
    }
    s
}

/// Every bit the steps leave: positions, velocities, rotations, the
/// reactions of the prescribed edge, and the ledger and next step of every
/// step (the last ledger also returned, with the number of steps the
/// combined nodal limit set).
fn bits_after_steps(threads: usize, steps: usize) -> (Vec<u64>, EnergyLedger, usize) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut s = lattice();
        let mut ledger = EnergyLedger::default();
        let (mut bits, mut combined) = (Vec::new(), 0);
        for _ in 0..steps {
            let r = s.step().unwrap();
            ledger = r.energy;
            bits.extend(ledger_bits(&ledger).into_iter().map(|(_, b)| b));
            bits.push(r.dt_next.to_bits());
            bits.push(r.limit.map_or(u64::MAX, |l| l.stable.element as u64));
            combined += r.limit.is_some_and(|l| l.combined) as usize;
        }
        let st = s.state();
        bits.extend(
            [&st.x, &st.v, &st.w]
                .iter()
                .flat_map(|a| a.iter().flat_map(|p| p.iter().map(|c| c.to_bits()))),
        );
        let (f, m) = s.reaction("pulled").unwrap();
        bits.extend(f.iter().chain(m.iter()).map(|c| c.to_bits()));
        (bits, ledger, combined)
    })
}

/// The ledger's terms as bits, named.
fn ledger_bits(e: &EnergyLedger) -> Vec<(&'static str, u64)> {
    [
        ("kinetic", e.kinetic),
        ("kinetic_rotational", e.kinetic_rotational),
        ("integration", e.integration),
        ("internal", e.internal),
        ("damping", e.damping),
        ("external_loads", e.external_loads),
        ("external_prescribed", e.external_prescribed),
        ("balance_abs", e.balance_abs),
    ]
    .into_iter()
    .map(|(k, v)| (k, v.to_bits()))
    .collect()
}

#[test]
fn one_and_two_threads_step_to_the_same_bits() {
    let (one, e1, combined) = bits_after_steps(1, 300);
    let (two, e2, _) = bits_after_steps(2, 300);
    assert_eq!(one.len(), two.len());
    let differ = one.iter().zip(&two).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} values differ between 1 and 2 threads");
    assert_eq!(ledger_bits(&e1), ledger_bits(&e2));
    // The run did something: the damping and the prescribed edge did work.
    assert!(e1.damping.abs() > 0.0 && e1.external_prescribed.abs() > 0.0);
    assert!(e1.kinetic_rotational > 0.0, "the moment turned the nodes");
    assert_eq!(combined, 300, "the combined nodal limit set every step");
}
