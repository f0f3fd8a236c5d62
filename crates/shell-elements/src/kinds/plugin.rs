//! `plugin`: a user material from a dynamic plugin (`blank.material.plugin`,
//! parameters in `blank.material.parameters`), through the C-ABI table of
//! [`plugins_api::material`].

use std::path::Path;

use plugins_api::Params;
use plugins_api::material::loader::MaterialLibrary;

use super::{MaterialKind, MaterialRequest, Shells, add_shells};
use crate::{PluginMaterial, ShellError};
use fem_core::Solver;

/// Where a plugin material comes from.
#[derive(Debug, Clone, Copy)]
pub struct PluginSource<'a> {
    /// The shared library.
    pub path: &'a Path,
    /// The scene's values for the plugin's parameters.
    pub params: &'a Params,
}

/// The scene keys whose values a plugin receives when its schema has a
/// parameter of that name and the scene's `parameters` do not set it.
const SHARED_KEYS: [&str; 3] = ["youngs_modulus", "poissons_ratio", "density"];

/// Open the plugin, create its material from `source.params` (the sheet's
/// `young`, `poisson`, `density` filling parameters of those names), and
/// check that the elastic constants it reports are the sheet's (they set the
/// wave speed, the contact stiffness and the estimate).
///
/// # Errors
/// The loader's message (path, symbol, version, parameters, a panic); or the
/// reported constants differing from the sheet's by more than 1e-12.
pub fn plugin_material(
    source: PluginSource<'_>,
    young: f64,
    poisson: f64,
    density: f64,
) -> Result<PluginMaterial, ShellError> {
    let bad = |e: &dyn std::fmt::Display| ShellError::InvalidInput(e.to_string());
    let lib = MaterialLibrary::open(source.path).map_err(|e| bad(&e))?;
    let mut params = source.params.clone();
    for (key, value) in SHARED_KEYS.into_iter().zip([young, poisson, density]) {
        if lib.params().iter().any(|p| p.name == key) && !params.0.contains_key(key) {
            params.set(key, value);
        }
    }
    let m = lib.build(&params).map_err(|e| bad(&e))?;
    let e = m.elastic();
    for (what, unit, got, want) in [
        ("Young's modulus", "MPa", e.young, young),
        ("Poisson's ratio", "-", e.poisson, poisson),
        ("density", "tonne/mm³", e.density, density),
    ] {
        if (got - want).abs() > 1e-12 * want.abs() {
            return Err(ShellError::InvalidInput(format!(
                "material plugin {} reports {what} {got} {unit}, the sheet's is {want} {unit}: they must agree",
                m.name()
            )));
        }
    }
    PluginMaterial::new(m)
}

/// The material of `r` and the user material's own name (listed in
/// `builtin.rs`).
pub(super) fn make(
    r: &MaterialRequest<'_>,
) -> Result<(PluginMaterial, Option<&'static str>), ShellError> {
    let Some(source) = r.plugin else {
        return Err(ShellError::InvalidInput(
            "material plugin needs plugin = \"path/to/library\"".into(),
        ));
    };
    let m = plugin_material(source, r.young, r.poisson, r.density)?;
    let name = m.plugin().name();
    Ok((m, Some(name)))
}

fn build(r: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    let (m, name) = make(r)?;
    let shells = add_shells(&r.shells, m, "plugin", solver)?;
    Ok(Shells {
        plugin: name,
        ..shells
    })
}

inventory::submit! {
    MaterialKind {
        name: "plugin",
        summary: "a user material from a shared library (C-ABI table formsim_material_plugin_v1): plugin (path, relative to the scene), parameters = { … } (the plugin's schema: formsim plugin check PATH); youngs_modulus (MPa), poissons_ratio, density (tonne/mm³) must agree with the plugin's",
        anisotropic: false,
        hardening: false,
        params: &[],
        // Depends on the plugin's own cost. Measured for the example
        // j2-voce on the square cup (`scenes/square-cup-plugin.toml` against
        // `scenes/square-cup.toml`, 2 threads, in turn): wall
        // 30.9 s against 15.9 s (median of 3; docs/materials.md).
        relative_cost: 2.0,
        build,
    }
}

/// Referenced from [`super::ensure_linked`].
pub(super) fn ensure_linked() {}
