//! MacNeal & Harder (1985) twisted beam through fem-core's explicit solver with dynamic
//! relaxation — the warped-element benchmark — for the fully integrated shell and for
//! Belytschko–Tsay with and without the warping correction, plus the one-element check
//! that explains the results: a rigid rotation of a warped element must not strain it.
//! Run in release: `cargo test -p shell-elements --release --test twisted_beam`; the
//! mesh and element study and the checks that fail today:
//! `-- --ignored --nocapture` (several minutes).
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
//! Tolerance (issue 4): 3 % on the tip displacement. No case meets it with the default
//! parameters (drilling γ = 1e-3, hourglass r = 0.05) at a converged mesh today, so the
//! benchmark tests are `#[ignore]`d with the reason; they are the acceptance tests for
//! the fix of the warped-element kinematics that the rigid-rotation checks isolate.
//! Measured (t = 0.32, release, `twisted_beam_study`; error to the reference):
//!
//! | mesh | load | FI | FI + warp | BT | BT + warp |
//! |---|---|---|---|---|---|
//! | 2×12 | in-plane | −72.7 % | −72.7 % | +11.0 % | +11.0 % |
//! | 4×24 | in-plane | −38.8 % | −38.8 % | +25.7 % | +25.7 % |
//! | 8×48 | in-plane | +0.75 % | +0.75 % | +30.6 % | +30.6 % |
//! | 16×96 | in-plane | +22.6 % (one run, 264 s; still rising) | | | |
//! | 2×12 | out-of-plane | −56.2 % | −56.2 % | +16.7 % | +16.6 % |
//! | 4×24 | out-of-plane | −31.7 % | −31.7 % | +22.8 % | +22.7 % |
//! | 8×48 | out-of-plane | +0.16 % | +0.11 % | +25.1 % | +25.1 % |
//!
//! The warping correction changes no result by more than 0.05 %. The fully integrated
//! shell does not converge: too stiff on coarse meshes (rigid rotations strain a warped
//! element, see the rigid-rotation check: the spurious membrane strain is ∝ c·h, its
//! energy ∝ t against the bending energy ∝ t³), too soft at 16×96 — the 8×48 value is a
//! crossing. Belytschko–Tsay's answer is set by its penalties (`twisted_beam_penalty_study`:
//! 4×24 in-plane −0.3 % with γ = 1e-2, +25.7 % with the default 1e-3; r = 0.05 → 0.2
//! moves it by −9 to −33 %). Thin variant (t = 0.0032, 2×12): FI 2.7e-7 and BT 6.6e-6
//! against 5.256e-3 (in-plane), FI 2.1e-7 and BT 1.7e-6 against 1.294e-3: locked, FI by
//! the same spurious membrane strain (unchanged with γ = 1e-4), BT by the membrane
//! hourglass forces that rigid rotations of warped elements raise (u ∝ 1/r: 6.1e-5 with
//! r = 0.005; unchanged with γ = 1e-4).

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

/// Tolerance on the tip displacement (issue 4).
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
    (nw, nl): (usize, usize),
    t: f64,
    hourglass: f64,
    load: Load,
) -> Run {
    let id = |i: usize, j: usize| j * (nl + 1) + i;
    let mut nodes = Vec::with_capacity((nl + 1) * (nw + 1));
    for j in 0..=nw {
        let s = WIDTH * (j as f64 / nw as f64 - 0.5);
        for i in 0..=nl {
            let x = LENGTH * i as f64 / nl as f64;
            let phi = TWIST_RATE * x;
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
    let t_end = 14.0 / omega;
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
    let (r, err) = case(label, form, mesh, 0.32, load);
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

// ----- the benchmark (acceptance tests of the warped-element fix) ----------------------

/// MacNeal & Harder (1985) standard mesh 2×12, t = 0.32, in-plane load, fully
/// integrated shell: 5.424e-3 within 3 %. Measured today: 1.479e-3 (−72.7 %).
#[test]
#[ignore = "fails today (−72.7 %): rigid rotations strain warped FI elements, see rigid_rotation_of_warped_element_is_strain_free_fully_integrated"]
fn twisted_beam_in_plane_2x12_fully_integrated() {
    assert_case("FI", fi(false), (2, 12), Load::InPlane);
}

/// Same, out-of-plane load: 1.754e-3 within 3 %. Measured today: 7.69e-4 (−56.2 %).
#[test]
#[ignore = "fails today (−56.2 %): rigid rotations strain warped FI elements"]
fn twisted_beam_out_of_plane_2x12_fully_integrated() {
    assert_case("FI", fi(false), (2, 12), Load::OutOfPlane);
}

/// MacNeal & Harder (1985) standard mesh 2×12, t = 0.32, in-plane load,
/// Belytschko–Tsay with the warping correction: 5.424e-3 within 3 %. Measured today:
/// 6.022e-3 (+11.0 %; without the correction: the same to 1e-4).
#[test]
#[ignore = "fails today (+11.0 %): the warping correction changes nothing; answer set by drilling and hourglass penalties"]
fn twisted_beam_in_plane_2x12_belytschko_tsay_warping_correction() {
    assert_case("BT+warp", bt(true), (2, 12), Load::InPlane);
}

/// Same, out-of-plane load: 1.754e-3 within 3 %. Measured today: 2.046e-3 (+16.6 %).
#[test]
#[ignore = "fails today (+16.6 %): the warping correction changes nothing; answer set by drilling and hourglass penalties"]
fn twisted_beam_out_of_plane_2x12_belytschko_tsay_warping_correction() {
    assert_case("BT+warp", bt(true), (2, 12), Load::OutOfPlane);
}

/// Mesh and element study, t = 0.32 (not asserted; prints the table of the report).
#[test]
#[ignore = "study: prints the table, ~10 min in release"]
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

/// Thin variant t = 0.0032, load 1e-6, mesh 2×12 (not asserted; ~100 times the steps
/// of the thick beam, since the step is set by the membrane waves and the relaxation
/// time by the first bending mode, ∝ t).
#[test]
#[ignore = "study: thin beam, several minutes in release"]
fn twisted_beam_thin_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        let _ = case("FI", fi(false), (2, 12), 0.0032, load);
        let _ = case("BT", bt(false), (2, 12), 0.0032, load);
        let _ = case("BT+warp", bt(true), (2, 12), 0.0032, load);
    }
}

/// How the penalties set the answer (t = 0.32, 2×12 and 4×24, not asserted): drilling
/// coefficient γ ∈ {1e-3 (default), 1e-2, 1e-1} for both elements, and the hourglass
/// coefficient r ∈ {0.05 (default), 0.2} for Belytschko–Tsay.
#[test]
#[ignore = "study: penalty sensitivity, several minutes in release"]
fn twisted_beam_penalty_study() {
    for load in [Load::InPlane, Load::OutOfPlane] {
        for mesh in [(2, 12), (4, 24)] {
            for gamma in [1e-3, 1e-2, 1e-1] {
                let label = format!("FI γ = {gamma}");
                let _ = case(
                    &label,
                    fi(false).with_drilling(gamma).unwrap(),
                    mesh,
                    0.32,
                    load,
                );
                for r in [0.05, 0.2] {
                    let label = format!("BT γ = {gamma}, r = {r}");
                    let _ = case_hourglass(
                        &label,
                        bt(false).with_drilling(gamma).unwrap(),
                        mesh,
                        r,
                        load,
                    );
                }
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
/// beam's) must not strain it (tolerance 1e-12 per radian). Fails today for rotations
/// about the local in-plane axes: the projected-plane kinematics read the in-plane
/// nodal velocities of the rotation, `v̂x = ω̂y ẑ_I`, `v̂y = −ω̂x ẑ_I` (ẑ_I = ±z_h), as
/// membrane strain rates; with the 2×2 B-matrix, `Σ ∂N_I/∂x ẑ_I = z_h η/a` and
/// `Σ ∂N_I/∂y ẑ_I = z_h ξ/b` are not zero off the centre, so `d_xx = ω̂y c b η`,
/// `d_yy = −ω̂x c a ξ` at the Gauss points (measured: σ/E′ = 0.038 per radian about x).
#[test]
#[ignore = "fails today: 0.038 strain per radian of rigid rotation (fully_integrated.rs, membrane rates from unprojected local velocities)"]
fn rigid_rotation_of_warped_element_is_strain_free_fully_integrated() {
    for axis in 0..3 {
        let (s, f) = rigid_rotation_response(fi(false), benchmark_warp(), axis);
        println!("FI, rotation about local axis {axis}: σ/E′ {s:.3e}, f/(E t) {f:.3e} per rad");
        assert!(s < 1e-12 && f < 1e-12, "axis {axis}: {s:.2e} {f:.2e}");
    }
}

/// The same for Belytschko–Tsay (with and without the warping correction): the centre
/// B-matrix is orthogonal to ẑ ∝ h, so no stress arises, but the membrane hourglass
/// rates `q_x = γ·v̂x`, `q_y = γ·v̂y` are not (Σ γ_I ẑ_I = 2 z_h), so the hourglass
/// control resists rigid rotations (measured: f/(E t) = 2.7e-4 per radian).
#[test]
#[ignore = "fails today: membrane hourglass forces under rigid rotation (belytschko_tsay.rs, q[0], q[1] from unprojected local velocities)"]
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
