//! [`ShellView`]: read access to a shell set whatever its element and
//! material (the concrete `ShellSet<E, M>` behind a registered choice).

use crate::{LogStrain, Material, ShellFormulation, ShellSet};
use fem_core::NodalState;

/// Read access to the blank's shells, whichever element the scene chose.
pub trait ShellView {
    /// Number of elements.
    fn len(&self) -> usize;
    /// True when there are no elements.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Current thickness of element `e` (mm).
    fn thickness(&self, e: usize) -> f64;
    /// Flow stress at the outer fibres `[bottom, top]` (MPa).
    fn outer_flow_stress(&self, e: usize) -> [f64; 2];
    /// Logarithmic membrane strain of element `e`.
    fn membrane_strain(&self, e: usize, state: &NodalState) -> LogStrain;
    /// Largest von Mises stress over the element's integration points
    /// (MPa); von Mises whatever the material (a Hill'48 blank's own
    /// equivalent stress is not this field).
    fn von_mises_max(&self, e: usize) -> f64;
    /// Largest equivalent plastic strain over the element's integration points (-).
    fn plastic_strain_max(&self, e: usize) -> f64;
}

impl<E: ShellFormulation, M: Material> ShellView for ShellSet<E, M> {
    fn len(&self) -> usize {
        ShellSet::len(self)
    }
    fn thickness(&self, e: usize) -> f64 {
        ShellSet::thickness(self, e)
    }
    fn outer_flow_stress(&self, e: usize) -> [f64; 2] {
        ShellSet::outer_flow_stress(self, e)
    }
    fn membrane_strain(&self, e: usize, state: &NodalState) -> LogStrain {
        ShellSet::membrane_strain(self, e, state)
    }
    fn von_mises_max(&self, e: usize) -> f64 {
        let n = self.section().rule.n;
        let mut m: f64 = 0.0;
        for p in 0..E::IN_PLANE_POINTS {
            for k in 0..n {
                m = m.max(crate::von_mises(&self.stress(e, p, k)));
            }
        }
        m
    }
    fn plastic_strain_max(&self, e: usize) -> f64 {
        let n = self.section().rule.n;
        let mut m: f64 = 0.0;
        for p in 0..E::IN_PLANE_POINTS {
            for k in 0..n {
                m = m.max(self.plastic_strain(e, p, k));
            }
        }
        m
    }
}
