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
        // Measured on the square cup (`scenes/square-cup-hill.toml` against
        // `scenes/square-cup.toml`, 2 threads, one after the other): 2.357e6
        // against 4.954e6 element cycles/s (the return runs lane by lane,
        // about 9× J2's lane kernel; contact is shared).
        relative_cost: 2.1,
        build,
    }
}

/// Referenced from [`super::ensure_linked`].
pub(super) fn ensure_linked() {}
