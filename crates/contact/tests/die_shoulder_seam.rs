//! Hard case: a blank point sliding over the die's flat face and across
//! the seam into the shoulder radius (exact NURBS square-cup die, docs/benchmarks.md §1)
//! keeps a continuous friction traction.

use contact::{BlankGeometry, BlankView, ContactPair, PairSpec, PointStatus};
use friction_laws::builtin;
use plugins_api::{Params, TangentMode, ToolSurface, Vec3};
use tools_nurbs::builders::square_cup::benchmark_quarter_die;

/// A 0.2 mm square patch of blank (one quad) is carried along y = 10 from
/// x = 50 on the die face, across the seam at x = 37 + 5 = 42, round the
/// shoulder (radius 5) to 60° down it, held at a constant penetration. In
/// steady slip the friction force on a node is `μ F_N` with `F_N = k δ` constant,
/// and it turns with the normal, so between steps it may change by at most
/// `μ F_N Δφ` (Δφ the normal's turn per step): the bound asserted is
/// `|F_{k+1} − F_k| ≤ μ F_N (Δφ + 1e-3)` at every step, the seam included (a
/// traction reset or a normal flip at the seam would break it by orders of magnitude).
#[test]
fn traction_is_continuous_across_the_die_shoulder_seam() {
    for formulation in ["convective", "jaumann"] {
        let die = benchmark_quarter_die().unwrap();
        let thickness = 0.78;
        let h = 0.2;
        // The patch's reference points, offset by the surface frame each step.
        let local = [(0.0, 0.0), (h, 0.0), (h, h), (0.0, h)];
        let quads = [[0u32, 1, 2, 3]];
        let mu = 0.144;
        let integ = builtin::integrator(
            "ac",
            &Params::new().with("mu", mu),
            formulation,
            TangentMode::None,
        )
        .unwrap();
        // Place the patch on the flat face first, to build the pair.
        let depth = 0.005;
        let place = |s_x: f64| -> (Vec<Vec3>, Vec3) {
            let mut xs = Vec::new();
            let mut n0 = Vec3::z();
            for (k, (dx, dy)) in local.iter().enumerate() {
                let probe = Vec3::new(s_x - dx, 10.0 + dy, 1.0);
                let pr = die.project(&probe, None).unwrap();
                if k == 0 {
                    n0 = pr.normal;
                }
                xs.push(pr.point + pr.normal * (0.5 * thickness - depth));
            }
            (xs, n0)
        };
        let (x0, _) = place(50.0);
        let geometry0 = BlankGeometry::new(4, &quads).unwrap();
        let mut pair = ContactPair::new(
            &PairSpec::new("die-blank", 0, 1.7e5),
            integ,
            &geometry0,
            &x0,
        )
        .unwrap();
        let mut g = geometry0.clone();
        let mass = vec![1e-6; 4];
        let thick = vec![thickness; 4];
        let dt = 1e-5;
        let mut x_prev = x0.clone();
        let mut t_prev: Option<Vec3> = None;
        let mut slipping_before = false;
        let mut n_prev = Vec3::z();
        let mut worst: f64 = 0.0;
        let mut crossed = false;
        let mut f = vec![Vec3::zeros(); 4];
        // Walk the probe: x from 50 to 42 on the flat, then round the shoulder:
        // probes on a circle of radius 5 + 1 about the shoulder axis (x = 37, z = -5).
        let mut probes: Vec<f64> = (0..=80).map(|i| 50.0 - 0.1 * i as f64).collect();
        let arc: Vec<f64> = (1..=60).map(|i| (i as f64).to_radians()).collect();
        probes.extend(arc.iter().map(|a| -a));
        for &s in &probes {
            let (x, n) = if s >= 0.0 {
                place(s)
            } else {
                // Angle a = -s down the shoulder: probe at the shoulder's normal line.
                let a = -s;
                let mut xs = Vec::new();
                let mut n0 = Vec3::z();
                for (k, (dx, dy)) in local.iter().enumerate() {
                    // Shoulder axis at x = 42, z = -5; the forward tangent at
                    // angle a is (-cos a, 0, -sin a); patch points lie ahead by dx.
                    let probe = Vec3::new(
                        42.0 - 6.0 * a.sin() - dx * a.cos(),
                        10.0 + dy,
                        -5.0 + 6.0 * a.cos() - dx * a.sin(),
                    );
                    let pr = die.project(&probe, None).unwrap();
                    if k == 0 {
                        n0 = pr.normal;
                    }
                    xs.push(pr.point + pr.normal * (0.5 * thickness - depth));
                }
                (xs, n0)
            };
            let v: Vec<Vec3> = x.iter().zip(&x_prev).map(|(a, b)| (a - b) / dt).collect();
            let view = BlankView {
                x0: &x0,
                x: &x,
                v: &v,
                mass: &mass,
                thickness: &thick,
                flow_stress: None,
            };
            g.update(&view, dt, pair.needs());
            f.iter_mut().for_each(|q| *q = Vec3::zeros());
            pair.step(&die, &g, &view, dt, &mut f).unwrap();
            // Friction force on node 0 (N): traction × nodal area. The area of the
            // test's patch changes as it bends over the radius, the force does
            // not (F_N = k δ at constant penetration), so the force is compared.
            let t = pair.traction[0] * g.area[0];
            let p = pair.pressure[0] * g.area[0];
            assert_ne!(
                pair.status[0],
                PointStatus::Open,
                "{formulation}: lost contact at s = {s}"
            );
            let slipping = pair.status[0] == PointStatus::Slip;
            if let Some(tp) = t_prev
                && slipping
                && slipping_before
            {
                let dphi = n.angle(&n_prev);
                let jump = (t - tp).norm();
                let bound = mu * p * (dphi + 1e-3);
                worst = worst.max(jump / (mu * p));
                assert!(
                    jump <= bound,
                    "{formulation}: s = {s}: |Δt| = {jump} > {bound} (Δφ = {dphi})"
                );
                if n.z < 0.999_999 && n_prev.z > 0.999_999 {
                    crossed = true;
                }
            }
            t_prev = Some(t);
            slipping_before = slipping;
            n_prev = n;
            x_prev = x;
        }
        assert!(crossed, "{formulation}: the walk must cross the seam");
        eprintln!("{formulation}: worst |ΔF|/(μ F_N) per step = {worst:.3e}");
    }
}
