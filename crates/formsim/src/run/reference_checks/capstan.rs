//! `kind = "capstan"`: a strip wrapped over a drum, held by `T_hold` at one
//! end and pulled at the other; the steady tension ratio `T_pull / T_hold`
//! against Euler–Eytelwein's `e^{μθ}`.
//!
//! - Its table `[output.capstan]`: `pull_set`, `pull_dof` (default `ux`),
//!   `hold_force` (N), `angle_deg`, `average_from` (s).
//! - Samples the pulled set's reaction along `pull_dof` from
//!   `average_from` on; its mean is `T_pull`.
//! - Figures: `tension_ratio = T_pull / hold_force`, `analytic =
//!   e^{μ angle_deg π/180}`.

use super::{AVERAGE_FROM, PULL_DOF_SPEC, PULL_SET, PullOnly, PulledEnd};
use crate::scene::check_table::{CheckTable, TableKey};
use crate::scene::kind::{Figures, ReferenceCheck, Sampler, needs_nothing_else};
use crate::scene::{LoadedScene, Model};
use plugins_api::ParamSpec;

inventory::submit! {
    ReferenceCheck {
        name: "capstan",
        summary: "strip wrapped over a drum and pulled: T_pull/T_hold against e^(mu theta); [output.capstan]",
        key: "capstan",
        keys: KEYS,
        value_key: "tension_ratio",
        needs: needs_nothing_else,
        start,
        line,
    }
}

/// Referenced from [`super::ensure_linked`].
#[inline(never)]
pub(super) fn anchor() -> usize {
    std::hint::black_box(1)
}

/// `[output.capstan]`.
const KEYS: &[TableKey] = &[
    PULL_SET,
    TableKey::Name(PULL_DOF_SPEC.or("ux")),
    TableKey::Number(
        ParamSpec::required(
            "hold_force",
            "N",
            0.0,
            f64::INFINITY,
            "the holding load T_hold at the other end",
        )
        .exclusive_min(),
    ),
    TableKey::Number(
        ParamSpec::required(
            "angle_deg",
            "deg",
            0.0,
            f64::INFINITY,
            "the wrap angle theta",
        )
        .exclusive_min(),
    ),
    AVERAGE_FROM,
];

/// The pulled end's mean reaction over `hold_force` against `e^{μθ}`.
fn start(_: &LoadedScene, table: &CheckTable, _: &Model) -> Option<Box<dyn Sampler>> {
    let hold_force = table.number("hold_force")?;
    let angle = table.number("angle_deg")?.to_radians();
    Some(PullOnly::boxed(
        &PulledEnd::of(table)?,
        hold_force,
        move |mu| (mu * angle).exp(),
    ))
}

fn line(f: &Figures) -> String {
    format!(
        "capstan: T_pull/T_hold = {:.4}, e^(mu theta) = {:.4} ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}
