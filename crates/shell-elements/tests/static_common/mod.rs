//! Shared helpers of the static-shell tests: materials, a trial state, a
//! strip clamped at one end, solver settings.
#![allow(dead_code)]

use fem_core::statics::TrialState;
use fem_core::{Mat3, Vec3};
use shell_elements::{Hardening, J2PlaneStress, Section};

/// Elastic material (flow stress 1e30 MPa), density of steel.
pub fn elastic(e: f64, nu: f64) -> J2PlaneStress {
    J2PlaneStress::new(e, nu, 7.85e-9, Hardening::swift(1e30, 1.0, 0.0).unwrap()).unwrap()
}

/// Mild steel: J2 with Swift hardening `σ_y = 565.32 (0.007117 + ε_p)^0.2589` MPa.
pub fn steel() -> J2PlaneStress {
    J2PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap()
}

/// The buffers of a trial state (the solver's, for tests that drive an
/// effect by hand): committed rotations are the identity.
pub struct Trial {
    pub x_start: Vec<Vec3>,
    pub x_committed: Vec<Vec3>,
    pub x: Vec<Vec3>,
    pub rotations: Vec<Mat3>,
    pub dtheta: Vec<Vec3>,
}

impl Trial {
    /// At rest at `x`.
    pub fn at(x: &[Vec3]) -> Self {
        Self {
            x_start: x.to_vec(),
            x_committed: x.to_vec(),
            x: x.to_vec(),
            rotations: vec![Mat3::identity(); x.len()],
            dtheta: vec![Vec3::zeros(); x.len()],
        }
    }

    /// The state as the effect sees it.
    pub fn state(&self) -> TrialState<'_> {
        TrialState {
            x_start: &self.x_start,
            x_committed: &self.x_committed,
            x: &self.x,
            rotation_committed: &self.rotations,
            dtheta: &self.dtheta,
            lambda: 1.0,
        }
    }

    /// Accept the trial state as committed (positions; the rotation
    /// increments restart from zero).
    pub fn commit(&mut self) {
        self.x_committed.clone_from(&self.x);
        self.dtheta.iter_mut().for_each(|d| *d = Vec3::zeros());
    }
}

/// A section of thickness `t` (mm) with `n` Gauss points.
pub fn section(t: f64, n: usize) -> Section {
    Section::new(t)
        .unwrap()
        .with_rule(shell_elements::RuleKind::Gauss, n)
        .unwrap()
}
