//! The `ShellFormulation` trait (one element's force kernel) and the through-thickness integration both elements share.

use crate::block_nodes::BlockNodes;
use crate::error::{ShellError, check};
use crate::geometry::{Frame, V3};
use crate::lanes::{F4, Lanes4, Real};
use crate::material::{Material, PointUpdate};
use crate::section::{Section, ThroughThickness};

/// Default drilling coefficient γ (-) of both formulations: the relative
/// drilling penalty `k = γ G t A` per element (see [`ShellFormulation::drilling`]
/// and `docs/shells.md` for the study that chose it).
pub const DEFAULT_DRILLING: f64 = 1e-3;

/// Largest drilling coefficient accepted: the drilling mode's frequency stays
/// below the stable step's limit with a wide margin up to here (`docs/shells.md`).
pub const MAX_DRILLING: f64 = 0.1;

/// Check a drilling coefficient: finite, in [0, [`MAX_DRILLING`]].
pub(crate) fn check_drilling(gamma: f64) -> Result<(), ShellError> {
    check(
        "drilling",
        gamma,
        "-",
        "in [0, 0.1] (relative drilling penalty coefficient)",
        (0.0..=MAX_DRILLING).contains(&gamma),
    )
}

/// One element's state, borrowed from the shell set's arrays for the kernel.
pub struct ElementState<'a, H> {
    /// Current thickness (mm).
    pub thickness: &'a mut f64,
    /// In-plane stresses `[σ_xx, σ_yy, σ_xy]` (MPa), co-rotational frame,
    /// `IN_PLANE_POINTS × n` entries, in-plane point major, bottom to top.
    pub stress: &'a mut [[f64; 3]],
    /// Material history, same layout as `stress`.
    pub history: &'a mut [H],
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa), one per in-plane point.
    pub shear: &'a mut [[f64; 2]],
    /// Hourglass generalised forces (N, N·mm), `HOURGLASS_VARS` entries.
    pub hourglass: &'a mut [f64],
    /// Drilling moments (N·mm) about the element normal, one per node.
    pub drilling: &'a mut [f64; 4],
}

/// What one element's kernel produces in one step (of four elements in
/// lanes with `T = F4`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ElementResult<T = f64> {
    /// Forces on the element's nodes (N), global frame (= −f_int).
    pub f: [[T; 3]; 4],
    /// Moments on the element's nodes (N·mm), global frame.
    pub m: [[T; 3]; 4],
    /// Internal work increment (mJ): stresses and the drilling penalty,
    /// hourglass excluded.
    pub d_internal: T,
    /// The drilling penalty's share of `d_internal` (mJ).
    pub d_drilling: T,
    /// Hourglass work increment (mJ).
    pub d_hourglass: T,
    /// Plastic dissipation increment (mJ).
    pub d_plastic: T,
    /// Characteristic length for the stable time step (mm); ≤ 0 or NaN
    /// when the element degenerated.
    pub length: T,
    /// Unit normal of the element's frame (global), `e3`.
    pub normal: [T; 3],
    /// Projected area of the element (mm²), the frame's; 0 when the element degenerated.
    pub area: T,
}

impl<T: Real> ElementResult<T> {
    /// All zero (built in place: `Default` for the arrays is out of line,
    /// and would leave an AVX kernel).
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        let z = T::splat(0.0);
        ElementResult {
            f: [[z; 3]; 4],
            m: [[z; 3]; 4],
            d_internal: z,
            d_drilling: z,
            d_hourglass: z,
            d_plastic: z,
            length: z,
            normal: [z; 3],
            area: z,
        }
    }
}

impl<L: Lanes4> ElementResult<L> {
    /// The same result in [`F4`] lanes.
    #[inline(always)]
    pub(crate) fn into_f4(self) -> ElementResult<F4> {
        // (Loops, not `array::map` or closures: see `belytschko_tsay::to_lanes`.)
        let (mut f, mut m) = ([[F4::default(); 3]; 4], [[F4::default(); 3]; 4]);
        for i in 0..4 {
            for c in 0..3 {
                f[i][c] = F4(self.f[i][c].to_array());
                m[i][c] = F4(self.m[i][c].to_array());
            }
        }
        ElementResult {
            f,
            m,
            d_internal: F4(self.d_internal.to_array()),
            d_drilling: F4(self.d_drilling.to_array()),
            d_hourglass: F4(self.d_hourglass.to_array()),
            d_plastic: F4(self.d_plastic.to_array()),
            length: F4(self.length.to_array()),
            normal: [
                F4(self.normal[0].to_array()),
                F4(self.normal[1].to_array()),
                F4(self.normal[2].to_array()),
            ],
            area: F4(self.area.to_array()),
        }
    }
}

impl ElementResult<F4> {
    /// The result of the element in lane `l`.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> ElementResult {
        ElementResult {
            f: lane_nodes(&self.f, l),
            m: lane_nodes(&self.m, l),
            d_internal: self.d_internal.0[l],
            d_drilling: self.d_drilling.0[l],
            d_hourglass: self.d_hourglass.0[l],
            d_plastic: self.d_plastic.0[l],
            length: self.length.0[l],
            normal: [
                self.normal[0].0[l],
                self.normal[1].0[l],
                self.normal[2].0[l],
            ],
            area: self.area.0[l],
        }
    }

    /// Put one element's result into lane `l`.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, r: &ElementResult) {
        for i in 0..4 {
            for c in 0..3 {
                self.f[i][c].0[l] = r.f[i][c];
                self.m[i][c].0[l] = r.m[i][c];
            }
        }
        self.d_internal.0[l] = r.d_internal;
        self.d_drilling.0[l] = r.d_drilling;
        self.d_hourglass.0[l] = r.d_hourglass;
        self.d_plastic.0[l] = r.d_plastic;
        self.length.0[l] = r.length;
        for c in 0..3 {
            self.normal[c].0[l] = r.normal[c];
        }
        self.area.0[l] = r.area;
    }
}

/// The state of four consecutive elements, borrowed from the shell set's
/// arrays for a four-lane kernel.
///
/// Two layouts, chosen by [`ShellFormulation::lane_major`]:
/// * element-major (default): as [`ElementState`], the four elements one
///   after the other;
/// * lane-major: the four elements' values of one quantity side by side
///   (element `l` at position `l` of each group of four), so that a lane
///   kernel loads each quantity of the block with one vector load. Flattened
///   to `f64`, stress component `c` of point `k` of element `l` is at
///   `(3k + c)·4 + l`, shear component `c` of in-plane point `p` at
///   `(2p + c)·4 + l`, hourglass force `k` at `4k + l`, and
///   `drilling[i][l]` is node `i`'s moment of element `l`.
///
/// Thicknesses are `[l]` and histories element-major in both.
pub struct ElementBlock<'a, H> {
    /// Current thicknesses (mm).
    pub thickness: &'a mut [f64; 4],
    /// Stresses, `4 × IN_PLANE_POINTS × n` entries.
    pub stress: &'a mut [[f64; 3]],
    /// Material histories, `4 × IN_PLANE_POINTS × n` entries, element-major.
    pub history: &'a mut [H],
    /// Transverse shear stresses, `4 × IN_PLANE_POINTS` entries.
    pub shear: &'a mut [[f64; 2]],
    /// Hourglass generalised forces, `4 × HOURGLASS_VARS` entries.
    pub hourglass: &'a mut [f64],
    /// Drilling moments (N·mm) of the four elements' nodes.
    pub drilling: &'a mut [[f64; 4]; 4],
}

/// An element formulation: what a shell set runs for each of its quads.
pub trait ShellFormulation: Clone + Send + Sync + 'static {
    /// Name used in reports (`bt`, `fully-integrated`).
    const NAME: &'static str;
    /// Number of in-plane integration points (1 or 4).
    const IN_PLANE_POINTS: usize;
    /// Number of hourglass generalised forces per element.
    const HOURGLASS_VARS: usize;

    /// Drilling coefficient γ (-) of the relative drilling penalty.
    fn drilling(&self) -> f64;

    /// Whether [`compute_x4`](Self::compute_x4) takes a block's state
    /// lane-major (see [`ElementBlock`]) for this section; the shell set
    /// stores its blocks so. Default: element-major.
    fn lane_major(&self, sec: &Section) -> bool {
        let _ = sec;
        false
    }

    /// Check the formulation's parameters (called when a shell set is built).
    fn validate(&self) -> Result<(), ShellError> {
        check_drilling(self.drilling())
    }

    /// Update the element's stresses from the nodal velocities (`v`, `w`: mm/s,
    /// rad/s, at `t_{n+1/2}`) over `dt` in the configuration `x` (`t_{n+1}`)
    /// and return its nodal forces and energy increments.
    #[allow(clippy::too_many_arguments)]
    fn compute<M: Material>(
        &self,
        mat: &M,
        sec: &Section,
        x: &[V3; 4],
        v: &[V3; 4],
        w: &[V3; 4],
        dt: f64,
        st: ElementState<'_, M::History>,
    ) -> ElementResult;

    /// The static form of a set of these shells at its current state (the
    /// implicit springback). By default none: one line naming the element.
    ///
    /// # Errors
    /// The formulation has no static form.
    fn static_form<M: Material>(
        set: &crate::ShellSet<Self, M>,
    ) -> Result<fem_core::StaticForm, String> {
        let _ = set;
        Err(format!(
            "the {} shell has no static form (springback method \"dynamic-relaxation\" works with every element)",
            Self::NAME
        ))
    }

    /// Take back into `set` the committed state of the static form
    /// [`ShellFormulation::static_form`] gave, after its solve.
    ///
    /// # Errors
    /// `solved` is not that static form.
    fn absorb_static<M: Material>(
        set: &mut crate::ShellSet<Self, M>,
        solved: &dyn fem_core::statics::StaticTangent,
    ) -> Result<(), String> {
        let _ = (set, solved);
        Err(format!("the {} shell has no static form", Self::NAME))
    }

    /// Four consecutive elements at once (their nodes in `nodes`), element
    /// `l`'s result into lane `l` of `out`. By default one after the other
    /// through [`compute`](Self::compute); a formulation that overrides it
    /// must give each element what `compute` gives it, to rounding (BT's
    /// lanes fuse the products of [`Real::madd`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn compute_x4<M: Material>(
        &self,
        mat: &M,
        sec: &Section,
        nodes: &BlockNodes<'_>,
        dt: f64,
        st: ElementBlock<'_, M::History>,
        out: &mut ElementResult<F4>,
    ) {
        compute_by_element(self, mat, sec, nodes, dt, st, out);
    }
}

/// [`ShellFormulation::compute_x4`] one element after the other through
/// [`ShellFormulation::compute`] (element-major block state).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn compute_by_element<F: ShellFormulation, M: Material>(
    form: &F,
    mat: &M,
    sec: &Section,
    nodes: &BlockNodes<'_>,
    dt: f64,
    st: ElementBlock<'_, M::History>,
    out: &mut ElementResult<F4>,
) {
    let nsp = st.stress.len() / 4;
    let ip = st.shear.len() / 4;
    let nhg = st.hourglass.len() / 4;
    for (l, (((((t, s), h), sh), hg), dr)) in st
        .thickness
        .iter_mut()
        .zip(st.stress.chunks_mut(nsp))
        .zip(st.history.chunks_mut(nsp))
        .zip(st.shear.chunks_mut(ip))
        .zip(st.hourglass.chunks_mut(nhg))
        .zip(st.drilling.iter_mut())
        .enumerate()
    {
        let (x, v, w) = nodes.element(l);
        let r = form.compute(
            mat,
            sec,
            &x,
            &v,
            &w,
            dt,
            ElementState {
                thickness: t,
                stress: s,
                history: h,
                shear: sh,
                hourglass: &mut hg[..F::HOURGLASS_VARS],
                drilling: dr,
            },
        );
        out.set_lane(l, &r);
    }
}

/// Element `l`'s nodes out of a four-lane block.
#[inline(always)]
pub(crate) fn lane_nodes(a: &[[F4; 3]; 4], l: usize) -> [V3; 4] {
    let mut o = [[0.0; 3]; 4];
    for i in 0..4 {
        o[i] = [a[i][0].0[l], a[i][1].0[l], a[i][2].0[l]];
    }
    o
}

/// Stress resultants and energy of one through-thickness integration.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SectionResult<T = f64> {
    /// Membrane forces N (N/mm), `[xx, yy, xy]`.
    pub n: [T; 3],
    /// Moments M (N·mm/mm), `[xx, yy, xy]`.
    pub m: [T; 3],
    /// Stress work per unit area (mJ/mm²), trapezoidal in time.
    pub work: T,
    /// Plastic dissipation per unit area (mJ/mm²).
    pub dissipation: T,
    /// Thickness strain increment, averaged through the thickness (-).
    pub deps_zz: T,
}

/// Update every point of one section for the membrane strain increment `de`
/// and the curvature increment `dk` (engineering shear in both), with
/// `Δε(z) = de + z dk`, `z = ζ t/2`. The common rules (3, 5, 7 points) run a
/// loop of fixed length, unrolled and free of bounds checks.
#[inline(always)]
pub(crate) fn integrate_section<M: Material>(
    mat: &M,
    rule: &ThroughThickness,
    t: f64,
    de: [f64; 3],
    dk: [f64; 3],
    stress: &mut [[f64; 3]],
    history: &mut [M::History],
) -> SectionResult {
    match rule.n {
        5 => integrate_points::<M, 5>(mat, rule, t, de, dk, stress, history),
        3 => integrate_points::<M, 3>(mat, rule, t, de, dk, stress, history),
        7 => integrate_points::<M, 7>(mat, rule, t, de, dk, stress, history),
        n => integrate_n(mat, rule, n, t, de, dk, stress, history),
    }
}

/// [`integrate_section`] for a rule of `N` points.
#[inline(always)]
fn integrate_points<M: Material, const N: usize>(
    mat: &M,
    rule: &ThroughThickness,
    t: f64,
    de: [f64; 3],
    dk: [f64; 3],
    stress: &mut [[f64; 3]],
    history: &mut [M::History],
) -> SectionResult {
    let (Some(stress), Some(history)) = (
        stress.first_chunk_mut::<N>(),
        history.first_chunk_mut::<N>(),
    ) else {
        return integrate_n(mat, rule, N, t, de, dk, stress, history);
    };
    let (h, z, d) = section_increments(rule, t, de, dk);
    let old = *stress;
    let u = mat.update_points(stress, history, &d);
    section_sums(rule, h, &z, &d, &old, stress, &u)
}

/// [`integrate_section`] for four elements in lanes, `N` points each
/// (`history[l]`: element `l`'s points).
#[inline(always)]
pub(crate) fn integrate_section_x4<M: Material, L: Lanes4, const N: usize>(
    mat: &M,
    rule: &ThroughThickness,
    t: L,
    de: [L; 3],
    dk: [L; 3],
    stress: &mut [[L; 3]; N],
    history: &mut [[M::History; N]; 4],
) -> SectionResult<L> {
    let (h, z, d) = section_increments(rule, t, de, dk);
    let old = *stress;
    let u = mat.update_points_x4(stress, history, &d);
    section_sums(rule, h, &z, &d, &old, stress, &u)
}

/// Half thickness, point heights and strain increments `Δε(z) = de + z dk`
/// of `N` points (one element or four in lanes).
#[inline(always)]
#[allow(clippy::type_complexity)]
pub(crate) fn section_increments<T: Real, const N: usize>(
    rule: &ThroughThickness,
    t: T,
    de: [T; 3],
    dk: [T; 3],
) -> (T, [T; N], [[T; 3]; N]) {
    let h = t * 0.5;
    let mut z = [T::default(); N];
    let mut d = [[T::default(); 3]; N];
    for k in 0..N {
        z[k] = h * rule.zeta[k];
        d[k] = [
            z[k].madd(dk[0], de[0]),
            z[k].madd(dk[1], de[1]),
            z[k].madd(dk[2], de[2]),
        ];
    }
    (h, z, d)
}

/// The section sums of [`integrate_section`] after the points' update from
/// `old` to `stress` (one element or four in lanes).
#[inline(always)]
pub(crate) fn section_sums<T: Real, const N: usize>(
    rule: &ThroughThickness,
    h: T,
    z: &[T; N],
    d: &[[T; 3]; N],
    old: &[[T; 3]; N],
    stress: &[[T; 3]; N],
    u: &[PointUpdate<T>; N],
) -> SectionResult<T> {
    let z0 = T::splat(0.0);
    let mut r = SectionResult::<T> {
        n: [z0; 3],
        m: [z0; 3],
        work: z0,
        dissipation: z0,
        deps_zz: z0,
    };
    for k in 0..N {
        let wk = h * rule.weight[k];
        let (s, o, d) = (stress[k], old[k], d[k]);
        let wz = wk * z[k];
        r.n[0] = wk.madd(s[0], r.n[0]);
        r.n[1] = wk.madd(s[1], r.n[1]);
        r.n[2] = wk.madd(s[2], r.n[2]);
        r.m[0] = wz.madd(s[0], r.m[0]);
        r.m[1] = wz.madd(s[1], r.m[1]);
        r.m[2] = wz.madd(s[2], r.m[2]);
        let pw = (o[2] + s[2]).madd(d[2], (o[1] + s[1]).madd(d[1], (o[0] + s[0]) * d[0]));
        r.work = (wk * 0.5).madd(pw, r.work);
        r.dissipation = wk.madd(u[k].dissipation, r.dissipation);
        r.deps_zz = u[k].deps_zz.madd(T::splat(rule.weight[k]), r.deps_zz);
    }
    r.deps_zz = r.deps_zz * 0.5;
    r
}

/// [`integrate_section`] for the first `n` points of `rule`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn integrate_n<M: Material>(
    mat: &M,
    rule: &ThroughThickness,
    n: usize,
    t: f64,
    de: [f64; 3],
    dk: [f64; 3],
    stress: &mut [[f64; 3]],
    history: &mut [M::History],
) -> SectionResult {
    let h = 0.5 * t;
    let mut r = SectionResult::default();
    let (stress, history) = (&mut stress[..n], &mut history[..n]);
    let (zeta, weight) = (&rule.zeta[..n], &rule.weight[..n]);
    for k in 0..n {
        let z = zeta[k] * h;
        let wk = weight[k] * h;
        let d = [de[0] + z * dk[0], de[1] + z * dk[1], de[2] + z * dk[2]];
        let s = &mut stress[k];
        let old = *s;
        let u = mat.update(s, &mut history[k], d);
        let s = *s;
        r.n[0] += wk * s[0];
        r.n[1] += wk * s[1];
        r.n[2] += wk * s[2];
        r.m[0] += wk * z * s[0];
        r.m[1] += wk * z * s[1];
        r.m[2] += wk * z * s[2];
        r.work +=
            wk * 0.5 * ((old[0] + s[0]) * d[0] + (old[1] + s[1]) * d[1] + (old[2] + s[2]) * d[2]);
        r.dissipation += wk * u.dissipation;
        r.deps_zz += weight[k] * u.deps_zz;
    }
    r.deps_zz *= 0.5;
    r
}

/// Local velocities of the nodes, `(v̂, ω̂)`.
#[inline(always)]
pub(crate) fn local_velocities<T: Real>(
    fr: &Frame<T>,
    v: &[[T; 3]; 4],
    w: &[[T; 3]; 4],
) -> ([[T; 3]; 4], [[T; 3]; 4]) {
    let mut vl = [[T::default(); 3]; 4];
    let mut wl = [[T::default(); 3]; 4];
    for i in 0..4 {
        vl[i] = fr.local(v[i]);
        wl[i] = fr.local(w[i]);
    }
    (vl, wl)
}

/// Remove the element's rigid rotation about its local in-plane axes from the
/// in-plane nodal velocities of a warped element (after Belytschko &
/// Leviathan 1994, "Projection schemes for one-point quadrature shell
/// elements", CMAME 115).
///
/// The kernels read the membrane rates and the membrane hourglass rates from
/// the in-plane velocities `v̂x`, `v̂y` as if the nodes lay in the mean plane,
/// but a warped element's nodes sit at heights `ẑ_I` off it, so a rigid
/// rotation `ω̂` about the in-plane axes moves them in-plane by
/// `(ω̂y ẑ_I, −ω̂x ẑ_I)`, which is not a linear field: the 2×2 B-matrix and
/// the hourglass vectors read it as strain. The element's rigid rotation
/// about the in-plane axes is the mean gradient of the normal velocity,
/// `ω̄x = Σ B2_I v̂z_I`, `ω̄y = −Σ B1_I v̂z_I` (mean B, exact for a rigid
/// motion); its in-plane velocity at the nodes' heights is taken out:
/// `v̂x_I −= ω̄y ẑ_I`, `v̂y_I += ω̄x ẑ_I`. The mean B is orthogonal to
/// `ẑ ∝ h`, so the centre membrane rates and the element spin are unchanged
/// and a flat element (`ẑ = 0`) is untouched. The nodal forces conjugate to
/// these velocities follow from [`warp_rotation_forces`]. Returns `(ω̄x, ω̄y)`.
/// Used by the fully integrated element; Belytschko–Tsay applies the same
/// correction in closed form to the only rates it changes there, the
/// membrane hourglass rates.
#[inline(always)]
pub(crate) fn remove_warp_rotation<T: Real>(
    z: &[T; 4],
    b1: &[T; 4],
    b2: &[T; 4],
    vl: &mut [[T; 3]; 4],
) -> (T, T) {
    let (mut wx, mut wy) = (T::splat(0.0), T::splat(0.0));
    for i in 0..4 {
        wx += b2[i] * vl[i][2];
        wy -= b1[i] * vl[i][2];
    }
    for i in 0..4 {
        vl[i][0] -= wy * z[i];
        vl[i][1] += wx * z[i];
    }
    (wx, wy)
}

/// Transpose of [`remove_warp_rotation`] on the local internal nodal forces
/// `f` (conjugate to the corrected velocities on entry, to the nodal
/// velocities on return): `f̂z_J += B1_J Σ f̂x_I ẑ_I + B2_J Σ f̂y_I ẑ_I`. The
/// power `Σ f·v̂` is then the stress power of the corrected rates, so the
/// energy ledger stays closed, and the forces balance the moments about the
/// in-plane axes that in-plane forces at the warped heights exert.
#[inline(always)]
pub(crate) fn warp_rotation_forces<T: Real>(
    z: &[T; 4],
    b1: &[T; 4],
    b2: &[T; 4],
    f: &mut [[T; 3]; 4],
) {
    let (mut sx, mut sy) = (T::splat(0.0), T::splat(0.0));
    for i in 0..4 {
        sx += f[i][0] * z[i];
        sy += f[i][1] * z[i];
    }
    for i in 0..4 {
        f[i][2] += b1[i] * sx + b2[i] * sy;
    }
}

/// Relative drilling penalty (after Hughes & Brezzi 1989 and Allman 1984,
/// lumped at the nodes): with the element's mean in-plane spin
/// `Ω = ½ Σ (B1_I v̂y_I − B2_I v̂x_I)` (skew part of the mean in-plane
/// velocity gradient, so the rigid rotation of the element about its normal)
/// and the nodal drilling rates `ω̂z_I`, each node's drilling moment follows
/// `m_I += k (ω̂z_I − Ω) Δt`, `k = γ G t A / 4` (the energy
/// `½ γ G t ∫ (θz − Ω)² dA` with θz lumped at the nodes). Rigid motions and
/// any in-plane rotation of the element leave `ω̂z_I − Ω = 0` and so no
/// drilling force. The internal power `Σ m_I (ω̂z_I − Ω)` gives the nodal
/// moments `m_I` about the normal and the in-plane forces
/// `(½ M B2_J, −½ M B1_J)`, `M = Σ m_I`, which the caller adds.
/// Returns `(M, work increment)`, the work trapezoidal in time (mJ).
///
/// With `tilt = Some(c, ω̄x, ω̄y)` (the warping correction: twist `c`, the
/// element's rigid rotation about its in-plane axes), the fibres lie along
/// the warped surface's nodal normals `n_I = e3 − c (ŷ_I, x̂_I, 0)` (`x`, `y`
/// the nodes' local coordinates), and the penalty acts on the rotation about
/// them relative to the surface's spin about them:
/// `r_I = ω̂z_I − Ω − c (ŷ_I (ω̂x_I − ω̄x) + x̂_I (ω̂y_I − ω̄y))`, zero for every
/// rigid motion. Unlike the plain `ω̂z_I − Ω` it does not resist the
/// bending rotations' share `c (ŷ_I ω̂x_I + x̂_I ω̂y_I)` along `e3`, which
/// scales with t against a bending stiffness ∝ t³ and locks thin warped
/// shells (thin twisted beam). Its conjugate loads, which the caller adds:
/// moments `−c ŷ_I m_I`, `−c x̂_I m_I` about x and y at node I and normal
/// forces `c (S_y B2_J − S_x B1_J)`, `S_x = Σ x̂_I m_I`, `S_y = Σ ŷ_I m_I`,
/// returned as the third and fourth values (0 without tilt).
///
/// `(x, y)` are the nodes' local coordinates where the rates are read (the
/// midpoint configuration), `(xf, yf)` where the forces are assembled
/// (`t_{n+1}`): the sums `S_x`, `S_y` take the latter.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn drilling_penalty<T: Real>(
    k: T,
    b1: &[T; 4],
    b2: &[T; 4],
    vl: &[[T; 3]; 4],
    wl: &[[T; 3]; 4],
    dt: f64,
    m: &mut [T; 4],
    tilt: Option<(T, T, T)>,
    (x, y): (&[T; 4], &[T; 4]),
    (xf, yf): (&[T; 4], &[T; 4]),
) -> (T, T, T, T) {
    let zero = T::splat(0.0);
    let mut spin = zero;
    for i in 0..4 {
        spin += b1[i].madd(vl[i][1], -(b2[i] * vl[i][0]));
    }
    spin = spin * 0.5;
    let mut rate = [zero; 4];
    for i in 0..4 {
        rate[i] = wl[i][2] - spin;
    }
    if let Some((c, ox, oy)) = tilt {
        for i in 0..4 {
            rate[i] = (-c).madd(x[i].madd(wl[i][1] - oy, y[i] * (wl[i][0] - ox)), rate[i]);
        }
    }
    let kdt = k * dt;
    let (mut sum, mut work) = (zero, zero);
    for i in 0..4 {
        let old = m[i];
        let new = kdt.madd(rate[i], old);
        m[i] = new;
        sum += new;
        work = (old + new).madd(rate[i], work);
    }
    let (mut sx, mut sy) = (zero, zero);
    if tilt.is_some() {
        for i in 0..4 {
            sx = xf[i].madd(m[i], sx);
            sy = yf[i].madd(m[i], sy);
        }
    }
    (sum, work * 0.5 * dt, sx, sy)
}

/// The step's midpoint configuration `x_{n+1/2} = x_{n+1} − ½Δt v_{n+1/2}`,
/// where the elements read their rates (docs/shells.md, "Strain increments
/// at the midpoint").
#[inline(always)]
pub(crate) fn midpoint<T: Real>(x: &[[T; 3]; 4], v: &[[T; 3]; 4], dt: f64) -> [[T; 3]; 4] {
    let h = T::splat(-0.5 * dt);
    std::array::from_fn(|i| std::array::from_fn(|k| h.madd(v[i][k], x[i][k])))
}

/// The in-plane turn from the frame `from` (the step's midpoint, where the
/// rates are read) to the frame `to` (its end, where the stresses are kept):
/// `(cos φ, sin φ)` of the angle of `to`'s e1 in `from`'s (e1, e2),
/// normalised (the two frames' normals differ by O(Δt)).
#[inline(always)]
pub(crate) fn frame_turn<T: Real>(from: &Frame<T>, to: &Frame<T>) -> (T, T) {
    let (e1, e2, f1) = (&from.r[0], &from.r[1], &to.r[0]);
    let c = f1[2].madd(e1[2], f1[1].madd(e1[1], f1[0] * e1[0]));
    let s = f1[2].madd(e2[2], f1[1].madd(e2[1], f1[0] * e2[0]));
    let inv = T::splat(1.0) / s.madd(s, c * c).sqrt();
    (c * inv, s * inv)
}

/// An in-plane tensor increment `[xx, yy, 2xy]` (engineering shear) turned
/// by [`frame_turn`]'s `(c, s)` into the new frame's components.
#[inline(always)]
pub(crate) fn turn_tensor<T: Real>((c, s): (T, T), [a, b, g]: [T; 3]) -> [T; 3] {
    let (cc, ss, cs) = (c * c, s * s, c * s);
    [
        cs.madd(g, cc.madd(a, ss * b)),
        (-cs).madd(g, ss.madd(a, cc * b)),
        (cc - ss).madd(g, (cs + cs) * (b - a)),
    ]
}

/// An in-plane vector `[x, y]` turned by [`frame_turn`]'s `(c, s)` into the
/// new frame's components.
#[inline(always)]
pub(crate) fn turn_vector<T: Real>((c, s): (T, T), [x, y]: [T; 2]) -> [T; 2] {
    [s.madd(y, c * x), c.madd(y, -(s * x))]
}

/// Thickness after a thickness-strain increment (second-order exponential).
#[inline(always)]
pub(crate) fn new_thickness<T: Real>(t: T, dzz: T) -> T {
    t * (dzz * 0.5).madd(dzz, dzz + 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Hardening, J2PlaneStress};
    use crate::section::{RuleKind, ThroughThickness};

    /// Bend one section in plane strain (ε_yy = 0, curvature κ_xx only) to `k_end`
    /// in `steps` equal increments; return M_xx (N·mm/mm) at each step.
    fn bend(
        rule: &ThroughThickness,
        mat: &J2PlaneStress,
        t: f64,
        k_end: f64,
        steps: usize,
    ) -> Vec<f64> {
        let mut s = vec![[0.0; 3]; rule.n];
        let mut h = vec![mat.initial_history(); rule.n];
        (0..steps)
            .map(|_| {
                integrate_section(
                    mat,
                    rule,
                    t,
                    [0.0; 3],
                    [k_end / steps as f64, 0.0, 0.0],
                    &mut s,
                    &mut h,
                )
                .m[0]
            })
            .collect()
    }

    /// Elastic–plastic plane-strain bending of a perfectly plastic section
    /// (Hill, *The Mathematical Theory of Plasticity*, 1950, ch. VII; Lubliner
    /// §4.4): with ν → 0.5 the elastic section has σ_yy = σ_xx/2, so the
    /// outer fibres yield at σ_xx = S = 2σ_y/√3 and M_e = S t²/6; beyond,
    /// M = S t²/4 (1 − ⅓ (κ_e/κ)²) → S t²/4. Through our own integration
    /// (Lobatto, 31 points: the outer points sit on the surfaces). Tolerances:
    /// first yield 0.1 %, the whole M(κ) curve 0.5 %, M at 50 κ_e within 0.5 % of S t²/4
    /// and within 0.1 % of the rule's own fully plastic moment S (t/2)² Σ w|ζ|.
    #[test]
    fn plane_strain_bending_reaches_elastic_and_fully_plastic_moments() {
        let (e, nu, sy, t) = (200_000.0, 0.4999, 250.0, 1.0);
        let mat =
            J2PlaneStress::new(e, nu, 7.85e-9, Hardening::swift(sy, 1e-3, 0.0).unwrap()).unwrap();
        let s_ps = 2.0 * sy / 3f64.sqrt();
        // Elastic plane strain: σ_xx = E/(1−ν²) κ z; first yield when σ_vm = σ_y at z = t/2.
        let c = e / (1.0 - nu * nu);
        let sxx_y = sy / (1.0 - nu + nu * nu).sqrt();
        let k_e = sxx_y / (c * 0.5 * t);
        let rule = ThroughThickness::new(RuleKind::Lobatto, 31).unwrap();
        let steps = 5000;
        let m = bend(&rule, &mat, t, 50.0 * k_e, steps);
        let me = s_ps * t * t / 6.0;
        let mp = s_ps * t * t / 4.0;
        // Step at which κ = κ_e: index steps/50 − 1.
        let m_first = m[steps / 50 - 1];
        assert!(
            (m_first / me - 1.0).abs() < 1e-3,
            "first yield: {m_first} vs S t²/6 = {me}"
        );
        for (i, mi) in m.iter().enumerate().skip(steps / 50) {
            let k = 50.0 * k_e * (i + 1) as f64 / steps as f64;
            let exact = mp * (1.0 - (k_e / k).powi(2) / 3.0);
            assert!(
                (mi / exact - 1.0).abs() < 5e-3,
                "κ/κ_e = {}: {mi} vs {exact}",
                k / k_e
            );
        }
        let m_end = *m.last().unwrap();
        let (z, w) = rule.points();
        let f31: f64 = z.iter().zip(w).map(|(z, w)| w * z.abs()).sum();
        println!(
            "Lobatto 31: M(50 κ_e) / (S t²/4) = {:.5}, Σ w|ζ| = {f31:.5}",
            m_end / mp
        );
        assert!((m_end / mp - 1.0).abs() < 5e-3, "{m_end} vs {mp}");
        assert!(
            (m_end / (mp * f31) - 1.0).abs() < 1e-3,
            "{m_end} vs {}",
            mp * f31
        );
        // The default 5 Gauss points: the fully plastic moment is S (t/2)² Σ w|ζ|.
        let g5 = ThroughThickness::new(RuleKind::Gauss, 5).unwrap();
        let m5 = *bend(&g5, &mat, t, 50.0 * k_e, steps).last().unwrap();
        let (z, w) = g5.points();
        let factor: f64 = z.iter().zip(w).map(|(z, w)| w * z.abs()).sum();
        println!(
            "5 Gauss points: M(50 κ_e) / (S t²/4) = {:.5}, Σ w|ζ| = {factor:.5}",
            m5 / mp
        );
        assert!((m5 / (mp * factor) - 1.0).abs() < 2e-3);
    }
}
