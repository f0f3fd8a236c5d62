//! `kind = "block-on-plane"`: a block pressed on a plane by a normal force
//! `N` and pulled; the mean friction force while sliding against `μN`.
//!
//! - Its table `[output.block]`: `pull_set`, `pull_dof`, `normal_force`
//!   (N), `average_from` (s).
//! - Samples the pulled set's reaction along `pull_dof` from
//!   `average_from` on; its mean is the slip force.
//! - Figures: `slip_force`, `analytic = μ normal_force`.

use super::{AVERAGE_FROM, PULL_DOF, PULL_SET, PullOnly, PulledEnd};
use crate::scene::check_table::{CheckTable, TableKey};
use crate::scene::kind::{Figures, ReferenceCheck, Sampler, needs_nothing_else};
use crate::scene::{LoadedScene, Model};
use plugins_api::ParamSpec;

inventory::submit! {
    ReferenceCheck {
        name: "block-on-plane",
        summary: "block pressed on a plane and pulled: slip force against mu N; [output.block]",
        key: "block",
        keys: KEYS,
        value_key: "slip_force",
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

/// `[output.block]`.
const KEYS: &[TableKey] = &[
    PULL_SET,
    PULL_DOF,
    TableKey::Number(
        ParamSpec::required(
            "normal_force",
            "N",
            0.0,
            f64::INFINITY,
            "the normal force N pressing the block on the plane",
        )
        .exclusive_min(),
    ),
    AVERAGE_FROM,
];

/// The pulled end's mean reaction against `μ normal_force`.
fn start(_: &LoadedScene, table: &CheckTable, _: &Model) -> Option<Box<dyn Sampler>> {
    let normal_force = table.number("normal_force")?;
    Some(PullOnly::boxed(&PulledEnd::of(table)?, 1.0, move |mu| {
        mu * normal_force
    }))
}

fn line(f: &Figures) -> String {
    format!(
        "block: slip force {:.3} N, mu N = {:.3} N ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}
