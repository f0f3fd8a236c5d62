//! `AnchorSprings`: linear springs from nodes to an anchor driven at a prescribed speed along one axis (a mass on a spring dragged over a plane).

use crate::springs::{scale_spring_mass, spring_dt};
use crate::{Amplitude, Effect, EnergyTally, FemError, Forces, NodalState, StableDt, StepContext};

/// Springs along one global axis from each node of a set to an anchor that
/// moves along that axis at `speed × A(t)` (mm/s; `A` on absolute time).
///
/// Node `i` feels `f_i = k_i (x_i0 + s(t) − x_i)` along the axis, `x_i0` its
/// coordinate at the start and `s(t) = ∫ speed A dt` the anchor's travel
/// (integrated at mid-step, as a prescribed velocity): the springs are slack
/// at the start. Energies: the stored `½ Σ k_i (x_i0 + s − x_i)²` (internal)
/// and the work the anchor does on the springs, `Σ ½ (F_n + F_{n+1}) Δs`
/// with `F = Σ f_i` (external), so the engine's energy balance closes over
/// them.
///
/// Stable time step and mass scaling as [`crate::Springs`] (Gershgorin:
/// `Δt = √(2 m_i / k_i)`).
#[derive(Debug, Clone)]
pub struct AnchorSprings {
    name: String,
    axis: usize,
    nodes: Vec<u32>,
    k: Vec<f64>,
    x0: Vec<f64>,
    speed: f64,
    amplitude: Option<Amplitude>,
    travel: f64,
    force: f64,
    stored: f64,
    work: f64,
}

impl AnchorSprings {
    /// Springs of total stiffness `stiffness` (N/mm), shared equally by
    /// `nodes`, along global axis `axis` (0, 1, 2), from the nodes' positions
    /// in `x` (the start) to an anchor moving at `speed × A(t)` (mm/s).
    ///
    /// # Errors
    /// An empty set, a node out of range, an axis above 2, a stiffness not
    /// finite and `> 0`, a speed not finite, an invalid amplitude.
    pub fn new(
        name: &str,
        x: &[crate::Vec3],
        nodes: &[u32],
        axis: usize,
        stiffness: f64,
        speed: f64,
        amplitude: Option<Amplitude>,
    ) -> Result<Self, FemError> {
        let bad = |field: &str, value: f64, unit: &'static str, range: &'static str| {
            FemError::InvalidParameter {
                field: format!("{name}.{field}"),
                value,
                unit,
                range,
            }
        };
        if nodes.is_empty() {
            return Err(FemError::InvalidSetup(format!(
                "{name}: the node set is empty"
            )));
        }
        if axis > 2 {
            return Err(bad("axis", axis as f64, "-", "0, 1 or 2 (x, y, z)"));
        }
        if !(stiffness.is_finite() && stiffness > 0.0) {
            return Err(bad("stiffness", stiffness, "N/mm", "> 0 and finite"));
        }
        if !speed.is_finite() {
            return Err(bad("speed", speed, "mm/s", "finite"));
        }
        if let Some(a) = &amplitude {
            a.validate()?;
        }
        let mut x0 = Vec::with_capacity(nodes.len());
        for (e, &n) in nodes.iter().enumerate() {
            let p = x.get(n as usize).ok_or(FemError::NodeOutOfRange {
                element: e,
                node: n as u64,
                n_nodes: x.len(),
            })?;
            x0.push(p[axis]);
        }
        Ok(Self {
            name: name.to_string(),
            axis,
            nodes: nodes.to_vec(),
            k: vec![stiffness / nodes.len() as f64; nodes.len()],
            x0,
            speed,
            amplitude,
            travel: 0.0,
            force: 0.0,
            stored: 0.0,
            work: 0.0,
        })
    }

    /// The anchor's travel so far (mm).
    pub fn travel(&self) -> f64 {
        self.travel
    }

    /// The force the springs pull the nodes with along the axis, summed (N).
    pub fn force(&self) -> f64 {
        self.force
    }
}

impl Effect for AnchorSprings {
    fn name(&self) -> &str {
        &self.name
    }

    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        let mut best: Option<StableDt> = None;
        for (e, (&n, &k)) in self.nodes.iter().zip(&self.k).enumerate() {
            if let Some(dt) = spring_dt(state.mass[n as usize], k)
                && best.is_none_or(|b| dt.is_nan() || dt < b.dt)
            {
                best = Some(StableDt {
                    dt,
                    element: e,
                    what: "anchor spring stiffness vs nodal mass (Gershgorin bound)",
                });
            }
        }
        best
    }

    fn stiffens_nodes(&self) -> bool {
        !self.nodes.is_empty()
    }

    /// `2 k` per spring's node: the Gershgorin bound of `stable_dt` as `2 √(m / s)`.
    fn nodal_stiffness(&self, _state: &NodalState, stiffness: &mut [f64]) {
        for (&n, &k) in self.nodes.iter().zip(&self.k) {
            stiffness[n as usize] += 2.0 * k;
        }
    }

    fn scale_mass(
        &mut self,
        _state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        _inertia: &mut [f64],
    ) -> f64 {
        self.nodes
            .iter()
            .zip(&self.k)
            .map(|(&n, &k)| scale_spring_mass(&mut mass[n as usize], k, target_dt))
            .sum()
    }

    fn add_forces(
        &mut self,
        ctx: &StepContext,
        state: &NodalState,
        forces: &mut Forces,
        _fields: &mut crate::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let a = self
            .amplitude
            .as_ref()
            .map_or(1.0, |a| a.value(ctx.time - 0.5 * ctx.dt));
        let ds = self.speed * a * ctx.dt;
        self.travel += ds;
        let (mut force, mut stored) = (0.0, 0.0);
        for ((&n, &k), &x0) in self.nodes.iter().zip(&self.k).zip(&self.x0) {
            let stretch = x0 + self.travel - state.x[n as usize][self.axis];
            let f = k * stretch;
            forces.f[n as usize][self.axis] += f;
            force += f;
            stored += 0.5 * k * stretch * stretch;
        }
        self.work += 0.5 * (self.force + force) * ds;
        self.force = force;
        self.stored = stored;
        Ok(())
    }

    fn energies(&self) -> EnergyTally {
        EnergyTally {
            internal: self.stored,
            external: self.work,
            ..Default::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Solver, SolverSettings, Vec3};

    /// One free mass on an anchor spring, the anchor dragged at `V` from
    /// rest: `x(t) = V t − (V/ω) sin ωt` (the textbook response to a ramp),
    /// tolerance 1e-3 of `V/ω`; and the energy balance closes to round-off:
    /// its absolute error within 1e-10 of the largest stored energy of the
    /// run (the run ends near a zero of the stored energy, where the
    /// ledger's relative error divides round-off by almost nothing).
    #[test]
    fn mass_on_a_dragged_spring_follows_the_ramp_response() {
        let (m, k, v): (f64, f64, f64) = (2.0e-6, 50.0, 100.0);
        let omega = (k / m).sqrt();
        let settings = SolverSettings {
            dt_max: Some(0.001 / omega),
            ..Default::default()
        };
        let sets = [("all".to_string(), vec![0])].into_iter().collect();
        let mut solver = Solver::from_nodes(&[Vec3::zeros()], sets, settings).unwrap();
        solver.add_point_mass("all", m, 0.0).unwrap();
        let springs = AnchorSprings::new("anchor", &[Vec3::zeros()], &[0], 0, k, v, None).unwrap();
        solver.add_effect(springs);
        let end = 5.0 * std::f64::consts::TAU / omega;
        let mut peak = 0.0f64;
        solver
            .run_until(end, &mut |_, r| {
                peak = peak.max(r.energy.internal);
                crate::Control::Continue
            })
            .unwrap();
        let t = solver.time();
        let exact = v * t - v / omega * (omega * t).sin();
        let x = solver.state().x[0].x;
        assert!((x - exact).abs() < 1e-3 * v / omega, "{x} vs {exact}");
        let l = solver.ledger();
        assert!(l.balance_abs.abs() < 1e-10 * peak, "{l:?}, peak {peak}");
    }
}
