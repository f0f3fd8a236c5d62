//! The shared return mapping of friction-math §2 for every isotropic law, with
//! consistent tangents, and the per-point state it updates.
//!
//! Stick/slip split with the stick stiffness `k_T`: trial `t_tr = t* - k_T Δu_T`,
//! stick if `|t_tr| ≤ τ_c`, otherwise radial return `t = τ φ_tr`. Laws whose `τ_c`
//! depends on the frictional work `ω` are integrated by backward Euler: the scalar
//! equation `f(Δγ) = |t_tr| - k_T Δγ - τ_c(p, ω_n + c τ Δγ) = 0`, `τ = |t_tr| - k_T Δγ`,
//! is solved by Newton's method safeguarded by bisection on the bracket
//! `[0, |t_tr|/k_T]` (where `f(0) > 0 ≥ f(|t_tr|/k_T)`). Here `c = φ_tr·d ∈ (0, 1]`
//! is the share of the slip along the traction, so that `ΔD = t·(-Δu_sl) = c τ Δγ`.

use crate::kinematics::tangent_projector;
use crate::{
    DirectionInputs, FrictionError, FrictionLaw, KinematicFormulation, Mat3, PointNeeds,
    ShearInputs, StepKinematics, Vec3,
};

/// Which tangent `∂t/∂Δu_T` the return mapping computes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TangentMode {
    /// No tangent (explicit dynamics needs none): cheapest.
    #[default]
    None,
    /// The consistent tangent of §2 (slip direction frozen over the linearisation).
    Consistent,
    /// Fig. 2.3's non-consistent simplification: `∂t/∂Δu_T = 0` in slip.
    Simplified,
}

/// History of one contact point between steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointState {
    /// Friction traction `t_n` on the blank (MPa), tangent to the last normal.
    pub t: Vec3,
    /// Pressure at the last step (MPa).
    pub p: f64,
    /// Frictional work density `ω` (N/mm): the running sum of `ΔD` (eqs. 2.18, 3.21).
    pub omega: f64,
}

impl Default for PointState {
    fn default() -> Self {
        Self { t: Vec3::zeros(), p: 0.0, omega: 0.0 }
    }
}

/// The data of one step at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepInput {
    /// Contact pressure at `n+1` (MPa), `≥ 0`; `0` means open contact.
    pub p: f64,
    /// Slip increment `Δu_T` of the step (mm); projected onto the tangent plane.
    pub du: Vec3,
    /// Kinematics of the step.
    pub kin: StepKinematics,
    /// Blank flow stress (MPa), read only by laws that need it.
    pub flow_stress: f64,
    /// Temperature (K), read only by laws that need it.
    pub temperature: f64,
}

impl StepInput {
    /// A step with no flow-stress or temperature data.
    #[must_use]
    pub fn new(p: f64, du: Vec3, kin: StepKinematics) -> Self {
        Self { p, du, kin, flow_stress: f64::NAN, temperature: f64::NAN }
    }
}

/// The result of one step at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOutput {
    /// Friction traction `t_{n+1}` on the blank (MPa).
    pub t: Vec3,
    /// Critical shear stress at the end of the step (MPa).
    pub tau_c: f64,
    /// Open contact (`p = 0`): traction zero, history cleared.
    pub open: bool,
    /// Stick (`Φ(t_tr) ≤ 0`).
    pub stick: bool,
    /// Slip multiplier `Δγ ≥ 0` (mm).
    pub dgamma: f64,
    /// Slip increment `Δu_sl = -Δγ d` (mm).
    pub slip: Vec3,
    /// Dissipation of the step per unit area `ΔD ≥ 0` (N/mm).
    pub dissipation: f64,
    /// `∂t/∂Δu_T` (MPa/mm) as chosen by [`TangentMode`]; zero for `None`.
    pub tangent: Mat3,
    /// `∂t/∂p` (-) as chosen by [`TangentMode`]; zero for `None`.
    pub dt_dp: Vec3,
    /// Whether a lower clamp of the law was active.
    pub clamped: bool,
}

impl Default for StepOutput {
    fn default() -> Self {
        Self {
            t: Vec3::zeros(),
            tau_c: 0.0,
            open: false,
            stick: false,
            dgamma: 0.0,
            slip: Vec3::zeros(),
            dissipation: 0.0,
            tangent: Mat3::zeros(),
            dt_dp: Vec3::zeros(),
            clamped: false,
        }
    }
}

fn check_vec(field: &'static str, unit: &'static str, v: &Vec3) -> Result<(), FrictionError> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(&bad) => Err(FrictionError::InvalidInput { field, value: bad, unit, reason: "not finite" }),
        None => Ok(()),
    }
}

fn check_input(input: &StepInput, needs: PointNeeds) -> Result<(), FrictionError> {
    if !input.p.is_finite() {
        return Err(FrictionError::InvalidInput { field: "p", value: input.p, unit: "MPa", reason: "not finite" });
    }
    if input.p < 0.0 {
        return Err(FrictionError::InvalidInput {
            field: "p",
            value: input.p,
            unit: "MPa",
            reason: "contact pressure must be >= 0 (0 = open contact)",
        });
    }
    if !(input.kin.dt.is_finite() && input.kin.dt > 0.0) {
        return Err(FrictionError::InvalidInput { field: "dt", value: input.kin.dt, unit: "s", reason: "time step must be finite and > 0" });
    }
    check_vec("du", "mm", &input.du)?;
    check_vec("n", "-", &input.kin.n_new)?;
    check_vec("n_old", "-", &input.kin.n_old)?;
    for (field, n) in [("n", &input.kin.n_new), ("n_old", &input.kin.n_old)] {
        let len = n.norm();
        if (len - 1.0).abs() > 1e-6 {
            return Err(FrictionError::InvalidInput { field, value: len, unit: "-", reason: "normal must be a unit vector (|n| = 1 within 1e-6)" });
        }
    }
    if needs.contains(PointNeeds::FLOW_STRESS) && !(input.flow_stress.is_finite() && input.flow_stress > 0.0) {
        return Err(FrictionError::InvalidInput { field: "sigma_y", value: input.flow_stress, unit: "MPa", reason: "the law needs the blank flow stress: finite and > 0" });
    }
    if needs.contains(PointNeeds::TEMPERATURE) && !(input.temperature.is_finite() && input.temperature > 0.0) {
        return Err(FrictionError::InvalidInput { field: "temperature", value: input.temperature, unit: "K", reason: "the law needs the temperature: finite and > 0" });
    }
    let mats = [
        (PointNeeds::SPIN.union(PointNeeds::VELOCITY_GRADIENT), "L", &input.kin.vel_grad),
        (PointNeeds::DEFORMATION_GRADIENT, "F_old", &input.kin.f_old),
        (PointNeeds::DEFORMATION_GRADIENT, "F", &input.kin.f_new),
        (PointNeeds::TOOL_ROTATION, "tool_rotation", &input.kin.tool_rotation),
    ];
    for (flag, field, m) in mats {
        if (needs.0 & flag.0) != 0 {
            if let Some(&bad) = m.iter().find(|x| !x.is_finite()) {
                return Err(FrictionError::InvalidInput { field, value: bad, unit: "-", reason: "not finite" });
            }
        }
    }
    Ok(())
}

#[inline]
fn evaluate<L: FrictionLaw + ?Sized>(law: &L, x: &ShearInputs) -> Result<crate::CriticalShear, FrictionError> {
    let cs = law.critical_shear(x);
    let bad = [cs.tau, cs.dtau_dp, cs.dtau_domega, cs.dtau_dspeed].into_iter().find(|v| !v.is_finite());
    if let Some(value) = bad {
        return Err(FrictionError::NonFiniteResult { component: law.name().to_string(), what: "critical shear stress or derivative", value, p: x.p });
    }
    if cs.tau < 0.0 {
        return Err(FrictionError::NonFiniteResult { component: law.name().to_string(), what: "negative critical shear stress", value: cs.tau, p: x.p });
    }
    Ok(cs)
}

/// Integrate one contact point over one step (friction-math §2) and update its state.
///
/// # Errors
/// Non-finite or out-of-domain input ([`FrictionError::InvalidInput`]); a law
/// returning a non-finite or negative `τ_c` ([`FrictionError::NonFiniteResult`]).
/// On error the state is left unchanged.
pub fn step<L, F>(
    law: &L,
    formulation: &F,
    tangent_mode: TangentMode,
    state: &mut PointState,
    input: &StepInput,
) -> Result<StepOutput, FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    let needs = law.needs().union(formulation.needs());
    check_input(input, needs)?;
    let kin = &input.kin;
    let n = kin.n_new.normalize();
    let p = input.p;
    let mut out = StepOutput::default();

    if p == 0.0 {
        // Open contact: no traction, history cleared, internal variables kept.
        state.t = Vec3::zeros();
        state.p = 0.0;
        out.open = true;
        return Ok(out);
    }

    let k_t = law.stick_stiffness();
    let project = |v: Vec3| v - n * n.dot(&v);
    let t_star = if state.t == Vec3::zeros() {
        Vec3::zeros()
    } else {
        project(formulation.transport(&state.t, kin))
    };
    check_vec("transported traction", "MPa", &t_star).map_err(|_| FrictionError::NonFiniteResult {
        component: formulation.name().to_string(),
        what: "transported traction",
        value: f64::NAN,
        p,
    })?;
    let du_t = project(input.du);
    let t_tr = t_star - du_t * k_t;
    let norm_tr = t_tr.norm();
    let du_norm = du_t.norm();
    let sliding_speed = if needs.contains(PointNeeds::SLIDING_VELOCITY) { du_norm / kin.dt } else { f64::NAN };
    let mut x = ShearInputs { p, omega: state.omega, sliding_speed, flow_stress: input.flow_stress, temperature: input.temperature };
    let cs = evaluate(law, &x)?;

    if norm_tr <= cs.tau || norm_tr == 0.0 {
        out.t = t_tr;
        out.tau_c = cs.tau;
        out.stick = true;
        out.clamped = cs.clamped;
        if tangent_mode != TangentMode::None {
            out.tangent = -k_t * tangent_projector(&n);
        }
        state.t = t_tr;
        state.p = p;
        return Ok(out);
    }

    // Slip.
    let phi = t_tr / norm_tr;
    let d = formulation
        .slip_direction(&DirectionInputs { kin, t_old: state.t, p_old: state.p, t_trial: t_tr, p_new: p })
        .and_then(|d| {
            let d = project(d);
            let len = d.norm();
            (len.is_finite() && len > 0.0).then(|| d / len)
        })
        .filter(|d| d.dot(&phi) > 0.0)
        .unwrap_or(phi);
    let c = d.dot(&phi).clamp(0.0, 1.0);

    let (dgamma, tau, cs_end) = if law.work_dependent() {
        solve_work_dependent(law, &mut x, state.omega, norm_tr, k_t, c, cs)?
    } else {
        ((norm_tr - cs.tau) / k_t, cs.tau, cs)
    };

    let dissipation = c * tau * dgamma;
    out.t = phi * tau;
    out.tau_c = cs_end.tau;
    out.dgamma = dgamma;
    out.slip = -dgamma * d;
    out.dissipation = dissipation;
    out.clamped = cs_end.clamped;

    match tangent_mode {
        TangentMode::None => {}
        TangentMode::Simplified => {
            out.dt_dp = phi * cs_end.dtau_dp;
        }
        TangentMode::Consistent => {
            let tau_w = cs_end.dtau_domega;
            let f_dg = -k_t - tau_w * c * (norm_tr - 2.0 * k_t * dgamma);
            let dgamma_dnorm = -(1.0 - tau_w * c * dgamma) / f_dg;
            let dtau_dnorm = 1.0 - k_t * dgamma_dnorm;
            let dtau_dp = -k_t * cs_end.dtau_dp / f_dg;
            let dtau_dv = -k_t * cs_end.dtau_dspeed / f_dg;
            let pp = phi * phi.transpose();
            let mut tangent = -k_t * ((tau / norm_tr) * (tangent_projector(&n) - pp) + dtau_dnorm * pp);
            if dtau_dv != 0.0 && du_norm > 0.0 {
                tangent += phi * (du_t / (du_norm * kin.dt)).transpose() * dtau_dv;
            }
            out.tangent = tangent;
            out.dt_dp = phi * dtau_dp;
        }
    }

    state.t = out.t;
    state.p = p;
    state.omega += dissipation;
    Ok(out)
}

/// Backward-Euler slip of a work-dependent law: returns `(Δγ, τ, τ_c(ω_{n+1}))`.
fn solve_work_dependent<L: FrictionLaw + ?Sized>(
    law: &L,
    x: &mut ShearInputs,
    omega_n: f64,
    norm_tr: f64,
    k_t: f64,
    c: f64,
    cs_n: crate::CriticalShear,
) -> Result<(f64, f64, crate::CriticalShear), FrictionError> {
    let residual = |x: &mut ShearInputs, dg: f64| -> Result<(f64, f64, crate::CriticalShear), FrictionError> {
        let tau = norm_tr - k_t * dg;
        x.omega = omega_n + c * tau * dg;
        let cs = evaluate(law, x)?;
        let f = tau - cs.tau;
        let df = -k_t - cs.dtau_domega * c * (norm_tr - 2.0 * k_t * dg);
        Ok((f, df, cs))
    };
    let mut lo = 0.0;
    let mut hi = norm_tr / k_t;
    let mut dg = ((norm_tr - cs_n.tau) / k_t).clamp(lo, hi);
    let tol = 1e-15 * norm_tr.max(f64::MIN_POSITIVE);
    let mut last = cs_n;
    for _ in 0..200 {
        let (f, df, cs) = residual(x, dg)?;
        last = cs;
        if f.abs() <= tol {
            break;
        }
        if f > 0.0 {
            lo = dg;
        } else {
            hi = dg;
        }
        let newton = dg - f / df;
        dg = if df != 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
    }
    // Enforce |t| = τ_c(ω_{n+1}) exactly: the traction takes the law's value at the
    // converged work, and Δγ follows from it.
    let tau = last.tau.min(norm_tr);
    let dgamma = (norm_tr - tau) / k_t;
    x.omega = omega_n + c * tau * dgamma;
    Ok((dgamma, tau, last))
}

/// A law paired with a formulation: the unit the engine drives per batch of
/// contact points. Dynamic dispatch happens once per batch, through this trait;
/// inside, [`PairedIntegrator`] is monomorphised over the concrete pair.
pub trait PointIntegrator: Send + Sync {
    /// Law name.
    fn law_name(&self) -> &str;
    /// Formulation name.
    fn formulation_name(&self) -> &str;
    /// Union of what the law and the formulation read (§6).
    fn needs(&self) -> PointNeeds;
    /// Tangential stiffness in stick of the law (MPa/mm).
    fn stick_stiffness(&self) -> f64;
    /// One step at one point.
    ///
    /// # Errors
    /// As [`step`].
    fn step(&self, state: &mut PointState, input: &StepInput) -> Result<StepOutput, FrictionError>;
    /// One step at many points; `states`, `inputs`, `outputs` have equal lengths.
    ///
    /// # Errors
    /// The first point's error, with the points before it already updated.
    fn step_batch(&self, states: &mut [PointState], inputs: &[StepInput], outputs: &mut [StepOutput]) -> Result<(), FrictionError>;
}

/// A concrete law-and-formulation pair with its tangent mode.
#[derive(Clone, Debug)]
pub struct PairedIntegrator<L, F> {
    /// The friction law.
    pub law: L,
    /// The kinematic formulation.
    pub formulation: F,
    /// Which tangent to compute.
    pub tangent: TangentMode,
}

impl<L: FrictionLaw, F: KinematicFormulation> PairedIntegrator<L, F> {
    /// Pair `law` and `formulation` without tangents (explicit dynamics).
    pub fn new(law: L, formulation: F) -> Self {
        Self { law, formulation, tangent: TangentMode::None }
    }
}

impl<L: FrictionLaw, F: KinematicFormulation> PointIntegrator for PairedIntegrator<L, F> {
    fn law_name(&self) -> &str {
        self.law.name()
    }
    fn formulation_name(&self) -> &str {
        self.formulation.name()
    }
    fn needs(&self) -> PointNeeds {
        self.law.needs().union(self.formulation.needs())
    }
    fn stick_stiffness(&self) -> f64 {
        self.law.stick_stiffness()
    }
    #[inline]
    fn step(&self, state: &mut PointState, input: &StepInput) -> Result<StepOutput, FrictionError> {
        step(&self.law, &self.formulation, self.tangent, state, input)
    }
    fn step_batch(&self, states: &mut [PointState], inputs: &[StepInput], outputs: &mut [StepOutput]) -> Result<(), FrictionError> {
        for ((state, input), output) in states.iter_mut().zip(inputs).zip(outputs.iter_mut()) {
            *output = step(&self.law, &self.formulation, self.tangent, state, input)?;
        }
        Ok(())
    }
}
