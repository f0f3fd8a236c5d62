//! Cost of the engine's own per-step work (nodal update, constraints, loads, ledger) per
//! node, with an effect that only adds a constant nodal force.
//!
//! Run: `cargo run --release -p fem-core --example engine_overhead`

use fem_core::{
    Control, Dof, Dofs, Effect, FemError, Forces, NodalLoad, NodalState, Solver, SolverSettings,
    StableDt, StepContext, rectangle,
};
use std::time::Instant;

/// Adds mass and a fixed stable time step; forces are a constant pull (no element work).
struct Lumped;

impl Effect for Lumped {
    fn name(&self) -> &str {
        "lumped"
    }
    fn add_lumped_mass(&self, _s: &NodalState, mass: &mut [f64], inertia: &mut [f64]) {
        mass.iter_mut().for_each(|m| *m += 1e-6);
        inertia.iter_mut().for_each(|j| *j += 1e-6);
    }
    fn stable_dt(&self, _s: &NodalState) -> Option<StableDt> {
        Some(StableDt {
            dt: 1e-7,
            element: 0,
            what: "fixed",
        })
    }
    fn add_forces(
        &mut self,
        _c: &StepContext,
        _s: &NodalState,
        f: &mut Forces,
        _fields: &mut fem_core::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        for fi in &mut f.f {
            fi.z += 1e-3;
        }
        Ok(())
    }
}

fn main() -> Result<(), FemError> {
    for (n, steps) in [(50usize, 20000u64), (100, 5000), (300, 500)] {
        let mesh = rectangle(100.0, 100.0, n, n)?;
        let settings = SolverSettings {
            damping: 10.0,
            ..Default::default()
        };
        let mut s = Solver::new(&mesh, settings)?;
        s.add_effect(Lumped);
        s.symmetry("x0", 0)?;
        s.symmetry("y0", 1)?;
        s.fix("x1", Dofs::ALL)?;
        s.add_load(&NodalLoad {
            set: "y1".into(),
            dof: Dof::Uy,
            value: 1.0,
            amplitude: fem_core::Amplitude::SmoothStep { t0: 0.0, t1: 1e-3 },
        })?;
        s.initialize()?;
        let t = Instant::now();
        let mut taken = 0u64;
        s.run_until(1.0, &mut |_, r| {
            taken = r.step;
            if r.step >= steps {
                Control::Stop
            } else {
                Control::Continue
            }
        })?;
        let ns = t.elapsed().as_secs_f64() * 1e9 / (taken as f64 * mesh.n_nodes() as f64);
        println!(
            "{:>6} nodes: {ns:.2} ns per node per step (engine only, {taken} steps, damping on)",
            mesh.n_nodes()
        );
    }
    Ok(())
}
