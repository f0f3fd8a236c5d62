//! Rational tensor-product B-spline (NURBS) surfaces: validation and evaluation up to second derivatives.

// Numeric kernels index several arrays with one counter.
#![allow(clippy::needless_range_loop)]

use crate::basis::{MAX_DEGREE, ORDER, basis_ders, bernstein_ders, find_span};
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
        let s = Self {
            p: def.degree_u,
            q: def.degree_v,
            nu,
            nv,
            ku: def.knots_u.clone(),
            kv: def.knots_v.clone(),
            cw,
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

    /// Homogeneous derivatives for fixed degrees (monomorphised, unrolled).
    #[inline(always)]
    fn accumulate<const P: usize, const Q: usize>(
        &self,
        su: usize,
        sv: usize,
        bu: &[[f64; ORDER]; 3],
        bv: &[[f64; ORDER]; 3],
    ) -> [[[f64; 4]; 3]; 3] {
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for i in 0..=P {
            let row = (su - P + i) * self.nv + sv - Q;
            let mut t = [[0.0f64; 4]; 3];
            for j in 0..=Q {
                let c = &self.cw[row + j];
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

    /// Homogeneous derivatives for any degrees.
    fn accumulate_any(
        &self,
        su: usize,
        sv: usize,
        bu: &[[f64; ORDER]; 3],
        bv: &[[f64; ORDER]; 3],
    ) -> [[[f64; 4]; 3]; 3] {
        let (p, q) = (self.p, self.q);
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for i in 0..=p {
            let row = (su - p + i) * self.nv + sv - q;
            let mut t = [[0.0f64; 4]; 3];
            for j in 0..=q {
                let c = &self.cw[row + j];
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
    #[inline]
    pub fn eval(&self, u: f64, v: f64) -> Derivs {
        let (p, q) = (self.p, self.q);
        let (du, dv) = self.domain();
        let u = u.clamp(du[0], du[1]);
        let v = v.clamp(dv[0], dv[1]);
        let su = find_span(self.nu, p, &self.ku, u);
        let sv = find_span(self.nv, q, &self.kv, v);
        let mut bu = [[0.0; ORDER]; 3];
        let mut bv = [[0.0; ORDER]; 3];
        if self.nu == p + 1 {
            bernstein_ders(u, du[0], du[1], p, &mut bu);
        } else {
            basis_ders(su, u, p, &self.ku, &mut bu);
        }
        if self.nv == q + 1 {
            bernstein_ders(v, dv[0], dv[1], q, &mut bv);
        } else {
            basis_ders(sv, v, q, &self.kv, &mut bv);
        }
        // a[k][l]: homogeneous derivative of order k in u and l in v.
        let a = match (p, q) {
            (1, 1) => self.accumulate::<1, 1>(su, sv, &bu, &bv),
            (1, 2) => self.accumulate::<1, 2>(su, sv, &bu, &bv),
            (2, 1) => self.accumulate::<2, 1>(su, sv, &bu, &bv),
            (2, 2) => self.accumulate::<2, 2>(su, sv, &bu, &bv),
            _ => self.accumulate_any(su, sv, &bu, &bv),
        };
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
}
