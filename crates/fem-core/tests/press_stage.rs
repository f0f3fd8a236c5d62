//! The press is a stage of the solver's step (stage 3): it moves the tools to
//! `t_{n+1}` before any effect computes forces, the effects read it through
//! `StepContext::press`, and what they report on the tools
//! (`Effect::tool_loads`) reaches the force-controlled tools in the next step.

use fem_core::{
    Dofs, Effect, FemError, FieldAccess, ForceLaw, Forces, NodalState, Press, PressStep, Solver,
    SolverSettings, StepContext, StepEnd, ToolLoad, ToolMotion, Vec3,
};
use plugins_api::RigidPose;
use std::collections::BTreeMap;

/// Tool 0 travels down at this speed (mm/s).
const SPEED: f64 = 100.0;
/// Tool 1 is pushed down with this force (N).
const FORCE: f64 = 50.0;

/// Records where the press put tool 0 at each step, and pushes back on tool 1
/// with `push` (N, along +z).
struct Seat {
    push: f64,
    loads: Vec<ToolLoad>,
    /// `(time, z of tool 0)` seen in each force computation.
    seen: Vec<(f64, f64)>,
}

impl Effect for Seat {
    fn name(&self) -> &str {
        "seat"
    }
    fn add_forces(
        &mut self,
        ctx: &StepContext<'_>,
        _state: &NodalState,
        _forces: &mut Forces,
        _fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let press = ctx.press.expect("the solver has a press");
        self.seen.push((ctx.time, press.pose(0).translation.z));
        self.loads[1].force = Vec3::new(0.0, 0.0, self.push);
        Ok(())
    }
    fn tool_loads(&self) -> &[ToolLoad] {
        &self.loads
    }
}

/// A fixed node, a press of two tools (one at constant speed, one
/// force-controlled) and a [`Seat`] pushing back on the force-controlled one.
fn solver(push: f64) -> (Solver, fem_core::EffectId) {
    let sets = BTreeMap::from([("all".to_string(), vec![0])]);
    let settings = SolverSettings {
        dt_max: Some(1e-5),
        ..SolverSettings::default()
    };
    let mut s = Solver::from_nodes(&[Vec3::zeros()], sets, settings).unwrap();
    s.fix("all", Dofs::ALL).unwrap();
    let down = -Vec3::z();
    let step = PressStep {
        name: "draw".into(),
        end: StepEnd::Duration(1e-3),
        motions: vec![
            (
                0,
                ToolMotion::Velocity {
                    direction: down,
                    speed: SPEED,
                    amplitude: None,
                },
            ),
            (
                1,
                ToolMotion::Force {
                    direction: down,
                    force: ForceLaw::Constant(FORCE),
                    amplitude: None,
                    mass: 1e-3,
                    damping: 0.0,
                    relative_damping: 0.0,
                },
            ),
        ],
        active_pairs: None,
    };
    let names = ["punch".to_string(), "holder".to_string()];
    let press = Press::new(&names, &[RigidPose::default(); 2], vec![step]).unwrap();
    s.set_press(press).unwrap();
    let id = s.add_effect(Seat {
        push,
        loads: vec![ToolLoad::default(); 2],
        seen: Vec::new(),
    });
    (s, id)
}

/// Every effect sees the tools where the press put them for the time of
/// its force computation: `z = −v t` to rounding.
#[test]
fn effects_read_the_press_at_the_time_of_their_forces() {
    let (mut s, id) = solver(FORCE);
    for _ in 0..50 {
        s.step().unwrap();
    }
    let seat: &Seat = s.effect(id).unwrap();
    // The set-up computation (t = 0) and 50 steps.
    assert_eq!(seat.seen.len(), 51);
    for &(t, z) in &seat.seen {
        assert!((z + SPEED * t).abs() < 1e-12, "t = {t}: z = {z}");
    }
    assert!(seat.seen.last().unwrap().0 > 4.9e-4);
}

/// A force-controlled tool held by an equal reaction from an effect stays
/// where it is; without the reaction it accelerates at `F/m`: the loads the
/// effects report reach the press.
#[test]
fn the_press_reads_the_loads_the_effects_report() {
    let (mut held, _) = solver(FORCE);
    let (mut free, _) = solver(0.0);
    for _ in 0..100 {
        held.step().unwrap();
        free.step().unwrap();
    }
    let z_held = held.press().unwrap().displacement(1).z;
    let z_free = free.press().unwrap().displacement(1).z;
    assert!(z_held.abs() < 1e-12, "held tool moved {z_held} mm");
    // s = F t² / (2 m) over t = 1 ms with F/m = 5e4 mm/s²: 0.025 mm, down.
    let t = free.time();
    let expected = -FORCE / 1e-3 * t * t / 2.0;
    assert!(
        (z_free / expected - 1.0).abs() < 0.02,
        "free tool at {z_free} mm, F t²/2m = {expected} mm"
    );
    assert_eq!(held.tool_loads()[1].force.z, FORCE);
}
