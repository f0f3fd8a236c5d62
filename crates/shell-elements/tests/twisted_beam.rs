//! MacNeal & Harder (1985) twisted beam through fem-core's explicit solver with dynamic
//! relaxation — the warped-element benchmark — for the fully integrated shell and for
//! Belytschko–Tsay with and without the warping correction, plus the one-element check
//! that explains the results: a rigid rotation of a warped element must not strain it.
//! Run in release: `cargo test -p shell-elements --release --test twisted_beam`; the
//! studies and the checks that still fail: `-- --ignored --nocapture` (several
//! minutes).
//!
//! Geometry (MacNeal & Harder 1985, "A proposed standard set of problems to test finite
//! element accuracy", Finite Elements in Analysis and Design 1, 3–20): length L = 12,
//! width 1.1, the cross-section twisted linearly by 90° from the clamped root (width
//! along global y) to the free tip (width along global z); E = 29.0e6, ν = 0.22.
//! Reference tip displacements in the load direction (linear theory), as published with
//! the problem and reproduced in the FinEtools twisted-beam tutorial (5.424534868469e-3 /
//! 1.753248285256e-3, thin: 5.256e-3 / 1.294e-3) and Altair's OptiStruct verification
//! OS-V 0700 (0.005424 / 0.001754):
//!
//! | t | tip load | in-plane (tip width, global z) | out-of-plane (tip thickness, global y) |
//! |---|---|---|---|
//! | 0.32 | 1 | 5.424e-3 | 1.754e-3 |
//! | 0.0032 | 1e-6 | 5.256e-3 | 1.294e-3 |
//!
//! (Check of the set-up: Euler–Bernoulli with the rotating section,
//! u = P ∫(L−x)² [cos²φ/EI_weak + sin²φ/EI_strong] dx = 5.426e-3 for the in-plane load.)
//!
//! Tolerance: 3 % on the tip displacement. Warped-element kinematics (`docs/shells.md`,
//! "Warped elements"): both elements remove a warped element's rigid rotation about its
//! in-plane axes from the in-plane velocities (the rigid-rotation checks below), and
//! the warping correction (option) is first-order kinematics on the twisted surface:
//! fibres along the nodal normals, twisted metric, drilling about the nodal normals.
//! Measured (release; `twisted_beam_study`, `twisted_beam_thin_study`,
//! `twisted_beam_thin_8x48_study`; error to the reference; "—": not run, for time):
//!
//! | t | mesh | load | FI | FI + warp | BT | BT + warp |
//! |---|---|---|---|---|---|---|
//! | 0.32 | 2×12 | in-plane | +27.6 % | −1.39 % | +29.7 % | +0.12 % |
//! | 0.32 | 4×24 | in-plane | +30.5 % | −0.52 % | +31.1 % | −0.12 % |
//! | 0.32 | 8×48 | in-plane | +31.8 % | −0.25 % | +32.0 % | −0.14 % |
//! | 0.32 | 2×12 | out-of-plane | +17.8 % | −8.32 % | +32.1 % | +6.08 % |
//! | 0.32 | 4×24 | out-of-plane | +23.5 % | −2.63 % | +27.2 % | +1.04 % |
//! | 0.32 | 8×48 | out-of-plane | +25.3 % | −0.81 % | +26.3 % | +0.13 % |
//! | 0.0032 | 2×12 | in-plane | −8.17 % | −2.52 % | −6.66 % | −0.78 % |
//! | 0.0032 | 4×24 | in-plane | −1.22 % | −1.01 % | −0.35 % | −0.13 % |
//! | 0.0032 | 8×48 | in-plane | — | — | — | −0.10 % |
//! | 0.0032 | 2×12 | out-of-plane | −3.77 % | −2.97 % | −2.83 % | −1.94 % |
//! | 0.0032 | 4×24 | out-of-plane | −0.91 % | −0.90 % | −0.47 % | −0.45 % |
//! | 0.0032 | 8×48 | out-of-plane | — | — | — | −0.19 % |
//!
//! What sets the rest:
//! * Without the warping correction the answer is set by the drilling penalty, not by
//!   the mesh: on the faceted twisted surface the nodal rotation about an element's
//!   normal is bending for the twisted section (the fibres' tilt), and the flat
//!   kinematics hold it only by the drilling penalty (∝ γ t). Thick, 2×12 in-plane
//!   (`twisted_beam_penalty_study`): FI +222 / +27.6 / +1.6 / −1.2 % and BT +235 /
//!   +29.7 / +3.1 / +0.14 % for γ = 1e-4 / 1e-3 (default) / 1e-2 / 1e-1 (4×24: FI +230
//!   / +30.5 / +2.6 / −0.26 %). With γ = 1e-3 the runs are settled: relaxing five times
//!   longer moves them by ≤ 0.08 % (`twisted_beam_relaxation_study`). With the
//!   correction the answer does not depend on γ: BT + warp in-plane 2×12 +0.14 /
//!   +0.12 / +0.08 / −0.19 %, FI + warp −1.33 / −1.39 / −1.43 / −1.53 % for the same γ.
//! * Out-of-plane, 2×12: the load runs along the root's width, so the root, where the
//!   moment is largest, bends in its plane, and two elements across the width are too
//!   few for bilinear membranes in in-plane bending: the same harness with no twist
//!   (`straight_strip_in_plane_bending_study`, Timoshenko reference 5.630e-4) gives FI
//!   −26.3 % (2×12) / −8.3 % (4×24) and BT +29.1 % / +5.9 % (one-point membrane,
//!   hourglass r = 0.05; r = 0.2: +19.7 % / +4.2 %). Hence FI + warp −8.3 % and BT + warp
//!   +6.1 % at 2×12, both within 3 % from 4×24 on (the 4×24 acceptance tests).
//! * Out-of-plane 2×12 without the correction: FI +224 / +17.8 / −5.9 / −9.3 %, BT +241 /
//!   +32.1 / +8.2 / +2.5 % for γ = 1e-4 / 1e-3 / 1e-2 / 1e-1; with it FI + warp −8.0 /
//!   −8.3 / −8.5 / −9.7 %, BT + warp +6.5 / +6.1 / +5.7 / +2.2 % (4×24: FI + warp −2.58 /
//!   −2.63 / −2.68 / −3.17 %, BT + warp +1.09 / +1.04 / +0.97 / +0.33 %).
//! * Thin (2×12 in-plane, `twisted_beam_thin_penalty_study`), the flat drilling penalty
//!   stiffens instead (it also holds the bending rotations' share along the element
//!   normal, ∝ t against bending ∝ t³): BT −1.36 / −6.66 / −28.7 % for γ = 1e-4 / 1e-3 /
//!   1e-2; the correction's drilling about the nodal normals removes it (BT + warp
//!   −0.77 / −0.78 / −0.86 %).
mod common;
use std::collections::BTreeMap;
use std::time::Instant;

use common::elastic;
use fem_core::{Amplitude, Control, Dof, Dofs, NodalLoad, Solver, SolverSettings, Vec3};
use shell_elements::{
    BelytschkoTsay, FullyIntegrated, RuleKind, Section, ShellFormulation, ShellSet,
};

const LENGTH: f64 = 12.0;
const WIDTH: f64 = 1.1;
const YOUNG: f64 = 29.0e6;
const POISSON: f64 = 0.22;
/// Twist rate of the benchmark, 90° over the length (rad/mm).
const TWIST_RATE: f64 = std::f64::consts::FRAC_PI_2 / LENGTH;

/// Direction of the tip load.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Load {
    /// Along the width of the tip section (global z): in the plane of the shell there.
    InPlane,
    /// Along the thickness of the tip section (global y): normal to the shell there.
    OutOfPlane,
}

/// Benchmark tip load: 1 for t = 0.32, 1e-6 for t = 0.0032.
fn load_magnitude(t: f64) -> f64 {
    if t > 0.01 { 1.0 } else { 1e-6 }
}

/// Reference tip displacement (MacNeal & Harder 1985) under the benchmark load.
fn reference(t: f64, load: Load) -> f64 {
    match (t > 0.01, load) {
        (true, Load::InPlane) => 5.424e-3,
        (true, Load::OutOfPlane) => 1.754e-3,
        (false, Load::InPlane) => 5.256e-3,
        (false, Load::OutOfPlane) => 1.294e-3,
    }
}

/// The result of one run.
#[derive(Debug, Clone, Copy)]
struct Run {
    /// Tip displacement in the load direction under the benchmark load (work-conjugate
    /// mean over the tip nodes), linear range.
    u: f64,
    /// Relative change of `u` over the last tenth of the run (convergence check).
    change: f64,
    steps: u64,
    seconds: f64,
}

/// The solver is geometrically nonlinear (co-rotational), the references linear:
/// every case runs at 1/1000 of the benchmark load and divides back.
const LINEAR_RANGE: f64 = 1e-3;

/// Tolerance on the tip displacement.
const TOL: f64 = 0.03;

/// The twisted beam with `nw` elements across the width and `nl` along the length,
/// thickness `t`, the benchmark tip load in direction `load` times [`LINEAR_RANGE`].
///
/// Nodes lie on the helicoid `(x, s cos φ, s sin φ)`, φ = x·90°/L, so every element is
/// warped: its nodes sit at ±z_h = ±c a b off its mean plane (c the twist rate, 2a × 2b
/// the element). The tip load is spread over the tip nodes as a uniform edge load (ends
/// 1/(2 nw), interior 1/nw); the displacement reported is the same weighted mean (the
/// one work-conjugate to the load). Quasi-static by dynamic relaxation:
/// mass-proportional damping `c = 2ω` with ω the first bending frequency of the
/// untwisted cantilever about its weak axis (a lower bound of the twisted beam's), run
/// for `14/ω`; elastic, two Gauss points through the thickness (exact for a linear
/// stress profile).
fn twisted_beam<F: ShellFormulation>(
    form: F,
    mesh: (usize, usize),
    t: f64,
    hourglass: f64,
    load: Load,
) -> Run {
    twisted_beam_for(form, mesh, t, hourglass, load, 14.0, TWIST_RATE)
}

/// [`twisted_beam`] relaxed for `periods / ω` instead of `14/ω`, with twist rate
/// `twist` (rad/mm) instead of 90° over the length (0: a straight strip).
fn twisted_beam_for<F: ShellFormulation>(
    form: F,
    (nw, nl): (usize, usize),
    t: f64,
    hourglass: f64,
    load: Load,
    periods: f64,
    twist: f64,
) -> Run {
    let id = |i: usize, j: usize| j * (nl + 1) + i;
    let mut nodes = Vec::with_capacity((nl + 1) * (nw + 1));
    for j in 0..=nw {
        let s = WIDTH * (j as f64 / nw as f64 - 0.5);
        for i in 0..=nl {
            let x = LENGTH * i as f64 / nl as f64;
            let phi = twist * x;
            nodes.push(Vec3::new(x, s * phi.cos(), s * phi.sin()));
        }
    }
    let mut quads = Vec::with_capacity(nl * nw);
    for j in 0..nw {
        for i in 0..nl {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)].map(|k| k as u32));
        }
    }
    let mut sets: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    sets.insert("root".into(), (0..=nw).map(|j| id(0, j) as u32).collect());
    let tip: Vec<(usize, f64)> = (0..=nw)
        .map(|j| {
            let w = if j == 0 || j == nw { 0.5 } else { 1.0 } / nw as f64;
            (id(nl, j), w)
        })
        .collect();
    for &(k, _) in &tip {
        sets.insert(format!("tip{k}"), vec![k as u32]);
    }
    let rho = 1.0;
    let mat = elastic(YOUNG, POISSON, rho);
    let section = Section::new(t)
        .unwrap()
        .with_rule(RuleKind::Gauss, 2)
        .unwrap()
        .with_hourglass(hourglass)
        .unwrap();
    let set = ShellSet::new("beam", &nodes, &quads, section, form, mat).unwrap();
    let i_weak = WIDTH * t.powi(3) / 12.0;
    let omega = 3.516 * (YOUNG * i_weak / (rho * WIDTH * t * LENGTH.powi(4))).sqrt();
    let t_end = periods / omega;
    let settings = SolverSettings {
        damping: 2.0 * omega,
        ..Default::default()
    };
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    s.add_effect(set);
    s.fix("root", Dofs::ALL).unwrap();
    let (dof, axis) = match load {
        Load::InPlane => (Dof::Uz, 2),
        Load::OutOfPlane => (Dof::Uy, 1),
    };
    let factor = load_magnitude(t) * LINEAR_RANGE;
    for &(k, w) in &tip {
        s.add_load(&NodalLoad {
            set: format!("tip{k}"),
            dof,
            value: w * factor,
            amplitude: Amplitude::Constant,
        })
        .unwrap();
    }
    let probe = |sv: &Solver| -> f64 {
        let st = sv.state();
        let u: f64 = tip
            .iter()
            .map(|&(k, w)| w * (st.x[k][axis] - st.x0[k][axis]))
            .sum();
        u / LINEAR_RANGE
    };
    let clock = Instant::now();
    let mut at_90 = None;
    s.run_until(t_end, &mut |sv, r| {
        if at_90.is_none() && r.time >= 0.9 * t_end {
            at_90 = Some(probe(sv));
        }
        Control::Continue
    })
    .unwrap();
    let u = probe(&s);
    Run {
        u,
        change: at_90.map_or(f64::INFINITY, |a| (u / a - 1.0).abs()),
        steps: s.steps(),
        seconds: clock.elapsed().as_secs_f64(),
    }
}

/// Run one case (default hourglass coefficient) and print it; returns the run and its
/// relative error to the reference.
fn case<F: ShellFormulation>(
    label: &str,
    form: F,
    mesh: (usize, usize),
    t: f64,
    load: Load,
) -> (Run, f64) {
    run_case(
        label,
        form,
        mesh,
        t,
        Section::new(t).unwrap().hourglass,
        load,
    )
}

/// [`case`] at t = 0.32 with hourglass coefficient `r`.
fn case_hourglass<F: ShellFormulation>(
    label: &str,
    form: F,
    mesh: (usize, usize),
    r: f64,
    load: Load,
) -> (Run, f64) {
    run_case(label, form, mesh, 0.32, r, load)
}

fn run_case<F: ShellFormulation>(
    label: &str,
    form: F,
    (nw, nl): (usize, usize),
    t: f64,
    hourglass: f64,
    load: Load,
) -> (Run, f64) {
    let r = twisted_beam(form, (nw, nl), t, hourglass, load);
    let err = r.u / reference(t, load) - 1.0;
    println!(
        "twisted beam t = {t}, {load:?}, {label}, {nw}×{nl}: u = {:.5e} (ref {:.4e}, {:+.2} %), \
         change over last 10 %: {:.1e}, {} steps, {:.1} s",
        r.u,
        reference(t, load),
        100.0 * err,
        r.change,
        r.steps,
        r.seconds
    );
    (r, err)
}

/// Assert a case: converged (relative change over the last tenth < 1e-3, a tenth of
/// the tolerance at most) and within 3 %.
fn assert_case<F: ShellFormulation>(label: &str, form: F, mesh: (usize, usize), load: Load) {
    assert_case_t(label, form, mesh, 0.32, load);
}

/// [`assert_case`] at thickness `t`.
fn assert_case_t<F: ShellFormulation>(
    label: &str,
    form: F,
    mesh: (usize, usize),
    t: f64,
    load: Load,
) {
    let (r, err) = case(label, form, mesh, t, load);
    assert!(r.change < 1e-3, "not converged: change {:.2e}", r.change);
    assert!(err.abs() < TOL, "{label}: {:+.2} %", 100.0 * err);
}

fn bt(warping_correction: bool) -> BelytschkoTsay {
    BelytschkoTsay {
        warping_correction,
        ..Default::default()
    }
}

fn fi(warping_correction: bool) -> FullyIntegrated {
    FullyIntegrated {
        warping_correction,
        ..Default::default()
    }
}

// ----- the benchmark (acceptance tests of the warped-element kinematics) ---------------

/// MacNeal & Harder (1985) standard mesh 2×12, t = 0.32, in-plane load, fully
/// integrated shell (default options, no warping correction): 5.424e-3 within 3 %.
/// Measured: 6.921e-3 (+27.6 %). Without the warping correction the
/// faceted twisted beam is drilling-soft: +27.6 / +30.5 / +31.8 % at 2×12 / 4×24 /
/// 8×48, +1.6 % with γ = 1e-2 (`twisted_beam_penalty_study`); with the correction
/// −1.39 % (`twisted_beam_study`).
#[test]
#[ignore = "fails (+27.6 %): without the warping correction the element is drilling-soft on the twisted facets (FI + warping correction: −1.39 %)"]
fn twisted_beam_in_plane_2x12_fully_integrated() {
    assert_case("FI", fi(false), (2, 12), Load::InPlane);
}

/// Same, out-of-plane load: 1.754e-3 within 3 %. Measured: 2.065e-3 (+17.8 %).
/// With the warping correction −8.3 % at 2×12 (−2.6 / −0.8 %
/// at 4×24 / 8×48): the root, where the moment is largest, bends in its plane, and a
/// 2-element-wide bilinear membrane locks in in-plane bending (straight strip, same
/// mesh: −26 %).
#[test]
#[ignore = "fails (+17.8 %): drilling-soft without the warping correction; with it −8.3 % from in-plane bending locking of the 2-element-wide membrane at the root"]
fn twisted_beam_out_of_plane_2x12_fully_integrated() {
    assert_case("FI", fi(false), (2, 12), Load::OutOfPlane);
}

/// MacNeal & Harder (1985) standard mesh 2×12, t = 0.32, in-plane load,
/// Belytschko–Tsay with the warping correction: 5.424e-3 within 3 % (and converged).
/// Measured: 5.430e-3 (+0.12 %; without the correction +29.7 %, drilling-soft).
#[test]
fn twisted_beam_in_plane_2x12_belytschko_tsay_warping_correction() {
    assert_case("BT+warp", bt(true), (2, 12), Load::InPlane);
}

/// Same, out-of-plane load: 1.754e-3 within 3 %. Measured: 1.861e-3 (+6.1 %; +1.0 /
/// +0.13 % at 4×24 / 8×48). The root bends in its plane, and a 2-element-wide strip of
/// one-point membranes with the default hourglass control (r = 0.05) is too soft in
/// in-plane bending (straight strip, same mesh: +29 %; r = 0.2: +20 %, and the
/// twisted beam +3.6 %). Insensitive to the drilling coefficient from 1e-4 to 1e-2.
#[test]
#[ignore = "fails (+6.1 %): one-point membrane with the default hourglass stiffness too soft in in-plane bending of the 2-element-wide root (4×24: +1.0 %)"]
fn twisted_beam_out_of_plane_2x12_belytschko_tsay_warping_correction() {
    assert_case("BT+warp", bt(true), (2, 12), Load::OutOfPlane);
}

/// MacNeal & Harder (1985) standard mesh 2×12, t = 0.32, in-plane load, fully
/// integrated shell with the warping correction: 5.424e-3 within 3 % (and converged).
/// Measured: 5.348e-3 (−1.39 %).
#[test]
fn twisted_beam_in_plane_2x12_fully_integrated_warping_correction() {
    assert_case("FI+warp", fi(true), (2, 12), Load::InPlane);
}

/// Out-of-plane load on the first refined mesh, 4×24 (the 2×12 mesh misses, see above),
/// Belytschko–Tsay with the warping correction: 1.754e-3 within 3 %. Measured:
/// 1.772e-3 (+1.04 %; 8×48: +0.13 %).
#[test]
fn twisted_beam_out_of_plane_4x24_belytschko_tsay_warping_correction() {
    assert_case("BT+warp", bt(true), (4, 24), Load::OutOfPlane);
}

/// Same, fully integrated shell with the warping correction: 1.754e-3 within 3 %.
/// Measured: 1.708e-3 (−2.63 %; 8×48: −0.81 %).
#[test]
fn twisted_beam_out_of_plane_4x24_fully_integrated_warping_correction() {
    assert_case("FI+warp", fi(true), (4, 24), Load::OutOfPlane);
}

/// Thin beam (t = 0.0032, load 1e-6), standard mesh 2×12, in-plane load,
/// Belytschko–Tsay with the warping correction: 5.256e-3 within 3 % (and converged).
/// Measured: 5.215e-3 (−0.78 %), about 40 s
/// in release (1.3 million steps).
#[test]
fn twisted_beam_thin_in_plane_2x12_belytschko_tsay_warping_correction() {
    assert_case_t("BT+warp", bt(true), (2, 12), 0.0032, Load::InPlane);
}

/// Mesh and element study, t = 0.32 (not asserted; prints the table of the report).
#[test]
#[ignore = "study: prints the table, ~2 min in release on an idle machine"]
fn twisted_beam_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        for mesh in [(2, 12), (4, 24), (8, 48)] {
            let _ = case("FI", fi(false), mesh, 0.32, load);
            let _ = case("FI+warp", fi(true), mesh, 0.32, load);
            let _ = case("BT", bt(false), mesh, 0.32, load);
            let _ = case("BT+warp", bt(true), mesh, 0.32, load);
        }
    }
}

/// Thin variant t = 0.0032, load 1e-6, meshes 2×12 and 4×24 (not asserted; ~100 times
/// the steps of the thick beam, since the step is set by the membrane waves and the
/// relaxation time by the first bending mode, ∝ t).
#[test]
#[ignore = "study: thin beam 2×12 and 4×24, about half an hour in release"]
fn twisted_beam_thin_study() {
    thin_study(&[(2, 12), (4, 24)]);
}

/// Thin variant on the 8×48 mesh, Belytschko–Tsay with the warping correction only
/// (not asserted; about 20 min per load in release).
#[test]
#[ignore = "study: thin beam 8×48, about 40 min in release"]
fn twisted_beam_thin_8x48_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        let _ = case("BT+warp", bt(true), (8, 48), 0.0032, load);
    }
}

fn thin_study(meshes: &[(usize, usize)]) {
    for load in [Load::InPlane, Load::OutOfPlane] {
        for &mesh in meshes {
            let _ = case("FI", fi(false), mesh, 0.0032, load);
            let _ = case("FI+warp", fi(true), mesh, 0.0032, load);
            let _ = case("BT", bt(false), mesh, 0.0032, load);
            let _ = case("BT+warp", bt(true), mesh, 0.0032, load);
        }
    }
}

/// How the penalties set the answer (t = 0.32, 2×12 and 4×24, not asserted): drilling
/// coefficient γ ∈ {1e-4, 1e-3 (default), 1e-2, 1e-1} for both elements with and
/// without the warping correction, and the hourglass coefficient r ∈ {0.05 (default),
/// 0.2} for Belytschko–Tsay.
#[test]
#[ignore = "study: penalty sensitivity, a few minutes in release"]
fn twisted_beam_penalty_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        for mesh in [(2, 12), (4, 24)] {
            for wc in [false, true] {
                let tag = if wc { "+warp" } else { "" };
                for gamma in [1e-4, 1e-3, 1e-2, 1e-1] {
                    let label = format!("FI{tag} γ = {gamma}");
                    let _ = case(
                        &label,
                        fi(wc).with_drilling(gamma).unwrap(),
                        mesh,
                        0.32,
                        load,
                    );
                    for r in [0.05, 0.2] {
                        let label = format!("BT{tag} γ = {gamma}, r = {r}");
                        let _ = case_hourglass(
                            &label,
                            bt(wc).with_drilling(gamma).unwrap(),
                            mesh,
                            r,
                            load,
                        );
                    }
                }
            }
        }
    }
}

/// Drilling coefficient in the thin limit (t = 0.0032, 2×12, in-plane load, not
/// asserted): Belytschko–Tsay with and without the warping correction for γ = 1e-4 and
/// 1e-2 (the default 1e-3 is in `twisted_beam_thin_study`).
#[test]
#[ignore = "study: thin beam penalty sensitivity, about three minutes in release"]
fn twisted_beam_thin_penalty_study() {
    for gamma in [1e-4, 1e-2] {
        for (tag, wc) in [("BT", false), ("BT+warp", true)] {
            let label = format!("{tag} γ = {gamma}");
            let form = bt(wc).with_drilling(gamma).unwrap();
            let _ = case(&label, form, (2, 12), 0.0032, Load::InPlane);
        }
    }
}

/// Is the relaxation long enough? The 2×12 cases (t = 0.32) relaxed for 14/ω (the
/// default) and for 70/ω (not asserted; prints both).
#[test]
#[ignore = "study: relaxation-time check, about a minute in release"]
fn twisted_beam_relaxation_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        for (label, wc) in [("no correction", false), ("warping correction", true)] {
            for periods in [14.0, 70.0] {
                let r = |u: f64| 100.0 * (u / reference(0.32, load) - 1.0);
                let hg = Section::new(0.32).unwrap().hourglass;
                let a = twisted_beam_for(fi(wc), (2, 12), 0.32, hg, load, periods, TWIST_RATE);
                let b = twisted_beam_for(bt(wc), (2, 12), 0.32, hg, load, periods, TWIST_RATE);
                println!(
                    "{load:?}, {label}, {periods}/ω: FI {:+.2} % (change {:.1e}), \
                     BT {:+.2} % (change {:.1e})",
                    r(a.u),
                    a.change,
                    r(b.u),
                    b.change
                );
            }
        }
    }
}

/// The same harness without twist (a straight strip, width along y, not asserted):
/// the out-of-plane load (global y) then bends the whole strip in its plane, which is
/// what the twisted beam's root does under that load. Reference: Timoshenko cantilever
/// about the strong axis, `P L³/(3 E I) + P L/(κ G A)` with `I = t w³/12`, κ = 5/6.
#[test]
#[ignore = "study: in-plane bending of the untwisted strip, under a minute in release"]
fn straight_strip_in_plane_bending_study() {
    let t = 0.32;
    let i_strong = t * WIDTH.powi(3) / 12.0;
    let g = YOUNG / (2.0 * (1.0 + POISSON));
    let u_ref = LENGTH.powi(3) / (3.0 * YOUNG * i_strong) + LENGTH / (5.0 / 6.0 * g * WIDTH * t);
    for mesh in [(2, 12), (4, 24)] {
        for r in [0.05, 0.2] {
            let runs = [
                (
                    "FI",
                    twisted_beam_for(fi(false), mesh, t, r, Load::OutOfPlane, 14.0, 0.0),
                ),
                (
                    "BT",
                    twisted_beam_for(bt(false), mesh, t, r, Load::OutOfPlane, 14.0, 0.0),
                ),
            ];
            for (label, run) in runs {
                println!(
                    "straight strip {label}, {}×{}, r = {r}: u = {:.4e} (ref {u_ref:.4e}, {:+.2} %), \
                     change {:.1e}",
                    mesh.0,
                    mesh.1,
                    run.u,
                    100.0 * (run.u / u_ref - 1.0),
                    run.change
                );
            }
        }
    }
}

// ----- rigid rotation of one element -----------------------------------------------------

/// One element 1 × 0.55 (the 2×12 twisted beam's), nodes at heights ±`zh` off its mean
/// plane, given the velocity field of a rigid rotation about local axis `axis` at
/// 1 rad/s for one step of 1e-6 s (x = x0). Returns the largest stress over its points
/// divided by E′ = E/(1−ν²) and by the rotation angle (-, per rad), and the largest
/// nodal force divided by E t·1 mm and by the angle (per rad). A correct element
/// gives zero for both (up to round-off): a rigid motion does no work.
fn rigid_rotation_response<F: ShellFormulation>(form: F, zh: f64, axis: usize) -> (f64, f64) {
    let t = 0.32;
    let x0 = vec![
        Vec3::new(-0.5, -0.275, zh),
        Vec3::new(0.5, -0.275, -zh),
        Vec3::new(0.5, 0.275, zh),
        Vec3::new(-0.5, 0.275, -zh),
    ];
    let mut omega = Vec3::zeros();
    omega[axis] = 1.0;
    let v: Vec<Vec3> = x0.iter().map(|p| omega.cross(p)).collect();
    let w = vec![omega; 4];
    let dt = 1e-6;
    let section = Section::new(t).unwrap();
    let n = section.rule.n;
    let mut set = ShellSet::new(
        "one",
        &x0,
        &[[0, 1, 2, 3]],
        section,
        form,
        elastic(YOUNG, POISSON, 1.0),
    )
    .unwrap();
    let f = common::one_step(&mut set, &x0, &v, &w, dt);
    let angle = dt;
    let e_ps = YOUNG / (1.0 - POISSON * POISSON);
    let mut s_max: f64 = 0.0;
    for p in 0..F::IN_PLANE_POINTS {
        for k in 0..n {
            for c in set.stress(0, p, k) {
                s_max = s_max.max(c.abs());
            }
        }
    }
    let f_max = f.f.iter().map(|x| x.norm()).fold(0.0, f64::max);
    (s_max / e_ps / angle, f_max / (YOUNG * t) / angle)
}

/// Warping of the 2×12 twisted beam's elements: z_h = c a b.
fn benchmark_warp() -> f64 {
    TWIST_RATE * 0.5 * 0.275
}

/// Control: rigid rotations about all three local axes of a *flat* element leave it
/// unstrained and force-free (tolerance 1e-12 per radian: round-off).
#[test]
fn rigid_rotation_of_flat_element_is_strain_free() {
    for axis in 0..3 {
        for (name, (s, f)) in [
            ("FI", rigid_rotation_response(fi(false), 0.0, axis)),
            ("BT", rigid_rotation_response(bt(false), 0.0, axis)),
            ("BT+warp", rigid_rotation_response(bt(true), 0.0, axis)),
        ] {
            assert!(
                s < 1e-12 && f < 1e-12,
                "{name}, axis {axis}: {s:.2e} {f:.2e}"
            );
        }
    }
}

/// A rigid rotation of a warped element (z_h = c a b = 0.018 mm, the 2×12 twisted
/// beam's) must not strain it (tolerance 1e-12 per radian). For rotations about the
/// local in-plane axes the projected-plane kinematics alone would read the in-plane
/// nodal velocities of the rotation, `v̂x = ω̂y ẑ_I`, `v̂y = −ω̂x ẑ_I` (ẑ_I = ±z_h), as
/// membrane strain rates; with the 2×2 B-matrix, `Σ ∂N_I/∂x ẑ_I = z_h η/a` and
/// `Σ ∂N_I/∂y ẑ_I = z_h ξ/b` are not zero off the centre, so `d_xx = ω̂y c b η`,
/// `d_yy = −ω̂x c a ξ` at the Gauss points (σ/E′ = 0.038 per radian about x).
/// The element's rigid rotation about its in-plane axes is therefore removed from the
/// in-plane velocities first (measured: σ/E′ ≤ 8.7e-17, f/(E t) ≤ 3.4e-17 per radian).
#[test]
fn rigid_rotation_of_warped_element_is_strain_free_fully_integrated() {
    for axis in 0..3 {
        let (s, f) = rigid_rotation_response(fi(false), benchmark_warp(), axis);
        println!("FI, rotation about local axis {axis}: σ/E′ {s:.3e}, f/(E t) {f:.3e} per rad");
        assert!(s < 1e-12 && f < 1e-12, "axis {axis}: {s:.2e} {f:.2e}");
    }
}

/// The same for Belytschko–Tsay (with and without the warping correction): the centre
/// B-matrix is orthogonal to ẑ ∝ h, so no stress arises, but the membrane hourglass
/// rates `q_x = γ·v̂x`, `q_y = γ·v̂y` are not (Σ γ_I ẑ_I = 2 z_h), so without the
/// removal the hourglass control would resist rigid rotations (measured with it:
/// f/(E t) = 0 to 2.6e-20 per radian).
#[test]
fn rigid_rotation_of_warped_element_is_force_free_belytschko_tsay() {
    for warping_correction in [false, true] {
        for axis in 0..3 {
            let (s, f) = rigid_rotation_response(bt(warping_correction), benchmark_warp(), axis);
            println!(
                "BT (warping correction {warping_correction}), rotation about local axis {axis}: \
                 σ/E′ {s:.3e}, f/(E t) {f:.3e} per rad"
            );
            assert!(s < 1e-12 && f < 1e-12, "axis {axis}: {s:.2e} {f:.2e}");
        }
    }
}
