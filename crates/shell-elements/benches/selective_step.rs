//! What selective mass scaling costs per explicit step: a 50 × 50 blank of
//! 1 mm steel shells (2,601 nodes, the square cup's size), clamped on one
//! edge and vibrating in bending, stepped by the solver at four times its
//! stable step, with conventional and with selective scaling (mass solve
//! tolerance 1e-4, the default). The two differ by the mass solve; each
//! benchmark is one `Solver::step`, and the selective one also prints the
//! mean conjugate-gradient iterations per solve.
//! Run: `cargo bench -p shell-elements --bench selective_step`.

use criterion::{Criterion, criterion_group, criterion_main};
use fem_core::{Dof, Dofs, MassScaling, Mesh, Solver, SolverSettings, rectangle};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};
use std::time::Duration;

fn solver(mesh: &Mesh, selective: bool) -> Solver {
    let mat = J2PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(1e30, 1.0, 0.0).unwrap(),
    )
    .unwrap();
    let set = ShellSet::from_mesh(
        "blank",
        mesh,
        "all",
        Section::new(1.0).unwrap(),
        BelytschkoTsay::default(),
        mat,
    )
    .unwrap();
    let probe = {
        let mut s = Solver::new(mesh, SolverSettings::default()).unwrap();
        s.add_effect(set.clone());
        s.initialize().unwrap().dt_initial
    };
    let mut settings = SolverSettings {
        mass_scaling_dt: Some(4.0 * probe),
        ..SolverSettings::default()
    };
    if selective {
        settings.mass_scaling = MassScaling::Selective {
            tolerance: MassScaling::DEFAULT_TOLERANCE,
        };
    }
    let mut s = Solver::new(mesh, settings).unwrap();
    s.add_effect(set);
    s.fix("x0", Dofs::of(&Dof::ALL)).unwrap();
    for (i, p) in mesh.nodes.iter().enumerate() {
        s.state_mut().v[i].z = 500.0 * (p.x / 50.0).powi(2) + 50.0 * (p.y / 10.0).sin();
    }
    for _ in 0..200 {
        s.step().unwrap();
    }
    s
}

fn steps(c: &mut Criterion) {
    let mesh = rectangle(50.0, 50.0, 50, 50).unwrap();
    let mut g = c.benchmark_group("selective_step_2500");
    g.measurement_time(Duration::from_secs(8));
    for (name, selective) in [("conventional", false), ("selective", true)] {
        let mut s = solver(&mesh, selective);
        g.bench_function(name, |b| b.iter(|| s.step().unwrap()));
        if let Some(st) = s.selective_stats() {
            println!(
                "selective: {:.1} iterations per solve (max {}), {} solves, added inertia {:.0} % of the mass",
                st.iterations as f64 / st.solves as f64,
                st.max_iterations,
                st.solves,
                100.0 * st.added_mass / s.state().mass.iter().sum::<f64>()
            );
        }
    }
    g.finish();
}

criterion_group!(benches, steps);
criterion_main!(benches);
