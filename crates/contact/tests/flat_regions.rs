//! Flat regions in the narrow phase: a pair whose points lie on the planar
//! face of the square-cup die answers most of them from the tool's flat
//! regions (`ToolSurface::flat_region`) instead of projecting them, with the
//! same contact as a pair on the same die with its planar shortcuts and
//! curved regions switched off (every projection by Newton).
//!
//! A 30 × 30 patch of blank (1 mm mesh) lies on the die face, pressed 0.01 mm
//! in, and drifts 3 µm per step towards the opening with a small jiggle, for
//! 400 steps: its first row starts 0.8 mm from the face's edge (the die
//! radius begins at x = 42 mm) and ends 0.4 mm past it, on the shoulder. Statuses must be equal and the nodal
//! forces, reactions and frictional dissipation equal to 1e-9 relative
//! (Newton stops at a step of 1e-11 mm; the plane's answer is exact).

use std::sync::atomic::{AtomicUsize, Ordering};

mod common;

use contact::{BlankGeometry, ContactPair, PairSpec};
use friction_laws::builtin;
use plugins_api::{
    Aabb, FlatRegion, Params, Projection, ProjectionHint, RigidPose, RigidVelocity, TangentMode,
    ToolError, ToolSurface, Vec3,
};
use tools_nurbs::NurbsTool;
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const T0: f64 = 0.78;
const DT: f64 = 1e-6;
const N: usize = 30;
const STEPS: usize = 400;

/// A tool that counts its projections.
struct Counting {
    tool: NurbsTool,
    projections: AtomicUsize,
}

impl ToolSurface for Counting {
    fn name(&self) -> &str {
        self.tool.name()
    }
    fn pose(&self) -> RigidPose {
        self.tool.pose()
    }
    fn set_pose(&mut self, pose: RigidPose, velocity: RigidVelocity) {
        self.tool.set_pose(pose, velocity);
    }
    fn velocity(&self) -> RigidVelocity {
        self.tool.velocity()
    }
    fn bounding_box(&self) -> Aabb {
        self.tool.bounding_box()
    }
    fn project(&self, x: &Vec3, hint: Option<ProjectionHint>) -> Result<Projection, ToolError> {
        self.projections.fetch_add(1, Ordering::Relaxed);
        self.tool.project(x, hint)
    }
    fn flat_region(&self, hint: &ProjectionHint) -> Option<FlatRegion> {
        self.tool.flat_region(hint)
    }
}

fn blank_at(base: &[Vec3], k: usize) -> Vec<Vec3> {
    let s = k as f64;
    base.iter()
        .enumerate()
        .map(|(i, p)| {
            let j = 1e-4 * (0.37 * s + 0.11 * i as f64).sin();
            Vec3::new(p.x - 3e-3 * s + j, p.y + j, 0.5 * T0 - 0.01 + j)
        })
        .collect()
}

/// Per step: statuses, nodal forces; at the end the dissipation; and the
/// projections the tool made.
type Run = (Vec<(Vec<contact::PointStatus>, Vec<Vec3>)>, f64, usize);

fn run(planar: bool) -> Run {
    let mut die = benchmark_quarter_die().unwrap();
    die.set_planar_path(planar);
    die.set_curved_regions(planar);
    let tool = Counting {
        tool: die,
        projections: AtomicUsize::new(0),
    };
    let mut mesh = fem_core::rectangle(30.0, 30.0, N, N).unwrap();
    mesh.nodes.iter_mut().for_each(|p| p.x += 42.8);
    let base = mesh.nodes.clone();
    let nn = base.len();
    let mut geometry = BlankGeometry::new(nn, &mesh.quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.144),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let x0 = blank_at(&base, 0);
    let mut pair =
        ContactPair::new(&PairSpec::new("die-blank", 0, 1.7e5), integ, &geometry, &x0).unwrap();
    let (mass, thickness) = (vec![1e-6; nn], vec![T0; nn]);
    let mut out = Vec::new();
    let mut prev = x0.clone();
    for k in 1..=STEPS {
        let x = blank_at(&base, k);
        let v: Vec<Vec3> = x.iter().zip(&prev).map(|(a, b)| (a - b) / DT).collect();
        let f = common::step_pair(
            &mut pair,
            &tool,
            &mut geometry,
            (&x0, &x, &v, &mass, &thickness),
            DT,
        );
        out.push((pair.status.clone(), f));
        prev = x;
    }
    (
        out,
        pair.energy.friction,
        tool.projections.load(Ordering::Relaxed),
    )
}

#[test]
fn flat_regions_give_the_contact_of_newton_projections() {
    let (fast, friction_fast, projected_fast) = run(true);
    let (slow, friction_slow, projected_slow) = run(false);
    let points = (N + 1) * (N + 1) * STEPS;
    println!(
        "projections: {projected_fast} with flat regions, {projected_slow} without, of {points} point-steps"
    );
    assert!(
        projected_fast * 5 < projected_slow,
        "flat regions saved too few projections: {projected_fast} of {projected_slow}"
    );
    let touching = |s: &[contact::PointStatus]| {
        s.iter()
            .filter(|p| **p != contact::PointStatus::Open)
            .count()
    };
    assert!(touching(&fast[STEPS - 1].0) > (N + 1) * (N + 1) / 2);
    for (step, ((sa, fa), (sb, fb))) in fast.iter().zip(&slow).enumerate() {
        assert_eq!(sa, sb, "step {}: statuses differ", step + 1);
        for (i, (a, b)) in fa.iter().zip(fb).enumerate() {
            assert!(
                (a - b).norm() <= 1e-9 * (1.0 + b.norm()),
                "step {}, node {i}: force {a} vs {b}",
                step + 1
            );
        }
    }
    assert!((friction_fast - friction_slow).abs() <= 1e-9 * friction_slow.abs());
}
