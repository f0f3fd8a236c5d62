//! Solver settings: time-step safety factor, mass scaling, dynamic-relaxation damping, time-step bounds, a fixed step.

use crate::FemError;

/// Settings of the explicit [`Solver`](crate::Solver).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Factor applied to the smallest stable time step of the effects (-), in `(0, 1]`; default 0.9.
    pub safety_factor: f64,
    /// Fixed-time-step mass scaling: the time step to run at (s, safety
    /// factor included). Effects add mass to every element whose
    /// `safety_factor × stable dt` falls below it, at set-up and again during
    /// the run whenever needed (then to 2 % above the target, see
    /// [`MASS_SCALING_HEADROOM`](crate::solver::MASS_SCALING_HEADROOM)); the step is then
    /// `min(target, safety × stable dt)`.
    /// `None`: no mass scaling.
    pub mass_scaling_dt: Option<f64>,
    /// How mass is added to reach `mass_scaling_dt`: to the lumped masses
    /// (default) or selectively, to the elements' relative motion only.
    pub mass_scaling: MassScaling,
    /// Mass-proportional damping coefficient `c` (1/s) for dynamic relaxation
    /// (nodal damping force `−c m v`, `−c I w`); 0 switches it off. For a
    /// quasi-static answer, about `2 ω₁` (ω₁ the lowest natural circular
    /// frequency) damps the lowest mode critically.
    pub damping: f64,
    /// Upper bound of the time step (s); required when no effect imposes one.
    pub dt_max: Option<f64>,
    /// A fixed time step (s): every step is this long (no safety factor, no
    /// mass scaling), and the run stops with
    /// [`FemError::StepAboveStableLimit`], naming the element or node, at the
    /// first step whose stable limit falls below it. Excludes
    /// `mass_scaling_dt` and `dt_max`. `None`: the step follows the limit.
    pub fixed_dt: Option<f64>,
    /// A run stops with [`FemError::TimeStepCollapse`] when the time step
    /// falls below this fraction of the initial one (-); default 1e-3.
    pub dt_floor_ratio: f64,
}

/// How [`SolverSettings::mass_scaling_dt`] is reached.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MassScaling {
    /// Mass added to the lumped nodal masses: every motion, rigid ones
    /// included, carries it.
    Conventional,
    /// Inertia added to each element's deformation modes only
    /// ([`crate::selective_mass`]), by effects that can
    /// ([`Effect::selective_mass`](crate::Effect::selective_mass)); the
    /// others, and nodes that contact springs stiffen, are scaled
    /// conventionally.
    Selective {
        /// Relative residual `|f − (M + ΔM) a| / |f|` at which a step's mass
        /// solve stops (-), in `(0, 0.1]`.
        tolerance: f64,
    },
}

impl MassScaling {
    /// The selective scaling's default solve tolerance (-).
    pub const DEFAULT_TOLERANCE: f64 = 1e-4;
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            safety_factor: 0.9,
            mass_scaling_dt: None,
            mass_scaling: MassScaling::Conventional,
            damping: 0.0,
            dt_max: None,
            fixed_dt: None,
            dt_floor_ratio: 1e-3,
        }
    }
}

impl SolverSettings {
    /// Check every field's range.
    pub fn validate(&self) -> Result<(), FemError> {
        let bad = |field: &str, value: f64, unit, range| {
            Err(FemError::InvalidParameter {
                field: field.to_string(),
                value,
                unit,
                range,
            })
        };
        if !(self.safety_factor > 0.0 && self.safety_factor <= 1.0) {
            return bad("safety_factor", self.safety_factor, "-", "in (0, 1]");
        }
        if let Some(t) = self.mass_scaling_dt
            && !(t.is_finite() && t > 0.0)
        {
            return bad("mass_scaling_dt", t, "s", "finite and > 0");
        }
        if let MassScaling::Selective { tolerance } = self.mass_scaling {
            if !(tolerance > 0.0 && tolerance <= 0.1) {
                return bad("mass_scaling_tolerance", tolerance, "-", "in (0, 0.1]");
            }
            if self.mass_scaling_dt.is_none() {
                return Err(FemError::InvalidSetup(
                    "selective mass scaling needs `mass_scaling_dt`, the step to reach".into(),
                ));
            }
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return bad("damping", self.damping, "1/s", "finite and >= 0");
        }
        if let Some(t) = self.dt_max
            && !(t.is_finite() && t > 0.0)
        {
            return bad("dt_max", t, "s", "finite and > 0");
        }
        if let Some(t) = self.fixed_dt {
            if !(t.is_finite() && t > 0.0) {
                return bad("fixed_dt", t, "s", "finite and > 0");
            }
            if self.mass_scaling_dt.is_some() || self.dt_max.is_some() {
                return Err(FemError::InvalidSetup(
                    "`fixed_dt` excludes `mass_scaling_dt` and `dt_max`".into(),
                ));
            }
        }
        if !(self.dt_floor_ratio >= 0.0 && self.dt_floor_ratio < 1.0) {
            return bad("dt_floor_ratio", self.dt_floor_ratio, "-", "in [0, 1)");
        }
        Ok(())
    }
}
