//! Point data a law or formulation declares it reads (friction-math §6).

/// A set of point quantities, beyond pressure and slip increment, that a
/// component needs. The engine computes only the union of what the active
/// components declare; everything else is left at a neutral value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PointNeeds(pub u32);

impl PointNeeds {
    /// Nothing beyond pressure, slip increment and the tool normals.
    pub const NONE: Self = Self(0);
    /// Sliding speed `|Δu_T|/Δt` (mm/s).
    pub const SLIDING_VELOCITY: Self = Self(1);
    /// Current flow stress of the blank at the point (MPa).
    pub const FLOW_STRESS: Self = Self(1 << 1);
    /// Temperature at the point (K).
    pub const TEMPERATURE: Self = Self(1 << 2);
    /// Blank spin `W` (skew part of the velocity gradient, 1/s).
    pub const SPIN: Self = Self(1 << 3);
    /// Blank velocity gradient `L` at mid-step (1/s).
    pub const VELOCITY_GRADIENT: Self = Self(1 << 4);
    /// Blank total deformation gradient `F` at both ends of the step.
    pub const DEFORMATION_GRADIENT: Self = Self(1 << 5);
    /// Rigid rotation of the tool over the step.
    pub const TOOL_ROTATION: Self = Self(1 << 6);

    const NAMES: [(Self, &'static str); 7] = [
        (Self::SLIDING_VELOCITY, "sliding_velocity"),
        (Self::FLOW_STRESS, "flow_stress"),
        (Self::TEMPERATURE, "temperature"),
        (Self::SPIN, "spin"),
        (Self::VELOCITY_GRADIENT, "velocity_gradient"),
        (Self::DEFORMATION_GRADIENT, "deformation_gradient"),
        (Self::TOOL_ROTATION, "tool_rotation"),
    ];

    /// Union of two sets.
    #[must_use]
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Whether every quantity of `other` is in `self`.
    #[must_use]
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Whether the set is empty.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Names of the quantities in the set, for reports.
    #[must_use]
    pub fn names(self) -> Vec<&'static str> {
        Self::NAMES
            .iter()
            .filter(|(flag, _)| self.contains(*flag))
            .map(|(_, name)| *name)
            .collect()
    }
}

impl std::ops::BitOr for PointNeeds {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        self.union(rhs)
    }
}

impl std::fmt::Display for PointNeeds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names = self.names();
        if names.is_empty() {
            write!(f, "pressure and slip only")
        } else {
            write!(f, "{}", names.join(", "))
        }
    }
}
