//! The static solver's interface of [`StaticShells`]: internal forces and
//! exact tangent assembled element by element, commit and revert, and the
//! [`Effect`] it must also be.

use super::StaticShells;
use super::dual::Dual;
use super::element::{ElementMotion, StaticKernel, StaticScalar};
use crate::formulation::{ElementResult, ShellFormulation};
use crate::material::Material;
use fem_core::statics::{Assembly, DofGroup, StaticTangent, TrialState};
use fem_core::{Effect, FemError, FieldAccess, Forces, Mat3, NodalState, StepContext, Vec3};

/// Element `e` of `shells`: its kernel at `state` over the scalar `T`, made
/// by `seed` from a value and its DOF index (`6 · local node + dof`).
fn run_element<T: StaticScalar, M: Material, F: StaticKernel>(
    shells: &mut StaticShells<M, F>,
    e: usize,
    state: &TrialState<'_>,
    seed: impl Fn(f64, usize) -> T,
) -> Result<ElementResult<T>, FemError> {
    let q = shells.conn[e];
    let mut motion = ElementMotion {
        x: [[T::splat(0.0); 3]; 4],
        dx: [[T::splat(0.0); 3]; 4],
        dtheta: [[T::splat(0.0); 3]; 4],
    };
    for (i, &n) in q.iter().enumerate() {
        let n = n as usize;
        if n >= state.len() {
            return Err(FemError::NodeOutOfRange {
                element: e,
                node: n as u64,
                n_nodes: state.len(),
            });
        }
        for c in 0..3 {
            let x = seed(state.x[n][c], 6 * i + c);
            motion.x[i][c] = x;
            motion.dx[i][c] = x - state.x_committed[n][c];
            motion.dtheta[i][c] = seed(state.dtheta[n][c], 6 * i + 3 + c);
        }
    }
    shells
        .formulation
        .element_forces(
            &shells.moduli,
            &shells.material,
            &shells.section.rule,
            &motion,
            e,
            &shells.committed,
            &mut shells.trial,
        )
        .ok_or_else(|| FemError::Element {
            effect: shells.name.clone(),
            element: e,
            message: "zero or negative area in the trial or the midpoint configuration".to_string(),
        })
}

/// `F_int` of a node from the kernel's `−F_int`.
fn internal(f: &[f64; 3]) -> Vec3 {
    -Vec3::new(f[0], f[1], f[2])
}

/// Add element result `r` (forces and, with derivatives, the tangent) on
/// nodes `q` to `out`: `F_int = −r.f`, `−r.m`; tangent block (row node `i`,
/// group; column node `j`, group) from the derivatives `6 j + dof`.
fn assemble_dual(q: &[u32; 4], r: &ElementResult<Dual>, out: &mut Assembly<'_>) {
    use DofGroup::{Rotation as R, Translation as T};
    for i in 0..4 {
        out.add_force3(q[i], T, &internal(&r.f[i].map(|v| v.re)));
        out.add_force3(q[i], R, &internal(&r.m[i].map(|v| v.re)));
    }
    for i in 0..4 {
        for (row, rows) in [(T, &r.f[i]), (R, &r.m[i])] {
            for j in 0..4 {
                for (col, off) in [(T, 0), (R, 3)] {
                    let block = Mat3::from_fn(|a, b| -rows[a].d[6 * j + off + b]);
                    out.add_block3((q[i], row), (q[j], col), &block);
                }
            }
        }
    }
}

impl<M: Material, F: StaticKernel> StaticTangent for StaticShells<M, F> {
    fn internal_forces(
        &mut self,
        state: &TrialState<'_>,
        out: &mut Assembly<'_>,
    ) -> Result<(), FemError> {
        use fem_core::statics::DofGroup::{Rotation as R, Translation as T};
        let tangent = out.wants_tangent();
        for e in 0..self.conn.len() {
            let q = self.conn[e];
            if tangent {
                let r = run_element(self, e, state, Dual::variable)?;
                assemble_dual(&q, &r, out);
            } else {
                let r = run_element(self, e, state, |v, _| v)?;
                for i in 0..4 {
                    out.add_force3(q[i], T, &internal(&r.f[i]));
                    out.add_force3(q[i], R, &internal(&r.m[i]));
                }
            }
        }
        Ok(())
    }

    /// Re-evaluate the point states at `state` (whatever the solver
    /// evaluated last) and keep them as committed.
    fn commit(&mut self, state: &TrialState<'_>) {
        for e in 0..self.conn.len() {
            // The solver evaluated this state successfully before committing
            // it, so the element cannot degenerate here; if it did, the trial
            // state of the last call stays.
            if let Ok(r) = run_element(self, e, state, |v, _| v) {
                self.work.internal += r.d_internal;
                self.work.hourglass += r.d_hourglass;
                self.work.plastic += r.d_plastic;
            }
        }
        self.committed.clone_from(&self.trial);
    }

    fn revert(&mut self) {
        self.trial.clone_from(&self.committed);
    }

    /// The co-rotational element's exact tangent is not symmetric away from
    /// equilibrium (the frame's rotation and the moments' parameterisation by
    /// incremental rotation vectors): LU.
    fn symmetric_tangent(&self) -> bool {
        false
    }
}

impl<M: Material, F: ShellFormulation> Effect for StaticShells<M, F> {
    fn name(&self) -> &str {
        &self.name
    }

    /// Static shells do not run in the explicit step (that is
    /// [`ShellSet`](crate::ShellSet)'s job): an error.
    fn add_forces(
        &mut self,
        _ctx: &StepContext<'_>,
        _state: &NodalState,
        _forces: &mut Forces,
        _fields: &mut FieldAccess<'_>,
    ) -> Result<(), FemError> {
        Err(FemError::Effect {
            effect: self.name.clone(),
            message:
                "static shells run in the static solver only; the explicit step takes a ShellSet"
                    .to_string(),
        })
    }
}
