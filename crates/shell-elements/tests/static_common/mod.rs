//! Shared helpers of the static-shell tests: materials, a trial state, a
//! strip clamped at one end, solver settings.
#![allow(dead_code)]

pub mod fd;

use fem_core::statics::{StaticTangent, TrialState};
use fem_core::{Mat3, Vec3};
use shell_elements::{Hardening, J2PlaneStress, Section, ShellFormulation, StaticShells};

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

/// Young's modulus (MPa), length, width and thickness (mm) of the strip.
pub const E: f64 = 200_000.0;
/// Strip length (mm).
pub const L: f64 = 100.0;
/// Strip width (mm).
pub const B: f64 = 10.0;
/// Strip thickness (mm).
pub const T: f64 = 1.0;
/// Bending stiffness `E b t³ / 12` (N·mm²).
pub const EI: f64 = E * B * T * T * T / 12.0;

/// An elastic strip (`E`, ν = 0) of `n × across` Belytschko–Tsay shells
/// along x in the plane z = 0, clamped at x = 0: the problem (no load yet)
/// and its tip nodes (x = L, by increasing y).
pub fn clamped_strip(n: usize, across: usize) -> (fem_core::statics::StaticProblem, Vec<u32>) {
    clamped_strip_of(n, across, shell_elements::BelytschkoTsay::default())
}

/// [`clamped_strip`] with the shells of formulation `form`.
pub fn clamped_strip_of<F: ShellFormulation>(
    n: usize,
    across: usize,
    form: F,
) -> (fem_core::statics::StaticProblem, Vec<u32>)
where
    StaticShells<J2PlaneStress, F>: StaticTangent,
{
    use fem_core::Dofs;
    let mesh = fem_core::rectangle(L, B, n, across).unwrap();
    let shells = StaticShells::new(
        "strip",
        &mesh.nodes,
        &mesh.quads,
        section(T, 5),
        form,
        elastic(E, 0.0),
    )
    .unwrap();
    let mut problem = fem_core::statics::StaticProblem::new(&mesh.nodes).unwrap();
    problem.add_effect(shells);
    problem.fix(&mesh.node_sets["x0"], Dofs::ALL).unwrap();
    (problem, mesh.node_sets["x1"].clone())
}

/// Newton settings with a fixed load increment `dl` (first and largest)
/// and a force floor of 100 N (N·mm), the strip's force scale `M / L`
/// (`EI / L² ≈ 17 N` to `2π EI / L² ≈ 105 N`): an end moment gives the
/// translation equations no force scale of their own (no load, no reaction
/// in pure bending), and their residual cannot fall below the membrane's
/// rounding, `E t b / ℓ × 1e-14 mm ≈ 1e-8 N` per node 100 mm from the
/// origin; the force criterion is then `‖R‖ ≤ 1e-6 N`. Full Newton steps
/// (no line search): the first step of an increment stretches the fibres
/// to second order in its rotation (the linearised kinematics of any exact
/// tangent), which raises `‖R‖` by two orders for one iteration before the
/// next ones remove it; backtracking on `‖R‖²` refuses that step and
/// crawls (21 iterations an increment and cut-backs to Δλ = 3e-3 on the
/// full circle, against 7 iterations at Δλ = 0.025 without).
pub fn fixed_steps(dl: f64) -> fem_core::statics::NewtonSettings {
    fem_core::statics::NewtonSettings {
        force_floor: 100.0,
        line_search_steps: 0,
        initial_increment: dl,
        max_increment: dl,
        min_increment: dl * 1e-3,
        ..Default::default()
    }
}

/// Mean of the nodes' values.
pub fn mean(nodes: &[u32], f: impl Fn(usize) -> Vec3) -> Vec3 {
    nodes.iter().map(|&n| f(n as usize)).sum::<Vec3>() / nodes.len() as f64
}

/// Angle (rad) of a rotation about the global y axis, `atan2(R_xz, R_xx)`.
pub fn angle_about_y(r: &Mat3) -> f64 {
    r[(0, 2)].atan2(r[(0, 0)])
}

/// Load `total` on `dof` of the tip nodes `tip` (by increasing y, equally
/// spaced) with the trapezoid rule's weights: the end nodes take half a
/// share (a uniform line load's consistent nodal values).
pub fn add_edge_load(
    problem: &mut fem_core::statics::StaticProblem,
    tip: &[u32],
    dof: fem_core::Dof,
    total: f64,
) {
    let shares = (tip.len() - 1) as f64;
    for (k, &n) in tip.iter().enumerate() {
        let w = if k == 0 || k + 1 == tip.len() {
            0.5
        } else {
            1.0
        };
        problem.add_load(&[n], dof, total * w / shares).unwrap();
    }
}

/// Roll the clamped strip of `40 × across` shells of `form` with an end
/// moment `M = factor · EI / L` about +y (a dead moment shared by the tip
/// nodes, trapezoid weights) in fixed increments `dl`: the tip's position
/// error over L and rotation error over `θ = M L / EI` against pure
/// bending (`R = EI / M`, tip at `x = R sin θ`, `z = −R (1 − cos θ)`).
pub fn roll_strip<F: ShellFormulation>(form: F, factor: f64, dl: f64, across: usize) -> (f64, f64)
where
    StaticShells<J2PlaneStress, F>: StaticTangent,
{
    let (mut problem, tip) = clamped_strip_of(40, across, form);
    let m = factor * EI / L;
    add_edge_load(&mut problem, &tip, fem_core::Dof::Ry, m);
    let mut solver = fem_core::statics::StaticSolver::new(problem, fixed_steps(dl)).unwrap();
    // The tip's rotation, unwrapped increment by increment.
    let (mut theta, mut last) = (0.0, 0.0);
    let report = solver
        .solve_observed(&mut |s| {
            let a = angle_about_y(&s.rotation(tip[0] as usize));
            let mut d = a - last;
            d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
            theta += d;
            last = a;
        })
        .unwrap();
    let exact_theta = m * L / EI;
    let r = EI / m;
    let exact = Vec3::new(r * exact_theta.sin(), 0.0, -r * (1.0 - exact_theta.cos()));
    let x = mean(&tip, |k| solver.positions()[k]);
    let tip_y = Vec3::new(0.0, B / 2.0, 0.0);
    let pos_err = (x - tip_y - exact).norm() / L;
    let rot_err = (theta - exact_theta).abs() / exact_theta;
    println!(
        "{}: 40 × {across} shells, M = {factor:.4} EI/L, Δλ = {dl}: {} increments, {} \
         iterations; tip at ({:.4}, {:.4}, {:.4}) mm, exact ({:.4}, 0, {:.4}); |Δx|/L = \
         {pos_err:.3e}; θ = {theta:.5} rad, exact {exact_theta:.5}, error {rot_err:.3e}",
        F::NAME,
        report.increments.len(),
        report.iterations(),
        x.x,
        x.y - tip_y.y,
        x.z,
        exact.x,
        exact.z,
    );
    (pos_err, rot_err)
}
