//! An effect with an unsymmetric tangent goes through the LU factorisation.

use fem_core::statics::{
    Assembly, NewtonSettings, SolveReport, StaticProblem, StaticSolver, StaticTangent, TrialState,
};
use fem_core::{Dof, Dofs, Effect, FemError, FieldAccess, Forces, NodalState, StepContext, Vec3};

/// Two nodes coupled one way along x: `F_0 = k u_0 − a u_1`,
/// `F_1 = k u_1 + b u_0³` (N, `u` the x-displacements in mm), a
/// nonlinear, non-conservative coupling whose tangent
/// `[[k, −a], [3 b u_0², k]]` is not symmetric.
struct OneWay {
    k: f64,
    a: f64,
    b: f64,
}

impl Effect for OneWay {
    fn name(&self) -> &str {
        "one-way"
    }

    fn add_forces(
        &mut self,
        _ctx: &StepContext<'_>,
        _state: &NodalState,
        _forces: &mut Forces,
        _fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        Ok(())
    }
}

impl StaticTangent for OneWay {
    fn internal_forces(
        &mut self,
        s: &TrialState<'_>,
        out: &mut Assembly<'_>,
    ) -> Result<(), FemError> {
        let u0 = s.x[0].x - s.x_start[0].x;
        let u1 = s.x[1].x - s.x_start[1].x;
        out.add_force(0, Dof::Ux, self.k * u0 - self.a * u1);
        out.add_force(1, Dof::Ux, self.k * u1 + self.b * u0.powi(3));
        if out.wants_tangent() {
            out.add_stiffness((0, Dof::Ux), (0, Dof::Ux), self.k);
            out.add_stiffness((0, Dof::Ux), (1, Dof::Ux), -self.a);
            out.add_stiffness((1, Dof::Ux), (0, Dof::Ux), 3.0 * self.b * u0 * u0);
            out.add_stiffness((1, Dof::Ux), (1, Dof::Ux), self.k);
        }
        Ok(())
    }

    fn symmetric_tangent(&self) -> bool {
        false
    }
}

/// The one-way pair along x (node 1 10 mm from node 0), y and z held,
/// `P_0 = p` on node 0.
fn one_way_problem(k: f64, a: f64, b: f64, p: f64) -> StaticProblem {
    let mut problem = StaticProblem::new(&[Vec3::zeros(), Vec3::new(10.0, 0.0, 0.0)]).unwrap();
    problem.add_effect(OneWay { k, a, b });
    problem.fix(&[0, 1], Dofs::of(&[Dof::Uy, Dof::Uz])).unwrap();
    problem.add_load(&[0], Dof::Ux, p).unwrap();
    problem
}

/// The pair's equilibrium `(u_0, u_1)` (mm) under `P_0 = p`: `u_1 = −b
/// u_0³ / k` and the cubic `k u_0 + a b u_0³ / k = p`, by scalar Newton
/// to round-off.
fn equilibrium(k: f64, a: f64, b: f64, p: f64) -> (f64, f64) {
    let mut u0: f64 = p / k;
    for _ in 0..60 {
        u0 -= (k * u0 + a * b * u0.powi(3) / k - p) / (k + 3.0 * a * b * u0 * u0 / k);
    }
    (u0, -b * u0.powi(3) / k)
}

/// Solve the pair under `P_0 = p` with `settings`: the report and the
/// errors of `u_0`, `u_1` against [`equilibrium`] (mm).
fn solve_pair(k: f64, a: f64, b: f64, p: f64, settings: NewtonSettings) -> (SolveReport, f64, f64) {
    let (u0, u1) = equilibrium(k, a, b, p);
    let mut solver = StaticSolver::new(one_way_problem(k, a, b, p), settings).unwrap();
    let report = solver.solve().unwrap();
    print!("{report}");
    let (e0, e1) = (solver.displacement(0).x - u0, solver.displacement(1).x - u1);
    println!("u0 = {u0:.12} mm, u1 = {u1:.12} mm; errors {e0:.3e}, {e1:.3e}");
    (report, e0, e1)
}

/// Loads `P_0 = 20 N`, `P_1 = 0` on the one-way pair (`k = 100`, `a = 60`
/// N/mm, `b = 50` N/mm³): equilibrium needs `u_1 = −b u_0³ / k` and
/// `k u_0 + a b u_0³ / k = P_0`, a cubic in `u_0` solved here by scalar
/// Newton to round-off. The solver must factorise with LU only (the
/// effect declares its tangent unsymmetric) and match both displacements
/// within 1e-12 mm, converging quadratically as with the symmetric
/// factorisations (at most 6 iterations per increment).
#[test]
fn unsymmetric_tangent_is_solved_with_lu() {
    let (k, a, b, p) = (100.0, 60.0, 50.0, 20.0);
    let settings = NewtonSettings {
        force_tolerance: 1e-12,
        ..Default::default()
    };
    let (report, e0, e1) = solve_pair(k, a, b, p, settings);
    let s = report.system;
    assert!(s.lu > 0 && s.llt == 0 && s.ldlt == 0, "{s:?}");
    assert!(e0.abs() < 1e-12 && e1.abs() < 1e-12);
    assert!(report.increments.iter().all(|i| i.iterations <= 6));
}

/// `StaticSolver::tangent_matrix` gives the tangent the solver factorises,
/// over its equations (`equation_dof`), at the converged state: on the
/// one-way pair (the loads and constants above), `[[k, −a], [0, k]]` at the
/// start and `[[k, −a], [3 b u_0², k]]` after the solve, the (1, 0) entry
/// stored at the start though zero (the pattern holds both triangles).
/// Asking for it leaves the converged state as it was. Tolerance: exact
/// at the start; 1e-12 relative after the solve.
#[test]
fn tangent_matrix_is_the_factorised_tangent() {
    let (k, a, b, p) = (100.0, 60.0, 50.0, 20.0);
    let problem = one_way_problem(k, a, b, p);
    let mut solver = StaticSolver::new(problem, NewtonSettings::default()).unwrap();
    assert_eq!(solver.equation_dof(0), Some((0, Dof::Ux)));
    assert_eq!(solver.equation_dof(1), Some((1, Dof::Ux)));
    assert_eq!(solver.equation_dof(2), None);
    let start = solver.tangent_matrix().unwrap();
    assert_eq!((start.nrows(), start.ncols()), (2, 2));
    assert_eq!(start.col_ptr(), &[0, 2, 4]);
    assert_eq!(start.row_idx(), &[0, 1, 0, 1]);
    assert_eq!(start.val(), &[k, 0.0, -a, k]);
    solver.solve().unwrap();
    let (u0, u1) = (solver.displacement(0).x, solver.displacement(1).x);
    let end = solver.tangent_matrix().unwrap();
    let expected = [k, 3.0 * b * u0 * u0, -a, k];
    for (got, want) in end.val().iter().zip(expected) {
        assert!(
            (got - want).abs() <= 1e-12 * want.abs(),
            "{got} against {want}"
        );
    }
    assert_eq!(
        (solver.displacement(0).x, solver.displacement(1).x),
        (u0, u1)
    );
}

/// The symmetric part of a strongly unsymmetric tangent does not make a
/// contracting iteration: on the one-way pair with `a = 300` N/mm (`k =
/// 100`, `b = 50`, `P_0 = 20 N`), `S = ½ (K + Kᵀ)` at the start is
/// `[[100, −150], [−150, 100]]` and Newton on it multiplies the error by
/// `S⁻¹ (S − K)`, whose eigenvalues are `±1.34`: it diverges at any load
/// increment, so cutting back cannot help. With `symmetrize` (and the
/// factor kept, as the springback step sets it) the solver must, after
/// the last cut-back allowed, go over to the exact tangent by LU and
/// converge to the closed-form equilibrium (the cubic above) within
/// 1e-12 mm. Without the fall-back the solve stops after 12 cut-backs.
#[test]
fn symmetric_part_that_diverges_falls_back_to_the_exact_tangent() {
    let (k, a, b, p) = (100.0, 300.0, 50.0, 20.0);
    let settings = NewtonSettings {
        force_tolerance: 1e-12,
        symmetrize: true,
        reuse_contraction: 0.5,
        line_search_steps: 0,
        ..Default::default()
    };
    let (report, e0, e1) = solve_pair(k, a, b, p, settings);
    assert!(report.exact_fallback, "{report}");
    assert!(report.system.lu >= 1, "{:?}", report.system);
    assert!(e0.abs() < 1e-12 && e1.abs() < 1e-12);
}
