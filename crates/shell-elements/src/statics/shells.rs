//! `StaticShells`: a set of shells (Belytschko–Tsay or fully integrated)
//! for the static solver — its constructors (a virgin mesh, or the state of
//! an explicit [`ShellSet`]) and what it gives back after a solve.

use super::element::StaticKernel;
use super::state::ShellState;
use crate::belytschko_tsay::Moduli;
use crate::error::ShellError;
use crate::formulation::ShellFormulation;
use crate::material::Material;
use crate::section::Section;
use crate::{BelytschkoTsay, ShellSet};

/// Shells as an effect of the static Newton solver
/// ([`fem_core::statics::StaticTangent`]): internal forces at a trial state
/// from the committed state, and their exact consistent tangent (see the
/// [module docs](crate::statics)).
///
/// `F` is the element formulation: [`BelytschkoTsay`] (the default) or
/// [`FullyIntegrated`](crate::FullyIntegrated); the static solver's
/// interface is implemented for those two (others have no static kernel).
/// The nodes are the static problem's (the same indices as in the quads);
/// their positions at the start of the solve are the reference the
/// stored stresses belong to.
#[derive(Debug, Clone)]
pub struct StaticShells<M: Material, F: ShellFormulation = BelytschkoTsay> {
    pub(super) name: String,
    pub(super) formulation: F,
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

impl<M: Material, F: ShellFormulation> StaticShells<M, F> {
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
        formulation: F,
        material: M,
    ) -> Result<Self, ShellError> {
        let name = name.into();
        let set = ShellSet::new(name.clone(), nodes, quads, section, formulation, material)?;
        Ok(Self::from_shell_set(name, &set))
    }

    /// The shells of an explicit set at the moment it is in: thickness,
    /// stresses, histories, transverse shear, hourglass and drilling forces
    /// as stored (every in-plane and through-thickness point), the
    /// formulation's options, section and material. The static problem's
    /// nodes must be the explicit model's nodes at that moment (its
    /// positions become the reference of the stresses); the nodal rotations
    /// are not needed (the elements have no directors: their fibres are
    /// normal to the co-rotational frame), so every rotation counts from
    /// that moment.
    pub fn from_shell_set(name: impl Into<String>, set: &ShellSet<F, M>) -> Self {
        let (ne, ip, np, nhg) = (
            set.len(),
            F::IN_PLANE_POINTS,
            set.section().rule.n,
            F::HOURGLASS_VARS,
        );
        // Point `i` of the state: element `i / (ip np)`, in-plane point
        // `i / np % ip`, through-thickness point `i % np`.
        let at = |i: usize| (i / (ip * np), i / np % ip, i % np);
        let state = ShellState {
            in_plane: ip,
            points: np,
            hourglass_vars: nhg,
            thickness: (0..ne).map(|e| set.thickness(e)).collect(),
            stress: (0..ne * ip * np)
                .map(|i| {
                    let (e, p, k) = at(i);
                    set.stress(e, p, k)
                })
                .collect(),
            history: (0..ne * ip * np)
                .map(|i| {
                    let (e, p, k) = at(i);
                    *set.history(e, p, k)
                })
                .collect(),
            shear: (0..ne * ip)
                .map(|i| set.transverse_shear(i / ip, i % ip))
                .collect(),
            hourglass: (0..ne * nhg)
                .map(|i| set.hourglass_force(i / nhg, i % nhg))
                .collect(),
            drilling: (0..ne).map(|e| set.drilling_moments(e)).collect(),
        };
        Self {
            name: name.into(),
            formulation: set.formulation().clone(),
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
    pub fn formulation(&self) -> &F {
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
    /// co-rotational frame) at in-plane point `p` (`p <
    /// F::IN_PLANE_POINTS`) and through-thickness point `k` (bottom = 0)
    /// of element `e`, as [`ShellSet::stress`] indexes them.
    pub fn stress_at(&self, e: usize, p: usize, k: usize) -> [f64; 3] {
        self.committed.stress[self.committed.points_of(e, p).start + k]
    }

    /// Committed material history at a point (indices as
    /// [`StaticShells::stress_at`]).
    pub fn history_at(&self, e: usize, p: usize, k: usize) -> &M::History {
        &self.committed.history[self.committed.points_of(e, p).start + k]
    }

    /// Committed transverse shear stresses `[τ_xz, τ_yz]` (MPa) at in-plane
    /// point `p` of element `e`.
    pub fn transverse_shear_at(&self, e: usize, p: usize) -> [f64; 2] {
        self.committed.shear[self.committed.in_plane_index(e, p)]
    }

    /// Committed hourglass generalised force `k` (N or N·mm, `k <
    /// F::HOURGLASS_VARS`) of element `e`, as [`ShellSet::hourglass_force`].
    pub fn hourglass_force(&self, e: usize, k: usize) -> f64 {
        self.committed.hourglass[self.committed.hourglass_of(e).start + k]
    }

    /// Committed drilling moments (N·mm) of element `e` at its nodes.
    pub fn drilling_moments(&self, e: usize) -> [f64; 4] {
        self.committed.drilling[e]
    }
}

impl<M: Material> StaticShells<M, BelytschkoTsay> {
    /// Committed stress `[σ_xx, σ_yy, σ_xy]` (MPa, the element's
    /// co-rotational frame) at through-thickness point `k` (bottom = 0) of
    /// element `e` (its one in-plane point).
    pub fn stress(&self, e: usize, k: usize) -> [f64; 3] {
        self.stress_at(e, 0, k)
    }

    /// Committed material history at point `k` of element `e`.
    pub fn history(&self, e: usize, k: usize) -> &M::History {
        self.history_at(e, 0, k)
    }

    /// Committed transverse shear stresses `[τ_xz, τ_yz]` (MPa) of element `e`.
    pub fn transverse_shear(&self, e: usize) -> [f64; 2] {
        self.transverse_shear_at(e, 0)
    }

    /// Committed hourglass generalised forces of element `e` (N, N·mm):
    /// membrane x, y, bending x, y, transverse.
    pub fn hourglass_forces(&self, e: usize) -> [f64; 5] {
        std::array::from_fn(|k| self.hourglass_force(e, k))
    }
}

/// The static form of an explicit set of shells whose formulation has a
/// static kernel: [`StaticShells::from_shell_set`] under the set's name
/// ([`ShellFormulation::static_form`]).
pub(crate) fn static_form_of<F: StaticKernel, M: Material>(
    set: &ShellSet<F, M>,
) -> fem_core::StaticForm {
    let name = fem_core::Effect::name(set).to_string();
    let shells = StaticShells::from_shell_set(name, set);
    fem_core::StaticForm::Tangent(Box::new(shells))
}

/// Every element's committed state of the solved static shells `solved`
/// (the form [`static_form_of`] gave) and the work of its increments taken
/// back into `set` ([`ShellFormulation::absorb_static`]).
///
/// # Errors
/// `solved` is not static shells of this formulation and material, or not
/// of as many elements.
pub(crate) fn absorb_static_into<F: StaticKernel, M: Material>(
    set: &mut ShellSet<F, M>,
    solved: &dyn fem_core::statics::StaticTangent,
) -> Result<(), String> {
    let any: &dyn std::any::Any = solved;
    let Some(s) = any.downcast_ref::<StaticShells<M, F>>() else {
        return Err(format!(
            "{}: the static form handed back is not its static shells",
            fem_core::Effect::name(set)
        ));
    };
    if s.len() != set.len() {
        return Err(format!(
            "{}: {} static shells handed back for {} elements",
            fem_core::Effect::name(set),
            s.len(),
            set.len()
        ));
    }
    for e in 0..s.len() {
        set.restore_element(
            e,
            s.thickness(e),
            |p, k| (s.stress_at(e, p, k), *s.history_at(e, p, k)),
            |p| s.transverse_shear_at(e, p),
            &s.committed.hourglass[s.committed.hourglass_of(e)],
            s.drilling_moments(e),
        );
    }
    set.add_static_work(&s.work());
    Ok(())
}
