//! `kind = "block-on-plane"`: a block pressed on a plane by a normal force
//! `N` and pulled; the mean friction force while sliding against `μN`.
//!
//! - Needs `[output.block]` (`pull_set`, `pull_dof`, `normal_force`,
//!   `average_from`).
//! - Samples the pulled set's reaction along `pull_dof` from
//!   `average_from` on; its mean is the slip force.
//! - Figures: `slip_force`, `analytic = μ normal_force`.

use super::{PullOnly, needs_table};
use crate::scene::kind::{Figures, ReferenceCheck, Sampler};
use crate::scene::{LoadedScene, Model, SceneError};

inventory::submit! {
    ReferenceCheck {
        name: "block-on-plane",
        summary: "block pressed on a plane and pulled: slip force against mu N; [output.block]",
        key: "block",
        value_key: "slip_force",
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
    let present = loaded.scene.output.block.is_some();
    needs_table(loaded, present, "block-on-plane", "block")
}

/// The pulled end's mean reaction against `μ normal_force`.
fn start(loaded: &LoadedScene, _model: &Model) -> Option<Box<dyn Sampler>> {
    let b = loaded.scene.output.block.as_ref()?;
    let normal_force = b.normal_force;
    Some(PullOnly::boxed(&b.pulled_end(), 1.0, move |mu| {
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
