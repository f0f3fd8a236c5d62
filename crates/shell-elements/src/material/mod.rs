//! The `Material` trait (plane-stress update at one integration point), the built-in materials
//! ([`J2PlaneStress`], [`Hill48PlaneStress`]) and user materials from plugins ([`PluginMaterial`]).
//!
//! A material is a parameter object shared by every point of a shell set; each
//! point's state (stress in the element's co-rotational frame and the
//! material's own history) is owned by the caller and passed in by reference,
//! so the element loop stays monomorphised and allocation-free.

mod curve;
mod hardening;
mod hill48_plane_stress;
mod j2_plane_stress;
mod plugin;

pub use hardening::Hardening;
pub use hill48_plane_stress::{
    HILL_RETURN_CLOSE, HILL_RETURN_TOL, Hill48History, Hill48PlaneStress, HillCoefficients,
    stress_rotation,
};
pub use j2_plane_stress::{J2History, J2PlaneStress, RETURN_CLOSE, RETURN_TOL};
pub use plugin::{CHUNK, PluginHistory, PluginMaterial};

use crate::lanes::Lanes4;

/// What a stress update reports besides the new stress (of one point, or
/// of four in lanes with `T = F4`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PointUpdate<T = f64> {
    /// Increment of the through-thickness (normal) strain that keeps σ_zz = 0 (-).
    pub deps_zz: T,
    /// Plastic dissipation increment per unit volume (MPa = mJ/mm³).
    pub dissipation: T,
}

/// A point history as a fixed number of `f64`s, to save it and read it back
/// exactly (forming in stages).
pub trait HistoryWords: Sized {
    /// Numbers per history.
    const WORDS: usize;
    /// Push the history's [`HistoryWords::WORDS`] numbers to `out`.
    fn write_words(&self, out: &mut Vec<f64>);
    /// The history from its numbers (`words.len() == WORDS`).
    fn read_words(words: &[f64]) -> Self;
}

/// A plane-stress constitutive model, evaluated in the element's co-rotational frame.
///
/// Stresses are `[σ_xx, σ_yy, σ_xy]` (MPa, tensor shear); strain increments
/// are `[Δε_xx, Δε_yy, Δγ_xy]` (engineering shear). Implementations keep
/// `σ_zz = 0` exactly (to the tolerance of their local iteration) and return
/// the thickness-strain increment that goes with it.
pub trait Material: Clone + Send + Sync + 'static {
    /// The state a point carries between steps (plastic strain, back stress, …).
    type History: Copy + Send + Sync + std::fmt::Debug + HistoryWords + 'static;

    /// Short name used in reports (e.g. `j2-swift`).
    fn name(&self) -> &'static str;
    /// Mass density (tonne/mm³).
    fn density(&self) -> f64;
    /// Young's modulus E (MPa), used for wave speeds and hourglass stiffness.
    fn young(&self) -> f64;
    /// Poisson's ratio ν (-).
    fn poisson(&self) -> f64;
    /// Shear modulus G = E / (2(1+ν)) (MPa).
    fn shear_modulus(&self) -> f64 {
        self.young() / (2.0 * (1.0 + self.poisson()))
    }
    /// The history of a virgin point.
    fn initial_history(&self) -> Self::History;
    /// Update `stress` and `history` for the strain increment `deps`.
    fn update(
        &self,
        stress: &mut [f64; 3],
        history: &mut Self::History,
        deps: [f64; 3],
    ) -> PointUpdate;
    /// Update the `N` points of one section (`deps[k]` for point `k`); by
    /// default one after the other. Same contract as [`Material::update`].
    #[inline(always)]
    fn update_points<const N: usize>(
        &self,
        stress: &mut [[f64; 3]; N],
        history: &mut [Self::History; N],
        deps: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        std::array::from_fn(|k| self.update(&mut stress[k], &mut history[k], deps[k]))
    }
    /// The `N` points of one section of four elements at once, element `l`
    /// in lane `l` of the stresses and increments and in `history[l]`
    /// (the shell set's own layout). By default lane by lane through
    /// [`Material::update_points`]; a material that overrides it must give
    /// each lane that result to rounding (the element kernels' four-lane
    /// path is tested against the one-element path within 1e-12 of each
    /// quantity's scale).
    #[inline(always)]
    fn update_points_x4<L: Lanes4, const N: usize>(
        &self,
        stress: &mut [[L; 3]; N],
        history: &mut [[Self::History; N]; 4],
        deps: &[[L; 3]; N],
    ) -> [PointUpdate<L>; N] {
        update_points_by_lane(self, stress, history, deps)
    }
    /// The algorithmic (consistent) tangent `∂σ_{n+1}/∂Δε` of
    /// [`Material::update`] from the committed `stress` and `history` for
    /// the increment `deps`: row `i`, column `j` is `∂σ_i/∂Δε_j` (MPa; the
    /// same component order as `update`, tensor shear stress against
    /// engineering shear strain). The static solver's Newton iterations
    /// need it; the explicit step never calls it.
    ///
    /// By default central finite differences of `update` (step
    /// [`TANGENT_FD_STEP`]), which any material satisfies; a material with
    /// a closed-form tangent overrides it (the tests check each override
    /// against these differences).
    fn consistent_tangent(
        &self,
        stress: &[f64; 3],
        history: &Self::History,
        deps: [f64; 3],
    ) -> [[f64; 3]; 3] {
        finite_difference_tangent(self, stress, history, deps)
    }
    /// Equivalent plastic strain of a point (-).
    fn plastic_strain(&self, history: &Self::History) -> f64;
    /// Current flow (yield) stress of a point (MPa).
    fn flow_stress(&self, history: &Self::History) -> f64;
    /// Equivalent (von Mises or the model's own) stress of a plane-stress state (MPa).
    fn equivalent_stress(&self, stress: &[f64; 3]) -> f64 {
        von_mises(stress)
    }
    /// The message of a failure inside the material since the last call
    /// (a user material's plugin that panicked or returned NaN), clearing
    /// it; the shell set asks after every element loop and stops the run.
    /// Built-in materials cannot fail and keep the default, `None`.
    #[inline(always)]
    fn take_failure(&self) -> Option<String> {
        None
    }
}

/// [`Material::update_points_x4`] lane by lane through [`Material::update_points`].
#[inline(always)]
pub fn update_points_by_lane<M: Material, L: Lanes4, const N: usize>(
    mat: &M,
    stress: &mut [[L; 3]; N],
    history: &mut [[M::History; N]; 4],
    deps: &[[L; 3]; N],
) -> [PointUpdate<L>; N] {
    let mut st = stress.map(|p| p.map(|c| c.to_array()));
    let de = deps.map(|p| p.map(|c| c.to_array()));
    let mut out = [PointUpdate::<[f64; 4]>::default(); N];
    for (l, h) in history.iter_mut().enumerate() {
        let mut s: [[f64; 3]; N] = std::array::from_fn(|p| st[p].map(|c| c[l]));
        let d: [[f64; 3]; N] = std::array::from_fn(|p| de[p].map(|c| c[l]));
        let u = mat.update_points(&mut s, h, &d);
        for p in 0..N {
            for c in 0..3 {
                st[p][c][l] = s[p][c];
            }
            out[p].deps_zz[l] = u[p].deps_zz;
            out[p].dissipation[l] = u[p].dissipation;
        }
    }
    *stress = st.map(|p| p.map(L::from_array));
    out.map(|u| PointUpdate {
        deps_zz: L::from_array(u.deps_zz),
        dissipation: L::from_array(u.dissipation),
    })
}

/// Strain step of the finite-difference tangent (-): small against the
/// strain increments of a Newton iteration (1e-5 and more), large against
/// the rounding of a stress update (1e-16 relative).
pub const TANGENT_FD_STEP: f64 = 1.0e-8;

/// `∂σ/∂Δε` of `mat.update` by central differences with step
/// [`TANGENT_FD_STEP`] (the default [`Material::consistent_tangent`]).
pub fn finite_difference_tangent<M: Material>(
    mat: &M,
    stress: &[f64; 3],
    history: &M::History,
    deps: [f64; 3],
) -> [[f64; 3]; 3] {
    let h = TANGENT_FD_STEP;
    let at = |d: [f64; 3]| {
        let (mut s, mut hist) = (*stress, *history);
        mat.update(&mut s, &mut hist, d);
        s
    };
    let mut c = [[0.0; 3]; 3];
    for j in 0..3 {
        let (mut up, mut down) = (deps, deps);
        up[j] += h;
        down[j] -= h;
        let (su, sd) = (at(up), at(down));
        for i in 0..3 {
            c[i][j] = (su[i] - sd[i]) / (2.0 * h);
        }
    }
    c
}

/// The isotropic plane-stress elasticity `C` of Young's modulus `young`
/// (MPa) and Poisson's ratio `poisson` (-): `σ = C ε`, tensor shear stress
/// against engineering shear strain, `C = E/(1−ν²) [[1, ν, 0], [ν, 1, 0],
/// [0, 0, (1−ν)/2]]` (the `(3, 3)` entry written as `G = E/(2(1+ν))`). The
/// tangent of every elastic step of the built-in materials.
pub fn plane_stress_elasticity(young: f64, poisson: f64) -> [[f64; 3]; 3] {
    let c11 = young / (1.0 - poisson * poisson);
    let c12 = poisson * c11;
    let g = young / (2.0 * (1.0 + poisson));
    [[c11, c12, 0.0], [c12, c11, 0.0], [0.0, 0.0, g]]
}

/// Von Mises stress of a plane-stress state `[σ_xx, σ_yy, σ_xy]` (MPa).
#[inline]
pub fn von_mises(s: &[f64; 3]) -> f64 {
    (s[0] * s[0] + s[1] * s[1] - s[0] * s[1] + 3.0 * s[2] * s[2]).sqrt()
}
