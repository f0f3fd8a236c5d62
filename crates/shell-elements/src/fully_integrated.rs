//! `FullyIntegrated`: the 4-node shell with 2×2 in-plane Gauss points and Bathe–Dvorkin (MITC4) transverse shear.
//!
//! Same co-rotational flat frame and Mindlin kinematics as
//! [`BelytschkoTsay`](crate::BelytschkoTsay), but the membrane and bending
//! rates are evaluated with the exact bilinear B-matrix at each of the 2×2
//! Gauss points (each with its own through-thickness stack), and the
//! transverse shear is the edge-tied assumed field interpolated to each point.
//! No zero-energy modes, so no hourglass control. One thickness per element:
//! the 2×2 average of the thickness-strain increments updates it. The
//! relative drilling penalty is the Belytschko–Tsay one (nodal drilling rates
//! against the element's mean in-plane spin, `k = γ G t A / 4` per node).
//!
//! Warped elements: the element's rigid rotation about its in-plane axes
//! (`ω̄x = Σ B̄2_I v̂z_I`, `ω̄y = −Σ B̄1_I v̂z_I`, mean B) is removed from the
//! in-plane velocities before the 2×2 B-matrices read them
//! (`v̂x_I −= ω̄y ẑ_I`, `v̂y_I += ω̄x ẑ_I`), with the transpose on the forces
//! (`formulation::remove_warp_rotation`, `warp_rotation_forces`): away from
//! the centre `Σ ∂N_I/∂x ẑ_I ≠ 0`, so without it a rigid rotation of a
//! warped element strained it (0.038 per radian on the twisted beam's
//! element). The optional warping correction is the Belytschko–Tsay one
//! (tilted fibres and twisted metric), evaluated at each Gauss point.
//!
//! The kernel (`FullyIntegrated::kernel`) is written once over [`Real`]
//! with the section's integration handed in: the explicit step runs it on
//! `f64` with the material's update ([`ShellFormulation::compute`]); the
//! static shells ([`crate::statics`]) run it as one step from the committed
//! state, on `f64` or on dual numbers for the exact tangent.

use crate::belytschko_tsay::Moduli;
use crate::error::ShellError;
use crate::formulation::{
    DEFAULT_DRILLING, ElementResult, ElementState, SectionResult, ShellFormulation, check_drilling,
    drilling_penalty, frame_turn, integrate_section, local_velocities, midpoint, new_thickness,
    remove_warp_rotation, turn_tensor, turn_vector, warp_rotation_forces,
};
use crate::geometry::{Frame, ShearB, V3, assumed_shear, b_matrix};
use crate::lanes::Real;
use crate::material::Material;
use crate::section::Section;

/// The fully integrated shell and its options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FullyIntegrated {
    /// Warping correction of the curvature, as in
    /// [`BelytschkoTsay`](crate::BelytschkoTsay); default on: without it the
    /// element is drilling-soft on warped meshes (twisted beam +25 to +32 %).
    pub warping_correction: bool,
    /// Drilling coefficient γ (-) of the relative drilling penalty
    /// `k = γ G t A`, as in [`BelytschkoTsay`](crate::BelytschkoTsay)
    /// (default [`DEFAULT_DRILLING`]; 0 turns it off).
    pub drilling: f64,
}

impl Default for FullyIntegrated {
    fn default() -> Self {
        Self {
            warping_correction: true,
            drilling: DEFAULT_DRILLING,
        }
    }
}

impl FullyIntegrated {
    /// Replace the drilling coefficient γ (in [0, 0.1]).
    pub fn with_drilling(mut self, gamma: f64) -> Result<Self, ShellError> {
        check_drilling(gamma)?;
        self.drilling = gamma;
        Ok(self)
    }
}

const G: f64 = 0.577_350_269_189_625_8;
const GP: [(f64, f64); 4] = [(-G, -G), (G, -G), (G, G), (-G, G)];

impl ShellFormulation for FullyIntegrated {
    const NAME: &'static str = "fully-integrated";
    const IN_PLANE_POINTS: usize = 4;
    const HOURGLASS_VARS: usize = 0;

    fn drilling(&self) -> f64 {
        self.drilling
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
            drilling,
            ..
        } = st;
        let shear = shear
            .first_chunk_mut::<4>()
            .expect("a shell set gives the fully integrated shell its 4 shear stresses");
        let (t, np) = (*thickness, sec.rule.n);
        let section = |p: usize, de: [f64; 3], dk: [f64; 3]| {
            let pts = p * np..(p + 1) * np;
            integrate_section(
                mat,
                &sec.rule,
                t,
                de,
                dk,
                &mut stress[pts.clone()],
                &mut history[pts],
            )
        };
        let st = PointLanes {
            thickness,
            shear,
            drilling,
        };
        match self.kernel(&Moduli::of(mat, sec), x, v, w, dt, st, section) {
            Ok(out) => out,
            Err(length) => ElementResult {
                length,
                ..Default::default()
            },
        }
    }
}

/// The element state the kernel updates besides the sections' points: one
/// element's, in `f64` (explicit) or in a static scalar.
pub(crate) struct PointLanes<'a, T> {
    /// Thickness (mm): read at the start, the updated one written at the end.
    pub(crate) thickness: &'a mut T,
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa) per Gauss point.
    pub(crate) shear: &'a mut [[T; 2]; 4],
    /// Drilling moments (N·mm) per node.
    pub(crate) drilling: &'a mut [T; 4],
}

impl FullyIntegrated {
    /// One step of the element: nodes at `x` (end of the step), velocities
    /// `v`, `w` over `dt`, its state `st`; `section(p, Δε, Δκ)` integrates
    /// Gauss point `p`'s stack for the membrane and curvature increments
    /// (turned into the end frame) and updates its points. Its forces and
    /// energies, or `Err(length)` (≤ 0 or NaN) when the element degenerates
    /// in the end or midpoint configuration (the state may then be partly
    /// updated, as the step stops).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(crate) fn kernel<T: Real<Mask = bool>>(
        &self,
        md: &Moduli,
        x: &[[T; 3]; 4],
        v: &[[T; 3]; 4],
        w: &[[T; 3]; 4],
        dt: f64,
        st: PointLanes<'_, T>,
        mut section: impl FnMut(usize, [T; 3], [T; 3]) -> SectionResult<T>,
    ) -> Result<ElementResult<T>, T> {
        // Rates in the midpoint configuration x_{n+1/2} = x_{n+1} − ½Δt v
        // (`fr`, `mb1`, `c`, …), forces at t_{n+1} (`fe`, `eb1`, `ce`, …), as
        // in Belytschko–Tsay (docs/shells.md, "Strain increments at the
        // midpoint").
        let zero = T::splat(0.0);
        let fe = Frame::new(x);
        if !fe.area.gt(zero) {
            return Err(fe.area);
        }
        let fr = Frame::new(&midpoint(x, v, dt));
        if !fr.area.gt(zero) {
            return Err(fr.area);
        }
        let (mut vl, wl) = local_velocities(&fr, v, w);
        // Mean B: the element's rigid rotation (warped elements) and spin (drilling).
        let (mb1, mb2) = fr.mean_b();
        let (eb1, eb2) = fe.mean_b();
        let (ox, oy) = remove_warp_rotation(&fr.z, &mb1, &mb2, &mut vl);
        let turn = frame_turn(&fr, &fe);
        let (c, ce) = if self.warping_correction {
            (fr.twist(), fe.twist())
        } else {
            (zero, zero)
        };
        // Warping correction, fibres along the warped surface's normals at the nodes:
        // they turn at θ̂ + c θ̂z (ŷ_I, x̂_I) (the rates the curvature reads).
        let mut tl = [[zero; 2]; 4];
        for i in 0..4 {
            tl[i] = [
                wl[i][0] + c * fr.y[i] * wl[i][2],
                wl[i][1] + c * fr.x[i] * wl[i][2],
            ];
        }
        let t = *st.thickness;
        let (g, ks) = (md.shear, md.ks);
        let mut acc = Forces {
            fl: [[zero; 3]; 4],
            ml: [[zero; 2]; 4],
            mb: [zero; 4],
        };
        let mut out = ElementResult::<T>::zero();
        let mut dzz = zero;
        for (p, &(xi, eta)) in GP.iter().enumerate() {
            let (b1, b2, det) = b_matrix(&fr, xi, eta);
            let (fb1, fb2, fdet) = b_matrix(&fe, xi, eta);
            if !det.gt(zero) || !fdet.gt(zero) {
                return Err(T::splat(-1.0));
            }
            let (de, dk, [gxz, gyz]) = point_rates(&fr, (xi, eta), (&b1, &b2), &vl, &wl, &tl, c);
            // The stresses are kept in the frame of t_{n+1}.
            let [gxz, gyz] = turn_vector(turn, [gxz, gyz]);
            let sr = section(
                p,
                turn_tensor(turn, de.map(|r| r * dt)),
                turn_tensor(turn, dk.map(|r| r * dt)),
            );
            let tau_old = st.shear[p];
            let tau = [
                tau_old[0] + gxz * (ks * g) * dt,
                tau_old[1] + gyz * (ks * g) * dt,
            ];
            st.shear[p] = tau;
            let shear_work =
                t * 0.5 * ((tau_old[0] + tau[0]) * gxz + (tau_old[1] + tau[1]) * gyz) * dt;
            out.d_internal += det * (sr.work + shear_work);
            out.d_plastic += det * sr.dissipation;
            dzz += sr.deps_zz * 0.25;
            let q = [t * tau[0], t * tau[1]];
            let point = (fb1, fb2, fdet, assumed_shear(&fe, xi, eta));
            add_point_forces(&fe, ce, point, &sr, q, &mut acc);
        }
        // Relative drilling penalty on the element's mean spin (about the nodal
        // normals with the warping correction).
        let tilt = if self.warping_correction {
            Some((c, ox, oy))
        } else {
            None
        };
        let (md_sum, d_drill, sx, sy) = drilling_penalty(
            t * (0.25 * self.drilling * g) * fr.area,
            &mb1,
            &mb2,
            &vl,
            &wl,
            dt,
            st.drilling,
            tilt,
            (&fr.x, &fr.y),
            (&fe.x, &fe.y),
        );
        out.d_internal += d_drill;
        out.d_drilling = d_drill;
        let drill = (md_sum * 0.5, [sx, sy], &*st.drilling);
        global_forces(&fe, ce, (&eb1, &eb2), drill, acc, &mut out);
        out.length = fe.char_length();
        out.area = fe.area;
        out.normal = fe.r[2];
        *st.thickness = new_thickness(t, dzz);
        Ok(out)
    }
}

/// The local nodal forces and moments summed over the Gauss points.
struct Forces<T> {
    /// Forces `[f̂x, f̂y, f̂z]` per node.
    fl: [[T; 3]; 4],
    /// In-plane moments `[m̂x, m̂y]` per node.
    ml: [[T; 2]; 4],
    /// The bending moments' share about the normal (warping correction).
    mb: [T; 4],
}

/// The membrane rates `[ε̇xx, ε̇yy, γ̇xy]`, curvature rates `[κ̇xx, κ̇yy,
/// 2κ̇xy]` (with the warping correction's twisted metric, `c`) and transverse
/// shear rates `[γ̇xz, γ̇yz]` at a Gauss point `(ξ, η)` of the midpoint frame
/// `fr`, with that point's `B` (`b`), the local velocities and the fibre
/// rotation rates `tl`.
#[allow(clippy::type_complexity)]
#[inline(always)]
fn point_rates<T: Real>(
    fr: &Frame<T>,
    (xi, eta): (f64, f64),
    (b1, b2): (&[T; 4], &[T; 4]),
    vl: &[[T; 3]; 4],
    wl: &[[T; 3]; 4],
    tl: &[[T; 2]; 4],
    c: T,
) -> ([T; 3], [T; 3], [T; 2]) {
    let zero = T::splat(0.0);
    let (mut dxx, mut dyy, mut vxy, mut vyx, mut kxx, mut kyy, mut kxy) =
        (zero, zero, zero, zero, zero, zero, zero);
    for i in 0..4 {
        dxx += b1[i] * vl[i][0];
        dyy += b2[i] * vl[i][1];
        vxy += b2[i] * vl[i][0];
        vyx += b1[i] * vl[i][1];
        kxx += b1[i] * tl[i][1];
        kyy -= b2[i] * tl[i][0];
        kxy += b2[i] * tl[i][1] - b1[i] * tl[i][0];
    }
    let gxy = vxy + vyx;
    // Warping correction, twisted metric: c × in-plane velocity gradient.
    kxx += c * vxy;
    kyy += c * vyx;
    kxy += c * (dxx + dyy);
    let sb = assumed_shear(fr, xi, eta);
    let (mut gxz, mut gyz) = (zero, zero);
    for i in 0..4 {
        gxz += sb.xz[0][i] * vl[i][2] + sb.xz[1][i] * wl[i][0] + sb.xz[2][i] * wl[i][1];
        gyz += sb.yz[0][i] * vl[i][2] + sb.yz[1][i] * wl[i][0] + sb.yz[2][i] * wl[i][1];
    }
    ([dxx, dyy, gxy], [kxx, kyy, kxy], [gxz, gyz])
}

/// A Gauss point's nodal forces at t_{n+1} added to `acc`: membrane with
/// the warping correction's terms folded in, f̂x = det((N_xx + c M_xy) B1 +
/// (N_xy + c M_xx) B2), f̂y likewise; transverse shear `q = [Q_x, Q_y]`;
/// `point` is that point's `(B1, B2, det, B̄_s)` in the frame `fe`.
#[inline(always)]
fn add_point_forces<T: Real>(
    fe: &Frame<T>,
    c: T,
    (b1, b2, det, sb): ([T; 4], [T; 4], T, ShearB<T>),
    sr: &SectionResult<T>,
    [qx, qy]: [T; 2],
    acc: &mut Forces<T>,
) {
    let (nr, mr) = (sr.n, sr.m);
    let (nxx, nyy) = (det * (nr[0] + c * mr[2]), det * (nr[1] + c * mr[2]));
    let (nxy_x, nxy_y) = (det * (nr[2] + c * mr[0]), det * (nr[2] + c * mr[1]));
    for i in 0..4 {
        acc.fl[i][0] += nxx * b1[i] + nxy_x * b2[i];
        acc.fl[i][1] += nyy * b2[i] + nxy_y * b1[i];
        acc.fl[i][2] += det * (qx * sb.xz[0][i] + qy * sb.yz[0][i]);
        let mxb = -det * (mr[1] * b2[i] + mr[2] * b1[i]);
        let myb = det * (mr[0] * b1[i] + mr[2] * b2[i]);
        acc.mb[i] += fe.y[i] * mxb + fe.x[i] * myb;
        acc.ml[i][0] += mxb + det * (qx * sb.xz[1][i] + qy * sb.yz[1][i]);
        acc.ml[i][1] += myb + det * (qx * sb.xz[2][i] + qy * sb.yz[2][i]);
    }
}

/// The element's local forces and moments `acc`, with the drilling
/// penalty's (`(½ Σ m_d, [S_x, S_y], the drilling moments)`), the warping
/// correction's tilt `ce` and the warped element's rigid-rotation terms,
/// turned into global nodal forces and moments in `out`.
#[allow(clippy::type_complexity)]
#[inline(always)]
fn global_forces<T: Real>(
    fe: &Frame<T>,
    ce: T,
    (eb1, eb2): (&[T; 4], &[T; 4]),
    (hmd, [sx, sy], drilling): (T, [T; 2], &[T; 4]),
    acc: Forces<T>,
    out: &mut ElementResult<T>,
) {
    let Forces { mut fl, mut ml, mb } = acc;
    for i in 0..4 {
        fl[i][0] += hmd * eb2[i];
        fl[i][1] -= hmd * eb1[i];
        fl[i][2] += ce * (sy * eb2[i] - sx * eb1[i]);
        ml[i][0] -= ce * fe.y[i] * drilling[i];
        ml[i][1] -= ce * fe.x[i] * drilling[i];
    }
    warp_rotation_forces(&fe.z, eb1, eb2, &mut fl);
    for i in 0..4 {
        let fg = fe.global(fl[i]);
        // Tilted fibres: the bending moments' share about the normal.
        let mg = fe.global([ml[i][0], ml[i][1], drilling[i] + ce * mb[i]]);
        out.f[i] = [-fg[0], -fg[1], -fg[2]];
        out.m[i] = [-mg[0], -mg[1], -mg[2]];
    }
}
