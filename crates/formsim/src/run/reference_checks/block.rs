//! `kind = "block-on-plane"`: a block pressed on a plane by a normal force
//! `N` and pulled; the mean friction force while sliding against `μN`.
//!
//! - Needs `[output.block]` (`pull_set`, `pull_dof`, `normal_force`,
//!   `average_from`).
//! - Samples the pulled set's reaction along `pull_dof` from
//!   `average_from` on; its mean is the slip force.
//! - Figures: `slip_force`, `analytic = μ normal_force`.

use super::PullMean;
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
    match loaded.scene.output.block {
        Some(_) => Ok(()),
        None => Err(loaded.key_error(
            "output.block",
            "a block-on-plane scene needs [output.block]",
        )),
    }
}

/// The pulled end's mean reaction and the normal force.
struct Block {
    pull: PullMean,
    normal_force: f64,
}

fn start(loaded: &LoadedScene, _model: &Model) -> Option<Box<dyn Sampler>> {
    let b = loaded.scene.output.block.as_ref()?;
    Some(Box::new(Block {
        pull: PullMean::new(&b.pulled_end()),
        normal_force: b.normal_force,
    }))
}

impl Sampler for Block {
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError> {
        self.pull.sample(loaded, model).map(|_| ())
    }

    fn sampled(&self) -> bool {
        self.pull.samples() > 0
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        Some(Figures {
            value: self.pull.mean(),
            analytic: mu * self.normal_force,
            more: Vec::new(),
        })
    }
}

fn line(f: &Figures) -> String {
    format!(
        "block: slip force {:.3} N, mu N = {:.3} N ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}
