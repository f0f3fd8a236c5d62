//! Rotational DOFs through the static solver: incremental rotation
//! vectors, their composition at commit, moment loads and the
//! commit/revert protocol, on a torsion spring defined here.

use fem_core::statics::{
    Assembly, DofGroup, NewtonSettings, StaticProblem, StaticSolver, StaticTangent, TrialState,
};
use fem_core::{Dof, Dofs, Effect, FemError, FieldAccess, Forces, Mat3, StepContext, Vec3};

/// A grounded torsion spring about z at one node, stiffening as it turns:
/// moment `M(θ) = k θ + c θ³` (N·mm) for the node's total rotation angle
/// `θ` about z. It counts commits and reverts, and refuses trial angles
/// above `max_angle` (to provoke cut-backs).
struct Torsion {
    node: u32,
    k: f64,
    c: f64,
    max_angle: f64,
    commits: usize,
    reverts: usize,
    committed_angle: f64,
}

impl Torsion {
    /// Total angle about z of the trial state: the committed rotation's
    /// angle plus the increment's (rotations about one axis add).
    fn angle(&self, state: &TrialState<'_>) -> f64 {
        let n = self.node as usize;
        let r = state.rotation_committed[n];
        r[(1, 0)].atan2(r[(0, 0)]) + state.dtheta[n].z
    }
}

impl Effect for Torsion {
    fn name(&self) -> &str {
        "torsion"
    }

    fn add_forces(
        &mut self,
        _ctx: &StepContext<'_>,
        _state: &fem_core::NodalState,
        _forces: &mut Forces,
        _fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        Ok(())
    }
}

impl StaticTangent for Torsion {
    fn internal_forces(
        &mut self,
        state: &TrialState<'_>,
        out: &mut Assembly<'_>,
    ) -> Result<(), FemError> {
        let t = self.angle(state);
        if t.abs() > self.max_angle {
            return Err(FemError::Element {
                effect: "torsion".into(),
                element: 0,
                message: format!("angle {t} rad beyond {} rad", self.max_angle),
            });
        }
        out.add_force3(
            self.node,
            DofGroup::Rotation,
            &Vec3::new(0.0, 0.0, self.k * t + self.c * t.powi(3)),
        );
        if out.wants_tangent() {
            // One entry: a 3×3 block would put rx and ry in the system too.
            let rz = (self.node, Dof::Rz);
            out.add_stiffness(rz, rz, self.k + 3.0 * self.c * t * t);
        }
        Ok(())
    }

    fn commit(&mut self, state: &TrialState<'_>) {
        self.commits += 1;
        self.committed_angle = self.angle(state);
    }

    fn revert(&mut self) {
        self.reverts += 1;
    }
}

/// The root of `k θ + c θ³ = m` (Newton on the scalar equation, to round-off).
fn cubic_root(k: f64, c: f64, m: f64) -> f64 {
    let mut theta: f64 = m / k;
    for _ in 0..60 {
        theta -= (k * theta + c * theta.powi(3) - m) / (k + 3.0 * c * theta * theta);
    }
    theta
}

/// One node held by a torsion spring (`k = 1000` N·mm/rad, `c = 500`
/// N·mm/rad³), its translations fixed, under a moment `m` about z; its
/// other rotations nothing stiffens (dropped).
fn torsion_solver(m: f64, max_angle: f64) -> (StaticSolver, usize) {
    let mut p = StaticProblem::new(&[Vec3::zeros()]).unwrap();
    let index = p.add_effect(Torsion {
        node: 0,
        k: 1000.0,
        c: 500.0,
        max_angle,
        commits: 0,
        reverts: 0,
        committed_angle: 0.0,
    });
    p.add_load(&[0], Dof::Rz, m).unwrap();
    p.fix(&[0], Dofs::TRANSLATIONS).unwrap();
    let settings = NewtonSettings {
        initial_increment: 0.3,
        force_tolerance: 1e-12,
        ..Default::default()
    };
    (StaticSolver::new(p, settings).unwrap(), index)
}

/// A moment of 3000 N·mm on the torsion spring `M = k θ + c θ³`: the solve
/// must reach the cubic's root (θ = 1.4562 rad) within 1e-12 rad, the
/// node's rotation matrix must be the rotation by θ about z, composed over
/// the increments' rotation vectors, within 1e-12, the reaction-free DOF
/// must be in equilibrium to 1e-9 of the moment, and the effect must have
/// been committed once per increment and reverted once (after set-up's
/// pattern recording). Reference: the scalar cubic solved to round-off.
#[test]
fn torsion_spring_under_moment_turns_to_the_cubic_root_across_increments() {
    let m = 3000.0;
    let theta = cubic_root(1000.0, 500.0, m);
    let (mut solver, index) = torsion_solver(m, 10.0);
    let report = solver.solve().unwrap();
    print!("{report}");
    let r = solver.rotation(0);
    let (s, c) = theta.sin_cos();
    let expected = Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
    let e: &Torsion = solver.effect(index).unwrap();
    println!(
        "θ = {theta:.12} rad; solved {:.12}; |R − Rz(θ)| = {:.3e}",
        e.committed_angle,
        (r - expected).norm()
    );
    assert!((e.committed_angle - theta).abs() < 1e-12);
    assert!((r - expected).norm() < 1e-12);
    assert!(report.increments.len() >= 2, "increments compose rotations");
    assert_eq!(e.commits, report.increments.len());
    assert_eq!(e.reverts, 1);
    assert_eq!(report.system.equations, 1);
    assert!(solver.reaction(0, Dof::Rz).abs() < 1e-9 * m);
}

/// The same spring refusing every trial angle above 1.2 rad (below the
/// answer): the increments that reach past it are cut back, each attempt
/// reverted, until the solve stops with `NotConverged`; the state stays at
/// the last committed increment, in equilibrium under its share of the
/// moment (`k θ + c θ³ = λ m` to 1e-9 of `m`) and below 1.2 rad.
#[test]
fn torsion_spring_refusing_large_angles_is_reverted_then_stops_at_last_commit() {
    let m = 3000.0;
    let (mut solver, index) = torsion_solver(m, 1.2);
    let err = solver.solve().unwrap_err();
    println!("{err}");
    let fem_core::statics::StaticsError::NotConverged {
        lambda_converged,
        cutbacks,
        ..
    } = err
    else {
        panic!("expected NotConverged, got {err}");
    };
    let e: &Torsion = solver.effect(index).unwrap();
    let t = e.committed_angle;
    println!(
        "stopped at λ = {lambda_converged}, θ = {t} rad, {cutbacks} cut-backs, {} reverts",
        e.reverts
    );
    assert_eq!(solver.lambda(), lambda_converged);
    assert!(t < 1.2 && t > 1.0, "θ = {t}");
    assert!((1000.0 * t + 500.0 * t.powi(3) - lambda_converged * m).abs() < 1e-9 * m);
    // Set-up, every cut-back, and the final failed attempt each revert.
    assert_eq!(e.reverts, 1 + cutbacks + 1);
}
