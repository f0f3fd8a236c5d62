//! Plane, cylinder (capstan), sphere zone and torus as exact NURBS tools.
//!
//! Orientation: the plane's normal is its `facing`; cylinder, sphere zone and
//! torus have outward normals (the blank lies outside, as on a capstan).

use super::sweep::{Material, Part, Piece, Spine, rectangle, sweep};
use super::{Placement, assemble, positive, require};
use crate::error::NurbsError;
use crate::nurbs_tool::NurbsTool;
use plugins_api::Vec3;
use std::f64::consts::FRAC_PI_2;

/// A flat rectangle `length × width` (x × y) centred on the origin, normal = facing.
pub fn plane(
    name: &str,
    length: f64,
    width: f64,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    let a = 0.5 * positive(name, "length", length)?;
    let b = 0.5 * positive(name, "width", width)?;
    assemble(name, &[rectangle([-a, a], [-b, b], 0.0, true)], place)
}

/// Parts of a cylinder of `radius` about the y axis, `-length/2 ≤ y ≤ length/2`,
/// covering the angles `[start, end]` (rad, measured from +x towards +z) in
/// pieces of at most 90°. Outward normal.
pub fn cylinder_parts(radius: f64, length: f64, start: f64, end: f64) -> Vec<Part> {
    let n = ((end - start) / FRAC_PI_2 - 1e-12).ceil().max(1.0) as usize;
    let step = (end - start) / n as f64;
    (0..n)
        .map(|k| {
            // Profile in (ρ, z) := (z_global, x_global) plane swept along y.
            let a0 = start + k as f64 * step;
            let arc = Piece::Arc {
                c: [0.0, 0.0],
                r: radius,
                a0,
                a1: a0 + step,
            };
            sweep(
                &arc,
                Material::Left,
                &Spine::Line {
                    p: [0.0, -0.5 * length],
                    dir: [0.0, 1.0],
                    len: length,
                    out: [1.0, 0.0],
                },
            )
            // sweep() puts (ρ, z) into (x, z): an arc about the origin in
            // (x, z) swept along y is the cylinder; the material lies on the
            // left of the counter-clockwise arc (inside), so the normal is outward.
        })
        .collect()
}

/// A cylinder (capstan) of `radius` about the y axis (see [`cylinder_parts`]).
pub fn cylinder(
    name: &str,
    radius: f64,
    length: f64,
    start_deg: f64,
    end_deg: f64,
    place: &Placement,
) -> Result<NurbsTool, NurbsError> {
    positive(name, "radius", radius)?;
    positive(name, "length", length)?;
    require(
        end_deg > start_deg && end_deg - start_deg <= 360.0,
        name,
        "end_deg",
        end_deg,
        format!("must lie in (start_deg, start_deg + 360] with start_deg = {start_deg}"),
    )?;
    let parts = cylinder_parts(radius, length, start_deg.to_radians(), end_deg.to_radians());
    assemble(name, &parts, place)
}

/// A sphere zone about `centre`: latitudes `[-lat, lat]` (rad, `lat ≤ 45°`),
/// longitudes `[0, 90°]`, outward normal (no poles: NURBS patches here must be regular).
pub fn sphere_zone(
    name: &str,
    centre: Vec3,
    radius: f64,
    lat: f64,
) -> Result<NurbsTool, NurbsError> {
    let arc = Piece::Arc {
        c: [0.0, 0.0],
        r: radius,
        a0: -lat,
        a1: lat,
    };
    let spine = Spine::Arc {
        c: [0.0, 0.0],
        r0: 0.0,
        a0: 0.0,
        a1: FRAC_PI_2,
        sigma: 1.0,
    };
    let part = sweep(&arc, Material::Left, &spine);
    let place = Placement {
        origin: centre,
        ..Placement::default()
    };
    assemble(name, &[part], &place)
}

/// A full torus about the z axis through `centre` (major radius `major`,
/// minor `minor < major`), 16 biquadratic patches, outward normal.
pub fn torus(name: &str, centre: Vec3, major: f64, minor: f64) -> Result<NurbsTool, NurbsError> {
    require(
        minor < major,
        name,
        "minor",
        minor,
        format!("must be smaller than major = {major} mm"),
    )?;
    let mut parts = Vec::new();
    for i in 0..4 {
        let a0 = i as f64 * FRAC_PI_2;
        let arc = Piece::Arc {
            c: [major, 0.0],
            r: minor,
            a0,
            a1: a0 + FRAC_PI_2,
        };
        for j in 0..4 {
            let b0 = j as f64 * FRAC_PI_2;
            let spine = Spine::Arc {
                c: [0.0, 0.0],
                r0: 0.0,
                a0: b0,
                a1: b0 + FRAC_PI_2,
                sigma: 1.0,
            };
            // Counter-clockwise profile about the tube centre: material on the left.
            parts.push(sweep(&arc, Material::Left, &spine));
        }
    }
    let place = Placement {
        origin: centre,
        ..Placement::default()
    };
    assemble(name, &parts, &place)
}
