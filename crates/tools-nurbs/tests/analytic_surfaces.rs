//! NURBS-built plane, cylinder, sphere and torus against their closed-form distance, normal and curvatures.
//!
//! Source: classical differential geometry (do Carmo, *Differential Geometry of
//! Curves and Surfaces*, §3-2/3-3: principal curvatures of the sphere, the
//! cylinder and the torus of revolution). Tolerance:
//! 1e-9 relative — distances relative to the shape's radius, normals
//! absolute, curvatures relative to 1/radius.

use plugins_api::{Mat3, ToolSurface, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::FRAC_PI_2;
use tools_nurbs::builders::primitives::{cylinder, plane, sphere_zone, torus};
use tools_nurbs::builders::{Facing, Placement};

const TOL: f64 = 1e-9;

fn check_tensor(k: &Mat3, expect: &Mat3, scale: f64, what: &str) {
    let e = (k - expect).abs().max();
    assert!(e <= TOL * scale, "{what}: curvature tensor off by {e:e}");
}

#[test]
fn nurbs_plane_matches_analytic_plane() {
    let place = Placement {
        origin: Vec3::new(1.0, -2.0, 3.0),
        facing: Facing::Down,
    };
    let tool = plane("plane", 100.0, 60.0, &place).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..2000 {
        let x = Vec3::new(
            rng.random_range(-48.0..48.0) + 1.0,
            rng.random_range(-28.0..28.0) - 2.0,
            rng.random_range(-20.0..20.0) + 3.0,
        );
        let p = tool.project(&x, None).unwrap();
        // Facing down: the normal is -z, distance positive below.
        let d = 3.0 - x.z;
        assert!(
            (p.distance - d).abs() <= TOL * 50.0,
            "plane distance {} vs {d}",
            p.distance
        );
        assert!((p.normal - Vec3::new(0.0, 0.0, -1.0)).norm() <= TOL);
        assert!((p.point - Vec3::new(x.x, x.y, 3.0)).norm() <= TOL * 50.0);
        assert!(p.k1.abs() <= TOL && p.k2.abs() <= TOL);
        check_tensor(&p.curvature, &Mat3::zeros(), 1.0, "plane");
    }
}

#[test]
fn nurbs_cylinder_matches_analytic_cylinder() {
    let r = 20.0;
    let tool = cylinder("capstan", r, 80.0, 0.0, 360.0, &Placement::default()).unwrap();
    assert_eq!(tool.patches().len(), 4);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for _ in 0..4000 {
        let rho = rng.random_range(2.0..40.0);
        let th = rng.random_range(0.0..std::f64::consts::TAU);
        let x = Vec3::new(
            rho * th.cos(),
            rng.random_range(-39.0..39.0),
            rho * th.sin(),
        );
        let p = tool.project(&x, None).unwrap();
        let n = Vec3::new(th.cos(), 0.0, th.sin());
        assert!(
            (p.distance - (rho - r)).abs() <= TOL * r,
            "cylinder distance {} vs {}",
            p.distance,
            rho - r
        );
        assert!(
            (p.normal - n).norm() <= TOL,
            "cylinder normal {:?} vs {n:?}",
            p.normal
        );
        assert!(
            (p.k1 - 1.0 / r).abs() <= TOL / r && p.k2.abs() <= TOL / r,
            "k = {}, {}",
            p.k1,
            p.k2
        );
        let t = Vec3::new(-th.sin(), 0.0, th.cos());
        check_tensor(&p.curvature, &(t * t.transpose() / r), 1.0 / r, "cylinder");
    }
}

#[test]
fn nurbs_sphere_matches_analytic_sphere() {
    let (c, r) = (Vec3::new(5.0, -3.0, 2.0), 15.0);
    let tool = sphere_zone("ball", c, r, 0.25 * std::f64::consts::PI).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..4000 {
        let lat: f64 = rng.random_range(-0.7..0.7);
        let lon = rng.random_range(0.05..FRAC_PI_2 - 0.05);
        let n = Vec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin());
        let rho = rng.random_range(1.0..35.0);
        let x = c + n * rho;
        let p = tool.project(&x, None).unwrap();
        assert!(
            (p.distance - (rho - r)).abs() <= TOL * r,
            "sphere distance {} vs {}",
            p.distance,
            rho - r
        );
        assert!((p.normal - n).norm() <= TOL);
        assert!((p.k1 - 1.0 / r).abs() <= TOL / r && (p.k2 - 1.0 / r).abs() <= TOL / r);
        let k = (Mat3::identity() - n * n.transpose()) / r;
        check_tensor(&p.curvature, &k, 1.0 / r, "sphere");
    }
}

#[test]
fn nurbs_torus_matches_analytic_torus() {
    let (c, big, small) = (Vec3::new(0.0, 0.0, 10.0), 30.0, 10.0);
    let tool = torus("torus", c, big, small).unwrap();
    assert_eq!(tool.patches().len(), 16);
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..4000 {
        let phi = rng.random_range(0.0..std::f64::consts::TAU);
        let th = rng.random_range(0.0..std::f64::consts::TAU);
        let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let n = radial * th.cos() + Vec3::z() * th.sin();
        let rho = rng.random_range(1.0..25.0);
        let x = c + radial * big + n * rho;
        let p = tool.project(&x, None).unwrap();
        assert!(
            (p.distance - (rho - small)).abs() <= TOL * small,
            "torus distance {} vs {}",
            p.distance,
            rho - small
        );
        assert!((p.normal - n).norm() <= TOL);
        let km = 1.0 / small;
        let kp = th.cos() / (big + small * th.cos());
        let (e1, e2) = (km.max(kp), km.min(kp));
        assert!(
            (p.k1 - e1).abs() <= TOL * km && (p.k2 - e2).abs() <= TOL * km,
            "torus k {} {} vs {e1} {e2}",
            p.k1,
            p.k2
        );
        let tm = radial * (-th.sin()) + Vec3::z() * th.cos();
        let tp = Vec3::new(-phi.sin(), phi.cos(), 0.0);
        let k = tm * tm.transpose() * km + tp * tp.transpose() * kp;
        check_tensor(&p.curvature, &k, km, "torus");
    }
}
