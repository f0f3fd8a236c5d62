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

mod batch;

use crate::kinematics::{is_identity, tangent_part, tangent_projector};
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
        Self {
            t: Vec3::zeros(),
            p: 0.0,
            omega: 0.0,
        }
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
        Self {
            p,
            du,
            kin,
            flow_stress: f64::NAN,
            temperature: f64::NAN,
        }
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

impl StepOutput {
    /// Write every field once: the given values, contact closed, no
    /// tangents (a tangent asked for is written after).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn write(
        &mut self,
        t: Vec3,
        tau_c: f64,
        stick: bool,
        dgamma: f64,
        slip: Vec3,
        dissipation: f64,
        clamped: bool,
    ) {
        *self = StepOutput {
            t,
            tau_c,
            open: false,
            stick,
            dgamma,
            slip,
            dissipation,
            tangent: Mat3::zeros(),
            dt_dp: Vec3::zeros(),
            clamped,
        };
    }

    /// Set every field to its default in place (no temporary, no copy).
    #[inline]
    fn reset(&mut self) {
        self.t.fill(0.0);
        self.tau_c = 0.0;
        self.open = false;
        self.stick = false;
        self.dgamma = 0.0;
        self.slip.fill(0.0);
        self.dissipation = 0.0;
        self.tangent.fill(0.0);
        self.dt_dp.fill(0.0);
        self.clamped = false;
    }
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
        Some(&bad) => Err(FrictionError::InvalidInput {
            field,
            value: bad,
            unit,
            reason: "not finite",
        }),
        None => Ok(()),
    }
}

/// 1 in the top bit for every non-finite `x` (exponent bits all ones), else 0:
/// `(bits & EXP) + 2^52` overflows into bit 63 exactly when the exponent is
/// all ones. An integer OR over a fixed-size array is associative and unrolls.
#[inline(always)]
fn nonfinite_bits<const N: usize>(values: [f64; N]) -> u64 {
    const EXP: u64 = 0x7FF0_0000_0000_0000;
    const ONE: u64 = 0x0010_0000_0000_0000;
    let mut acc = 0;
    for x in values {
        acc |= (x.to_bits() & EXP) + ONE;
    }
    acc
}

/// [`nonfinite_bits`] of the nine entries of a matrix.
#[inline(always)]
fn nonfinite_bits_mat(m: &Mat3) -> u64 {
    let [a, b, c] = m.data.0;
    nonfinite_bits([a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]])
}

/// `0 < x < ∞` (false for NaN): on the bit pattern, `x` positive, non-zero
/// and below `+∞` is `bits - 1 < bits(+∞) - 1` (zero wraps to the top).
#[inline(always)]
fn positive_finite(x: f64) -> bool {
    x.to_bits().wrapping_sub(1) < f64::INFINITY.to_bits() - 1
}

/// `|n|²` of a normal within 1e-6 of unit length (kept slightly inside `2e-6`;
/// false for NaN and infinities, so it also proves the normal finite).
#[inline(always)]
fn unit_norm2(n2: f64) -> bool {
    (n2 - 1.0).abs() <= 1.999e-6
}

/// The one fast validity test of a step's input, folded into values the step
/// computes anyway: pressure `+0 ≤ p < ∞`, `0 < Δt < ∞`, unit normals (`|n|²`,
/// which a NaN or infinity fails), the declared point data (flow stress and
/// temperature finite and `> 0`, matrices finite; a tool rotation that is
/// exactly the identity needs no test). The slip `Δu` is not tested here:
/// a non-finite one makes the trial traction's square norm non-finite, which
/// the step tests. When either test says no, [`check_input`] finds the
/// culprit and words the error.
#[inline(always)]
fn input_ok(input: &StepInput, needs: PointNeeds) -> bool {
    let k = &input.kin;
    let mut bits = 0;
    if (needs.0 & (PointNeeds::SPIN.0 | PointNeeds::VELOCITY_GRADIENT.0)) != 0 {
        bits |= nonfinite_bits_mat(&k.vel_grad);
    }
    if needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
        bits |= nonfinite_bits_mat(&k.f_old) | nonfinite_bits_mat(&k.f_new);
    }
    if needs.contains(PointNeeds::TOOL_ROTATION) && !is_identity(&k.tool_rotation) {
        bits |= nonfinite_bits_mat(&k.tool_rotation);
    }
    (input.p == 0.0 || positive_finite(input.p))
        && positive_finite(k.dt)
        && unit_norm2(k.n_new.norm_squared())
        && unit_norm2(k.n_old.norm_squared())
        && (bits >> 63) == 0
        && (!needs.contains(PointNeeds::FLOW_STRESS) || positive_finite(input.flow_stress))
        && (!needs.contains(PointNeeds::TEMPERATURE) || positive_finite(input.temperature))
}

fn check_input(input: &StepInput, needs: PointNeeds) -> Result<(), FrictionError> {
    if !input.p.is_finite() {
        return Err(FrictionError::InvalidInput {
            field: "p",
            value: input.p,
            unit: "MPa",
            reason: "not finite",
        });
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
        return Err(FrictionError::InvalidInput {
            field: "dt",
            value: input.kin.dt,
            unit: "s",
            reason: "time step must be finite and > 0",
        });
    }
    check_vec("du", "mm", &input.du)?;
    check_vec("n", "-", &input.kin.n_new)?;
    check_vec("n_old", "-", &input.kin.n_old)?;
    for (field, n) in [("n", &input.kin.n_new), ("n_old", &input.kin.n_old)] {
        let len = n.norm();
        if (len - 1.0).abs() > 1e-6 {
            return Err(FrictionError::InvalidInput {
                field,
                value: len,
                unit: "-",
                reason: "normal must be a unit vector (|n| = 1 within 1e-6)",
            });
        }
    }
    if needs.contains(PointNeeds::FLOW_STRESS)
        && !(input.flow_stress.is_finite() && input.flow_stress > 0.0)
    {
        return Err(FrictionError::InvalidInput {
            field: "sigma_y",
            value: input.flow_stress,
            unit: "MPa",
            reason: "the law needs the blank flow stress: finite and > 0",
        });
    }
    if needs.contains(PointNeeds::TEMPERATURE)
        && !(input.temperature.is_finite() && input.temperature > 0.0)
    {
        return Err(FrictionError::InvalidInput {
            field: "temperature",
            value: input.temperature,
            unit: "K",
            reason: "the law needs the temperature: finite and > 0",
        });
    }
    let mats = [
        (
            PointNeeds::SPIN.union(PointNeeds::VELOCITY_GRADIENT),
            "L",
            &input.kin.vel_grad,
        ),
        (PointNeeds::DEFORMATION_GRADIENT, "F_old", &input.kin.f_old),
        (PointNeeds::DEFORMATION_GRADIENT, "F", &input.kin.f_new),
        (
            PointNeeds::TOOL_ROTATION,
            "tool_rotation",
            &input.kin.tool_rotation,
        ),
    ];
    for (flag, field, m) in mats {
        if (needs.0 & flag.0) != 0
            && let Some(&bad) = m.iter().find(|x| !x.is_finite())
        {
            return Err(FrictionError::InvalidInput {
                field,
                value: bad,
                unit: "-",
                reason: "not finite",
            });
        }
    }
    Ok(())
}

#[inline(always)]
fn evaluate<L: FrictionLaw + ?Sized>(
    law: &L,
    x: &ShearInputs,
) -> Result<crate::CriticalShear, FrictionError> {
    check_shear(law.critical_shear(x), x.p, || law.name().to_string())
        .map_err(|e| explained(law, e))
}

/// The law's own account of a failed `τ_c` evaluation (a plugin's panic), if
/// it has one, else `error`.
#[cold]
#[inline(never)]
pub(crate) fn explained<L: FrictionLaw + ?Sized>(law: &L, error: FrictionError) -> FrictionError {
    law.take_failure().unwrap_or(error)
}

/// A law's answer checked against its contract: `τ_c` and its derivatives
/// finite, `τ_c ≥ 0`; otherwise an error naming the law (`name` is called only
/// then) and the pressure `p`.
#[inline(always)]
pub(crate) fn check_shear(
    cs: crate::CriticalShear,
    p: f64,
    name: impl FnOnce() -> String,
) -> Result<crate::CriticalShear, FrictionError> {
    if nonfinite_bits([cs.tau, cs.dtau_dp, cs.dtau_domega, cs.dtau_dspeed]) >> 63 == 0
        && cs.tau >= 0.0
    {
        return Ok(cs);
    }
    Err(shear_error(&cs, p, name()))
}

/// The error of [`check_shear`] (out of line: never on the hot path).
#[cold]
#[inline(never)]
fn shear_error(cs: &crate::CriticalShear, p: f64, component: String) -> FrictionError {
    if let Some(value) = [cs.tau, cs.dtau_dp, cs.dtau_domega, cs.dtau_dspeed]
        .into_iter()
        .find(|v| !v.is_finite())
    {
        return FrictionError::NonFiniteResult {
            component,
            what: "a non-finite critical shear stress or derivative",
            value,
            p,
        };
    }
    FrictionError::NonFiniteResult {
        component,
        what: "a negative critical shear stress",
        value: cs.tau,
        p,
    }
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
    let mut out = StepOutput::default();
    step_into(law, formulation, tangent_mode, state, input, &mut out)?;
    Ok(out)
}

/// [`step`], writing the result into `out` (no copy of the output: the form
/// the batch loop uses). Every field of `out` is written; `tangent` and `dt_dp`
/// are zero under [`TangentMode::None`]. On error `out` is unspecified.
///
/// # Errors
/// As [`step`].
#[inline]
pub fn step_into<L, F>(
    law: &L,
    formulation: &F,
    tangent_mode: TangentMode,
    state: &mut PointState,
    input: &StepInput,
    out: &mut StepOutput,
) -> Result<(), FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    let pairing = Pairing::new(law, formulation);
    if !input_ok(input, pairing.needs) {
        check_input(input, pairing.needs)?;
    }
    let p = input.p;
    if p == 0.0 {
        // Open contact: no traction, history cleared, internal variables
        // kept; the slip, not read, must still be finite.
        if nonfinite_bits([input.du.x, input.du.y, input.du.z]) >> 63 != 0 {
            check_input(input, pairing.needs)?;
        }
        out.reset();
        state.t = Vec3::zeros();
        state.p = 0.0;
        out.open = true;
        return Ok(());
    }
    let trial = Trial::new(&pairing, state, input);
    if !trial.norm2_tr.is_finite() {
        // A non-finite slip (refused here), a non-finite transported history
        // (below) or a square norm that overflows (carried on).
        check_input(input, pairing.needs)?;
    }
    if !trial.t_star.iter().all(|v| v.is_finite()) {
        return Err(FrictionError::NonFiniteResult {
            component: formulation.name().to_string(),
            what: "a non-finite transported traction",
            value: f64::NAN,
            p,
        });
    }
    let cs = evaluate(law, &trial.x)?;
    conclude(&pairing, tangent_mode, state, input, &trial, cs, out)
}

/// What is fixed for a whole batch, or for one step: the law, the
/// formulation and what they declare.
#[derive(Clone, Copy)]
pub(crate) struct Pairing<'a, L: ?Sized, F: ?Sized> {
    law: &'a L,
    formulation: &'a F,
    needs: PointNeeds,
    k_t: f64,
    work_dependent: bool,
    backward_euler: bool,
}

impl<'a, L: FrictionLaw + ?Sized, F: KinematicFormulation + ?Sized> Pairing<'a, L, F> {
    #[inline(always)]
    pub(crate) fn new(law: &'a L, formulation: &'a F) -> Self {
        Self {
            law,
            formulation,
            needs: law.needs().union(formulation.needs()),
            k_t: law.stick_stiffness(),
            work_dependent: law.work_dependent(),
            backward_euler: formulation.backward_euler(),
        }
    }
}

/// A closed point's trial state (friction-math §2): the unit normal, the
/// transported history `t*`, the tangential slip `Δu_T`, the trial traction
/// `t_tr = t* − k_T Δu_T` and its square norm, and what the law is asked.
struct Trial {
    n: Vec3,
    t_star: Vec3,
    du_t: Vec3,
    t_tr: Vec3,
    norm2_tr: f64,
    x: ShearInputs,
}

impl Trial {
    /// The trial of a validated input with `p > 0`.
    #[inline(always)]
    fn new<L, F>(pairing: &Pairing<'_, L, F>, state: &PointState, input: &StepInput) -> Self
    where
        L: FrictionLaw + ?Sized,
        F: KinematicFormulation + ?Sized,
    {
        let kin = &input.kin;
        // |n| is within 1e-6 of 1 (validated): one Newton step for 1/|n|
        // around 1 normalises to ~1e-12 without a square root or a division.
        let n = kin.n_new * (1.5 - 0.5 * kin.n_new.norm_squared());
        let t_star = if state.t == Vec3::zeros() {
            Vec3::zeros()
        } else {
            tangent_part(&n, &pairing.formulation.transport(&state.t, kin))
        };
        let du_t = tangent_part(&n, &input.du);
        let t_tr = t_star - du_t * pairing.k_t;
        let sliding_speed = if pairing.needs.contains(PointNeeds::SLIDING_VELOCITY) {
            du_t.norm() / kin.dt
        } else {
            f64::NAN
        };
        Self {
            n,
            t_star,
            du_t,
            t_tr,
            norm2_tr: t_tr.norm_squared(),
            x: ShearInputs {
                p: input.p,
                omega: state.omega,
                sliding_speed,
                flow_stress: input.flow_stress,
                temperature: input.temperature,
            },
        }
    }
}

/// The return proper, once the law has answered `cs` at the start of the
/// step: stick (`|t_tr| ≤ τ_c`) or radial return onto `τ_c`, backward Euler
/// for a work-dependent law, the tangent asked for. Writes every field of
/// `out` and, on success only, the state.
///
/// # Errors
/// The work-dependent solve's, or the consistent tangent's law evaluations'.
#[inline(always)]
fn conclude<L, F>(
    pairing: &Pairing<'_, L, F>,
    tangent_mode: TangentMode,
    state: &mut PointState,
    input: &StepInput,
    trial: &Trial,
    cs: crate::CriticalShear,
    out: &mut StepOutput,
) -> Result<(), FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    let &Trial {
        n,
        t_star,
        du_t,
        t_tr,
        norm2_tr,
        x,
    } = trial;
    let (k_t, p) = (pairing.k_t, input.p);
    let stick = norm2_tr <= cs.tau * cs.tau || norm2_tr == 0.0;
    if tangent_mode == TangentMode::None && !pairing.work_dependent && pairing.backward_euler {
        // The explicit-dynamics hot path: radial return with selects instead
        // of a stick/slip branch (random stick/slip patterns defeat the
        // branch predictor); the same bits as the branches below.
        let slip = !stick;
        let norm_tr = norm2_tr.sqrt();
        let phi = t_tr * if slip { norm_tr.recip() } else { 0.0 };
        let t = if slip { phi * cs.tau } else { t_tr };
        let dgamma = if slip { (norm_tr - cs.tau) / k_t } else { 0.0 };
        let dissipation = if slip { cs.tau * dgamma } else { 0.0 };
        let slip_vec = if slip { -dgamma * phi } else { Vec3::zeros() };
        out.write(t, cs.tau, !slip, dgamma, slip_vec, dissipation, cs.clamped);
        state.t = t;
        state.p = p;
        state.omega += dissipation;
        return Ok(());
    }
    if stick {
        out.write(t_tr, cs.tau, true, 0.0, Vec3::zeros(), 0.0, cs.clamped);
        if tangent_mode != TangentMode::None {
            out.tangent = -k_t * tangent_projector(&n);
        }
        state.t = t_tr;
        state.p = p;
        return Ok(());
    }
    // Slip.
    let norm_tr = norm2_tr.sqrt();
    let phi = t_tr * norm_tr.recip();
    let frame = Frame {
        formulation: pairing.formulation,
        kin: &input.kin,
        n,
        t_old: state.t,
        p_old: state.p,
        t_star,
        k_t,
        needs: pairing.needs,
    };
    let (d, c, from_formulation) = frame.direction(t_tr, norm_tr, cs.tau, p);
    let mut x = x;
    let (dgamma, tau, dissipation, cs_end) = if pairing.work_dependent {
        solve_work_dependent(pairing.law, &mut x, state.omega, norm_tr, k_t, c, cs)?
    } else {
        let dgamma = (norm_tr - cs.tau) / k_t;
        (dgamma, cs.tau, c * cs.tau * dgamma, cs)
    };
    let t = phi * tau;
    out.write(
        t,
        cs_end.tau,
        false,
        dgamma,
        -dgamma * d,
        dissipation,
        cs_end.clamped,
    );
    if tangent_mode != TangentMode::None {
        let slip = Slip {
            phi,
            norm_tr,
            tau,
            c,
            from_formulation,
            cs_end,
        };
        slip_tangent(
            pairing.law,
            &frame,
            tangent_mode,
            input,
            state.omega,
            x,
            du_t,
            &slip,
            out,
        )?;
    }
    state.t = t;
    state.p = p;
    state.omega += dissipation;
    Ok(())
}

/// What a slip step's tangent reads of the return.
struct Slip {
    phi: Vec3,
    norm_tr: f64,
    tau: f64,
    c: f64,
    from_formulation: bool,
    cs_end: crate::CriticalShear,
}

/// `∂t/∂Δu_T` and `∂t/∂p` of a slip step, into `out`.
///
/// # Errors
/// A law evaluation of the share's differentiation.
#[allow(clippy::too_many_arguments)]
fn slip_tangent<L, F>(
    law: &L,
    frame: &Frame<'_, F>,
    tangent_mode: TangentMode,
    input: &StepInput,
    omega_n: f64,
    x: ShearInputs,
    du_t: Vec3,
    slip: &Slip,
    out: &mut StepOutput,
) -> Result<(), FrictionError>
where
    L: FrictionLaw + ?Sized,
    F: KinematicFormulation + ?Sized,
{
    let &Slip {
        phi,
        norm_tr,
        tau,
        c,
        from_formulation,
        cs_end,
    } = slip;
    let k_t = frame.k_t;
    if tangent_mode == TangentMode::Simplified {
        out.dt_dp = phi * cs_end.dtau_dp;
        return Ok(());
    }
    // Implicit differentiation of g(τ) = τ - τ_c(p, ω(τ), v) = 0,
    // ω(τ) = ω_n + c τ (|t_tr| - τ)/k_T (see `solve_work_dependent`).
    let tau_w = cs_end.dtau_domega;
    let g_tau = 1.0 - tau_w * c * (norm_tr - 2.0 * tau) / k_t;
    let dtau_dnorm = tau_w * c * tau / (k_t * g_tau);
    let dtau_dc = tau_w * tau * (norm_tr - tau) / (k_t * g_tau);
    let mut dtau_dp = cs_end.dtau_dp / g_tau;
    let dtau_dv = cs_end.dtau_dspeed / g_tau;
    let pp = phi * phi.transpose();
    let mut tangent =
        -k_t * ((tau / norm_tr) * (tangent_projector(&frame.n) - pp) + dtau_dnorm * pp);
    let du_norm = du_t.norm();
    if dtau_dv != 0.0 && du_norm > 0.0 {
        tangent += phi * (du_t / (du_norm * input.kin.dt)).transpose() * dtau_dv;
    }
    if dtau_dc != 0.0 && from_formulation {
        // The dissipated share c = φ_tr·d depends on Δu_T and p through the
        // formulation's slip direction: differentiate it numerically (central
        // differences over the slip scale |t_tr|/k_T; only when a consistent
        // tangent is asked for).
        let x = ShearInputs {
            omega: omega_n,
            ..x
        };
        let (dc_du, dc_dp) = frame.share_gradient(law, input.du, x, norm_tr)?;
        tangent += phi * dc_du.transpose() * dtau_dc;
        dtau_dp += dtau_dc * dc_dp;
    }
    out.tangent = tangent;
    out.dt_dp = phi * dtau_dp;
    Ok(())
}

/// What the slip direction of a step depends on, so that it can be evaluated
/// again for perturbed `Δu_T` and `p` (consistent tangent).
struct Frame<'a, F: ?Sized> {
    formulation: &'a F,
    kin: &'a StepKinematics,
    n: Vec3,
    t_old: Vec3,
    p_old: f64,
    t_star: Vec3,
    k_t: f64,
    needs: PointNeeds,
}

impl<F: KinematicFormulation + ?Sized> Frame<'_, F> {
    /// Unit slip direction `d`, share `c = φ_tr·d`, and whether the formulation
    /// chose `d` (rather than the backward-Euler fallback `φ_tr`), for a trial
    /// `t_tr` (norm `norm_tr > 0`), start-of-step `τ_c` and pressure `p`.
    #[inline(always)]
    fn direction(&self, t_tr: Vec3, norm_tr: f64, tau_c: f64, p: f64) -> (Vec3, f64, bool) {
        let phi = t_tr * norm_tr.recip();
        let t_end = phi * tau_c.min(norm_tr);
        let chosen = self
            .formulation
            .slip_direction(&DirectionInputs {
                kin: self.kin,
                t_old: self.t_old,
                p_old: self.p_old,
                t_star: self.t_star,
                t_trial: t_tr,
                t_end,
                p_new: p,
            })
            .and_then(|d| {
                let d = tangent_part(&self.n, &d);
                let len = d.norm();
                (len.is_finite() && len > 0.0).then(|| d * len.recip())
            })
            .filter(|d| d.dot(&phi) > 0.0);
        match chosen {
            Some(d) => (d, d.dot(&phi).clamp(0.0, 1.0), true),
            None => (phi, 1.0, false),
        }
    }

    /// The share `c` for slip increment `du` and shear inputs `x` (pressure,
    /// `ω_n`, speed): the trial and `τ_c` recomputed, for differentiation.
    fn share<L: FrictionLaw + ?Sized>(
        &self,
        law: &L,
        du: Vec3,
        x: ShearInputs,
    ) -> Result<f64, FrictionError> {
        let du_t = tangent_part(&self.n, &du);
        let t_tr = self.t_star - du_t * self.k_t;
        let mut x = x;
        if self.needs.contains(PointNeeds::SLIDING_VELOCITY) {
            x.sliding_speed = du_t.norm() / self.kin.dt;
        }
        let cs = evaluate(law, &x)?;
        Ok(self.direction(t_tr, t_tr.norm(), cs.tau, x.p).1)
    }

    /// `(∂c/∂Δu_T, ∂c/∂p)` by central differences.
    fn share_gradient<L: FrictionLaw + ?Sized>(
        &self,
        law: &L,
        du: Vec3,
        x: ShearInputs,
        norm_tr: f64,
    ) -> Result<(Vec3, f64), FrictionError> {
        let h = 1e-6 * norm_tr / self.k_t;
        let mut grad = Vec3::zeros();
        for i in 0..3 {
            let mut e = Vec3::zeros();
            e[i] = h;
            grad[i] = (self.share(law, du + e, x)? - self.share(law, du - e, x)?) / (2.0 * h);
        }
        let hp = 1e-6 * x.p;
        let plus = self.share(law, du, ShearInputs { p: x.p + hp, ..x })?;
        let minus = self.share(law, du, ShearInputs { p: x.p - hp, ..x })?;
        Ok((grad, (plus - minus) / (2.0 * hp)))
    }
}

/// Backward-Euler slip of a work-dependent law: returns `(Δγ, τ, ΔD, τ_c(ω_{n+1}))`.
///
/// Solved for the traction magnitude `τ ∈ [0, |t_tr|]` rather than for `Δγ`, so
/// that `τ` carries no cancellation error: `g(τ) = τ - τ_c(p, ω(τ))` with
/// `ω(τ) = ω_n + c τ (|t_tr| - τ)/k_T`, `g(0) = -τ_c(ω_n) ≤ 0 < g(|t_tr|)`
/// (slip). Newton's method, safeguarded by bisection. The result is made exactly
/// consistent: `ω_{n+1} = ω(τ*)`, and the traction is `τ_c(p, ω_{n+1})` itself,
/// so `|t| = τ_c(ω_{n+1})` holds to the last bit and `ΔD = ω_{n+1} - ω_n ≥ 0`.
fn solve_work_dependent<L: FrictionLaw + ?Sized>(
    law: &L,
    x: &mut ShearInputs,
    omega_n: f64,
    norm_tr: f64,
    k_t: f64,
    c: f64,
    cs_n: crate::CriticalShear,
) -> Result<(f64, f64, f64, crate::CriticalShear), FrictionError> {
    let c_over_k = c / k_t;
    let work = |tau: f64| c_over_k * tau * (norm_tr - tau);
    let mut lo = 0.0;
    let mut hi = norm_tr;
    // Start from one Newton step off the radial return with the old work,
    // linearised with the start-of-step evaluation (`g(τ0) ≈ -τ_ω ω'(τ0)`,
    // exact to first order): for the usual mild work dependence the next
    // evaluation is already converged.
    let tau0 = cs_n.tau.clamp(lo, hi);
    let g0 = -cs_n.dtau_domega * work(tau0);
    let dg0 = 1.0 - cs_n.dtau_domega * c_over_k * (norm_tr - 2.0 * tau0);
    let predicted = tau0 - g0 / dg0;
    let mut tau = if predicted.is_finite() {
        predicted.clamp(lo, hi)
    } else {
        tau0
    };
    let mut cs = cs_n;
    for _ in 0..200 {
        x.omega = omega_n + work(tau);
        cs = evaluate(law, x)?;
        let g = tau - cs.tau;
        // |g| at the level of round-off of τ: the traction is taken from this
        // very evaluation, so no further one is needed.
        if g.abs() <= 8.0 * f64::EPSILON * (tau + cs.tau) {
            break;
        }
        if g < 0.0 {
            lo = tau;
        } else {
            hi = tau;
        }
        let dg = 1.0 - cs.dtau_domega * c_over_k * (norm_tr - 2.0 * tau);
        let newton = tau - g / dg;
        let next = if dg.is_finite() && dg != 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        let converged = (next - tau).abs() <= 2.0 * f64::EPSILON * norm_tr
            || hi - lo <= 2.0 * f64::EPSILON * norm_tr;
        tau = next;
        if converged {
            x.omega = omega_n + work(tau);
            cs = evaluate(law, x)?;
            break;
        }
    }
    let dissipation = work(tau);
    let dgamma = (norm_tr - tau) / k_t;
    Ok((dgamma, cs.tau.min(norm_tr), dissipation, cs))
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
    fn step_batch(
        &self,
        states: &mut [PointState],
        inputs: &[StepInput],
        outputs: &mut [StepOutput],
    ) -> Result<(), FrictionError>;
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
        Self {
            law,
            formulation,
            tangent: TangentMode::None,
        }
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
    fn step_batch(
        &self,
        states: &mut [PointState],
        inputs: &[StepInput],
        outputs: &mut [StepOutput],
    ) -> Result<(), FrictionError> {
        if self.tangent == TangentMode::None {
            // Explicit dynamics: the lean kernel (same bits as `step_into`).
            return batch::explicit_batch(&self.law, &self.formulation, states, inputs, outputs);
        }
        for ((state, input), output) in states.iter_mut().zip(inputs).zip(outputs.iter_mut()) {
            step_into(
                &self.law,
                &self.formulation,
                self.tangent,
                state,
                input,
                output,
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::rotate_minimal;
    use rand::{Rng, SeedableRng};

    struct Coulomb;
    impl FrictionLaw for Coulomb {
        fn name(&self) -> &str {
            "coulomb"
        }
        fn stick_stiffness(&self) -> f64 {
            1e5
        }
        fn critical_shear(&self, x: &ShearInputs) -> crate::CriticalShear {
            crate::CriticalShear {
                tau: 0.144 * x.p,
                dtau_dp: 0.144,
                ..Default::default()
            }
        }
    }

    /// Convective-like transport, declared (or not) as backward Euler.
    struct Minimal(bool);
    impl KinematicFormulation for Minimal {
        fn name(&self) -> &str {
            "minimal"
        }
        fn needs(&self) -> PointNeeds {
            PointNeeds::NONE
        }
        fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
            rotate_minimal(&kin.n_old, &kin.n_new, t_old)
        }
        fn slip_direction(&self, _x: &DirectionInputs<'_>) -> Option<Vec3> {
            None
        }
        fn backward_euler(&self) -> bool {
            self.0
        }
    }

    /// The branch-free hot path (no tangent, work-independent law, backward
    /// Euler) gives bit for bit the results of the general path, over a random
    /// history with stick, slip and lift-off.
    #[test]
    fn branch_free_radial_return_equals_the_general_path_bitwise() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let (mut fast, mut general) = (PointState::default(), PointState::default());
        let mut n = Vec3::z();
        let (mut slips, mut sticks) = (0, 0);
        for _ in 0..2000 {
            let n_new = (n + Vec3::new(
                rng.random_range(-0.01..0.01),
                rng.random_range(-0.01..0.01),
                0.0,
            ))
            .normalize();
            let p = if rng.random_bool(0.05) {
                0.0
            } else {
                rng.random_range(0.0..100.0)
            };
            let du = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                0.0,
            ) * 10f64.powf(rng.random_range(-7.0..-3.0));
            let input = StepInput::new(p, du, StepKinematics::simple(1e-6, n, n_new));
            let a = step(
                &Coulomb,
                &Minimal(true),
                TangentMode::None,
                &mut fast,
                &input,
            )
            .unwrap();
            let b = step(
                &Coulomb,
                &Minimal(false),
                TangentMode::None,
                &mut general,
                &input,
            )
            .unwrap();
            for (x, y) in [a.t, a.slip]
                .iter()
                .flat_map(|v| v.iter())
                .zip([b.t, b.slip].iter().flat_map(|v| v.iter()))
            {
                assert_eq!(x.to_bits(), y.to_bits());
            }
            assert_eq!((a.stick, a.open, a.clamped), (b.stick, b.open, b.clamped));
            for (x, y) in [
                (a.dgamma, b.dgamma),
                (a.dissipation, b.dissipation),
                (a.tau_c, b.tau_c),
            ] {
                assert_eq!(x.to_bits(), y.to_bits());
            }
            assert_eq!(fast, general);
            slips += usize::from(!a.stick && !a.open);
            sticks += usize::from(a.stick);
            n = n_new;
        }
        assert!(
            slips > 100 && sticks > 100,
            "{slips} slips, {sticks} sticks"
        );
    }

    #[test]
    fn nonfinite_bits_flags_exactly_nan_and_infinities() {
        for x in [0.0, -0.0, 1.0, -1e308, f64::MAX, f64::MIN_POSITIVE, 5e-324] {
            assert_eq!(nonfinite_bits([x]) >> 63, 0, "{x}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -f64::NAN] {
            assert_eq!(nonfinite_bits([1.0, x, 2.0]) >> 63, 1, "{x}");
        }
    }
}
