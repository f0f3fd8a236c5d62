//! The built-in elements and materials, each listed once: the two lists
//! generate [`add_shells`] (a material with every built-in element) and
//! [`with_builtin_material`] (an element with every built-in material), the
//! places where a registered name becomes a type. A new built-in element or
//! material is its own file plus one line here.

use super::{MaterialRequest, ShellRequest, Shells, add_set, elements, hill48, j2, plugin};
use super::{materials, names};
use crate::{Material, ShellError, ShellFormulation};
use fem_core::Solver;

/// `add_shells` over the built-in elements, each `name => maker`, the maker
/// making the formulation from the [`ShellRequest`].
macro_rules! builtin_elements {
    ($($name:literal => $make:path),+ $(,)?) => {
        /// Add the shells of `request.element`, a built-in element, with
        /// `material` (registered as `material_name`) to `solver`.
        ///
        /// # Errors
        /// An element that is not built in (the message lists those that
        /// are); the element's or the shell set's own checks.
        pub fn add_shells<M: Material>(
            request: &ShellRequest<'_>,
            material: M,
            material_name: &'static str,
            solver: &mut Solver,
        ) -> Result<Shells, ShellError> {
            match request.element {
                $($name => add_set(request, $make(request)?, material, $name, material_name, solver),)+
                other => Err(ShellError::InvalidInput(format!(
                    "element \"{other}\" is not built in, so material {material_name} has no pairing with it (built-in elements: {})",
                    [$($name),+].join(", ")
                ))),
            }
        }
    };
}

/// `with_builtin_material` over the built-in materials, each
/// `name => maker`, the maker making the material (and the user material's
/// own name, for `plugin`) from the [`MaterialRequest`].
macro_rules! builtin_materials {
    ($($name:literal => $make:path),+ $(,)?) => {
        /// Add the shells of `form`, the element registered as `element`,
        /// with `request.model`, a built-in material, to `solver`: what an
        /// element registered outside this crate calls from its
        /// [`ElementKind::add`](super::ElementKind::add).
        ///
        /// # Errors
        /// A material that is not built in (the message lists those that
        /// are); the material's or the shell set's own checks.
        pub fn with_builtin_material<E: ShellFormulation>(
            request: &MaterialRequest<'_>,
            form: E,
            element: &'static str,
            solver: &mut Solver,
        ) -> Result<Shells, ShellError> {
            match request.model {
                $($name => {
                    let (m, own) = $make(request)?;
                    let s = add_set(&request.shells, form, m, element, $name, solver)?;
                    Ok(Shells { plugin: own, ..s })
                })+
                other => Err(ShellError::InvalidInput(format!(
                    "material \"{other}\" is not built in, so element {element} has no pairing with it (built-in materials: {}; registered: {})",
                    [$($name),+].join(", "),
                    names(materials().iter().map(|k| k.name))
                ))),
            }
        }
    };
}

builtin_elements! {
    "belytschko-tsay" => elements::belytschko_tsay,
    "fully-integrated" => elements::fully_integrated,
}

builtin_materials! {
    "j2" => j2::make,
    "hill48" => hill48::make,
    "plugin" => plugin::make,
}
