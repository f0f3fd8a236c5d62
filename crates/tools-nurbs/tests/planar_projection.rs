//! The planar warm projection (`tools_nurbs::planar`) against Newton.
//!
//! On every planar patch of the square cup's and the S-rail's tools, points
//! at random heights above and below random points of the patch (and beyond
//! its edges) are projected warm-started from the answer of a nearby point,
//! once with the planar closed form and once with Newton alone. The answers
//! must agree: the same patch, point and signed distance to 1e-9 mm (Newton
//! stops at a step of 1e-11 relative), the normal to 1e-12, zero curvature,
//! and the parameters to 1e-8 of the patch's widths (the closed form updates
//! them to first order; the error is of the order of the squared step, a
//! step being at most 1 % of the patch). The planar path must have answered
//! most of the interior points, or the comparison would test nothing.

use plugins_api::{Projection, ToolSurface, Vec3};
use tools_nurbs::NurbsTool;
use tools_nurbs::builders::square_cup::{
    DieParams, HolderParams, PunchParams, blankholder, die, punch,
};
use tools_nurbs::builders::{Facing, Model, Placement, s_rail};
use tools_nurbs::closest_point::ParamBox;
use tools_nurbs::planar::{self, MAX_STEP};
use tools_nurbs::surface::Derivs;

/// A small deterministic generator (64-bit LCG, top 53 bits) for sample points.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

fn place(facing: Facing) -> Placement {
    Placement {
        origin: Vec3::zeros(),
        facing,
    }
}

fn tools() -> Vec<NurbsTool> {
    let rail = s_rail::SRailParams::default();
    vec![
        die(
            "die",
            &DieParams::default(),
            Model::Full,
            &place(Facing::Up),
        )
        .unwrap(),
        blankholder(
            "holder",
            &HolderParams::default(),
            Model::Full,
            &place(Facing::Down),
        )
        .unwrap(),
        punch(
            "punch",
            &PunchParams::default(),
            Model::Full,
            &place(Facing::Up),
        )
        .unwrap(),
        s_rail::die("rail-die", &rail, &place(Facing::Down)).unwrap(),
        s_rail::blankholder("rail-holder", &rail, &place(Facing::Up)).unwrap(),
    ]
}

/// Compare two answers; returns the largest parameter error in the widths of `dom`.
fn agree(tool: &str, x: &Vec3, fast: &Projection, slow: &Projection, dom: &ParamBox) -> f64 {
    let ctx = format!("{tool}: x = {x:?}: planar {fast:?}, Newton {slow:?}");
    assert_eq!(fast.patch, slow.patch, "{ctx}");
    assert!((fast.point - slow.point).norm() <= 1e-9, "{ctx}");
    assert!((fast.distance - slow.distance).abs() <= 1e-9, "{ctx}");
    assert!((fast.normal - slow.normal).norm() <= 1e-12, "{ctx}");
    assert!((fast.curvature - slow.curvature).norm() <= 1e-9, "{ctx}");
    let du = (fast.u - slow.u).abs() / (dom.u[1] - dom.u[0]);
    let dv = (fast.v - slow.v).abs() / (dom.v[1] - dom.v[0]);
    du.max(dv)
}

#[test]
fn planar_warm_projection_matches_newton_on_the_benchmark_tools() {
    let mut rng = Lcg(20_261_125);
    let mut planar_patches = 0;
    for fast in tools() {
        let mut slow = fast.clone();
        slow.set_planar_path(false);
        let (mut samples, mut closed_form) = (0usize, 0usize);
        // The largest parameter error, alone and relative to the correction.
        let (mut worst_ratio, mut worst_err) = (0.0f64, 0.0f64);
        for (pi, patch) in fast.patches().iter().enumerate() {
            if !fast.is_planar(pi) {
                continue;
            }
            planar_patches += 1;
            let (du, dv) = patch.surface.domain();
            let dom = ParamBox { u: du, v: dv };
            let plane = planar::plane_of(patch, &dom).expect("a planar patch has a plane");
            for _ in 0..400 {
                // Mostly inside, some within 2 % beyond the edges.
                let u = du[0] + (du[1] - du[0]) * rng.range(-0.02, 1.02);
                let v = dv[0] + (dv[1] - dv[0]) * rng.range(-0.02, 1.02);
                let base = patch
                    .surface
                    .point(u.clamp(du[0], du[1]), v.clamp(dv[0], dv[1]));
                let x = base + plane.normal * rng.range(-1.5, 3.0);
                // The hint: the answer for a point up to 0.001, 0.01 or 0.1 mm away.
                let reach = [1e-3, 1e-2, 1e-1][samples % 3];
                let jitter = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0) * reach;
                let hint = slow.project(&(x + jitter), None).unwrap().hint();
                if hint.patch as usize != pi {
                    continue;
                }
                samples += 1;
                let mut d = Derivs::ZERO;
                let xl = fast.pose().to_local(&x);
                let hit = planar::warm(&patch.surface, &dom, &plane, &xl, hint.u, hint.v, &mut d);
                let a = fast.project(&x, Some(hint)).unwrap();
                let b = slow.project(&x, Some(hint)).unwrap();
                let [pu0, pu1, pv0, pv1] = patch.surface.piece_box(hint.u, hint.v);
                let piece = ParamBox {
                    u: [pu0, pu1],
                    v: [pv0, pv1],
                };
                let err = agree(fast.name(), &x, &a, &b, &piece);
                if let Some(hit) = hit {
                    closed_form += 1;
                    assert!(a.curvature.norm() == 0.0 && b.curvature.norm() <= 1e-9);
                    // The corrected parameters: within a fraction of the
                    // correction, beyond Newton's own tolerance (its physical
                    // step of 1e-11 mm is up to 1e-10 of a piece's widths).
                    worst_ratio = worst_ratio.max((err - 1e-10).max(0.0) / hit.error);
                    worst_err = worst_err.max(err);
                }
            }
        }
        println!(
            "{}: {samples} samples on planar patches, {closed_form} by the closed form; \
             parameter error at most {worst_err:.2e} of the piece's widths, {worst_ratio:.2e} x the correction",
            fast.name()
        );
        // The closed form accepts a foot inside by twice the correction: the
        // true parameters must be within a fraction of it.
        assert!(
            worst_ratio <= 0.25,
            "{}: parameter error {worst_ratio} x the correction",
            fast.name()
        );
        if samples > 0 {
            assert!(
                closed_form * 10 >= samples * 7,
                "{}: the closed form answered {closed_form} of {samples}",
                fast.name()
            );
        }
    }
    assert!(
        planar_patches >= 4,
        "only {planar_patches} planar patches found"
    );
}

/// A move of more than `MAX_STEP` of the patch, or a foot beyond the patch,
/// is left to Newton; a foot well inside is taken.
#[test]
fn planar_warm_projection_refuses_long_steps_and_edges() {
    let tool = die(
        "die",
        &DieParams::default(),
        Model::Full,
        &place(Facing::Up),
    )
    .unwrap();
    let pi = (0..tool.patches().len())
        .find(|&i| tool.is_planar(i))
        .expect("the die face is planar");
    let patch = &tool.patches()[pi];
    let (du, dv) = patch.surface.domain();
    let dom = ParamBox { u: du, v: dv };
    let plane = planar::plane_of(patch, &dom).unwrap();
    let (um, vm) = (0.5 * (du[0] + du[1]), 0.5 * (dv[0] + dv[1]));
    let mut d = Derivs::ZERO;
    let at = |u: f64, v: f64| patch.surface.point(u, v) + plane.normal * 0.4;
    // A small move inside: taken, with the plane's distance.
    let x = at(um + 1e-4 * (du[1] - du[0]), vm);
    let hit = planar::warm(&patch.surface, &dom, &plane, &x, um, vm, &mut d).unwrap();
    assert!((hit.dist - 0.4).abs() < 1e-12, "{hit:?}");
    // A long move: refused.
    let far = at(um + 3.0 * MAX_STEP * (du[1] - du[0]), vm);
    assert!(planar::warm(&patch.surface, &dom, &plane, &far, um, vm, &mut d).is_none());
    // A foot on the edge: refused.
    let edge = at(du[1], vm);
    let hint_u = du[1] - 1e-5 * (du[1] - du[0]);
    assert!(planar::warm(&patch.surface, &dom, &plane, &edge, hint_u, vm, &mut d).is_none());
}

/// Flat regions (`ToolSurface::flat_region`): around random points of the
/// planar patches of every benchmark tool, points whose foot lies in the
/// region's disc (at random heights) have that foot as their closest point
/// on the patch: the best of Newton's answers from every seed of the patch
/// (`project_on_patch`, local frame) agrees in distance and point to 1e-9 mm
/// and in normal to 1e-12. (A warm Newton from a far hint can stall on a
/// knot where the parametrisation is only C⁰, short of the foot: the region
/// is the better answer there.)
#[test]
fn flat_regions_hold_the_closest_points_of_their_patch() {
    let mut rng = Lcg(7);
    let mut regions = 0;
    for tool in tools() {
        let mut off = tool.clone();
        off.set_planar_path(false);
        let any = plugins_api::ProjectionHint {
            patch: 0,
            u: 0.0,
            v: 0.0,
        };
        assert!(off.flat_region(&any).is_none());
        for (pi, patch) in tool.patches().iter().enumerate() {
            if !tool.is_planar(pi) {
                continue;
            }
            let (du, dv) = patch.surface.domain();
            for _ in 0..50 {
                let (u, v) = (rng.range(du[0], du[1]), rng.range(dv[0], dv[1]));
                let hint = plugins_api::ProjectionHint {
                    patch: pi as u32,
                    u,
                    v,
                };
                let Some(r) = tool.flat_region(&hint) else {
                    continue;
                };
                regions += 1;
                assert!(r.radius > 0.0 && r.radius.is_finite(), "{r:?}");
                for _ in 0..20 {
                    // A foot in the disc: a random in-plane offset.
                    let a = Vec3::new(
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                        rng.range(-1.0, 1.0),
                    );
                    let t = (a - r.normal * a.dot(&r.normal)).normalize()
                        * (0.999 * r.radius * rng.next());
                    let xl = r.centre + t + r.normal * rng.range(-1.5, 3.0);
                    let (distance, foot) = r.project_local(&xl).expect("the foot is in the disc");
                    let b = tool.project_on_patch(pi, &xl).unwrap();
                    let ctx = format!(
                        "{}: patch {pi}, x_local {xl:?}, region {r:?}, patch's closest {b:?}",
                        tool.name()
                    );
                    assert!((b.distance - distance).abs() <= 1e-9, "{ctx}");
                    assert!((b.point - foot).norm() <= 1e-9, "{ctx}");
                    assert!((b.normal - r.normal).norm() <= 1e-12, "{ctx}");
                }
            }
        }
    }
    assert!(regions >= 100, "only {regions} flat regions found");
}
