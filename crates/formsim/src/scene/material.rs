//! The blank's material axes for Hill'48 (`blank.material.r_values`): the
//! rolling direction is global x projected onto the blank, carried into the
//! shells' co-rotational frame as one angle from the elements' `e1` axis.
//!
//! `Hill48PlaneStress` holds one angle for the whole shell set (stresses live
//! in each element's co-rotational frame, which convects the axes with the
//! element). [`rolling_angle`] measures it on every element of the initial
//! mesh and refuses a blank whose elements disagree (modulo 180°, the
//! criterion's symmetry) by more than [`ANGLE_TOL`] rad: a flat blank
//! meshed with consistently numbered elements passes (the generated
//! rectangle does); a curved or unstructured blank would need a per-element
//! angle, which the shells do not carry.

use fem_core::Mesh;
use shell_elements::corotational_basis;

/// Largest difference (rad) between the elements' rolling angles.
pub const ANGLE_TOL: f64 = 1e-6;

/// Smallest length of global x projected onto an element's plane (of a
/// unit vector) for the rolling direction to be defined.
const MIN_PROJECTION: f64 = 1e-3;

/// Why the blank has no single rolling angle ([`rolling_angle`]).
#[derive(Debug, thiserror::Error)]
pub enum RollingAngleError {
    /// An element's plane is normal to global x.
    #[error(
        "element {element}: its plane is normal to global x, so the rolling direction (x projected onto the blank) is undefined"
    )]
    NormalToX {
        /// The element (0-based).
        element: usize,
    },
    /// An element's rolling angle differs from element 0's.
    #[error(
        "element {element}: the rolling direction is at {angle_deg:.6} deg from its e1 axis, element 0's at {first_deg:.6} deg; Hill'48 needs one angle for the whole blank (a flat blank with consistently numbered elements)"
    )]
    Disagree {
        /// The element (0-based).
        element: usize,
        /// Its angle from `e1` (degrees).
        angle_deg: f64,
        /// Element 0's angle (degrees).
        first_deg: f64,
    },
    /// The mesh has no elements.
    #[error("the blank has no elements")]
    NoElements,
}

/// Angle (rad) from the elements' co-rotational `e1` to global x projected
/// onto their plane, the same for every element of `mesh`.
///
/// # Errors
/// An empty mesh, an element whose plane is normal to x, or elements that
/// disagree; the message names the element and the angles in degrees.
pub fn rolling_angle(mesh: &Mesh) -> Result<f64, RollingAngleError> {
    let mut first: Option<f64> = None;
    for (e, q) in mesh.quads.iter().enumerate() {
        let x = q.map(|n| {
            let p = mesh.nodes[n as usize];
            [p.x, p.y, p.z]
        });
        let [e1, e2, _] = corotational_basis(&x);
        // Global x in the element's frame: (e1·x, e2·x).
        let (a, b) = (e1[0], e2[0]);
        if a.hypot(b) < MIN_PROJECTION {
            return Err(RollingAngleError::NormalToX { element: e });
        }
        let theta = b.atan2(a);
        match first {
            None => first = Some(theta),
            Some(t0) => {
                // Orthotropic axes: θ and θ + 180° are the same.
                let d = (theta - t0).rem_euclid(std::f64::consts::PI);
                if d.min(std::f64::consts::PI - d) > ANGLE_TOL {
                    return Err(RollingAngleError::Disagree {
                        element: e,
                        angle_deg: theta.to_degrees(),
                        first_deg: t0.to_degrees(),
                    });
                }
            }
        }
    }
    first.ok_or(RollingAngleError::NoElements)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fem_core::{Vec3, rectangle};

    /// The generated rectangle: RD along e1 (angle 0) for every element.
    #[test]
    fn a_rectangle_has_its_rolling_direction_along_e1() {
        let mesh = rectangle(75.0, 75.0, 10, 10).unwrap();
        assert!(rolling_angle(&mesh).unwrap().abs() < 1e-12);
    }

    /// Renumbering one element by a quarter turn turns its e1 by 90°: refused,
    /// naming the element; by a half turn (180°): accepted.
    #[test]
    fn elements_that_disagree_are_refused_by_name() {
        let mut mesh = rectangle(2.0, 1.0, 2, 1).unwrap();
        let q = mesh.quads[1];
        mesh.quads[1] = [q[2], q[3], q[0], q[1]];
        assert!(rolling_angle(&mesh).is_ok());
        mesh.quads[1] = [q[1], q[2], q[3], q[0]];
        let e = rolling_angle(&mesh).unwrap_err().to_string();
        assert!(e.starts_with("element 1:") && e.contains("90.0"), "{e}");
    }

    /// A blank in the y–z plane has no rolling direction along x.
    #[test]
    fn a_plane_normal_to_x_is_refused() {
        let mut mesh = rectangle(1.0, 1.0, 1, 1).unwrap();
        for p in &mut mesh.nodes {
            *p = Vec3::new(0.0, p.x, p.y);
        }
        let e = rolling_angle(&mesh).unwrap_err().to_string();
        assert!(e.contains("normal to global x"), "{e}");
    }

    use crate::scene::{build, load, resolved};

    fn scene(name: &str) -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.toml"))
    }

    /// `r_values` builds Hill'48 shells (Belytschko–Tsay or fully
    /// integrated); without it the cup builds J2 shells as before; the
    /// resolved settings show the key only when it is set.
    #[test]
    fn r_values_choose_hill_shells_and_show_in_the_settings() {
        let sets = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        for (name, over, want) in [
            ("square-cup", sets(&[]), "bt-j2"),
            ("square-cup-hill", sets(&[]), "bt-hill"),
            ("square-cup-al-hill", sets(&[]), "bt-hill"),
            (
                "square-cup-hill",
                sets(&["blank.element=fully-integrated"]),
                "fi-hill",
            ),
            (
                "square-cup",
                sets(&["blank.material.r_values=[1, 1, 1]"]),
                "bt-hill",
            ),
        ] {
            let loaded = load(&scene(name), &over).unwrap();
            let model = build(&loaded).unwrap();
            let got = match (model.shells.element, model.shells.material) {
                ("belytschko-tsay", "j2") => "bt-j2",
                ("fully-integrated", "j2") => "fi-j2",
                ("belytschko-tsay", "hill48") => "bt-hill",
                ("fully-integrated", "hill48") => "fi-hill",
                other => panic!("{other:?}"),
            };
            assert_eq!(got, want, "{name} {over:?}");
            let lines = resolved::dotted_lines(&loaded.scene).unwrap();
            let shown = lines
                .iter()
                .any(|l| l.starts_with("blank.material.r_values = ["));
            assert_eq!(shown, want != "bt-j2", "{name}: {lines:?}");
        }
    }

    /// Bad r-values name the key, the r-value, its value and its unit.
    #[test]
    fn bad_r_values_name_key_value_and_unit() {
        for (value, needles) in [
            (
                "[1.79, -1.0, 2.27]",
                ["blank.material.r_values[1]", "r45 = -1 (-)"],
            ),
            (
                "[0.0, 1.0, 1.0]",
                ["blank.material.r_values[0]", "r0 = 0 (-)"],
            ),
            (
                "[1.0, 1.0, nan]",
                ["blank.material.r_values[2]", "r90 = NaN (-)"],
            ),
            ("[1.0, 1.0]", ["blank.material", "r_values"]),
        ] {
            let set = vec![format!("blank.material.r_values={value}")];
            let e = load(&scene("square-cup"), &set).unwrap_err().to_string();
            for n in needles {
                assert!(e.contains(n), "{value}: {e}");
            }
        }
    }

    /// The rolling angle carries the axes into the shells' frame with the
    /// right sign: one Belytschko–Tsay element with Hill'48 (steel r-values,
    /// RD = global x), square and aligned with x or turned by 30° (so its
    /// e1 is at 30° and its rolling angle −30°), under the same homogeneous
    /// in-plane velocity gradient (stretch along x, contraction and shear)
    /// reaches the same stress in global axes, to 1e-9 of its size. With the
    /// angle's sign reversed the turned element's axes would be at 60° from
    /// x, and the stresses differ by percents (checked below).
    #[test]
    fn hill_shell_response_does_not_depend_on_the_elements_orientation() {
        use fem_core::{Effect, FieldAccess, Forces, NodalState, StepContext};
        use shell_elements::material::Hill48PlaneStress;
        use shell_elements::{BelytschkoTsay, Hardening, Section, ShellSet};
        let global_stress = |turn: f64, sign: f64| {
            let (s, c) = turn.sin_cos();
            let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
            let nodes: Vec<Vec3> = corners
                .iter()
                .map(|p| Vec3::new(c * p[0] - s * p[1], s * p[0] + c * p[1], 0.0))
                .collect();
            let mesh = Mesh {
                nodes: nodes.clone(),
                quads: vec![[0, 1, 2, 3]],
                ..rectangle(1.0, 1.0, 1, 1).unwrap()
            };
            let angle = rolling_angle(&mesh).unwrap();
            let hardening = Hardening::swift(565.32, 0.007117, 0.2589).unwrap();
            let mat = Hill48PlaneStress::new(206e3, 0.3, 7.85e-9, hardening, [1.79, 1.51, 2.27])
                .and_then(|m| m.with_rolling_angle(sign * angle))
                .unwrap();
            let section = Section::new(0.78).unwrap();
            let mut set = ShellSet::new(
                "one",
                &nodes,
                &mesh.quads,
                section,
                BelytschkoTsay::default(),
                mat,
            )
            .unwrap();
            let mut state = NodalState::at_rest(&nodes);
            for (v, p) in state.v.iter_mut().zip(&nodes) {
                *v = Vec3::new(p.x + 0.2 * p.y, -0.4 * p.y, 0.0);
            }
            let mut forces = Forces::zeros(nodes.len());
            let ctx = StepContext {
                time: 0.0,
                dt: 1e-4,
                step: 1,
                press: None,
            };
            for _ in 0..200 {
                forces.clear();
                set.add_forces(&ctx, &state, &mut forces, &mut FieldAccess::none())
                    .unwrap();
            }
            assert!(set.plastic_strain(0, 0, 2) > 0.005, "plastic");
            let x = nodes.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>();
            let [e1, e2, _] = corotational_basis(&[x[0], x[1], x[2], x[3]]);
            let sl = set.stress(0, 0, 2);
            // σ_global = R σ_local Rᵀ (in-plane 2×2), R's columns e1, e2.
            let t = [[sl[0], sl[2]], [sl[2], sl[1]]];
            let r = [[e1[0], e2[0]], [e1[1], e2[1]]];
            let g = |i: usize, j: usize| -> f64 {
                (0..2)
                    .map(|a| (0..2).map(|b| r[i][a] * t[a][b] * r[j][b]).sum::<f64>())
                    .sum()
            };
            [g(0, 0), g(1, 1), g(0, 1)]
        };
        let aligned = global_stress(0.0, 1.0);
        let turned = global_stress(30f64.to_radians(), 1.0);
        let size = aligned.iter().map(|c| c.abs()).fold(0.0, f64::max);
        for c in 0..3 {
            let miss = (aligned[c] - turned[c]).abs() / size;
            assert!(miss <= 1e-9, "{aligned:?} vs {turned:?}");
        }
        let wrong = global_stress(30f64.to_radians(), -1.0);
        let off = (0..3)
            .map(|c| (aligned[c] - wrong[c]).abs())
            .fold(0.0, f64::max)
            / size;
        assert!(off > 1e-3, "a reversed angle must show: {off:e}");
    }
}
