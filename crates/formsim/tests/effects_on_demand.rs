//! Effects on demand (the tests): a scene computes only
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
//! - a frictionless pair (`contact.law = "frictionless"`) hands no point to
//!   a friction law: no return mapping, no stick spring, no blank gradient;
//! - a run with `output.frames = 0` writes no frame (it wrote the first and
//!   the last, without their `.pvd`, until this test found it).

mod common;

use common::{root, run_scene};
use fem_core::NodalField;
use formsim::scene;

/// The coarse cup built with `sets` and stepped to 3 ms, with at least two
/// of its pairs in contact.
fn stepped(sets: &[&str]) -> scene::Model {
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
    model
}

/// The velocity- and deformation-gradient evaluations of the stepped cup's
/// contact and whether the flow stresses are allocated as shared fields.
fn counts(sets: &[&str]) -> (u64, u64, bool) {
    let model = stepped(sets);
    let g = model.contact().unwrap().geometry();
    let fields = model.solver.shared_fields();
    let flow = fields.get(NodalField::FLOW_STRESS_TOP).is_some()
        || fields.get(NodalField::FLOW_STRESS_BOTTOM).is_some();
    (g.vel_grad_evaluations, g.def_grad_evaluations, flow)
}

/// `contact.law = "frictionless"`: no point is handed to a friction law
/// (AC's pairs, the control, hand thousands), every touching point has a
/// zero traction, no friction energy, no blank gradient.
#[test]
fn a_frictionless_pair_runs_no_return_mapping() {
    let model = stepped(&["contact.law=frictionless"]);
    let c = model.contact().unwrap();
    for p in c.pairs() {
        assert_eq!(p.friction_model(), ("frictionless", "none"));
        assert_eq!(p.friction_points, 0, "{}", p.name());
        assert_eq!(p.energy.friction, 0.0, "{}", p.name());
        assert!(p.traction.iter().all(|t| *t == fem_core::Vec3::zeros()));
        assert!(p.status.iter().all(|s| *s != contact::PointStatus::Stick));
    }
    let g = c.geometry();
    assert_eq!((g.vel_grad_evaluations, g.def_grad_evaluations), (0, 0));
    let model = stepped(&["contact.law=ac"]);
    let handed: u64 = model
        .contact()
        .unwrap()
        .pairs()
        .iter()
        .map(|p| p.friction_points)
        .sum();
    assert!(handed > 1000, "ac: {handed} point steps");
}

/// A frictionless pair takes no friction parameters: one is refused, named.
#[test]
fn a_frictionless_pair_refuses_parameters() {
    let loaded = scene::load(
        &root().join("scenes/square-cup.toml"),
        &[
            "contact.law=frictionless".to_string(),
            "contact.params.frictionless.mu=0.1".to_string(),
        ],
    )
    .unwrap();
    let e = scene::build(&loaded).unwrap_err().to_string();
    assert!(
        e.contains("contact.params.frictionless.mu") && e.contains("no parameters"),
        "{e}"
    );
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
    assert_eq!(r.summary.status, formsim::run::Status::Completed);
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
