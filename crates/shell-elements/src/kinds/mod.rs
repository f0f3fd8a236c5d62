//! Materials and shell elements by registration, as friction laws and tool
//! kinds are: each material a scene's `blank.material.model` may name is a
//! [`MaterialKind`], each `blank.element` an [`ElementKind`], submitted to
//! the registry (`inventory`) from their own files in this folder.
//!
//! The element loop is monomorphised over the element and the material, so
//! a run needs the pair's type, made at compile time. Each side reaches the
//! other side's built-ins, generated from one list (`builtin.rs`):
//!
//! - A new **material** is one file: its `MaterialKind` (name, summary,
//!   declared keys) and a builder that makes the material from a
//!   [`MaterialRequest`] and hands it to [`add_shells`], which pairs it with
//!   every built-in element.
//! - A new **element** is one file: its formulation (a
//!   [`ShellFormulation`]), its `ElementKind` (name, summary, declared keys)
//!   and an [`ElementKind::add`] that hands the formulation to
//!   [`with_builtin_material`], which pairs it with every built-in material.
//!   A built-in element or material is its file plus one line of the list in
//!   `builtin.rs`.
//!
//! [`add_blank`] resolves a scene's pair. Two components both registered
//! outside this crate pair only if one of them names the other (as
//! `tests/components_from_a_scene.rs` does).
//!
//! [`materials`] and [`elements`] list them (`formsim components`);
//! [`ensure_linked`] keeps this crate's registrations in a binary that names
//! nothing else of it.

mod builtin;
mod elements;
mod hill48;
mod j2;
mod plugin;

pub use builtin::{add_shells, with_builtin_material};
pub use plugin::{PluginSource, plugin_material};

use crate::{Hardening, Material, Section, ShellError, ShellSet};
use crate::{ShellFormulation, ShellView};
use fem_core::{EffectId, Solver, Vec3};

/// A registered material model.
#[derive(Debug)]
pub struct MaterialKind {
    /// The name a scene gives as `blank.material.model`.
    pub name: &'static str,
    /// One line: what it models and the keys it reads (units).
    pub summary: &'static str,
    /// Whether it reads `blank.material.r_values` (and needs them).
    pub anisotropic: bool,
    /// Whether it reads `[blank.material.hardening]` (and needs it).
    pub hardening: bool,
    /// Its own keys, given in `blank.material.parameters` and resolved
    /// against these specs (name, unit, default, range, doc) before the
    /// builder runs; the built-in models have none (the `plugin` model's
    /// keys are the library's own schema).
    pub params: &'static [plugins_api::ParamSpec],
    /// A whole run's cost per element cycle relative to `j2`'s, for the
    /// run-time estimate (measured; the material's file says where).
    pub relative_cost: f64,
    /// Make the material and add the blank's shells of `request.shells.element`.
    pub build: AddShells,
}

/// A registered shell element.
#[derive(Debug)]
pub struct ElementKind {
    /// The name a scene gives as `blank.element`.
    pub name: &'static str,
    /// One line: the formulation and its integration.
    pub summary: &'static str,
    /// Integration points in the plane (for the memory estimate).
    pub in_plane_points: usize,
    /// A whole run's cost per element cycle relative to Belytschko–Tsay's,
    /// for the run-time estimate (measured; the element's file says where).
    pub relative_cost: f64,
    /// Its own keys, given in `blank.element_parameters` and resolved
    /// against these specs (name, unit, default, range, doc) into
    /// [`ShellRequest::element_params`]; the built-in elements have none
    /// (the keys every shell reads are `[blank]`'s: section, hourglass,
    /// drilling, warping correction).
    pub params: &'static [plugins_api::ParamSpec],
    /// How its shells are added: `None` for a built-in element, which every
    /// material's builder reaches through [`add_shells`]; for an element
    /// registered elsewhere, a function that makes its formulation from the
    /// [`ShellRequest`] and hands it to [`with_builtin_material`].
    pub add: Option<AddShells>,
    /// Whether its shells have a static form (`ShellFormulation::static_form`),
    /// which a springback step's implicit method needs.
    pub static_form: bool,
}

/// Add the blank's shells of a request to a solver (a material's builder,
/// an element's [`ElementKind::add`]).
pub type AddShells = fn(&MaterialRequest<'_>, &mut Solver) -> Result<Shells, ShellError>;

inventory::collect!(MaterialKind);
inventory::collect!(ElementKind);

/// What a material's builder receives: the scene's `[blank.material]` values
/// and the shells to make.
#[derive(Debug)]
pub struct MaterialRequest<'a> {
    /// The material model asked for ([`MaterialKind::name`]).
    pub model: &'a str,
    /// Young's modulus (MPa).
    pub young: f64,
    /// Poisson's ratio (-).
    pub poisson: f64,
    /// Density (tonne/mm³).
    pub density: f64,
    /// Hardening curve (the built-in models need it; a plugin has its own).
    pub hardening: Option<Hardening>,
    /// Lankford coefficients `[r0, r45, r90]`, when the scene gives them.
    pub r_values: Option<[f64; 3]>,
    /// Angle from the elements' first axis to the rolling direction (rad),
    /// when the scene gives r-values.
    pub rolling_angle: Option<f64>,
    /// The values of the kind's own keys ([`MaterialKind::params`]), in the
    /// order of its specs.
    pub params: &'a [f64],
    /// The user material's library and parameters (`plugin` model).
    pub plugin: Option<PluginSource<'a>>,
    /// The shells.
    pub shells: ShellRequest<'a>,
}

impl MaterialRequest<'_> {
    /// The hardening curve, which a built-in `model` needs.
    ///
    /// # Errors
    /// None given.
    pub fn hardening_of(&self, model: &str) -> Result<Hardening, ShellError> {
        self.hardening.clone().ok_or_else(|| {
            ShellError::InvalidInput(format!("material {model} needs a hardening curve"))
        })
    }
}

/// The blank's shells, whatever the material.
#[derive(Debug)]
pub struct ShellRequest<'a> {
    /// The effect's name (`blank`).
    pub name: &'a str,
    /// The element asked for ([`ElementKind::name`]).
    pub element: &'a str,
    /// The values of the element's own keys ([`ElementKind::params`]), in
    /// the order of its specs.
    pub element_params: &'a [f64],
    /// Initial nodal positions (mm).
    pub nodes: &'a [Vec3],
    /// Quadrilaterals (node indices).
    pub quads: &'a [[u32; 4]],
    /// Thickness, through-thickness rule and hourglass control.
    pub section: Section,
    /// Warping correction of the element's frame.
    pub warping_correction: bool,
    /// Drilling-penalty factor (-).
    pub drilling: f64,
}

/// The shells a builder added: their effect, and read access through
/// [`ShellView`] whatever their concrete type.
#[derive(Debug, Clone, Copy)]
pub struct Shells {
    /// The effect.
    pub id: EffectId,
    /// Its element ([`ElementKind::name`]).
    pub element: &'static str,
    /// Its material ([`MaterialKind::name`]).
    pub material: &'static str,
    /// The user material's own name, for the `plugin` model.
    pub plugin: Option<&'static str>,
    view: fn(&Solver, EffectId) -> Option<&dyn ShellView>,
}

impl Shells {
    /// The shells in `solver`, read through [`ShellView`] (`None` if `solver`
    /// is not the one they were added to).
    pub fn view<'s>(&self, solver: &'s Solver) -> Option<&'s dyn ShellView> {
        (self.view)(solver, self.id)
    }

    /// The shells as their concrete type, when it is `ShellSet<E, M>`.
    pub fn get<'s, E: ShellFormulation, M: Material>(
        &self,
        solver: &'s Solver,
    ) -> Option<&'s ShellSet<E, M>> {
        solver.effect(self.id)
    }
}

fn view_of<E: ShellFormulation, M: Material>(
    solver: &Solver,
    id: EffectId,
) -> Option<&dyn ShellView> {
    solver
        .effect::<ShellSet<E, M>>(id)
        .map(|s| s as &dyn ShellView)
}

/// Add the blank's shells of `request`'s element and material to `solver`:
/// through the material's builder for a built-in element, through the
/// element's [`ElementKind::add`] for one registered elsewhere.
///
/// # Errors
/// An element or material not registered (the message lists those that
/// are); a pair with no monomorphised instance; the element's, the
/// material's or the shell set's own checks.
pub fn add_blank(request: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    let e = request.shells.element;
    let element = element(e).ok_or_else(|| {
        ShellError::InvalidInput(format!(
            "element \"{e}\" is not registered (registered: {})",
            names(elements().iter().map(|k| k.name))
        ))
    })?;
    match element.add {
        Some(add) => add(request, solver),
        None => {
            let m = request.model;
            let material = material(m).ok_or_else(|| {
                ShellError::InvalidInput(format!(
                    "material \"{m}\" is not registered (registered: {})",
                    names(materials().iter().map(|k| k.name))
                ))
            })?;
            (material.build)(request, solver)
        }
    }
}

/// Add a shell set of `form` and `material` to `solver` as the blank's
/// shells, under the registered names `element` and `material_name`.
///
/// # Errors
/// The shell set's own checks (mesh, section, formulation).
pub fn add_set<E: ShellFormulation, M: Material>(
    r: &ShellRequest<'_>,
    form: E,
    material: M,
    element: &'static str,
    material_name: &'static str,
    solver: &mut Solver,
) -> Result<Shells, ShellError> {
    let set = ShellSet::new(r.name, r.nodes, r.quads, r.section, form, material)?;
    Ok(Shells {
        id: solver.add_effect(set),
        element,
        material: material_name,
        plugin: None,
        view: view_of::<E, M>,
    })
}

/// Every registered material, sorted by name.
pub fn materials() -> Vec<&'static MaterialKind> {
    let mut v: Vec<_> = inventory::iter::<MaterialKind>.into_iter().collect();
    v.sort_by_key(|k| k.name);
    v
}

/// Every registered element, sorted by name.
pub fn elements() -> Vec<&'static ElementKind> {
    let mut v: Vec<_> = inventory::iter::<ElementKind>.into_iter().collect();
    v.sort_by_key(|k| k.name);
    v
}

/// The material named `name`.
pub fn material(name: &str) -> Option<&'static MaterialKind> {
    inventory::iter::<MaterialKind>
        .into_iter()
        .find(|k| k.name == name)
}

/// The element named `name`.
pub fn element(name: &str) -> Option<&'static ElementKind> {
    inventory::iter::<ElementKind>
        .into_iter()
        .find(|k| k.name == name)
}

/// `a, b, c` for messages.
pub fn names<'a>(it: impl Iterator<Item = &'a str>) -> String {
    it.collect::<Vec<_>>().join(", ")
}

/// Keep this crate's registrations in the final binary (call once at
/// start-up from a binary that names nothing else of the registry).
pub fn ensure_linked() {
    elements::ensure_linked();
    j2::ensure_linked();
    hill48::ensure_linked();
    plugin::ensure_linked();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both registries hold the built-ins, each name once.
    #[test]
    fn registries_are_not_empty_and_names_are_unique() {
        ensure_linked();
        let m: Vec<_> = materials().iter().map(|k| k.name).collect();
        let e: Vec<_> = elements().iter().map(|k| k.name).collect();
        assert!(
            m.contains(&"j2") && m.contains(&"hill48") && m.contains(&"plugin"),
            "{m:?}"
        );
        assert!(
            e.contains(&"belytschko-tsay") && e.contains(&"fully-integrated"),
            "{e:?}"
        );
        for list in [&m, &e] {
            let mut d = list.clone();
            d.dedup();
            assert_eq!(&d, list);
        }
        assert!(material("nope").is_none() && element("nope").is_none());
    }
}
