//! Contact reads the blank's thickness of the current step from the shared
//! field its writer fills in the same step (fem-core's shared fields): with
//! the blank's shells, the thickness contact reads at step n is the shells'
//! nodal thickness at step n, not step n − 1; with a writer that toggles the
//! thickness every step, the gap follows the toggle in the same step. The
//! nodal areas and normals the shells write from their element frames are
//! those contact would compute itself from the same positions.

mod common;
use common::Plane;
use contact::{BlankGeometry, ContactEffect, ContactPair, PairSpec, PointStatus};
use fem_core::{
    Amplitude, Control, Dof, Dofs, Effect, EffectId, FemError, FieldAccess, Forces, MotionKind,
    NodalField, NodalState, Solver, SolverSettings, StepContext, Vec3, rectangle,
};
use friction_laws::builtin;
use plugins_api::{Params, RigidPose, RigidVelocity, TangentMode, ToolSurface};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};
use std::collections::BTreeMap;

type Shells = ShellSet<BelytschkoTsay, J2PlaneStress>;

/// Contact of the blank `nodes`/`quads` (thickness `t0`) against the plane `z = 0`.
fn contact_on_plane(nodes: &[Vec3], quads: &[[u32; 4]], t0: f64) -> ContactEffect {
    let geometry = BlankGeometry::new(nodes.len(), quads).unwrap();
    let law = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.1),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let pair = ContactPair::new(
        &PairSpec::new("plane-blank", 0, 1.7e5),
        law,
        &geometry,
        nodes,
    )
    .unwrap();
    let plane: Box<dyn ToolSurface> = Box::new(Plane {
        pose: RigidPose::default(),
        vel: RigidVelocity::default(),
    });
    ContactEffect::new(vec![plane], vec![pair], geometry, vec![t0; nodes.len()]).unwrap()
}

/// A solver with contact on the plane (added first) and steel shells of
/// thickness `t0` over `mesh`, pulled at x1 at 2 m/s with x0 and y0 held and
/// out-of-plane motion fixed; returns it with the contact and shell ids.
fn stretched_plate(mesh: &fem_core::Mesh, t0: f64) -> (Solver, EffectId, EffectId) {
    let settings = SolverSettings {
        mass_scaling_dt: Some(2e-7),
        ..SolverSettings::default()
    };
    let mut solver = Solver::new(mesh, settings).unwrap();
    let cid = solver.add_effect(contact_on_plane(&mesh.nodes, &mesh.quads, t0));
    let steel = J2PlaneStress::new(
        2.06e5,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap();
    let sid = solver.add_effect(
        ShellSet::new(
            "blank",
            &mesh.nodes,
            &mesh.quads,
            Section::new(t0).unwrap(),
            BelytschkoTsay::default(),
            steel,
        )
        .unwrap(),
    );
    solver.fix("x0", Dofs::of(&[Dof::Ux])).unwrap();
    solver.fix("y0", Dofs::of(&[Dof::Uy])).unwrap();
    solver
        .fix("all", Dofs::of(&[Dof::Uz, Dof::Rx, Dof::Ry]))
        .unwrap();
    solver
        .prescribe(
            "x1",
            Dof::Ux,
            MotionKind::Velocity,
            2e3,
            Amplitude::Constant,
        )
        .unwrap();
    (solver, cid, sid)
}

/// `Σ_e∋n t_e / valence(n)` of the shells' current element thickness.
fn nodal_thickness(shells: &Shells, nodes: usize) -> Vec<f64> {
    let mut sum = vec![0.0; nodes];
    let mut valence = vec![0usize; nodes];
    for (e, q) in shells.quads().iter().enumerate() {
        for &n in q {
            sum[n as usize] += shells.thickness(e);
            valence[n as usize] += 1;
        }
    }
    sum.iter()
        .zip(&valence)
        .map(|(s, &v)| s * (1.0 / v as f64))
        .collect()
}

/// A 3 × 2 plate of shells on the plane, stretched into plasticity so that
/// it thins every step, with contact added before the shells. After every
/// step the thickness contact read equals the shells' nodal thickness of
/// that step (exactly) and differs from the previous step's.
#[test]
fn contact_reads_the_shells_thickness_of_the_same_step() {
    let t0 = 1.0;
    let mut mesh = rectangle(30.0, 20.0, 3, 2).unwrap();
    mesh.nodes.iter_mut().for_each(|p| p.z = 0.5 * t0);
    let (mut solver, cid, sid) = stretched_plate(&mesh, t0);
    solver.initialize().unwrap();
    assert_eq!(solver.effect_order(), &[sid.0, cid.0]);
    let n = mesh.nodes.len();
    let mut previous = vec![t0; n];
    let mut steps = 0;
    solver
        .run_until(1e-4, &mut |s: &Solver, _| {
            let shells: &Shells = s.effect(sid).unwrap();
            let now = nodal_thickness(shells, n);
            let read = s.field(NodalField::THICKNESS).expect("contact reads it");
            assert_eq!(read, &now[..], "step {}", s.steps());
            assert_ne!(now, previous, "step {}: the plate did not thin", s.steps());
            previous = now;
            steps += 1;
            Control::Continue
        })
        .unwrap();
    assert!(steps > 100, "{steps} steps");
    assert!(previous[0] < 0.998 * t0, "{}", previous[0]);
}

/// A warped 6 × 4 plate of shells stretched into plasticity: after every
/// step the nodal areas and normals contact read from the shells' shared
/// fields equal those of contact's own quad geometry
/// ([`BlankGeometry::update_areas`]) at the step's positions, to 1e-12
/// relative (the same quantities, `¼ Σ ½ |d₁₃ × d₂₄|` and the
/// area-weighted mean of the normals, rounded in another order).
#[test]
fn contact_reads_the_shells_nodal_area_and_normal_of_the_same_step() {
    let t0 = 1.0;
    let mut mesh = rectangle(30.0, 20.0, 6, 4).unwrap();
    mesh.nodes
        .iter_mut()
        .for_each(|p| p.z = 0.5 * t0 + 0.8 * (0.2 * p.x).sin() * (0.3 * p.y).cos());
    let (mut solver, cid, _) = stretched_plate(&mesh, t0);
    let mut own = BlankGeometry::new(mesh.nodes.len(), &mesh.quads).unwrap();
    let mut steps = 0;
    solver
        .run_until(5e-5, &mut |s: &Solver, _| {
            let c: &ContactEffect = s.effect(cid).unwrap();
            own.update_areas(&s.state().x);
            let shared = c.geometry();
            assert_eq!(
                shared.nodal_evaluations, 0,
                "contact computed its own areas"
            );
            let tilted = own.normal.iter().filter(|n| n.z.abs() < 0.999).count();
            assert!(2 * tilted > mesh.nodes.len(), "the plate is not warped");
            for i in 0..mesh.nodes.len() {
                let (a, b) = (shared.area[i], own.area[i]);
                assert!(
                    (a - b).abs() <= 1e-12 * b,
                    "step {}, node {i}: area {a} vs {b}",
                    s.steps()
                );
                let (m, n) = (shared.normal[i], own.normal[i]);
                assert!(
                    (m - n).norm() <= 1e-12,
                    "step {}, node {i}: normal {m} vs {n}",
                    s.steps()
                );
            }
            steps += 1;
            Control::Continue
        })
        .unwrap();
    assert!(steps > 50, "{steps} steps");
}

/// Writes a nodal thickness of 1.2 mm at even steps and 1.0 mm at odd ones.
struct Toggle;

impl Effect for Toggle {
    fn name(&self) -> &str {
        "toggle"
    }
    fn writes(&self) -> &[NodalField] {
        &[NodalField::THICKNESS]
    }
    fn add_forces(
        &mut self,
        ctx: &StepContext,
        _state: &NodalState,
        _forces: &mut Forces,
        fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        if let Some(t) = fields.write(NodalField::THICKNESS) {
            t.fill(if ctx.step.is_multiple_of(2) { 1.2 } else { 1.0 });
        }
        Ok(())
    }
}

/// Four nodes held 0.55 mm above the plane: with this step's thickness the
/// blank face penetrates at even steps (half thickness 0.6 mm) and is clear
/// at odd ones (0.5 mm). A one-step lag would invert the pattern.
#[test]
fn the_gap_uses_the_thickness_written_in_the_same_step() {
    let nodes: Vec<Vec3> = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]
        .iter()
        .map(|&(x, y)| Vec3::new(x, y, 0.55))
        .collect();
    let sets = BTreeMap::from([("all".to_string(), vec![0, 1, 2, 3])]);
    let settings = SolverSettings {
        dt_max: Some(1e-5),
        ..SolverSettings::default()
    };
    let mut solver = Solver::from_nodes(&nodes, sets, settings).unwrap();
    let cid: EffectId = solver.add_effect(contact_on_plane(&nodes, &[[0, 1, 2, 3]], 1.0));
    solver.add_effect(Toggle);
    solver.add_point_mass("all", 1e-3, 0.0).unwrap();
    solver.fix("all", Dofs::ALL).unwrap();
    solver
        .run_until(2e-4, &mut |s: &Solver, r| {
            let c: &ContactEffect = s.effect(cid).unwrap();
            let even = r.step.is_multiple_of(2);
            let read = s.field(NodalField::THICKNESS).expect("contact reads it");
            assert_eq!(read, &[if even { 1.2 } else { 1.0 }; 4]);
            let touching = c.pairs()[0]
                .status
                .iter()
                .all(|st| *st != PointStatus::Open);
            let open = c.pairs()[0]
                .status
                .iter()
                .all(|st| *st == PointStatus::Open);
            assert!(if even { touching } else { open }, "step {}", r.step);
            Control::Continue
        })
        .unwrap();
}
