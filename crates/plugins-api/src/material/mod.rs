//! User materials: the plane-stress constitutive contract that a dynamic
//! material plugin implements, its versioned C-ABI table ([`abi`]), the host
//! side that loads and calls it ([`loader`]), and the conformance suite that
//! `formsim plugin check` runs on it ([`conformance`]).
//!
//! # The contract (what Abaqus users know as a VUMAT, LS-DYNA users as a umat)
//!
//! At every integration point of a shell, once per explicit step, the engine
//! hands the material, in the element's **co-rotational frame**:
//!
//! - the strain increment `[Δε_xx, Δε_yy, Δγ_xy]` (engineering shear, -);
//! - the stress at the start of the step `[σ_xx, σ_yy, σ_xy]` (MPa, plane
//!   stress, tensor shear);
//! - the point's state variables, as many as the material declares
//!   ([`UserMaterial::N_STATE`], at most [`MAX_STATE`]).
//!
//! It returns the stress at the end of the step, the new state variables,
//! and a [`PointResult`]: the through-thickness strain increment that keeps
//! `σ_zz = 0`, the plastic dissipation per unit volume of the step (MPa =
//! mJ/mm³, ≥ 0), the equivalent plastic strain and the flow stress (for
//! reports and for friction laws that read the blank's flow stress).
//!
//! **Rotation.** The frame turns with the element, so the stress and the
//! increment arrive already expressed in the rotated frame: the rigid
//! rotation of the step has been removed before the call and the material
//! must not rotate its stress (as in Abaqus/Explicit's VUMAT). A tensor-valued
//! state variable (a back stress, say) is kept in the same frame. The
//! conformance suite checks both halves: a pure rotation leaves the stress
//! alone (the increment the frame sees is zero), and, for a material that
//! declares itself isotropic, turning a whole loading history by a rigid
//! in-plane angle turns its stresses by that angle.
//!
//! **Batches.** The engine calls the material with many points at once
//! (four elements × every through-thickness point of one in-plane point), so
//! the cost of the call through the table is shared; the points are
//! independent.
//!
//! **Units.** mm, N, MPa, tonne, s: the elastic constants are MPa and
//! tonne/mm³.

pub mod abi;
pub mod conformance;
pub mod loader;

use crate::ParamSpec;

/// The most state variables per point a user material may declare (the
/// engine keeps them in a fixed-size array, so that the element loop does not
/// allocate).
pub const MAX_STATE: usize = 16;

/// A material's elastic constants and density, which the engine needs for
/// wave speeds (the stable time step), hourglass control and masses.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Elastic {
    /// Young's modulus E (MPa).
    pub young: f64,
    /// Poisson's ratio ν (-).
    pub poisson: f64,
    /// Mass density (tonne/mm³).
    pub density: f64,
}

impl Elastic {
    /// Check the constants: `E > 0`, `-1 < ν < 0.5`, `ρ > 0`, all finite.
    ///
    /// # Errors
    /// The first constant out of range, with its value and unit.
    pub fn check(&self) -> Result<(), String> {
        let Self {
            young,
            poisson,
            density,
        } = *self;
        if !(young.is_finite() && young > 0.0) {
            return Err(format!(
                "Young's modulus {young} MPa must be finite and > 0"
            ));
        }
        if !(poisson > -1.0 && poisson < 0.5) {
            return Err(format!("Poisson's ratio {poisson} must be in (-1, 0.5)"));
        }
        if !(density.is_finite() && density > 0.0) {
            return Err(format!(
                "density {density} tonne/mm³ must be finite and > 0"
            ));
        }
        Ok(())
    }
}

/// What one point's update returns besides its stress and state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct PointResult {
    /// Through-thickness strain increment that keeps `σ_zz = 0` (-).
    pub deps_zz: f64,
    /// Plastic dissipation of the step per unit volume (MPa = mJ/mm³), ≥ 0.
    pub dissipation: f64,
    /// Equivalent plastic strain after the step (-).
    pub plastic_strain: f64,
    /// Flow stress after the step (MPa): by convention the current yield
    /// stress in uniaxial tension along the frame's x axis (the rolling
    /// direction of an anisotropic sheet); the conformance suite checks it.
    pub flow_stress: f64,
}

/// A plane-stress material that can be exported as a dynamic plugin with
/// [`export_material!`](crate::export_material).
///
/// One value of the type holds the parameters; it is shared by every point
/// and by several threads at once (`update` takes `&self`), the points' state
/// lives in the engine.
pub trait UserMaterial: Send + Sync + Sized + 'static {
    /// Name as typed in scenes: lowercase ASCII letters, digits, `-`, `_`.
    const NAME: &'static str;
    /// One line: the model and its parameters.
    const SUMMARY: &'static str;
    /// Parameter schema; [`Self::from_values`] receives one value per entry, in order.
    const PARAMS: &'static [ParamSpec];
    /// State variables per point (at most [`MAX_STATE`]).
    const N_STATE: usize;
    /// Whether the response is isotropic in the plane (then the conformance
    /// suite checks that a rotated loading history gives rotated stresses).
    const ISOTROPIC: bool;

    /// Build the material from one value per entry of [`Self::PARAMS`],
    /// already range-checked by the host.
    ///
    /// # Errors
    /// A one-line reason naming the parameters of an invalid combination.
    fn from_values(values: &[f64]) -> Result<Self, String>;

    /// Elastic constants and density.
    fn elastic(&self) -> Elastic;

    /// Fill the state of a virgin point (`state.len() == N_STATE`) and
    /// return its flow stress (MPa).
    fn initial_state(&self, state: &mut [f64]) -> f64;

    /// One point's step: `stress` and `state` in at the start, out at the end
    /// (`state.len() == N_STATE`); see the [module docs](self) for frames and
    /// units. Inputs are finite (the shim refuses others before the call).
    ///
    /// # Errors
    /// A one-line reason (e.g. the local iteration did not converge), which
    /// stops the run with the message.
    fn update(
        &self,
        deps: [f64; 3],
        stress: &mut [f64; 3],
        state: &mut [f64],
    ) -> Result<PointResult, String>;
}
