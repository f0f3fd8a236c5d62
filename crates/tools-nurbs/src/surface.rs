//! Rational tensor-product B-spline (NURBS) surfaces: validation and evaluation up to second derivatives.

// Numeric kernels index several arrays with one counter.
#![allow(clippy::needless_range_loop)]

use crate::basis::{MAX_DEGREE, ORDER, find_span};
use crate::error::NurbsError;
use plugins_api::Vec3;

/// The definition of one NURBS patch as a user or a builder gives it.
///
/// Control points are stored u-major: point `(i, j)` (`i` along u, `j` along
/// v) is `points[i * count_v + j]`. Knot vectors must be clamped (first and
/// last knots repeated `degree + 1` times) so that the patch interpolates its
/// corner points.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchDef {
    /// Degree along u (1..=[`MAX_DEGREE`]).
    pub degree_u: usize,
    /// Degree along v.
    pub degree_v: usize,
    /// Knot vector along u (non-decreasing, clamped).
    pub knots_u: Vec<f64>,
    /// Knot vector along v.
    pub knots_v: Vec<f64>,
    /// Number of control points along v (along u: `points.len() / count_v`).
    pub count_v: usize,
    /// Control points (mm), u-major.
    pub points: Vec<Vec3>,
    /// Weights (> 0), one per control point.
    pub weights: Vec<f64>,
}

/// Position and partial derivatives of a surface at one `(u, v)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Derivs {
    /// `S(u, v)` (mm).
    pub s: Vec3,
    /// `∂S/∂u`.
    pub su: Vec3,
    /// `∂S/∂v`.
    pub sv: Vec3,
    /// `∂²S/∂u²`.
    pub suu: Vec3,
    /// `∂²S/∂u∂v`.
    pub suv: Vec3,
    /// `∂²S/∂v²`.
    pub svv: Vec3,
}

impl Derivs {
    /// All six vectors zero.
    pub const ZERO: Self = Self {
        s: Vec3::new(0.0, 0.0, 0.0),
        su: Vec3::new(0.0, 0.0, 0.0),
        sv: Vec3::new(0.0, 0.0, 0.0),
        suu: Vec3::new(0.0, 0.0, 0.0),
        suv: Vec3::new(0.0, 0.0, 0.0),
        svv: Vec3::new(0.0, 0.0, 0.0),
    };
}

/// A validated NURBS surface ready for fast evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsSurface {
    p: usize,
    q: usize,
    nu: usize,
    nv: usize,
    ku: Vec<f64>,
    kv: Vec<f64>,
    /// Homogeneous control points `(w x, w y, w z, w)`, u-major.
    cw: Vec<[f64; 4]>,
    /// Distinct knots along u: the ends of the Bézier pieces (`pu + 1` values).
    bu: Vec<f64>,
    /// Distinct knots along v.
    bv: Vec<f64>,
    /// Parameter domain `[u_min, u_max, v_min, v_max]`.
    lim: [f64; 4],
    /// Number of pieces along v.
    pv: usize,
    /// The Bézier pieces, `(a, b)` (span `a` along u, `b` along v) at `a * pv + b`.
    pieces: Vec<Piece>,
    /// Every non-affine piece as a polynomial in `(Δu, Δv)`, the offsets from
    /// the piece's centre, from the Bézier extraction of the net: the
    /// homogeneous coefficients `M[i][j]` of `Δu^i Δv^j` and those of its first
    /// and second `v` derivatives, `(j + 1) M[i][j + 1]` and
    /// `(j + 2)(j + 1) M[i][j + 2]`, so that an evaluation is two nested Horner
    /// schemes (about a third of the operations of the tensor-product
    /// Bernstein sums). `(p + 1) 3 q` entries per piece from [`Piece::off`],
    /// row `i` at `3 q i`: `q + 1`, `q` and `q - 1` entries.
    mono: Vec<[f64; 4]>,
}

/// One Bézier piece of a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    /// How it is evaluated.
    kind: Kind,
    /// Its centre `(u, v)`.
    centre: [f64; 2],
    /// Its parameter box `[u_0, u_1, v_0, v_1]`.
    bounds: [f64; 4],
    /// Its coefficients' offset in [`NurbsSurface`]'s `mono` (non-affine pieces).
    off: usize,
    /// Affine pieces: `S(centre)`, `S_u`, `S_v` (zero otherwise).
    affine: [Vec3; 3],
}

/// How a Bézier piece is evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Equal weights and `S = M[0][0] + M[1][0] Δu + M[0][1] Δv` (a flat piece
    /// with a linear parametrisation, such as a plane or a straight wall):
    /// three coefficients, no basis, zero second derivatives.
    Affine,
    /// Equal weights: Cartesian coefficients (weight 1), no quotient rule.
    Poly,
    /// Homogeneous coefficients and the quotient rule.
    Rational,
}

fn check_knots(
    patch: usize,
    dir: char,
    knots: &[f64],
    count: usize,
    degree: usize,
) -> Result<(), NurbsError> {
    if !(1..=MAX_DEGREE).contains(&degree) {
        return Err(NurbsError::Degree {
            patch,
            dir,
            value: degree,
            max: MAX_DEGREE,
        });
    }
    if count < degree + 1 {
        return Err(NurbsError::NetSize {
            patch,
            field: if dir == 'u' {
                "control points along u"
            } else {
                "control points along v"
            },
            len: count,
            expected: degree + 1,
        });
    }
    let expected = count + degree + 1;
    if knots.len() != expected {
        return Err(NurbsError::KnotCount {
            patch,
            dir,
            len: knots.len(),
            expected,
            count,
            degree,
        });
    }
    let bad = |index: usize, problem: &'static str| NurbsError::Knot {
        patch,
        dir,
        index,
        value: knots[index],
        problem,
    };
    for (i, k) in knots.iter().enumerate() {
        if !k.is_finite() {
            return Err(bad(i, "is not finite"));
        }
        if i > 0 && *k < knots[i - 1] {
            return Err(bad(
                i,
                "is smaller than the knot before it (knots must not decrease)",
            ));
        }
    }
    for i in 1..=degree {
        if knots[i] != knots[0] {
            return Err(bad(
                i,
                "breaks the clamped start (the first degree + 1 knots must be equal)",
            ));
        }
        let j = expected - 1 - i;
        if knots[j] != knots[expected - 1] {
            return Err(bad(
                j,
                "breaks the clamped end (the last degree + 1 knots must be equal)",
            ));
        }
    }
    if knots[expected - 1] <= knots[0] {
        return Err(bad(expected - 1, "leaves an empty parameter domain"));
    }
    // Interior multiplicity at most `degree` (the surface stays continuous).
    let mut run = 1;
    for i in degree + 1..count {
        run = if knots[i] == knots[i - 1] { run + 1 } else { 1 };
        if run > degree {
            return Err(bad(
                i,
                "has multiplicity above the degree (the surface would break apart)",
            ));
        }
    }
    Ok(())
}

/// The distinct knots of the domain `knots[p..=n]` (the piece ends).
fn breakpoints(knots: &[f64], p: usize, n: usize) -> Vec<f64> {
    let mut b: Vec<f64> = Vec::with_capacity(n - p + 1);
    for &k in &knots[p..=n] {
        if b.last() != Some(&k) {
            b.push(k);
        }
    }
    b
}

/// Bézier extraction of a homogeneous curve: insert every interior knot up
/// to multiplicity `p` (Boehm's knot insertion, *The NURBS Book* A5.1; the
/// curve is unchanged), then piece `s` has control points `s p ..= s p + p`.
/// Returns the pieces' control points, `p + 1` per piece.
fn extract_curve(pts: &[[f64; 4]], p: usize, knots: &[f64]) -> Vec<[f64; 4]> {
    let mut pts = pts.to_vec();
    let mut knots = knots.to_vec();
    let n = pts.len();
    let (lo, hi) = (knots[p], knots[n]);
    let mut i = p + 1;
    while i < knots.len() - p - 1 {
        let t = knots[i];
        if t <= lo || t >= hi {
            i += 1;
            continue;
        }
        let mult = knots.iter().filter(|&&k| k == t).count();
        if mult >= p {
            i += mult;
            continue;
        }
        // Span k with knots[k] <= t < knots[k + 1].
        let k = knots.iter().rposition(|&x| x <= t).unwrap_or(p);
        let mut q = Vec::with_capacity(pts.len() + 1);
        for j in 0..=pts.len() {
            if j + p <= k {
                q.push(pts[j]);
            } else if j > k {
                q.push(pts[j - 1]);
            } else {
                let a = (t - knots[j]) / (knots[j + p] - knots[j]);
                let mut c = [0.0; 4];
                for m in 0..4 {
                    c[m] = a * pts[j][m] + (1.0 - a) * pts[j - 1][m];
                }
                q.push(c);
            }
        }
        knots.insert(k + 1, t);
        pts = q;
        // Same i again: the run of t is now one longer.
    }
    // Every interior knot now has multiplicity >= p, so on each non-empty
    // span s the basis is the Bernstein basis of points s - p ..= s.
    let mut out = Vec::new();
    for s in p..pts.len() {
        if knots[s] < knots[s + 1] {
            out.extend_from_slice(&pts[s - p..=s]);
        }
    }
    out
}

/// Bézier extraction of a tensor-product net (u-major, `nu × nv`) into the
/// Bézier pieces: `(p + 1)(q + 1)` points per piece (u-major), piece `(a, b)`
/// (span `a` along u, `b` along v) at `(a * pieces_v + b) * (p + 1)(q + 1)`.
fn extract(
    cw: &[[f64; 4]],
    nu: usize,
    nv: usize,
    p: usize,
    q: usize,
    ku: &[f64],
    kv: &[f64],
) -> Vec<[f64; 4]> {
    // Along u for every column j: cols[j] = (pieces_u * (p + 1)) points.
    let cols: Vec<Vec<[f64; 4]>> = (0..nv)
        .map(|j| {
            let col: Vec<[f64; 4]> = (0..nu).map(|i| cw[i * nv + j]).collect();
            extract_curve(&col, p, ku)
        })
        .collect();
    let mu = cols[0].len();
    // Along v for every extracted row r: rows[r] = (pieces_v * (q + 1)) points.
    let rows: Vec<Vec<[f64; 4]>> = (0..mu)
        .map(|r| {
            let row: Vec<[f64; 4]> = (0..nv).map(|j| cols[j][r]).collect();
            extract_curve(&row, q, kv)
        })
        .collect();
    let (pu, pv) = (mu / (p + 1), rows[0].len() / (q + 1));
    let mut out = Vec::with_capacity(pu * pv * (p + 1) * (q + 1));
    for a in 0..pu {
        for b in 0..pv {
            for i in 0..=p {
                out.extend_from_slice(&rows[a * (p + 1) + i][b * (q + 1)..=b * (q + 1) + q]);
            }
        }
    }
    out
}

impl NurbsSurface {
    /// Validate a patch definition (`patch` is its index, used in errors) and
    /// prepare it for evaluation. Checks degrees, knot vectors, net size,
    /// weights, finite points, and that the surface is regular (a defined
    /// normal) on a sample grid of every knot span, corners included.
    pub fn new(patch: usize, def: &PatchDef) -> Result<Self, NurbsError> {
        let nv = def.count_v;
        if nv == 0 || !def.points.len().is_multiple_of(nv) {
            return Err(NurbsError::NetSize {
                patch,
                field: "points",
                len: def.points.len(),
                expected: nv.max(1) * (def.points.len() / nv.max(1) + 1),
            });
        }
        let nu = def.points.len() / nv;
        check_knots(patch, 'u', &def.knots_u, nu, def.degree_u)?;
        check_knots(patch, 'v', &def.knots_v, nv, def.degree_v)?;
        if def.weights.len() != def.points.len() {
            return Err(NurbsError::NetSize {
                patch,
                field: "weights",
                len: def.weights.len(),
                expected: def.points.len(),
            });
        }
        let mut cw = Vec::with_capacity(def.points.len());
        for (index, (p, &w)) in def.points.iter().zip(&def.weights).enumerate() {
            if !(w.is_finite() && w > 0.0) {
                return Err(NurbsError::Weight {
                    patch,
                    index,
                    value: w,
                });
            }
            if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                return Err(NurbsError::Point {
                    patch,
                    index,
                    x: p.x,
                    y: p.y,
                    z: p.z,
                });
            }
            cw.push([w * p.x, w * p.y, w * p.z, w]);
        }
        let (p, q) = (def.degree_u, def.degree_v);
        let bu = breakpoints(&def.knots_u, p, nu);
        let bv = breakpoints(&def.knots_v, q, nv);
        let bez = extract(&cw, nu, nv, p, q, &def.knots_u, &def.knots_v);
        let pv = bv.len() - 1;
        let (tp, tq) = (centred_bernstein(p), centred_bernstein(q));
        let mut mono = Vec::new();
        let mut pieces = Vec::with_capacity(bez.len() / ((p + 1) * (q + 1)));
        for (k, piece) in bez.chunks_exact((p + 1) * (q + 1)).enumerate() {
            let (a, b) = (k / pv, k % pv);
            let widths = (bu[a + 1] - bu[a], bv[b + 1] - bv[b]);
            let (m, kind) = monomial_piece(piece, p, q, &tp, &tq, widths);
            let v3 = |x: &[f64; 4]| Vec3::new(x[0], x[1], x[2]);
            let affine = if kind == Kind::Affine {
                [v3(&m[0]), v3(&m[3 * q]), v3(&m[1])]
            } else {
                [Vec3::zeros(); 3]
            };
            pieces.push(Piece {
                kind,
                centre: [0.5 * (bu[a] + bu[a + 1]), 0.5 * (bv[b] + bv[b + 1])],
                bounds: [bu[a], bu[a + 1], bv[b], bv[b + 1]],
                off: mono.len(),
                affine,
            });
            if kind != Kind::Affine {
                mono.extend_from_slice(&m);
            }
        }
        let s = Self {
            p,
            q,
            nu,
            nv,
            ku: def.knots_u.clone(),
            kv: def.knots_v.clone(),
            cw,
            lim: [bu[0], bu[bu.len() - 1], bv[0], bv[bv.len() - 1]],
            pv,
            bu,
            bv,
            pieces,
            mono,
        };
        s.check_regular(patch)?;
        Ok(s)
    }

    fn check_regular(&self, patch: usize) -> Result<(), NurbsError> {
        let scale = self.control_box_diagonal().max(1e-300);
        const M: usize = 6;
        for (u0, u1) in self.spans_u() {
            for (v0, v1) in self.spans_v() {
                for a in 0..=M {
                    for b in 0..=M {
                        let u = u0 + (u1 - u0) * a as f64 / M as f64;
                        let v = v0 + (v1 - v0) * b as f64 / M as f64;
                        let d = self.eval(u, v);
                        let su = d.su * (u1 - u0);
                        let sv = d.sv * (v1 - v0);
                        let c = su.cross(&sv).norm();
                        if !(c > 1e-10 * scale * scale && c > 1e-6 * su.norm() * sv.norm()) {
                            return Err(NurbsError::Degenerate { patch, u, v });
                        }
                    }
                }
            }
        }
        Ok(())
    }

    fn control_box_diagonal(&self) -> f64 {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for c in &self.cw {
            let p = Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3]);
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
        (hi - lo).norm()
    }

    /// Degrees `(p, q)` along u and v.
    pub fn degrees(&self) -> (usize, usize) {
        (self.p, self.q)
    }

    /// Parameter domain `([u_min, u_max], [v_min, v_max])`.
    pub fn domain(&self) -> ([f64; 2], [f64; 2]) {
        (
            [self.ku[self.p], self.ku[self.nu]],
            [self.kv[self.q], self.kv[self.nv]],
        )
    }

    fn spans(knots: &[f64], p: usize, n: usize) -> Vec<(f64, f64)> {
        (p..n)
            .filter(|&i| knots[i + 1] > knots[i])
            .map(|i| (knots[i], knots[i + 1]))
            .collect()
    }

    /// The non-empty knot spans along u, as parameter intervals.
    pub fn spans_u(&self) -> Vec<(f64, f64)> {
        Self::spans(&self.ku, self.p, self.nu)
    }

    /// The non-empty knot spans along v.
    pub fn spans_v(&self) -> Vec<(f64, f64)> {
        Self::spans(&self.kv, self.q, self.nv)
    }

    /// Cartesian control points (mm) whose basis functions are non-zero on the
    /// span containing `(u, v)` (convex hull of that piece of surface).
    pub fn span_control_points(&self, u: f64, v: f64) -> impl Iterator<Item = Vec3> + '_ {
        let su = find_span(self.nu, self.p, &self.ku, u);
        let sv = find_span(self.nv, self.q, &self.kv, v);
        (su - self.p..=su).flat_map(move |i| {
            (sv - self.q..=sv).map(move |j| {
                let c = self.cw[i * self.nv + j];
                Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3])
            })
        })
    }

    /// Every Cartesian control point of the net (mm); the surface lies in
    /// their convex hull (positive weights).
    pub fn control_points(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.cw
            .iter()
            .map(|c| Vec3::new(c[0] / c[3], c[1] / c[3], c[2] / c[3]))
    }

    /// Number of control points `(along u, along v)`.
    pub fn net_size(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }

    /// The weights of the net, in the order of [`Self::control_points`].
    pub fn weights(&self) -> impl Iterator<Item = f64> + '_ {
        self.cw.iter().map(|c| c[3])
    }

    /// Point only (mm).
    pub fn point(&self, u: f64, v: f64) -> Vec3 {
        self.eval(u, v).s
    }

    /// Point and first and second partial derivatives at `(u, v)` (clamped to the domain).
    ///
    /// Evaluates the Bézier piece holding `(u, v)` (the knot span with
    /// `knots[s] <= t < knots[s + 1]`, the last one at the end of the domain)
    /// from its centred polynomial coefficients.
    #[inline]
    pub fn eval(&self, u: f64, v: f64) -> Derivs {
        let mut d = Derivs::ZERO;
        self.eval_into(u, v, &mut d);
        d
    }

    /// [`Self::eval`] written into `out` (no copy of the result). Returns the
    /// index of the evaluated Bézier piece when that piece is affine (flat with
    /// a linear parametrisation: zero second derivatives, and Newton's step
    /// from any of its points lands on the plane's closest point exactly).
    #[inline(never)]
    pub(crate) fn eval_into(&self, u: f64, v: f64, out: &mut Derivs) -> Option<usize> {
        let (index, u, v) = self.locate(u, v);
        self.eval_piece(index, u, v, out).then_some(index)
    }

    /// [`Self::eval_into`] that returns the parameter box `[u_0, u_1, v_0,
    /// v_1]` of the evaluated piece (located once).
    #[inline]
    pub(crate) fn eval_boxed(&self, u: f64, v: f64, out: &mut Derivs) -> [f64; 4] {
        let (index, u, v) = self.locate(u, v);
        self.eval_piece(index, u, v, out);
        self.pieces[index].bounds
    }

    /// Evaluate piece `index` at the (clamped, located) `(u, v)` into `out`;
    /// true when the piece is affine.
    #[inline(always)]
    fn eval_piece(&self, index: usize, u: f64, v: f64, out: &mut Derivs) -> bool {
        let piece = &self.pieces[index];
        let (du, dv) = (u - piece.centre[0], v - piece.centre[1]);
        match piece.kind {
            Kind::Affine => {
                let [c, mu, mv] = piece.affine;
                *out = Derivs {
                    s: c + mu * du + mv * dv,
                    su: mu,
                    sv: mv,
                    suu: Vec3::zeros(),
                    suv: Vec3::zeros(),
                    svv: Vec3::zeros(),
                };
                return true;
            }
            Kind::Poly => *out = polynomial(&self.homogeneous(piece.off, du, dv)),
            Kind::Rational => *out = rational(&self.homogeneous(piece.off, du, dv)),
        }
        false
    }

    /// The parameter box `[u_0, u_1, v_0, v_1]` of the piece `index` (as
    /// [`Self::eval_into`] returns it).
    #[inline]
    pub(crate) fn piece_bounds(&self, index: usize) -> [f64; 4] {
        self.pieces[index].bounds
    }

    /// The parameter box `[u_0, u_1, v_0, v_1]` of the Bézier piece holding
    /// `(u, v)` (clamped to the domain), the one [`Self::eval`] evaluates there.
    #[inline]
    pub fn piece_box(&self, u: f64, v: f64) -> [f64; 4] {
        self.pieces[self.locate(u, v).0].bounds
    }

    /// Homogeneous derivatives `[A, A_u, A_v, A_uu, A_uv, A_vv]` of the piece
    /// at `off`, monomorphised for the degrees the builders use (the slice
    /// lengths are constants there, so the unrolled loops check no bounds).
    #[inline(always)]
    fn homogeneous(&self, off: usize, du: f64, dv: f64) -> [[f64; 4]; 6] {
        let m = &self.mono[off..];
        match (self.p, self.q) {
            (1, 1) => horner2(&m[..6], 1, 1, du, dv),
            (1, 2) => horner2(&m[..12], 1, 2, du, dv),
            (2, 1) => horner2(&m[..9], 2, 1, du, dv),
            (2, 2) => horner2(&m[..18], 2, 2, du, dv),
            (p, q) => horner_any(&m[..(p + 1) * 3 * q], p, q, du, dv),
        }
    }

    /// The piece holding the clamped `(u, v)`, with the clamped parameters.
    #[inline(always)]
    fn locate(&self, u: f64, v: f64) -> (usize, f64, f64) {
        let u = u.clamp(self.lim[0], self.lim[1]);
        let v = v.clamp(self.lim[2], self.lim[3]);
        let iu = if self.bu.len() == 2 {
            0
        } else {
            self.bu[1..self.bu.len() - 1].partition_point(|&k| k <= u)
        };
        let iv = if self.pv == 1 {
            0
        } else {
            self.bv[1..self.pv].partition_point(|&k| k <= v)
        };
        (iu * self.pv + iv, u, v)
    }
}

/// `T[i][a]`: the coefficient of `σ^a` in the Bernstein polynomial
/// `B_i^p(1/2 + σ)` (exact: binomials times powers of 1/2).
fn centred_bernstein(p: usize) -> [[f64; ORDER]; ORDER] {
    let mut t = [[0.0; ORDER]; ORDER];
    for (i, row) in t.iter_mut().enumerate().take(p + 1) {
        // C(p, i) (1/2 + σ)^i (1/2 - σ)^(p - i), multiplied out.
        let mut c = [0.0; ORDER];
        c[0] = (0..i).fold(1.0, |b, k| b * (p - k) as f64 / (k + 1) as f64);
        for k in 0..p {
            let sign = if k < i { 1.0 } else { -1.0 };
            for a in (0..=k + 1).rev() {
                let lower = if a > 0 { c[a - 1] } else { 0.0 };
                c[a] = 0.5 * c[a] + sign * lower;
            }
        }
        *row = c;
    }
    t
}

/// The centred coefficients of one Bézier piece (`(p + 1)(q + 1)` homogeneous
/// points, u-major, of parameter widths `w`) in the layout of
/// [`NurbsSurface`]'s `mono`, and how the piece is evaluated.
fn monomial_piece(
    piece: &[[f64; 4]],
    p: usize,
    q: usize,
    tp: &[[f64; ORDER]; ORDER],
    tq: &[[f64; ORDER]; ORDER],
    w: (f64, f64),
) -> (Vec<[f64; 4]>, Kind) {
    let w0 = piece[0][3];
    let equal = piece
        .iter()
        .all(|c| (c[3] - w0).abs() <= 4.0 * f64::EPSILON * w0);
    // Equal weights: the Cartesian points with weight 1 (the same surface).
    let pts: Vec<[f64; 4]> = piece
        .iter()
        .map(|c| {
            if equal {
                [c[0] / c[3], c[1] / c[3], c[2] / c[3], 1.0]
            } else {
                *c
            }
        })
        .collect();
    // Coefficients of σ^a τ^b (σ, τ: offsets from the centre in units of the widths).
    let mut sig = vec![[[0.0; 4]; ORDER]; p + 1];
    let mut size = 0.0f64;
    for a in 0..=p {
        for b in 0..=q {
            let mut c = [0.0; 4];
            for i in 0..=p {
                for j in 0..=q {
                    let f = tp[i][a] * tq[j][b];
                    if f != 0.0 {
                        for ch in 0..4 {
                            c[ch] += f * pts[i * (q + 1) + j][ch];
                        }
                    }
                }
            }
            sig[a][b] = c;
        }
    }
    for c in &pts {
        size = size.max(c[0].abs()).max(c[1].abs()).max(c[2].abs());
    }
    // Affine: every term but 1, σ and τ vanishes to rounding (at most 1/2^(a+b)
    // of the coefficient on the piece).
    let affine = equal
        && (0..=p).all(|a| {
            (0..=q).all(|b| {
                a + b <= 1 || {
                    let c = &sig[a][b];
                    let scale = 0.5f64.powi((a + b) as i32);
                    (0..3).all(|ch| c[ch].abs() * scale <= 16.0 * f64::EPSILON * size)
                }
            })
        });
    let (iu, iv) = (1.0 / w.0, 1.0 / w.1);
    let mut out = Vec::with_capacity((p + 1) * 3 * q);
    for (a, row) in sig.iter().enumerate() {
        let sa = iu.powi(a as i32);
        let m: Vec<[f64; 4]> = (0..=q)
            .map(|b| {
                let f = sa * iv.powi(b as i32);
                let keep = !affine || a + b <= 1;
                row[b].map(|x| if keep { x * f } else { 0.0 })
            })
            .collect();
        out.extend_from_slice(&m);
        out.extend((0..q).map(|b| m[b + 1].map(|x| x * (b + 1) as f64)));
        out.extend(
            (0..q.saturating_sub(1)).map(|b| m[b + 2].map(|x| x * ((b + 2) * (b + 1)) as f64)),
        );
    }
    let kind = if affine {
        Kind::Affine
    } else if equal {
        Kind::Poly
    } else {
        Kind::Rational
    };
    (out, kind)
}

#[inline(always)]
fn madd(h: [f64; 4], x: f64, c: [f64; 4]) -> [f64; 4] {
    [
        h[0] * x + c[0],
        h[1] * x + c[1],
        h[2] * x + c[2],
        h[3] * x + c[3],
    ]
}

#[inline(always)]
fn scaled(h: [f64; 4], k: f64) -> [f64; 4] {
    [h[0] * k, h[1] * k, h[2] * k, h[3] * k]
}

/// `Σ c[i] x^i` for `i = 0..n` (Horner; `n ≥ 1`).
#[inline(always)]
fn poly(c: &[[f64; 4]], n: usize, x: f64) -> [f64; 4] {
    let mut h = c[n - 1];
    for i in (0..n - 1).rev() {
        h = madd(h, x, c[i]);
    }
    h
}

/// `Σ k(k-1)…(k-d+1) c[k] x^(k-d)` for `k = d..n` (the `d`-th derivative of
/// [`poly`]; `n > d`).
#[inline(always)]
fn poly_der(c: &[[f64; 4]], n: usize, d: usize, x: f64) -> [f64; 4] {
    let f = |k: usize| (k + 1 - d..=k).product::<usize>() as f64;
    let mut h = scaled(c[n - 1], f(n - 1));
    for k in (d..n - 1).rev() {
        h = madd(h, x, scaled(c[k], f(k)));
    }
    h
}

/// Homogeneous derivatives `[A, A_u, A_v, A_uu, A_uv, A_vv]` at `(Δu, Δv)`
/// from a piece's centred coefficients `m` (layout of [`NurbsSurface`]'s
/// `mono`). Inlined with constant degrees, the loops unroll completely.
#[inline(always)]
fn horner2(m: &[[f64; 4]], p: usize, q: usize, du: f64, dv: f64) -> [[f64; 4]; 6] {
    // Rows along v: r0 = Σ_j M[i][j] Δv^j and its first two v derivatives.
    let mut r0 = [[0.0; 4]; ORDER];
    let mut r1 = [[0.0; 4]; ORDER];
    let mut r2 = [[0.0; 4]; ORDER];
    for i in 0..=p {
        let row = &m[3 * q * i..3 * q * (i + 1)];
        r0[i] = poly(&row[..=q], q + 1, dv);
        r1[i] = poly(&row[q + 1..2 * q + 1], q, dv);
        if q >= 2 {
            r2[i] = poly(&row[2 * q + 1..3 * q], q - 1, dv);
        }
    }
    let zero = [0.0; 4];
    let a00 = poly(&r0, p + 1, du);
    let a10 = poly_der(&r0, p + 1, 1, du);
    let a20 = if p >= 2 {
        poly_der(&r0, p + 1, 2, du)
    } else {
        zero
    };
    let a01 = poly(&r1, p + 1, du);
    let a11 = poly_der(&r1, p + 1, 1, du);
    let a02 = if q >= 2 { poly(&r2, p + 1, du) } else { zero };
    [a00, a10, a01, a20, a11, a02]
}

/// [`horner2`] for any degrees (not inlined).
fn horner_any(m: &[[f64; 4]], p: usize, q: usize, du: f64, dv: f64) -> [[f64; 4]; 6] {
    horner2(m, p, q, du, dv)
}

/// Cartesian derivatives of a polynomial piece (weights 1: `a` holds them).
#[inline(always)]
fn polynomial(a: &[[f64; 4]; 6]) -> Derivs {
    let v3 = |x: &[f64; 4]| Vec3::new(x[0], x[1], x[2]);
    Derivs {
        s: v3(&a[0]),
        su: v3(&a[1]),
        sv: v3(&a[2]),
        suu: v3(&a[3]),
        suv: v3(&a[4]),
        svv: v3(&a[5]),
    }
}

/// Cartesian derivatives from homogeneous ones (`[A, A_u, A_v, A_uu, A_uv,
/// A_vv]`), by the quotient rule (*The NURBS Book* A4.4).
#[inline(always)]
fn rational(a: &[[f64; 4]; 6]) -> Derivs {
    let v3 = |x: &[f64; 4]| Vec3::new(x[0], x[1], x[2]);
    let w = a[0][3];
    let inv = 1.0 / w;
    let (wu, wv) = (a[1][3], a[2][3]);
    let (wuu, wuv, wvv) = (a[3][3], a[4][3], a[5][3]);
    let s = v3(&a[0]) * inv;
    let s_u = (v3(&a[1]) - s * wu) * inv;
    let s_v = (v3(&a[2]) - s * wv) * inv;
    let suu = (v3(&a[3]) - s_u * (2.0 * wu) - s * wuu) * inv;
    let suv = (v3(&a[4]) - s_u * wv - s_v * wu - s * wuv) * inv;
    let svv = (v3(&a[5]) - s_v * (2.0 * wv) - s * wvv) * inv;
    Derivs {
        s,
        su: s_u,
        sv: s_v,
        suu,
        suv,
        svv,
    }
}

#[cfg(test)]
mod extraction_tests {
    use super::*;
    use crate::basis::basis_ders;

    /// Reference evaluation straight from the original net with the Cox–de Boor
    /// basis (*The NURBS Book* A2.3 + A4.4), against which the Bézier pieces are checked.
    fn reference(s: &NurbsSurface, u: f64, v: f64) -> [[[f64; 4]; 3]; 3] {
        let su = find_span(s.nu, s.p, &s.ku, u);
        let sv = find_span(s.nv, s.q, &s.kv, v);
        let mut bu = [[0.0; ORDER]; 3];
        let mut bv = [[0.0; ORDER]; 3];
        basis_ders(su, u, s.p, &s.ku, &mut bu);
        basis_ders(sv, v, s.q, &s.kv, &mut bv);
        let mut a = [[[0.0; 4]; 3]; 3];
        for i in 0..=s.p {
            for j in 0..=s.q {
                let c = s.cw[(su - s.p + i) * s.nv + sv - s.q + j];
                for k in 0..3 {
                    for l in 0..3 - k {
                        for m in 0..4 {
                            a[k][l][m] += bu[k][i] * bv[l][j] * c[m];
                        }
                    }
                }
            }
        }
        a
    }

    /// How the test net is built.
    #[derive(Clone, Copy, PartialEq)]
    enum Net {
        /// Points on a plane at the Greville abscissae, unit weights: a linear
        /// parametrisation, so every piece must be found affine.
        Affine,
        /// A wavy net with unit weights (the polynomial pieces' path).
        Poly,
        /// The wavy net with uneven weights.
        Rational,
    }

    /// Knot insertion to full multiplicity and the centred polynomial form
    /// leave the surface unchanged: patches of degrees 1–5 (every pair the
    /// evaluator monomorphises, and others) with single, double and uneven
    /// interior knots, flat-affine, polynomial and rational, evaluate (point,
    /// first and second derivatives) like Cox–de Boor on the original net
    /// (*The NURBS Book* A2.3 + A4.4), to rounding (1e-12 relative).
    #[test]
    fn bezier_extraction_matches_cox_de_boor_on_multi_span_patch() {
        for (p, q) in [(1, 1), (1, 2), (2, 1), (2, 2), (3, 2), (2, 3), (5, 4)] {
            for net in [Net::Affine, Net::Poly, Net::Rational] {
                extraction_case(p, q, net);
            }
        }
    }

    fn extraction_case(p: usize, q: usize, net: Net) {
        let mut knots_u = vec![0.0; p + 1];
        knots_u.push(0.2);
        knots_u.extend(vec![0.5; p.min(2)]);
        knots_u.push(0.9);
        knots_u.extend(vec![1.0; p + 1]);
        let mut knots_v = vec![-1.0; q + 1];
        knots_v.push(0.3);
        knots_v.extend(vec![2.0; q + 1]);
        let (nu, nv) = (knots_u.len() - p - 1, knots_v.len() - q - 1);
        let greville =
            |k: &[f64], d: usize, i: usize| k[i + 1..=i + d].iter().sum::<f64>() / d as f64;
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                if net == Net::Affine {
                    let (a, b) = (greville(&knots_u, p, i), greville(&knots_v, q, j));
                    points.push(Vec3::new(
                        40.0 * a + 3.0 * b,
                        7.0 * b,
                        5.0 * a - 2.0 * b + 1.0,
                    ));
                } else {
                    let (x, y) = (i as f64 * 10.0, j as f64 * 7.0);
                    points.push(Vec3::new(x, y, (0.3 * x).sin() * 4.0 + 0.05 * x * y));
                }
                weights.push(if net == Net::Rational {
                    1.0 + 0.3 * ((i * 7 + j * 3) % 5) as f64 / 4.0
                } else {
                    1.0
                });
            }
        }
        let def = PatchDef {
            degree_u: p,
            degree_v: q,
            knots_u,
            knots_v,
            count_v: nv,
            points,
            weights,
        };
        let s = NurbsSurface::new(0, &def).unwrap();
        assert_eq!((s.bu.len(), s.bv.len()), (5, 3));
        let want = match net {
            Net::Affine => Kind::Affine,
            Net::Poly => Kind::Poly,
            Net::Rational => Kind::Rational,
        };
        assert!(s.pieces.iter().all(|c| c.kind == want), "{p}×{q}");
        for a in 0..=23 {
            for b in 0..=17 {
                let u = a as f64 / 23.0;
                let v = -1.0 + 3.0 * b as f64 / 17.0;
                let r = reference(&s, u, v);
                let w = r[0][0][3];
                let x = Vec3::new(r[0][0][0], r[0][0][1], r[0][0][2]) / w;
                let d = s.eval(u, v);
                let scale = 1.0 + x.norm();
                assert!((d.s - x).norm() < 1e-12 * scale, "{p}×{q} u={u} v={v}");
                // Homogeneous derivatives from the pieces, rebuilt from `d`.
                let (wu, wv) = (r[1][0][3], r[0][1][3]);
                let su = (Vec3::new(r[1][0][0], r[1][0][1], r[1][0][2]) - x * wu) / w;
                let sv = (Vec3::new(r[0][1][0], r[0][1][1], r[0][1][2]) - x * wv) / w;
                let suu = (Vec3::new(r[2][0][0], r[2][0][1], r[2][0][2])
                    - su * (2.0 * wu)
                    - x * r[2][0][3])
                    / w;
                let suv = (Vec3::new(r[1][1][0], r[1][1][1], r[1][1][2])
                    - su * wv
                    - sv * wu
                    - x * r[1][1][3])
                    / w;
                let svv = (Vec3::new(r[0][2][0], r[0][2][1], r[0][2][2])
                    - sv * (2.0 * wv)
                    - x * r[0][2][3])
                    / w;
                for (got, want) in [
                    (d.su, su),
                    (d.sv, sv),
                    (d.suu, suu),
                    (d.suv, suv),
                    (d.svv, svv),
                ] {
                    assert!(
                        (got - want).norm() < 1e-11 * (1.0 + want.norm()) * scale,
                        "{p}×{q} u={u} v={v}: {got} vs {want}"
                    );
                }
            }
        }
    }
}
