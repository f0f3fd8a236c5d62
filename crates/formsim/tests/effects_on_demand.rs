//! Effects on demand (issue 18, item 4, the tests): a scene computes only
//! what its laws, formulations and outputs ask for. Counted, not timed, on
//! the square cup with a coarse 10 × 10 mesh stepped 3 ms into the draw
//! (the die and the holder in contact):
//!
//! - the contact's blank geometry evaluates the velocity gradient only for a
//!   formulation that declares the spin or the velocity gradient (jaumann,
//!   updated-lagrangian), and the deformation gradients only for one that
//!   declares them (lagrangian); convective needs neither;
//! - the shells' outer-fibre flow stresses are a shared nodal field only
//!   when a law reads them (Levanov), so no other run computes them;
//! - a run with `output.frames = 0` writes no frame (it wrote the first and
//!   the last, without their `.pvd`, until this test found it).

mod common;

use common::{root, run_scene};
use fem_core::NodalField;
use formsim::scene;

/// Build the coarse cup with `sets` and step it to 3 ms; the velocity- and
/// deformation-gradient evaluations of its contact and whether the flow
/// stresses are allocated as shared fields.
fn counts(sets: &[&str]) -> (u64, u64, bool) {
    let mut all: Vec<String> = vec![
        "blank.mesh.divisions=10".into(),
        "output.frames=0".into(),
        "solver.end_time=3e-3".into(),
    ];
    all.extend(sets.iter().map(|s| s.to_string()));
    let loaded = scene::load(&root().join("scenes/square-cup.toml"), &all).unwrap();
    let mut model = scene::build(&loaded).unwrap();
    let end = model.end_time;
    while model.solver.time() < end {
        model.solver.step_toward(end).unwrap();
    }
    let touching = model
        .contact()
        .unwrap()
        .pairs()
        .iter()
        .filter(|p| p.status.iter().any(|s| *s != contact::PointStatus::Open))
        .count();
    assert!(touching >= 2, "{sets:?}: {touching} pairs in contact");
    let g = model.contact().unwrap().geometry();
    let fields = model.solver.shared_fields();
    let flow = fields.get(NodalField::FLOW_STRESS_TOP).is_some()
        || fields.get(NodalField::FLOW_STRESS_BOTTOM).is_some();
    (g.vel_grad_evaluations, g.def_grad_evaluations, flow)
}

#[test]
fn each_formulation_and_law_computes_only_what_it_declares() {
    let ac = |f: &str| counts(&["contact.law=ac", &format!("contact.formulation={f}")]);
    let (l, f, flow) = ac("convective");
    assert_eq!((l, f, flow), (0, 0, false), "ac convective");
    let (l, f, flow) = ac("jaumann");
    assert!(l > 0 && f == 0 && !flow, "ac jaumann: {l} {f} {flow}");
    let (l, f, flow) = ac("updated-lagrangian");
    assert!(
        l > 0 && f == 0 && !flow,
        "ac updated-lagrangian: {l} {f} {flow}"
    );
    let (l, f, flow) = ac("lagrangian");
    assert!(l == 0 && f > 0 && !flow, "ac lagrangian: {l} {f} {flow}");
    let (l, f, flow) = counts(&["contact.law=levanov", "contact.formulation=convective"]);
    assert_eq!((l, f, flow), (0, 0, true), "levanov convective");
    for law in ["wvs", "wh"] {
        let c = counts(&[
            &format!("contact.law={law}"),
            "contact.formulation=convective",
        ]);
        assert_eq!(c, (0, 0, false), "{law} convective");
    }
}

#[test]
fn a_run_without_frames_writes_no_frame() {
    let (dir, r) = run_scene(
        "square-cup",
        &[
            "blank.mesh.divisions=10",
            "output.frames=0",
            "solver.end_time=1e-3",
        ],
    );
    assert_eq!(r.summary.status, "completed");
    assert!(!dir.path().join("blank.pvd").exists());
    assert!(!dir.path().join("vtk").exists());
    let (dir, _) = run_scene(
        "square-cup",
        &[
            "blank.mesh.divisions=10",
            "output.frames=2",
            "solver.end_time=1e-3",
        ],
    );
    assert!(dir.path().join("blank.pvd").is_file());
}
