//! `StaticShells`: a set of Belytschko–Tsay shells for the static solver —
//! its constructors (a virgin mesh, or the state of an explicit
//! [`ShellSet`]) and what it gives back after a solve.

use super::state::ShellState;
use crate::belytschko_tsay::Moduli;
use crate::error::ShellError;
use crate::material::Material;
use crate::section::Section;
use crate::{BelytschkoTsay, ShellSet};

/// Belytschko–Tsay shells as an effect of the static Newton solver
/// ([`fem_core::statics::StaticTangent`]): internal forces at a trial state
/// from the committed state, and their exact consistent tangent (see the
/// [module docs](crate::statics)).
///
/// The nodes are the static problem's (the same indices as in the quads);
/// their positions at the start of the solve are the reference the
/// stored stresses belong to.
#[derive(Debug, Clone)]
pub struct StaticShells<M: Material> {
    pub(super) name: String,
    pub(super) formulation: BelytschkoTsay,
    pub(super) material: M,
    pub(super) section: Section,
    pub(super) moduli: Moduli,
    pub(super) conn: Vec<[u32; 4]>,
    pub(super) committed: ShellState<M::History>,
    pub(super) trial: ShellState<M::History>,
    /// Work done on the shells over the committed increments (mJ): the
    /// stresses' and drilling penalty's, the hourglass control's, and the
    /// plastic dissipation within the first.
    pub(super) work: fem_core::EnergyTally,
}

impl<M: Material> StaticShells<M> {
    /// Virgin shells (zero stress, initial history, thickness of
    /// `section`) on `quads` (0-based indices into `nodes`,
    /// counter-clockwise seen from the top).
    ///
    /// # Errors
    /// As [`ShellSet::new`]: a node out of range or repeated, zero area, an
    /// inverted or non-convex corner, invalid formulation parameters.
    pub fn new(
        name: impl Into<String>,
        nodes: &[fem_core::Vec3],
        quads: &[[u32; 4]],
        section: Section,
        formulation: BelytschkoTsay,
        material: M,
    ) -> Result<Self, ShellError> {
        let name = name.into();
        let set = ShellSet::new(name.clone(), nodes, quads, section, formulation, material)?;
        Ok(Self::from_shell_set(name, &set))
    }

    /// The shells of an explicit set at the moment it is in: thickness,
    /// stresses, histories, transverse shear, hourglass and drilling forces
    /// as stored, the formulation's options, section and material. The
    /// static problem's nodes must be the explicit model's nodes at that
    /// moment (its positions become the reference of the stresses); the
    /// nodal rotations are not needed (the element has no directors: its
    /// fibres are normal to the co-rotational frame), so every rotation
    /// counts from that moment.
    pub fn from_shell_set(name: impl Into<String>, set: &ShellSet<BelytschkoTsay, M>) -> Self {
        let (ne, np) = (set.len(), set.section().rule.n);
        let state = ShellState {
            points: np,
            thickness: (0..ne).map(|e| set.thickness(e)).collect(),
            stress: (0..ne * np)
                .map(|p| set.stress(p / np, 0, p % np))
                .collect(),
            history: (0..ne * np)
                .map(|p| *set.history(p / np, 0, p % np))
                .collect(),
            shear: (0..ne).map(|e| set.transverse_shear(e, 0)).collect(),
            hourglass: (0..ne)
                .map(|e| std::array::from_fn(|k| set.hourglass_force(e, k)))
                .collect(),
            drilling: (0..ne).map(|e| set.drilling_moments(e)).collect(),
        };
        Self {
            name: name.into(),
            formulation: *set.formulation(),
            material: set.material().clone(),
            section: *set.section(),
            moduli: Moduli::of(set.material(), set.section()),
            conn: set.quads().to_vec(),
            trial: state.clone(),
            committed: state,
            work: fem_core::EnergyTally::default(),
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.conn.len()
    }

    /// Whether the set has no element.
    pub fn is_empty(&self) -> bool {
        self.conn.is_empty()
    }

    /// Connectivity.
    pub fn quads(&self) -> &[[u32; 4]] {
        &self.conn
    }

    /// The material.
    pub fn material(&self) -> &M {
        &self.material
    }

    /// The section.
    pub fn section(&self) -> &Section {
        &self.section
    }

    /// The formulation's options.
    pub fn formulation(&self) -> &BelytschkoTsay {
        &self.formulation
    }

    /// Work done on the shells since they were built, over the committed
    /// increments (mJ): `internal` (stresses and drilling penalty, of
    /// which `plastic` dissipated) and `hourglass`.
    pub fn work(&self) -> fem_core::EnergyTally {
        self.work
    }

    /// Committed thickness of element `e` (mm).
    pub fn thickness(&self, e: usize) -> f64 {
        self.committed.thickness[e]
    }

    /// Committed stress `[σ_xx, σ_yy, σ_xy]` (MPa, the element's
    /// co-rotational frame) at through-thickness point `k` (bottom = 0) of
    /// element `e`.
    pub fn stress(&self, e: usize, k: usize) -> [f64; 3] {
        self.committed.stress[e * self.committed.points + k]
    }

    /// Committed material history at point `k` of element `e`.
    pub fn history(&self, e: usize, k: usize) -> &M::History {
        &self.committed.history[e * self.committed.points + k]
    }

    /// Committed transverse shear stresses `[τ_xz, τ_yz]` (MPa) of element `e`.
    pub fn transverse_shear(&self, e: usize) -> [f64; 2] {
        self.committed.shear[e]
    }

    /// Committed hourglass generalised forces of element `e` (N, N·mm):
    /// membrane x, y, bending x, y, transverse.
    pub fn hourglass_forces(&self, e: usize) -> [f64; 5] {
        self.committed.hourglass[e]
    }

    /// Committed drilling moments (N·mm) of element `e` at its nodes.
    pub fn drilling_moments(&self, e: usize) -> [f64; 4] {
        self.committed.drilling[e]
    }
}
