//! Properties of the four kinematic formulations of friction-math §4, driven
//! through the shared return mapping (`plugins_api::return_mapping::step`).

use friction_laws::formulations::{Convective, Jaumann, Lagrangian, UpdatedLagrangian};
use plugins_api::kinematics::{cayley, skew};
use plugins_api::return_mapping::{PointState, StepInput, StepOutput, TangentMode, step};
use plugins_api::{
    CriticalShear, DirectionInputs, FrictionLaw, KinematicFormulation, Mat3, ShearInputs,
    StepKinematics, Vec3,
};

// ---------------------------------------------------------------- test laws

/// Amontons–Coulomb, `τ_c = μ p` (friction-math §3, eq. 2.13), defined here so
/// these tests do not depend on the built-in laws.
struct Coulomb {
    mu: f64,
    k_t: f64,
}

impl FrictionLaw for Coulomb {
    fn name(&self) -> &str {
        "test-coulomb"
    }
    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        CriticalShear {
            tau: self.mu * x.p,
            dtau_dp: self.mu,
            ..CriticalShear::default()
        }
    }
}

/// Work-dependent test law `τ_c = max(a0 + a1 ω, 0) p` (the linear WH form of
/// friction-math §3, eqs. 2.17–2.19), clamped at zero.
struct WorkLaw {
    a0: f64,
    a1: f64,
    k_t: f64,
}

impl FrictionLaw for WorkLaw {
    fn name(&self) -> &str {
        "test-work"
    }
    fn stick_stiffness(&self) -> f64 {
        self.k_t
    }
    fn work_dependent(&self) -> bool {
        true
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        let mu = self.a0 + self.a1 * x.omega;
        if mu <= 0.0 {
            CriticalShear {
                clamped: true,
                ..CriticalShear::default()
            }
        } else {
            CriticalShear {
                tau: mu * x.p,
                dtau_dp: mu,
                dtau_domega: self.a1 * x.p,
                ..CriticalShear::default()
            }
        }
    }
}

const K_T: f64 = 1e5;
const COULOMB: Coulomb = Coulomb {
    mu: 0.144,
    k_t: K_T,
};
/// Thesis square-cup WH fit in N–mm units (friction-math §7): β = 0.1448, α = -8.757e-5 mm/N.
const WORK: WorkLaw = WorkLaw {
    a0: 0.1448,
    a1: -8.757e-5,
    k_t: K_T,
};

fn formulations() -> [(&'static str, &'static dyn KinematicFormulation); 4] {
    [
        ("convective", &Convective),
        ("jaumann", &Jaumann),
        ("lagrangian", &Lagrangian),
        ("updated-lagrangian", &UpdatedLagrangian),
    ]
}

fn laws() -> [(&'static str, &'static dyn FrictionLaw); 2] {
    [("coulomb", &COULOMB), ("work", &WORK)]
}

// ---------------------------------------------------------------- histories

/// Inverse Cayley map: the mid-step gradient `L` with `cay(Δt L) = ΔF` exactly,
/// `L = (2/Δt)(ΔF - I)(ΔF + I)⁻¹`.
fn inverse_cayley(df: &Mat3, dt: f64) -> Mat3 {
    (2.0 / dt)
        * (df - Mat3::identity())
        * (df + Mat3::identity())
            .try_inverse()
            .expect("ΔF + I invertible")
}

/// Rotation by angle `a` about the unit axis `e` (Rodrigues).
fn rotation(e: &Vec3, a: f64) -> Mat3 {
    let k = skew(e);
    Mat3::identity() + a.sin() * k + (1.0 - a.cos()) * k * k
}

/// How the mid-step velocity gradient of a history is obtained.
#[derive(Clone, Copy, Debug, PartialEq)]
enum VelGrad {
    /// `L = Ḟ F⁻¹` evaluated analytically at mid-step (what an engine computes from
    /// mid-step velocities); `cay(Δt L)` then differs from `F_{n+1} F_n⁻¹` by `O(Δt³)`.
    Analytic,
    /// `L = inverse_cayley(F_{n+1} F_n⁻¹)`: the step gradients of TL and UL coincide.
    Consistent,
    /// `L = (F_{n+1} F_n⁻¹ - I)/Δt`, a forward-difference velocity gradient that is
    /// inconsistent with `F` at first order: `cay(Δt L) - F_{n+1} F_n⁻¹ = O(Δt²)` per step.
    ForwardDifference,
}

/// Blank-point state at normalised time `s ∈ [0, 1]` (duration 1 s).
#[derive(Clone, Copy, Debug)]
struct Snap {
    /// Unit tool normal at the contact point.
    n: Vec3,
    /// Contact point on the (fixed) tool surface; slip increments are its differences.
    c: Vec3,
    /// Pressure (MPa).
    p: f64,
    /// Blank deformation gradient.
    f: Mat3,
    /// Its rate `Ḟ` (1/s).
    f_rate: Mat3,
}

/// A smooth blank motion: rigid spin `β` (rad/s) about `axis` times the stretch
/// `I + s A + s² B`; `F = Rot(axis, β s)(I + s A + s² B)`.
#[derive(Clone, Copy, Debug)]
struct Blank {
    axis: Vec3,
    beta: f64,
    a: Mat3,
    b: Mat3,
}

impl Blank {
    fn rigid_fixed() -> Self {
        Self {
            axis: Vec3::z(),
            beta: 0.0,
            a: Mat3::zeros(),
            b: Mat3::zeros(),
        }
    }
    fn spinning(beta: f64) -> Self {
        Self {
            axis: Vec3::new(0.3, -0.5, 0.8).normalize(),
            beta,
            ..Self::rigid_fixed()
        }
    }
    fn deforming(beta: f64) -> Self {
        Self {
            a: Mat3::new(0.20, 0.15, -0.05, -0.10, -0.12, 0.08, 0.04, 0.06, -0.07),
            b: Mat3::new(-0.06, 0.05, 0.02, 0.09, 0.08, -0.03, 0.01, -0.04, 0.03),
            ..Self::spinning(beta)
        }
    }
    fn f(&self, s: f64) -> (Mat3, Mat3) {
        let r = rotation(&self.axis, self.beta * s);
        let r_rate = self.beta * skew(&self.axis) * r;
        let u = Mat3::identity() + s * self.a + s * s * self.b;
        let u_rate = self.a + 2.0 * s * self.b;
        (r * u, r_rate * u + r * u_rate)
    }
}

/// Sliding over a sphere of radius `r` centred at the origin: `n = (sinθ cosϕ, sinθ sinϕ, cosθ)`.
fn sphere_snap(r: f64, theta: f64, phi: f64, p: f64, blank: &Blank, s: f64) -> Snap {
    let n = Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    );
    let (f, f_rate) = blank.f(s);
    Snap {
        n,
        c: r * n,
        p,
        f,
        f_rate,
    }
}

/// Build the step inputs of a history sampled at `N + 1` instants.
fn inputs_from(snaps: &[Snap], vel_grad: VelGrad, mid: &dyn Fn(f64) -> Snap) -> Vec<StepInput> {
    let steps = snaps.len() - 1;
    let dt = 1.0 / steps as f64;
    (0..steps)
        .map(|i| {
            let (a, b) = (&snaps[i], &snaps[i + 1]);
            let l = match vel_grad {
                VelGrad::Analytic => {
                    let m = mid((i as f64 + 0.5) * dt);
                    m.f_rate * m.f.try_inverse().unwrap()
                }
                VelGrad::Consistent => inverse_cayley(&(b.f * a.f.try_inverse().unwrap()), dt),
                VelGrad::ForwardDifference => {
                    (b.f * a.f.try_inverse().unwrap() - Mat3::identity()) / dt
                }
            };
            let kin = StepKinematics {
                dt,
                n_old: a.n,
                n_new: b.n,
                tool_rotation: Mat3::identity(),
                vel_grad: l,
                f_old: a.f,
                f_new: b.f,
            };
            StepInput::new(b.p, b.c - a.c, kin)
        })
        .collect()
}

/// A parametrised curved-tool history.
#[derive(Clone, Copy, Debug)]
struct CurvedHistory {
    /// Sphere radius (mm).
    radius: f64,
    /// `θ(s)`, `ϕ(s)` of the contact point.
    path: fn(f64) -> (f64, f64),
    /// Pressure `p(s)` (MPa).
    pressure: fn(f64) -> f64,
    blank: Blank,
    vel_grad: VelGrad,
}

impl CurvedHistory {
    fn snap(&self, s: f64) -> Snap {
        let (theta, phi) = (self.path)(s);
        sphere_snap(self.radius, theta, phi, (self.pressure)(s), &self.blank, s)
    }
    fn inputs(&self, steps: usize) -> Vec<StepInput> {
        let snaps: Vec<Snap> = (0..=steps)
            .map(|i| self.snap(i as f64 / steps as f64))
            .collect();
        inputs_from(&snaps, self.vel_grad, &|s| self.snap(s))
    }
}

/// Smoothly turning path without reversal (θ grows, ϕ accelerates).
fn turning_path(s: f64) -> (f64, f64) {
    (0.4 + 0.5 * s, 0.2 + 0.6 * s + 0.9 * s * s)
}

/// Back-and-forth path: the sliding velocity reverses smoothly at s = 1/3 and 1.
fn reversing_path(s: f64) -> (f64, f64) {
    (
        0.5 + 0.3 * (1.5 * std::f64::consts::PI * s).sin(),
        0.3 + 0.8 * s * s,
    )
}

fn smooth_pressure(s: f64) -> f64 {
    80.0 + 30.0 * (2.0 * std::f64::consts::PI * s).sin() + 10.0 * s
}

/// Run one law × formulation over a history from a fresh state.
fn run(
    law: &dyn FrictionLaw,
    form: &dyn KinematicFormulation,
    inputs: &[StepInput],
) -> Vec<(StepOutput, PointState)> {
    let mut state = PointState::default();
    inputs
        .iter()
        .map(|input| {
            let out = step(law, form, TangentMode::None, &mut state, input).expect("step succeeds");
            (out, state)
        })
        .collect()
}

/// A rigid superposed motion `Q(t)` with constant spin `Ω`:
/// `Q_{n+1} = cay(Δt Ω) Q_n`, so every increment is an exact Cayley rotation.
fn superposed_rotations(steps: usize) -> Vec<Mat3> {
    let dt = 1.0 / steps as f64;
    let increment = cayley(&(dt * skew(&Vec3::new(0.7, -1.1, 0.4))));
    let mut q = vec![cayley(&skew(&Vec3::new(0.3, 0.2, -0.5)))];
    for i in 0..steps {
        q.push(increment * q[i]);
    }
    q
}

/// The same step seen by an observer rotated by `Q`: `n' = Q n`, `Δu' = Q_{n+1} Δu`,
/// tool increment `Q_{n+1} R Q_nᵀ` (= `ΔQ R` for a fixed base tool), `F' = Q F`,
/// `L' = inverse_cayley(Q_{n+1} cay(Δt L) Q_nᵀ)`.
fn rotate_input(input: &StepInput, q0: &Mat3, q1: &Mat3) -> StepInput {
    let k = &input.kin;
    let df = q1 * cayley(&(k.dt * k.vel_grad)) * q0.transpose();
    let kin = StepKinematics {
        dt: k.dt,
        n_old: q0 * k.n_old,
        n_new: q1 * k.n_new,
        tool_rotation: q1 * k.tool_rotation * q0.transpose(),
        vel_grad: inverse_cayley(&df, k.dt),
        f_old: q0 * k.f_old,
        f_new: q1 * k.f_new,
    };
    StepInput {
        kin,
        du: q1 * input.du,
        ..*input
    }
}

/// Objectivity discrepancies of one law × formulation over a history:
/// `(global traction, global ω, local traction, local ΔD)`, each relative:
/// global = `max_n |t'_n - Q_n t_n| / max_n |t_n|` and `max_n |ω'_n - ω_n| / ω_N` along
/// the two runs; local = the same for one step started from the exactly rotated state.
fn objectivity_errors(
    law: &dyn FrictionLaw,
    form: &dyn KinematicFormulation,
    inputs: &[StepInput],
) -> [f64; 4] {
    let q = superposed_rotations(inputs.len());
    let base = run(law, form, inputs);
    let rotated: Vec<StepInput> = inputs
        .iter()
        .enumerate()
        .map(|(i, x)| rotate_input(x, &q[i], &q[i + 1]))
        .collect();
    let primed = run(law, form, &rotated);
    let t_max = base.iter().map(|(o, _)| o.t.norm()).fold(0.0, f64::max);
    let omega_end = base.last().unwrap().1.omega;
    let d_max = base.iter().map(|(o, _)| o.dissipation).fold(0.0, f64::max);
    let mut e = [0.0_f64; 4];
    let mut state = PointState::default();
    for (i, ((b, bs), (p, ps))) in base.iter().zip(&primed).enumerate() {
        e[0] = e[0].max((p.t - q[i + 1] * b.t).norm() / t_max);
        e[1] = e[1].max((ps.omega - bs.omega).abs() / omega_end);
        let mut local = PointState {
            t: q[i] * state.t,
            ..state
        };
        let out =
            step(law, form, TangentMode::None, &mut local, &rotated[i]).expect("step succeeds");
        e[2] = e[2].max((out.t - q[i + 1] * b.t).norm() / t_max);
        e[3] = e[3].max((out.dissipation - b.dissipation).abs() / d_max);
        state = *bs;
    }
    e
}

/// Observed order `log2(e(N)/e(2N))`.
fn order(coarse: f64, fine: f64) -> f64 {
    (coarse / fine).log2()
}

/// One objectivity case: base history, law, formulation; errors at N and 2N.
fn objectivity_case(
    blank: Blank,
    law: &dyn FrictionLaw,
    form: &dyn KinematicFormulation,
    steps: usize,
) -> ([f64; 4], [f64; 4]) {
    let history = |steps| {
        CurvedHistory {
            radius: 0.05,
            path: reversing_path,
            pressure: smooth_pressure,
            blank,
            vel_grad: VelGrad::Analytic,
        }
        .inputs(steps)
    };
    (
        objectivity_errors(law, form, &history(steps)),
        objectivity_errors(law, form, &history(2 * steps)),
    )
}

/// friction-math §4, "Objectivity": superpose a rigid rotation `Q(t)` (constant
/// spin, exact Cayley increments) on tool, blank and history; tractions and the
/// frictional work `ω` must rotate with, resp. not see, `Q`.
///
/// Base histories: back-and-forth sliding over a sphere (R = 0.05 mm; stick at
/// the reversals, slip in varying directions, smooth p), blank spinning rigidly
/// (`rigid`) or deforming and spinning (`deforming`); both test laws; N = 400 and 800.
///
/// Exact (tolerance 1e-11 relative, round-off over 400 steps; measured ≤ 2e-13):
/// tractions AND `ω` of every formulation with both laws, except `jaumann` on the
/// deforming blank. The rate-based directions `d = forward_direction(t*, t_end,
/// n_{n+1})` read only objective quantities, so `c = φ_tr·d` and with it `ΔD` and
/// `ω` are frame-indifferent as soon as `t*` is.
///
/// Not exact: `jaumann` on a deforming blank. The observer's `L'` is the inverse
/// Cayley of `Q_{n+1} cay(Δt L) Q_nᵀ`; its skew part equals the rotated spin plus
/// `Ω` only up to commutators of `Ω` with the stretching, `O(Δt³)` per step, so
/// `cay(Δt W')` is not `Q_{n+1} cay(Δt W) Q_nᵀ`. Measured at N = 400 (both laws):
/// accumulated traction 1.4e-10 (order 1.99), local 3.5e-11 (order 2.82).
/// Asserted: both above 1e-12, orders 2 and 3 ± 0.3. The error is a rotation of
/// `t*` (both `R_W` and `R_surf` are rotations, `|t*|` is exact), so it reaches
/// `|t_tr|` and `c` only at second order: `ω` is objective to the round-off
/// tolerance (measured 2.7e-13 accumulated, 1.9e-12 per step), asserted ≤ 1e-11.
#[test]
fn objectivity_under_superposed_rigid_rotation() {
    println!(
        "\nobjectivity: relative discrepancies (N = 400), local = one step from the rotated exact state; orders N=400->800"
    );
    println!(
        "{:10} {:8} {:20} {:>9} {:>9} {:>9} {:>9} | {:>6} {:>6} {:>6} {:>6}",
        "blank",
        "law",
        "formulation",
        "glob t",
        "glob w",
        "loc t",
        "loc dD",
        "ord gt",
        "ord gw",
        "ord lt",
        "ord lD"
    );
    const EXACT: f64 = 1e-11;
    for (blank_label, blank) in [
        ("rigid", Blank::spinning(0.8)),
        ("deforming", Blank::deforming(0.8)),
    ] {
        for (lname, law) in laws() {
            for (fname, form) in formulations() {
                let (e, e2) = objectivity_case(blank, law, form, 400);
                let o: Vec<f64> = (0..4).map(|i| order(e[i], e2[i])).collect();
                println!(
                    "{blank_label:10} {lname:8} {fname:20} {:9.2e} {:9.2e} {:9.2e} {:9.2e} | {:6.2} {:6.2} {:6.2} {:6.2}",
                    e[0], e[1], e[2], e[3], o[0], o[1], o[2], o[3]
                );
                let case = format!("{blank_label}/{lname}/{fname}");
                if !(fname == "jaumann" && blank_label == "deforming") {
                    assert!(
                        e.iter().chain(&e2).all(|&v| v <= EXACT),
                        "{case}: {e:?} {e2:?}"
                    );
                    continue;
                }
                // Tractions: measurably above the round-off of the exact cases, vanishing
                // at the orders of the transport error.
                assert!(
                    e[0] > 1e-12 && e[2] > 1e-12,
                    "{case}: expected measurable traction discrepancies, got {e:?}"
                );
                assert!(
                    (o[0] - 2.0).abs() <= 0.3,
                    "{case}: accumulated traction order {} (expected 2)",
                    o[0]
                );
                assert!(
                    (o[2] - 3.0).abs() <= 0.3,
                    "{case}: local traction order {} (expected 3)",
                    o[2]
                );
                // Work: the error is a rotation of t* (|t*| exact), which enters |t_tr|
                // and c only at second order: ω stays objective to the round-off tolerance.
                assert!(
                    e[1] <= EXACT && e[3] <= EXACT && e2[1] <= EXACT && e2[3] <= EXACT,
                    "{case}: ω {e:?} {e2:?}"
                );
            }
        }
    }
}

/// Flat tool, straight sliding with a smooth reversal, no blank deformation or spin.
fn flat_translation(steps: usize) -> Vec<StepInput> {
    let snaps: Vec<Snap> = (0..=steps)
        .map(|i| {
            let s = i as f64 / steps as f64;
            let x = 0.02 * (1.5 * std::f64::consts::PI * s).sin();
            Snap {
                n: Vec3::z(),
                c: Vec3::new(x, 0.0, 0.0),
                p: smooth_pressure(s),
                f: Mat3::identity(),
                f_rate: Mat3::zeros(),
            }
        })
        .collect();
    inputs_from(&snaps, VelGrad::Analytic, &|_| Snap {
        n: Vec3::z(),
        c: Vec3::zeros(),
        p: 0.0,
        f: Mat3::identity(),
        f_rate: Mat3::zeros(),
    })
}

/// friction-math §4, "Pure translation of the blank over a flat tool: all four
/// give the same answer". Straight sliding then reversal (stick, then slip the
/// other way), W = 0, F = I. Tolerance 1e-14 relative on every traction and on ω
/// (the rate-based `d` equals `φ_tr` up to round-off here).
#[test]
fn pure_translation_over_flat_tool_all_formulations_agree() {
    let inputs = flat_translation(400);
    for (lname, law) in laws() {
        let reference = run(law, &Convective, &inputs);
        let t_max = reference
            .iter()
            .map(|(o, _)| o.t.norm())
            .fold(0.0, f64::max);
        let omega_end = reference.last().unwrap().1.omega;
        assert!(reference.iter().any(|(o, _)| o.stick) && reference.iter().any(|(o, _)| !o.stick));
        for (fname, form) in formulations() {
            let res = run(law, form, &inputs);
            for (i, ((a, sa), (b, sb))) in reference.iter().zip(&res).enumerate() {
                assert!(
                    (a.t - b.t).norm() <= 1e-14 * t_max,
                    "{lname}/{fname} step {i}: {} vs {}",
                    a.t,
                    b.t
                );
                assert!(
                    (sa.omega - sb.omega).abs() <= 1e-14 * omega_end,
                    "{lname}/{fname} step {i}: ω {} vs {}",
                    sa.omega,
                    sb.omega
                );
            }
        }
    }
}

/// friction-math §4: "`jaumann` equals `convective` exactly whenever W = 0".
/// Curved tool (sphere R = 0.05 mm, back-and-forth path), fixed tool, blank
/// without spin. The transports are compared bit for bit at every step of the
/// history, and so are the Coulomb tractions (which do not depend on `d`).
///
/// `ω` is not identical: jaumann's `d = forward_direction(t*, t_end)` is not
/// `φ_tr`. For a turn `α = O(Δt)` per step and `r = |t_end|/|t*| = 1 + O(Δt)`,
/// the angle between `d` and `φ_tr` is `atan(r sin α) - α = (r - 1)α - α³/2 + … =
/// O(Δt²)`, so `1 - c = O(Δt⁴)` per step; times `ΔD = O(Δt)` per step over
/// `O(1/Δt)` steps the relative ω difference is `O(Δt⁴)`. Measured for N = 100·2^k
/// (printed): 3.6e-7 at N = 100, 1.8e-13 at N = 3200, orders 4.6, 4.2, 3.9, 4.0,
/// 4.2; asserted 4 ± 0.3 on the pairs from N = 200. The work-law tractions differ
/// through ω (`τ_c = μ(ω) p`): relative difference `|a1| ω/μ · |Δω|/ω`, asserted
/// within 5 % (measured ratio 1.006–1.011 at N = 100…800; checked while above round-off).
#[test]
fn jaumann_equals_convective_without_spin() {
    let h = |steps| {
        CurvedHistory {
            radius: 0.05,
            path: reversing_path,
            pressure: smooth_pressure,
            blank: Blank::rigid_fixed(),
            vel_grad: VelGrad::Analytic,
        }
        .inputs(steps)
    };
    let inputs = h(400);
    for (lname, law) in laws() {
        let conv = run(law, &Convective, &inputs);
        let jau = run(law, &Jaumann, &inputs);
        for (i, input) in inputs.iter().enumerate() {
            let (before_c, before_j) = if i == 0 {
                (Vec3::zeros(), Vec3::zeros())
            } else {
                (conv[i - 1].1.t, jau[i - 1].1.t)
            };
            assert_eq!(
                Jaumann.transport(&before_c, &input.kin),
                Convective.transport(&before_c, &input.kin),
                "{lname} step {i}"
            );
            assert_eq!(
                Jaumann.transport(&before_j, &input.kin),
                Convective.transport(&before_j, &input.kin),
                "{lname} step {i}"
            );
            if lname == "coulomb" {
                assert_eq!(conv[i].0.t, jau[i].0.t, "step {i}");
            }
        }
    }
    println!(
        "\njaumann vs convective, W = 0, curved path: final |ω_J - ω_C|/ω_C and |t_J - t_C|/|t_C|"
    );
    for (lname, law) in laws() {
        let mut dw = vec![];
        let mut dt = vec![];
        let mut runs_omega = vec![];
        for k in 0..6 {
            let inputs = h(100 << k);
            let (tc, sc) = *run(law, &Convective, &inputs).last().unwrap();
            let (tj, sj) = *run(law, &Jaumann, &inputs).last().unwrap();
            dw.push((sj.omega - sc.omega).abs() / sc.omega);
            runs_omega.push(sc.omega);
            dt.push((tj.t - tc.t).norm() / tc.t.norm());
        }
        let orders: Vec<f64> = dw.windows(2).map(|w| order(w[0], w[1])).collect();
        println!(
            "  {lname:8} ω diff {:?}\n  {lname:8} orders {:?}\n  {lname:8} t diff {:?}",
            fmt_all(&dw),
            fmt_all(&orders),
            fmt_all(&dt)
        );
        assert!(
            orders[1..].iter().all(|&o| (o - 4.0).abs() <= 0.3),
            "{lname}: orders {orders:?}"
        );
        for (k, (&t, &w)) in dt.iter().zip(&dw).enumerate() {
            if lname == "coulomb" {
                assert_eq!(
                    t,
                    0.0,
                    "Coulomb tractions must be identical (N = {})",
                    100 << k
                );
            } else if k <= 3 {
                // |Δτ|/τ = |a1| ω/μ(ω) · |Δω|/ω for τ_c = μ(ω) p (last step slipping);
                // the direction of φ_tr differs only at higher order: 5 %.
                let omega = runs_omega[k];
                let expected = WORK.a1.abs() * omega / (WORK.a0 + WORK.a1 * omega) * w;
                println!(
                    "  {lname:8} N = {:4}: t diff / (|a1| ω/μ · ω diff) = {:.3}",
                    100 << k,
                    t / expected
                );
                assert!(
                    (0.95..=1.05).contains(&(t / expected)),
                    "N = {}: t diff {t:e}, expected ~{expected:e}",
                    100 << k
                );
            }
        }
    }
}

fn fmt_all(v: &[f64]) -> Vec<String> {
    v.iter().map(|x| format!("{x:.3e}")).collect()
}

/// friction-math §4: "`lagrangian` and `updated-lagrangian` agree to O(Δt) on
/// smooth histories". Smooth deforming, spinning blank sliding over a sphere
/// (R = 0.05 mm, turning path), N = 100·2^k, both laws; final traction
/// `|t_TL - t_UL|/|t_TL|` and `|ω_TL - ω_UL|/ω_TL`.
///
/// Both use the same `d = forward_direction(t*, t_end)`, so they differ only
/// through their transports, `P F_{n+1} F_n⁻¹ t_n` vs `P cay(Δt L) t_n`:
/// - `Consistent` (`L` the inverse Cayley of `F_{n+1} F_n⁻¹`, the exact mid-step
///   gradient): same step gradient up to round-off, so they coincide step by
///   step. Asserted: every traction and ω along the history (not only the final
///   ones) within 1e-12 relative, both laws.
/// - `ForwardDifference` (`L = (F_{n+1} F_n⁻¹ - I)/Δt`): the step gradients differ
///   by `O(Δt²)` per step, so tractions and ω by `O(Δt)`: order 1 ± 0.3 asserted
///   on all pairs (this is the `O(Δt)` of friction-math §4).
/// - `Analytic` (`L = Ḟ F⁻¹` at mid-step, what an engine computes from mid-step
///   velocities): `cay(Δt L)` differs from the step gradient by `O(Δt³)`, so the
///   difference is `O(Δt²)`: order 2 ± 0.3 asserted on all pairs.
#[test]
fn lagrangian_and_updated_lagrangian_agree_on_smooth_deforming_history() {
    println!(
        "\nlagrangian vs updated-lagrangian (sphere R = 0.05 mm, deforming blank): final |Δt_vec|/|t| and |Δω|/ω, N = 100·2^k"
    );
    for vel_grad in [
        VelGrad::Consistent,
        VelGrad::ForwardDifference,
        VelGrad::Analytic,
    ] {
        let h = CurvedHistory {
            radius: 0.05,
            path: turning_path,
            pressure: smooth_pressure,
            blank: Blank::deforming(0.8),
            vel_grad,
        };
        for (lname, law) in laws() {
            let mut dt_diff = vec![];
            let mut dw_diff = vec![];
            for k in 0..6 {
                let inputs = h.inputs(100 << k);
                let tl = run(law, &Lagrangian, &inputs);
                let ul = run(law, &UpdatedLagrangian, &inputs);
                let ((a, sa), (b, sb)) = (tl.last().unwrap(), ul.last().unwrap());
                dt_diff.push((a.t - b.t).norm() / a.t.norm());
                dw_diff.push((sa.omega - sb.omega).abs() / sa.omega);
                if vel_grad == VelGrad::Consistent {
                    let t_max = tl.iter().map(|(o, _)| o.t.norm()).fold(0.0, f64::max);
                    for (i, ((x, sx), (y, sy))) in tl.iter().zip(&ul).enumerate() {
                        assert!(
                            (x.t - y.t).norm() <= 1e-12 * t_max
                                && (sx.omega - sy.omega).abs() <= 1e-12 * sa.omega,
                            "{lname} N = {} step {i}: {} vs {}, ω {} vs {}",
                            100 << k,
                            x.t,
                            y.t,
                            sx.omega,
                            sy.omega
                        );
                    }
                }
            }
            let ot: Vec<f64> = dt_diff.windows(2).map(|w| order(w[0], w[1])).collect();
            let ow: Vec<f64> = dw_diff.windows(2).map(|w| order(w[0], w[1])).collect();
            if vel_grad == VelGrad::Consistent {
                println!(
                    "  {:17} {lname:8} t diff {:?}, ω diff {:?} (round-off, no orders)",
                    format!("{vel_grad:?}"),
                    fmt_all(&dt_diff),
                    fmt_all(&dw_diff)
                );
                continue;
            }
            println!(
                "  {:17} {lname:8} t diff {:?} orders {:?}",
                format!("{vel_grad:?}"),
                fmt_all(&dt_diff),
                fmt_all(&ot)
            );
            println!(
                "  {:17} {lname:8} ω diff {:?} orders {:?}",
                format!("{vel_grad:?}"),
                fmt_all(&dw_diff),
                fmt_all(&ow)
            );
            let expected = if vel_grad == VelGrad::ForwardDifference {
                1.0
            } else {
                2.0
            };
            assert!(
                ot.iter().chain(&ow).all(|o| (o - expected).abs() <= 0.3),
                "{vel_grad:?}/{lname}: traction orders {ot:?}, ω orders {ow:?}"
            );
        }
    }
}

/// A cylinder of radius `r` about the y axis; the normal at angle `a` computed
/// as `x_u × x_v / |x_u × x_v|` from one of two parametrisations (so the normals
/// differ by round-off, as they would between two CAD patches):
/// - one patch: `x(u, v) = (r sin u, v, r cos u)`, `u = a`;
/// - two patches meeting at the seam `a = 0`: for `a < 0`, `a = 0.7 (u - 1)`,
///   `x(u, v) = (r sin a, 1.3 v, r cos a)`; for `a ≥ 0` the reversed
///   `a = 0.9 (1 - w)`, whose `x_w × x_v` points inwards and is flipped towards the blank.
fn cylinder_normal(r: f64, a: f64, two_patches: bool) -> Vec3 {
    let (x_u, x_v) = if !two_patches {
        (Vec3::new(r * a.cos(), 0.0, -r * a.sin()), Vec3::y())
    } else if a < 0.0 {
        let u = a / 0.7 + 1.0;
        let a = 0.7 * (u - 1.0);
        (
            0.7 * Vec3::new(r * a.cos(), 0.0, -r * a.sin()),
            1.3 * Vec3::y(),
        )
    } else {
        let w = 1.0 - a / 0.9;
        let a = 0.9 * (1.0 - w);
        (-0.9 * Vec3::new(r * a.cos(), 0.0, -r * a.sin()), Vec3::y())
    };
    let n = x_u.cross(&x_v).normalize();
    // Orient towards the blank (outside the cylinder), as a tool's patch flag would.
    if n.dot(&Vec3::new(a.sin(), 0.0, a.cos())) < 0.0 {
        -n
    } else {
        n
    }
}

/// friction-math §4 (convective row): parallel transport is "independent of the
/// surface parametrisation, so nothing jumps at patch seams". The same physical
/// path over a cylinder (R = 0.05 mm, crossing the seam at mid-path), normals from
/// one patch or from two patches (the second with reversed u); spinning deforming
/// blank. Traction histories identical to 1e-12 relative for every formulation
/// (required of `convective` and `jaumann`; the others hold too).
#[test]
fn seam_independence_on_cylinder() {
    let (r, steps) = (0.05, 400);
    let blank = Blank::deforming(0.8);
    let history = |two_patches: bool| {
        let snaps: Vec<Snap> = (0..=steps)
            .map(|i| {
                let s = i as f64 / steps as f64;
                let a = -0.6 + 1.2 * s + 0.1 * (3.0 * s).sin();
                let y = 0.03 * s * s;
                let n = cylinder_normal(r, a, two_patches);
                let (f, f_rate) = blank.f(s);
                Snap {
                    n,
                    c: Vec3::new(r * a.sin(), y, r * a.cos()),
                    p: smooth_pressure(s),
                    f,
                    f_rate,
                }
            })
            .collect();
        inputs_from(&snaps, VelGrad::Consistent, &|_| unreachable!())
    };
    let (one, two) = (history(false), history(true));
    let max_normal_gap = one
        .iter()
        .zip(&two)
        .map(|(a, b)| (a.kin.n_new - b.kin.n_new).norm())
        .fold(0.0, f64::max);
    println!("\nseam: max |n_one - n_two| = {max_normal_gap:.2e}");
    for (lname, law) in laws() {
        for (fname, form) in formulations() {
            let a = run(law, form, &one);
            let b = run(law, form, &two);
            let t_max = a.iter().map(|(o, _)| o.t.norm()).fold(0.0, f64::max);
            let gap = a
                .iter()
                .zip(&b)
                .map(|((x, _), (y, _))| (x.t - y.t).norm() / t_max)
                .fold(0.0, f64::max);
            let w_gap = (a.last().unwrap().1.omega - b.last().unwrap().1.omega).abs()
                / a.last().unwrap().1.omega;
            println!("  {lname:8} {fname:20} max traction gap {gap:.2e}, ω gap {w_gap:.2e}");
            assert!(
                gap <= 1e-12 && w_gap <= 1e-12,
                "{lname}/{fname}: {gap:e} {w_gap:e}"
            );
        }
    }
}

/// Orders `log2(|x_k - x_{k+1}| / |x_{k+1} - x_{k+2}|)` from consecutive refinements
/// (no reference solution needed).
fn three_level_orders(values: &[f64]) -> Vec<f64> {
    let d: Vec<f64> = values.windows(2).map(|w| (w[0] - w[1]).abs()).collect();
    d.windows(2).map(|w| order(w[0], w[1])).collect()
}

/// friction-math §4, "Every formulation converges as Δt → 0 at its expected order".
///
/// History: sliding over a sphere along a turning path (direction changes
/// continuously), smooth p(t), spinning and deforming blank, 1 s; N = 100·2^k
/// steps, k = 0..5. Observed orders from three consecutive levels, for the
/// final traction (vector difference) and ω.
///
/// Expected order 1 for every formulation, traction and ω: the radial return is
/// backward Euler (local error O(Δt²)); each transport is consistent to O(Δt²)
/// per step (exact rotations, exact step gradients), and the rate-based `d`
/// differs from `φ_tr` by `O(Δt²)` in angle, so it enters `c` at `O(Δt⁴)`.
///
/// Two regimes: `resolved` (R = 0.05 mm: the slip per step is comparable to or
/// below the elastic slip τ_c/k_T ≈ 1.3e-4 mm) and `unresolved` (R = 50 mm: slip
/// per step 100–3000 × τ_c/k_T). With `d = forward_direction(t*, t_end)` (built
/// from the end traction, not from the trial) both regimes are clean: every
/// order of the table is 1 ± 0.3, asserted on every triple. In the unresolved
/// regime the rate-based ω at N = 100 must also be as close to convective's as
/// the formulations are in the limit: asserted `|ω_f(100)/ω_C(100) - 1|` below a
/// tenth of convective's own discretisation error `|ω_C(100) - ω_C(3200)|/ω_C(3200)`.
#[test]
fn convergence_orders_as_dt_goes_to_zero() {
    println!(
        "\nconvergence orders (three-level, N = 100·2^k, triples (100,200,400) … (800,1600,3200)); rel = ω(100)/ω_convective(100) - 1"
    );
    for (regime, radius) in [("resolved", 0.05), ("unresolved", 50.0)] {
        let h = CurvedHistory {
            radius,
            path: turning_path,
            pressure: smooth_pressure,
            blank: Blank::deforming(0.8),
            vel_grad: VelGrad::Analytic,
        };
        let inputs: Vec<Vec<StepInput>> = (0..6).map(|k| h.inputs(100 << k)).collect();
        println!("{regime} (R = {radius} mm)");
        println!(
            "  {:8} {:20} {:>26} {:>26}  {:>10} {:>10} {:>9}",
            "law", "formulation", "orders t", "orders ω", "ω(N=100)", "ω(N=3200)", "rel"
        );
        for (lname, law) in laws() {
            let mut conv_omega = [0.0; 6];
            for (fname, form) in formulations() {
                let finals: Vec<(Vec3, f64)> = inputs
                    .iter()
                    .map(|inp| {
                        let (o, s) = *run(law, form, inp).last().unwrap();
                        (o.t, s.omega)
                    })
                    .collect();
                if fname == "convective" {
                    for (c, f) in conv_omega.iter_mut().zip(&finals) {
                        *c = f.1;
                    }
                }
                let d_t: Vec<f64> = finals
                    .windows(2)
                    .map(|w| (w[0].0 - w[1].0).norm())
                    .collect();
                let o_t: Vec<f64> = d_t.windows(2).map(|w| order(w[0], w[1])).collect();
                let o_w = three_level_orders(&finals.iter().map(|f| f.1).collect::<Vec<_>>());
                let rel = finals[0].1 / conv_omega[0] - 1.0;
                let f2 = |v: &[f64]| {
                    v.iter()
                        .map(|x| format!("{x:5.2}"))
                        .collect::<Vec<_>>()
                        .join(" ")
                };
                println!(
                    "  {lname:8} {fname:20} {:>26} {:>26}  {:10.4e} {:10.4e} {rel:9.1e}",
                    f2(&o_t),
                    f2(&o_w),
                    finals[0].1,
                    finals[5].1
                );
                assert!(
                    o_t.iter().chain(&o_w).all(|o| (o - 1.0).abs() <= 0.3),
                    "{regime}/{lname}/{fname}: traction orders {o_t:?}, ω orders {o_w:?}"
                );
                if regime == "unresolved" {
                    let conv_error = (conv_omega[0] - conv_omega[5]).abs() / conv_omega[5];
                    assert!(
                        rel.abs() <= 0.1 * conv_error,
                        "{lname}/{fname}: ω(100) {rel:e} from convective, discretisation error {conv_error:e}"
                    );
                }
            }
        }
    }
}

/// friction-math §4, "Surface spin of the contact frame: ṅ = K v_T + Ω_tool × n",
/// `K = (1/R)(I - n⊗n)` for a sphere: the discrete spin `(n_{n+1} - n_n)/Δt` used
/// by the rate-based directions tends to `K v` at first order (forward difference).
/// Sphere R = 40 mm, point sliding along a curved path at ~100 mm/s; error
/// relative to |K v| at s = 0.3, observed order 1 ± 0.1 over Δt = 1e-3 … 1.25e-4.
#[test]
fn discrete_surface_spin_tends_to_curvature_times_velocity() {
    let r = 40.0;
    let angles = |s: f64| (0.5 + 1.5 * s + 0.4 * s * s, 0.1 + 2.0 * s);
    let normal = |s: f64| {
        let (t, p) = angles(s);
        Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    };
    let s = 0.3;
    let h = 1e-7;
    let velocity = r * (normal(s + h) - normal(s - h)) / (2.0 * h);
    let n = normal(s);
    let k_v = (Mat3::identity() - n * n.transpose()) * velocity / r;
    let errors: Vec<f64> = (0..4)
        .map(|k| {
            let dt = 1e-3 / f64::from(1 << k);
            ((normal(s + dt) - n) / dt - k_v).norm() / k_v.norm()
        })
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|w| order(w[0], w[1])).collect();
    println!(
        "\nsurface spin: |v| = {:.1} mm/s, rel. errors {:?}, orders {:?}",
        velocity.norm(),
        fmt_all(&errors),
        fmt_all(&orders)
    );
    assert!(orders.iter().all(|o| (o - 1.0).abs() <= 0.1), "{orders:?}");
}

/// The dissipated share `c = φ_tr·d` of one step, recomputed here from the
/// formulation exactly as the shared return mapping defines it (friction-math §2,
/// docs/friction.md step 5): `t* = P transport(t_n)`, `t_tr = t* - k_T P Δu_T`,
/// `t_end = τ_c(p, ω_n) φ_tr`, `d` normalised; `None` when the formulation gives no
/// usable direction (the return mapping then uses `φ_tr`, `c = 1`).
fn share(
    law: &dyn FrictionLaw,
    form: &dyn KinematicFormulation,
    state: &PointState,
    du: &Vec3,
    p: f64,
    kin: &StepKinematics,
) -> Option<f64> {
    let n = kin.n_new;
    let project = |v: Vec3| v - n * n.dot(&v);
    let t_star = project(form.transport(&state.t, kin));
    let t_trial = t_star - law.stick_stiffness() * project(*du);
    let phi = t_trial / t_trial.norm();
    let x = ShearInputs {
        p,
        omega: state.omega,
        sliding_speed: f64::NAN,
        flow_stress: f64::NAN,
        temperature: f64::NAN,
    };
    let t_end = phi * law.critical_shear(&x).tau;
    let d = form.slip_direction(&DirectionInputs {
        kin,
        t_old: state.t,
        p_old: state.p,
        t_star,
        t_trial,
        t_end,
        p_new: p,
    })?;
    let d = project(d).normalize();
    let c = d.dot(&phi);
    (c > 0.0).then_some(c)
}

/// friction-math §5, "tangents against central differences", for the
/// work-dependent law and the rate-based formulations, whose `c = φ_tr·d` depends
/// on `Δu_T` and `p` through `d` (the share-gradient term of the consistent
/// tangent, docs/friction.md step 6).
///
/// Curved-tool histories: turning path over a sphere, deforming spinning blank,
/// `unresolved` (R = 50 mm, N = 100: large slip per step, so a large share term)
/// and `resolved` (R = 0.05 mm, N = 400). At every slipping step with `|t_tr| ≥
/// (1 + 1e-3) τ` (away from the stick/slip kink) and a formulation direction:
/// `∂t/∂Δu_T` and `∂t/∂p` of `TangentMode::Consistent` against central differences
/// of the whole step (steps `1e-6 |t_tr|/k_T` and `1e-6 p`: truncation ~1e-12,
/// round-off ≤ 1e-9 relative). Tolerance 1e-6 relative (Frobenius / vector norm).
///
/// So that the check can fail when the share term is missing, the share term
/// `φ ⊗ ∇c · ∂τ/∂c` is estimated independently (central differences of [`share`],
/// `∂τ/∂c = τ_ω τ (|t_tr| - τ)/(k_T g)`, `g = 1 - τ_ω c (|t_tr| - 2τ)/k_T`) and
/// must exceed 1e-5 of the tangent (10× the tolerance) at some checked point of
/// the coarsest history (N = 25), and the tangent with it removed (`c` frozen)
/// must miss the central differences by as much there.
#[test]
fn consistent_tangent_of_work_law_matches_central_differences() {
    println!(
        "\nconsistent tangent vs central differences, work law (max relative errors; share = max |share term|/|tangent|)"
    );
    let k_t = WORK.k_t;
    for (regime, radius, steps) in [
        ("unresolved", 50.0, 25),
        ("unresolved", 50.0, 100),
        ("resolved", 0.05, 400),
    ] {
        let inputs = CurvedHistory {
            radius,
            path: turning_path,
            pressure: smooth_pressure,
            blank: Blank::deforming(0.8),
            vel_grad: VelGrad::Analytic,
        }
        .inputs(steps);
        for (fname, form) in formulations().into_iter().skip(1) {
            let (mut err_du, mut err_p, mut share_max, mut checked) =
                (0.0_f64, 0.0_f64, 0.0_f64, 0);
            let (mut frozen_du, mut frozen_p) = (0.0_f64, 0.0_f64);
            let mut state = PointState::default();
            for input in &inputs {
                let before = state;
                let out = step(&WORK, form, TangentMode::Consistent, &mut state, input)
                    .expect("step succeeds");
                let tau = out.t.norm();
                let norm_tr = tau + k_t * out.dgamma;
                let Some(c) = share(&WORK, form, &before, &input.du, input.p, &input.kin) else {
                    continue;
                };
                if out.stick || norm_tr < (1.0 + 1e-3) * tau {
                    continue;
                }
                checked += 1;
                let traction = |du: Vec3, p: f64| {
                    let mut s = before;
                    step(
                        &WORK,
                        form,
                        TangentMode::None,
                        &mut s,
                        &StepInput { du, p, ..*input },
                    )
                    .expect("step succeeds")
                    .t
                };
                let h = 1e-6 * norm_tr / k_t;
                let hp = 1e-6 * input.p;
                let mut fd = Mat3::zeros();
                let mut grad_c = Vec3::zeros();
                for j in 0..3 {
                    let mut e = Vec3::zeros();
                    e[j] = h;
                    let column = (traction(input.du + e, input.p)
                        - traction(input.du - e, input.p))
                        / (2.0 * h);
                    fd.set_column(j, &column);
                    let plus = share(&WORK, form, &before, &(input.du + e), input.p, &input.kin);
                    let minus = share(&WORK, form, &before, &(input.du - e), input.p, &input.kin);
                    grad_c[j] = (plus.unwrap_or(1.0) - minus.unwrap_or(1.0)) / (2.0 * h);
                }
                let fd_p = (traction(input.du, input.p + hp) - traction(input.du, input.p - hp))
                    / (2.0 * hp);
                err_du = err_du.max((fd - out.tangent).norm() / out.tangent.norm());
                err_p = err_p.max((fd_p - out.dt_dp).norm() / out.dt_dp.norm());
                // Independent estimate of the share term.
                let x = ShearInputs {
                    p: input.p,
                    omega: state.omega,
                    sliding_speed: f64::NAN,
                    flow_stress: f64::NAN,
                    temperature: f64::NAN,
                };
                let tau_w = WORK.critical_shear(&x).dtau_domega;
                let g = 1.0 - tau_w * c * (norm_tr - 2.0 * tau) / k_t;
                let dtau_dc = tau_w * tau * (norm_tr - tau) / (k_t * g);
                let phi = out.t / tau;
                let share_term = phi * grad_c.transpose() * dtau_dc;
                let dc_dp = (share(&WORK, form, &before, &input.du, input.p + hp, &input.kin)
                    .unwrap_or(1.0)
                    - share(&WORK, form, &before, &input.du, input.p - hp, &input.kin)
                        .unwrap_or(1.0))
                    / (2.0 * hp);
                share_max = share_max.max(share_term.norm() / out.tangent.norm());
                // The tangent with the share term removed (c frozen) must miss by it.
                frozen_du =
                    frozen_du.max((fd - (out.tangent - share_term)).norm() / out.tangent.norm());
                frozen_p = frozen_p
                    .max((fd_p - (out.dt_dp - phi * (dtau_dc * dc_dp))).norm() / out.dt_dp.norm());
            }
            println!(
                "  {regime:10} N = {steps:3} {fname:20} points {checked:4}  ∂t/∂Δu {err_du:9.2e}  ∂t/∂p {err_p:9.2e}  share {share_max:9.2e}  frozen-c errors {frozen_du:9.2e} {frozen_p:9.2e}"
            );
            assert!(
                checked >= steps / 4,
                "{regime}/{fname}: only {checked} slipping points checked"
            );
            assert!(
                err_du <= 1e-6 && err_p <= 1e-6,
                "{regime}/{fname}: ∂t/∂Δu {err_du:e}, ∂t/∂p {err_p:e}"
            );
            if steps == 25 {
                assert!(
                    share_max >= 1e-5 && frozen_du >= 1e-5,
                    "{fname}: share term {share_max:e} (frozen-c error {frozen_du:e}) too small to be exercised"
                );
            }
        }
    }
}
