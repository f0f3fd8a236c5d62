//! The static tangent of [`Springs`]: exact consistent tangent of the
//! geometrically nonlinear axial spring (material + geometric stiffness).

use super::{Assembly, DofGroup, StaticTangent, TrialState};
use crate::{Effect, FemError, Mat3, Spring, Springs, Vec3};

/// Internal force on node `b` (N) and its derivative with respect to `x_b`
/// (N/mm) of spring `s` with axis `d = x_b − x_a`; node `a` gets the
/// negatives. Energy `W = ½ k (L − L0)²`, `L = |d|`, `n = d / L`:
///
/// - `F_b = ∂W/∂x_b = k (L − L0) n = T n`;
/// - `K = ∂F_b/∂x_b = k n nᵀ + (T / L) (I − n nᵀ)`: material (axial)
///   stiffness plus geometric stiffness of the axial force `T`.
///
/// A spring of zero free length is linear in `d` (`F_b = k d`, `K = k I`),
/// whatever its length. A spring of zero length and nonzero free length
/// has no axis: `None`.
pub(crate) fn spring_force_tangent(s: &Spring, d: &Vec3) -> Option<(Vec3, Mat3)> {
    if s.length0 == 0.0 {
        return Some((d * s.k, Mat3::identity() * s.k));
    }
    let l = d.norm();
    if l == 0.0 {
        return None;
    }
    let n = d / l;
    let t = s.k * (l - s.length0);
    let nn = n * n.transpose();
    let k = nn * s.k + (Mat3::identity() - nn) * (t / l);
    Some((n * t, k))
}

impl StaticTangent for Springs {
    fn internal_forces(
        &mut self,
        state: &TrialState<'_>,
        out: &mut Assembly<'_>,
    ) -> Result<(), FemError> {
        use DofGroup::Translation as T;
        let tangent = out.wants_tangent();
        for (e, s) in self.springs().iter().enumerate() {
            let (a, b) = (s.a, s.b);
            if let Some(node) = [a, b].into_iter().find(|&n| n as usize >= state.len()) {
                return Err(FemError::NodeOutOfRange {
                    element: e,
                    node: node.into(),
                    n_nodes: state.len(),
                });
            }
            let d = state.x[b as usize] - state.x[a as usize];
            let Some((f, k)) = spring_force_tangent(s, &d) else {
                return Err(FemError::Element {
                    effect: self.name().to_string(),
                    element: e,
                    message: format!(
                        "zero length at the trial state (free length {} mm): its axis is undefined",
                        s.length0
                    ),
                });
            };
            out.add_force3(b, T, &f);
            out.add_force3(a, T, &-f);
            if tangent {
                let minus = -k;
                out.add_block3((a, T), (a, T), &k);
                out.add_block3((a, T), (b, T), &minus);
                out.add_block3((b, T), (a, T), &minus);
                out.add_block3((b, T), (b, T), &k);
            }
        }
        Ok(())
    }
}
