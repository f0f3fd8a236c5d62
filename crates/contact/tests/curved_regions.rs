//! Curved regions in the narrow phase: a pair whose points lie over the
//! shoulder radius of the square-cup die (a cylinder along the side, a torus
//! at the corner) answers most of them from the tool's curved regions
//! (`ToolSurface::curved_region`) instead of projecting them, with the same
//! contact as a pair on the same die with its regions switched off (every
//! projection by Newton).
//!
//! A 24 × 24-quad patch of blank is wrapped over the shoulder: node `(a, b)`
//! sits half its thickness less 0.01 mm (with a small jiggle) above the
//! die's closest point to a reference point 7 mm from the shoulder's axis,
//! at the angle `φ` from the face (−10° to 100°, so some nodes lie over the
//! face and the opening wall) and at `y` from 12 to 32 mm (the side radius
//! ends and the corner torus begins at 25 mm). The reference grid turns
//! 0.01° and moves 3 µm along y per step, for 300 steps, so nodes cross the
//! seams. Statuses must be equal and the nodal forces and the frictional
//! dissipation equal to 1e-9 relative (Newton stops at a step of 1e-11 mm;
//! the closed form is exact). With regions a fifth larger than their patches
//! the same comparison must fail.

use std::sync::atomic::{AtomicUsize, Ordering};

mod common;

use contact::{BlankGeometry, ContactPair, PairSpec};
use friction_laws::builtin;
use plugins_api::{
    Aabb, CurvedRegion, CurvedShape, FlatRegion, Params, Projection, ProjectionHint, RigidPose,
    RigidVelocity, TangentMode, ToolError, ToolSurface, Vec3,
};
use tools_nurbs::NurbsTool;
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

const T0: f64 = 0.78;
const DT: f64 = 1e-6;
const N: usize = 24;
const STEPS: usize = 300;

/// A tool that counts its projections and can enlarge its curved regions.
struct Counting {
    tool: NurbsTool,
    projections: AtomicUsize,
    /// Factor on the curved regions' angles and lengths (1: as the tool gives them).
    enlarge: f64,
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
    fn curved_region(&self, hint: &ProjectionHint) -> Option<CurvedRegion> {
        let r = self.tool.curved_region(hint)?;
        let f = self.enlarge;
        let wider = |c: f64| (c.acos() * f).min(std::f64::consts::PI).cos();
        let shape = match r.shape {
            CurvedShape::Cylinder { along } => {
                let (m, h) = (0.5 * (along[0] + along[1]), 0.5 * (along[1] - along[0]));
                CurvedShape::Cylinder {
                    along: [m - f * h, m + f * h],
                }
            }
            CurvedShape::Torus {
                spine,
                tube_mid,
                tube_cos,
            } => CurvedShape::Torus {
                spine,
                tube_mid,
                tube_cos: wider(tube_cos),
            },
        };
        Some(CurvedRegion {
            cos_half: wider(r.cos_half),
            shape,
            ..r
        })
    }
}

/// The blank's nodes at step `k`: over the die's closest points to the
/// reference grid (see the module docs).
fn blank_at(die: &NurbsTool, k: usize) -> Vec<Vec3> {
    let s = k as f64;
    let mut x = Vec::with_capacity((N + 1) * (N + 1));
    for a in 0..=N {
        for b in 0..=N {
            let i = (a * (N + 1) + b) as f64;
            let phi = (-10.0 + 110.0 * a as f64 / N as f64 + 0.01 * s).to_radians();
            let y = 12.0 + 20.0 * b as f64 / N as f64 + 3e-3 * s;
            let reference = Vec3::new(42.0 - 7.0 * phi.sin(), y, -5.0 + 7.0 * phi.cos());
            let p = die.project(&reference, None).unwrap();
            let j = 1e-4 * (0.37 * s + 0.11 * i).sin();
            x.push(p.point + p.normal * (0.5 * T0 - 0.01 + j));
        }
    }
    x
}

/// Per step: statuses, nodal forces; at the end the dissipation; and the
/// projections the tool made and the curved answers.
type Run = (Vec<(Vec<contact::PointStatus>, Vec<Vec3>)>, f64, usize, u64);

fn run(regions: bool, enlarge: f64) -> Run {
    let reference = benchmark_quarter_die().unwrap();
    let mut die = reference.clone();
    die.set_planar_path(regions);
    die.set_curved_regions(regions);
    let tool = Counting {
        tool: die,
        projections: AtomicUsize::new(0),
        enlarge,
    };
    let mesh = fem_core::rectangle(1.0, 1.0, N, N).unwrap();
    let x0 = blank_at(&reference, 0);
    let nn = x0.len();
    let mut geometry = BlankGeometry::new(nn, &mesh.quads).unwrap();
    let integ = builtin::integrator(
        "ac",
        &Params::new().with("mu", 0.144),
        "convective",
        TangentMode::None,
    )
    .unwrap();
    let mut pair =
        ContactPair::new(&PairSpec::new("die-blank", 0, 1.7e5), integ, &geometry, &x0).unwrap();
    let (mass, thickness) = (vec![1e-6; nn], vec![T0; nn]);
    let mut out = Vec::new();
    let mut prev = x0.clone();
    for k in 1..=STEPS {
        let x = blank_at(&reference, k);
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
        pair.curved_answers,
    )
}

/// The first step and node where `fast` departs from `slow` (statuses not
/// equal, or a force off by more than 1e-9 relative), or the dissipation.
fn first_difference(fast: &Run, slow: &Run) -> Option<String> {
    for (step, ((sa, fa), (sb, fb))) in fast.0.iter().zip(&slow.0).enumerate() {
        if sa != sb {
            return Some(format!("step {}: statuses differ", step + 1));
        }
        for (i, (a, b)) in fa.iter().zip(fb).enumerate() {
            if (a - b).norm() > 1e-9 * (1.0 + b.norm()) {
                return Some(format!("step {}, node {i}: force {a} vs {b}", step + 1));
            }
        }
    }
    ((fast.1 - slow.1).abs() > 1e-9 * slow.1.abs())
        .then(|| format!("dissipation {} vs {}", fast.1, slow.1))
}

#[test]
fn curved_regions_give_the_contact_of_newton_projections_over_the_die_shoulder() {
    let fast = run(true, 1.0);
    let slow = run(false, 1.0);
    let points = (N + 1) * (N + 1) * STEPS;
    println!(
        "projections: {} with regions ({} curved answers), {} without, of {points} point-steps",
        fast.2, fast.3, slow.2
    );
    assert!(
        fast.3 as usize * 2 > points,
        "curved regions answered only {} of {points} point-steps",
        fast.3
    );
    assert!(
        fast.2 * 4 < slow.2,
        "regions saved too few projections: {} of {}",
        fast.2,
        slow.2
    );
    let touching = |s: &[contact::PointStatus]| {
        s.iter()
            .filter(|p| **p != contact::PointStatus::Open)
            .count()
    };
    assert!(touching(&fast.0[STEPS - 1].0) > (N + 1) * (N + 1) / 2);
    if let Some(d) = first_difference(&fast, &slow) {
        panic!("curved regions changed the contact: {d}");
    }
}

#[test]
fn curved_regions_a_fifth_too_large_change_the_contact() {
    let fast = run(true, 1.2);
    let slow = run(false, 1.0);
    let d = first_difference(&fast, &slow);
    println!("enlarged regions: {d:?}");
    assert!(d.is_some(), "enlarged curved regions went unnoticed");
}
