//! Rational tensor-product B-spline (NURBS) surfaces: validation and evaluation up to second derivatives.

// Numeric kernels index several arrays with one counter.
#![allow(clippy::needless_range_loop)]

use crate::basis::{MAX_DEGREE, ORDER, bernstein_ders_inv, find_span};
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
    /// Inverse widths `1 / (bu[i + 1] - bu[i])` of the pieces along u.
    iwu: Vec<f64>,
    /// Inverse widths of the pieces along v.
    iwv: Vec<f64>,
    /// Number of pieces along v.
    pv: usize,
    /// Bézier extraction of the net: the homogeneous control points of piece
    /// `(a, b)` (span `a` along u, `b` along v) are the `(p + 1)(q + 1)`
    /// consecutive entries from `(a * pv + b) * (p + 1) * (q + 1)`, u-major.
    /// Every evaluation uses the Bernstein basis of one piece.
    bez: Vec<[f64; 4]>,
    /// Per piece: all its weights are equal (a polynomial piece). Its entries
    /// in `bez` then hold the Cartesian points with weight 1 (the same surface),
    /// and evaluation skips the weight channel and the quotient rule.
    poly: Vec<bool>,
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
/// piece layout of [`NurbsSurface`]'s `bez`.
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
        let mut bez = extract(&cw, nu, nv, p, q, &def.knots_u, &def.knots_v);
        let block = (p + 1) * (q + 1);
        let poly: Vec<bool> = bez
            .chunks_exact_mut(block)
            .map(|piece| {
                let w0 = piece[0][3];
                let equal = piece
                    .iter()
                    .all(|c| (c[3] - w0).abs() <= 4.0 * f64::EPSILON * w0);
                if equal {
                    for c in piece.iter_mut() {
                        *c = [c[0] / c[3], c[1] / c[3], c[2] / c[3], 1.0];
                    }
                }
                equal
            })
            .collect();
        let s = Self {
            p,
            q,
            nu,
            nv,
            ku: def.knots_u.clone(),
            kv: def.knots_v.clone(),
            cw,
            pv: bv.len() - 1,
            iwu: bu.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect(),
            iwv: bv.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect(),
            bu,
            bv,
            bez,
            poly,
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

    /// Homogeneous derivatives on one Bézier piece for fixed degrees
    /// (monomorphised and unrolled; derivative orders above the degree, which
    /// vanish, are skipped).
    #[inline(always)]
    fn accumulate<const P: usize, const Q: usize, const C: usize>(
        &self,
        off: usize,
        bu: &[[f64; ORDER]; 3],
        bv: &[[f64; ORDER]; 3],
    ) -> [[[f64; 4]; 3]; 3] {
        let net = &self.bez[off..off + (P + 1) * (Q + 1)];
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for i in 0..=P {
            let row = &net[i * (Q + 1)..(i + 1) * (Q + 1)];
            let mut t = [[0.0f64; 4]; 3];
            for j in 0..=Q {
                let c = &row[j];
                for l in 0..3 {
                    if l <= Q {
                        let b = bv[l][j];
                        for m in 0..C {
                            t[l][m] += b * c[m];
                        }
                    }
                }
            }
            for k in 0..3 {
                if k <= P {
                    let bk = bu[k][i];
                    for l in 0..(3 - k) {
                        if l <= Q {
                            for m in 0..C {
                                a[k][l][m] += bk * t[l][m];
                            }
                        }
                    }
                }
            }
        }
        a
    }

    /// Homogeneous derivatives on one Bézier piece for any degrees.
    fn accumulate_any(
        &self,
        off: usize,
        bu: &[[f64; ORDER]; 3],
        bv: &[[f64; ORDER]; 3],
    ) -> [[[f64; 4]; 3]; 3] {
        let (p, q) = (self.p, self.q);
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for i in 0..=p {
            let row = off + i * (q + 1);
            let mut t = [[0.0f64; 4]; 3];
            for j in 0..=q {
                let c = &self.bez[row + j];
                for (l, tl) in t.iter_mut().enumerate() {
                    let b = bv[l][j];
                    for m in 0..4 {
                        tl[m] += b * c[m];
                    }
                }
            }
            for k in 0..3 {
                let bk = bu[k][i];
                for l in 0..(3 - k) {
                    for m in 0..4 {
                        a[k][l][m] += bk * t[l][m];
                    }
                }
            }
        }
        a
    }

    /// Point only (mm).
    pub fn point(&self, u: f64, v: f64) -> Vec3 {
        self.eval(u, v).s
    }

    /// Point and first and second partial derivatives at `(u, v)` (clamped to the domain).
    ///
    /// Evaluates the Bézier piece holding `(u, v)` (the knot span with
    /// `knots[s] <= t < knots[s + 1]`, the last one at the end of the domain)
    /// in its Bernstein basis.
    #[inline]
    pub fn eval(&self, u: f64, v: f64) -> Derivs {
        match (self.p, self.q) {
            (1, 1) => self.eval_pq::<1, 1>(u, v),
            (1, 2) => self.eval_pq::<1, 2>(u, v),
            (2, 1) => self.eval_pq::<2, 1>(u, v),
            (2, 2) => self.eval_pq::<2, 2>(u, v),
            _ => self.eval_any(u, v),
        }
    }

    /// The piece `(iu, iv)` holding the clamped `(u, v)`, with the clamped parameters.
    #[inline(always)]
    fn locate(&self, u: f64, v: f64) -> (usize, usize, f64, f64) {
        let (nbu, nbv) = (self.bu.len() - 1, self.bv.len() - 1);
        let u = u.clamp(self.bu[0], self.bu[nbu]);
        let v = v.clamp(self.bv[0], self.bv[nbv]);
        let iu = if nbu == 1 {
            0
        } else {
            self.bu[1..nbu].partition_point(|&k| k <= u)
        };
        let iv = if nbv == 1 {
            0
        } else {
            self.bv[1..nbv].partition_point(|&k| k <= v)
        };
        (iu, iv, u, v)
    }

    /// [`Self::eval`] for fixed degrees.
    #[inline(always)]
    fn eval_pq<const P: usize, const Q: usize>(&self, u: f64, v: f64) -> Derivs {
        let (iu, iv, u, v) = self.locate(u, v);
        let mut bu = [[0.0; ORDER]; 3];
        let mut bv = [[0.0; ORDER]; 3];
        bernstein_ders_inv(u, self.bu[iu], self.iwu[iu], P, &mut bu);
        bernstein_ders_inv(v, self.bv[iv], self.iwv[iv], Q, &mut bv);
        let piece = iu * self.pv + iv;
        let off = piece * (P + 1) * (Q + 1);
        if self.poly[piece] {
            polynomial(&self.accumulate::<P, Q, 3>(off, &bu, &bv))
        } else {
            rational(&self.accumulate::<P, Q, 4>(off, &bu, &bv))
        }
    }

    /// [`Self::eval`] for any degrees.
    fn eval_any(&self, u: f64, v: f64) -> Derivs {
        let (p, q) = (self.p, self.q);
        let (iu, iv, u, v) = self.locate(u, v);
        let mut bu = [[0.0; ORDER]; 3];
        let mut bv = [[0.0; ORDER]; 3];
        bernstein_ders_inv(u, self.bu[iu], self.iwu[iu], p, &mut bu);
        bernstein_ders_inv(v, self.bv[iv], self.iwv[iv], q, &mut bv);
        let off = (iu * self.pv + iv) * (p + 1) * (q + 1);
        rational(&self.accumulate_any(off, &bu, &bv))
    }
}

/// Cartesian derivatives of a polynomial piece (weights 1: `a` holds them).
#[inline(always)]
fn polynomial(a: &[[[f64; 4]; 3]; 3]) -> Derivs {
    let v3 = |x: &[f64; 4]| Vec3::new(x[0], x[1], x[2]);
    Derivs {
        s: v3(&a[0][0]),
        su: v3(&a[1][0]),
        sv: v3(&a[0][1]),
        suu: v3(&a[2][0]),
        suv: v3(&a[1][1]),
        svv: v3(&a[0][2]),
    }
}

/// Cartesian derivatives from homogeneous ones (`a[k][l]`: order `k` in u,
/// `l` in v), by the quotient rule (*The NURBS Book* A4.4).
#[inline(always)]
fn rational(a: &[[[f64; 4]; 3]; 3]) -> Derivs {
    let v3 = |x: &[f64; 4]| Vec3::new(x[0], x[1], x[2]);
    let w = a[0][0][3];
    let inv = 1.0 / w;
    let (wu, wv) = (a[1][0][3], a[0][1][3]);
    let (wuu, wuv, wvv) = (a[2][0][3], a[1][1][3], a[0][2][3]);
    let s = v3(&a[0][0]) * inv;
    let s_u = (v3(&a[1][0]) - s * wu) * inv;
    let s_v = (v3(&a[0][1]) - s * wv) * inv;
    let suu = (v3(&a[2][0]) - s_u * (2.0 * wu) - s * wuu) * inv;
    let suv = (v3(&a[1][1]) - s_u * wv - s_v * wu - s * wuv) * inv;
    let svv = (v3(&a[0][2]) - s_v * (2.0 * wv) - s * wvv) * inv;
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

    /// Knot insertion to full multiplicity leaves the surface unchanged: a
    /// cubic × quadratic with single, double and uneven interior knots, rational
    /// and with unit weights (the polynomial pieces' path), evaluates (point,
    /// first and second derivatives) like Cox–de Boor on the original net, to
    /// rounding (1e-12 relative).
    #[test]
    fn bezier_extraction_matches_cox_de_boor_on_multi_span_patch() {
        for rational in [true, false] {
            extraction_case(rational);
        }
    }

    fn extraction_case(rational: bool) {
        let (p, q) = (3, 2);
        let knots_u = vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.5, 0.9, 1.0, 1.0, 1.0, 1.0];
        let knots_v = vec![-1.0, -1.0, -1.0, 0.3, 2.0, 2.0, 2.0];
        let (nu, nv) = (knots_u.len() - p - 1, knots_v.len() - q - 1);
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                let (x, y) = (i as f64 * 10.0, j as f64 * 7.0);
                points.push(Vec3::new(x, y, (0.3 * x).sin() * 4.0 + 0.05 * x * y));
                weights.push(if rational {
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
        assert_eq!(s.poly.iter().all(|&b| b), !rational);
        for a in 0..=23 {
            for b in 0..=17 {
                let u = a as f64 / 23.0;
                let v = -1.0 + 3.0 * b as f64 / 17.0;
                let r = reference(&s, u, v);
                let w = r[0][0][3];
                let x = Vec3::new(r[0][0][0], r[0][0][1], r[0][0][2]) / w;
                let d = s.eval(u, v);
                let scale = 1.0 + x.norm();
                assert!((d.s - x).norm() < 1e-12 * scale, "u={u} v={v}");
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
                        "u={u} v={v}: {got} vs {want}"
                    );
                }
            }
        }
    }
}
