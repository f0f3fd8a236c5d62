//! `j2`: isotropic plane-stress J2 plasticity (the default material).

use super::{MaterialKind, MaterialRequest, Shells, add_shells};
use crate::{J2PlaneStress, ShellError};
use fem_core::Solver;

/// The material of `r` (listed in `builtin.rs`).
pub(super) fn make(
    r: &MaterialRequest<'_>,
) -> Result<(J2PlaneStress, Option<&'static str>), ShellError> {
    if r.r_values.is_some() {
        return Err(ShellError::InvalidInput(
            "material j2 is isotropic: it takes no r_values (use model = \"hill48\")".into(),
        ));
    }
    let m = J2PlaneStress::new(r.young, r.poisson, r.density, r.hardening_of("j2")?)?;
    Ok((m, None))
}

fn build(r: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    add_shells(&r.shells, make(r)?.0, "j2", solver)
}

inventory::submit! {
    MaterialKind {
        name: "j2",
        summary: "isotropic plane-stress J2 (von Mises) plasticity, radial return; youngs_modulus (MPa), poissons_ratio, density (tonne/mm³), hardening",
        hardening: true,
        params: &[],
        anisotropic: false,
        relative_cost: 1.0,
        build,
    }
}

/// Referenced from [`super::ensure_linked`].
pub(super) fn ensure_linked() {}
