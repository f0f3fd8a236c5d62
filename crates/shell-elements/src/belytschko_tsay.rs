//! `BelytschkoTsay`: the one-point co-rotational shell with stiffness-based hourglass control, warped-element projection and the optional BWC-style warping correction.
//!
//! Kinematics (Belytschko, Lin & Tsay 1984): Mindlin plate in the element's
//! co-rotational frame, velocity at height z: `v̂ + z (ω̂_y, −ω̂_x, 0)`, so with
//! the one-point B-matrix at the centre `B1 = ∂N/∂x`, `B2 = ∂N/∂y`:
//!
//! * membrane rate `d = (B1·v̂x, B2·v̂y, B2·v̂x + B1·v̂y)`,
//! * curvature rate `κ = (B1·θ̂y, −B2·θ̂x, B2·θ̂y − B1·θ̂x)`,
//! * transverse shear `γ = (∂w/∂x + θy, ∂w/∂y − θx)`, either at the centre
//!   with `θ` the node average (original BT) or, by default, the
//!   Bathe–Dvorkin edge-tied field evaluated at the centre (as in the
//!   Belytschko–Wong–Chiang element), which makes the element pass the
//!   bending patch test on distorted meshes.
//!
//! Warped elements (`docs/shells.md`): the nodes lie at heights
//! `ẑ_I = (h·ẑ/4) h_I` off the mean plane, so a rigid rotation `ω̂` about the
//! in-plane axes moves them in-plane by `(ω̂y ẑ_I, −ω̂x ẑ_I)`. The centre B is
//! orthogonal to `h` and does not see it, but the membrane hourglass rates
//! do (`γ·ẑ = ½ h·ẑ`). Always on: the element's rigid rotation about its
//! in-plane axes, `ω̄x = Σ B2_I v̂z_I`, `ω̄y = −Σ B1_I v̂z_I`, is removed from
//! the in-plane velocities (after Belytschko & Leviathan 1994; see
//! `formulation::remove_warp_rotation`), which here reduces to
//! `q_x −= ω̄y ½h·ẑ`, `q_y += ω̄x ½h·ẑ`, with the transpose on the forces,
//! `f̂z_J += ½ h·ẑ (B1_J Q_x + B2_J Q_y)`.
//!
//! Warping correction (option, after Belytschko, Wong & Chiang 1992; derived
//! here): first-order Mindlin kinematics on the twisted surface
//! `z = c x̂ ŷ`, `c = Σ h_I ẑ_I / A`. The fibres lie along the surface
//! normals at the nodes, `n_I = e3 − c (ŷ_I, x̂_I, 0)`, so a nodal rotation
//! about `e3` turns them: the curvature reads `θ̂x + c ŷ_I θ̂z`,
//! `θ̂y + c x̂_I θ̂z`; and the surface's metric varies through the thickness,
//! adding `κ_xx += c ∂v̂x/∂y`, `κ_yy += c ∂v̂y/∂x`,
//! `2κ_xy += c (d_xx + d_yy)`. Rigid motions still give no strain (the two
//! terms cancel for a rotation about the normal); a homogeneous deformation
//! of the body does not bend the section (unit test); and the nodal
//! rotation about the element normal, which the drilling penalty alone holds
//! only weakly, bends warped elements as the fibres' tilt demands, which
//! is what keeps the twisted beam from going soft with a small drilling
//! coefficient (+30 % without the correction).
//!
//! Hourglass control (stiffness-based, Flanagan–Belytschko vectors
//! `γ_I = ½(h_I − (h·x̂) B1_I − (h·ŷ) B2_I)`): membrane `q_x = γ·v̂x`,
//! `q_y = γ·v̂y`; bending `q_θx = γ·θ̂x`, `q_θy = γ·θ̂y`; transverse
//! `q_w = Σ γ_I (v̂z_I − ½(ŷ_I θ̂x_I − x̂_I θ̂y_I))`, which vanishes for every
//! quadratic w with Kirchhoff rotations (so constant-curvature patches stay
//! free of hourglass forces). Generalised forces accumulate
//! `Q += C q̇ Δt` with `C_m = r E t A ΣB²/8`, `C_θ = r E t³ A ΣB²/192`,
//! `C_w = r κ G t A ΣB²/8`.
//!
//! Drilling (relative penalty, after Hughes & Brezzi 1989): each node's
//! moment about the normal follows `m_I += k (ω̂z_I − Ω) Δt`, with `Ω` the
//! element's mean in-plane spin and `k = γ G t A / 4`, γ =
//! [`drilling`](BelytschkoTsay::drilling) (default 1e-3); rigid motions and
//! in-plane rotations give no drilling force. Its work is internal energy
//! (see `formulation::drilling_penalty`).
//!
//! The kernel is written once over [`Real`] (`rates`, then the section's
//! points, then `forces`): `f64` for one element ([`ShellFormulation::compute`]),
//! `F4` for four consecutive elements in SIMD lanes
//! ([`ShellFormulation::compute_x4`], AVX2 + FMA chosen at run time), alike
//! to rounding: the lanes fuse the products of `Real::madd`
//! (`tests/lanes_match_scalar.rs`).

use crate::block_nodes::BlockNodes;
use crate::error::ShellError;
use crate::formulation::{
    DEFAULT_DRILLING, ElementBlock, ElementResult, ElementState, SectionResult, ShellFormulation,
    check_drilling, compute_by_element, drilling_penalty, frame_turn, integrate_section,
    integrate_section_x4, local_velocities, midpoint, new_thickness, turn_tensor, turn_vector,
};
use crate::geometry::{Frame, H, ShearB, V3, assumed_shear};
use crate::lanes::{F4, KernelLanes, LaneKernel, Lanes4, Real, run_fastest};
use crate::material::Material;
use crate::section::Section;

/// The Belytschko–Tsay one-point shell and its options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BelytschkoTsay {
    /// Warping correction of the curvature (after Belytschko–Wong–Chiang:
    /// fibres along the warped surface's nodal normals and the twisted
    /// metric, see the module docs); default on: without it the element is
    /// drilling-soft on warped meshes (twisted beam +25 to +32 %).
    pub warping_correction: bool,
    /// Bathe–Dvorkin edge-tied transverse shear evaluated at the centre
    /// (default on); off gives the original centre-point shear with
    /// node-averaged rotations.
    pub shear_projection: bool,
    /// Drilling coefficient γ (-) of the relative drilling penalty
    /// `k = γ G t A` (default [`DEFAULT_DRILLING`]; 0 turns it off; at most
    /// [`MAX_DRILLING`](crate::formulation::MAX_DRILLING)).
    pub drilling: f64,
}

impl Default for BelytschkoTsay {
    fn default() -> Self {
        Self {
            warping_correction: true,
            shear_projection: true,
            drilling: DEFAULT_DRILLING,
        }
    }
}

impl BelytschkoTsay {
    /// Replace the drilling coefficient γ (in [0, 0.1]).
    pub fn with_drilling(mut self, gamma: f64) -> Result<Self, ShellError> {
        check_drilling(gamma)?;
        self.drilling = gamma;
        Ok(self)
    }
}

impl ShellFormulation for BelytschkoTsay {
    const NAME: &'static str = "belytschko-tsay";
    const IN_PLANE_POINTS: usize = 1;
    const HOURGLASS_VARS: usize = 5;

    fn drilling(&self) -> f64 {
        self.drilling
    }

    /// Lane-major blocks for the rules the lane kernel runs (3, 5, 7 points).
    fn lane_major(&self, sec: &Section) -> bool {
        matches!(sec.rule.n, 3 | 5 | 7)
    }

    /// [`StaticShells`](crate::statics::StaticShells) from the set's state.
    fn static_form<M: Material>(
        set: &crate::ShellSet<Self, M>,
    ) -> Result<fem_core::StaticForm, String> {
        Ok(crate::statics::static_form_of(set))
    }

    /// Every element's committed state of the solved static shells.
    fn absorb_static<M: Material>(
        set: &mut crate::ShellSet<Self, M>,
        solved: &dyn fem_core::statics::StaticTangent,
    ) -> Result<(), String> {
        crate::statics::absorb_static_into(set, solved)
    }

    #[inline]
    fn compute<M: Material>(
        &self,
        mat: &M,
        sec: &Section,
        x: &[V3; 4],
        v: &[V3; 4],
        w: &[V3; 4],
        dt: f64,
        st: ElementState<'_, M::History>,
    ) -> ElementResult {
        let ElementState {
            thickness,
            stress,
            history,
            shear,
            hourglass,
            drilling,
        } = st;
        let rt = self.rates(x, v, w, dt);
        if !rt.valid {
            return ElementResult {
                length: if rt.end.fr.area > 0.0 {
                    rt.fr.area
                } else {
                    rt.end.fr.area
                },
                ..Default::default()
            };
        }
        let hourglass = hourglass
            .first_chunk_mut::<5>()
            .expect("a shell set gives BT its 5 hourglass forces");
        let sr = integrate_section(
            mat,
            &sec.rule,
            *thickness,
            rt.membrane,
            rt.bending,
            stress,
            history,
        );
        let mut out = ElementResult::default();
        self.forces(
            &Moduli::of(mat, sec),
            &rt,
            sr,
            dt,
            Lanes {
                thickness,
                shear: &mut shear[0],
                hourglass,
                drilling,
            },
            &mut out,
        );
        out
    }

    #[inline]
    fn compute_x4<M: Material>(
        &self,
        mat: &M,
        sec: &Section,
        nodes: &BlockNodes<'_>,
        dt: f64,
        st: ElementBlock<'_, M::History>,
        out: &mut ElementResult<F4>,
    ) {
        match sec.rule.n {
            5 => self.lanes_dispatch::<M, 5>(mat, sec, nodes, dt, st, out),
            3 => self.lanes_dispatch::<M, 3>(mat, sec, nodes, dt, st, out),
            7 => self.lanes_dispatch::<M, 7>(mat, sec, nodes, dt, st, out),
            _ => {
                compute_by_element(self, mat, sec, nodes, dt, st, out);
            }
        }
    }
}

/// Nodal lanes in another lane type (loops, not `array::map` or closures,
/// whose out-of-line instances would run the AVX conversions outside the
/// caller's target features).
#[inline(always)]
fn to_lanes<L: Lanes4>(a: &[[F4; 3]; 4]) -> [[L; 3]; 4] {
    let mut o = [[L::splat(0.0); 3]; 4];
    for i in 0..4 {
        for c in 0..3 {
            o[i][c] = L::from_array(a[i][c].0);
        }
    }
    o
}

/// The material and section constants the kernel reads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moduli {
    /// Young's modulus E (MPa).
    young: f64,
    /// Shear modulus G (MPa).
    pub(crate) shear: f64,
    /// Transverse shear correction factor (-).
    pub(crate) ks: f64,
    /// Hourglass coefficient (-).
    hourglass: f64,
}

impl Moduli {
    #[inline(always)]
    pub(crate) fn of<M: Material>(mat: &M, sec: &Section) -> Self {
        Self {
            young: mat.young(),
            shear: mat.shear_modulus(),
            ks: sec.shear_factor,
            hourglass: sec.hourglass,
        }
    }
}

/// The element's geometry at `t_{n+1}`, where its forces are assembled.
pub(crate) struct EndGeometry<T: Real> {
    pub(crate) fr: Frame<T>,
    b1: [T; 4],
    b2: [T; 4],
    sb: ShearB<T>,
    /// Twist of the warping correction (0 without it).
    c: T,
}

/// What the first half of the kernel hands the second (see
/// [`BelytschkoTsay::rates`]): the rates in the midpoint configuration
/// `x_{n+1/2}` and the geometry at `t_{n+1}`.
pub(crate) struct Rates<T: Real> {
    /// Frame of the midpoint configuration.
    pub(crate) fr: Frame<T>,
    pub(crate) valid: T::Mask,
    vl: [[T; 3]; 4],
    wl: [[T; 3]; 4],
    b1: [T; 4],
    b2: [T; 4],
    /// Twist of the warping correction (0 without it).
    c: T,
    /// Rigid rotation rate of the element about its local x and y axes.
    ox: T,
    oy: T,
    gxz: T,
    gyz: T,
    /// Membrane strain increments `[Δε_xx, Δε_yy, Δγ_xy]` (-).
    pub(crate) membrane: [T; 3],
    /// Curvature increments `[Δκ_xx, Δκ_yy, 2Δκ_xy]` (1/mm).
    pub(crate) bending: [T; 3],
    /// Where the forces are assembled.
    pub(crate) end: EndGeometry<T>,
    /// `(cos, sin)` of the in-plane turn from the midpoint frame to the end's.
    turn: (T, T),
}

/// The element state the kernel updates besides the section's points.
pub(crate) struct Lanes<'a, T> {
    pub(crate) thickness: &'a mut T,
    pub(crate) shear: &'a mut [T; 2],
    pub(crate) hourglass: &'a mut [T; 5],
    pub(crate) drilling: &'a mut [T; 4],
}

/// What the nodes of an element are loaded with at t_{n+1}.
#[derive(Clone, Copy)]
struct NodeLoads<T> {
    /// Membrane forces and moments `[xx, yy, xy]` (N/mm, N·mm/mm).
    n: [T; 3],
    m: [T; 3],
    /// Transverse shear forces `[Q_x, Q_y]` (N/mm).
    q: [T; 2],
    /// Hourglass generalised forces.
    qf: [T; 5],
    /// The drilling penalty's `S_x`, `S_y`.
    s: [T; 2],
    /// Half the drilling penalty's moment sum.
    hmd: T,
}

/// Hourglass control: the five hourglass rates (membrane, bending, warping
/// out-of-plane) with the warped element's rigid rotation removed, turned
/// into the frame of t_{n+1}, the stiffness-based generalised forces
/// advanced in `hg` (kept in that frame), and their work in the step.
#[inline(always)]
fn hourglass<T: Real>(md: &Moduli, rt: &Rates<T>, t: T, dt: f64, hg: &mut [T; 5]) -> ([T; 5], T) {
    let zero = T::splat(0.0);
    let (xl, yl, vl, wl) = (&rt.fr.x, &rt.fr.y, &rt.vl, &rt.wl);
    let (b1, b2) = (&rt.b1, &rt.b2);
    let gam = hourglass_vectors(xl, yl, b1, b2);
    // Warped element: the rigid rotation about the in-plane axes moves the
    // nodes in-plane by (ω̄y ẑ_I, −ω̄x ẑ_I) and is removed from the membrane
    // hourglass rates (`formulation::remove_warp_rotation`; the centre B is
    // orthogonal to ẑ, so only these rates change, by ∓ω̄ γ·ẑ with
    // γ·ẑ = ½ h·ẑ).
    let gz = rt.fr.warp * 0.5;
    let mut q = [-rt.oy * gz, rt.ox * gz, zero, zero, zero];
    for i in 0..4 {
        q[0] = gam[i].madd(vl[i][0], q[0]);
        q[1] = gam[i].madd(vl[i][1], q[1]);
        q[2] = gam[i].madd(wl[i][0], q[2]);
        q[3] = gam[i].madd(wl[i][1], q[3]);
        let tilt = yl[i].madd(wl[i][0], -(xl[i] * wl[i][1]));
        q[4] = gam[i].madd((-tilt).madd(T::splat(0.5), vl[i][2]), q[4]);
    }
    // Into the frame of t_{n+1}, where the hourglass forces are kept.
    [q[0], q[1]] = turn_vector(rt.turn, [q[0], q[1]]);
    [q[2], q[3]] = turn_vector(rt.turn, [q[2], q[3]]);
    let mut bb = zero;
    for i in 0..4 {
        bb += b2[i].madd(b2[i], b1[i] * b1[i]);
    }
    let (r, e, g, ks, a) = (md.hourglass, md.young, md.shear, md.ks, rt.fr.area);
    let cm = t * (r * e) * a * bb / 8.0;
    let ct = t * (r * e) * t * t * a * bb / 192.0;
    let cw = t * (r * ks * g) * a * bb / 8.0;
    let cs = [cm, cm, ct, ct, cw];
    let mut d_hg = zero;
    let mut qf = [zero; 5];
    for k in 0..5 {
        let old = hg[k];
        let new = (cs[k] * q[k]).madd(T::splat(dt), old);
        hg[k] = new;
        qf[k] = new;
        d_hg = ((old + new) * 0.5 * q[k]).madd(T::splat(dt), d_hg);
    }
    (qf, d_hg)
}

/// A block's element state in lanes (lane `l`: element `l`), loaded from
/// and stored to the lane-major block (see `ElementBlock`).
struct BlockState<L, const N: usize> {
    /// Stresses of the section's `N` points.
    s: [[L; 3]; N],
    /// Thickness.
    t: L,
    /// Transverse shear stresses.
    sh: [L; 2],
    /// Hourglass generalised forces.
    hg: [L; 5],
    /// Drilling moments.
    dr: [L; 4],
}

impl<L: Lanes4, const N: usize> BlockState<L, N> {
    /// The state of the block's arrays, in lanes.
    #[inline(always)]
    fn load(
        stress: &[[f64; 4]],
        thickness: &[f64; 4],
        shear: &[[f64; 4]; 2],
        hourglass: &[[f64; 4]; 5],
        drilling: &[[f64; 4]; 4],
    ) -> Self {
        let mut s = [[L::splat(0.0); 3]; N];
        for k in 0..N {
            for c in 0..3 {
                s[k][c] = L::from_array(stress[3 * k + c]);
            }
        }
        let mut hg = [L::splat(0.0); 5];
        for k in 0..5 {
            hg[k] = L::from_array(hourglass[k]);
        }
        let mut dr = [L::splat(0.0); 4];
        for i in 0..4 {
            dr[i] = L::from_array(drilling[i]);
        }
        Self {
            s,
            t: L::from_array(*thickness),
            sh: [L::from_array(shear[0]), L::from_array(shear[1])],
            hg,
            dr,
        }
    }

    /// `old` in the lanes not in `valid`.
    #[inline(always)]
    fn keep_where_not(&mut self, valid: L::Mask, old: &Self) {
        for k in 0..N {
            for c in 0..3 {
                self.s[k][c] = L::select(valid, self.s[k][c], old.s[k][c]);
            }
        }
        self.t = L::select(valid, self.t, old.t);
        for c in 0..2 {
            self.sh[c] = L::select(valid, self.sh[c], old.sh[c]);
        }
        for k in 0..5 {
            self.hg[k] = L::select(valid, self.hg[k], old.hg[k]);
        }
        for i in 0..4 {
            self.dr[i] = L::select(valid, self.dr[i], old.dr[i]);
        }
    }

    /// Back into the block's arrays.
    #[inline(always)]
    fn store(
        &self,
        stress: &mut [[f64; 4]],
        thickness: &mut [f64; 4],
        shear: &mut [[f64; 4]; 2],
        hourglass: &mut [[f64; 4]; 5],
        drilling: &mut [[f64; 4]; 4],
    ) {
        for k in 0..N {
            for c in 0..3 {
                stress[3 * k + c] = self.s[k][c].to_array();
            }
        }
        *thickness = self.t.to_array();
        for c in 0..2 {
            shear[c] = self.sh[c].to_array();
        }
        for k in 0..5 {
            hourglass[k] = self.hg[k].to_array();
        }
        for i in 0..4 {
            drilling[i] = self.dr[i].to_array();
        }
    }
}

/// Forces, moments and energies zero in the lanes not in `valid`.
#[inline(always)]
fn zero_where_not<L: Real>(valid: L::Mask, res: &mut ElementResult<L>) {
    let zero = L::splat(0.0);
    for i in 0..4 {
        for c in 0..3 {
            res.f[i][c] = L::select(valid, res.f[i][c], zero);
            res.m[i][c] = L::select(valid, res.m[i][c], zero);
        }
    }
    res.d_internal = L::select(valid, res.d_internal, zero);
    res.d_drilling = L::select(valid, res.d_drilling, zero);
    res.d_hourglass = L::select(valid, res.d_hourglass, zero);
    res.d_plastic = L::select(valid, res.d_plastic, zero);
}

/// One block of four elements through [`BelytschkoTsay::lanes`], as a
/// [`LaneKernel`] (run in the fastest lanes by [`run_fastest`]).
struct Block<'a, 'b, M: Material, const N: usize> {
    bt: &'a BelytschkoTsay,
    mat: &'a M,
    sec: &'a Section,
    nodes: &'a BlockNodes<'b>,
    dt: f64,
    st: ElementBlock<'a, M::History>,
    out: &'a mut ElementResult<F4>,
}

impl<M: Material, const N: usize> LaneKernel for Block<'_, '_, M, N> {
    type Output = ();
    /// The block's nodes gathered into lanes of `L` and the kernel run.
    #[inline(always)]
    fn run<L: KernelLanes>(self) {
        let [x, v, w] = L::gather(self.nodes);
        let (x, v, w) = (to_lanes::<L>(&x), to_lanes::<L>(&v), to_lanes::<L>(&w));
        let (mat, sec, dt) = (self.mat, self.sec, self.dt);
        self.bt
            .lanes::<M, L, N>(mat, sec, &x, &v, &w, dt, self.st, self.out)
    }
}

impl BelytschkoTsay {
    /// Four elements in SIMD lanes, in AVX registers where the processor
    /// has them (see [`run_fastest`]).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn lanes_dispatch<M: Material, const N: usize>(
        &self,
        mat: &M,
        sec: &Section,
        nodes: &BlockNodes<'_>,
        dt: f64,
        st: ElementBlock<'_, M::History>,
        out: &mut ElementResult<F4>,
    ) {
        if st.stress.len() != 4 * N || st.shear.len() != 4 || st.hourglass.len() != 20 {
            return compute_by_element(self, mat, sec, nodes, dt, st, out);
        }
        run_fastest(Block::<M, N> {
            bt: self,
            mat,
            sec,
            nodes,
            dt,
            st,
            out,
        })
    }

    /// Four elements with `N` points each through the kernel in lanes:
    /// gather the block's state into lanes, run, and write back the lanes
    /// of the elements that did not degenerate (a degenerate element keeps
    /// its state, as in [`compute`](ShellFormulation::compute)).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn lanes<M: Material, L: Lanes4, const N: usize>(
        &self,
        mat: &M,
        sec: &Section,
        x: &[[L; 3]; 4],
        v: &[[L; 3]; 4],
        w: &[[L; 3]; 4],
        dt: f64,
        st: ElementBlock<'_, M::History>,
        out: &mut ElementResult<F4>,
    ) {
        let rt = self.rates(x, v, w, dt);
        if !L::any(rt.valid) {
            *out = ElementResult {
                length: F4(
                    L::select(rt.end.fr.area.gt(L::splat(0.0)), rt.fr.area, rt.end.fr.area)
                        .to_array(),
                ),
                ..Default::default()
            };
            return;
        }
        let ElementBlock {
            thickness,
            stress,
            history,
            shear,
            hourglass,
            drilling,
        } = st;
        // Lane-major block (see `ElementBlock`): one vector per quantity.
        let stress = stress.as_flattened_mut().as_chunks_mut::<4>().0;
        let (Some(history), Some(shear), Some(hourglass), true) = (
            history.as_chunks_mut::<N>().0.first_chunk_mut::<4>(),
            shear
                .as_flattened_mut()
                .as_chunks_mut::<4>()
                .0
                .first_chunk_mut::<2>(),
            hourglass.as_chunks_mut::<4>().0.first_chunk_mut::<5>(),
            stress.len() == 3 * N,
        ) else {
            unreachable!("lanes_dispatch checked the block's sizes");
        };
        let mut b = BlockState::<L, N>::load(stress, thickness, shear, hourglass, drilling);
        let valid = rt.valid;
        let saved = if L::mask_all(valid) {
            None
        } else {
            Some(*history)
        };
        let sr = integrate_section_x4(
            mat,
            &sec.rule,
            b.t,
            rt.membrane,
            rt.bending,
            &mut b.s,
            history,
        );
        let mut res = ElementResult::<L>::zero();
        self.forces(
            &Moduli::of(mat, sec),
            &rt,
            sr,
            dt,
            Lanes {
                thickness: &mut b.t,
                shear: &mut b.sh,
                hourglass: &mut b.hg,
                drilling: &mut b.dr,
            },
            &mut res,
        );
        if let Some(saved) = &saved {
            // Rare: a degenerate lane keeps its old state and reports only
            // its length (≤ 0 or NaN); the masks stay out of the common
            // path, where they would turn into masked stores.
            for l in 0..4 {
                if !L::mask_lane(valid, l) {
                    history[l] = saved[l];
                }
            }
            let old = BlockState::<L, N>::load(stress, thickness, shear, hourglass, drilling);
            b.keep_where_not(valid, &old);
            zero_where_not(valid, &mut res);
        }
        b.store(stress, thickness, shear, hourglass, drilling);
        *out = res.into_f4();
    }

    /// First half of the element kernel over [`Real`] (one element, `f64`,
    /// or four in lanes, `F4`): frames, local velocities and the rates;
    /// `valid` is false in the lanes that degenerated (area ≤ 0 or NaN at
    /// `t_{n+1}` or at the midpoint), whose rates are meaningless but
    /// computed without a branch; the caller returns if no lane is valid.
    /// The caller updates the section's points with `rates.membrane`,
    /// `rates.bending` and hands the result to [`Self::forces`].
    ///
    /// The rates (membrane, curvature, transverse shear, hourglass and
    /// drilling) are read in the midpoint configuration
    /// `x_{n+1/2} = x_{n+1} − ½Δt v_{n+1/2}`, the forces assembled at
    /// `x_{n+1}` (after Hughes & Winget 1980): with the frame of `x_{n+1}`
    /// a strain increment carries a bias of `+|Δu|²/L` per step (a rigid
    /// rotation by `θ` strains a fibre by `θ²/2`), which a vibrating element
    /// ratchets into strain energy from nothing (docs/shells.md, "Strain
    /// increments at the midpoint").
    #[inline(always)]
    pub(crate) fn rates<T: Real>(
        &self,
        x: &[[T; 3]; 4],
        v: &[[T; 3]; 4],
        w: &[[T; 3]; 4],
        dt: f64,
    ) -> Rates<T> {
        let fr = Frame::new(x);
        let (b1, b2) = fr.mean_b();
        let end = EndGeometry {
            sb: self.shear_b(&fr, b1, b2),
            c: if self.warping_correction {
                fr.twist()
            } else {
                T::splat(0.0)
            },
            fr,
            b1,
            b2,
        };
        self.rates_at(&midpoint(x, v, dt), v, w, dt, end)
    }

    /// Transverse shear coefficients `[w, θx, θy]` per node of frame `fr`.
    #[inline(always)]
    fn shear_b<T: Real>(&self, fr: &Frame<T>, b1: [T; 4], b2: [T; 4]) -> ShearB<T> {
        if self.shear_projection {
            assumed_shear(fr, 0.0, 0.0)
        } else {
            let zero = T::splat(0.0);
            ShearB {
                xz: [b1, [zero; 4], [T::splat(0.25); 4]],
                yz: [b2, [T::splat(-0.25); 4], [zero; 4]],
            }
        }
    }

    /// The rates in configuration `x` (the midpoint), with `end` the
    /// geometry at `t_{n+1}`.
    #[inline(always)]
    fn rates_at<T: Real>(
        &self,
        x: &[[T; 3]; 4],
        v: &[[T; 3]; 4],
        w: &[[T; 3]; 4],
        dt: f64,
        end: EndGeometry<T>,
    ) -> Rates<T> {
        let fr = Frame::new(x);
        let zero = T::splat(0.0);
        let valid = T::select(end.fr.area.gt(zero), fr.area, zero).gt(zero);
        let (vl, wl) = local_velocities(&fr, v, w);
        let (xl, yl) = (&fr.x, &fr.y);
        let (b1, b2) = fr.mean_b();
        // Membrane and curvature rates at the centre, and the element's rigid
        // rotation about its in-plane axes (ω̄x, ω̄y) for the warped-element
        // projection in `forces`.
        let (mut dxx, mut dyy, mut vxy, mut vyx, mut kxx, mut kyy, mut kxy) =
            (zero, zero, zero, zero, zero, zero, zero);
        let (mut ox, mut oy) = (zero, zero);
        for i in 0..4 {
            dxx = b1[i].madd(vl[i][0], dxx);
            dyy = b2[i].madd(vl[i][1], dyy);
            vxy = b2[i].madd(vl[i][0], vxy);
            vyx = b1[i].madd(vl[i][1], vyx);
            kxx = b1[i].madd(wl[i][1], kxx);
            kyy = (-b2[i]).madd(wl[i][0], kyy);
            kxy += b2[i].madd(wl[i][1], -(b1[i] * wl[i][0]));
            ox = b2[i].madd(vl[i][2], ox);
            oy = (-b1[i]).madd(vl[i][2], oy);
        }
        let gxy = vxy + vyx;
        let c = if self.warping_correction {
            fr.twist()
        } else {
            zero
        };
        if self.warping_correction {
            // Fibres along the warped surface's normals at the nodes
            // (θ̂ + c θ̂z (ŷ, x̂)) and the twisted metric (c × in-plane
            // velocity gradient).
            for i in 0..4 {
                let tz = c * wl[i][2];
                kxx = (b1[i] * xl[i]).madd(tz, kxx);
                kyy = (-(b2[i] * yl[i])).madd(tz, kyy);
                kxy = b2[i].madd(xl[i], -(b1[i] * yl[i])).madd(tz, kxy);
            }
            kxx = c.madd(vxy, kxx);
            kyy = c.madd(vyx, kyy);
            kxy = c.madd(dxx + dyy, kxy);
        }
        let sb = self.shear_b(&fr, b1, b2);
        // The stresses are kept in the frame of t_{n+1}: every increment read
        // here is turned into it.
        let turn = frame_turn(&fr, &end.fr);
        let (mut gxz, mut gyz) = (zero, zero);
        for i in 0..4 {
            gxz += sb.xz[2][i].madd(wl[i][1], sb.xz[1][i].madd(wl[i][0], sb.xz[0][i] * vl[i][2]));
            gyz += sb.yz[2][i].madd(wl[i][1], sb.yz[1][i].madd(wl[i][0], sb.yz[0][i] * vl[i][2]));
        }
        let [gxz, gyz] = turn_vector(turn, [gxz, gyz]);

        Rates {
            fr,
            valid,
            vl,
            wl,
            b1,
            b2,
            c,
            ox,
            oy,
            gxz,
            gyz,
            membrane: turn_tensor(turn, [dxx * dt, dyy * dt, gxy * dt]),
            bending: turn_tensor(turn, [kxx * dt, kyy * dt, kxy * dt]),
            end,
            turn,
        }
    }

    /// Second half of the element kernel: transverse shear, hourglass and
    /// drilling updates, nodal forces and energies from the section result.
    #[inline(always)]
    pub(crate) fn forces<T: Real>(
        &self,
        md: &Moduli,
        rt: &Rates<T>,
        sr: SectionResult<T>,
        dt: f64,
        st: Lanes<'_, T>,
        out: &mut ElementResult<T>,
    ) {
        let Rates {
            fr,
            valid,
            vl,
            wl,
            b1,
            b2,
            c,
            ox,
            oy,
            gxz,
            gyz,
            end,
            ..
        } = rt;
        let (c, ox, oy, gxz, gyz) = (*c, *ox, *oy, *gxz, *gyz);
        // The rates and the generalised stresses' updates in the midpoint
        // frame (`a`, `xl`, …); the nodal forces at t_{n+1} (`nodal_forces`).
        let a = fr.area;
        let zero = T::splat(0.0);
        let (xl, yl) = (&fr.x, &fr.y);
        let t = *st.thickness;
        let (g, ks) = (md.shear, md.ks);
        let tau_old = *st.shear;
        let tau = [
            (gxz * (ks * g)).madd(T::splat(dt), tau_old[0]),
            (gyz * (ks * g)).madd(T::splat(dt), tau_old[1]),
        ];
        *st.shear = tau;
        let shear_work =
            t * 0.5 * (tau_old[1] + tau[1]).madd(gyz, (tau_old[0] + tau[0]) * gxz) * dt;
        let (qf, d_hg) = hourglass(md, rt, t, dt, st.hourglass);
        let (exl, eyl) = (&end.fr.x, &end.fr.y);

        // Relative drilling penalty (about the nodal normals with the correction).
        let tilt = if self.warping_correction {
            Some((c, ox, oy))
        } else {
            None
        };
        let (md_sum, d_drill, sx, sy) = drilling_penalty(
            t * (0.25 * self.drilling * g) * a,
            b1,
            b2,
            vl,
            wl,
            dt,
            st.drilling,
            tilt,
            (xl, yl),
            (exl, eyl),
        );

        // Every field of `out` is written: the energies here, the nodes in
        // `nodal_forces`.
        out.d_internal = a * (sr.work + shear_work) + d_drill;
        out.d_drilling = d_drill;
        out.d_hourglass = d_hg;
        out.d_plastic = a * sr.dissipation;
        out.length = T::select(*valid, end.fr.char_length(), end.fr.area);
        out.area = T::select(*valid, end.fr.area, zero);
        for c in 0..3 {
            out.normal[c] = T::select(*valid, end.fr.r[2][c], zero);
        }
        let loads = NodeLoads {
            n: sr.n,
            m: sr.m,
            q: [t * tau[0], t * tau[1]],
            qf,
            s: [sx, sy],
            hmd: md_sum * 0.5,
        };
        self.nodal_forces(end, &loads, st.drilling, out);
        *st.thickness = new_thickness(t, sr.deps_zz);
    }

    /// The nodal forces and moments at t_{n+1} from the element's
    /// generalised stresses (`loads`) and drilling moments, in global axes
    /// (`out.f`, `out.m`).
    #[inline(always)]
    fn nodal_forces<T: Real>(
        &self,
        end: &EndGeometry<T>,
        loads: &NodeLoads<T>,
        drilling: &[T; 4],
        out: &mut ElementResult<T>,
    ) {
        let NodeLoads {
            n: nr,
            m: mr,
            q: [qx, qy],
            qf,
            s: [sx, sy],
            hmd,
        } = *loads;
        let (ae, ce, exl, eyl, eb1, eb2, esb) = (
            end.fr.area,
            end.c,
            &end.fr.x,
            &end.fr.y,
            &end.b1,
            &end.b2,
            &end.sb,
        );
        let egam = hourglass_vectors(exl, eyl, eb1, eb2);
        let egz = end.fr.warp * 0.5;
        // Transpose of the projection: f̂z_J += ½ h·ẑ (B1_J Q_x + B2_J Q_y).
        // The warping correction's membrane terms fold into the membrane
        // forces: f̂x = A((N_xx + c M_xy) B1 + (N_xy + c M_xx) B2), f̂y likewise;
        // its tilted drilling penalty adds c (S_y B2 − S_x B1).
        let (hqx, hqy) = (egz.madd(qf[0], -(ce * sx)), egz.madd(qf[1], ce * sy));
        let (nxx, nyy) = (ae * ce.madd(mr[2], nr[0]), ae * ce.madd(mr[2], nr[1]));
        let (nxy_x, nxy_y) = (
            ae.madd(ce.madd(mr[0], nr[2]), hmd),
            ae.madd(ce.madd(mr[1], nr[2]), -hmd),
        );
        for i in 0..4 {
            let mxb = -ae * mr[2].madd(eb1[i], mr[1] * eb2[i]);
            let myb = ae * mr[2].madd(eb2[i], mr[0] * eb1[i]);
            let fx = egam[i].madd(qf[0], nxy_x.madd(eb2[i], nxx * eb1[i]));
            let fy = egam[i].madd(qf[1], nxy_y.madd(eb1[i], nyy * eb2[i]));
            let fz = eb2[i].madd(
                hqy,
                eb1[i].madd(
                    hqx,
                    egam[i].madd(qf[4], ae * qy.madd(esb.yz[0][i], qx * esb.xz[0][i])),
                ),
            );
            let mut mx = egam[i].madd(
                (-(eyl[i] * 0.5)).madd(qf[4], qf[2]),
                ae.madd(qy.madd(esb.yz[1][i], qx * esb.xz[1][i]), mxb),
            );
            let mut my = egam[i].madd(
                (exl[i] * 0.5).madd(qf[4], qf[3]),
                ae.madd(qy.madd(esb.yz[2][i], qx * esb.xz[2][i]), myb),
            );
            let mut mz = drilling[i];
            if self.warping_correction {
                // Tilted fibres: the bending moments' share about the normal,
                // and the drilling moment's share about the in-plane axes.
                mz = ce.madd(exl[i].madd(myb, eyl[i] * mxb), mz);
                mx = (-(ce * eyl[i])).madd(drilling[i], mx);
                my = (-(ce * exl[i])).madd(drilling[i], my);
            }
            let fg = end.fr.global([fx, fy, fz]);
            let mg = end.fr.global([mx, my, mz]);
            out.f[i] = [-fg[0], -fg[1], -fg[2]];
            out.m[i] = [-mg[0], -mg[1], -mg[2]];
        }
    }
}

/// The hourglass vectors `γ_I = ½ (h_I − (h·x) B1_I − (h·y) B2_I)` of a
/// frame's local coordinates `x`, `y` and mean B.
#[inline(always)]
fn hourglass_vectors<T: Real>(x: &[T; 4], y: &[T; 4], b1: &[T; 4], b2: &[T; 4]) -> [T; 4] {
    let zero = T::splat(0.0);
    let (mut hx, mut hy) = (zero, zero);
    for i in 0..4 {
        hx = x[i].madd(T::splat(H[i]), hx);
        hy = y[i].madd(T::splat(H[i]), hy);
    }
    let mut gam = [zero; 4];
    for i in 0..4 {
        gam[i] = (-hy).madd(b2[i], (-hx).madd(b1[i], T::splat(H[i]))) * 0.5;
    }
    gam
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::{Hardening, J2History, J2PlaneStress, Material};

    /// The block kernel compiled for the baseline target (SSE2, where
    /// `madd` is the C library's exact `fma`) and for AVX2 + FMA gives the
    /// same bits (IEEE operations lane by lane, fused multiply–adds exactly
    /// where the kernel writes `madd`), so a run does not depend on the
    /// processor it lands on. Skipped (passes) on a processor without AVX2
    /// and FMA. Tolerance: none.
    #[test]
    fn baseline_and_avx2_block_kernels_agree_bit_for_bit() {
        if crate::lanes::Avx2Fma::detect().is_some() {
            let mat = J2PlaneStress::new(
                206_000.0,
                0.3,
                7.85e-9,
                Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
            )
            .unwrap();
            let sec = Section::new(0.8).unwrap();
            let bt = BelytschkoTsay {
                warping_correction: true,
                ..Default::default()
            };
            // Four warped quads, large strain increments (plastic flow).
            let x: [[F4; 3]; 4] = std::array::from_fn(|i| {
                let (xi, eta) = ([0.0, 1.0, 1.0, 0.0][i], [0.0, 0.0, 1.0, 1.0][i]);
                [
                    F4::from_fn(|l| xi + 0.1 * l as f64 * eta),
                    F4::from_fn(|l| eta - 0.05 * l as f64 * xi),
                    F4::from_fn(|l| 0.02 * (l as f64 + 1.0) * (xi - 0.5) * (eta - 0.5)),
                ]
            });
            let v: [[F4; 3]; 4] = std::array::from_fn(|i| {
                [
                    F4::from_fn(|l| 300.0 * x[i][0].0[l] + 10.0 * l as f64),
                    F4::from_fn(|l| -120.0 * x[i][1].0[l]),
                    F4::from_fn(|l| 40.0 * x[i][0].0[l] * x[i][1].0[l]),
                ]
            });
            let w: [[F4; 3]; 4] = std::array::from_fn(|i| {
                [
                    F4::from_fn(|l| 5.0 * x[i][1].0[l] - l as f64),
                    F4::from_fn(|l| -7.0 * x[i][0].0[l]),
                    F4::from_fn(|l| 0.3 * l as f64),
                ]
            });
            let fresh = || {
                (
                    [0.8; 4],
                    vec![[0.0; 3]; 20],
                    vec![mat.initial_history(); 20],
                    vec![[0.0; 2]; 4],
                    vec![0.0; 20],
                    [[0.0; 4]; 4],
                )
            };
            let (mut a, mut b) = (fresh(), fresh());
            type State = (
                [f64; 4],
                Vec<[f64; 3]>,
                Vec<J2History>,
                Vec<[f64; 2]>,
                Vec<f64>,
                [[f64; 4]; 4],
            );
            fn block(s: &mut State) -> ElementBlock<'_, J2History> {
                ElementBlock {
                    thickness: &mut s.0,
                    stress: &mut s.1,
                    history: &mut s.2,
                    shear: &mut s.3,
                    hourglass: &mut s.4,
                    drilling: &mut s.5,
                }
            }
            // The same blocks as nodal arrays: element l's node i is node 4l + i.
            let nodal = |a: &[[F4; 3]; 4]| -> Vec<fem_core::Vec3> {
                (0..16)
                    .map(|k| {
                        let (l, i) = (k / 4, k % 4);
                        fem_core::Vec3::new(a[i][0].0[l], a[i][1].0[l], a[i][2].0[l])
                    })
                    .collect()
            };
            let (xn, vn, wn) = (nodal(&x), nodal(&v), nodal(&w));
            let q = [[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11], [12, 13, 14, 15]];
            let nodes = BlockNodes::new(&xn, &vn, &wn, &q).unwrap();
            for _ in 0..20 {
                let (mut ra, mut rb) = (ElementResult::<F4>::default(), ElementResult::default());
                bt.lanes::<J2PlaneStress, F4, 5>(
                    &mat,
                    &sec,
                    &x,
                    &v,
                    &w,
                    1e-5,
                    block(&mut a),
                    &mut ra,
                );
                // AVX2 is present (checked above): the AVX lanes.
                run_fastest(Block::<J2PlaneStress, 5> {
                    bt: &bt,
                    mat: &mat,
                    sec: &sec,
                    nodes: &nodes,
                    dt: 1e-5,
                    st: block(&mut b),
                    out: &mut rb,
                });
                for l in 0..4 {
                    assert_eq!(ra.lane(l), rb.lane(l));
                }
                assert_eq!(a, b);
            }
            assert!(a.2.iter().any(|h| h.eps_p > 0.0), "no plastic flow");
        }
    }
}
