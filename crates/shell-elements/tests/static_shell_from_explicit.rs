//! `StaticShells::from_shell_set` takes over an explicit set's state: at
//! the explicit model's positions, with no increment, the static shells'
//! internal forces are the forces the explicit step assembled from the
//! same stresses, hourglass and drilling forces, on the same frame.
//!
//! Source: both evaluate the Belytschko–Tsay nodal forces of one state on
//! one configuration (module docs of `shell_elements::statics`); with a
//! zero increment the static element's stresses are the committed ones
//! (the material update of a zero increment returns the stress it got).
//! Set-up: six shells (a block of four, stored lane-major by the explicit
//! set, and two more, stored element-major) of a steel strip stretched
//! plastically, bent and twisted over 20 explicit steps (warped by the
//! twist), then one step at rest. Tolerance:
//! `|F_static + F_explicit| ≤ 1e-12 · max |F_explicit|` (measured 2e-16:
//! the explicit block of four runs in SIMD lanes, the static kernel in
//! `f64`, and the two round alike here).

mod static_common;

use fem_core::statics::dense_tangent;
use fem_core::{Effect, FieldAccess, Forces, NodalState, StepContext, Vec3};
use shell_elements::{BelytschkoTsay, Material, ShellSet, StaticShells};
use static_common::{Trial, section, steel};

#[test]
fn static_shells_take_over_an_explicit_state() {
    let mesh = fem_core::rectangle(30.0, 5.0, 6, 1).unwrap();
    let mut set = ShellSet::new(
        "strip",
        &mesh.nodes,
        &mesh.quads,
        section(1.0, 5),
        BelytschkoTsay::default(),
        steel(),
    )
    .unwrap();
    let mut st = NodalState::at_rest(&mesh.nodes);
    let dt = 1e-4;
    // Stretch along x (plastic), bend about y and twist about x.
    for (i, p) in mesh.nodes.iter().enumerate() {
        st.v[i] = Vec3::new(20.0 * p.x, 0.0, 0.0);
        st.w[i] = Vec3::new(0.3 * p.x, 0.5 * p.x + 0.2 * p.y, 0.0);
    }
    let mut f = Forces::zeros(mesh.nodes.len());
    // 20 steps of motion, then one at rest: the explicit kernel integrates
    // a step's section with the thickness at its start, the static one with
    // the committed thickness, so the comparison takes a step that does not
    // change it.
    for step in 1..=21 {
        if step == 21 {
            st.v.iter_mut()
                .chain(st.w.iter_mut())
                .for_each(|v| *v = Vec3::zeros());
        }
        for (x, v) in st.x.iter_mut().zip(&st.v) {
            *x += dt * v;
        }
        let ctx = StepContext {
            time: step as f64 * dt,
            dt,
            step,
            press: None,
        };
        f = Forces::zeros(mesh.nodes.len());
        set.add_forces(&ctx, &st, &mut f, &mut FieldAccess::none())
            .unwrap();
        if step == 1 {
            // Bend and twist: the normal velocity follows the rotations.
            for (i, p) in mesh.nodes.iter().enumerate() {
                st.v[i].z = 0.25 * p.x * p.x + 0.3 * p.x * (p.y - 2.5);
            }
        }
    }
    let eps_p = set.plastic_strain(0, 0, 2);
    assert!(eps_p > 0.01, "the stretch should be plastic: ε_p = {eps_p}");
    let mut shells = StaticShells::from_shell_set("strip", &set);
    for e in 0..set.len() {
        assert_eq!(shells.thickness(e), set.thickness(e));
        assert_eq!(shells.stress(e, 4), set.stress(e, 0, 4));
        assert_eq!(shells.transverse_shear(e), set.transverse_shear(e, 0));
        assert_eq!(shells.drilling_moments(e), set.drilling_moments(e));
        let p = shells.material().plastic_strain(shells.history(e, 1));
        assert_eq!(p, set.plastic_strain(e, 0, 1));
    }
    assert!((0..6).any(|e| shells.hourglass_forces(e).iter().any(|&q| q != 0.0)));
    let t = Trial::at(&st.x);
    let stat = dense_tangent(&mut shells, &t.state(), false).unwrap();
    let scale = f.f.iter().chain(&f.m).fold(0.0f64, |m, v| m.max(v.amax()));
    let mut worst: f64 = 0.0;
    for n in 0..mesh.nodes.len() {
        for c in 0..3 {
            worst = worst.max((stat.forces[6 * n + c] + f.f[n][c]).abs());
            worst = worst.max((stat.forces[6 * n + 3 + c] + f.m[n][c]).abs());
        }
    }
    println!(
        "ε_p = {eps_p:.4}, max |F| = {scale:.4e}, max |F_static + F_explicit| = {worst:.3e} \
         ({:.2e} of max |F|)",
        worst / scale
    );
    assert!(worst <= 1e-12 * scale);
}
