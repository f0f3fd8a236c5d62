//! The example dynamic plugin (`plugins/exp-decay`) is built, loaded through the
//! C-ABI table and passes the conformance suite with every built-in formulation.

use friction_laws::builtin::{BuiltinFormulation, FORMULATION_NAMES};
use plugins_api::conformance::{Options, Subject, check_law};
use plugins_api::loader::PluginLibrary;
use plugins_api::{KinematicFormulation, Params};

#[test]
fn example_plugin_passes_conformance_with_every_formulation() {
    let path = formsim_integration_tests::build_example_plugin();
    let library = PluginLibrary::open(&path).unwrap_or_else(|e| panic!("{e}"));
    let forms: Vec<BuiltinFormulation> = FORMULATION_NAMES
        .iter()
        .map(|n| BuiltinFormulation::from_name(n).unwrap())
        .collect();
    let refs: Vec<&dyn KinematicFormulation> = forms
        .iter()
        .map(|f| f as &dyn KinematicFormulation)
        .collect();
    let build = |p: &Params| library.build(p);
    let subject = Subject {
        name: format!("plugin {}", library.name()),
        params: library.params(),
        build: &build,
        base: Params::new()
            .with("mu_s", 0.2)
            .with("mu_k", 0.12)
            .with("d", 0.05),
    };
    let report = check_law(&subject, &refs, &Options::default());
    println!("{report}");
    assert!(report.passed(), "{report}");
}
