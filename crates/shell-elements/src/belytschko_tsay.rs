//! `BelytschkoTsay`: the one-point co-rotational shell with stiffness-based hourglass control and the optional BWC warping correction.
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
//! Warping correction (after Belytschko, Wong & Chiang 1992): for a warped
//! element whose nodes lie at heights `ẑ_I` off the mean plane, the twist
//! `c = Σ h_I ẑ_I / A` of the mid-surface couples membrane rates into the
//! curvature rate of the fibres: `κ_xx += c d_xy`, `κ_yy += c d_xy`,
//! `2κ_xy += c (d_xx + d_yy)` (tensor `d_xy`), the first-order term of the
//! rate of deformation of a Mindlin continuum on a twisted reference surface,
//! with the element spin standing in for the drilling rotation (so that a
//! rigid rotation produces no strain).
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

use crate::error::ShellError;
use crate::formulation::{
    DEFAULT_DRILLING, ElementResult, ElementState, ShellFormulation, check_drilling,
    drilling_penalty, integrate_section, local_velocities, new_thickness,
};
use crate::geometry::{Frame, H, V3, assumed_shear};
use crate::material::Material;
use crate::section::Section;

/// The Belytschko–Tsay one-point shell and its options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BelytschkoTsay {
    /// Belytschko–Wong–Chiang warping (twist) correction of the curvature; default off.
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
            warping_correction: false,
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
        let fr = Frame::new(x);
        let a = fr.area;
        if a.is_nan() || a <= 0.0 {
            return ElementResult {
                length: a,
                ..Default::default()
            };
        }
        let (vl, wl) = local_velocities(&fr, v, w);
        let (xl, yl) = (&fr.x, &fr.y);
        let (b1, b2) = fr.mean_b();
        let (mut dxx, mut dyy, mut gxy, mut kxx, mut kyy, mut kxy) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..4 {
            dxx += b1[i] * vl[i][0];
            dyy += b2[i] * vl[i][1];
            gxy += b2[i] * vl[i][0] + b1[i] * vl[i][1];
            kxx += b1[i] * wl[i][1];
            kyy -= b2[i] * wl[i][0];
            kxy += b2[i] * wl[i][1] - b1[i] * wl[i][0];
        }
        let c = if self.warping_correction {
            fr.twist()
        } else {
            0.0
        };
        kxx += 0.5 * c * gxy;
        kyy += 0.5 * c * gxy;
        kxy += c * (dxx + dyy);
        // Transverse shear coefficients: [w, θx, θy] per node.
        let sb = if self.shear_projection {
            assumed_shear(&fr, 0.0, 0.0)
        } else {
            crate::geometry::ShearB {
                xz: [b1, [0.0; 4], [0.25; 4]],
                yz: [b2, [-0.25; 4], [0.0; 4]],
            }
        };
        let (mut gxz, mut gyz) = (0.0, 0.0);
        for i in 0..4 {
            gxz += sb.xz[0][i] * vl[i][2] + sb.xz[1][i] * wl[i][0] + sb.xz[2][i] * wl[i][1];
            gyz += sb.yz[0][i] * vl[i][2] + sb.yz[1][i] * wl[i][0] + sb.yz[2][i] * wl[i][1];
        }

        // Stress update through the thickness.
        let t = *st.thickness;
        let sr = integrate_section(
            mat,
            &sec.rule,
            t,
            [dxx * dt, dyy * dt, gxy * dt],
            [kxx * dt, kyy * dt, kxy * dt],
            st.stress,
            st.history,
        );
        let g = mat.shear_modulus();
        let ks = sec.shear_factor;
        let tau_old = st.shear[0];
        let tau = [
            tau_old[0] + ks * g * gxz * dt,
            tau_old[1] + ks * g * gyz * dt,
        ];
        st.shear[0] = tau;
        let shear_work = t * 0.5 * ((tau_old[0] + tau[0]) * gxz + (tau_old[1] + tau[1]) * gyz) * dt;
        let (nr, mr) = (sr.n, sr.m);
        let (qx, qy) = (t * tau[0], t * tau[1]);

        // Hourglass control.
        let hx: f64 = (0..4).map(|i| H[i] * xl[i]).sum();
        let hy: f64 = (0..4).map(|i| H[i] * yl[i]).sum();
        let mut gam = [0.0; 4];
        for i in 0..4 {
            gam[i] = 0.5 * (H[i] - hx * b1[i] - hy * b2[i]);
        }
        let mut q = [0.0; 5];
        for i in 0..4 {
            q[0] += gam[i] * vl[i][0];
            q[1] += gam[i] * vl[i][1];
            q[2] += gam[i] * wl[i][0];
            q[3] += gam[i] * wl[i][1];
            q[4] += gam[i] * (vl[i][2] - 0.5 * (yl[i] * wl[i][0] - xl[i] * wl[i][1]));
        }
        let bb: f64 = (0..4).map(|i| b1[i] * b1[i] + b2[i] * b2[i]).sum();
        let r = sec.hourglass;
        let e = mat.young();
        let cm = r * e * t * a * bb / 8.0;
        let ct = r * e * t * t * t * a * bb / 192.0;
        let cw = r * ks * g * t * a * bb / 8.0;
        let cs = [cm, cm, ct, ct, cw];
        let hg = st.hourglass;
        let mut d_hg = 0.0;
        let mut qf = [0.0; 5];
        for k in 0..5 {
            let old = hg[k];
            let new = old + cs[k] * q[k] * dt;
            hg[k] = new;
            qf[k] = new;
            d_hg += 0.5 * (old + new) * q[k] * dt;
        }

        // Relative drilling penalty.
        let (md, d_drill) = drilling_penalty(
            0.25 * self.drilling * g * t * a,
            &b1,
            &b2,
            &vl,
            &wl,
            dt,
            st.drilling,
        );
        let hmd = 0.5 * md;

        // Nodal forces (local, internal), then global forces on the nodes.
        let msum = 0.5 * (mr[0] + mr[1]);
        let mut out = ElementResult {
            d_internal: a * (sr.work + shear_work) + d_drill,
            d_drilling: d_drill,
            d_hourglass: d_hg,
            d_plastic: a * sr.dissipation,
            length: fr.char_length(),
            ..Default::default()
        };
        for i in 0..4 {
            let fx = a * (nr[0] * b1[i] + nr[2] * b2[i] + c * (msum * b2[i] + mr[2] * b1[i]))
                + gam[i] * qf[0]
                + hmd * b2[i];
            let fy = a * (nr[1] * b2[i] + nr[2] * b1[i] + c * (msum * b1[i] + mr[2] * b2[i]))
                + gam[i] * qf[1]
                - hmd * b1[i];
            let fz = a * (qx * sb.xz[0][i] + qy * sb.yz[0][i]) + gam[i] * qf[4];
            let mx = a * (-mr[1] * b2[i] - mr[2] * b1[i] + qx * sb.xz[1][i] + qy * sb.yz[1][i])
                + gam[i] * (qf[2] - 0.5 * yl[i] * qf[4]);
            let my = a * (mr[0] * b1[i] + mr[2] * b2[i] + qx * sb.xz[2][i] + qy * sb.yz[2][i])
                + gam[i] * (qf[3] + 0.5 * xl[i] * qf[4]);
            let fg = fr.global([fx, fy, fz]);
            let mg = fr.global([mx, my, st.drilling[i]]);
            out.f[i] = [-fg[0], -fg[1], -fg[2]];
            out.m[i] = [-mg[0], -mg[1], -mg[2]];
        }
        *st.thickness = new_thickness(t, sr.deps_zz);
        out
    }
}
