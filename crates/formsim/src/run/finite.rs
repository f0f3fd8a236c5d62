//! The first non-finite value of a run: which quantity, at which node or
//! element (by the mesh file's numbers when the blank was read from a file),
//! at which step and time.
//!
//! [`ledger`] reads the handful of numbers of the energy ledger and runs
//! after every step; [`scan`] reads every node and element and runs when
//! the recorder is about to keep the state (a history sample, a report
//! stroke, a frame) and when the solver stops. Neither allocates.

use crate::scene::Model;
use crate::scene::blank_mesh::FileIds;
use fem_core::{EnergyLedger, Vec3};

/// Where a non-finite value sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// A node (the file's id, else the 0-based index).
    Node(i64),
    /// A shell element (the file's id, else the 0-based index).
    Element(i64),
    /// The model as a whole (an energy of the ledger).
    Model,
}

/// The first non-finite value found in the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NonFinite {
    /// The quantity, with its unit (`nodal velocity (mm/s)`, …).
    pub quantity: &'static str,
    /// Where.
    pub place: Place,
    /// The value (NaN or ±infinity).
    pub value: f64,
    /// The step (number of steps taken).
    pub step: u64,
    /// The time (s).
    pub time: f64,
}

impl std::fmt::Display for NonFinite {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let at = match self.place {
            Place::Node(n) => format!(" of node {n}"),
            Place::Element(e) => format!(" of element {e}"),
            Place::Model => String::new(),
        };
        write!(
            f,
            "{}{at} is {} at step {} (t = {:.6e} s)",
            self.quantity, self.value, self.step, self.time
        )
    }
}

fn bad(v: &Vec3) -> Option<f64> {
    [v.x, v.y, v.z].into_iter().find(|c| !c.is_finite())
}

/// The first non-finite energy of `e`, with its name.
fn ledger_value(e: &EnergyLedger) -> Option<(&'static str, f64)> {
    [
        ("kinetic energy (mJ)", e.kinetic),
        ("internal energy (mJ)", e.internal),
        ("hourglass energy (mJ)", e.hourglass),
        ("plastic dissipation (mJ)", e.plastic),
        ("contact energy (mJ)", e.contact),
        ("friction dissipation (mJ)", e.friction),
        ("external work (mJ)", e.external),
        ("energy balance error (-)", e.balance_error),
    ]
    .into_iter()
    .find(|(_, v)| !v.is_finite())
}

/// A non-finite energy in the solver's ledger (a few numbers: cheap enough
/// for every step).
pub fn ledger(model: &Model) -> Option<NonFinite> {
    let s = &model.solver;
    ledger_value(s.ledger()).map(|(quantity, value)| NonFinite {
        quantity,
        place: Place::Model,
        value,
        step: s.steps(),
        time: s.time(),
    })
}

/// The first non-finite value of the model, in the order a step computes
/// them: the nodes' displacement, velocity and angular velocity, then each
/// shell's thickness, largest von Mises stress and plastic strain, then the
/// nodal forces and moments, then the energies.
pub fn scan(model: &Model) -> Option<NonFinite> {
    let s = &model.solver;
    let ids = model.file_ids.as_ref();
    let state = s.state();
    let forces = s.forces();
    let node = |quantity, list: &[Vec3]| {
        list.iter().enumerate().find_map(|(i, v)| {
            bad(v).map(|value| (quantity, Place::Node(FileIds::node(ids, i)), value))
        })
    };
    let found = node("nodal displacement (mm)", &state.x)
        .or_else(|| node("nodal velocity (mm/s)", &state.v))
        .or_else(|| node("nodal angular velocity (rad/s)", &state.w))
        .or_else(|| {
            let shells = model.shells();
            (0..shells.len()).find_map(|e| {
                [
                    ("shell thickness (mm)", shells.thickness(e)),
                    ("shell von Mises stress (MPa)", shells.von_mises_max(e)),
                    ("shell plastic strain (-)", shells.plastic_strain_max(e)),
                ]
                .into_iter()
                .find(|(_, v)| !v.is_finite())
                .map(|(q, value)| (q, Place::Element(FileIds::element(ids, e)), value))
            })
        })
        .or_else(|| node("nodal force (N)", &forces.f))
        .or_else(|| node("nodal moment (N·mm)", &forces.m))
        .or_else(|| ledger_value(s.ledger()).map(|(q, v)| (q, Place::Model, v)));
    found.map(|(quantity, place, value)| NonFinite {
        quantity,
        place,
        value,
        step: s.steps(),
        time: s.time(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_value_names_quantity_place_step_and_time() {
        let v = NonFinite {
            quantity: "shell thickness (mm)",
            place: Place::Element(616),
            value: f64::NAN,
            step: 2871,
            time: 1.4355e-3,
        };
        assert_eq!(
            v.to_string(),
            "shell thickness (mm) of element 616 is NaN at step 2871 (t = 1.435500e-3 s)"
        );
    }

    #[test]
    fn the_ledger_check_finds_the_first_non_finite_energy() {
        let mut e = EnergyLedger::default();
        assert_eq!(ledger_value(&e), None);
        e.internal = f64::INFINITY;
        assert_eq!(
            ledger_value(&e),
            Some(("internal energy (mJ)", f64::INFINITY))
        );
    }
}
