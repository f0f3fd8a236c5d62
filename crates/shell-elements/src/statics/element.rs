//! One element's internal forces at a trial state: the explicit kernel
//! (Belytschko–Tsay or fully integrated) run as a single step from the
//! committed state, over `f64` (forces) or [`Dual`] (forces and their
//! exact derivatives).

use super::dual::{Dual, N_DERIV};
use super::state::ShellState;
use crate::belytschko_tsay::{Lanes, Moduli};
use crate::formulation::{ElementResult, SectionResult, ShellFormulation};
use crate::fully_integrated::PointLanes;
use crate::lanes::Real;
use crate::material::{Material, PointUpdate};
use crate::section::ThroughThickness;
use crate::{BelytschkoTsay, FullyIntegrated};

/// A scalar the static kernel runs on: `f64` for the forces alone,
/// [`Dual`] for the forces and their derivatives.
pub(crate) trait StaticScalar: Real<Mask = bool> {
    /// The value (without derivatives).
    fn value(self) -> f64;

    /// Update one point from its committed `stress` and `history` (copied
    /// into `stress_out`, `history_out` and updated there) for the strain
    /// increment `deps`; the new stress as `Self`. For [`Dual`] the stress
    /// derivatives follow the chain rule through the material's
    /// [`Material::consistent_tangent`]: `∂σ = C_alg ∂Δε`.
    fn update_point<M: Material>(
        mat: &M,
        committed: (&[f64; 3], &M::History),
        deps: [Self; 3],
        stress_out: &mut [f64; 3],
        history_out: &mut M::History,
    ) -> ([Self; 3], PointUpdate<Self>);
}

impl StaticScalar for f64 {
    #[inline(always)]
    fn value(self) -> f64 {
        self
    }

    fn update_point<M: Material>(
        mat: &M,
        (stress, history): (&[f64; 3], &M::History),
        deps: [f64; 3],
        stress_out: &mut [f64; 3],
        history_out: &mut M::History,
    ) -> ([f64; 3], PointUpdate) {
        *stress_out = *stress;
        *history_out = *history;
        let u = mat.update(stress_out, history_out, deps);
        (*stress_out, u)
    }
}

impl StaticScalar for Dual {
    #[inline(always)]
    fn value(self) -> f64 {
        self.re
    }

    fn update_point<M: Material>(
        mat: &M,
        (stress, history): (&[f64; 3], &M::History),
        deps: [Dual; 3],
        stress_out: &mut [f64; 3],
        history_out: &mut M::History,
    ) -> ([Dual; 3], PointUpdate<Dual>) {
        let de = deps.map(|d| d.re);
        let (s, u) = f64::update_point(mat, (stress, history), de, stress_out, history_out);
        let c = mat.consistent_tangent(stress, history, de);
        let sigma = std::array::from_fn(|i| {
            let mut d = [0.0; N_DERIV];
            for (j, dj) in deps.iter().enumerate() {
                for (x, g) in d.iter_mut().zip(&dj.d) {
                    *x += c[i][j] * g;
                }
            }
            Dual { re: s[i], d }
        });
        let u = PointUpdate {
            deps_zz: Dual::constant(u.deps_zz),
            dissipation: Dual::constant(u.dissipation),
        };
        (sigma, u)
    }
}

/// Integrate one section from its committed points `points` (a range
/// into the state's points, bottom to top): strain increment
/// `Δε(z) = de + z dk` at each point of `rule` (`z = ζ t/2`, committed
/// thickness `t`), the material update from the committed point state into
/// `trial`, and the resultants and work as the explicit `section_sums`
/// forms them.
#[allow(clippy::too_many_arguments)]
fn integrate_section<T: StaticScalar, M: Material>(
    mat: &M,
    rule: &ThroughThickness,
    t: f64,
    de: [T; 3],
    dk: [T; 3],
    points: std::ops::Range<usize>,
    committed: &ShellState<M::History>,
    trial: &mut ShellState<M::History>,
) -> SectionResult<T> {
    let zero = T::splat(0.0);
    let mut r = SectionResult::<T> {
        n: [zero; 3],
        m: [zero; 3],
        work: zero,
        dissipation: zero,
        deps_zz: zero,
    };
    let h = 0.5 * t;
    for (k, p) in points.enumerate() {
        let (z, wk) = (h * rule.zeta[k], h * rule.weight[k]);
        let d: [T; 3] = std::array::from_fn(|c| dk[c] * z + de[c]);
        let old = committed.stress[p];
        let (s, u) = T::update_point(
            mat,
            (&old, &committed.history[p]),
            d,
            &mut trial.stress[p],
            &mut trial.history[p],
        );
        for c in 0..3 {
            r.n[c] += s[c] * wk;
            r.m[c] += s[c] * (wk * z);
            r.work += (s[c] + old[c]) * d[c] * (0.5 * wk);
        }
        r.dissipation += u.dissipation * wk;
        r.deps_zz += u.deps_zz * rule.weight[k];
    }
    r.deps_zz = r.deps_zz * 0.5;
    r
}

/// The kernel's inputs for one element: trial positions `x` (mm), the
/// translation increments `dx = x − x_committed` (mm) and the rotation
/// increments `dtheta` (rad, global) since the committed state.
pub(crate) struct ElementMotion<T> {
    /// Trial positions of the four nodes.
    pub x: [[T; 3]; 4],
    /// Translation increments since the committed state.
    pub dx: [[T; 3]; 4],
    /// Rotation vectors since the committed state.
    pub dtheta: [[T; 3]; 4],
}

/// A formulation the static shells can run: its explicit kernel as one
/// step of length 1 from the committed state.
pub(crate) trait StaticKernel: ShellFormulation {
    /// Element `e`'s nodal forces and moments at the trial state `motion`,
    /// in the explicit kernel's convention (`out.f`, `out.m` are `−F_int`,
    /// global), with its trial state written into `trial`; `None` when the
    /// element degenerates (zero or negative area in the trial or the
    /// midpoint configuration).
    #[allow(clippy::too_many_arguments)]
    fn element_forces<T: StaticScalar, M: Material>(
        &self,
        md: &Moduli,
        mat: &M,
        rule: &ThroughThickness,
        motion: &ElementMotion<T>,
        e: usize,
        committed: &ShellState<M::History>,
        trial: &mut ShellState<M::History>,
    ) -> Option<ElementResult<T>>;
}

impl StaticKernel for BelytschkoTsay {
    fn element_forces<T: StaticScalar, M: Material>(
        &self,
        md: &Moduli,
        mat: &M,
        rule: &ThroughThickness,
        motion: &ElementMotion<T>,
        e: usize,
        committed: &ShellState<M::History>,
        trial: &mut ShellState<M::History>,
    ) -> Option<ElementResult<T>> {
        // One explicit step of length 1 from the committed state: the
        // "rates" are the increments, the midpoint is ½ (x_committed + x).
        let rt = self.rates(&motion.x, &motion.dx, &motion.dtheta, 1.0);
        if !rt.valid {
            return None;
        }
        let t = committed.thickness[e];
        let points = committed.points_of(e, 0);
        let sr = integrate_section(
            mat,
            rule,
            t,
            rt.membrane,
            rt.bending,
            points,
            committed,
            trial,
        );
        let (ip, hg) = (committed.in_plane_index(e, 0), committed.hourglass_of(e));
        let mut thickness = T::splat(t);
        let mut shear = committed.shear[ip].map(T::splat);
        let mut hourglass: [T; 5] =
            std::array::from_fn(|k| T::splat(committed.hourglass[hg.start + k]));
        let mut drilling = committed.drilling[e].map(T::splat);
        let mut out = ElementResult::<T>::zero();
        self.forces(
            md,
            &rt,
            sr,
            1.0,
            Lanes {
                thickness: &mut thickness,
                shear: &mut shear,
                hourglass: &mut hourglass,
                drilling: &mut drilling,
            },
            &mut out,
        );
        trial.thickness[e] = thickness.value();
        trial.shear[ip] = shear.map(T::value);
        for (q, h) in trial.hourglass[hg].iter_mut().zip(hourglass) {
            *q = h.value();
        }
        trial.drilling[e] = drilling.map(T::value);
        Some(out)
    }
}

impl StaticKernel for FullyIntegrated {
    fn element_forces<T: StaticScalar, M: Material>(
        &self,
        md: &Moduli,
        mat: &M,
        rule: &ThroughThickness,
        motion: &ElementMotion<T>,
        e: usize,
        committed: &ShellState<M::History>,
        trial: &mut ShellState<M::History>,
    ) -> Option<ElementResult<T>> {
        let t = committed.thickness[e];
        let ip = committed.in_plane_index(e, 0);
        let mut thickness = T::splat(t);
        let mut shear: [[T; 2]; 4] = std::array::from_fn(|p| committed.shear[ip + p].map(T::splat));
        let mut drilling = committed.drilling[e].map(T::splat);
        // Each Gauss point's stack from its committed points.
        let section = |p: usize, de: [T; 3], dk: [T; 3]| {
            let points = committed.points_of(e, p);
            integrate_section(mat, rule, t, de, dk, points, committed, trial)
        };
        let st = PointLanes {
            thickness: &mut thickness,
            shear: &mut shear,
            drilling: &mut drilling,
        };
        // One explicit step of length 1 from the committed state, as above.
        let out = self
            .kernel(md, &motion.x, &motion.dx, &motion.dtheta, 1.0, st, section)
            .ok()?;
        trial.thickness[e] = thickness.value();
        for (s, tau) in trial.shear[ip..ip + 4].iter_mut().zip(shear) {
            *s = tau.map(T::value);
        }
        trial.drilling[e] = drilling.map(T::value);
        Some(out)
    }
}
