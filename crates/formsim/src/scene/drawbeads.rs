//! `[[drawbeads]]`: drawbeads as equivalent line forces on a tool
//! (docs/drawbeads.md): the scene's entries, their checks and the
//! [`contact::DrawbeadSpec`]s they build.

use serde::{Deserialize, Serialize};

use super::validate::number;
use super::{LoadedScene, SceneError};

/// Default slip across a bead at which its restraint reaches `F_t` (mm).
pub const DEFAULT_ELASTIC_SLIP: f64 = 0.05;
/// Default length of the bins that carry a bead's state (mm).
pub const DEFAULT_SPACING: f64 = 0.5;

/// One `[[drawbeads]]` entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DrawbeadEntry {
    /// Name in reports and `summary.json` (`beads`).
    pub name: String,
    /// The tool the bead is fixed to (a `[tools.NAME]`).
    pub tool: String,
    /// The polyline in the tool's frame at its initial pose (mm), at least two points.
    pub points: Vec<[f64; 3]>,
    /// Restraining force per unit length `F_t` (N/mm): one number, or one per point.
    pub restraining_force: PerPoint,
    /// Normal (clamping) force per unit length `F_n` (N/mm): one number, or
    /// one per point; default 0.
    #[serde(default)]
    pub normal_force: PerPoint,
    /// Slip across the bead at which the restraint reaches `F_t` (mm); default 0.05.
    #[serde(default = "default_elastic_slip")]
    pub elastic_slip: f64,
    /// Length of the bins along the bead that carry its state (mm); default 0.5.
    #[serde(default = "default_spacing")]
    pub spacing: f64,
}

fn default_elastic_slip() -> f64 {
    DEFAULT_ELASTIC_SLIP
}

fn default_spacing() -> f64 {
    DEFAULT_SPACING
}

/// A force per unit length along a bead: constant, or one value per point.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum PerPoint {
    /// The same everywhere (N/mm).
    Constant(f64),
    /// At each point, linear in between (N/mm).
    Points(Vec<f64>),
}

impl Default for PerPoint {
    fn default() -> Self {
        PerPoint::Constant(0.0)
    }
}

impl PerPoint {
    /// `50` or `[50, 80, 50]`.
    fn describe(&self) -> String {
        match self {
            PerPoint::Constant(v) => format!("{v}"),
            PerPoint::Points(v) => format!("{v:?}"),
        }
    }

    /// The values at `n` points.
    fn at_points(&self, n: usize) -> Vec<f64> {
        match self {
            PerPoint::Constant(v) => vec![*v; n],
            PerPoint::Points(v) => v.clone(),
        }
    }
}

/// Check every `[[drawbeads]]` entry: a plain unique name, a tool of the
/// scene, at least two distinct finite points, forces finite and `>= 0`
/// (per point: one per point), slip and spacing finite and `> 0`.
///
/// # Errors
/// The first bad key, with its value and unit.
pub fn validate(loaded: &LoadedScene) -> Result<(), SceneError> {
    let s = &loaded.scene;
    for (i, b) in s.drawbeads.iter().enumerate() {
        let key = |k: &str| format!("drawbeads[{i}].{k}");
        let err = |k: &str, m: String| Err(loaded.key_error(&key(k), m));
        if !super::validate::is_plain_name(&b.name) {
            return err(
                "name",
                format!("\"{}\": must be letters, digits, `-`, `_` or `.`", b.name),
            );
        }
        if s.drawbeads[..i].iter().any(|o| o.name == b.name) {
            return err(
                "name",
                format!("\"{}\": two drawbeads of that name", b.name),
            );
        }
        if !s.tools.contains_key(&b.tool) {
            return err(
                "tool",
                format!("\"{}\": no [tools.{}] in the scene", b.tool, b.tool),
            );
        }
        let n = b.points.len();
        if n < 2 {
            return err("points", format!("{n} points: a drawbead needs at least 2"));
        }
        for (j, p) in b.points.iter().enumerate() {
            if let Some(c) = p.iter().find(|c| !c.is_finite()) {
                return err(
                    &format!("points[{j}]"),
                    format!("{} mm: must be finite", number(*c)),
                );
            }
            if j > 0 && p == &b.points[j - 1] {
                return err(
                    &format!("points[{j}]"),
                    format!("{p:?} mm: repeats the point before it"),
                );
            }
        }
        forces(loaded, &key("restraining_force"), &b.restraining_force, n)?;
        forces(loaded, &key("normal_force"), &b.normal_force, n)?;
        for (k, v) in [("elastic_slip", b.elastic_slip), ("spacing", b.spacing)] {
            if !(v.is_finite() && v > 0.0) {
                return err(k, format!("{} mm: must be finite and > 0", number(v)));
            }
        }
    }
    Ok(())
}

/// A force per unit length given for a bead of `n` points.
fn forces(loaded: &LoadedScene, key: &str, f: &PerPoint, n: usize) -> Result<(), SceneError> {
    if let PerPoint::Points(v) = f
        && v.len() != n
    {
        return Err(loaded.key_error(
            key,
            format!(
                "{} values for {n} points: give one number, or one per point",
                v.len()
            ),
        ));
    }
    for v in f.at_points(n) {
        if !(v.is_finite() && v >= 0.0) {
            return Err(
                loaded.key_error(key, format!("{} N/mm: must be finite and >= 0", number(v)))
            );
        }
    }
    Ok(())
}

/// One line per bead for `scene check`: name, tool, points, length and forces.
pub fn describe(scene: &super::Scene) -> Vec<String> {
    scene
        .drawbeads
        .iter()
        .map(|b| {
            let length: f64 = b
                .points
                .windows(2)
                .map(|w| (0..3).map(|d| (w[1][d] - w[0][d]).powi(2)).sum::<f64>().sqrt())
                .sum();
            format!(
                "{} on {}: {} points, {length:.1} mm, F_t = {} N/mm, F_n = {} N/mm, elastic slip {} mm, bins {} mm",
                b.name,
                b.tool,
                b.points.len(),
                b.restraining_force.describe(),
                b.normal_force.describe(),
                b.elastic_slip,
                b.spacing
            )
        })
        .collect()
}

/// The beads of a validated scene for contact (tool `i` is `tool_names[i]`).
pub fn specs(loaded: &LoadedScene, tool_names: &[String]) -> Vec<contact::DrawbeadSpec> {
    loaded
        .scene
        .drawbeads
        .iter()
        .map(|b| {
            let n = b.points.len();
            contact::DrawbeadSpec {
                name: b.name.clone(),
                tool: tool_names
                    .iter()
                    .position(|t| *t == b.tool)
                    .expect("validated: the tool exists"),
                points: b
                    .points
                    .iter()
                    .map(|p| plugins_api::Vec3::new(p[0], p[1], p[2]))
                    .collect(),
                restraining: b.restraining_force.at_points(n),
                normal: b.normal_force.at_points(n),
                elastic_slip: b.elastic_slip,
                spacing: b.spacing,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scenes/strip-draw.toml` with a bead entry of `keys` (TOML lines).
    fn strip_with(keys: &str) -> Result<LoadedScene, SceneError> {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/strip-draw.toml");
        let text = std::fs::read_to_string(&path).unwrap() + "\n[[drawbeads]]\n" + keys;
        super::super::parse(&text, &path, &[])
    }

    const GOOD: &str = "name = \"b\"\ntool = \"holder\"\npoints = [[0.0, -8.0, 1.0], [0.0, 8.0, 1.0]]\nrestraining_force = 20.0\n";

    /// A good bead loads, with its defaults, and is described for `scene check`.
    #[test]
    fn a_good_bead_loads_with_its_defaults() {
        let loaded = strip_with(GOOD).unwrap();
        let b = &loaded.scene.drawbeads[0];
        assert_eq!((b.elastic_slip, b.spacing), (0.05, 0.5));
        let lines = describe(&loaded.scene);
        assert_eq!(
            lines,
            [
                "b on holder: 2 points, 16.0 mm, F_t = 20 N/mm, F_n = 0 N/mm, elastic slip 0.05 mm, bins 0.5 mm"
            ]
        );
    }

    /// Each bad value is one line naming the key, the value and the unit.
    #[test]
    fn bad_bead_values_name_the_key_the_value_and_the_unit() {
        let cases = [
            (
                GOOD.replace("\"holder\"", "\"press\""),
                "drawbeads[0].tool: \"press\": no [tools.press]",
            ),
            (
                GOOD.replace("[[0.0, -8.0, 1.0], [0.0, 8.0, 1.0]]", "[[0.0, -8.0, 1.0]]"),
                "drawbeads[0].points: 1 points: a drawbead needs at least 2",
            ),
            (
                GOOD.replace("[0.0, 8.0, 1.0]]", "[0.0, -8.0, 1.0]]"),
                "drawbeads[0].points[1]: [0.0, -8.0, 1.0] mm: repeats the point before it",
            ),
            (
                GOOD.replace("20.0", "-1.0"),
                "drawbeads[0].restraining_force: -1 N/mm: must be finite and >= 0",
            ),
            (
                GOOD.replace("20.0", "nan"),
                "drawbeads[0].restraining_force: NaN N/mm: must be finite and >= 0",
            ),
            (
                GOOD.replace("20.0", "[20.0, 10.0, 5.0]"),
                "drawbeads[0].restraining_force: 3 values for 2 points",
            ),
            (
                GOOD.to_string() + "normal_force = [1.0, inf]\n",
                "drawbeads[0].normal_force: inf N/mm: must be finite and >= 0",
            ),
            (
                GOOD.to_string() + "elastic_slip = 0.0\n",
                "drawbeads[0].elastic_slip: 0 mm: must be finite and > 0",
            ),
            (
                GOOD.to_string() + "spacing = -2.0\n",
                "drawbeads[0].spacing: -2 mm: must be finite and > 0",
            ),
            (
                GOOD.replace("\"b\"", "\"a b\""),
                "drawbeads[0].name: \"a b\"",
            ),
        ];
        for (keys, expected) in cases {
            let e = strip_with(&keys).expect_err(expected).to_string();
            assert!(e.contains(expected), "{e}\nexpected: {expected}");
            assert_eq!(e.lines().count(), 1, "{e}");
        }
    }
}
