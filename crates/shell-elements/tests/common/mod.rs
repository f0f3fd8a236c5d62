//! Shared helpers of the shell verification tests: materials, meshes, one-shot force evaluation.
#![allow(dead_code)]

use fem_core::{Effect, Forces, NodalState, StepContext, Vec3};
use shell_elements::{Hardening, J2PlaneStress, Material, ShellFormulation, ShellSet};

/// Elastic material (flow stress 1e30 MPa).
pub fn elastic(e: f64, nu: f64, rho: f64) -> J2PlaneStress {
    J2PlaneStress::new(e, nu, rho, Hardening::swift(1e30, 1.0, 0.0).unwrap()).unwrap()
}

/// Evaluate the forces of one step of `dt` with nodal velocities `v`, `w`
/// read in the reference configuration: the classic explicit patch check.
/// The elements read their rates in the step's midpoint configuration, so
/// the step runs from `x0 − ½Δt v` to `x0 + ½Δt v`.
pub fn one_step<E: ShellFormulation, M: Material>(
    set: &mut ShellSet<E, M>,
    x0: &[Vec3],
    v: &[Vec3],
    w: &[Vec3],
    dt: f64,
) -> Forces {
    let mut st = NodalState::at_rest(x0);
    for (x, u) in st.x.iter_mut().zip(v) {
        *x += 0.5 * dt * u;
    }
    st.v = v.to_vec();
    st.w = w.to_vec();
    let mut f = Forces::zeros(x0.len());
    let ctx = StepContext {
        time: dt,
        dt,
        step: 1,
        press: None,
    };
    set.add_forces(&ctx, &st, &mut f, &mut fem_core::FieldAccess::none())
        .unwrap();
    f
}

/// Rotate a local `[xx, yy, xy]` tensor with the in-plane basis rows `e1`, `e2` to global x-y.
pub fn to_global_xy(s: [f64; 3], e1: [f64; 3], e2: [f64; 3]) -> [f64; 3] {
    // σ_g = Rᵀ σ_l R with R rows e1, e2 (x-y parts).
    let r = [[e1[0], e1[1]], [e2[0], e2[1]]];
    let l = [[s[0], s[2]], [s[2], s[1]]];
    let mut g = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            for a in 0..2 {
                for b in 0..2 {
                    g[i][j] += r[a][i] * l[a][b] * r[b][j];
                }
            }
        }
    }
    [g[0][0], g[1][1], g[0][1]]
}

/// The plane-strain strip of the bending tests: `length × width`,
/// `elements × 1` shells of thickness `thickness` with a Lobatto rule of
/// `rule_points`, clamped at x = 0 (set `x0`) and in plane strain across
/// its width: uy = 0 (ε_yy = 0), rx = 0 (κ_yy = 0) and rz = 0 (no drilling)
/// at every node.
#[derive(Debug, Clone, Copy)]
pub struct PlaneStrainStrip {
    /// Young's modulus (MPa).
    pub young: f64,
    /// Poisson's ratio (ν → ½ for Hill's plane-strain solution).
    pub poisson: f64,
    /// Density (tonne/mm³).
    pub density: f64,
    /// Thickness (mm).
    pub thickness: f64,
    /// Length along x (mm).
    pub length: f64,
    /// Width along y (mm).
    pub width: f64,
    /// Shells along the length.
    pub elements: usize,
    /// Lobatto points through the thickness.
    pub rule_points: usize,
}

/// The strip both bending tests use: steel-like elasticity with ν → ½ (the
/// plane-strain solution is for incompressible elasticity), `4 × 1` mm of
/// 1 mm sheet in 4 shells, 15 Lobatto points.
pub const STEEL_STRIP: PlaneStrainStrip = PlaneStrainStrip {
    young: 200_000.0,
    poisson: 0.4999,
    density: 7.85e-9,
    thickness: 1.0,
    length: 4.0,
    width: 1.0,
    elements: 4,
    rule_points: 15,
};

impl PlaneStrainStrip {
    /// The strip's first circular frequency (clamped–guided,
    /// ω₁ = 2.365² √(E′I/(ρA))/L², rad/s).
    pub fn omega(&self) -> f64 {
        let e_ps = self.young / (1.0 - self.poisson * self.poisson);
        2.365f64.powi(2) * (e_ps * self.thickness.powi(2) / (12.0 * self.density)).sqrt()
            / self.length.powi(2)
    }

    /// A solver of the strip meshed as `mesh` (its `rectangle`, node sets
    /// added as a test needs) with `form` and J2 of `hardening`, and light
    /// mass-proportional damping c = ω₁/20.
    pub fn solver<F: ShellFormulation>(
        &self,
        mesh: &fem_core::Mesh,
        form: F,
        hardening: Hardening,
    ) -> fem_core::Solver {
        use fem_core::{Dof, Dofs, Solver, SolverSettings};
        let mat = J2PlaneStress::new(self.young, self.poisson, self.density, hardening).unwrap();
        let section = shell_elements::Section::new(self.thickness)
            .unwrap()
            .with_rule(shell_elements::RuleKind::Lobatto, self.rule_points)
            .unwrap();
        let set = ShellSet::from_mesh("strip", mesh, "all", section, form, mat).unwrap();
        let settings = SolverSettings {
            damping: 0.05 * self.omega(),
            ..Default::default()
        };
        let mut s = Solver::new(mesh, settings).unwrap();
        s.add_effect(set);
        s.fix("x0", Dofs::ALL).unwrap();
        s.fix("all", Dofs::of(&[Dof::Uy, Dof::Rx, Dof::Rz]))
            .unwrap();
        s
    }

    /// The strip's mesh, `rectangle(length, width, elements, 1)`.
    pub fn mesh(&self) -> fem_core::Mesh {
        fem_core::rectangle(self.length, self.width, self.elements, 1).unwrap()
    }
}
