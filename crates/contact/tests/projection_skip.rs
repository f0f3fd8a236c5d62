//! Skipping far nodes (`PairSpec::skip_far`) and projecting in parallel must
//! not change the answer: a 40×40-quad patch of blank is driven (prescribed
//! motion, no dynamics) down onto the exact NURBS square-cup die, over the
//! opening's corner, the shoulder and the flat face, and up again, while part
//! of it sags deep into the opening, the die translates and rocks and the
//! blank's thickness varies. The pair is stepped with and without skipping,
//! and on one and on two threads, and the nodal forces, statuses and energies
//! are compared at every step. A last case rises through the die face from
//! its far side (contact within `max_penetration`).

mod common;

use contact::{BlankGeometry, BlankView, ContactEnergy, ContactPair, PairSpec, PointStatus};
use friction_laws::builtin;
use plugins_api::{Mat3, Params, RigidPose, RigidVelocity, TangentMode, ToolSurface, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const CELLS: usize = 40;
const STEPS: usize = 300;
const DT: f64 = 1e-5;
const T0: f64 = 0.78;

/// What one step produced.
struct Record {
    forces: Vec<Vec3>,
    status: Vec<PointStatus>,
    energy: ContactEnergy,
    reaction: Vec3,
}

/// The run's result and the pair's projection counters.
struct Run {
    records: Vec<Record>,
    /// Candidates so far: projected, or answered from a flat or curved region.
    projections: Vec<u64>,
    skipped: Vec<u64>,
}

fn grid() -> (Vec<Vec3>, Vec<[u32; 4]>) {
    let n = CELLS + 1;
    let mut x = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            x.push(Vec3::new(
                10.0 + 50.0 * i as f64 / CELLS as f64,
                10.0 + 50.0 * j as f64 / CELLS as f64,
                0.0,
            ));
        }
    }
    let mut q = Vec::new();
    for j in 0..CELLS {
        for i in 0..CELLS {
            let a = (j * n + i) as u32;
            q.push([a, a + 1, a + 1 + n as u32, a + n as u32]);
        }
    }
    (x, q)
}

/// Height of the mid-surface above the die face (mm) at step fraction `tau`:
/// 4 mm at the start, down to 0.33 at mid-run (0.06 mm into a 0.78 mm
/// blank), up to 3.33 at the end.
fn height(tau: f64) -> f64 {
    if tau <= 0.5 {
        0.33 + 3.67 * (1.0 - 2.0 * tau).powi(2)
    } else {
        0.33 + 3.0 * (2.0 * tau - 1.0).powi(2)
    }
}

/// How far (mm) the blank sags into the die opening at (x, y): up to 10 mm at
/// mid-run, 8 mm and more inside the opening's walls (x, y < 37).
fn sag(tau: f64, x: f64, y: f64) -> f64 {
    let inside = ((37.0 - x.max(y)) / 8.0).clamp(0.0, 1.0);
    10.0 * (std::f64::consts::PI * tau).sin() * inside * inside
}

/// Blank positions and thicknesses at step `k`.
fn blank_at(base: &[Vec3], k: usize) -> (Vec<Vec3>, Vec<f64>) {
    let tau = k as f64 / STEPS as f64;
    let slide = 3.0 * tau;
    let x = base
        .iter()
        .map(|p| {
            let wave = 0.1 * (0.4 * p.x + 6.0 * tau).sin() * (0.3 * p.y).cos();
            Vec3::new(
                p.x + slide,
                p.y - 0.5 * slide,
                height(tau) + wave - sag(tau, p.x, p.y),
            )
        })
        .collect();
    let t = (0..base.len())
        .map(|i| T0 * (1.0 + 0.03 * (6.3 * tau + 0.1 * i as f64).sin()))
        .collect();
    (x, t)
}

/// The die's pose at step `k`: a drift and a rock about a tilted axis.
fn die_pose(k: usize) -> RigidPose {
    let tau = k as f64 / STEPS as f64;
    let axis = Vec3::new(0.3, 1.0, 0.0).normalize();
    let angle = 0.01 * (2.0 * std::f64::consts::PI * tau).sin();
    RigidPose {
        translation: Vec3::new(
            0.5 * tau,
            -0.3 * tau,
            0.2 * (std::f64::consts::PI * tau).sin(),
        ),
        rotation: nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
            .into_inner(),
    }
}

/// Run the scenario with a pair of default settings but `skip_far` and, when
/// `tight`, no search margin and `max_penetration` = 1 (the reach of a node is
/// then exactly half its thickness: the skipping bound gets no slack).
fn run(skip_far: bool, tight: bool) -> Run {
    let mut tool = benchmark_quarter_die().unwrap();
    let (base, quads) = grid();
    let nn = base.len();
    let (x0, _) = blank_at(&base, 0);
    let geometry0 = BlankGeometry::new(nn, &quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.144),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let mut spec = PairSpec {
        skip_far,
        ..PairSpec::new("die-blank", 0, 1.7e5)
    };
    if tight {
        spec.search_margin = 0.0;
        spec.max_penetration = 1.0;
    }
    let mut pair = ContactPair::new(&spec, integ, &geometry0, &x0).unwrap();
    let mut g = geometry0;
    let mass = vec![1e-6; nn];
    let mut x_prev = x0.clone();
    let mut pose_prev = die_pose(0);
    let mut out = Run {
        records: Vec::new(),
        projections: Vec::new(),
        skipped: Vec::new(),
    };
    for k in 1..=STEPS {
        let (x, thickness) = blank_at(&base, k);
        let v: Vec<Vec3> = x.iter().zip(&x_prev).map(|(a, b)| (a - b) / DT).collect();
        let pose = die_pose(k);
        // Angular velocity from the step's rotation increment (small angle).
        let dr: Mat3 = pose.rotation * pose_prev.rotation.transpose();
        let w = Vec3::new(
            dr[(2, 1)] - dr[(1, 2)],
            dr[(0, 2)] - dr[(2, 0)],
            dr[(1, 0)] - dr[(0, 1)],
        ) * (0.5 / DT);
        tool.set_pose(
            pose,
            RigidVelocity {
                linear: (pose.translation - pose_prev.translation) / DT,
                angular: w,
            },
        );
        let view = BlankView {
            x0: &x0,
            x: &x,
            v: &v,
            mass: &mass,
            thickness: &thickness,
            flow_stress: None,
        };
        g.update(&view, DT, pair.needs());
        let mut f = vec![Vec3::zeros(); nn];
        pair.step(&tool, &g, &view, DT, &mut f).unwrap();
        out.records.push(Record {
            forces: f,
            status: pair.status.clone(),
            energy: pair.energy,
            reaction: pair.reaction.force,
        });
        out.projections
            .push(pair.projections + pair.flat_answers + pair.curved_answers);
        out.skipped.push(pair.skipped);
        x_prev = x;
        pose_prev = pose;
    }
    out
}

fn touching(r: &Record) -> usize {
    r.status.iter().filter(|s| **s != PointStatus::Open).count()
}

/// Skipping gives the same contact set at every step and the same forces and
/// energies, with the default margins and with none. Tolerance: the
/// closest-point Newton iteration of the NURBS tool stops at a relative step
/// of 1e-11 (tools-nurbs `STEP_TOL`), so a node projected from an older warm
/// start may land a few ulps away; forces are compared to 1e-9 of the largest
/// nodal force, energies to 1e-9 relative.
#[test]
fn skipping_far_nodes_changes_no_force_status_or_energy() {
    for tight in [false, true] {
        compare_skip(tight);
    }
}

fn compare_skip(tight: bool) {
    let full = run(false, tight);
    let skip = run(true, tight);
    let nn = (CELLS + 1) * (CELLS + 1);
    // The run must exercise what it checks: contact comes and goes, and many
    // node-steps are skipped (parts of the blank sag deep into the opening).
    let most = full.records.iter().map(touching).max().unwrap();
    assert!(most > nn / 3, "at most {most} of {nn} nodes touch");
    assert_eq!(
        touching(full.records.last().unwrap()),
        0,
        "the blank lifts off"
    );
    assert_eq!(*full.skipped.last().unwrap(), 0);
    let skipped = *skip.skipped.last().unwrap();
    assert!(
        skipped as f64 > 0.15 * (nn * STEPS) as f64,
        "tight {tight}: only {skipped} of {} node-steps skipped",
        nn * STEPS
    );
    assert!(*skip.projections.last().unwrap() + skipped == *full.projections.last().unwrap());
    let mut bit_equal_steps = 0;
    for (k, (a, b)) in full.records.iter().zip(&skip.records).enumerate() {
        let step = k + 1;
        assert_eq!(
            a.status, b.status,
            "tight {tight}, step {step}: contact status differs"
        );
        let scale = a.forces.iter().map(|f| f.norm()).fold(0.0, f64::max);
        let worst = a
            .forces
            .iter()
            .zip(&b.forces)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-9 * scale + 1e-12,
            "tight {tight}, step {step}: nodal forces differ by {worst} N (largest {scale} N)"
        );
        if worst == 0.0 {
            bit_equal_steps += 1;
        }
        assert!((a.reaction - b.reaction).norm() <= 1e-9 * a.reaction.norm() + 1e-12);
        for (name, p, q) in [
            ("friction", a.energy.friction, b.energy.friction),
            ("tool_work", a.energy.tool_work, b.energy.tool_work),
            ("blank_work", a.energy.blank_work, b.energy.blank_work),
            ("stored", a.energy.stored, b.energy.stored),
        ] {
            assert!(
                (p - q).abs() <= 1e-9 * p.abs().max(1e-9),
                "tight {tight}, step {step}: energy `{name}` {p} vs {q}"
            );
        }
    }
    eprintln!(
        "skip_far (tight {tight}): {skipped} of {} node-steps skipped; \
         {bit_equal_steps} of {STEPS} steps bit-for-bit",
        nn * STEPS
    );
}

/// Projection and friction in parallel land every answer in its own slot and
/// the forces are summed after them in node order, so one and two threads
/// must agree bit for bit (exact comparison).
#[test]
fn two_threads_give_the_same_bits_as_one() {
    for skip_far in [false, true] {
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(skip_far, false))
        };
        let one = on(1);
        let two = on(2);
        // The parallel path (more than 512 candidates) must have been taken.
        let per_step = one
            .projections
            .windows(2)
            .map(|w| w[1] - w[0])
            .max()
            .unwrap();
        assert!(
            per_step > ContactPair::PARALLEL_MIN_CANDIDATES as u64,
            "{per_step}"
        );
        for (k, (a, b)) in one.records.iter().zip(&two.records).enumerate() {
            assert_eq!(a.status, b.status, "skip_far {skip_far}, step {}", k + 1);
            assert_eq!(a.forces, b.forces, "skip_far {skip_far}, step {}", k + 1);
            assert_eq!(a.energy, b.energy, "skip_far {skip_far}, step {}", k + 1);
            assert_eq!(
                a.reaction,
                b.reaction,
                "skip_far {skip_far}, step {}",
                k + 1
            );
        }
    }
}

/// A node deep on the far side of a tool surface counts as touching once it is
/// within `max_penetration` thicknesses (less half) of it, so skipping must
/// keep such nodes in reach too: one quad rises at 0.25 mm per step from 6 mm
/// under the die's flat face to 4 mm above it, with no search margin, and the
/// statuses and forces must match the run without skipping exactly (no
/// projection here is warm-started differently: the quad is projected every
/// step once in reach in both runs).
#[test]
fn far_side_nodes_within_max_penetration_are_not_skipped() {
    let run = |skip_far: bool| {
        let tool = benchmark_quarter_die().unwrap();
        let quads = [[0u32, 1, 2, 3]];
        let base = [(60.0, 60.0), (61.0, 60.0), (61.0, 61.0), (60.0, 61.0)];
        let at = |z: f64| -> Vec<Vec3> { base.iter().map(|&(x, y)| Vec3::new(x, y, z)).collect() };
        let x0 = at(-6.0);
        let mut g = BlankGeometry::new(4, &quads).unwrap();
        let integ = builtin::integrator(
            "ac",
            &Params::new().with("mu", 0.144),
            "convective",
            TangentMode::None,
        )
        .unwrap();
        let spec = PairSpec {
            skip_far,
            search_margin: 0.0,
            ..PairSpec::new("die-blank", 0, 1.7e5)
        };
        let mut pair = ContactPair::new(&spec, integ, &g, &x0).unwrap();
        let mass = [1e-6; 4];
        let thickness = [T0; 4];
        let v = [Vec3::new(0.0, 0.0, 0.25 / DT); 4];
        let mut out = Vec::new();
        for k in 1..=40 {
            let z = -6.0 + 0.25 * k as f64;
            let x = at(z);
            let blank = (&x0[..], &x[..], &v[..], &mass[..], &thickness[..]);
            let f = common::step_pair(&mut pair, &tool, &mut g, blank, DT);
            out.push((z, pair.status.clone(), f));
        }
        (out, pair.skipped)
    };
    let (full, _) = run(false);
    let (skip, skipped) = run(true);
    assert!(
        skipped > 0,
        "the quad starts out of reach and must be skipped"
    );
    // Far-side contact happens: touching while the mid-surface is more than
    // half a thickness under the face.
    assert!(
        full.iter()
            .any(|(z, s, _)| *z < -0.5 * T0 && s[0] != PointStatus::Open),
        "no far-side contact in the run"
    );
    for ((z, sa, fa), (_, sb, fb)) in full.iter().zip(&skip) {
        assert_eq!(sa, sb, "z = {z} mm: status differs");
        assert_eq!(fa, fb, "z = {z} mm: forces differ");
    }
}
