//! The springback step (`kind = "springback"` in `[[steps]]`) end to end:
//! the tools let go of a coarse square cup, the free z translation is
//! removed by one fixed DOF, the cup comes to rest, and the run reports it
//! without crying wolf; bad springback keys are one-line errors.

mod common;

use common::{root, run_scene};
use formsim::scene;

/// The 10 × 10 cup drawn 5 mm, then released: at rest within its
/// tolerance, one DOF (uz) fixed for the one free mode (the symmetry planes
/// hold the rest), a springback displacement that is finite and not zero,
/// `springback.csv` with a row per node, VTK frames as the tools let go and
/// at the end with the springback displacement, the energy balance closed
/// to 1e-3,
/// and no warning beyond those of the same cup without the release (the
/// release's motion is not a quasi-static failure).
#[test]
fn square_cup_springback_comes_to_rest_and_reports() {
    let coarse = [
        "blank.mesh.divisions=10",
        "steps[2].duration=3e-3",
        "steps[2].motions[1].distance=4.99",
        "output.report_strokes=[2.0, 5.0]",
        "output.frames=3",
    ];
    let (dir, r) = run_scene("square-cup-springback", &coarse);
    let (_, formed) = run_scene("square-cup", &coarse);
    let s = &r.summary;
    let b = s.springback.as_ref().expect("a springback summary");
    println!("{b:?}");
    assert!(b.settled, "{b:?}");
    assert!(b.residual_n <= b.tolerance * b.residual_start_n, "{b:?}");
    assert_eq!(b.free_modes, 1, "{b:?}");
    assert_eq!(b.fixed.len(), 1, "{b:?}");
    assert!(b.fixed[0].ends_with(" uz"), "{b:?}");
    assert!(
        b.displacement_max_mm.is_finite() && b.displacement_max_mm > 1e-3,
        "{b:?}"
    );
    // It ends when at rest, well before the step's longest duration.
    assert!(b.duration_s < 0.5 * 2.0e-2, "{b:?}");
    assert!(s.energy.balance_error_rel < 1e-3, "{:?}", s.energy);
    assert_eq!(s.warnings, formed.summary.warnings);
    assert_eq!(s.stroke, formed.summary.stroke);
    let csv = std::fs::read_to_string(dir.path().join("springback.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + s.nodes, "one row per node");
    // Frames: the start, as the tools let go, …, the end; from the
    // release on they carry the springback displacement.
    let vtk = |k: usize| std::fs::read_to_string(dir.path().join(format!("vtk/blank_{k:04}.vtu")));
    let has = |k: usize| vtk(k).unwrap().contains("springback_displacement");
    let last = (1..).find(|&k| vtk(k).is_err()).unwrap() - 1;
    assert!(!has(0) && has(1) && has(last), "{last} frames");
}

/// A springback step with a motion, an `until`, an unknown method or a
/// tolerance out of (0, 1) is refused at its key; a press step refuses the
/// springback keys. (The implicit method with shells that have no static
/// form is refused at `steps[i].method`: every built-in element has one,
/// so `tests/components_from_a_scene.rs` checks it with its registered
/// element.) Both built-in elements take the implicit method.
#[test]
fn springback_step_keys_are_checked() {
    let path = root().join("scenes/square-cup-springback.toml");
    for (set, key, says) in [
        (
            "steps[3].method=\"newton\"",
            "steps[3].method",
            "not a springback method",
        ),
        ("steps[3].tolerance=1.5", "steps[3].tolerance", "(0, 1)"),
        (
            "steps[3].motions=[{kind=\"hold\", tool=\"punch\"}]",
            "steps[3].motions",
            "moves no tool",
        ),
        (
            "steps[2].kind=\"springback\"",
            "steps[2].kind",
            "must be the programme's last",
        ),
        (
            "steps[2].tolerance=1e-3",
            "steps[2].tolerance",
            "only read by a kind = \"springback\" step",
        ),
    ] {
        let e = scene::load(&path, &[set.to_string()]).expect_err(set);
        let m = e.to_string();
        assert!(m.contains(key) && m.contains(says), "{set}: {m}");
        assert_eq!(m.lines().count(), 1, "{m}");
    }
    for element in ["belytschko-tsay", "fully-integrated"] {
        let set = format!("blank.element=\"{element}\"");
        scene::load(&path, &[set]).unwrap_or_else(|e| panic!("{element}: {e}"));
    }
}
