//! The square-cup tool set (docs/benchmarks.md §1): global closest points on a million random points, seams, bad input.

use plugins_api::{Mat3, Projection, ProjectionHint, ToolSurface, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tools_nurbs::builders::square_cup::{
    DieParams, HolderParams, PunchParams, blankholder, die, punch,
};
use tools_nurbs::builders::{Facing, Model, Placement};
use tools_nurbs::{NurbsError, NurbsTool, PatchDef};

fn tools(model: Model) -> Vec<NurbsTool> {
    let place = Placement::default();
    vec![
        punch("punch", &PunchParams::default(), model, &place).unwrap(),
        die("die", &DieParams::default(), model, &place).unwrap(),
        blankholder(
            "blankholder",
            &HolderParams::default(),
            model,
            &Placement {
                origin: Vec3::new(0.0, 0.0, 0.78),
                facing: Facing::Down,
            },
        )
        .unwrap(),
    ]
}

/// A random point within `reach` mm of a random surface point of `tool`.
fn near_point(tool: &NurbsTool, rng: &mut ChaCha8Rng, reach: f64) -> Vec3 {
    let pi = rng.random_range(0..tool.patches().len());
    let s = &tool.patches()[pi].surface;
    let (du, dv) = s.domain();
    let p = s.point(
        rng.random_range(du[0]..=du[1]),
        rng.random_range(dv[0]..=dv[1]),
    );
    let dir = loop {
        let d = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let n = d.norm();
        if n > 1e-3 && n <= 1.0 {
            break d / n;
        }
    };
    p + dir * rng.random_range(0.0..reach)
}

/// Independent global search: dense sampling of every patch, then a
/// shrinking-grid pattern search (no derivatives, no Newton) around the best
/// sample of every patch that could still hold the minimum.
fn brute_force(tool: &NurbsTool, x: &Vec3) -> f64 {
    const N: usize = 24;
    let mut best: Vec<(f64, usize, f64, f64, f64)> = Vec::new();
    for (pi, p) in tool.patches().iter().enumerate() {
        let s = &p.surface;
        let (du, dv) = s.domain();
        let mut b = (f64::INFINITY, pi, 0.0, 0.0, 0.0);
        let mut h = 0.0f64;
        for i in 0..=N {
            for j in 0..=N {
                let u = du[0] + (du[1] - du[0]) * i as f64 / N as f64;
                let v = dv[0] + (dv[1] - dv[0]) * j as f64 / N as f64;
                let q = s.point(u, v);
                let d = (q - x).norm();
                if i > 0 {
                    let u0 = du[0] + (du[1] - du[0]) * (i - 1) as f64 / N as f64;
                    h = h.max((s.point(u0, v) - q).norm());
                }
                if j > 0 {
                    let v0 = dv[0] + (dv[1] - dv[0]) * (j - 1) as f64 / N as f64;
                    h = h.max((s.point(u, v0) - q).norm());
                }
                if d < b.0 {
                    b = (d, pi, u, v, 0.0);
                }
            }
        }
        b.4 = h;
        best.push(b);
    }
    let floor = best.iter().map(|b| b.0).fold(f64::INFINITY, f64::min);
    let mut result = f64::INFINITY;
    for &(d, pi, u, v, h) in &best {
        if d > floor + h {
            continue;
        }
        let s = &tool.patches()[pi].surface;
        let (du, dv) = s.domain();
        let (mut u, mut v, mut d) = (u, v, d);
        let (mut wu, mut wv) = ((du[1] - du[0]) / N as f64, (dv[1] - dv[0]) / N as f64);
        for _ in 0..60 {
            let (mut bu, mut bv) = (u, v);
            for a in -2..=2 {
                for b in -2..=2 {
                    let uu = (u + a as f64 * wu * 0.5).clamp(du[0], du[1]);
                    let vv = (v + b as f64 * wv * 0.5).clamp(dv[0], dv[1]);
                    let dd = (s.point(uu, vv) - x).norm();
                    if dd < d {
                        (d, bu, bv) = (dd, uu, vv);
                    }
                }
            }
            if (bu, bv) == (u, v) {
                wu *= 0.5;
                wv *= 0.5;
            }
            (u, v) = (bu, bv);
        }
        result = result.min(d);
    }
    result
}

fn sane(p: &Projection, x: &Vec3, reach: f64) -> bool {
    let k_n = (p.curvature * p.normal).norm();
    p.point.iter().all(|v| v.is_finite())
        && (p.normal.norm() - 1.0).abs() < 1e-12
        && p.distance.abs() <= reach + 1e-9
        && ((x - p.point).norm() - p.distance.abs()).abs() < 1e-9
        && k_n < 1e-9
        && (p.curvature - p.curvature.transpose()).abs().max() < 1e-12
        && p.k1 >= p.k2
}

/// 10^6 random points within 20 mm of the square-cup
/// punch and die (quarter model, what the scene uses) project without failure;
/// a sample of 2000 is checked against an independent brute-force search
/// (dense sampling + derivative-free pattern search) to 1e-8 mm, and warm
/// starts from a neighbour 0.01 mm away agree with the cold answer to 1e-9 mm.
#[test]
fn square_cup_million_points_project_to_the_global_closest_point() {
    let set = tools(Model::Quarter);
    let mut rng = ChaCha8Rng::seed_from_u64(93);
    for tool in &set[..2] {
        let n = 500_000;
        let points: Vec<Vec3> = (0..n).map(|_| near_point(tool, &mut rng, 20.0)).collect();
        let hints = vec![None; n];
        let mut out = vec![tool.project(&points[0], None).unwrap(); n];
        tool.project_batch(&points, &hints, &mut out).unwrap();
        let bad = points
            .iter()
            .zip(&out)
            .filter(|(x, p)| !sane(p, x, 20.0))
            .count();
        assert_eq!(
            bad,
            0,
            "{}: {bad} projections fail the sanity checks",
            tool.name()
        );
        let mut worst = 0.0f64;
        for (x, p) in points.iter().zip(&out).take(1000) {
            let d = brute_force(tool, x);
            let e = (p.distance.abs() - d).abs();
            worst = worst.max(e);
            assert!(
                e < 1e-8,
                "{}: point {x:?}: projection distance {} but brute force {d}",
                tool.name(),
                p.distance.abs()
            );
            let near = x + Vec3::new(0.01, -0.007, 0.004);
            let h: ProjectionHint = tool.project(&near, None).unwrap().hint();
            let w = tool.project(x, Some(h)).unwrap();
            assert!(
                (w.distance - p.distance).abs() < 1e-9,
                "{}: warm {} vs cold {}",
                tool.name(),
                w.distance,
                p.distance
            );
        }
        eprintln!(
            "{}: worst |projection - brute force| = {worst:e} mm",
            tool.name()
        );
    }
}

/// Seams of every builder (quarter and full models): normals agree to 1e-9
/// (G1), and the curvature tensor applied to the seam tangent, `K t = dn/ds`
/// along the seam, agrees to 1e-9/mm (it is fixed by the common normal);
/// only the across-seam curvature `m·K·m` may jump, and it does not at seams
/// between a patch and its own mirror image (the same analytic surface).
#[test]
fn square_cup_builder_seams_are_g1_and_curvature_jumps_only_across() {
    for model in [Model::Quarter, Model::Full] {
        for tool in tools(model) {
            let mut seams = 0;
            let mut jumps = 0;
            let patches = tool.patches();
            for (a, pa) in patches.iter().enumerate() {
                let (du, dv) = pa.surface.domain();
                for edge in 0..4 {
                    for k in 0..7 {
                        let t = (k as f64 + 0.5) / 7.0;
                        let (u, v) = match edge {
                            0 => (du[0], dv[0] + t * (dv[1] - dv[0])),
                            1 => (du[1], dv[0] + t * (dv[1] - dv[0])),
                            2 => (du[0] + t * (du[1] - du[0]), dv[0]),
                            _ => (du[0] + t * (du[1] - du[0]), dv[1]),
                        };
                        let d = pa.surface.eval(u, v);
                        let tangent = if edge < 2 { d.sv } else { d.su }.normalize();
                        let x = d.s;
                        let on_a = tool.project_on_patch(a, &x).unwrap();
                        for b in 0..patches.len() {
                            if b == a {
                                continue;
                            }
                            let on_b = tool.project_on_patch(b, &x).unwrap();
                            if (on_b.point - x).norm() > 1e-9 {
                                continue;
                            }
                            seams += 1;
                            let dn = (on_a.normal - on_b.normal).norm();
                            assert!(
                                dn < 1e-9,
                                "{} patches {a}/{b}: normal jump {dn:e}",
                                tool.name()
                            );
                            let kt = (on_a.curvature * tangent - on_b.curvature * tangent).norm();
                            assert!(
                                kt < 1e-9,
                                "{} patches {a}/{b}: K t jump {kt:e} 1/mm",
                                tool.name()
                            );
                            let m = on_a.normal.cross(&tangent);
                            let jump =
                                (m.dot(&(on_a.curvature * m)) - m.dot(&(on_b.curvature * m))).abs();
                            if jump > 1e-9 {
                                jumps += 1;
                                // A jump needs two different surfaces: a patch and its mirror never jump.
                                let mirror = mirror_of(&tool, a, b);
                                assert!(
                                    !mirror,
                                    "{} patches {a}/{b}: jump {jump} across a mirror seam",
                                    tool.name()
                                );
                            }
                        }
                    }
                }
            }
            assert!(
                seams > 0 || tool.patches().len() == 1,
                "{}: no seam found",
                tool.name()
            );
            eprintln!(
                "{} {model:?}: {seams} seam samples, {jumps} with a curvature jump across",
                tool.name()
            );
        }
    }
}

/// Whether patch b is patch a mirrored through x = 0 or y = 0.
fn mirror_of(tool: &NurbsTool, a: usize, b: usize) -> bool {
    let pa = &tool.patches()[a].surface;
    let pb = &tool.patches()[b].surface;
    let (du, dv) = pa.domain();
    let c = pa.point(0.5 * (du[0] + du[1]), 0.5 * (dv[0] + dv[1]));
    [
        Mat3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0)),
        Mat3::from_diagonal(&Vec3::new(1.0, -1.0, 1.0)),
    ]
    .iter()
    .any(|m| {
        let q = m * c;
        let (eu, ev) = pb.domain();
        let cb = pb.point(0.5 * (eu[0] + eu[1]), 0.5 * (ev[0] + ev[1]));
        (cb - q).norm() < 1e-9
    })
}

/// The holder and die face are flat: zero curvature; the punch fillet is a
/// cylinder of the profile radius along the sides (docs/benchmarks.md §1 sizes).
#[test]
fn square_cup_curvature_matches_the_drawing() {
    let set = tools(Model::Quarter);
    // Above the punch nose centre: flat.
    let p = set[0].project(&Vec3::new(5.0, 5.0, 3.0), None).unwrap();
    assert!((p.distance - 3.0).abs() < 1e-12 && p.k1.abs() < 1e-12);
    // Beside the fillet at the middle of the x side, 45° up: 1/8 along the profile.
    let c = Vec3::new(35.0 - 8.0, 5.0, -8.0);
    let dir = Vec3::new(1.0, 0.0, 1.0).normalize();
    let p = set[0].project(&(c + dir * 10.0), None).unwrap();
    assert!((p.distance - 2.0).abs() < 1e-10 && (p.k1 - 0.125).abs() < 1e-10 && p.k2.abs() < 1e-10);
    // Die shoulder (radius 5) seen from above the opening edge: convex, 1/5.
    let c = Vec3::new(37.0 + 5.0, 3.0, -5.0);
    let dir = Vec3::new(-1.0, 0.0, 1.0).normalize();
    let p = set[1].project(&(c + dir * 6.0), None).unwrap();
    assert!((p.distance - 1.0).abs() < 1e-10 && (p.k1 - 0.2).abs() < 1e-10);
    // Blankholder faces down: a point below it has positive distance.
    let p = set[2].project(&Vec3::new(60.0, 60.0, 0.0), None).unwrap();
    assert!((p.distance - 0.78).abs() < 1e-12 && (p.normal.z + 1.0).abs() < 1e-15);
}

fn bilinear(points: Vec<Vec3>) -> PatchDef {
    PatchDef {
        degree_u: 1,
        degree_v: 1,
        knots_u: vec![0.0, 0.0, 1.0, 1.0],
        knots_v: vec![0.0, 0.0, 1.0, 1.0],
        count_v: 2,
        weights: vec![1.0; points.len()],
        points,
    }
}

fn square(z: f64, x0: f64) -> PatchDef {
    bilinear(vec![
        Vec3::new(x0, 0.0, z),
        Vec3::new(x0, 1.0, z),
        Vec3::new(x0 + 1.0, 0.0, z),
        Vec3::new(x0 + 1.0, 1.0, z),
    ])
}

/// Bad input: each error names the patch and the field.
#[test]
fn bad_patches_and_points_give_errors_naming_patch_and_field() {
    let ok = square(0.0, 0.0);
    let mut collapsed = ok.clone();
    collapsed.points[1] = collapsed.points[0];
    let e = NurbsTool::from_defs("t", &[ok.clone(), collapsed], &[1.0, 1.0]).unwrap_err();
    assert!(matches!(e, NurbsError::Degenerate { patch: 1, .. }), "{e}");
    assert!(e.to_string().contains("patch 1") && e.to_string().contains("degenerate"));

    let mut knots = ok.clone();
    knots.knots_u = vec![0.0, 0.0, 1.0, 0.5];
    let e = NurbsTool::from_defs("t", &[knots], &[1.0]).unwrap_err();
    assert!(
        e.to_string().starts_with("patch 0: knots_u[3] = 0.5"),
        "{e}"
    );

    let mut count = ok.clone();
    count.knots_v = vec![0.0, 0.0, 1.0];
    let e = NurbsTool::from_defs("t", &[ok.clone(), ok.clone(), count], &[1.0; 3]).unwrap_err();
    assert!(
        e.to_string().starts_with("patch 2: knots_v has 3 values"),
        "{e}"
    );

    for w in [0.0, -1.0, f64::NAN] {
        let mut wt = ok.clone();
        wt.weights[2] = w;
        let e = NurbsTool::from_defs("t", &[wt], &[1.0]).unwrap_err();
        assert!(e.to_string().starts_with("patch 0: weights[2] = "), "{e}");
    }
    let mut nan = ok.clone();
    nan.points[3].z = f64::NAN;
    let e = NurbsTool::from_defs("t", &[nan], &[1.0]).unwrap_err();
    assert!(e.to_string().starts_with("patch 0: points[3]"), "{e}");

    let tool = NurbsTool::from_defs("flat", &[ok], &[1.0]).unwrap();
    let e = tool
        .project(&Vec3::new(f64::NAN, 0.0, 0.0), None)
        .unwrap_err();
    assert!(e.to_string().contains("tool `flat`") && e.to_string().contains("not finite"));
    let e = punch(
        "punch",
        &PunchParams {
            profile_radius: 12.0,
            ..PunchParams::default()
        },
        Model::Quarter,
        &Placement::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("profile_radius = 12 mm must be smaller than corner_radius"),
        "{e}"
    );
}

/// A point equidistant from two patches gets the lower patch index on a cold
/// search; a warm start keeps its (interior) hinted patch, so the answer is
/// deterministic either way and never flips between steps.
#[test]
fn equidistant_point_returns_the_lowest_patch_deterministically() {
    // Two parallel unit squares at z = 0 and z = 2, both facing the gap.
    let tool =
        NurbsTool::from_defs("gap", &[square(2.0, 0.0), square(0.0, 0.0)], &[-1.0, 1.0]).unwrap();
    let x = Vec3::new(0.3, 0.6, 1.0);
    for (hint, patch) in [
        (None, 0),
        (
            Some(ProjectionHint {
                patch: 1,
                u: 0.9,
                v: 0.1,
            }),
            1,
        ),
    ] {
        for _ in 0..3 {
            let p = tool.project(&x, hint).unwrap();
            assert_eq!(p.patch, patch);
            assert!((p.distance - 1.0).abs() < 1e-12);
        }
    }
    // Side by side: a point above their shared edge.
    let tool =
        NurbsTool::from_defs("pair", &[square(0.0, 1.0), square(0.0, 0.0)], &[1.0, 1.0]).unwrap();
    for _ in 0..3 {
        let p = tool.project(&Vec3::new(1.0, 0.5, 0.7), None).unwrap();
        assert_eq!(p.patch, 0);
        assert!((p.distance - 0.7).abs() < 1e-12);
    }
}
