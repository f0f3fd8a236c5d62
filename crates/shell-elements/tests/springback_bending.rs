//! Springback of a strip bent in plane strain and released, through fem-core's
//! explicit solver: the ratio of the released curvature to the bent one,
//! `κ_f/κ = R/R_f`, against the closed form.
//! Run in release: `cargo test -p shell-elements --release --test springback_bending`.
//!
//! Reference: Gardiner's formula for an elastic–perfectly plastic sheet in
//! plane strain (F. J. Gardiner, "The springback of metals", Trans. ASME 79,
//! 1957), `R/R_f = 1 − 3x + 4x³` with `x = S R/(E′ t)`; for Swift hardening,
//! the same elastic unloading `Δκ = 12 M/(E′ t³)` from the moment integrated
//! through the thickness. Both are `shell_elements::bending` (ν → ½, Hill's
//! plane-strain idealisation, as in `plane_strain_bending.rs`).
//!
//! The strip (`4 × 1` mm, 4 shells, Lobatto 15 points, clamped at x = 0, plane
//! strain across its width) is bent by an end moment that rises along a smooth
//! step over 200 periods of its first mode, falls back to zero over another
//! 200 and is held at zero for 100, with light mass-proportional damping
//! `c = ω₁/20`: the released strip comes to rest. The curvature is the end
//! rotation over the length (uniform moment, so uniform curvature below the
//! rule's saturation). Tolerance 2 % on the ratio: the 15-point rule's moment
//! is within 0.8 % of the continuum's (`plane_strain_bending.rs`), and the
//! springback `Δκ/κ` carries that error at most; the rest is the residual
//! motion after 100 damped periods.

mod common;

use fem_core::{Amplitude, Control, Dof, NodalLoad};
use shell_elements::bending::{PlaneStrainStrip, gardiner_ratio};
use shell_elements::{BelytschkoTsay, FullyIntegrated, Hardening, ShellFormulation};

/// The strip (module docs).
const STRIP: common::PlaneStrainStrip = common::STEEL_STRIP;
const YOUNG: f64 = STRIP.young;
const POISSON: f64 = STRIP.poisson;
const THICKNESS: f64 = STRIP.thickness;
const LENGTH: f64 = STRIP.length;
const WIDTH: f64 = STRIP.width;

/// What a bend and release measured.
#[derive(Debug, Clone, Copy)]
struct Measured {
    /// Largest curvature reached (1/mm).
    kappa_max: f64,
    /// Curvature at rest after release: the mean over the last 50 periods (1/mm).
    kappa_final: f64,
    /// Peak-to-peak of the curvature over those periods, relative to `kappa_final`.
    wobble: f64,
}

/// Bend the strip of `hardening` with `form` by the end moment `moment` (N·mm
/// per mm of width) and release it (module docs).
fn bend_and_release<F: ShellFormulation>(form: F, hardening: Hardening, moment: f64) -> Measured {
    let mesh = STRIP.mesh();
    let mut s = STRIP.solver(&mesh, form, hardening);
    let period = 2.0 * std::f64::consts::PI / STRIP.omega();
    let (t_up, t_down, t_end) = (200.0 * period, 400.0 * period, 500.0 * period);
    // Two end nodes share the moment; the second load takes it off again.
    let per_node = moment * WIDTH / 2.0;
    for (value, t0, t1) in [(per_node, 0.0, t_up), (-per_node, t_up, t_down)] {
        s.add_load(&NodalLoad {
            set: "x1".into(),
            dof: Dof::Ry,
            value,
            amplitude: Amplitude::SmoothStep { t0, t1 },
        })
        .unwrap();
    }
    let tip = mesh.node_sets["x1"][0] as usize;
    let (mut theta, mut kappa_max) = (0.0f64, 0.0f64);
    let (mut sum, mut n, mut lo, mut hi) = (0.0, 0usize, f64::INFINITY, f64::NEG_INFINITY);
    s.run_until(t_end, &mut |sv, r| {
        theta += sv.state().w[tip].y * r.dt;
        let kappa = theta / LENGTH;
        kappa_max = kappa_max.max(kappa.abs());
        if r.time >= t_end - 50.0 * period {
            sum += kappa;
            n += 1;
            lo = lo.min(kappa);
            hi = hi.max(kappa);
        }
        Control::Continue
    })
    .unwrap();
    let kappa_final = sum / n as f64;
    Measured {
        kappa_max,
        kappa_final,
        wobble: (hi - lo) / kappa_final.abs(),
    }
}

/// The strip of `hardening` bent to about `kappa` and released with `form`:
/// its ratio `κ_f/κ_max` and the reference's at `κ_max`.
fn ratio<F: ShellFormulation>(form: F, hardening: Hardening, kappa: f64) -> (f64, f64, Measured) {
    let strip = PlaneStrainStrip::new(YOUNG, POISSON, THICKNESS, hardening.clone()).unwrap();
    let m = bend_and_release(form, hardening, strip.moment(kappa));
    let reference = strip.springback(m.kappa_max).unwrap().ratio;
    let got = m.kappa_final / m.kappa_max;
    println!(
        "{}: κ_max = {:.5} 1/mm (asked {kappa:.5}), κ_f = {:.5} 1/mm, κ_f/κ_max = {got:.4} \
         against {reference:.4} ({:+.2} %), wobble {:.1e}",
        F::NAME,
        m.kappa_max,
        m.kappa_final,
        100.0 * (got / reference - 1.0),
        m.wobble
    );
    (got, reference, m)
}

/// Elastic–perfectly plastic strip bent to twice its first-yield curvature
/// (`x = ¼`): `κ_f/κ` within 2 % of Gardiner's `1 − 3x + 4x³` at the
/// curvature reached, for both elements.
#[test]
fn strip_springback_elastic_perfectly_plastic_gardiner() {
    let perfect = Hardening::swift(250.0, 1.0, 0.0).unwrap();
    let strip = PlaneStrainStrip::new(YOUNG, POISSON, THICKNESS, perfect.clone()).unwrap();
    let kappa = 2.0 * strip.first_yield_curvature();
    for (got, reference, m) in [
        ratio(BelytschkoTsay::default(), perfect.clone(), kappa),
        ratio(FullyIntegrated::default(), perfect.clone(), kappa),
    ] {
        let x =
            strip.plane_strain_yield() / (strip.plane_strain_modulus() * THICKNESS * m.kappa_max);
        assert!((gardiner_ratio(x) / reference - 1.0).abs() < 1e-9);
        assert!(
            (got / reference - 1.0).abs() < 0.02,
            "{got} vs {reference}: {m:?}"
        );
        assert!(m.wobble < 0.01, "not at rest: {m:?}");
    }
}

/// Swift-hardening strip (NUMISHEET'93 mild steel, K = 565.32 MPa,
/// ε0 = 0.007117, n = 0.2589) bent to R = 25 mm (outer fibre strain 2 %):
/// `κ_f/κ` within 2 % of the through-thickness integral at the curvature
/// reached, for both elements.
#[test]
fn strip_springback_swift_hardening_through_thickness() {
    let swift = Hardening::swift(565.32, 0.007117, 0.2589).unwrap();
    for (got, reference, m) in [
        ratio(BelytschkoTsay::default(), swift.clone(), 1.0 / 25.0),
        ratio(FullyIntegrated::default(), swift.clone(), 1.0 / 25.0),
    ] {
        assert!(
            (got / reference - 1.0).abs() < 0.02,
            "{got} vs {reference}: {m:?}"
        );
        assert!(m.wobble < 0.01, "not at rest: {m:?}");
    }
}
