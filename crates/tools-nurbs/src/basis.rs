//! Basis functions and their first two derivatives on stack buffers: B-spline (Cox–de Boor) and the Bernstein basis of one Bézier piece.
//!
//! The recurrences follow Piegl & Tiller, *The NURBS Book* (2nd ed.), algorithms
//! A2.1 (span) and A2.3 (derivatives), rewritten here for fixed-size arrays so
//! that evaluation never allocates.

/// Largest supported degree in either direction.
pub const MAX_DEGREE: usize = 5;
/// `MAX_DEGREE + 1`: the number of non-zero basis functions on a span.
pub const ORDER: usize = MAX_DEGREE + 1;

/// Index `s` of the knot span with `knots[s] <= t < knots[s + 1]` (the last
/// non-empty span for `t` at the end of the domain). `count` is the number of
/// control points, `p` the degree; `t` is clamped into the domain.
#[inline]
pub fn find_span(count: usize, p: usize, knots: &[f64], t: f64) -> usize {
    if count == p + 1 {
        return p;
    }
    if t >= knots[count] {
        return count - 1;
    }
    if t <= knots[p] {
        return p;
    }
    let (mut lo, mut hi) = (p, count);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if t < knots[mid] {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

/// Basis functions `N_{span-p+j}` (`ders[0][j]`) and their first and second
/// derivatives (`ders[1][j]`, `ders[2][j]`) at `t`, `j = 0..=p`.
#[inline]
pub fn basis_ders(span: usize, t: f64, p: usize, knots: &[f64], ders: &mut [[f64; ORDER]; 3]) {
    let mut ndu = [[0.0; ORDER]; ORDER];
    let mut left = [0.0; ORDER];
    let mut right = [0.0; ORDER];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
        ders[1][j] = 0.0;
        ders[2][j] = 0.0;
    }
    let n = p.min(2);
    let mut a = [[0.0; ORDER]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=n {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1: usize = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2: usize = if r as isize - 1 <= pk as isize {
                k - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut fac = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(n + 1).skip(1) {
        for v in row.iter_mut().take(p + 1) {
            *v *= fac;
        }
        fac *= (p - k) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bernstein polynomials of degree 2 on [0, 1] and their derivatives (closed form).
    #[test]
    fn quadratic_bezier_basis_matches_bernstein() {
        let knots = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
        let t = 0.3;
        let mut d = [[0.0; ORDER]; 3];
        basis_ders(find_span(3, 2, &knots, t), t, 2, &knots, &mut d);
        let b = [(1.0 - t) * (1.0 - t), 2.0 * t * (1.0 - t), t * t];
        let db = [-2.0 * (1.0 - t), 2.0 - 4.0 * t, 2.0 * t];
        let ddb = [2.0, -4.0, 2.0];
        for j in 0..3 {
            assert!((d[0][j] - b[j]).abs() < 1e-15);
            assert!((d[1][j] - db[j]).abs() < 1e-14);
            assert!((d[2][j] - ddb[j]).abs() < 1e-13);
        }
    }

    /// Partition of unity and derivative sums on a multi-span cubic.
    #[test]
    fn cubic_basis_partition_of_unity() {
        let knots = [0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        for t in [0.0, 0.1, 0.3, 0.45, 0.5, 0.77, 1.0] {
            let s = find_span(7, 3, &knots, t);
            assert!(knots[s] <= t && (t < knots[s + 1] || s == 6));
            let mut d = [[0.0; ORDER]; 3];
            basis_ders(s, t, 3, &knots, &mut d);
            let sums: Vec<f64> = (0..3).map(|k| d[k][..4].iter().sum()).collect();
            assert!(
                (sums[0] - 1.0).abs() < 1e-14 && sums[1].abs() < 1e-12 && sums[2].abs() < 1e-10
            );
        }
    }
}

/// Bernstein basis of degree `p` on `[a, b]` with first and second
/// derivatives with respect to `t` (the B-spline basis of a single clamped
/// span), written into `ders` like [`basis_ders`].
#[inline]
pub fn bernstein_ders(t: f64, a: f64, b: f64, p: usize, ders: &mut [[f64; ORDER]; 3]) {
    bernstein_ders_inv(t, a, 1.0 / (b - a), p, ders);
}

/// [`bernstein_ders`] on `[a, a + 1/inv]`, with the inverse width `inv` given
/// (precomputed per knot span, so evaluation does not divide).
#[inline(always)]
pub fn bernstein_ders_inv(t: f64, a: f64, inv: f64, p: usize, ders: &mut [[f64; ORDER]; 3]) {
    let s = (t - a) * inv;
    let r = 1.0 - s;
    match p {
        1 => {
            ders[0][0] = r;
            ders[0][1] = s;
            ders[1][0] = -inv;
            ders[1][1] = inv;
            ders[2][0] = 0.0;
            ders[2][1] = 0.0;
        }
        2 => {
            let i2 = inv * inv;
            ders[0][0] = r * r;
            ders[0][1] = 2.0 * s * r;
            ders[0][2] = s * s;
            ders[1][0] = -2.0 * r * inv;
            ders[1][1] = (2.0 - 4.0 * s) * inv;
            ders[1][2] = 2.0 * s * inv;
            ders[2][0] = 2.0 * i2;
            ders[2][1] = -4.0 * i2;
            ders[2][2] = 2.0 * i2;
        }
        _ => {
            // Rows of the Bernstein triangle: tri[d][i] = B_i^d(s).
            let mut tri = [[0.0; ORDER]; ORDER];
            tri[0][0] = 1.0;
            for d in 1..=p {
                tri[d][0] = r * tri[d - 1][0];
                for i in 1..d {
                    tri[d][i] = r * tri[d - 1][i] + s * tri[d - 1][i - 1];
                }
                tri[d][d] = s * tri[d - 1][d - 1];
            }
            let at = |d: usize, i: isize| -> f64 {
                if i < 0 || i as usize > d {
                    0.0
                } else {
                    tri[d][i as usize]
                }
            };
            let pf = p as f64;
            for i in 0..=p {
                let ii = i as isize;
                ders[0][i] = tri[p][i];
                ders[1][i] = pf * (at(p - 1, ii - 1) - at(p - 1, ii)) * inv;
                ders[2][i] = pf
                    * (pf - 1.0)
                    * (at(p - 2, ii - 2) - 2.0 * at(p - 2, ii - 1) + at(p - 2, ii))
                    * inv
                    * inv;
            }
        }
    }
}

#[cfg(test)]
mod bernstein_tests {
    use super::*;

    /// The Bernstein fast path equals Cox–de Boor on a single clamped span (degrees 1–5).
    #[test]
    fn bernstein_fast_path_matches_cox_de_boor() {
        for p in 1..=MAX_DEGREE {
            let mut knots = vec![-1.0; p + 1];
            knots.extend(vec![2.0; p + 1]);
            for t in [-1.0, -0.3, 0.5, 1.7, 2.0] {
                let mut a = [[0.0; ORDER]; 3];
                let mut b = [[0.0; ORDER]; 3];
                basis_ders(find_span(p + 1, p, &knots, t), t, p, &knots, &mut a);
                bernstein_ders(t, -1.0, 2.0, p, &mut b);
                for k in 0..3 {
                    for j in 0..=p {
                        assert!((a[k][j] - b[k][j]).abs() < 1e-12, "p={p} t={t} k={k} j={j}");
                    }
                }
            }
        }
    }
}
