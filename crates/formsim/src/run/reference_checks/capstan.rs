//! `kind = "capstan"`: a strip wrapped over a drum, held by `T_hold` at one
//! end and pulled at the other; the steady tension ratio `T_pull / T_hold`
//! against Euler–Eytelwein's `e^{μθ}`.
//!
//! - Needs `[output.capstan]` (`pull_set`, `pull_dof`, `hold_force`,
//!   `angle_deg`, `average_from`).
//! - Samples the pulled set's reaction along `pull_dof` from
//!   `average_from` on; its mean is `T_pull`.
//! - Figures: `tension_ratio = T_pull / hold_force`, `analytic =
//!   e^{μ angle_deg π/180}`.

use super::{PullOnly, needs_table};
use crate::scene::kind::{Figures, ReferenceCheck, Sampler};
use crate::scene::{LoadedScene, Model, SceneError};

inventory::submit! {
    ReferenceCheck {
        name: "capstan",
        summary: "strip wrapped over a drum and pulled: T_pull/T_hold against e^(mu theta); [output.capstan]",
        key: "capstan",
        value_key: "tension_ratio",
        needs,
        start,
        line,
    }
}

/// Referenced from [`super::ensure_linked`].
#[inline(never)]
pub(super) fn anchor() -> usize {
    std::hint::black_box(1)
}

fn needs(loaded: &LoadedScene) -> Result<(), SceneError> {
    let present = loaded.scene.output.capstan.is_some();
    needs_table(loaded, present, "capstan", "capstan")
}

/// The pulled end's mean reaction over `hold_force` against `e^{μθ}`.
fn start(loaded: &LoadedScene, _model: &Model) -> Option<Box<dyn Sampler>> {
    let c = loaded.scene.output.capstan.as_ref()?;
    let angle = c.angle_deg.to_radians();
    Some(PullOnly::boxed(&c.pulled_end(), c.hold_force, move |mu| {
        (mu * angle).exp()
    }))
}

fn line(f: &Figures) -> String {
    format!(
        "capstan: T_pull/T_hold = {:.4}, e^(mu theta) = {:.4} ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}
