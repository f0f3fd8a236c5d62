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

use super::PullMean;
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
    match loaded.scene.output.capstan {
        Some(_) => Ok(()),
        None => Err(loaded.key_error("output.capstan", "a capstan scene needs [output.capstan]")),
    }
}

/// The pulled end's mean reaction, and what it is divided by and compared with.
struct Capstan {
    pull: PullMean,
    hold_force: f64,
    angle_deg: f64,
}

fn start(loaded: &LoadedScene, _model: &Model) -> Option<Box<dyn Sampler>> {
    let c = loaded.scene.output.capstan.as_ref()?;
    Some(Box::new(Capstan {
        pull: PullMean::new(&c.pulled_end()),
        hold_force: c.hold_force,
        angle_deg: c.angle_deg,
    }))
}

impl Sampler for Capstan {
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError> {
        self.pull.sample(loaded, model).map(|_| ())
    }

    fn sampled(&self) -> bool {
        self.pull.samples() > 0
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        Some(Figures {
            value: self.pull.mean() / self.hold_force,
            analytic: (mu * self.angle_deg.to_radians()).exp(),
            more: Vec::new(),
        })
    }
}

fn line(f: &Figures) -> String {
    format!(
        "capstan: T_pull/T_hold = {:.4}, e^(mu theta) = {:.4} ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}
