//! The opt-in friction record (`ContactPair::record_friction`): a pair that
//! records gives the same bits as one that does not, and its record holds
//! the history, the inputs with every kinematic field filled (`L`, `F_n`,
//! `F_{n+1}`, the tool's rotation) and the outputs of every touching point.
//!
//! Set-up: a 10 × 10 patch of blank (1 mm mesh) pressed 0.01 mm into the
//! face of the exact square-cup die, drifting 3 µm per step towards the
//! opening with a small stretch and a jiggle, for 200 steps, AC μ = 0.144,
//! convective (which declares only the tool's rotation) and jaumann.

mod common;

use contact::{BlankGeometry, ContactPair, PairSpec, PointStatus};
use friction_laws::builtin;
use plugins_api::{Mat3, Params, TangentMode, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const T0: f64 = 0.78;
const DT: f64 = 1e-6;
const N: usize = 10;
const STEPS: usize = 200;

fn blank_at(base: &[Vec3], k: usize) -> Vec<Vec3> {
    let s = k as f64;
    base.iter()
        .enumerate()
        .map(|(i, p)| {
            let j = 1e-4 * (0.37 * s + 0.11 * i as f64).sin();
            let stretch = 1.0 + 1e-5 * s;
            Vec3::new(
                42.0 + (p.x - 42.0) * stretch - 3e-3 * s + j,
                p.y * stretch + j,
                0.5 * T0 - 0.01 + j,
            )
        })
        .collect()
}

/// Per step the nodal forces and, when recording, the record's length and
/// whether its kinematics were all filled.
fn run(formulation: &str, record: bool) -> (Vec<Vec<Vec3>>, usize) {
    let die = benchmark_quarter_die().unwrap();
    let mut mesh = fem_core::rectangle(10.0, 10.0, N, N).unwrap();
    mesh.nodes.iter_mut().for_each(|p| p.x += 36.5);
    let base = mesh.nodes.clone();
    let nn = base.len();
    let mut geometry = BlankGeometry::new(nn, &mesh.quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.144),
        formulation,
        TangentMode::None,
    )
    .unwrap();
    let x0 = blank_at(&base, 0);
    let mut pair =
        ContactPair::new(&PairSpec::new("die-blank", 0, 1.7e5), integ, &geometry, &x0).unwrap();
    pair.record_friction(record);
    let (mass, thickness) = (vec![1e-6; nn], vec![T0; nn]);
    let (mut out, mut recorded) = (Vec::new(), 0);
    let mut prev = x0.clone();
    for k in 1..=STEPS {
        let x = blank_at(&base, k);
        let v: Vec<Vec3> = x.iter().zip(&prev).map(|(a, b)| (a - b) / DT).collect();
        let f = common::step_pair(
            &mut pair,
            &die,
            &mut geometry,
            (&x0, &x, &v, &mass, &thickness),
            DT,
        );
        if let Some(r) = pair.friction_record() {
            let touching = pair
                .status
                .iter()
                .filter(|s| **s != PointStatus::Open)
                .count();
            assert_eq!(r.points.len(), touching, "step {k}");
            assert_eq!(r.inputs.len(), touching);
            assert_eq!(r.history.len(), touching);
            assert_eq!(r.outputs.len(), touching);
            for (i, (&pk, o)) in r.points.iter().zip(&r.outputs).enumerate() {
                assert_eq!(o.t, pair.traction[pk as usize], "step {k}, point {pk}");
                let kin = &r.inputs[i].kin;
                // The stretch makes L and F differ from their neutral values.
                assert!(kin.vel_grad != Mat3::zeros() && kin.f_new != Mat3::identity());
                assert!(kin.f_old != Mat3::identity());
            }
            recorded += touching;
        } else {
            assert!(!record);
        }
        out.push(f);
        prev = x;
    }
    (out, recorded)
}

#[test]
fn recording_the_friction_stage_changes_no_bit() {
    for formulation in ["convective", "jaumann"] {
        let (plain, none) = run(formulation, false);
        let (recorded, points) = run(formulation, true);
        assert_eq!(none, 0);
        // At least a row of points touching at every step.
        assert!(points > STEPS * N, "{formulation}: {points}");
        assert_eq!(
            plain, recorded,
            "{formulation}: forces differ with the record"
        );
    }
}

/// A plate spinning rigidly about the normal of a fixed flat tool (θ = 1e-3
/// rad per step about its centre, pressed 0.01 mm in, AC μ = 0.1,
/// convective, recording): the spin the contact geometry measures turns
/// the history of jaumann, updated-lagrangian and lagrangian by θ about the
/// normal in the sense of the spin, while convective's stays put (the
/// normal does not turn). This is what makes the formulations differ on a
/// fixed tool: the blank's spin about the normal, `(w·n) Δt` per step.
/// Tolerance: 1e-6 relative on the angle (the chord velocity's spin is
/// `sin θ / Δt` and the Cayley angle `2 atan(sin θ / 2)`, both θ to O(θ³))
/// and on `|t*|/|t_n|` (the chord velocity's symmetric part `(1 − cos θ)/Δt`
/// stretches updated-lagrangian's by θ²/2 = 5e-7); convective exactly
/// (`n_{n+1} = n_n`).
#[test]
fn a_spinning_plate_turns_the_spin_formulations_history_and_not_convectives() {
    use friction_laws::formulations::{Convective, Jaumann, Lagrangian, UpdatedLagrangian};
    use plugins_api::{KinematicFormulation, RigidPose, RigidVelocity};
    let theta: f64 = 1e-3;
    let mesh = fem_core::rectangle(4.0, 4.0, 4, 4).unwrap();
    let nn = mesh.nodes.len();
    let at = |k: usize| -> Vec<Vec3> {
        let (s, c) = (theta * k as f64).sin_cos();
        mesh.nodes
            .iter()
            .map(|p| {
                let (x, y) = (p.x - 2.0, p.y - 2.0);
                Vec3::new(c * x - s * y, s * x + c * y, 0.5 * T0 - 0.01)
            })
            .collect()
    };
    let plane = common::Plane {
        pose: RigidPose::default(),
        vel: RigidVelocity::default(),
    };
    let mut geometry = BlankGeometry::new(nn, &mesh.quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.1),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let x0 = at(0);
    let mut pair = ContactPair::new(
        &PairSpec::new("plane-blank", 0, 1.7e5),
        integ,
        &geometry,
        &x0,
    )
    .unwrap();
    pair.record_friction(true);
    let (mass, thickness) = (vec![1e-6; nn], vec![T0; nn]);
    let mut checked = 0;
    for k in 1..=4 {
        let (x, prev) = (at(k), at(k - 1));
        let v: Vec<Vec3> = x.iter().zip(&prev).map(|(a, b)| (a - b) / DT).collect();
        common::step_pair(
            &mut pair,
            &plane,
            &mut geometry,
            (&x0, &x, &v, &mass, &thickness),
            DT,
        );
        let r = pair.friction_record().unwrap();
        for (h, input) in r.history.iter().zip(&r.inputs) {
            if h.t.norm() == 0.0 {
                continue;
            }
            let kin = &input.kin;
            assert_eq!(Convective.transport(&h.t, kin), h.t, "step {k}");
            for (name, f) in [
                ("jaumann", &Jaumann as &dyn KinematicFormulation),
                ("updated-lagrangian", &UpdatedLagrangian),
                ("lagrangian", &Lagrangian),
            ] {
                let t = f.transport(&h.t, kin);
                let turn = h.t.cross(&t).z.atan2(h.t.dot(&t));
                assert!(
                    (turn / theta - 1.0).abs() < 1e-6 && (t.norm() / h.t.norm() - 1.0).abs() < 1e-6,
                    "{name}, step {k}: turned {turn} rad (θ = {theta}), |t*|/|t_n| = {}",
                    t.norm() / h.t.norm()
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 3 * nn / 2, "{checked} points with a history");
}
