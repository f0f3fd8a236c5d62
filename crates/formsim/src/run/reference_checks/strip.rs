//! `kind = "strip-draw"`: a strip drawn between a force-controlled holder
//! and a die; the mean draw force against `2μF` (friction on both faces),
//! with `F` the holder's mean prescribed force, and the force the holder
//! delivered against `F`.
//!
//! - Its table `[output.strip]`: `pull_set`, `pull_dof`, `holder` (a
//!   tool), `average_from` (s); needs the `holder` to be a tool,
//!   force-controlled in some step.
//! - Samples, from `average_from` on: the pulled set's reaction along
//!   `pull_dof` (the draw force), the holder's force on the strip along its
//!   press axis (delivered) and the force prescribed to it.
//! - Figures: `draw_force`, `analytic = 2 μ F`, `holder_force` (mean
//!   delivered), `holder_prescribed` (`F`), `mu`.

use super::{AVERAGE_FROM, PULL_DOF, PULL_SET, PullMean, PulledEnd};
use crate::run::tools_report::press_axes;
use crate::scene::check_table::{CheckTable, NameSpec, TableKey};
use crate::scene::kind::{Figures, ReferenceCheck, Sampler};
use crate::scene::schema::Motion;
use crate::scene::{LoadedScene, Model, SceneError};
use plugins_api::Vec3;

inventory::submit! {
    ReferenceCheck {
        name: "strip-draw",
        summary: "strip drawn between a force-controlled holder and a die: draw force against 2 mu F; [output.strip]",
        key: "strip",
        keys: KEYS,
        value_key: "draw_force",
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

/// `[output.strip]`.
const KEYS: &[TableKey] = &[
    PULL_SET,
    PULL_DOF,
    TableKey::Name(NameSpec::required(
        "holder",
        "tool",
        "the force-controlled tool pressing the strip on the die",
    )),
    AVERAGE_FROM,
];

/// The holder is a tool, force-controlled in some step.
fn needs(loaded: &LoadedScene, table: &CheckTable) -> Result<(), SceneError> {
    let s = &loaded.scene;
    let holder = table.name("holder").unwrap_or_default();
    if !s.tools.contains_key(holder) {
        return Err(loaded.key_error("output.strip.holder", format!("\"{holder}\": no such tool")));
    }
    let force_controlled = s
        .steps
        .iter()
        .flat_map(|step| &step.motions)
        .any(|m| matches!(m, Motion::Force { .. }) && m.tool() == holder);
    if !force_controlled {
        return Err(loaded.key_error(
            "output.strip.holder",
            format!(
                "\"{holder}\": the holder must be force-controlled in some step (its force is the reference 2 mu F)"
            ),
        ));
    }
    Ok(())
}

/// The draw force's mean and the holder's sums over the same samples.
struct Strip {
    pull: PullMean,
    /// The holder's tool index and press axis (with contact in the model).
    holder: Option<(usize, Option<Vec3>)>,
    /// Σ of the holder's force on the strip along its axis.
    delivered: f64,
    /// Σ of the force prescribed to it.
    prescribed: f64,
}

fn start(_: &LoadedScene, table: &CheckTable, model: &Model) -> Option<Box<dyn Sampler>> {
    let holder_name = table.name("holder")?;
    let holder = model
        .tool_names
        .iter()
        .position(|n| n == holder_name)
        .map(|i| (i, press_axes(model).get(i).copied()));
    Some(Box::new(Strip {
        pull: PullMean::new(&PulledEnd::of(table)?),
        holder,
        delivered: 0.0,
        prescribed: 0.0,
    }))
}

impl Sampler for Strip {
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError> {
        if !self.pull.sample(loaded, model)? {
            return Ok(());
        }
        if let (Some((i, Some(axis))), Some(c)) = (self.holder, model.contact()) {
            self.delivered -= c.reactions()[i].dot(&axis);
            self.prescribed += model
                .press()
                .and_then(|p| p.applied_force(i))
                .unwrap_or(0.0);
        }
        Ok(())
    }

    fn sampled(&self) -> bool {
        self.pull.samples() > 0
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        self.holder?;
        // The sums are over the pull's samples (0 before the first).
        let n = self.pull.samples().max(1) as f64;
        let (delivered, prescribed) = (self.delivered / n, self.prescribed / n);
        Some(Figures {
            value: self.pull.mean(),
            analytic: 2.0 * mu * prescribed,
            more: vec![
                ("holder_force", delivered),
                ("holder_prescribed", prescribed),
                ("mu", mu),
            ],
        })
    }
}

fn line(f: &Figures) -> String {
    let get = |name| f.get(name).unwrap_or(f64::NAN);
    format!(
        "strip: draw force {:.2} N, 2 mu F = {:.2} N ({:+.2} %; F = {:.1} N prescribed, {:.1} N delivered, mu = {})",
        f.value,
        f.analytic,
        f.deviation_percent(),
        get("holder_prescribed"),
        get("holder_force"),
        get("mu")
    )
}
