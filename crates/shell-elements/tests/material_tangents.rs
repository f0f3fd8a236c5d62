//! The closed-form algorithmic tangents of the built-in plane-stress
//! materials (`Material::consistent_tangent` of `J2PlaneStress` and
//! `Hill48PlaneStress`) against central differences of their own `update`
//! (`finite_difference_tangent`), and the plugin material's default.
//!
//! Tolerance: `max |C_alg − C_fd| ≤ 1e-5 E` (E the material's Young's
//! modulus, the scale of every entry). The differences' own error is far
//! below it: truncation `h² σ‴ / 6 ≲ 1e-10 E` for the step `h = 1e-8`
//! (σ‴ ≲ E per yield strain squared, ~1e-6), rounding `1e-16 σ / h ~
//! 1e-11 E`, and J2's return, which stops at `|σ_vm/σ_y − 1|
//! ≤ 5e-10` (Hill's at 1e-14), changes its error smoothly with Δε unless its
//! iteration count changes inside ±h (then the differences can be off by up
//! to about `5e-10 σ_y / h`, of order 1e-5 E; none of the cases here is: the
//! worst measured error is 1.9e-10 E, and every case's is printed).
//! A wrong tangent misses by far more: the negative controls below (the
//! elastic matrix and the continuum tangent in a plastic state) miss by
//! more than 1e-2 E, a thousand times the tolerance.
//!
//! Increments are several yield strains (clearly plastic) or a fraction of
//! one (clearly elastic), so that `Δε ± h` never crosses the yield surface,
//! and each case asserts which side it is on; the tabulated curve's new ε_p
//! is kept away from its kinks.
//!
//! Run with `--nocapture` to see the worst error of every case.

use plugins_api::Params;
use plugins_api::material::loader::MaterialLibrary;
use shell_elements::material::{Hill48PlaneStress, PluginMaterial};
use shell_elements::{
    Hardening, J2PlaneStress, Material, finite_difference_tangent, plane_stress_elasticity,
};

/// `max |C_alg − C_fd| / E` allowed (see the module docs).
const TOL: f64 = 1e-5;
/// What the negative controls must miss by, at least (`/ E`).
const WRONG: f64 = 1e-2;

const E: f64 = 206_000.0;
const NU: f64 = 0.3;

/// The square cup's steel (docs/benchmarks.md §1): Swift hardening.
fn swift() -> Hardening {
    Hardening::swift(565.32, 0.007117, 0.2589).unwrap()
}

/// A three-row table (the one of the J2 section-update test): kinks at
/// ε_p = 0.05 and 0.3, slope 2000 MPa, then 400 MPa.
const TABLE_KINKS: [f64; 2] = [0.05, 0.3];
fn table() -> Hardening {
    Hardening::table(&[(0.0, 300.0), (0.05, 400.0), (0.3, 500.0)]).unwrap()
}

/// NUMISHEET'93 steel and aluminium r-values (r0, r45, r90), as in the Hill'48 tests.
const STEEL_R: [f64; 3] = [1.79, 1.51, 2.27];
const AL_R: [f64; 3] = [0.71, 0.58, 0.70];

fn j2(h: Hardening) -> J2PlaneStress {
    J2PlaneStress::new(E, NU, 7.85e-9, h).unwrap()
}

fn hill(h: Hardening, r: [f64; 3], theta: f64) -> Hill48PlaneStress {
    Hill48PlaneStress::new(E, NU, 7.85e-9, h, r)
        .unwrap()
        .with_rolling_angle(theta)
        .unwrap()
}

fn max_diff(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> f64 {
    let mut m = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            m = m.max((a[i][j] - b[i][j]).abs());
        }
    }
    m
}

/// The state after `steps` equal increments summing to `total`.
fn loaded<M: Material>(m: &M, total: [f64; 3], steps: usize) -> ([f64; 3], M::History) {
    let (mut s, mut h) = ([0.0; 3], m.initial_history());
    for _ in 0..steps {
        m.update(&mut s, &mut h, total.map(|c| c / steps as f64));
    }
    (s, h)
}

/// Whether the increment `de` from `(s, h)` is plastic.
fn is_plastic<M: Material>(m: &M, s: &[f64; 3], h: &M::History, de: [f64; 3]) -> bool {
    let (mut s1, mut h1) = (*s, *h);
    m.update(&mut s1, &mut h1, de);
    m.plastic_strain(&h1) > m.plastic_strain(h)
}

/// `max |C_alg − C_fd| / E` of one case, asserted within [`TOL`] and printed.
fn check<M: Material>(label: &str, m: &M, s: &[f64; 3], h: &M::History, de: [f64; 3]) -> f64 {
    let alg = m.consistent_tangent(s, h, de);
    let fd = finite_difference_tangent(m, s, h, de);
    let err = max_diff(&alg, &fd) / m.young();
    println!("{:>14} {label:<40} {err:.2e}", m.name());
    assert!(err <= TOL, "{label}: {err:e} E\nalg {alg:?}\nfd  {fd:?}");
    err
}

/// The four plastic directions of the strain increment (uniaxial-stress
/// like, equibiaxial, pure shear, mixed), unit size.
const DIRECTIONS: [(&str, [f64; 3]); 4] = [
    ("uniaxial", [1.0, -0.5, 0.0]),
    ("equibiaxial", [1.0, 1.0, 0.0]),
    ("pure shear", [0.0, 0.0, 2.0]),
    ("mixed", [0.8, -0.3, 0.9]),
];

/// Every case of one material: elastic from a virgin point, plastic in the
/// four directions from a virgin point and from a prestrained one
/// (`prestrain`, ε_p of a few per cent), elastic unloading from it. `ey`
/// the initial yield strain; returns the worst error and the plastic
/// strains the cases end at.
fn all_cases<M: Material>(m: &M, prestrain: [f64; 3]) -> (f64, Vec<f64>) {
    let ey = m.flow_stress(&m.initial_history()) / m.young();
    let virgin = ([0.0; 3], m.initial_history());
    let plastic = loaded(m, prestrain, 40);
    assert!(m.plastic_strain(&plastic.1) > 0.01, "prestrain is plastic");
    let mut worst = 0.0f64;
    let mut ends = Vec::new();
    let mut run = |label: String, (s, h): &([f64; 3], M::History), de: [f64; 3], yields: bool| {
        assert_eq!(is_plastic(m, s, h, de), yields, "{label}: plastic?");
        worst = worst.max(check(&label, m, s, h, de));
        let (mut s1, mut h1) = (*s, *h);
        m.update(&mut s1, &mut h1, de);
        ends.push(m.plastic_strain(&h1));
    };
    for (name, d) in DIRECTIONS {
        run(
            format!("elastic from virgin, {name}"),
            &virgin,
            d.map(|c| 0.3 * ey * c),
            false,
        );
        for mag in [5.0, 20.0] {
            let de = d.map(|c| mag * ey * c);
            run(
                format!("plastic from virgin, {name} ×{mag}"),
                &virgin,
                de,
                true,
            );
            run(
                format!("plastic from plastic, {name} ×{mag}"),
                &plastic,
                de,
                true,
            );
        }
    }
    let norm = prestrain.iter().map(|c| c * c).sum::<f64>().sqrt();
    let back = prestrain.map(|c| -0.5 * ey * c / norm);
    run(
        "elastic unloading from plastic".into(),
        &plastic,
        back,
        false,
    );
    (worst, ends)
}

#[test]
fn j2_swift_tangent_matches_finite_differences() {
    let (worst, _) = all_cases(&j2(swift()), [0.03, -0.01, 0.01]);
    println!("J2, Swift: worst {worst:.2e} E");
}

#[test]
fn j2_table_tangent_matches_finite_differences() {
    let (worst, ends) = all_cases(&j2(table()), [0.03, -0.01, 0.01]);
    for e in ends {
        for k in TABLE_KINKS {
            assert!((e - k).abs() > 1e-4, "ε_p {e} is at a kink of the table");
        }
    }
    println!("J2, table: worst {worst:.2e} E");
}

#[test]
fn hill48_tangent_matches_finite_differences() {
    for (label, m, tabulated) in [
        (
            "steel r, θ = 0.7, Swift",
            hill(swift(), STEEL_R, 0.7),
            false,
        ),
        (
            "aluminium r, θ = 0.3, Swift",
            hill(swift(), AL_R, 0.3),
            false,
        ),
        ("steel r, θ = 0.2, table", hill(table(), STEEL_R, 0.2), true),
    ] {
        let (worst, ends) = all_cases(&m, [0.03, -0.01, 0.01]);
        for e in ends.into_iter().filter(|_| tabulated) {
            for k in TABLE_KINKS {
                assert!((e - k).abs() > 1e-4, "{label}: ε_p {e} is at a kink");
            }
        }
        println!("Hill'48, {label}: worst {worst:.2e} E");
    }
}

/// The continuum (rate) tangent `C − (CPσ)(CPσ)ᵀ / (σᵀPCPσ + β)` at the
/// stress σ, for a criterion `σᵀPσ` and the hardening term β.
fn continuum(p: &[[f64; 3]; 3], s: &[f64; 3], beta: f64) -> [[f64; 3]; 3] {
    let c = plane_stress_elasticity(E, NU);
    let mv = |m: &[[f64; 3]; 3], v: &[f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|k| m[i][k] * v[k]).sum())
    };
    let ps = mv(p, s);
    let n = mv(&c, &ps);
    let den = (0..3).map(|k| ps[k] * n[k]).sum::<f64>() + beta;
    std::array::from_fn(|i| std::array::from_fn(|j| c[i][j] - n[i] * n[j] / den))
}

/// J2's `P` (`σᵀPσ = ⅔ σ_vm²`), with which its continuum tangent's
/// hardening term is `β = 4/9 σ_y² H`.
const P_J2: [[f64; 3]; 3] = [
    [2.0 / 3.0, -1.0 / 3.0, 0.0],
    [-1.0 / 3.0, 2.0 / 3.0, 0.0],
    [0.0, 0.0, 2.0],
];

/// The continuum tangent of `m` after the increment `de` from `(s, h)`.
type Continuum<M> = fn(&M, &[f64; 3], &<M as Material>::History) -> [[f64; 3]; 3];

/// Negative controls in a plastic state (a mixed increment of `mag` yield
/// strains from a prestrained point): the elastic matrix and the continuum
/// tangent both miss the differences by more than [`WRONG`] E while the
/// algorithmic tangent meets [`TOL`]; and for a small increment the
/// continuum tangent approaches the algorithmic one (Δλ → 0), linearly,
/// which checks the continuum formula used as a control.
fn controls<M: Material>(m: &M, cont: Continuum<M>) {
    let ey = m.flow_stress(&m.initial_history()) / m.young();
    let (s, h) = loaded(m, [0.03, -0.01, 0.01], 40);
    let dir = [0.8, -0.3, 0.9];
    let at = |mag: f64| {
        let de = dir.map(|c| mag * ey * c);
        assert!(is_plastic(m, &s, &h, de));
        let (mut s1, mut h1) = (s, h);
        m.update(&mut s1, &mut h1, de);
        let fd = finite_difference_tangent(m, &s, &h, de);
        (m.consistent_tangent(&s, &h, de), fd, cont(m, &s1, &h1))
    };
    let (alg, fd, ct) = at(10.0);
    let el = plane_stress_elasticity(E, NU);
    let e = |a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]| max_diff(a, b) / E;
    println!(
        "{}: |alg − fd| {:.2e}, |C − fd| {:.2e}, |cont − fd| {:.2e}, |alg − cont| {:.2e} (E)",
        m.name(),
        e(&alg, &fd),
        e(&el, &fd),
        e(&ct, &fd),
        e(&alg, &ct)
    );
    assert!(e(&alg, &fd) <= TOL);
    assert!(e(&el, &fd) > WRONG, "the elastic matrix passes the check");
    assert!(
        e(&ct, &fd) > WRONG,
        "the continuum tangent passes the check"
    );
    assert!(
        e(&alg, &ct) > WRONG,
        "consistent and continuum tangents agree"
    );
    let small: Vec<f64> = [1e-2, 1e-3]
        .into_iter()
        .map(|mag| {
            let (alg, _, ct) = at(mag);
            e(&alg, &ct)
        })
        .collect();
    println!(
        "  |alg − cont| at 1e-2, 1e-3 yield strains: {:.2e}, {:.2e} (E)",
        small[0], small[1]
    );
    assert!(small[1] < 0.2 * small[0] && small[1] < 1e-3, "{small:?}");
}

#[test]
fn wrong_tangents_fail_the_check_j2() {
    controls(&j2(swift()), |m, s, h| {
        let slope = m.hardening().eval(h.eps_p).1;
        continuum(&P_J2, s, 4.0 / 9.0 * h.sigma_y * h.sigma_y * slope)
    });
}

#[test]
fn wrong_tangents_fail_the_check_hill48() {
    controls(&hill(swift(), STEEL_R, 0.7), |m, s, h| {
        let slope = m.hardening().eval(h.eps_p).1;
        continuum(&m.criterion_matrix(), s, h.sigma_y * h.sigma_y * slope)
    });
}

/// The example plugin j2-voce, linked into the test (no shared library):
/// plane-stress J2 with `σ_y = σ0 + h ε_p` (Voce's term off).
fn plugin_j2(sigma0: f64, slope: f64) -> PluginMaterial {
    let lib = MaterialLibrary::linked::<j2_voce::J2Voce>().expect("table");
    let params = Params::new()
        .with("youngs_modulus", E)
        .with("poissons_ratio", NU)
        .with("density", 7.85e-9)
        .with("sigma0", sigma0)
        .with("h", slope);
    PluginMaterial::new(lib.build(&params).expect("material")).expect("adapter")
}

/// A plugin material keeps the default tangent (finite differences): in
/// the elastic range, from a virgin point and from a plastic one, it is
/// the plane-stress elasticity within [`TOL`] E; in a plastic state it
/// equals the built-in J2's closed form for the same law (the plugin's own
/// return, converged) within [`TOL`] E.
#[test]
fn plugin_material_default_tangent() {
    let (sigma0, slope) = (300.0, 1000.0);
    let p = plugin_j2(sigma0, slope);
    let builtin = j2(Hardening::table(&[(0.0, sigma0), (10.0, sigma0 + 10.0 * slope)]).unwrap());
    let ey = sigma0 / E;
    let el = plane_stress_elasticity(E, NU);
    let virgin = ([0.0; 3], p.initial_history());
    let plastic = loaded(&p, [0.03, -0.01, 0.01], 40);
    let back = [-0.5 * ey, 0.2 * ey, -0.1 * ey];
    for (label, (s, h), de) in [
        ("virgin", &virgin, [0.3 * ey, -0.1 * ey, 0.2 * ey]),
        ("unloading", &plastic, back),
    ] {
        assert!(!is_plastic(&p, s, h, de), "{label} is elastic");
        let err = max_diff(&p.consistent_tangent(s, h, de), &el) / E;
        println!("plugin, elastic from {label}: {err:.2e} E");
        assert!(err <= TOL, "{label}: {err:e}");
    }
    let (sb, hb) = loaded(&builtin, [0.03, -0.01, 0.01], 40);
    for (name, d) in DIRECTIONS {
        let de = d.map(|c| 5.0 * ey * c);
        assert!(is_plastic(&p, &plastic.0, &plastic.1, de));
        let fd = p.consistent_tangent(&plastic.0, &plastic.1, de);
        let err = max_diff(&builtin.consistent_tangent(&sb, &hb, de), &fd) / E;
        println!("plugin vs built-in J2, plastic {name}: {err:.2e} E");
        assert!(err <= TOL, "{name}: {err:e}");
    }
}
