//! Curved regions (`ToolSurface::curved_region`, `tools_nurbs::curved`)
//! against Newton on the square cup's and the S-rail's tools.
//!
//! Every patch recognised as a cylinder or torus offers a region. Points at
//! random heights (−1.5 to 3 mm, so also penetrating) along the normal at
//! random points of the patch, and up to 2 % beyond its edges, are answered
//! by the region's closed form where it answers, and compared with the
//! tool's warm Newton from a hint on the patch (the same patch, the signed
//! distance to 1e-9 mm and the normal to 1e-9; the foot to 1e-8 mm: Newton
//! stops at a step of 1e-11 mm, but points a few µm from the surface, where
//! the distance is flat along it, leave up to 1.4e-9 mm) and with the patch's best seeded Newton
//! (`project_on_patch`: the same patch and distance to 1e-9 mm, so no point
//! of the patch is nearer). The regions must answer most interior points, and the same
//! check must fail for regions a fifth larger than their patches.

use plugins_api::{CurvedRegion, CurvedShape, ProjectionHint, ToolSurface, Vec3};
use tools_nurbs::NurbsTool;
use tools_nurbs::builders::square_cup::{
    DieParams, HolderParams, PunchParams, blankholder, die, punch,
};
use tools_nurbs::builders::{Facing, Model, Placement, s_rail};

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
        s_rail::punch("rail-punch", &rail, &place(Facing::Up)).unwrap(),
        s_rail::blankholder("rail-holder", &rail, &place(Facing::Up)).unwrap(),
    ]
}

/// `r` with its angles and lengths `f` times as large about their middles.
fn enlarged(r: &CurvedRegion, f: f64) -> CurvedRegion {
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
    CurvedRegion {
        cos_half: wider(r.cos_half),
        shape,
        ..*r
    }
}

/// Over every curved patch of every tool: (curved patches, points the
/// regions answered, of them those that disagree with Newton), with the
/// regions enlarged `f` times; with `strict`, a disagreement panics.
fn compare(f: f64, strict: bool) -> (usize, usize, usize) {
    let mut rng = Lcg(20_261_129);
    let (mut patches, mut answered, mut wrong) = (0, 0, 0);
    for tool in tools() {
        let mut off = tool.clone();
        off.set_curved_regions(false);
        let (mut tool_patches, mut tool_answered, mut interior) = (0, 0, 0);
        for (pi, patch) in tool.patches().iter().enumerate() {
            let hint0 = ProjectionHint {
                patch: pi as u32,
                u: 0.0,
                v: 0.0,
            };
            assert!(off.curved_region(&hint0).is_none());
            let Some(region) = tool.curved_region(&hint0) else {
                assert!(!tool.is_curved(pi));
                continue;
            };
            assert!(tool.is_curved(pi) && !tool.is_planar(pi));
            tool_patches += 1;
            let region = enlarged(&region, f);
            let (du, dv) = patch.surface.domain();
            for _ in 0..200 {
                let fu = rng.range(-0.02, 1.02);
                let fv = rng.range(-0.02, 1.02);
                let inside = (0.0..=1.0).contains(&fu) && (0.0..=1.0).contains(&fv);
                let (u, v) = (
                    du[0] + (du[1] - du[0]) * fu.clamp(0.0, 1.0),
                    dv[0] + (dv[1] - dv[0]) * fv.clamp(0.0, 1.0),
                );
                let d = patch.surface.eval(u, v);
                let n = d.su.cross(&d.sv).normalize() * patch.sign;
                let jitter = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                let x = d.s + n * rng.range(-1.5, 3.0) + jitter * 0.05;
                let Some((distance, normal)) = region.project_local(&x) else {
                    continue;
                };
                if inside {
                    interior += 1;
                }
                tool_answered += 1;
                let foot = x - normal * distance;
                // The warm Newton from a hint near the sample, and the best
                // seeded Newton on the patch.
                let hint = ProjectionHint {
                    patch: pi as u32,
                    u: (u + 0.01 * (du[1] - du[0])).min(du[1]),
                    v,
                };
                let warm = off.project_local_frame(&x, Some(hint));
                let best = off.project_on_patch(pi, &x).unwrap();
                let ok = |p: &plugins_api::Projection| {
                    p.patch as usize == pi
                        && (p.distance - distance).abs() <= 1e-9
                        && (p.point - foot).norm() <= 1e-8
                        && (p.normal - normal).norm() <= 1e-9
                };
                // The seeded Newton proves the foot the patch's closest
                // point by its distance (it may stop a few 1e-9 mm along
                // the surface from the foot, where the distance is flat).
                let closest = best.patch as usize == pi && (best.distance - distance).abs() <= 1e-9;
                if !(ok(&warm) && closest) {
                    wrong += 1;
                    assert!(
                        !strict,
                        "{}: patch {pi}, x {x:?}: region ({distance}, {normal:?}, foot {foot:?}); \
                         warm Newton {warm:?}; patch's closest {best:?}",
                        tool.name()
                    );
                }
            }
        }
        println!(
            "{}: {tool_patches} curved patches, {tool_answered} points answered ({interior} of them over the patch)",
            tool.name()
        );
        patches += tool_patches;
        answered += tool_answered;
    }
    (patches, answered, wrong)
}

#[test]
fn curved_regions_give_the_closest_points_of_newton_on_the_benchmark_tools() {
    let (patches, answered, wrong) = compare(1.0, true);
    assert_eq!(wrong, 0);
    // The cup: punch 4 side radii and 4 corner tori, 4 corner walls; die 4
    // side radii, 4 corner tori, 4 corner walls (quarter × 4 in the full model).
    assert!(patches >= 24, "only {patches} curved patches recognised");
    assert!(
        answered >= patches * 200 / 2,
        "the regions answered only {answered} points on {patches} patches"
    );
}

#[test]
fn curved_regions_a_fifth_too_large_give_wrong_answers() {
    let (patches, answered, wrong) = compare(1.2, false);
    println!("enlarged regions: {wrong} wrong of {answered} answered on {patches} patches");
    assert!(
        wrong * 50 > answered,
        "enlarged regions went unnoticed: {wrong} wrong of {answered}"
    );
}
