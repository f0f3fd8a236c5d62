//! Curved regions of a tool: patches that are exactly circular cylinders or
//! tori, on which the closest point has a closed form (see
//! [`crate::ToolSurface::curved_region`]).
//!
//! Both shapes are tubes of radius `radius` about a spine: a straight line
//! (cylinder) or a circle of radius `spine` (torus). The closest point of the
//! whole tube to a point `x` is found by going to the spine point `c` nearest
//! to `x` (radially off the axis line, or onto the spine circle in `x`'s
//! meridian half-plane) and from there `radius` along `x − c`. Every point
//! `y` of the tube lies at distance `radius` from the spine (for the torus
//! this needs the tube not to cross the axis, which the tool checks), so
//! `|x − y| ≥ |x − c| − radius` outside the tube and
//! `|x − y| ≥ radius − |x − c|` inside it: the foot is the unique closest
//! point of the tube, hence of any patch of it that contains the foot,
//! whichever side of the surface `x` lies on.

use crate::Vec3;

/// Which tube a [`CurvedRegion`] is, and the part of it the patch covers
/// along the second direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CurvedShape {
    /// A circular cylinder about the axis line through the region's origin;
    /// the foot is inside when its axial coordinate `(foot − origin)·axis`
    /// lies strictly within `along` (mm).
    Cylinder {
        /// Axial range `[lo, hi]` of the patch, less the margin (mm).
        along: [f64; 2],
    },
    /// A torus: the tube about the circle of radius `spine` centred at the
    /// region's origin, in the plane normal to the axis. The foot's tube
    /// direction `t` (unit, from the spine point to the foot) is inside when
    /// `t · (tube_mid[0] e + tube_mid[1] axis) > tube_cos`, `e` the unit
    /// direction of the foot's meridian half-plane.
    Torus {
        /// Spine circle radius (mm, ≥ 0).
        spine: f64,
        /// Middle of the patch's tube angles in the meridian plane, as
        /// components along `e` and the axis (unit).
        tube_mid: [f64; 2],
        /// Cosine of the patch's tube half-angle less the margin.
        tube_cos: f64,
    },
}

/// A patch of a tool that is a circular cylinder or a torus, in the tool's
/// local frame, with the part of it where its closed-form closest point is
/// that of the patch (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvedRegion {
    /// A point of the axis: the torus centre (local frame, mm).
    pub origin: Vec3,
    /// Unit axis direction.
    pub axis: Vec3,
    /// Tube radius (mm).
    pub radius: f64,
    /// `+1` when the blank side is outside the tube (a convex tool, like a
    /// punch nose or a die shoulder), `−1` when it is inside.
    pub side: f64,
    /// Unit direction normal to the axis in the middle of the patch's
    /// angles about the axis.
    pub mid: Vec3,
    /// Cosine of the patch's half-angle about the axis less the margin: the
    /// foot is inside when its direction `e` off the axis has `e·mid` above it.
    pub cos_half: f64,
    /// The tube and its second range.
    pub shape: CurvedShape,
}

/// A query point must lie at least this fraction of the tube radius from
/// the spine (so at most three quarters of the radius deep on the concave
/// side), and off the axis by half the spine radius, for the closed form to
/// answer; nearer, the directions it divides by lose digits.
pub const CURVED_MIN_FRACTION: f64 = 0.25;

impl CurvedRegion {
    /// The answer for the point `x_local` (tool's local frame) when its
    /// closed-form foot lies in the region: its signed distance (mm,
    /// positive on the blank side) and the unit normal towards the blank
    /// side (local frame); `None` outside the region or too near the spine
    /// or the axis ([`CURVED_MIN_FRACTION`]).
    #[inline]
    pub fn project_local(&self, x_local: &Vec3) -> Option<(f64, Vec3)> {
        let w = x_local - self.origin;
        let z = w.dot(&self.axis);
        let radial = w - self.axis * z;
        let rho = radial.norm();
        match self.shape {
            CurvedShape::Cylinder { along } => {
                let inside = rho > CURVED_MIN_FRACTION * self.radius
                    && z > along[0]
                    && z < along[1]
                    && radial.dot(&self.mid) > self.cos_half * rho;
                if !inside {
                    return None;
                }
                let t = radial / rho;
                Some((self.side * (rho - self.radius), t * self.side))
            }
            CurvedShape::Torus {
                spine,
                tube_mid,
                tube_cos,
            } => {
                if !(rho > 0.5 * spine && rho > 0.0 && radial.dot(&self.mid) > self.cos_half * rho)
                {
                    return None;
                }
                let e = radial / rho;
                // From the spine point `origin + spine e` to x, in the
                // meridian plane spanned by e and the axis.
                let (qe, qz) = (rho - spine, z);
                let q = (qe * qe + qz * qz).sqrt();
                if !(q > CURVED_MIN_FRACTION * self.radius
                    && qe * tube_mid[0] + qz * tube_mid[1] > tube_cos * q)
                {
                    return None;
                }
                let t = (e * qe + self.axis * qz) / q;
                Some((self.side * (q - self.radius), t * self.side))
            }
        }
    }
}

/// A region of a tool around a projection's answer on which the closest
/// point has a closed form: a disc of a plane or a part of a cylinder or
/// torus (see [`crate::ToolSurface::region`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ToolRegion {
    /// A disc of a planar patch.
    Flat(crate::FlatRegion),
    /// A patch that is a cylinder or a torus.
    Curved(CurvedRegion),
}

impl ToolRegion {
    /// The signed distance (mm) and the unit normal (local frame) of the
    /// closest point to `x_local` when the region answers it, else `None`.
    #[inline]
    pub fn project_local(&self, x_local: &Vec3) -> Option<(f64, Vec3)> {
        match self {
            ToolRegion::Flat(r) => r.project_local(x_local).map(|(d, _)| (d, r.normal)),
            ToolRegion::Curved(r) => r.project_local(x_local),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quarter of a cylinder of radius 5 about the x axis (angles about
    /// it from +y to +z), x in [0, 10], the blank outside.
    fn quarter_cylinder() -> CurvedRegion {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        CurvedRegion {
            origin: Vec3::zeros(),
            axis: Vec3::x(),
            radius: 5.0,
            side: 1.0,
            mid: Vec3::new(0.0, s, s),
            cos_half: s,
            shape: CurvedShape::Cylinder { along: [0.0, 10.0] },
        }
    }

    #[test]
    fn cylinder_answers_inside_its_angles_and_length_only() {
        let r = quarter_cylinder();
        let h = 3f64.sqrt();
        let (d, n) = r.project_local(&Vec3::new(3.0, 3.0, 3.0 * h)).unwrap();
        assert!((d - 1.0).abs() < 1e-14 && (n - Vec3::new(0.0, 0.5, 0.5 * h)).norm() < 1e-15);
        let (d, n) = r.project_local(&Vec3::new(3.0, 3.0, 3.0)).unwrap();
        assert!((d - (18f64.sqrt() - 5.0)).abs() < 1e-14);
        assert!((n - Vec3::new(0.0, 1.0, 1.0).normalize()).norm() < 1e-15);
        // Beyond the angles (below +y), beyond the length, near the axis.
        assert!(r.project_local(&Vec3::new(3.0, 6.0, -0.1)).is_none());
        assert!(r.project_local(&Vec3::new(10.5, 3.0, 3.0)).is_none());
        assert!(r.project_local(&Vec3::new(3.0, 0.5, 0.5)).is_none());
    }

    #[test]
    fn torus_answers_inside_its_tube_angles_only() {
        // Spine radius 10 about z, tube radius 2, the tube's upper outer
        // quarter (tube angles 0 to 90°), spine angles 0 to 90°.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let r = CurvedRegion {
            origin: Vec3::zeros(),
            axis: Vec3::z(),
            radius: 2.0,
            side: 1.0,
            mid: Vec3::new(s, s, 0.0),
            cos_half: s,
            shape: CurvedShape::Torus {
                spine: 10.0,
                tube_mid: [s, s],
                tube_cos: s,
            },
        };
        // 5 mm from the spine at tube angle atan(3/4): 3 mm out.
        let x = Vec3::new(14.0 * s, 14.0 * s, 3.0);
        let (d, n) = r.project_local(&x).unwrap();
        assert!((d - 3.0).abs() < 1e-14, "{d}");
        assert!((n - Vec3::new(0.8 * s, 0.8 * s, 0.6)).norm() < 1e-15);
        // Below the spine plane: tube angle negative, outside the patch.
        assert!(
            r.project_local(&Vec3::new(13.0 * s, 13.0 * s, -0.5))
                .is_none()
        );
        // Inside the tube: a negative distance with the blank outside.
        let (d, _) = r
            .project_local(&Vec3::new(10.5 * s, 10.5 * s, 1.0))
            .unwrap();
        assert!((d - (1.25f64.sqrt() - 2.0)).abs() < 1e-14, "{d}");
    }
}
