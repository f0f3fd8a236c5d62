//! `Springs`: linear axial springs between nodes, an effect for verifying the engine and for lumped-parameter models.

use crate::{Effect, EnergyTally, FemError, Forces, NodalState, StableDt, StepContext, Vec3};

/// A linear axial spring between nodes `a` and `b`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// First node.
    pub a: u32,
    /// Second node.
    pub b: u32,
    /// Stiffness (N/mm), `> 0`.
    pub k: f64,
    /// Free length (mm), `>= 0`.
    pub length0: f64,
}

/// A set of axial springs: force `k (L − L0)` along the current axis, energy
/// `½ k (L − L0)²` (exact, so the engine's energy balance can be checked
/// against it).
///
/// Stable time step: Gershgorin's bound on `M⁻¹K`, `ω² ≤ max_i 2 Σ k_j / m_i`
/// over the springs `j` at node `i` (axial stiffness only), so
/// `Δt = √(2 m_i / Σ k_j)`, reported against the stiffest spring at the
/// limiting node; massless nodes (which the solver does not move) are
/// skipped. It is conservative: for one mass on one grounded spring it
/// gives `√2/ω` where the exact limit is `2/ω`.
#[derive(Debug, Clone, PartialEq)]
pub struct Springs {
    name: String,
    springs: Vec<Spring>,
    /// Σ k at each node (N/mm).
    node_k: Vec<f64>,
    /// The stiffest spring at each node.
    node_spring: Vec<u32>,
    energy: f64,
}

impl Springs {
    /// Springs over `n_nodes` nodes; checks indices, `k > 0`, `length0 >= 0`.
    pub fn new(name: &str, n_nodes: usize, springs: Vec<Spring>) -> Result<Self, FemError> {
        let mut node_k = vec![0.0; n_nodes];
        let mut node_spring = vec![0u32; n_nodes];
        let mut node_kmax = vec![0.0f64; n_nodes];
        for (e, s) in springs.iter().enumerate() {
            for node in [s.a, s.b] {
                if node as usize >= n_nodes {
                    return Err(FemError::NodeOutOfRange {
                        element: e,
                        node: node as u64,
                        n_nodes,
                    });
                }
            }
            if s.a == s.b {
                return Err(FemError::DuplicateNode {
                    element: e,
                    node: s.a,
                });
            }
            if !(s.k.is_finite() && s.k > 0.0) {
                return Err(FemError::InvalidParameter {
                    field: format!("spring {e}: k"),
                    value: s.k,
                    unit: "N/mm",
                    range: "finite and > 0",
                });
            }
            if !(s.length0.is_finite() && s.length0 >= 0.0) {
                return Err(FemError::InvalidParameter {
                    field: format!("spring {e}: length0"),
                    value: s.length0,
                    unit: "mm",
                    range: "finite and >= 0",
                });
            }
            for node in [s.a as usize, s.b as usize] {
                node_k[node] += s.k;
                if s.k > node_kmax[node] {
                    node_kmax[node] = s.k;
                    node_spring[node] = e as u32;
                }
            }
        }
        Ok(Self {
            name: name.to_string(),
            springs,
            node_k,
            node_spring,
            energy: 0.0,
        })
    }

    /// The springs.
    pub fn springs(&self) -> &[Spring] {
        &self.springs
    }

    /// Axial force of spring `e` (N, tension positive) in the configuration `x`.
    pub fn axial_force(&self, e: usize, x: &[Vec3]) -> f64 {
        let s = &self.springs[e];
        s.k * ((x[s.b as usize] - x[s.a as usize]).norm() - s.length0)
    }
}

/// Gershgorin's stable step of a node of mass `m` held by springs of total
/// stiffness `k`, `√(2 m / k)` (`None` for a massless node, which the solver
/// does not move, or no spring).
pub(crate) fn spring_dt(m: f64, k: f64) -> Option<f64> {
    (k > 0.0 && m > 0.0).then(|| (2.0 * m / k).sqrt())
}

/// Raise `m` to the mass whose [`spring_dt`] is `target_dt` under springs of
/// total stiffness `k`; returns the mass added (tonne).
pub(crate) fn scale_spring_mass(m: &mut f64, k: f64, target_dt: f64) -> f64 {
    let needed = 0.5 * k * target_dt * target_dt;
    if k > 0.0 && *m < needed {
        let added = needed - *m;
        *m = needed;
        added
    } else {
        0.0
    }
}

impl Effect for Springs {
    fn name(&self) -> &str {
        &self.name
    }

    fn stable_dt(&self, state: &NodalState) -> Option<StableDt> {
        let mut best: Option<StableDt> = None;
        for (i, &k) in self.node_k.iter().enumerate() {
            // Massless nodes do not move (the solver skips them): no limit.
            if let Some(dt) = spring_dt(state.mass[i], k)
                && best.is_none_or(|b| dt.is_nan() || dt < b.dt)
            {
                best = Some(StableDt {
                    dt,
                    element: self.node_spring[i] as usize,
                    what: "spring stiffness vs nodal mass (Gershgorin bound)",
                });
            }
        }
        best
    }

    fn stiffens_nodes(&self) -> bool {
        !self.springs.is_empty()
    }

    /// `2 k` per node (`k` its springs' total): the Gershgorin step `√(2 m / k)` as `2 √(m / s)`.
    fn nodal_stiffness(&self, _state: &NodalState, stiffness: &mut [f64]) {
        for (s, &k) in stiffness.iter_mut().zip(&self.node_k) {
            *s += 2.0 * k;
        }
    }

    fn scale_mass(
        &mut self,
        _state: &NodalState,
        target_dt: f64,
        mass: &mut [f64],
        _inertia: &mut [f64],
    ) -> f64 {
        mass.iter_mut()
            .zip(&self.node_k)
            .map(|(m, &k)| scale_spring_mass(m, k, target_dt))
            .sum()
    }

    fn add_forces(
        &mut self,
        _ctx: &StepContext,
        state: &NodalState,
        forces: &mut Forces,
        _fields: &mut crate::FieldAccess<'_>,
    ) -> Result<(), FemError> {
        let mut energy = 0.0;
        for s in &self.springs {
            let (a, b) = (s.a as usize, s.b as usize);
            let d = state.x[b] - state.x[a];
            let l = d.norm();
            let stretch = l - s.length0;
            energy += 0.5 * s.k * stretch * stretch;
            if l > 0.0 {
                let f = d * (s.k * stretch / l);
                forces.f[a] += f;
                forces.f[b] -= f;
            }
        }
        self.energy = energy;
        Ok(())
    }

    fn energies(&self) -> EnergyTally {
        EnergyTally {
            internal: self.energy,
            ..Default::default()
        }
    }

    /// Elastic springs are their own static form: a copy.
    fn static_form(&self) -> Result<crate::StaticForm, String> {
        Ok(crate::StaticForm::Tangent(Box::new(self.clone())))
    }

    /// Nothing to take back but the energy at the positions `x`.
    fn absorb_static(
        &mut self,
        _solved: &dyn crate::statics::StaticTangent,
        x: &[Vec3],
    ) -> Result<(), String> {
        self.energy = self
            .springs
            .iter()
            .map(|s| {
                let stretch = (x[s.b as usize] - x[s.a as usize]).norm() - s.length0;
                0.5 * s.k * stretch * stretch
            })
            .sum();
        Ok(())
    }
}
