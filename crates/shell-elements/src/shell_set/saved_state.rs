//! The set's state saved and restored whole (forming in stages): every
//! point's stress and history, the shear, hourglass and drilling state, the
//! thickness and the mass-scaling factors, in the set's own storage order
//! (lane-major in blocks of four when the formulation asks), so that a
//! restored set continues bit for bit.

use super::ShellSet;
use crate::formulation::ShellFormulation;
use crate::material::{HistoryWords, Material};
use fem_core::StateArrays;

impl<E: ShellFormulation, M: Material> ShellSet<E, M> {
    /// Push the state to `out` (see the module docs).
    pub(super) fn save_arrays(&self, out: &mut StateArrays) {
        out.push(
            "conn",
            self.conn.iter().flatten().map(|&i| f64::from(i)).collect(),
        );
        out.push("thickness", self.thickness.clone());
        out.push("stress", self.stress.iter().flatten().copied().collect());
        let mut h = Vec::with_capacity(self.history.len() * M::History::WORDS);
        self.history.iter().for_each(|p| p.write_words(&mut h));
        out.push("history", h);
        out.push("shear", self.shear.iter().flatten().copied().collect());
        out.push("hourglass", self.hourglass.clone());
        out.push(
            "drilling",
            self.drilling.iter().flatten().copied().collect(),
        );
        out.push("density_scale", self.density_scale.clone());
        out.push("selective_scale", self.selective_scale.clone());
    }

    /// Take back what [`ShellSet::save_arrays`] pushed.
    ///
    /// # Errors
    /// Another connectivity, or an array of another length (another
    /// formulation, material or number of points through the thickness).
    pub(super) fn restore_arrays(&mut self, saved: &StateArrays) -> Result<(), String> {
        let conn = saved.get("conn", 4 * self.conn.len())?;
        let same = self
            .conn
            .iter()
            .flatten()
            .zip(conn)
            .all(|(&a, &b)| f64::from(a) == b);
        if !same {
            return Err("another connectivity of the elements".into());
        }
        let thickness = saved.get("thickness", self.thickness.len())?;
        let stress = saved.get("stress", 3 * self.stress.len())?;
        let words = M::History::WORDS;
        let history = saved.get("history", words * self.history.len())?;
        let shear = saved.get("shear", 2 * self.shear.len())?;
        let hourglass = saved.get("hourglass", self.hourglass.len())?;
        let drilling = saved.get("drilling", 4 * self.drilling.len())?;
        let density = saved.get("density_scale", self.density_scale.len())?;
        let selective = saved.get("selective_scale", self.selective_scale.len())?;
        self.thickness.copy_from_slice(thickness);
        for (s, c) in self.stress.iter_mut().zip(stress.chunks_exact(3)) {
            s.copy_from_slice(c);
        }
        for (h, c) in self
            .history
            .iter_mut()
            .zip(history.chunks_exact(words.max(1)))
        {
            *h = M::History::read_words(c);
        }
        for (s, c) in self.shear.iter_mut().zip(shear.chunks_exact(2)) {
            s.copy_from_slice(c);
        }
        self.hourglass.copy_from_slice(hourglass);
        for (d, c) in self.drilling.iter_mut().zip(drilling.chunks_exact(4)) {
            d.copy_from_slice(c);
        }
        self.density_scale.copy_from_slice(density);
        self.selective_scale.copy_from_slice(selective);
        Ok(())
    }
}
