//! User-material plugins end to end: build the example `j2-voce` and the
//! fixture `test-broken-material` as shared libraries, load them through
//! `plugins_api::material::loader`, run the conformance suite on them, and
//! check the loader's refusals (a friction plugin is not a material plugin,
//! nor the other way round; parameters are checked against the schema).

use std::path::PathBuf;
use std::sync::OnceLock;

use plugins_api::Params;
use plugins_api::loader::PluginLibrary;
use plugins_api::material::PointResult;
use plugins_api::material::conformance::check_material;
use plugins_api::material::loader::MaterialLibrary;

mod support;
use support::build_plugins;

/// `j2-voce`, `test-broken-material`, `exp-decay`.
fn libraries() -> &'static [PathBuf] {
    static BUILT: OnceLock<Vec<PathBuf>> = OnceLock::new();
    BUILT.get_or_init(|| build_plugins(&["j2-voce", "test-broken-material", "exp-decay"]))
}

fn steel() -> Params {
    Params::new()
        .with("youngs_modulus", 206_000.0)
        .with("density", 7.85e-9)
        .with("sigma0", 170.0)
        .with("q", 250.0)
        .with("b", 9.0)
}

/// The example plugin loads, describes itself and passes the suite.
#[test]
fn j2_voce_library_loads_and_passes_the_suite() {
    let lib = MaterialLibrary::open(&libraries()[0]).expect("open");
    assert_eq!(lib.name(), "j2-voce");
    assert_eq!((lib.n_state(), lib.isotropic()), (1, true));
    assert!(lib.params().iter().any(|p| p.name == "sigma0"));
    let m = lib.build(&steel()).expect("build");
    assert_eq!(m.elastic().young, 206_000.0);
    let report = check_material(&m);
    assert!(report.passed(), "{report}");
}

/// A panic inside the library's `update` comes back as an error naming the
/// plugin, the call, the point and the panic's message; the host goes on.
#[test]
fn a_panic_in_a_loaded_material_is_an_error_not_an_abort() {
    let lib = MaterialLibrary::open(&libraries()[1]).expect("open");
    let m = lib.build(&steel().with("fault", 3.0)).expect("build");
    let (mut s, mut st, mut r) = ([[0.0; 3]], [0.0], [PointResult::default()]);
    m.initial_state(&mut st).expect("state");
    let e = m
        .update(&[[0.01, -0.005, 0.0]], &mut s, &mut st, &mut r)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(
            "material plugin test-broken-material panicked: test-broken-material: fault 3"
        ),
        "{e}"
    );
    assert!(e.contains("in update at point 0"), "{e}");
}

/// Parameters go through the schema (unknown and out of range are refused,
/// each naming the parameter) and then the plugin (its own refusal passed on).
#[test]
fn material_parameters_are_checked_against_the_schema() {
    let lib = MaterialLibrary::open(&libraries()[0]).expect("open");
    let unknown = lib
        .build(&steel().with("sigma_0", 1.0))
        .unwrap_err()
        .to_string();
    assert!(unknown.contains("unknown parameter `sigma_0`"), "{unknown}");
    // In range for the schema (≤ 0.5), refused by the plugin itself.
    let refused = lib
        .build(&steel().with("poissons_ratio", 0.5))
        .unwrap_err()
        .to_string();
    assert!(
        refused.contains(
            "invalid parameters of material plugin j2-voce: poissons_ratio = 0.5 must be < 0.5"
        ),
        "{refused}"
    );
    let range = lib
        .build(&steel().with("poissons_ratio", 0.7))
        .unwrap_err()
        .to_string();
    assert!(range.contains("`poissons_ratio` = 0.7"), "{range}");
}

/// Each loader says when a library is a plugin of the other kind.
#[test]
fn a_plugin_of_the_other_kind_is_named_as_such() {
    let as_material = MaterialLibrary::open(&libraries()[2])
        .unwrap_err()
        .to_string();
    assert!(
        as_material.contains("not a formsim material plugin")
            && as_material.contains("it is a friction plugin"),
        "{as_material}"
    );
    let as_friction = PluginLibrary::open(&libraries()[0])
        .unwrap_err()
        .to_string();
    assert!(
        as_friction.contains("not a formsim friction plugin")
            && as_friction.contains("it is a material plugin"),
        "{as_friction}"
    );
}
