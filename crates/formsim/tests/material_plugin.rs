//! User materials from dynamic plugins, end to end
//! (docs/materials.md): the example `plugins/j2-voce` through `formsim plugin
//! check` and in the square cup, the fixture `plugins/test-broken-material`
//! failing the check and stopping a run, and the scene's checks of
//! `blank.material.plugin`.

use std::path::PathBuf;
use std::sync::OnceLock;

mod cli_support;
use cli_support::{formsim, text};
mod common;

use common::{root, run_scene};

fn j2_voce() -> &'static PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| cli_support::plugin("j2-voce"))
}

fn broken() -> &'static PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| cli_support::plugin("test-broken-material"))
}

/// The coarse cup of `run_scene.rs` (10 × 10 quarter mesh, 5 mm draw).
const COARSE: [&str; 4] = [
    "blank.mesh.divisions=10",
    "steps[2].duration=3e-3",
    "steps[2].motions[1].distance=4.99",
    "output.report_strokes=[2.0, 5.0]",
];

/// Verification: the square cup with its material from the plugin (j2-voce
/// with linear hardening, σ_y = 200 + 600 ε_p MPa) gives the built-in J2's
/// cup with the same curve (a two-point table): punch force, thinning and
/// draw-in agree to 1e-6, and the plugin run reports its material in
/// summary.json. The point-level agreement (1e-9 of σ_y) is
/// `plugin_j2_with_linear_hardening_matches_the_builtin_j2` in shell-elements.
#[test]
fn square_cup_with_the_plugin_j2_matches_the_builtin_j2() {
    let table = "blank.material.hardening={ kind = \"table\", eps_p = [0.0, 10.0], sigma_y = [200.0, 6200.0] }";
    let mut builtin_sets = COARSE.to_vec();
    // The cup's forming limit curve reads the Swift exponent, which a
    // table has not: give it (the curve does not touch the run's figures).
    builtin_sets.extend([table, "formability.n=0.2589"]);
    let (_d1, builtin) = run_scene("square-cup", &builtin_sets);
    let plugin = format!("blank.material.plugin={}", j2_voce().display());
    let mut plugin_sets = COARSE.to_vec();
    plugin_sets.extend([
        plugin.as_str(),
        "blank.material.parameters={ sigma0 = 200.0, h = 600.0 }",
    ]);
    let (_d2, user) = run_scene("square-cup-plugin", &plugin_sets);
    let (b, u) = (&builtin.summary, &user.summary);
    assert_eq!((b.material.as_str(), u.material.as_str()), ("j2", "plugin"));
    let p = u.material_plugin.as_ref().expect("material_plugin");
    assert_eq!(p.name, "j2-voce");
    assert_eq!(p.parameters.get("h"), Some(&600.0));
    let close = |what: &str, a: f64, c: f64| {
        assert!(
            (a - c).abs() <= 1e-6 * c.abs().max(1e-3),
            "{what}: built-in {c}, plugin {a}"
        );
    };
    close("punch force max (N)", u.punch_force_max, b.punch_force_max);
    close("thinning max", u.thinning_max, b.thinning_max);
    assert!(b.thinning_max > 0.0 && b.punch_force_max > 1000.0, "{b:?}");
    for (name, d) in &b.draw_in {
        close(name, u.draw_in[name], *d);
    }
    assert!(u.energy.balance_error_rel.abs() < 0.02, "{:?}", u.energy);
}

/// `formsim plugin check` on the example passes every check; on the fixture
/// each fault fails with a report that says what went wrong, and the panic
/// is reported, not printed by the plugin.
#[test]
fn plugin_check_passes_the_example_and_fails_each_fault() {
    let ok = formsim(&["plugin", "check", j2_voce().to_str().unwrap()]);
    assert!(ok.status.success(), "{}", text(&ok));
    assert!(text(&ok).contains("9 passed, 0 failed"), "{}", text(&ok));
    assert!(
        text(&ok).contains("material plugin j2-voce"),
        "{}",
        text(&ok)
    );

    let lib = broken().to_str().unwrap();
    for (fault, says) in [
        (
            "fault=1",
            "FAIL  elastic            uniaxial stress increment",
        ),
        (
            "fault=2",
            "returned a non-finite value: σ = [NaN, NaN, NaN] MPa",
        ),
        (
            "fault=3",
            "material plugin test-broken-material panicked: test-broken-material: fault 3",
        ),
    ] {
        let o = formsim(&["plugin", "check", lib, "--param", fault]);
        assert!(!o.status.success(), "{fault}: {}", text(&o));
        assert!(text(&o).contains(says), "{fault}: {}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !err.contains("thread '"),
            "{fault}: the plugin printed: {err}"
        );
    }
}

/// A cup whose user material panics once the blank yields stops with one
/// error line naming the plugin, its panic and the simulated time (the
/// coarse mesh's warning aside); the run's results so far are kept.
#[test]
fn a_run_with_a_panicking_material_stops_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let scene = root().join("scenes/square-cup-plugin.toml");
    let plugin = format!("blank.material.plugin={}", broken().display());
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--out",
        out.to_str().unwrap(),
        "--set",
        &plugin,
        "--set",
        "blank.material.parameters={ sigma0 = 165.59, fault = 3.0 }",
    ];
    for s in &COARSE {
        args.extend(["--set", s]);
    }
    let o = formsim(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{}", text(&o));
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(
        errors[0].starts_with("error: run stopped at t = ")
            && errors[0].contains(
                "`blank`: material plugin test-broken-material panicked: test-broken-material: fault 3"
            ),
        "{err}"
    );
    assert!(
        out.join("summary.json").is_file(),
        "results so far are kept"
    );
}

/// The scene's checks name the key: a plugin with a hardening curve, a
/// missing library, an unknown parameter, elastic constants that disagree
/// with the sheet's, and plugin keys under a built-in model.
#[test]
fn plugin_material_keys_are_checked_by_the_scene() {
    let scene = root().join("scenes/square-cup-plugin.toml");
    let cup = root().join("scenes/square-cup.toml");
    let lib = format!("blank.material.plugin={}", j2_voce().display());
    let cases: [(&PathBuf, Vec<&str>, &str); 5] = [
        (
            &cup,
            vec!["blank.material.model=\"plugin\""],
            "blank.material.hardening: not read by a plugin material",
        ),
        (
            &scene,
            vec!["blank.material.plugin=\"nope.so\""],
            "blank.material.plugin: material plugin",
        ),
        (
            &scene,
            vec![&lib, "blank.material.parameters={ sigma_0 = 1.0 }"],
            "unknown parameter `sigma_0` for `j2-voce`",
        ),
        (
            &scene,
            vec![
                &lib,
                "blank.material.parameters={ youngs_modulus = 70000.0 }",
            ],
            "reports Young's modulus 70000 MPa, the sheet's is 206000 MPa",
        ),
        (
            &cup,
            vec!["blank.material.parameters={ q = 1.0 }"],
            "blank.material.parameters: unknown parameter `q` for `j2`; known: none, it takes no parameters",
        ),
    ];
    for (file, sets, says) in cases {
        let mut args = vec!["scene", "check", file.to_str().unwrap()];
        for s in &sets {
            args.extend(["--set", s]);
        }
        let o = formsim(&args);
        assert!(!o.status.success(), "{sets:?}: {}", text(&o));
        assert!(text(&o).contains(says), "{sets:?}: {}", text(&o));
        assert_eq!(
            String::from_utf8_lossy(&o.stderr).lines().count(),
            1,
            "{}",
            text(&o)
        );
    }
}
