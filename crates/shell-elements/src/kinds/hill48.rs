//! `hill48`: Hill'48 plane-stress anisotropy from the r-values.

use super::{MaterialKind, MaterialRequest, Shells, add_shells};
use crate::ShellError;
use crate::material::Hill48PlaneStress;
use fem_core::Solver;

/// The material of `r` (listed in `builtin.rs`).
pub(super) fn make(
    r: &MaterialRequest<'_>,
) -> Result<(Hill48PlaneStress, Option<&'static str>), ShellError> {
    let Some(rv) = r.r_values else {
        return Err(ShellError::InvalidInput(
            "material hill48 needs r_values = [r0, r45, r90]".into(),
        ));
    };
    let m = Hill48PlaneStress::new(r.young, r.poisson, r.density, r.hardening_of("hill48")?, rv)
        .and_then(|m| m.with_rolling_angle(r.rolling_angle.unwrap_or(0.0)))?;
    Ok((m, None))
}

fn build(r: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    add_shells(&r.shells, make(r)?.0, "hill48", solver)
}

inventory::submit! {
    MaterialKind {
        name: "hill48",
        summary: "Hill'48 plane-stress anisotropy from r_values = [r0, r45, r90], rolling direction along global x, the rolling direction's hardening; youngs_modulus (MPa), poissons_ratio, density (tonne/mm³), hardening",
        hardening: true,
        params: &[],
        anisotropic: true,
        // Measured on the square cups (`scenes/square-cup-hill.toml`
        // against `scenes/square-cup.toml`, 2 threads, one after the
        // other): 3.270e6 against 3.380e6 element cycles/s, and 3.208e6
        // against 3.357e6 for the aluminium's (the return runs in lanes,
        // about 1.2× J2's element cost; contact is shared).
        relative_cost: 1.04,
        build,
    }
}

/// Referenced from [`super::ensure_linked`].
pub(super) fn ensure_linked() {}
