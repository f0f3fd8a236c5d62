//! Element geometry in the co-rotational frame: local basis, projected coordinates, B-matrices, assumed transverse shear.
//!
//! Node numbering and natural coordinates: 1 (−1,−1), 2 (1,−1), 3 (1,1), 4 (−1,1)
//! (0-based 0..3 below). The frame normal `e3` is normal to both diagonals;
//! `e1` bisects the directions of sides 1→2 and 4→3, so the frame spins with
//! the element (co-rotational) and is independent of the node at which one
//! starts. Coordinates are relative to the node average.
//!
//! Written over [`Real`], so that the same code serves one element (`f64`)
//! and four in SIMD lanes (`F4`, whose [`Real::madd`] is fused).

use crate::lanes::Real;

/// A 3-vector as a plain array (the kernels avoid generic matrix types).
pub type V3 = [f64; 3];

#[inline(always)]
pub(crate) fn sub<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline(always)]
pub(crate) fn dot<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[2].madd(b[2], a[1].madd(b[1], a[0] * b[0]))
}
#[inline(always)]
pub(crate) fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1].madd(b[2], -(a[2] * b[1])),
        a[2].madd(b[0], -(a[0] * b[2])),
        a[0].madd(b[1], -(a[1] * b[0])),
    ]
}

/// Natural coordinates of the nodes.
pub(crate) const XI: [f64; 4] = [-1.0, 1.0, 1.0, -1.0];
/// Natural coordinates of the nodes.
pub(crate) const ETA: [f64; 4] = [-1.0, -1.0, 1.0, 1.0];
/// Hourglass base vector h = (1, −1, 1, −1).
pub(crate) const H: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// The co-rotational frame of a quad and its nodes' local coordinates
/// (of one element, `T = f64`, or of four in lanes, `T = F4`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame<T: Real = f64> {
    /// Rows: e1, e2, e3.
    pub r: [[T; 3]; 3],
    /// Local in-plane coordinates and heights (warping) of the nodes.
    pub x: [T; 4],
    pub y: [T; 4],
    pub z: [T; 4],
    /// Projected area (mm²); ≤ 0 signals a degenerate or inverted element.
    pub area: T,
    /// Warp `h·ẑ = Σ h_I ẑ_I` (mm): the heights are `ẑ = (h·ẑ/4) h`, since `e3`
    /// is normal to both diagonals (`ẑ_1 = ẑ_3`, `ẑ_2 = ẑ_4`, `Σ ẑ_I = 0`).
    pub warp: T,
}

impl<T: Real> Frame<T> {
    #[inline(always)]
    pub fn new(p: &[[T; 3]; 4]) -> Frame<T> {
        let d13 = sub(p[2], p[0]);
        let d24 = sub(p[3], p[1]);
        let n = cross(d13, d24);
        let nn = dot(n, n).sqrt();
        let inn = T::splat(1.0) / nn;
        let e3 = [n[0] * inn, n[1] * inn, n[2] * inn];
        let s = [
            p[1][0] - p[0][0] + p[2][0] - p[3][0],
            p[1][1] - p[0][1] + p[2][1] - p[3][1],
            p[1][2] - p[0][2] + p[2][2] - p[3][2],
        ];
        let sn = dot(s, e3);
        let s = [
            (-sn).madd(e3[0], s[0]),
            (-sn).madd(e3[1], s[1]),
            (-sn).madd(e3[2], s[2]),
        ];
        let sl = dot(s, s).sqrt();
        let isl = T::splat(1.0) / sl;
        let e1 = [s[0] * isl, s[1] * isl, s[2] * isl];
        let e2 = cross(e3, e1);
        let c = [
            (p[0][0] + p[1][0] + p[2][0] + p[3][0]) * 0.25,
            (p[0][1] + p[1][1] + p[2][1] + p[3][1]) * 0.25,
            (p[0][2] + p[1][2] + p[2][2] + p[3][2]) * 0.25,
        ];
        let mut x = [T::default(); 4];
        let mut y = [T::default(); 4];
        let mut z = [T::default(); 4];
        for i in 0..4 {
            let d = sub(p[i], c);
            x[i] = dot(e1, d);
            y[i] = dot(e2, d);
            z[i] = dot(e3, d);
        }
        let area = (x[2] - x[0]).madd(y[3] - y[1], -((x[3] - x[1]) * (y[2] - y[0]))) * 0.5;
        Frame {
            r: [e1, e2, e3],
            x,
            y,
            z,
            area: T::select(area.is_finite(), area, T::splat(-1.0)),
            // Σ h_I ẑ_I = e3·(p0 − p1 + p2 − p3) = 2 e3·(p0 − p1), as e3 ⟂ both
            // diagonals (e3·p2 = e3·p0, e3·p3 = e3·p1).
            warp: dot(e3, sub(p[0], p[1])) * 2.0,
        }
    }

    /// A global vector in local components.
    #[inline(always)]
    pub fn local(&self, v: [T; 3]) -> [T; 3] {
        [dot(self.r[0], v), dot(self.r[1], v), dot(self.r[2], v)]
    }

    /// A local vector in global components.
    #[inline(always)]
    pub fn global(&self, v: [T; 3]) -> [T; 3] {
        let r = &self.r;
        [
            r[2][0].madd(v[2], r[1][0].madd(v[1], r[0][0] * v[0])),
            r[2][1].madd(v[2], r[1][1].madd(v[1], r[0][1] * v[0])),
            r[2][2].madd(v[2], r[1][2].madd(v[1], r[0][2] * v[0])),
        ]
    }

    /// Mean (one-point) B-matrix `∂N/∂x`, `∂N/∂y` over the projected
    /// element, `(1/A) ∫ ∂N/∂x dA` (Flanagan & Belytschko 1981): exact for
    /// linear fields on any quad.
    #[inline(always)]
    pub fn mean_b(&self) -> ([T; 4], [T; 4]) {
        let (xl, yl) = (&self.x, &self.y);
        let i2a = T::splat(0.5) / self.area;
        (
            [
                i2a * (yl[1] - yl[3]),
                i2a * (yl[2] - yl[0]),
                i2a * (yl[3] - yl[1]),
                i2a * (yl[0] - yl[2]),
            ],
            [
                i2a * (xl[3] - xl[1]),
                i2a * (xl[0] - xl[2]),
                i2a * (xl[1] - xl[3]),
                i2a * (xl[2] - xl[0]),
            ],
        )
    }

    /// Characteristic length for the time step: area / longest side (mm).
    #[inline(always)]
    pub fn char_length(&self) -> T {
        let mut m = T::splat(0.0);
        for i in 0..4 {
            let j = (i + 1) & 3;
            let dx = self.x[j] - self.x[i];
            let dy = self.y[j] - self.y[i];
            m = m.max(dy.madd(dy, dx * dx));
        }
        self.area / m.sqrt()
    }

    /// Twist of the warped mid-surface, c = Σ h_I z_I / A (1/mm): exact
    /// `∂²z/∂x∂y` for a rectangle whose nodes lie on z = c x y.
    #[inline(always)]
    pub fn twist(&self) -> T {
        self.warp / self.area
    }
}

impl Frame<f64> {
    /// Smallest corner cross product over the element's mean size squared,
    /// < 0 for an inverted or non-convex corner (set-up check).
    pub fn corner_quality(&self) -> (usize, f64) {
        let mut worst = (0, f64::INFINITY);
        for i in 0..4 {
            let a = (i + 1) & 3;
            let b = (i + 3) & 3;
            let c = (self.x[a] - self.x[i]) * (self.y[b] - self.y[i])
                - (self.y[a] - self.y[i]) * (self.x[b] - self.x[i]);
            let q = c / self.area;
            if q < worst.1 {
                worst = (i, q);
            }
        }
        worst
    }
}

/// Shape-function derivatives ∂N/∂x, ∂N/∂y at (ξ, η) and the Jacobian determinant.
#[inline(always)]
pub(crate) fn b_matrix<T: Real>(f: &Frame<T>, xi: f64, eta: f64) -> ([T; 4], [T; 4], T) {
    let mut nxi = [0.0; 4];
    let mut neta = [0.0; 4];
    for i in 0..4 {
        nxi[i] = 0.25 * XI[i] * (1.0 + ETA[i] * eta);
        neta[i] = 0.25 * ETA[i] * (1.0 + XI[i] * xi);
    }
    let zero = T::splat(0.0);
    let (mut x_xi, mut x_eta, mut y_xi, mut y_eta) = (zero, zero, zero, zero);
    for i in 0..4 {
        x_xi += f.x[i] * nxi[i];
        x_eta += f.x[i] * neta[i];
        y_xi += f.y[i] * nxi[i];
        y_eta += f.y[i] * neta[i];
    }
    let det = x_xi * y_eta - x_eta * y_xi;
    let inv = T::splat(1.0) / det;
    let mut b1 = [zero; 4];
    let mut b2 = [zero; 4];
    for i in 0..4 {
        b1[i] = inv * (y_eta * nxi[i] - y_xi * neta[i]);
        b2[i] = inv * (-x_eta * nxi[i] + x_xi * neta[i]);
    }
    (b1, b2, det)
}

/// Assumed (Bathe–Dvorkin / MITC4) transverse shear at (ξ, η): coefficients
/// of the nodal `w` (local normal velocity), `θx`, `θy` in γ_xz and γ_yz.
///
/// Covariant shear is tied at the edge midpoints — γ_ξz on η = ±1, γ_ηz on
/// ξ = ±1 — with `γ_ξz = ∂w/∂ξ + x,ξ θy − y,ξ θx` on each edge, interpolated
/// linearly across, and mapped to Cartesian with the Jacobian at (ξ, η).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ShearB<T: Real = f64> {
    pub xz: [[T; 4]; 3],
    pub yz: [[T; 4]; 3],
}

#[inline(always)]
pub(crate) fn assumed_shear<T: Real>(f: &Frame<T>, xi: f64, eta: f64) -> ShearB<T> {
    let (x, y) = (&f.x, &f.y);
    // Edge vectors (half-lengths enter as ½ below).
    let (x12, y12) = (x[1] - x[0], y[1] - y[0]); // η = −1
    let (x43, y43) = (x[2] - x[3], y[2] - y[3]); // η = +1
    let (x14, y14) = (x[3] - x[0], y[3] - y[0]); // ξ = −1
    let (x23, y23) = (x[2] - x[1], y[2] - y[1]); // ξ = +1
    let wm = 0.5 * (1.0 - eta);
    let wp = 0.5 * (1.0 + eta);
    let vm = 0.5 * (1.0 - xi);
    let vp = 0.5 * (1.0 + xi);
    // γ_ξz = wm γ^C + wp γ^A; γ^C = ½(w2−w1) + ½x12·½(θy1+θy2) − ½y12·½(θx1+θx2).
    let gxi_w = [-0.5 * wm, 0.5 * wm, 0.5 * wp, -0.5 * wp];
    let gxi_ty = [
        x12 * (0.25 * wm),
        x12 * (0.25 * wm),
        x43 * (0.25 * wp),
        x43 * (0.25 * wp),
    ];
    let gxi_tx = [
        y12 * (-0.25 * wm),
        y12 * (-0.25 * wm),
        y43 * (-0.25 * wp),
        y43 * (-0.25 * wp),
    ];
    // γ_ηz = vm γ^B + vp γ^D; γ^B = ½(w4−w1) + ½x14·½(θy1+θy4) − …
    let get_w = [-0.5 * vm, -0.5 * vp, 0.5 * vp, 0.5 * vm];
    let get_ty = [
        x14 * (0.25 * vm),
        x23 * (0.25 * vp),
        x23 * (0.25 * vp),
        x14 * (0.25 * vm),
    ];
    let get_tx = [
        y14 * (-0.25 * vm),
        y23 * (-0.25 * vp),
        y23 * (-0.25 * vp),
        y14 * (-0.25 * vm),
    ];
    // Jacobian at (ξ, η).
    let zero = T::splat(0.0);
    let (mut x_xi, mut x_eta, mut y_xi, mut y_eta) = (zero, zero, zero, zero);
    for i in 0..4 {
        let nxi = 0.25 * XI[i] * (1.0 + ETA[i] * eta);
        let neta = 0.25 * ETA[i] * (1.0 + XI[i] * xi);
        let (nxi, neta) = (T::splat(nxi), T::splat(neta));
        x_xi = x[i].madd(nxi, x_xi);
        x_eta = x[i].madd(neta, x_eta);
        y_xi = y[i].madd(nxi, y_xi);
        y_eta = y[i].madd(neta, y_eta);
    }
    let inv = T::splat(1.0) / x_xi.madd(y_eta, -(x_eta * y_xi));
    // [γx; γy] = J⁻¹ [γξ; γη], J = [[x,ξ, y,ξ], [x,η, y,η]].
    let (a, b, c, d) = (inv * y_eta, -inv * y_xi, -inv * x_eta, inv * x_xi);
    let mut s = ShearB {
        xz: [[zero; 4]; 3],
        yz: [[zero; 4]; 3],
    };
    for i in 0..4 {
        let (gw, ew) = (T::splat(gxi_w[i]), T::splat(get_w[i]));
        s.xz[0][i] = b.madd(ew, a * gw);
        s.xz[1][i] = b.madd(get_tx[i], a * gxi_tx[i]);
        s.xz[2][i] = b.madd(get_ty[i], a * gxi_ty[i]);
        s.yz[0][i] = d.madd(ew, c * gw);
        s.yz[1][i] = d.madd(get_tx[i], c * gxi_tx[i]);
        s.yz[2][i] = d.madd(get_ty[i], c * gxi_ty[i]);
    }
    s
}

/// The co-rotational basis `[e1, e2, e3]` (rows) of a quad with corners `x`:
/// the frame in which [`ShellSet::stress`](crate::ShellSet::stress) and the
/// resultants are expressed.
pub fn corotational_basis(x: &[V3; 4]) -> [V3; 3] {
    Frame::new(x).r
}
