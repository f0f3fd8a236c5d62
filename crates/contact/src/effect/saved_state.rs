//! The contact effect's state saved and restored (forming in stages): each
//! pair's per-point state under `pair.NAME.` and the blank's deformation
//! gradients (which the Lagrangian formulations carry from step to step).
//! Pairs are matched by name; the state of a saved pair with no pair of its
//! name here is dropped, and a pair with no saved state starts afresh, each
//! with one line in the notes.

use super::ContactEffect;
use fem_core::StateArrays;
use plugins_api::Mat3;

fn flatten_mats(m: &[Mat3]) -> Vec<f64> {
    m.iter()
        .flat_map(|a| a.iter().copied().collect::<Vec<_>>())
        .collect()
}

fn unflatten_mats(flat: &[f64], out: &mut [Mat3]) {
    for (a, c) in out.iter_mut().zip(flat.chunks_exact(9)) {
        *a = Mat3::from_column_slice(c);
    }
}

impl ContactEffect {
    /// Push the state (see the module docs).
    pub(super) fn save_arrays(&self, out: &mut StateArrays) {
        out.push("f_old", flatten_mats(&self.geometry.f_old));
        out.push("f_new", flatten_mats(&self.geometry.f_new));
        out.push("reactions", fem_core::resume::flatten(&self.reactions));
        for p in &self.pairs {
            p.save_arrays(&format!("pair.{}.", p.name()), out);
        }
    }

    /// Take back what [`ContactEffect::save_arrays`] pushed.
    ///
    /// # Errors
    /// A pair of the same name over other nodes, an array of another length.
    pub(super) fn restore_arrays(
        &mut self,
        saved: &StateArrays,
        notes: &mut Vec<String>,
    ) -> Result<(), String> {
        let f_old = saved.get("f_old", 9 * self.geometry.f_old.len())?;
        let f_new = saved.get("f_new", 9 * self.geometry.f_new.len())?;
        unflatten_mats(f_old, &mut self.geometry.f_old);
        unflatten_mats(f_new, &mut self.geometry.f_new);
        if let Ok(r) = saved.get("reactions", 3 * self.reactions.len()) {
            // The tools' last reactions (the first record of the next run
            // reads them); tools are matched by index, as the pairs' names
            // name them.
            fem_core::resume::unflatten(r, &mut self.reactions);
        }
        let saved_pairs: Vec<&str> = saved
            .entries()
            .iter()
            .filter_map(|(k, _)| k.strip_prefix("pair.")?.strip_suffix(".nodes"))
            .collect();
        for p in &mut self.pairs {
            let name = p.name().to_string();
            if saved_pairs.contains(&name.as_str()) {
                p.restore_arrays(&format!("pair.{name}."), saved)?;
            } else {
                notes.push(format!(
                    "contact pair `{name}` has no saved friction state: it starts afresh"
                ));
            }
        }
        for name in saved_pairs {
            if !self.pairs.iter().any(|p| p.name() == name) {
                notes.push(format!(
                    "the friction state of contact pair `{name}` is dropped: no pair of that name here"
                ));
            }
        }
        Ok(())
    }
}
