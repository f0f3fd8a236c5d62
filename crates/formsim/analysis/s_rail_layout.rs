//! The S-rail scene's layout in plan view (docs/img/s-rail-sections.png): the
//! initial blank, the rail's centre line, the punch walls, the swept flange's
//! outer edges, the die face's apron, and the sections and draw-in points of `[output]`, all read
//! from the scene file, drawn with formsim's plotting.
//!
//! ```sh
//! cargo run --release -p formsim --example s_rail_layout -- scenes/s-rail.toml docs/img/s-rail-sections.png
//! ```

use formsim::plot::{Panel, Series, draw_panels};
use formsim::scene::schema::MeshSpec;
use std::path::Path;
use tools_nurbs::builders::s_rail::{SRailParams, apron_rectangles, centre_line, die_face_inner};
use tools_nurbs::builders::sweep::Spine;

/// Points of the plan curve at offset `rho` (mm, left of travel) from the centre line.
fn offset_curve(spine: &[Spine], rho: f64) -> Vec<(f64, f64)> {
    let mut pts = Vec::new();
    for s in spine {
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            pts.push(match *s {
                Spine::Line { p, dir, len, out } => (
                    p[0] + dir[0] * len * t + out[0] * rho,
                    p[1] + dir[1] * len * t + out[1] * rho,
                ),
                Spine::Arc {
                    c,
                    r0,
                    a0,
                    a1,
                    sigma,
                } => {
                    // sigma = -1: the centre lies on the left (a left turn),
                    // so an offset to the left moves towards it.
                    let a = a0 + (a1 - a0) * t;
                    let r = r0 + sigma * rho;
                    (c[0] + r * a.cos(), c[1] + r * a.sin())
                }
            });
        }
    }
    pts
}

/// The S-rail keys of the scene's punch table.
fn rail_params(tools: &toml::Table) -> Result<SRailParams, String> {
    let mut t = tools
        .get("punch")
        .and_then(|v| v.as_table())
        .ok_or("the scene has no [tools.punch] table")?
        .clone();
    for key in ["kind", "origin", "facing"] {
        t.remove(key);
    }
    toml::Value::Table(t)
        .try_into()
        .map_err(|e| format!("tools.punch: {e}"))
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene_path, out] = args.as_slice() else {
        return Err("usage: s_rail_layout SCENE.toml OUT.png".into());
    };
    let loaded = formsim::scene::load(Path::new(scene_path), &[]).map_err(|e| e.to_string())?;
    let s = &loaded.scene;
    let p = rail_params(&s.tools)?;
    let spine = centre_line(&p);
    let MeshSpec::Rectangle { size, origin, .. } = s.blank.mesh else {
        return Err("the blank is not a rectangle".into());
    };
    let (x0, y0, x1, y1) = (
        origin[0],
        origin[1],
        origin[0] + size[0],
        origin[1] + size[1],
    );
    let mut series = vec![
        Series {
            label: format!("blank {} x {} mm", size[0], size[1]),
            points: vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
        },
        Series {
            label: "rail centre line".into(),
            points: offset_curve(&spine, 0.0),
        },
    ];
    let w = 0.5 * p.punch_width;
    // Each band as one closed outline: along the left offset, back along the right.
    for (label, rho) in [
        (format!("punch walls (±{w} mm)"), w),
        (
            format!("swept flange edge (±{} mm)", p.flange_width),
            p.flange_width,
        ),
    ] {
        let mut points = offset_curve(&spine, rho);
        points.extend(offset_curve(&spine, -rho).into_iter().rev());
        points.push(points[0]);
        series.push(Series { label, points });
    }
    for (k, (x, y)) in apron_rectangles(&p, die_face_inner(&p))
        .into_iter()
        .enumerate()
    {
        series.push(Series {
            label: format!(
                "die-face apron, {} ({} mm beyond the flange)",
                ["upper", "lower"][k],
                p.apron
            ),
            points: vec![
                (x[0], y[0]),
                (x[1], y[0]),
                (x[1], y[1]),
                (x[0], y[1]),
                (x[0], y[0]),
            ],
        });
    }
    for sec in &s.output.sections {
        series.push(Series {
            label: format!("section {} (from {:?} to {:?})", sec.name, sec.from, sec.to),
            points: vec![(sec.from[0], sec.from[1]), (sec.to[0], sec.to[1])],
        });
    }
    for d in &s.output.draw_in {
        let n = d.inward[0].hypot(d.inward[1]);
        let (ux, uy) = (8.0 * d.inward[0] / n, 8.0 * d.inward[1] / n);
        series.push(Series {
            label: format!("draw-in {}", d.name),
            points: vec![(d.at[0], d.at[1]), (d.at[0] + ux, d.at[1] + uy)],
        });
    }
    let panel = Panel {
        title: format!(
            "{}: initial blank, sections and draw-in points (plan view)",
            s.scene.name
        ),
        x_label: "x (mm)".into(),
        y_label: "y (mm)".into(),
        series,
    };
    draw_panels(Path::new(out), &[panel], 1300, 800).map_err(|e| e.to_string())
}
