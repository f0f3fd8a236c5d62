//! The shape of a channel's cross-section (`[[output.profiles]]`): the
//! angles θ1 (web to wall) and θ2 (wall to flange) and the wall's radius of
//! curvature ρ, the measures of the NUMISHEET'93 2-D draw bending benchmark,
//! of the formed part (when the tools let go) and after springback.
//!
//! A profile is the row of nodes along a line of the initial blank. Its
//! points are read in the vertical plane of that line: `s` the horizontal
//! distance along the line's direction, `z` the height. The formed shape
//! sorts them into web (`s ≤ web_to`), flange (`s ≥ flange_from`) and wall
//! (between the two, and more than `shoulder_clear` from the web's and the
//! flange's mean heights: the shoulders' bends are left out); the same
//! nodes are measured after springback. Each segment's line is its total
//! least-squares fit, directed in the material's order (from the line's
//! start to its end):
//!
//! - θ1: the angle between the web, pointing back to the start, and the
//!   wall, pointing on (90° for a square corner);
//! - θ2: the angle between the wall, pointing back, and the flange,
//!   pointing on (90° for a square corner);
//! - ρ: the radius of the circle fitted to the wall's points (algebraic
//!   least squares); absent when the wall is straight (a radius beyond
//!   [`STRAIGHT_RADIUS`] times the wall's length).

use std::collections::BTreeMap;
use std::path::Path;

use fem_core::{Mesh, Vec3};
use serde::Serialize;

use crate::output::OutputError;
use crate::output::csv_text::CsvText;
use crate::plot::{Panel, Series, draw_panels};
use crate::scene::schema::ProfileLine;

/// A fitted radius beyond this many wall lengths counts as a straight wall.
pub const STRAIGHT_RADIUS: f64 = 1.0e3;

/// Where each point of a profile belongs in the formed shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Segment {
    /// The channel's bottom, under the punch.
    Web,
    /// A bend (punch or die shoulder): in no fit.
    Shoulder,
    /// The side wall.
    Wall,
    /// The flange, on the die face.
    Flange,
}

impl Segment {
    /// The name in `profiles/NAME.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Segment::Web => "web",
            Segment::Shoulder => "shoulder",
            Segment::Wall => "wall",
            Segment::Flange => "flange",
        }
    }
}

/// A profile's nodes, found once on the initial mesh.
#[derive(Debug, Clone)]
pub struct ProfileIndex {
    /// The scene's line.
    pub line: ProfileLine,
    /// Its nodes, in order along the line.
    pub nodes: Vec<usize>,
    /// The line's unit direction in the plan `[x, y]`.
    pub dir: [f64; 2],
}

/// The nodes of the initial mesh within half an element of `line`, in
/// order along it (an element's size: the square root of the mean area).
pub fn profile_index(mesh: &Mesh, line: &ProfileLine) -> ProfileIndex {
    let (dx, dy) = (line.to[0] - line.from[0], line.to[1] - line.from[1]);
    let len = dx.hypot(dy);
    let dir = [dx / len, dy / len];
    let area: f64 = mesh
        .quads
        .iter()
        .map(|q| {
            let p = q.map(|n| mesh.nodes[n as usize]);
            0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm()
        })
        .sum::<f64>()
        / mesh.quads.len().max(1) as f64;
    let half = 0.5 * area.sqrt() * (1.0 + 1e-6);
    let mut along: Vec<(usize, f64)> = mesh
        .nodes
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let (rx, ry) = (p.x - line.from[0], p.y - line.from[1]);
            let s = rx * dir[0] + ry * dir[1];
            let off = (rx * dir[1] - ry * dir[0]).abs();
            (off <= half && s >= -half && s <= len + half).then_some((i, s))
        })
        .collect();
    along.sort_by(|a, b| a.1.total_cmp(&b.1));
    ProfileIndex {
        line: line.clone(),
        nodes: along.into_iter().map(|(i, _)| i).collect(),
        dir,
    }
}

impl ProfileIndex {
    /// The profile's points `[s, z]` (mm) at the positions `x`.
    pub fn points(&self, x: &[Vec3]) -> Vec<[f64; 2]> {
        self.nodes
            .iter()
            .map(|&n| {
                let p = x[n];
                let s = (p.x - self.line.from[0]) * self.dir[0]
                    + (p.y - self.line.from[1]) * self.dir[1];
                [s, p.z]
            })
            .collect()
    }
}

/// θ1, θ2 and ρ of one shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShapeMeasures {
    /// Angle between web and wall (degrees).
    pub theta1_deg: f64,
    /// Angle between wall and flange (degrees).
    pub theta2_deg: f64,
    /// Radius of curvature of the wall (mm); absent for a straight wall
    /// (and from `summary.json`, where a null would read as a NaN).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_radius_mm: Option<f64>,
}

/// `summary.json`'s `profiles.NAME`.
#[derive(Debug, Clone, Serialize)]
pub struct ProfileSummary {
    /// Points in the web, the wall and the flange (the shoulders' points are in none).
    pub points: BTreeMap<&'static str, usize>,
    /// The shape when the tools let go (the end of the run without a springback step).
    pub formed: ShapeMeasures,
    /// The shape after springback (with a springback step).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub released: Option<ShapeMeasures>,
}

impl ShapeMeasures {
    fn radius_text(&self) -> String {
        self.wall_radius_mm
            .map_or_else(|| "straight".to_string(), |r| format!("{r:.0} mm"))
    }
}

impl ProfileSummary {
    /// One line: each measure formed, and after springback when there is one.
    pub fn line(&self) -> String {
        let f = &self.formed;
        match &self.released {
            Some(r) => format!(
                "theta1 {:.2} -> {:.2} deg, theta2 {:.2} -> {:.2} deg, wall radius {} -> {} (formed -> after springback)",
                f.theta1_deg,
                r.theta1_deg,
                f.theta2_deg,
                r.theta2_deg,
                f.radius_text(),
                r.radius_text()
            ),
            None => format!(
                "theta1 {:.2} deg, theta2 {:.2} deg, wall radius {} (formed)",
                f.theta1_deg,
                f.theta2_deg,
                f.radius_text()
            ),
        }
    }
}

/// `profiles/NAME.csv` (node, segment, `s` and `z` formed and after
/// springback, mm) and, with plots, `plots/profile_NAME.png`.
///
/// # Errors
/// A file that cannot be written.
pub fn write(out: &Path, measured: &[Measured], plots: bool) -> Result<(), OutputError> {
    for m in measured {
        let dir = out.join("profiles");
        std::fs::create_dir_all(&dir).map_err(|e| OutputError::io(&dir, e))?;
        let path = dir.join(format!("{}.csv", m.name));
        let mut csv = CsvText::new();
        let io = |e| OutputError::io(&path, e);
        csv.record([
            "node",
            "segment",
            "s_formed",
            "z_formed",
            "s_released",
            "z_released",
        ])
        .map_err(io)?;
        for (k, (&node, p)) in m.nodes.iter().zip(&m.formed).enumerate() {
            let seg = m.segments.as_ref().map_or("", |s| s[k].name());
            let r = m.released.as_ref().map(|r| r[k]);
            let num = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6e}"));
            csv.record([
                node.to_string(),
                seg.to_string(),
                format!("{:.6e}", p[0]),
                format!("{:.6e}", p[1]),
                num(r.map(|r| r[0])),
                num(r.map(|r| r[1])),
            ])
            .map_err(io)?;
        }
        csv.write_to(&path).map_err(io)?;
        if plots {
            plot(out, m)?;
        }
    }
    Ok(())
}

/// `plots/profile_NAME.png`: the profile formed and after springback.
fn plot(out: &Path, m: &Measured) -> Result<(), OutputError> {
    let tuples = |p: &[[f64; 2]]| p.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>();
    let mut series = vec![Series {
        label: "formed (tools closed)".into(),
        points: tuples(&m.formed),
    }];
    if let Some(r) = &m.released {
        series.push(Series {
            label: "after springback".into(),
            points: tuples(r),
        });
    }
    let panel = Panel {
        title: format!("profile {}", m.name),
        x_label: "s along the profile (mm)".into(),
        y_label: "z (mm)".into(),
        series,
    };
    let path = out.join("plots").join(format!("profile_{}.png", m.name));
    draw_panels(&path, &[panel], 900, 520).map_err(super::write::plot_err(&path))
}

/// Sort the formed points into segments.
///
/// # Errors
/// A segment with too few points to fit (two for a line, three for the
/// wall's circle), one line naming the profile's keys to change.
pub fn classify(p: &[[f64; 2]], line: &ProfileLine) -> Result<Vec<Segment>, String> {
    let mean_z = |keep: &dyn Fn(&[f64; 2]) -> bool| {
        let z: Vec<f64> = p.iter().filter(|q| keep(q)).map(|q| q[1]).collect();
        (z.len(), z.iter().sum::<f64>() / z.len().max(1) as f64)
    };
    let (n_web, z_web) = mean_z(&|q| q[0] <= line.web_to);
    let (n_flange, z_flange) = mean_z(&|q| q[0] >= line.flange_from);
    if n_web < 2 || n_flange < 2 {
        return Err(format!(
            "{} points with s <= web_to = {} mm and {} with s >= flange_from = {} mm in the formed part (2 each needed)",
            n_web, line.web_to, n_flange, line.flange_from
        ));
    }
    let lo = z_web.min(z_flange) + line.shoulder_clear;
    let hi = z_web.max(z_flange) - line.shoulder_clear;
    let seg: Vec<Segment> = p
        .iter()
        .map(|q| {
            if q[0] <= line.web_to {
                Segment::Web
            } else if q[0] >= line.flange_from {
                Segment::Flange
            } else if q[1] >= lo && q[1] <= hi {
                Segment::Wall
            } else {
                Segment::Shoulder
            }
        })
        .collect();
    let n_wall = seg.iter().filter(|s| **s == Segment::Wall).count();
    if n_wall < 3 {
        return Err(format!(
            "{n_wall} wall points between the web's height {z_web:.2} mm and the flange's {z_flange:.2} mm, shoulder_clear = {} mm from each (3 needed)",
            line.shoulder_clear
        ));
    }
    Ok(seg)
}

/// θ1, θ2 and ρ of the points `p` sorted into `seg`.
pub fn measure(p: &[[f64; 2]], seg: &[Segment]) -> ShapeMeasures {
    let pick = |s: Segment| -> Vec<[f64; 2]> {
        p.iter()
            .zip(seg)
            .filter(|(_, k)| **k == s)
            .map(|(q, _)| *q)
            .collect()
    };
    let (web, wall, flange) = (
        pick(Segment::Web),
        pick(Segment::Wall),
        pick(Segment::Flange),
    );
    let (dw, dv, df) = (fit_line(&web), fit_line(&wall), fit_line(&flange));
    ShapeMeasures {
        theta1_deg: angle_deg([-dw[0], -dw[1]], dv),
        theta2_deg: angle_deg([-dv[0], -dv[1]], df),
        wall_radius_mm: fit_radius(&wall),
    }
}

/// The angle between two vectors (degrees, 0 to 180).
fn angle_deg(a: [f64; 2], b: [f64; 2]) -> f64 {
    let cross = a[0] * b[1] - a[1] * b[0];
    let dot = a[0] * b[0] + a[1] * b[1];
    cross.abs().atan2(dot).to_degrees()
}

/// The unit direction of the total least-squares line through `p` (at
/// least two points), directed from the first point towards the last.
fn fit_line(p: &[[f64; 2]]) -> [f64; 2] {
    let n = p.len() as f64;
    let c = p
        .iter()
        .fold([0.0, 0.0], |a, q| [a[0] + q[0] / n, a[1] + q[1] / n]);
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for q in p {
        let (x, y) = (q[0] - c[0], q[1] - c[1]);
        sxx += x * x;
        sxy += x * y;
        syy += y * y;
    }
    // The principal axis of the scatter: angle ½ atan2(2 sxy, sxx − syy).
    let phi = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    let d = [phi.cos(), phi.sin()];
    let (first, last) = (p[0], p[p.len() - 1]);
    if d[0] * (last[0] - first[0]) + d[1] * (last[1] - first[1]) < 0.0 {
        [-d[0], -d[1]]
    } else {
        d
    }
}

/// The radius of the circle fitted to `p` (at least three points), `None`
/// when they lie on a line (a radius beyond [`STRAIGHT_RADIUS`] times their
/// extent).
///
/// In the frame of the points' fitted line (`u` along it, `v` across, from
/// their centroid) the circle is `A (u² + v²) + B u + D = v`: linear least
/// squares in `(A, B, D)`, well posed for a straight wall too (`A = 0`),
/// where the circle through `(u, v)` would not be.
fn fit_radius(p: &[[f64; 2]]) -> Option<f64> {
    let n = p.len() as f64;
    let c = p
        .iter()
        .fold([0.0, 0.0], |a, q| [a[0] + q[0] / n, a[1] + q[1] / n]);
    let d = fit_line(p);
    let local = |q: &[f64; 2]| {
        let (x, y) = (q[0] - c[0], q[1] - c[1]);
        (x * d[0] + y * d[1], y * d[0] - x * d[1])
    };
    let extent = p.iter().map(|q| local(q).0.abs()).fold(0.0, f64::max);
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = nalgebra::Vector3::<f64>::zeros();
    for q in p {
        let (u, v) = local(q);
        let row = nalgebra::Vector3::new(u * u + v * v, u, 1.0);
        m += row * row.transpose();
        r += row * v;
    }
    let sol = m.lu().solve(&r)?;
    let (a, b, dd) = (sol[0], sol[1], sol[2]);
    // Centre (−B/2A, 1/2A); radius² = (B² + 1)/(4A²) − D/A.
    let radius = ((b * b + 1.0) / (4.0 * a * a) - dd / a).sqrt();
    (radius.is_finite() && radius <= STRAIGHT_RADIUS * 2.0 * extent).then_some(radius)
}

/// One profile measured at the end of a run.
#[derive(Debug, Clone)]
pub struct Measured {
    /// The profile's name.
    pub name: String,
    /// Its nodes.
    pub nodes: Vec<usize>,
    /// The formed points' segments, or why they cannot be sorted.
    pub segments: Result<Vec<Segment>, String>,
    /// Points `[s, z]` when the tools let go (mm).
    pub formed: Vec<[f64; 2]>,
    /// Points after springback (mm).
    pub released: Option<Vec<[f64; 2]>>,
}

impl Measured {
    /// `summary.json`'s figures (`None` when the segments cannot be sorted).
    pub fn summary(&self) -> Option<ProfileSummary> {
        let seg = self.segments.as_ref().ok()?;
        let count = |s: Segment| seg.iter().filter(|k| **k == s).count();
        Some(ProfileSummary {
            points: [Segment::Web, Segment::Wall, Segment::Flange]
                .into_iter()
                .map(|s| (s.name(), count(s)))
                .collect(),
            formed: measure(&self.formed, seg),
            released: self.released.as_ref().map(|p| measure(p, seg)),
        })
    }
}

/// Every profile of `lines` on `mesh`: formed at `x_formed` (when the tools
/// let go, or the end of a run without springback), released at
/// `x_released` (after springback, rigid motion removed).
pub fn measure_all(
    mesh: &Mesh,
    lines: &[ProfileLine],
    x_formed: &[Vec3],
    x_released: Option<&[Vec3]>,
) -> Vec<Measured> {
    lines
        .iter()
        .map(|line| {
            let index = profile_index(mesh, line);
            let formed = index.points(x_formed);
            Measured {
                name: line.name.clone(),
                segments: classify(&formed, line),
                released: x_released.map(|x| index.points(x)),
                formed,
                nodes: index.nodes,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line() -> ProfileLine {
        ProfileLine {
            name: "X".into(),
            from: [0.0, 0.0],
            to: [100.0, 0.0],
            web_to: 20.0,
            flange_from: 40.0,
            shoulder_clear: 4.0,
        }
    }

    /// A U profile drawn by hand: web at z = −50 up to s = 25, a wall from
    /// (30, −45) to (30 + 40 tan δ, −5) leaning out by δ, a flange at z = 0
    /// rising by β from s = 45 on. θ1 = 90° + δ, θ2 = 90° + δ + β exactly.
    fn u_profile(delta: f64, beta: f64) -> Vec<[f64; 2]> {
        let mut p: Vec<[f64; 2]> = (0..=10).map(|i| [2.5 * f64::from(i), -50.0]).collect();
        p.push([29.0, -48.0]);
        for i in 0..=8 {
            let z = -45.0 + 5.0 * f64::from(i);
            p.push([30.0 + (z + 45.0) * delta.tan(), z]);
        }
        p.push([38.0, -1.0]);
        for i in 0..=10 {
            let r = 3.0 * f64::from(i);
            p.push([45.0 + r * beta.cos(), r * beta.sin()]);
        }
        p
    }

    #[test]
    fn straight_u_profile_gives_exact_angles_and_no_radius() {
        let (delta, beta) = (7.0_f64.to_radians(), 4.0_f64.to_radians());
        // A drooping flange closes θ2 instead: 90 + 7 − 4.
        let droop = u_profile(delta, -beta);
        let seg = classify(&droop, &line()).unwrap();
        assert!((measure(&droop, &seg).theta2_deg - 93.0).abs() < 1e-9);
        let p = u_profile(delta, beta);
        let seg = classify(&p, &line()).unwrap();
        assert_eq!(seg.iter().filter(|s| **s == Segment::Wall).count(), 9);
        let m = measure(&p, &seg);
        assert!((m.theta1_deg - 97.0).abs() < 1e-9, "{m:?}");
        assert!((m.theta2_deg - 101.0).abs() < 1e-9, "{m:?}");
        assert_eq!(m.wall_radius_mm, None);
    }

    /// A straight wall's absent radius leaves no null in `summary.json`
    /// (which the run would read as a NaN and refuse).
    #[test]
    fn straight_wall_writes_no_null() {
        let p = u_profile(0.0, 0.0);
        let m = measure(&p, &classify(&p, &line()).unwrap());
        assert_eq!(m.wall_radius_mm, None);
        let json = serde_json::to_string(&m).unwrap();
        assert!(
            !json.contains("null") && !json.contains("wall_radius"),
            "{json}"
        );
    }

    #[test]
    fn curled_wall_gives_its_circle_radius() {
        let mut p = u_profile(0.0, 0.0);
        // The wall on a circle of radius 150 mm bulging outwards.
        let centre = [30.0 - 150.0, -25.0];
        for q in p
            .iter_mut()
            .filter(|q| q[0] > 25.0 && q[0] < 40.0 && q[1] > -46.0)
        {
            let a = ((q[1] - centre[1]) / 150.0).asin();
            *q = [centre[0] + 150.0 * a.cos(), q[1]];
        }
        let seg = classify(&p, &line()).unwrap();
        let r = measure(&p, &seg).wall_radius_mm.expect("a curved wall");
        assert!((r - 150.0).abs() < 1e-6 * 150.0, "{r}");
    }

    #[test]
    fn too_few_wall_points_name_the_key() {
        let p = u_profile(0.0, 0.0);
        let mut l = line();
        l.shoulder_clear = 30.0;
        let e = classify(&p, &l).unwrap_err();
        assert!(e.contains("shoulder_clear = 30"), "{e}");
    }
}
