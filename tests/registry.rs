//! The link-time registry is populated once `ensure_linked` is called (an
//! unreferenced crate's `inventory` submissions are dropped by the linker).

use plugins_api::registry;

#[test]
fn registry_holds_the_four_builtin_laws_and_formulations() {
    friction_laws::ensure_linked();
    let laws: Vec<&str> = registry::laws()
        .iter()
        .map(|e| e.description.name)
        .collect();
    let forms: Vec<&str> = registry::formulations().iter().map(|e| e.name).collect();
    for name in ["ac", "wvs", "wh", "levanov"] {
        assert!(laws.contains(&name), "law {name} not registered: {laws:?}");
    }
    for name in ["convective", "jaumann", "lagrangian", "updated-lagrangian"] {
        assert!(
            forms.contains(&name),
            "formulation {name} not registered: {forms:?}"
        );
    }
}

#[test]
fn unknown_names_list_the_known_ones() {
    friction_laws::ensure_linked();
    let e = registry::law("coulomb").unwrap_err().to_string();
    assert!(
        e.contains("unknown law `coulomb`") && e.contains("ac") && e.contains("levanov"),
        "{e}"
    );
    let e = registry::formulation("eulerian").unwrap_err().to_string();
    assert!(
        e.contains("unknown formulation `eulerian`") && e.contains("jaumann"),
        "{e}"
    );
}
