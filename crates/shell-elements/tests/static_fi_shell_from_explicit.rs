//! The static fully integrated shell reproduces the explicit one: from an
//! explicit set's state (`StaticShells::from_shell_set`), its internal
//! forces at the explicit model's positions are the explicit step's, with
//! no increment and over one explicit step's increment; committed, its
//! state and work are the explicit step's; a trial elsewhere, reverted,
//! leaves no trace (bit for bit).
//!
//! Source: both run the same kernel (`FullyIntegrated::kernel`, module
//! docs of `shell_elements::statics`): one explicit step from `x_n` with
//! velocities `v`, `ω` over `Δt` is the static element's step from the
//! committed `x_n` to the trial `x_{n+1}`, `Δθ = ω Δt`. With a zero
//! increment the static element's stresses are the committed ones (the
//! material update of a zero increment returns the stress it got).
//! Set-up: six shells of a steel strip stretched plastically, bent and
//! twisted over 20 explicit steps (warped by the twist), then one step
//! more, at rest or moving on (the increment plastic at every Gauss point).
//! Tolerances: forces `|F_static + F_explicit| ≤ 1e-12 · max |F_explicit|`
//! at rest and over the step, as the Belytschko–Tsay test
//! (`static_shell_from_explicit.rs`; measured: 0 at rest, 1.7e-16 over the
//! step, where the increments differ by the rounding of `x_{n+1} − x_n`
//! against `v Δt` and the section's sums are added in another order); the
//! committed stresses, shear stresses and drilling moments within `1e-12`
//! of their largest (measured ≤ 2.4e-15), the thickness within `1e-12`
//! relative (4.4e-16), the step's internal and plastic work within `1e-11`
//! relative (2.7e-15, 2.3e-14).

mod static_common;

use fem_core::statics::{StaticTangent, dense_tangent};
use fem_core::{Effect, FieldAccess, Forces, NodalState, StepContext, Vec3};
use shell_elements::{FullyIntegrated, J2PlaneStress, Material, ShellSet, StaticShells};
use static_common::{Trial, section, steel};

const DT: f64 = 1e-4;

/// The strip's set after 20 explicit steps of stretch, bend and twist, and
/// the nodal state then (with the velocities of the motion).
fn formed() -> (ShellSet<FullyIntegrated, J2PlaneStress>, NodalState) {
    let mesh = fem_core::rectangle(30.0, 5.0, 6, 1).unwrap();
    let mut set = ShellSet::new(
        "strip",
        &mesh.nodes,
        &mesh.quads,
        section(1.0, 5),
        FullyIntegrated::default(),
        steel(),
    )
    .unwrap();
    let mut st = NodalState::at_rest(&mesh.nodes);
    // Stretch along x (plastic), bend about y and twist about x.
    for (i, p) in mesh.nodes.iter().enumerate() {
        st.v[i] = Vec3::new(20.0 * p.x, 0.0, 0.0);
        st.w[i] = Vec3::new(0.3 * p.x, 0.5 * p.x + 0.2 * p.y, 0.0);
    }
    for step in 1..=20 {
        step_once(&mut set, &mut st, step);
        if step == 1 {
            // Bend and twist: the normal velocity follows the rotations.
            for (i, p) in mesh.nodes.iter().enumerate() {
                st.v[i].z = 0.25 * p.x * p.x + 0.3 * p.x * (p.y - 2.5);
            }
        }
    }
    (set, st)
}

/// One explicit step: the nodes moved by `Δt v`, the set's forces there.
fn step_once(
    set: &mut ShellSet<FullyIntegrated, J2PlaneStress>,
    st: &mut NodalState,
    step: u64,
) -> Forces {
    for (x, v) in st.x.iter_mut().zip(&st.v) {
        *x += DT * v;
    }
    let ctx = StepContext {
        time: step as f64 * DT,
        dt: DT,
        step,
        press: None,
    };
    let mut f = Forces::zeros(st.x.len());
    set.add_forces(&ctx, st, &mut f, &mut FieldAccess::none())
        .unwrap();
    f
}

/// `max |F_static + F_explicit|` over every node and DOF, and `max |F_explicit|`.
fn force_gap(stat: &[f64], f: &Forces) -> (f64, f64) {
    let scale = f.f.iter().chain(&f.m).fold(0.0f64, |m, v| m.max(v.amax()));
    let mut worst: f64 = 0.0;
    for n in 0..f.f.len() {
        for c in 0..3 {
            worst = worst.max((stat[6 * n + c] + f.f[n][c]).abs());
            worst = worst.max((stat[6 * n + 3 + c] + f.m[n][c]).abs());
        }
    }
    (worst, scale)
}

#[test]
fn static_fi_shells_take_over_an_explicit_state() {
    let (mut set, mut st) = formed();
    let eps_p = set.plastic_strain(0, 3, 2);
    assert!(eps_p > 0.01, "the stretch should be plastic: ε_p = {eps_p}");
    let mut shells = StaticShells::from_shell_set("strip", &set);
    for e in 0..set.len() {
        assert_eq!(shells.thickness(e), set.thickness(e));
        assert_eq!(shells.drilling_moments(e), set.drilling_moments(e));
        for p in 0..4 {
            assert_eq!(shells.stress_at(e, p, 4), set.stress(e, p, 4));
            assert_eq!(shells.transverse_shear_at(e, p), set.transverse_shear(e, p));
            let ep = shells.material().plastic_strain(shells.history_at(e, p, 1));
            assert_eq!(ep, set.plastic_strain(e, p, 1));
        }
    }
    // One step at rest: the explicit step's forces from the same state.
    st.v.iter_mut()
        .chain(st.w.iter_mut())
        .for_each(|v| *v = Vec3::zeros());
    let f = step_once(&mut set, &mut st, 21);
    let t = Trial::at(&st.x);
    let stat = dense_tangent(&mut shells, &t.state(), false).unwrap();
    let (worst, scale) = force_gap(&stat.forces, &f);
    println!(
        "at rest: ε_p = {eps_p:.4}, max |F| = {scale:.4e}, max |F_static + F_explicit| = \
         {worst:.3e} ({:.2e} of max |F|)",
        worst / scale
    );
    assert!(worst <= 1e-12 * scale);
}

#[test]
fn static_fi_shells_follow_an_explicit_step() {
    let (mut set, mut st) = formed();
    let mut shells = StaticShells::from_shell_set("strip", &set);
    let (x_n, work_n) = (st.x.clone(), set.energies());
    let plastic_n: Vec<f64> = (0..set.len())
        .flat_map(|e| (0..4).map(move |p| (e, p)))
        .map(|(e, p)| set.plastic_strain(e, p, 4))
        .collect();
    // Step 21 moves on: the explicit forces at x_{n+1}.
    let f = step_once(&mut set, &mut st, 21);
    let mut t = Trial::at(&x_n);
    t.x.clone_from(&st.x);
    for (d, w) in t.dtheta.iter_mut().zip(&st.w) {
        *d = DT * w;
    }
    let stat = dense_tangent(&mut shells, &t.state(), false).unwrap();
    let (worst, scale) = force_gap(&stat.forces, &f);
    // A trial elsewhere (three steps' increment), reverted, leaves no trace.
    let mut far = Trial::at(&x_n);
    for (n, x) in far.x.iter_mut().enumerate() {
        *x += 3.0 * (st.x[n] - x_n[n]);
        far.dtheta[n] = 3.0 * t.dtheta[n];
    }
    dense_tangent(&mut shells, &far.state(), true).unwrap();
    shells.revert();
    let again = dense_tangent(&mut shells, &t.state(), false).unwrap();
    assert_eq!(again.forces, stat.forces, "revert left a trace");
    // Committed, the static state is the explicit step's.
    shells.commit(&t.state());
    let (mut ds, mut smax, mut dq, mut qmax, mut dm, mut mmax, mut dt_rel) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut flowed = 0;
    for e in 0..set.len() {
        dt_rel = dt_rel.max((shells.thickness(e) / set.thickness(e) - 1.0).abs());
        for (a, b) in shells
            .drilling_moments(e)
            .iter()
            .zip(set.drilling_moments(e))
        {
            dm = dm.max((a - b).abs());
            mmax = mmax.max(b.abs());
        }
        for p in 0..4 {
            for (a, b) in shells
                .transverse_shear_at(e, p)
                .iter()
                .zip(set.transverse_shear(e, p))
            {
                dq = dq.max((a - b).abs());
                qmax = qmax.max(b.abs());
            }
            for k in 0..5 {
                for (a, b) in shells.stress_at(e, p, k).iter().zip(set.stress(e, p, k)) {
                    ds = ds.max((a - b).abs());
                    smax = smax.max(b.abs());
                }
            }
            let ep = shells.material().plastic_strain(shells.history_at(e, p, 4));
            if ep > plastic_n[4 * e + p] {
                flowed += 1;
            }
        }
    }
    let work = |a: f64, b: f64| (a - b).abs() / b.abs();
    let (wi, wp) = (
        set.energies().internal - work_n.internal,
        set.energies().plastic - work_n.plastic,
    );
    let (w_int, w_pl) = (
        work(shells.work().internal, wi),
        work(shells.work().plastic, wp),
    );
    println!(
        "one step: max |F| = {scale:.4e}, max |F_static + F_explicit| = {worst:.3e} ({:.2e}); \
         committed: stress {:.2e}, shear {:.2e}, drilling {:.2e} of their largest, thickness \
         {dt_rel:.2e}; work {wi:.4e} mJ ({w_int:.2e}), plastic {wp:.4e} mJ ({w_pl:.2e}); \
         {flowed} of {} Gauss points flowed",
        worst / scale,
        ds / smax,
        dq / qmax,
        dm / mmax,
        4 * set.len()
    );
    assert_eq!(
        flowed,
        4 * set.len(),
        "the step should flow at every Gauss point"
    );
    assert!(worst <= 1e-12 * scale);
    assert!(ds <= 1e-12 * smax && dq <= 1e-12 * qmax && dm <= 1e-12 * mmax);
    assert!(dt_rel <= 1e-12);
    assert!(w_int <= 1e-11 && w_pl <= 1e-11);
}
