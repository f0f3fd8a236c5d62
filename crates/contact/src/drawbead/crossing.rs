//! Where a straight piece of a drawbead crosses one quad of the blank: the
//! segment, projected on the quad's mean plane, clipped against the quad's
//! four edges (Cyrus–Beck clipping; the quad is taken as convex).

use plugins_api::Vec3;

/// The part of a segment `a → b` over one quad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Clip {
    /// Parameters `0 <= t0 < t1 <= 1` of the part inside the quad.
    pub t0: f64,
    /// See `t0`.
    pub t1: f64,
    /// Unit normal of the quad's mean plane, `(x3 − x1) × (x4 − x2)`.
    pub normal: Vec3,
    /// Unit in-plane direction across the segment, `normal × (b − a)`.
    pub across: Vec3,
    /// Centroid of the quad's nodes (mm).
    pub centroid: Vec3,
    /// Signed distance of the quad's mid-plane from the crossing's
    /// midpoint on the segment, along `normal` (mm).
    pub offset: f64,
}

/// Clip `a → b` (mm) against the quad `x` (its nodes, in order): `None` when
/// the projected segment misses the quad, the quad is degenerate, or the
/// crossing lies farther than `reach` (mm) from the quad's mean plane.
pub(crate) fn clip(a: &Vec3, b: &Vec3, x: &[Vec3; 4], reach: f64) -> Option<Clip> {
    let centroid = (x[0] + x[1] + x[2] + x[3]) * 0.25;
    let normal = (x[2] - x[0]).cross(&(x[3] - x[1])).try_normalize(0.0)?;
    let in_plane = |p: &Vec3| p - normal * (p - centroid).dot(&normal);
    let (pa, pb) = (in_plane(a), in_plane(b));
    let d = pb - pa;
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for k in 0..4 {
        let p = in_plane(&x[k]);
        let q = in_plane(&x[(k + 1) % 4]);
        // Points inward for nodes in counter-clockwise order about `normal`.
        let inward = normal.cross(&(q - p));
        let num = (pa - p).dot(&inward);
        let den = d.dot(&inward);
        let edge = (q - p).norm_squared();
        if den.abs() <= 1e-9 * d.norm() * edge.sqrt() {
            // Parallel to the edge. On it (within round-off), the segment
            // belongs to one of the two quads that share the edge: the one
            // whose inward normal is positive along its largest component.
            if num < -1e-9 * edge || (num.abs() <= 1e-9 * edge && !positive(&inward)) {
                return None;
            }
            continue;
        }
        let t = -num / den;
        if den > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 >= t1 {
            return None;
        }
    }
    let mid = a + (b - a) * (0.5 * (t0 + t1));
    let offset = (centroid - mid).dot(&normal);
    if offset.abs() > reach {
        return None;
    }
    let across = normal.cross(&d).try_normalize(0.0)?;
    Some(Clip {
        t0,
        t1,
        normal,
        across,
        centroid,
        offset,
    })
}

/// Whether the largest component of `v` (in magnitude) is positive.
fn positive(v: &Vec3) -> bool {
    v[v.iamax()] > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_square(z: f64) -> [Vec3; 4] {
        [
            Vec3::new(0.0, 0.0, z),
            Vec3::new(1.0, 0.0, z),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(0.0, 1.0, z),
        ]
    }

    /// A line across the unit square at x = 0.25 crosses it over length 1,
    /// whatever its ends and its height above the square (within reach).
    #[test]
    fn a_line_across_a_square_crosses_it_over_its_width() {
        let a = Vec3::new(0.25, -2.0, 0.4);
        let b = Vec3::new(0.25, 3.0, 0.4);
        let c = clip(&a, &b, &unit_square(0.0), 0.5).unwrap();
        let length = (c.t1 - c.t0) * (b - a).norm();
        assert!((length - 1.0).abs() < 1e-12, "{length}");
        assert!((c.across.x.abs() - 1.0).abs() < 1e-12);
        assert!(clip(&a, &b, &unit_square(0.0), 0.3).is_none());
    }

    /// A line along the edge two squares share crosses one of them only.
    #[test]
    fn a_line_on_a_shared_edge_belongs_to_one_quad() {
        let left = unit_square(0.0);
        let right = left.map(|p| p + Vec3::new(1.0, 0.0, 0.0));
        let (a, b) = (Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 2.0, 0.0));
        let n = [left, right]
            .iter()
            .filter(|q| clip(&a, &b, q, 1.0).is_some())
            .count();
        assert_eq!(n, 1);
    }

    /// A line beside the square, or ending before it, does not cross it.
    #[test]
    fn a_line_beside_a_square_misses_it() {
        let sq = unit_square(0.0);
        let beside = clip(
            &Vec3::new(1.5, -1.0, 0.0),
            &Vec3::new(1.5, 2.0, 0.0),
            &sq,
            1.0,
        );
        assert!(beside.is_none());
        let short = clip(
            &Vec3::new(0.5, -2.0, 0.0),
            &Vec3::new(0.5, -0.1, 0.0),
            &sq,
            1.0,
        );
        assert!(short.is_none());
        let half = clip(
            &Vec3::new(0.5, -2.0, 0.0),
            &Vec3::new(0.5, 0.5, 0.0),
            &sq,
            1.0,
        )
        .unwrap();
        assert!(((half.t1 - half.t0) * 2.5 - 0.5).abs() < 1e-12);
    }
}
