//! The individual checks of the suite and the sequence that runs them under one formulation.

use super::driver::{Driver, Failure, all_finite, fingerprint, guarded, state_bits};
use super::histories::{self, REFERENCE_STEPS, single, tangent_basis};
use super::{CHECKS, CheckResult, Options, Subject};
use crate::kinematics::{cayley, skew};
use crate::{
    DirectionInputs, FrictionError, FrictionLaw, KinematicFormulation, Mat3, PointNeeds,
    PointState, StepInput, StepKinematics, StepOutput, Vec3,
};

/// Reference pressure of the designed cases (MPa).
const P_REF: f64 = 100.0;
/// Relative tolerance of `|t| ≤ τ_c(1 + tol)` (friction-math §5).
const BOUND_TOL: f64 = 1e-12;
/// Relative tolerance of `Φ = 0` while slipping.
const CONSISTENCY_TOL: f64 = 1e-10;
/// Relative tolerance of `t' = Q t` and `ω' = ω` under a superposed rotation.
const OBJECTIVITY_TOL: f64 = 1e-10;
/// Relative tolerance of `t = -k_T Δu_T` in stick (round-off only).
const STICK_TOL: f64 = 1e-12;
/// Tangent points with `|Φ_tr| ≤ margin · τ_c` are skipped (stick/slip boundary).
const BOUNDARY_MARGIN: f64 = 1e-2;
/// Slip increment of the central differences, relative to `max(|t_tr|, τ_c)/k_T`.
const FD_REL_DU: f64 = 1e-4;
/// Pressure step of the central differences, relative to `p`.
const FD_REL_P: f64 = 1e-5;

/// A law built from the subject's base parameters, with its fixed properties
/// queried once (guarded).
pub(super) struct LawUnderTest<'a> {
    subject: &'a Subject<'a>,
    law: Box<dyn FrictionLaw>,
    k_t: f64,
    needs: PointNeeds,
}

impl<'a> LawUnderTest<'a> {
    /// Build the law from `subject.base`.
    ///
    /// # Errors
    /// The reason it cannot be built or queried (error text or panic message).
    pub fn build(subject: &'a Subject<'a>) -> Result<Self, String> {
        let law = match guarded(|| (subject.build)(&subject.base)) {
            Ok(Ok(law)) => law,
            Ok(Err(e)) => return Err(format!("the base parameter set does not build: {e}")),
            Err(m) => {
                return Err(format!(
                    "building the law from the base parameter set panicked: {m}"
                ));
            }
        };
        let (k_t, needs) = guarded(|| (law.stick_stiffness(), law.needs()))
            .map_err(|m| format!("querying the law (stick stiffness, needs) panicked: {m}"))?;
        Ok(Self {
            subject,
            law,
            k_t,
            needs,
        })
    }
}

/// Worst value and first violation of one property along histories.
#[derive(Clone, Debug)]
struct Tally {
    checked: usize,
    violations: usize,
    worst: f64,
    first: Option<String>,
}

impl Default for Tally {
    fn default() -> Self {
        Self {
            checked: 0,
            violations: 0,
            worst: f64::NEG_INFINITY,
            first: None,
        }
    }
}

impl Tally {
    fn record(&mut self, measure: f64, ok: bool, what: impl FnOnce() -> String) {
        self.checked += 1;
        if measure > self.worst || measure.is_nan() {
            self.worst = measure;
        }
        if !ok {
            self.violations += 1;
            if self.first.is_none() {
                self.first = Some(what());
            }
        }
    }

    fn merged(&self, other: &Self) -> Self {
        Self {
            checked: self.checked + other.checked,
            violations: self.violations + other.violations,
            worst: if other.worst > self.worst {
                other.worst
            } else {
                self.worst
            },
            first: self.first.clone().or_else(|| other.first.clone()),
        }
    }
}

/// Checks 2, 3, 5, 6 (and finiteness) along a set of histories.
#[derive(Clone, Debug, Default)]
struct Along {
    histories: usize,
    steps: usize,
    stick: usize,
    slip: usize,
    open: usize,
    clamped: usize,
    max_omega: f64,
    errors: usize,
    first_error: Option<String>,
    bound: Tally,
    consistency: Tally,
    dissipation: Tally,
    work: Tally,
}

impl Along {
    fn error(&mut self, what: String) {
        self.errors += 1;
        if self.first_error.is_none() {
            self.first_error = Some(what);
        }
    }

    fn merged(&self, other: &Self) -> Self {
        Self {
            histories: self.histories + other.histories,
            steps: self.steps + other.steps,
            stick: self.stick + other.stick,
            slip: self.slip + other.slip,
            open: self.open + other.open,
            clamped: self.clamped + other.clamped,
            max_omega: self.max_omega.max(other.max_omega),
            errors: self.errors + other.errors,
            first_error: self
                .first_error
                .clone()
                .or_else(|| other.first_error.clone()),
            bound: self.bound.merged(&other.bound),
            consistency: self.consistency.merged(&other.consistency),
            dissipation: self.dissipation.merged(&other.dissipation),
            work: self.work.merged(&other.work),
        }
    }

    fn summary(&self) -> String {
        format!(
            "{} steps in {} histories ({} stick, {} slip, {} open, {} with clamp active; max ω = {:.3e} N/mm)",
            self.steps,
            self.histories,
            self.stick,
            self.slip,
            self.open,
            self.clamped,
            self.max_omega
        )
    }

    /// Outcome of one of the along-checks: failed if any step failed or violated it.
    fn outcome(&self, tally: &Tally, what: impl FnOnce(f64) -> String) -> Result<String, String> {
        if let Some(e) = &self.first_error {
            return Err(format!(
                "{} histories stopped by a failed step; first: {e}",
                self.errors
            ));
        }
        match &tally.first {
            Some(first) => Err(format!(
                "{} of {} steps violate it; first: {first}",
                tally.violations, tally.checked
            )),
            None => Ok(format!("{}; {}", self.summary(), what(tally.worst))),
        }
    }
}

/// Short description of a step's input, for failure messages.
fn describe(label: &str, k: usize, x: &StepInput) -> String {
    format!(
        "{label} step {k} (p = {:e} MPa, |Δu_T| = {:e} mm)",
        x.p,
        x.du.norm()
    )
}

/// Drive one history from a zero state, recording checks 2, 3, 5, 6 and finiteness.
fn run_along(drv: &Driver<'_>, steps: &[StepInput], label: &str, along: &mut Along) {
    along.histories += 1;
    let mut state = PointState::default();
    for (k, raw) in steps.iter().enumerate() {
        let input = drv.prepare(raw);
        let omega_before = state.omega;
        let out = match drv.step(&mut state, &input) {
            Ok(out) => out,
            Err(f) => return along.error(format!("{}: {f}", describe(label, k, &input))),
        };
        along.steps += 1;
        if !all_finite(&out, &state) {
            return along.error(format!(
                "{}: non-finite output {out:?}, state {state:?}",
                describe(label, k, &input)
            ));
        }
        if out.open {
            along.open += 1;
        } else if out.stick {
            along.stick += 1;
        } else {
            along.slip += 1;
        }
        along.clamped += usize::from(out.clamped);
        along.max_omega = along.max_omega.max(state.omega);
        let cs = match drv.critical_shear(&input, state.omega) {
            Ok(cs) => cs,
            Err(f) => {
                return along.error(format!(
                    "{}: τ_c(p, ω_n+1) = {f}",
                    describe(label, k, &input)
                ));
            }
        };
        let t = out.t.norm();
        let ratio = |x: f64| {
            if cs.tau > 0.0 {
                x / cs.tau
            } else if x > 0.0 {
                f64::INFINITY
            } else {
                0.0
            }
        };
        along
            .bound
            .record(ratio(t - cs.tau), t <= cs.tau * (1.0 + BOUND_TOL), || {
                format!(
                    "{}: |t| = {t:e} MPa > τ_c(p, ω_n+1) = {:e} MPa (ω_n+1 = {:e} N/mm)",
                    describe(label, k, &input),
                    cs.tau,
                    state.omega
                )
            });
        if !out.open && !out.stick {
            let phi = (t - cs.tau).abs();
            along.consistency.record(ratio(phi), phi <= CONSISTENCY_TOL * cs.tau, || {
                format!("{}: slipping with |t| = {t:e} MPa but τ_c(p, ω_n+1) = {:e} MPa (|Φ|/τ_c = {:e})", describe(label, k, &input), cs.tau, ratio(phi))
            });
        }
        let work_done = out.t.dot(&(-out.slip));
        let d_ok = out.dissipation >= 0.0 && work_done >= -1e-12 * t * out.slip.norm();
        along
            .dissipation
            .record(-out.dissipation.min(work_done), d_ok, || {
                format!(
                    "{}: ΔD = {:e} N/mm, t·(-Δu_sl) = {work_done:e} N/mm",
                    describe(label, k, &input),
                    out.dissipation
                )
            });
        along.work.record(
            omega_before - state.omega,
            state.omega >= omega_before,
            || {
                format!(
                    "{}: ω went from {omega_before:e} to {:e} N/mm",
                    describe(label, k, &input),
                    state.omega
                )
            },
        );
    }
}

/// Drive a history from a zero state, returning each step's output and `ω_{n+1}`.
fn run_plain(
    drv: &Driver<'_>,
    steps: &[StepInput],
    label: &str,
) -> Result<Vec<(StepOutput, f64)>, String> {
    let mut state = PointState::default();
    steps
        .iter()
        .enumerate()
        .map(|(k, raw)| {
            let input = drv.prepare(raw);
            let out = drv
                .step(&mut state, &input)
                .map_err(|f| format!("{}: {f}", describe(label, k, &input)))?;
            Ok((out, state.omega))
        })
        .collect()
}

/// The suite for one law: the random histories, shared by all formulations.
pub(super) struct Suite<'a> {
    law: &'a LawUnderTest<'a>,
    options: &'a Options,
    random: Vec<Vec<StepInput>>,
}

impl<'a> Suite<'a> {
    /// Prepare the random histories of `options` for `law`.
    pub fn new(law: &'a LawUnderTest<'a>, options: &'a Options) -> Self {
        let random = (0..options.random_histories)
            .map(|h| {
                histories::random(
                    options.seed.wrapping_add(h as u64),
                    options.steps_per_history,
                )
            })
            .collect();
        Self {
            law,
            options,
            random,
        }
    }

    /// Checks 1–11 under `form`, in the order of [`CHECKS`].
    pub fn run(&self, form: &dyn KinematicFormulation) -> Vec<CheckResult> {
        let law = self.law;
        let drv = Driver::new(law.law.as_ref(), law.needs, form);
        let scale = self.stick_scale(&drv);
        // With no usable stick limit the stick check fails; the others still run.
        let u_star = scale.as_ref().copied().unwrap_or(1e-4);
        let mut reference = Along::default();
        run_along(
            &drv,
            &histories::reference(u_star, P_REF, false),
            "reference history",
            &mut reference,
        );
        let mut random = Along::default();
        for (h, hist) in self.random.iter().enumerate() {
            run_along(&drv, hist, &format!("random history {h}"), &mut random);
        }
        let all = reference.merged(&random);
        let outcomes: [Result<String, String>; 11] = [
            self.stick(&drv, &scale),
            all.outcome(&all.bound, |w| format!("max |t|/τ_c - 1 = {w:.1e}")),
            all.outcome(&all.consistency, |w| {
                format!(
                    "{} slipping steps, max |Φ|/τ_c = {w:.1e}",
                    all.consistency.checked
                )
            }),
            self.tangent(&drv, u_star),
            all.outcome(&all.dissipation, |w| format!("min ΔD = {:.1e} N/mm", -w)),
            all.outcome(&all.work, |_| "ω never decreases".to_string()),
            self.objectivity(&drv, u_star),
            self.edge_cases(&drv, u_star),
            Self::random_histories(&random),
            self.non_finite_input(&drv, u_star),
            self.determinism(&drv, u_star),
        ];
        outcomes
            .into_iter()
            .zip(CHECKS)
            .map(|(outcome, check)| CheckResult {
                check,
                formulation: Some(form.name().to_string()),
                passed: outcome.is_ok(),
                detail: outcome.unwrap_or_else(|e| e),
            })
            .collect()
    }

    /// The stick limit `u* = τ_c(p_ref, ω = 0)/k_T` (mm) that scales the designed histories.
    fn stick_scale(&self, drv: &Driver<'_>) -> Result<f64, String> {
        let k_t = self.law.k_t;
        if !(k_t.is_finite() && k_t > 0.0) {
            return Err(format!(
                "stick stiffness k_T = {k_t:e} MPa/mm must be finite and > 0"
            ));
        }
        let probe = drv.prepare(&single(P_REF, Vec3::zeros(), Vec3::z()));
        let cs = drv
            .critical_shear(&probe, 0.0)
            .map_err(|f| format!("τ_c(p = {P_REF} MPa, ω = 0): {f}"))?;
        if cs.tau > 0.0 {
            Ok(cs.tau / k_t)
        } else {
            Err(format!(
                "τ_c(p = {P_REF} MPa, ω = 0) = {:e} MPa: the law has no stick range",
                cs.tau
            ))
        }
    }

    /// Check 1: From a zero history, increments of 0.1–0.5 `u*` stick with `t = -k_T Δu_T`.
    fn stick(&self, drv: &Driver<'_>, scale: &Result<f64, String>) -> Result<String, String> {
        let u_star = scale.clone()?;
        let k_t = self.law.k_t;
        let mut worst: f64 = 0.0;
        let mut cases = 0;
        for n in [Vec3::z(), Vec3::new(0.3, -0.4, 0.866).normalize()] {
            let (a, b) = tangent_basis(&n);
            for (dir, frac) in [(a, 0.1), (b, 0.3), ((a * 0.6 - b * 0.8), 0.5)] {
                let du = dir * (frac * u_star);
                let input = drv.prepare(&single(P_REF, du, n));
                let mut state = PointState::default();
                let label = format!(
                    "Δu_T = {frac} τ_c/k_T = {:e} mm at p = {P_REF} MPa, n = {:?}",
                    du.norm(),
                    n.as_slice()
                );
                let out = drv
                    .step(&mut state, &input)
                    .map_err(|f| format!("{label}: {f}"))?;
                if out.open || !out.stick {
                    return Err(format!(
                        "{label} did not stick (Δγ = {:e} mm, |t| = {:e} MPa)",
                        out.dgamma,
                        out.t.norm()
                    ));
                }
                let expect = -k_t * du;
                let err = (out.t - expect).norm() / expect.norm();
                worst = worst.max(err);
                if err.is_nan() || err > STICK_TOL {
                    return Err(format!(
                        "{label}: t = {:?} but -k_T Δu_T = {:?} (rel. error {err:e})",
                        out.t.as_slice(),
                        expect.as_slice()
                    ));
                }
                if out.dissipation != 0.0 || state.omega != 0.0 || out.dgamma != 0.0 {
                    return Err(format!(
                        "{label}: stick with Δγ = {:e}, ΔD = {:e}, ω = {:e} (must all be 0)",
                        out.dgamma, out.dissipation, state.omega
                    ));
                }
                cases += 1;
            }
        }
        Ok(format!(
            "{cases} increments of 0.1–0.5 τ_c/k_T stick with t = -k_T Δu_T (max rel. error {worst:.1e})"
        ))
    }

    /// Check 4: Consistent tangents against central differences of the step along the
    /// reference history, away from the stick/slip boundary.
    fn tangent(&self, drv: &Driver<'_>, u_star: f64) -> Result<String, String> {
        let tol = self.options.tangent_rel_tol;
        let k_t = self.law.k_t;
        let hist = histories::reference(u_star, P_REF, false);
        let (mut n_stick, mut n_slip, mut skipped) = (0, 0, 0);
        let (mut worst_du, mut worst_p): (f64, f64) = (0.0, 0.0);
        let mut state = PointState::default();
        let label = "reference history";
        for (k, raw) in hist.iter().enumerate() {
            let input = drv.prepare(raw);
            let before = state;
            let out = drv
                .step(&mut state, &input)
                .map_err(|f| format!("{}: {f}", describe(label, k, &input)))?;
            if out.open {
                continue;
            }
            let cs_n = drv
                .critical_shear(&input, before.omega)
                .map_err(|f| format!("{}: τ_c = {f}", describe(label, k, &input)))?;
            let norm_tr = if out.stick {
                out.t.norm()
            } else {
                out.t.norm() + k_t * out.dgamma
            };
            if cs_n.tau <= 0.0 || (norm_tr - cs_n.tau).abs() <= BOUNDARY_MARGIN * cs_n.tau {
                skipped += 1;
                continue;
            }
            let from = |x: &StepInput| -> Result<StepOutput, String> {
                let mut s = before;
                drv.step(&mut s, x).map_err(|f| {
                    format!(
                        "{} (perturbed for differences): {f}",
                        describe(label, k, &input)
                    )
                })
            };
            let h = FD_REL_DU * norm_tr.max(cs_n.tau) / k_t;
            let mut fd = Mat3::zeros();
            let mut crossed = false;
            for j in 0..3 {
                let (mut plus, mut minus) = (input, input);
                plus.du[j] += h;
                minus.du[j] -= h;
                let (op, om) = (from(&plus)?, from(&minus)?);
                crossed |= op.stick != out.stick || om.stick != out.stick;
                fd.set_column(j, &((op.t - om.t) / (2.0 * h)));
            }
            let hp = FD_REL_P * input.p;
            let (mut plus, mut minus) = (input, input);
            plus.p += hp;
            minus.p -= hp;
            let (op, om) = (from(&plus)?, from(&minus)?);
            crossed |= op.stick != out.stick || om.stick != out.stick;
            if crossed {
                skipped += 1;
                continue;
            }
            let fd_p = (op.t - om.t) / (2.0 * hp);
            let err_du = (out.tangent - fd).norm()
                / out.tangent.norm().max(fd.norm()).max(f64::MIN_POSITIVE);
            let scale_p = out.dt_dp.norm().max(fd_p.norm()).max(cs_n.tau / input.p);
            let err_p = (out.dt_dp - fd_p).norm() / scale_p;
            let phase = if out.stick { "stick" } else { "slip" };
            if err_du.is_nan() || err_du > tol {
                return Err(format!(
                    "{} in {phase}: ∂t/∂Δu_T = {:?} but central differences give {:?} (rel. error {err_du:.2e} > {tol:e})",
                    describe(label, k, &input),
                    out.tangent.as_slice(),
                    fd.as_slice()
                ));
            }
            if err_p.is_nan() || err_p > tol {
                return Err(format!(
                    "{} in {phase}: ∂t/∂p = {:?} but central differences give {:?} (rel. error {err_p:.2e} > {tol:e}); check ∂τ_c/∂p",
                    describe(label, k, &input),
                    out.dt_dp.as_slice(),
                    fd_p.as_slice()
                ));
            }
            worst_du = worst_du.max(err_du);
            worst_p = worst_p.max(err_p);
            if out.stick {
                n_stick += 1;
            } else {
                n_slip += 1;
            }
        }
        let text = format!(
            "checked {n_stick} stick + {n_slip} slip points of {REFERENCE_STEPS} ({skipped} skipped within {:.0} % of Φ_tr = 0); max rel. error ∂t/∂Δu_T {worst_du:.1e}, ∂t/∂p {worst_p:.1e} (tol {tol:e})",
            100.0 * BOUNDARY_MARGIN
        );
        if n_stick == 0 || n_slip == 0 {
            Err(format!("{text}: need points in both stick and slip"))
        } else {
            Ok(text)
        }
    }

    /// Check 7: A superposed rigid rotation `Q(t)` rotates the tractions and leaves `ω`.
    fn objectivity(&self, drv: &Driver<'_>, u_star: f64) -> Result<String, String> {
        let base = histories::reference(u_star, P_REF, true);
        let q0 = cayley(&skew(&Vec3::new(0.7, -0.4, 0.9)));
        let spin = Vec3::new(8.0, -5.0, 12.0);
        let (rotated, qs) = histories::superpose(&base, q0, spin);
        let base_run = run_plain(drv, &base, "rigid base history")?;
        let rot_run = run_plain(drv, &rotated, "rotated history")?;
        let (err_t, err_w, first) = compare_rotated(&base_run, &rot_run, &qs);
        let (stick, open) = (
            base_run.iter().filter(|(o, _)| o.stick).count(),
            base_run.iter().filter(|(o, _)| o.open).count(),
        );
        let setting = format!(
            "{} steps ({stick} stick, {} slip, {open} open) over a sphere under Q(t) with Q_0 of {:.2} rad and spin {:.1} rad/s",
            base.len(),
            base.len() - stick - open,
            2.0 * (0.5 * Vec3::new(0.7, -0.4, 0.9).norm()).atan(),
            spin.norm()
        );
        let Some(first) = first else {
            return Ok(format!(
                "{setting}: max |t' - Q t|/|t| = {err_t:.1e}, max |ω' - ω|/ω = {err_w:.1e}"
            ));
        };
        // Tell the formulation's part from the law's: run the rotated history
        // with the formulation conjugated by Q (objective by construction).
        let mut state = PointState::default();
        let mut conj_run = Vec::with_capacity(rotated.len());
        for (k, y) in rotated.iter().enumerate() {
            let conj = Conjugated {
                inner: drv.form,
                q_old: if k == 0 { q0 } else { qs[k - 1] },
                q_new: qs[k],
                base_kin: drv.prepare(&base[k]).kin,
            };
            let d2 = Driver {
                law: drv.law,
                form: &conj,
                needs: drv.needs,
            };
            let input = d2.prepare(y);
            let out = d2
                .step(&mut state, &input)
                .map_err(|f| format!("{}: {f}", describe("rotated history", k, &input)))?;
            conj_run.push((out, state.omega));
        }
        let (c_t, c_w, c_first) = compare_rotated(&base_run, &conj_run, &qs);
        match c_first {
            None => Err(format!(
                "formulation `{}` is not objective ({setting}: {first}); the law itself is: with the formulation conjugated by Q, max |t' - Q t|/|t| = {c_t:.1e}, max |ω' - ω|/ω = {c_w:.1e}",
                drv.form.name()
            )),
            Some(c_first) => Err(format!(
                "{setting}: {c_first} (also with the formulation conjugated by Q; unconjugated: {first}, max errors {err_t:.1e}, {err_w:.1e})"
            )),
        }
    }

    /// Check 8: The edge cases of friction-math §2: finite, documented answers.
    fn edge_cases(&self, drv: &Driver<'_>, u_star: f64) -> Result<String, String> {
        let n = Vec3::new(0.2, -0.3, 0.93).normalize();
        let (a, _) = tangent_basis(&n);
        let slipped = self.slipped_state(drv, u_star, n)?;
        let cases = edge_case_inputs(self.law.k_t, u_star, n, slipped);
        let mut worst_excess: f64 = 0.0;
        for (label, start, raw) in cases {
            if let Some(excess) = edge_case(drv, label, start, &raw)? {
                worst_excess = worst_excess.max(excess);
            }
        }
        let probes = critical_shear_probes(drv, a, n)?;
        Ok(format!(
            "{} cases finite: |t_tr| = 0 sticks with a finite tangent; p = 0 opens, clears the history, keeps ω; p → 0⁺ (1e-300, 1e-12 MPa), Δu_T = 0, |Δu_T| = 1e6 mm, p = 1e6 MPa; max |t|/τ_c - 1 = {worst_excess:.1e}; τ_c finite and ≥ 0 at {probes} probes of p ∈ [0, 1e6] MPa, ω ∈ [0, 1e9] N/mm, |Δu_T| ∈ [0, 1e3] mm",
            cases.len()
        ))
    }

    /// Check 9: Random histories: every output finite; checks 2, 3, 5, 6 along them.
    fn random_histories(random: &Along) -> Result<String, String> {
        if let Some(e) = &random.first_error {
            return Err(format!(
                "{} of {} histories stopped by a failed or non-finite step; first: {e}",
                random.errors, random.histories
            ));
        }
        let violated: Vec<String> = [
            ("traction-bound", &random.bound),
            ("consistency", &random.consistency),
            ("dissipation", &random.dissipation),
            ("monotone-work", &random.work),
        ]
        .into_iter()
        .filter_map(|(name, t)| {
            t.first
                .as_ref()
                .map(|f| format!("{name} ({} steps; first: {f})", t.violations))
        })
        .collect();
        if violated.is_empty() {
            Ok(format!(
                "{}: all outputs finite; max |t|/τ_c - 1 = {:.1e}, max |Φ|/τ_c in slip = {:.1e}, min ΔD = {:.1e} N/mm, ω monotone",
                random.summary(),
                random.bound.worst,
                random.consistency.worst,
                -random.dissipation.worst
            ))
        } else {
            Err(format!(
                "{}: violated {}",
                random.summary(),
                violated.join("; ")
            ))
        }
    }

    /// Check 10: NaN/inf input is refused with `InvalidInput` and leaves the state unchanged.
    fn non_finite_input(&self, drv: &Driver<'_>, u_star: f64) -> Result<String, String> {
        let n = Vec3::new(0.2, -0.3, 0.93).normalize();
        let (a, _) = tangent_basis(&n);
        let slipped = self.slipped_state(drv, u_star, n)?;
        let good = drv.prepare(&single(P_REF, a * (2.0 * u_star), n));
        let mut cases: Vec<(String, StepInput)> = Vec::new();
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut x = good;
            x.p = v;
            cases.push((format!("p = {v}"), x));
            for j in 0..3 {
                let mut x = good;
                x.du[j] = v;
                cases.push((format!("Δu_T[{j}] = {v}"), x));
                let mut x = good;
                x.kin.n_new[j] = v;
                cases.push((format!("n[{j}] = {v}"), x));
            }
            let mut x = good;
            x.kin.n_old[1] = v;
            cases.push((format!("n_old[1] = {v}"), x));
            let needs = drv.needs;
            if needs.contains(PointNeeds::FLOW_STRESS) {
                let mut x = good;
                x.flow_stress = v;
                cases.push((format!("flow stress = {v}"), x));
            }
            if needs.contains(PointNeeds::TEMPERATURE) {
                let mut x = good;
                x.temperature = v;
                cases.push((format!("temperature = {v}"), x));
            }
            if needs.contains(PointNeeds::SPIN) || needs.contains(PointNeeds::VELOCITY_GRADIENT) {
                let mut x = good;
                x.kin.vel_grad[(0, 1)] = v;
                cases.push((format!("L[0][1] = {v}"), x));
            }
            if needs.contains(PointNeeds::DEFORMATION_GRADIENT) {
                let mut x = good;
                x.kin.f_new[(2, 0)] = v;
                cases.push((format!("F[2][0] = {v}"), x));
            }
            if needs.contains(PointNeeds::TOOL_ROTATION) {
                let mut x = good;
                x.kin.tool_rotation[(1, 2)] = v;
                cases.push((format!("tool rotation[1][2] = {v}"), x));
            }
        }
        for (label, input) in &cases {
            let mut state = slipped;
            let before = state_bits(&state);
            match drv.step(&mut state, input) {
                Err(Failure::Error(FrictionError::InvalidInput { .. })) => {}
                Err(f) => return Err(format!("{label}: expected an InvalidInput error, got {f}")),
                Ok(out) => {
                    return Err(format!(
                        "{label}: accepted, returned t = {:?}",
                        out.t.as_slice()
                    ));
                }
            }
            if state_bits(&state) != before {
                return Err(format!(
                    "{label}: the state changed on error: {slipped:?} → {state:?}"
                ));
            }
        }
        Ok(format!(
            "{} non-finite inputs (p, Δu_T, n, n_old and declared point data) refused with InvalidInput, state unchanged",
            cases.len()
        ))
    }

    /// Check 11: The same history twice, with the same and with a rebuilt law, gives the same bits.
    fn determinism(&self, drv: &Driver<'_>, u_star: f64) -> Result<String, String> {
        let mut hists = vec![(
            "reference history",
            histories::reference(u_star, P_REF, false),
        )];
        if let Some(first) = self.random.first() {
            hists.push(("random history 0", first.clone()));
        }
        let run = |d: &Driver<'_>| -> Vec<Result<Vec<u64>, String>> {
            let mut all = Vec::new();
            for (_, hist) in &hists {
                let mut state = PointState::default();
                for raw in hist {
                    let mut bits = Vec::with_capacity(40);
                    all.push(match d.step(&mut state, &d.prepare(raw)) {
                        Ok(out) => {
                            fingerprint(&out, &state, &mut bits);
                            Ok(bits)
                        }
                        Err(f) => Err(f.to_string()),
                    });
                }
            }
            all
        };
        let first = run(drv);
        let second = run(drv);
        let rebuilt = match guarded(|| (self.law.subject.build)(&self.law.subject.base)) {
            Ok(Ok(law)) => law,
            Ok(Err(e)) => return Err(format!("rebuilding from the base set failed: {e}")),
            Err(m) => return Err(format!("rebuilding from the base set panicked: {m}")),
        };
        let third = run(&Driver::new(rebuilt.as_ref(), self.law.needs, drv.form));
        let steps = first.len();
        for (what, other) in [
            ("a second run", &second),
            ("a run with a rebuilt law", &third),
        ] {
            if let Some(k) = (0..steps).find(|&k| first[k] != other[k]) {
                return Err(format!(
                    "step {k} of {steps} differs between the first run and {what}"
                ));
            }
        }
        Ok(format!(
            "{steps} steps bitwise identical over 3 runs (same law twice, rebuilt law once)"
        ))
    }

    /// A state after two slipping steps of 5 `u*` at `p_ref`, normal `n`.
    fn slipped_state(&self, drv: &Driver<'_>, u_star: f64, n: Vec3) -> Result<PointState, String> {
        let (a, _) = tangent_basis(&n);
        let mut state = PointState::default();
        for _ in 0..2 {
            let input = drv.prepare(&single(P_REF, a * (5.0 * u_star), n));
            drv.step(&mut state, &input).map_err(|f| {
                format!("preparing a slipped state (p = {P_REF} MPa, Δu_T = 5 τ_c/k_T): {f}")
            })?;
        }
        Ok(state)
    }
}

/// The edge cases of check 8 (friction-math §2), each a label, a starting
/// state (the zero history or `slipped`) and a step at normal `n`, scaled by
/// the stick limit `u_star` and the stick stiffness `k_t`.
fn edge_case_inputs(
    k_t: f64,
    u_star: f64,
    n: Vec3,
    slipped: PointState,
) -> [(&'static str, PointState, StepInput); 11] {
    let (a, b) = tangent_basis(&n);
    let zero = PointState::default();
    [
        (
            "|t_tr| = 0 (zero history, Δu_T = 0)",
            zero,
            single(P_REF, Vec3::zeros(), n),
        ),
        (
            "|t_tr| ≈ 0 after slip (Δu_T = t_n/k_T)",
            slipped,
            single(P_REF, slipped.t / k_t, n),
        ),
        ("p = 0 after slip", slipped, single(0.0, a * u_star, n)),
        (
            "p = 1e-300 MPa after slip",
            slipped,
            single(1e-300, a * u_star, n),
        ),
        (
            "p = 1e-12 MPa after slip",
            slipped,
            single(1e-12, b * u_star, n),
        ),
        (
            "p = 1e-300 MPa from zero history",
            zero,
            single(1e-300, b * u_star, n),
        ),
        (
            "Δu_T = 0 after slip",
            slipped,
            single(P_REF, Vec3::zeros(), n),
        ),
        (
            "|Δu_T| = 1e6 mm after slip",
            slipped,
            single(P_REF, b * 1e6, n),
        ),
        (
            "p = 1e6 MPa after slip",
            slipped,
            single(1e6, a * u_star, n),
        ),
        (
            "p = 1e6 MPa, |Δu_T| = 1e6 mm from zero history",
            zero,
            single(1e6, a * -1e6, n),
        ),
        (
            "p = 1e-12 MPa, |Δu_T| = 1e6 mm after slip",
            slipped,
            single(1e-12, a * 1e6, n),
        ),
    ]
}

/// One edge case of check 8: the step from `start` must give a finite answer
/// within the traction bound, never decrease ω, open at `p = 0` and stick with
/// `t = 0` for a zero increment from the zero history. Returns `|t|/τ_c - 1`
/// when `τ_c > 0`.
fn edge_case(
    drv: &Driver<'_>,
    label: &str,
    start: PointState,
    raw: &StepInput,
) -> Result<Option<f64>, String> {
    let input = drv.prepare(raw);
    let mut state = start;
    let out = drv
        .step(&mut state, &input)
        .map_err(|f| format!("{label}: {f}"))?;
    if !all_finite(&out, &state) {
        return Err(format!(
            "{label}: non-finite output {out:?}, state {state:?}"
        ));
    }
    let cs = drv
        .critical_shear(&input, state.omega)
        .map_err(|f| format!("{label}: τ_c(p, ω_n+1) = {f}"))?;
    let t = out.t.norm();
    if t > cs.tau * (1.0 + BOUND_TOL) {
        return Err(format!(
            "{label}: |t| = {t:e} MPa > τ_c(p, ω_n+1) = {:e} MPa (ω_n+1 = {:e} N/mm)",
            cs.tau, state.omega
        ));
    }
    let excess = (cs.tau > 0.0).then(|| t / cs.tau - 1.0);
    if state.omega < start.omega {
        return Err(format!(
            "{label}: ω decreased from {:e} to {:e} N/mm",
            start.omega, state.omega
        ));
    }
    if raw.p == 0.0
        && !(out.open
            && out.t == Vec3::zeros()
            && state.t == Vec3::zeros()
            && state.omega == start.omega)
    {
        return Err(format!(
            "{label}: expected open contact with t = 0, history cleared and ω kept; got open = {}, t = {:?}, history {:?}, ω {:e} → {:e}",
            out.open,
            out.t.as_slice(),
            state.t.as_slice(),
            start.omega,
            state.omega
        ));
    }
    if start == PointState::default()
        && raw.du == Vec3::zeros()
        && !(out.stick && out.t == Vec3::zeros())
    {
        return Err(format!(
            "{label}: expected stick with t = 0; got stick = {}, t = {:?}",
            out.stick,
            out.t.as_slice()
        ));
    }
    Ok(excess)
}

/// The law's own contract, probed directly rather than only where the
/// return mapping happens to evaluate it: τ_c finite and ≥ 0 for every
/// p ≥ 0, ω ≥ 0 and sliding speed ≥ 0 (trait `FrictionLaw`), along `a` at
/// normal `n`. Returns the number of probes.
fn critical_shear_probes(drv: &Driver<'_>, a: Vec3, n: Vec3) -> Result<usize, String> {
    let mut probes = 0;
    for p in [0.0, 1e-300, 1e-12, 1e-3, 1.0, 100.0, 1e4, 1e6] {
        for omega in [0.0, 1.0, 1e2, 1e4, 1e6, 1e9] {
            for du in [0.0, 1e-6, 1e-3, 1.0, 1e3] {
                let input = single(p, a * du, n);
                drv.critical_shear(&input, omega).map_err(|f| {
                    format!("τ_c(p = {p:e} MPa, ω = {omega:e} N/mm, |Δu_T| = {du:e} mm): {f}")
                })?;
                probes += 1;
            }
        }
    }
    Ok(probes)
}

/// Compare a rotated run with its base: max relative errors of `t' = Q t` and
/// `ω' = ω`, and the first violation of [`OBJECTIVITY_TOL`].
fn compare_rotated(
    base: &[(StepOutput, f64)],
    rotated: &[(StepOutput, f64)],
    qs: &[Mat3],
) -> (f64, f64, Option<String>) {
    let (mut err_t, mut err_w): (f64, f64) = (0.0, 0.0);
    let mut first = None;
    for (k, (((b, wb), (r, wr)), q)) in base.iter().zip(rotated).zip(qs).enumerate() {
        let scale_t = b.t.norm().max(b.tau_c).max(f64::MIN_POSITIVE);
        let et = (r.t - q * b.t).norm() / scale_t;
        let ew = if *wb == 0.0 && *wr == 0.0 {
            0.0
        } else {
            (wr - wb).abs() / wb.abs().max(wr.abs())
        };
        err_t = err_t.max(et);
        err_w = err_w.max(ew);
        if first.is_none()
            && (et.is_nan() || ew.is_nan() || et > OBJECTIVITY_TOL || ew > OBJECTIVITY_TOL)
        {
            first = Some(format!(
                "step {k}: |t' - Q t|/|t| = {et:.2e}, |ω' - ω|/ω = {ew:.2e} (tol {OBJECTIVITY_TOL:e}); t = {:?}, t' = {:?}",
                (q * b.t).as_slice(),
                r.t.as_slice()
            ));
        }
    }
    (err_t, err_w, first)
}

/// A formulation made objective by conjugation with a superposed rotation:
/// it maps rotated quantities back to the base frame, calls the inner
/// formulation with the base kinematics, and rotates the answer forward.
struct Conjugated<'a> {
    inner: &'a dyn KinematicFormulation,
    q_old: Mat3,
    q_new: Mat3,
    base_kin: StepKinematics,
}

impl KinematicFormulation for Conjugated<'_> {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn needs(&self) -> PointNeeds {
        self.inner.needs()
    }
    fn transport(&self, t_old: &Vec3, _kin: &StepKinematics) -> Vec3 {
        self.q_new
            * self
                .inner
                .transport(&(self.q_old.transpose() * t_old), &self.base_kin)
    }
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        let base = DirectionInputs {
            kin: &self.base_kin,
            t_old: self.q_old.transpose() * x.t_old,
            p_old: x.p_old,
            t_star: self.q_new.transpose() * x.t_star,
            t_trial: self.q_new.transpose() * x.t_trial,
            t_end: self.q_new.transpose() * x.t_end,
            p_new: x.p_new,
        };
        self.inner.slip_direction(&base).map(|d| self.q_new * d)
    }
}

/// Whether `text` contains `name` as a whole word (not inside a longer identifier).
fn names_word(text: &str, name: &str) -> bool {
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(name).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + name.len()..].chars().next();
        !before.is_some_and(is_ident) && !after.is_some_and(is_ident)
    })
}

/// A value just outside the bound `b` (relative distance 1e-6, at least 1e-6).
fn beyond(b: f64, sign: f64) -> f64 {
    b + sign * 1e-6 * b.abs().max(1.0)
}

/// Check 12: The base set builds; NaN and values just outside each finite bound are
/// refused with an error naming the parameter.
pub(super) fn parameter_validation(subject: &Subject<'_>) -> CheckResult {
    let outcome = (|| -> Result<String, String> {
        match guarded(|| (subject.build)(&subject.base)) {
            Ok(Ok(_)) => {}
            Ok(Err(e)) => return Err(format!("the base parameter set does not build: {e}")),
            Err(m) => {
                return Err(format!(
                    "building from the base parameter set panicked: {m}"
                ));
            }
        }
        let mut probes = 0;
        let mut failures = Vec::new();
        for spec in subject.params {
            let mut values = vec![f64::NAN];
            if spec.min.is_finite() {
                values.push(if spec.min_exclusive {
                    spec.min
                } else {
                    beyond(spec.min, -1.0)
                });
            }
            if spec.max.is_finite() {
                values.push(beyond(spec.max, 1.0));
            }
            for v in values {
                probes += 1;
                let params = subject.base.clone().with(spec.name, v);
                let what = format!(
                    "`{}` = {v} {} (valid: {})",
                    spec.name,
                    spec.unit,
                    spec.range_text()
                );
                match guarded(|| (subject.build)(&params)) {
                    Ok(Ok(_)) => failures.push(format!("{what} was accepted")),
                    Ok(Err(e)) => {
                        let text = e.to_string();
                        if !names_word(&text, spec.name) {
                            failures.push(format!("{what} was refused but the error does not name the parameter: {text}"));
                        }
                    }
                    Err(m) => failures.push(format!("{what}: the builder panicked: {m}")),
                }
            }
        }
        if failures.is_empty() {
            Ok(format!(
                "base set builds; {probes} values (NaN and just outside each finite bound of {} parameters) refused with errors naming the parameter",
                subject.params.len()
            ))
        } else {
            Err(format!(
                "{} of {probes} probes failed: {}",
                failures.len(),
                failures.join("; ")
            ))
        }
    })();
    CheckResult {
        check: CHECKS[11],
        formulation: None,
        passed: outcome.is_ok(),
        detail: outcome.unwrap_or_else(|e| e),
    }
}
