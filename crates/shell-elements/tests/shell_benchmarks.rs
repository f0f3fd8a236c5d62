//! Linear-elastic shell benchmarks of MacNeal & Harder (1985) through fem-core's explicit
//! solver with dynamic relaxation: Scordelis–Lo roof and pinched hemisphere with an 18° hole.
//! Run in release: `cargo test -p shell-elements --release --test shell_benchmarks`.

mod common;
use std::collections::BTreeMap;
use std::time::Instant;

use common::elastic;
use fem_core::{
    Amplitude, Control, Dof, Dofs, Effect, EffectId, NodalLoad, Solver, SolverSettings, Vec3,
};
use shell_elements::{
    BelytschkoTsay, FullyIntegrated, J2PlaneStress, RuleKind, Section, ShellFormulation, ShellSet,
};

/// A structured `nu × nv` quad grid over a parametric surface `p(u, v)`,
/// `u, v ∈ [0, 1]`; node `(i, j)` is `j (nu + 1) + i`.
fn grid(nu: usize, nv: usize, p: impl Fn(f64, f64) -> Vec3) -> (Vec<Vec3>, Vec<[u32; 4]>) {
    let id = |i: usize, j: usize| (j * (nu + 1) + i) as u32;
    let mut nodes = Vec::with_capacity((nu + 1) * (nv + 1));
    for j in 0..=nv {
        for i in 0..=nu {
            nodes.push(p(i as f64 / nu as f64, j as f64 / nv as f64));
        }
    }
    let mut quads = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (nodes, quads)
}

/// Share of the shell set's internal energy held by the drilling penalty.
fn drilling_share<F: ShellFormulation>(s: &Solver, id: EffectId) -> f64 {
    let set = s.effect::<ShellSet<F, J2PlaneStress>>(id).unwrap();
    set.drilling_energy() / set.energies().internal
}

/// Quasi-static run by dynamic relaxation: returns the displacement measured
/// by `probe` at the end, and its relative change over the last tenth of the
/// run (a convergence check).
fn relax(s: &mut Solver, t_end: f64, probe: &dyn Fn(&Solver) -> f64) -> (f64, f64) {
    let mut at_90 = None;
    s.run_until(t_end, &mut |sv, r| {
        if at_90.is_none() && r.time >= 0.9 * t_end {
            at_90 = Some(probe(sv));
        }
        if std::env::var("SHELL_DEBUG").is_ok() && r.step % 5000 == 0 {
            println!(
                "  t = {:.4e} s, step {}, probe {:.6}",
                r.time,
                r.step,
                probe(sv)
            );
        }
        Control::Continue
    })
    .unwrap();
    let u = probe(s);
    let change = at_90.map_or(f64::INFINITY, |a| (u / a - 1.0).abs());
    (u, change)
}

/// Scordelis–Lo roof (MacNeal & Harder 1985): cylindrical roof R = 25,
/// L = 50, half-angle 40°, t = 0.25, E = 4.32e8, ν = 0, self-weight 90 per
/// unit area (−z), rigid diaphragms at the ends (uy = uz = 0 in the
/// cross-section plane), free straight edges. A quarter is modelled
/// (x ∈ [0, 25] from mid-span to the diaphragm, θ ∈ [0, 40°] from the crown)
/// with symmetry at x = 0 and at the crown y = 0. Returns the downward
/// displacement at the mid-span free edge (reference 0.3024).
fn scordelis_lo<F: ShellFormulation>(form: F, n: usize, load_factor: f64) -> f64 {
    let (r, half_l, phi, t, e) = (25.0, 25.0, 40f64.to_radians(), 0.25, 4.32e8);
    let qf = load_factor;
    let q = 90.0 * qf;
    let (nodes, quads) = grid(n, n, |u, v| {
        let th = v * phi;
        Vec3::new(u * half_l, r * th.sin(), r * th.cos())
    });
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut sets: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    let col = |i: usize| (0..=n).map(|j| id(i, j) as u32).collect::<Vec<_>>();
    sets.insert("midspan".into(), col(0));
    sets.insert("diaphragm".into(), col(n));
    sets.insert("crown".into(), (0..=n).map(|i| id(i, 0) as u32).collect());
    // Consistent self-weight: a quarter of each element's area to each node.
    let mut fz = vec![0.0; nodes.len()];
    for quad in &quads {
        let x = quad.map(|k| nodes[k as usize]);
        let a = 0.5 * (x[2] - x[0]).cross(&(x[3] - x[1])).norm();
        for &k in quad {
            fz[k as usize] -= 0.25 * q * a;
        }
    }
    for (k, _) in nodes.iter().enumerate() {
        sets.insert(format!("n{k}"), vec![k as u32]);
    }
    let rho = 1.0;
    let mat = elastic(e, 0.0, rho);
    let section = Section::new(t)
        .unwrap()
        .with_rule(RuleKind::Gauss, 2)
        .unwrap();
    let set = ShellSet::new("roof", &nodes, &quads, section, form, mat).unwrap();
    // Lowest mode ω₁ ≈ 40 rad/s at ρ = 1: c = 2ω₁ damps it critically; 0.5 s ≈ 10 / ω₁.
    let (damping, t_end) = (80.0, 0.5);
    let settings = SolverSettings {
        damping,
        ..Default::default()
    };
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    let set_id = s.add_effect(set);
    s.symmetry("midspan", 0).unwrap();
    s.symmetry("crown", 1).unwrap();
    s.fix("diaphragm", Dofs::of(&[Dof::Uy, Dof::Uz])).unwrap();
    for (k, &f) in fz.iter().enumerate() {
        s.add_load(&NodalLoad {
            set: format!("n{k}"),
            dof: Dof::Uz,
            value: f,
            amplitude: Amplitude::Constant,
        })
        .unwrap();
    }
    let probe_node = id(0, n);
    let t0 = Instant::now();
    let (u, change) = relax(&mut s, t_end, &|sv: &Solver| {
        let st = sv.state();
        (st.x0[probe_node].z - st.x[probe_node].z) / qf
    });
    println!(
        "Scordelis–Lo {} {n}×{n}: w = {u:.5} (ref 0.3024, {:+.2} %), change over last 10 %: {change:.1e}, drilling share of internal energy {:.1e}, {} steps, {:.1} s",
        F::NAME,
        (u / 0.3024 - 1.0) * 100.0,
        drilling_share::<F>(&s, set_id),
        s.steps(),
        t0.elapsed().as_secs_f64()
    );
    assert!(change < 1e-3, "not converged: relative change {change:.2e}");
    u
}

/// Pinched hemisphere with an 18° hole (MacNeal & Harder 1985): R = 10,
/// t = 0.04, E = 6.825e7, ν = 0.3, four alternating radial forces ±2 on the
/// equator. A quarter (azimuth 0–90°, polar angle 18°–90°) is modelled with
/// symmetry on the planes y = 0 and x = 0, so the forces on them are halved
/// to 1: outward (+x) at (R, 0, 0) and inward (−y) at (0, R, 0); uz is fixed
/// at the equator's mid node against rigid motion. Returns the radial
/// displacements at both loads (reference 0.0924 each).
fn pinched_hemisphere<F: ShellFormulation>(form: F, n: usize, load_factor: f64) -> (f64, f64) {
    let (r, t, e, nu) = (10.0, 0.04, 6.825e7, 0.3);
    let hole = 18f64.to_radians();
    let half_pi = std::f64::consts::FRAC_PI_2;
    // u: azimuth 0..90°, v: polar angle from the equator (90°) up to the hole (18°).
    let (nodes, quads) = grid(n, n, |u, v| {
        let th = u * half_pi;
        let ph = half_pi - v * (half_pi - hole);
        Vec3::new(
            r * ph.sin() * th.cos(),
            r * ph.sin() * th.sin(),
            r * ph.cos(),
        )
    });
    let id = |i: usize, j: usize| j * (n + 1) + i;
    let mut sets: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    sets.insert("y0".into(), (0..=n).map(|j| id(0, j) as u32).collect());
    sets.insert("x0".into(), (0..=n).map(|j| id(n, j) as u32).collect());
    sets.insert("load_x".into(), vec![id(0, 0) as u32]);
    sets.insert("load_y".into(), vec![id(n, 0) as u32]);
    sets.insert("anchor".into(), vec![id(n / 2, 0) as u32]);
    let rho = 1.0;
    let mat = elastic(e, nu, rho);
    let section = Section::new(t)
        .unwrap()
        .with_rule(RuleKind::Gauss, 2)
        .unwrap();
    let set = ShellSet::new("hemisphere", &nodes, &quads, section, form, mat).unwrap();
    // Lowest (inextensional) mode ω₁ ≈ 3 rad/s: c = 2ω₁; settled by ≈ 3 s.
    let (damping, t_end) = (6.0, 4.0);
    // Equal time step everywhere: mass-scale the small elements near the hole
    // up to the step of the largest (does not change the static answer).
    let c = (e / (rho * (1.0 - nu * nu))).sqrt();
    let l_eq = r * half_pi / n as f64;
    let settings = SolverSettings {
        damping,
        mass_scaling_dt: Some(0.9 * 0.9 * l_eq / c),
        ..Default::default()
    };
    let mut s = Solver::from_nodes(&nodes, sets, settings).unwrap();
    let set_id = s.add_effect(set);
    s.symmetry("y0", 1).unwrap();
    s.symmetry("x0", 0).unwrap();
    s.fix("anchor", Dofs::of(&[Dof::Uz])).unwrap();
    let qf = load_factor;
    for (set, dof, value) in [("load_x", Dof::Ux, qf), ("load_y", Dof::Uy, -qf)] {
        s.add_load(&NodalLoad {
            set: set.into(),
            dof,
            value,
            amplitude: Amplitude::Constant,
        })
        .unwrap();
    }
    let (ix, iy) = (id(0, 0), id(n, 0));
    let t0 = Instant::now();
    let (ux, change) = relax(&mut s, t_end, &|sv: &Solver| {
        let st = sv.state();
        (st.x[ix].x - st.x0[ix].x) / qf
    });
    let st = s.state();
    let uy = (st.x0[iy].y - st.x[iy].y) / qf;
    println!(
        "pinched hemisphere {} {n}×{n}: u_x = {ux:.5} ({:+.2} %), -u_y = {uy:.5} ({:+.2} %) (ref 0.0924), change over last 10 %: {change:.1e}, drilling share of internal energy {:.1e}, {} steps, added mass {:.1} %, {:.1} s",
        F::NAME,
        (ux / 0.0924 - 1.0) * 100.0,
        (uy / 0.0924 - 1.0) * 100.0,
        drilling_share::<F>(&s, set_id),
        s.steps(),
        s.setup_report().map_or(0.0, |r| r.added_mass_percent),
        t0.elapsed().as_secs_f64()
    );
    assert!(change < 1e-3, "not converged: relative change {change:.2e}");
    (ux, uy)
}

/// The references are linear solutions (MacNeal & Harder 1985); the solver
/// is geometrically nonlinear (co-rotational) and at the full loads the roof
/// is measurably stiffer. Both benchmarks are
/// therefore run in the linear range, at 1/1000 of the load, and the
/// displacement is divided by that factor.
const LINEAR_RANGE: f64 = 1e-3;

// Mesh studies below: linear range, the set-ups above, default elements
// (drilling γ = 1e-3). γ study in docs/shells.md.

/// Scordelis–Lo roof, Belytschko–Tsay (default: hourglass r = 0.05,
/// drilling γ = 1e-3), 32×32 on the quarter. Mesh study (w, error vs
/// 0.3024): 8×8 0.31629 (+4.6 %), 16×16 0.30610 (+1.2 %), 32×32 0.30361
/// (+0.4 %), 64×64 0.30299 (+0.2 %): converges from above. Source: MacNeal &
/// Harder (1985), reference w = 0.3024 at the mid-span free edge; tolerance
/// 3 %.
#[test]
fn scordelis_lo_roof_midspan_edge_deflection_belytschko_tsay() {
    let w = scordelis_lo(BelytschkoTsay::default(), 32, LINEAR_RANGE);
    assert!((w / 0.3024 - 1.0).abs() < 0.03, "{w}");
}

/// Scordelis–Lo roof, fully integrated shell (drilling γ = 1e-3), 32×32 on
/// the quarter. Mesh study: 8×8 0.29439 (−2.7 %), 16×16 0.29966 (−0.9 %),
/// 32×32 0.30142 (−0.3 %), 64×64 0.30216 (−0.1 %): converges from below.
/// Source: MacNeal & Harder (1985), w = 0.3024; tolerance 3 %.
#[test]
fn scordelis_lo_roof_midspan_edge_deflection_fully_integrated() {
    let w = scordelis_lo(FullyIntegrated::default(), 32, LINEAR_RANGE);
    assert!((w / 0.3024 - 1.0).abs() < 0.03, "{w}");
}

/// Pinched hemisphere with an 18° hole, Belytschko–Tsay (default), 16×16 on
/// the quarter. Mesh study (u at both loads): 8×8 0.09427 (+2.0 %), 16×16
/// 0.09398 (+1.7 %), 32×32 0.09379 (+1.5 %, 87,000 steps: too long for CI).
/// Source: MacNeal & Harder (1985), u = 0.0924 at both loads; tolerance 3 %.
#[test]
fn pinched_hemisphere_radial_displacement_belytschko_tsay() {
    let (ux, uy) = pinched_hemisphere(BelytschkoTsay::default(), 16, LINEAR_RANGE);
    assert!(
        (ux / 0.0924 - 1.0).abs() < 0.03 && (uy / 0.0924 - 1.0).abs() < 0.03,
        "{ux} {uy}"
    );
}

/// Pinched hemisphere with an 18° hole, fully integrated shell (drilling
/// γ = 1e-3), 16×16 on the quarter. Mesh study: 8×8 0.09231 (−0.1 %), 16×16
/// 0.09284 (+0.5 %), 32×32 0.09327 (+0.9 %); BT and FI approach each other
/// at ≈ +1 %, where the finer-mesh solutions of this problem in the
/// literature lie (0.0924 is MacNeal & Harder's value). Source: MacNeal &
/// Harder (1985), u = 0.0924 at both loads; tolerance 3 %.
#[test]
fn pinched_hemisphere_radial_displacement_fully_integrated() {
    let (ux, uy) = pinched_hemisphere(FullyIntegrated::default(), 16, LINEAR_RANGE);
    assert!(
        (ux / 0.0924 - 1.0).abs() < 0.03 && (uy / 0.0924 - 1.0).abs() < 0.03,
        "{ux} {uy}"
    );
}
