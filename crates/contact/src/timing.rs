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
    /// Placing the tools and updating the blank's nodal geometry (areas,
    /// normals, gradients the laws read) (stage 5a) (s).
    pub geometry: f64,
    /// Candidate selection: bounding-box margin and far-node skipping (stage 5b, `stages::broad_phase`) (s).
    pub broad_phase: f64,
    /// Projecting the candidates on the tool (stage 5c, `stages::narrow_phase`) (s).
    pub projection: f64,
    /// Gap, penalty pressure, gathering the touching points (stage 5d, `stages::normal`) (s).
    pub normal: f64,
    /// The friction law's batch return mapping (stage 5e, `stages::friction`) (s).
    pub friction: f64,
    /// Scattering forces, reactions and energies (stage 5f, `stages::scatter`) (s).
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
