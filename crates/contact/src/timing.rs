//! Wall-clock seconds contact spends per stage of its step.

/// Seconds spent per stage of the contact step, summed over the steps
/// (wall clock, [`std::time::Instant`] read at the stage boundaries only).
///
/// A [`crate::ContactPair`] fills the stages of its own step
/// (`broad_phase` … `scatter`); [`crate::ContactEffect::timing`] adds its
/// pairs' together with its own `geometry`. The press is a stage of the
/// solver's step, timed there (`fem_core::StepTiming::press`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactTiming {
    /// The blank's nodal geometry update (areas, normals, gradients the laws read) (s).
    pub geometry: f64,
    /// Candidate selection: bounding-box margin and far-node skipping (pair step 1a, `stages::broad_phase`) (s).
    pub broad_phase: f64,
    /// Projecting the candidates on the tool (pair step 1b, `stages::narrow_phase`) (s).
    pub projection: f64,
    /// Gap, penalty pressure, gathering the touching points (pair step 1c, `stages::normal`) (s).
    pub normal: f64,
    /// The friction law's batch return mapping (pair step 2, `stages::friction`) (s).
    pub friction: f64,
    /// Scattering forces, reactions and energies (pair step 3, `stages::scatter`) (s).
    pub scatter: f64,
}

impl ContactTiming {
    /// Stage-wise sum.
    pub fn add(&mut self, o: &ContactTiming) {
        self.geometry += o.geometry;
        self.broad_phase += o.broad_phase;
        self.projection += o.projection;
        self.normal += o.normal;
        self.friction += o.friction;
        self.scatter += o.scatter;
    }

    /// Sum of the stages (s).
    pub fn sum(&self) -> f64 {
        self.geometry
            + self.broad_phase
            + self.projection
            + self.normal
            + self.friction
            + self.scatter
    }

    /// The stages as `(name, seconds)`, in the order of the step.
    pub fn stages(&self) -> [(&'static str, f64); 6] {
        [
            ("geometry", self.geometry),
            ("broad_phase", self.broad_phase),
            ("projection", self.projection),
            ("normal", self.normal),
            ("friction", self.friction),
            ("scatter", self.scatter),
        ]
    }
}
