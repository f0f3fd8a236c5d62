//! The forming limit diagram on single elements driven along the classic
//! strain paths (uniaxial, plane-strain and equibiaxial stretching, a
//! drawn flange, pure compression). One 10 × 10 mm Belytschko–Tsay shell
//! of the NUMISHEET'93 steel (0.78 mm, Swift n = 0.2589) is stretched by
//! prescribed edge velocities through the explicit solver; after every step
//! its logarithmic membrane strains are placed on the scene's
//! Keeler–Brazier curve (`FLD0 = (23.3 + 14.13 t) · min(n, 0.21)/0.21 %`
//! = 34.3214 %, left branch at constant thickness strain, right branch of
//! slope 0.6 in engineering strain; Keeler and Brazier 1977, as given in the
//! AHSS Application Guidelines). Each path must pass through its zones in
//! order, and change zone between the two steps whose strains bracket the
//! analytic value (one step moves the strain by about 2e-4).

use formsim::formability::zones::{FldPoint, Zone};
use formsim::scene;
use std::path::Path;

/// Plane-strain limit of the scene's curve (engineering, -).
const FLD0: f64 = 0.343_214;

/// One element, `x1` pulled at `vx` and `y1` at `vy` (mm/s; `None`: free).
fn element_scene(vx: f64, vy: Option<f64>, end: f64) -> String {
    let y = vy.map_or(String::new(), |v| {
        format!(
            "[[boundary]]\nkind = \"prescribed\"\nset = \"y1\"\ndof = \"uy\"\nmotion = \"velocity\"\nvalue = {v:?}\n"
        )
    });
    format!(
        r#"[scene]
name = "fld-element"
regime = "dynamic"
units = {{ length = "mm", force = "N", stress = "MPa", mass = "tonne", time = "s" }}

[blank]
mesh = {{ kind = "rectangle", size = [10.0, 10.0], divisions = 1 }}
thickness = 0.78

[blank.material]
youngs_modulus = 206000.0
poissons_ratio = 0.30
density = 7.85e-9
hardening = {{ kind = "swift", k = 565.32, eps0 = 0.007117, n = 0.2589 }}

[[boundary]]
kind = "symmetry"
set = "x0"
axis = "x"

[[boundary]]
kind = "symmetry"
set = "y0"
axis = "y"

# A membrane path: the element stays in its plane (a compressed single
# shell would otherwise fold out of it).
[[boundary]]
kind = "fixed"
set = "x0"
dofs = ["uz", "rx", "ry"]

[[boundary]]
kind = "fixed"
set = "x1"
dofs = ["uz", "rx", "ry"]

[[boundary]]
kind = "prescribed"
set = "x1"
dof = "ux"
motion = "velocity"
value = {vx:?}

{y}
[solver]
end_time = {end:?}

[formability]
"#
    )
}

/// The element's true strains and its point on the diagram after every step.
fn drive(vx: f64, vy: Option<f64>, end: f64) -> Vec<((f64, f64), FldPoint)> {
    let text = element_scene(vx, vy, end);
    let loaded = scene::parse(&text, Path::new("fld-element.toml"), &[]).unwrap();
    let mut model = scene::build(&loaded).unwrap();
    let fld = model.formability.clone().expect("[formability] is set");
    let mut out = Vec::new();
    while model.solver.time() < end {
        model.solver.step_toward(end).unwrap();
        let s = model.shells().membrane_strain(0, model.solver.state());
        out.push(((s.major, s.minor), fld.point(s.major, s.minor)));
    }
    out
}

/// The zones in the order the path meets them, each with the step it starts.
fn sequence(path: &[((f64, f64), FldPoint)]) -> Vec<(Zone, usize)> {
    let mut seq: Vec<(Zone, usize)> = Vec::new();
    for (k, (_, p)) in path.iter().enumerate() {
        if seq.last().is_none_or(|(z, _)| *z != p.zone) {
            seq.push((p.zone, k));
        }
    }
    seq
}

/// The zones of a stretched sheet, in the order a path meets them.
const STRETCHED: [Zone; 4] = [
    Zone::InsufficientStretch,
    Zone::Safe,
    Zone::Marginal,
    Zone::Failure,
];

/// The zones of `seq`, without the steps.
fn zones_met(seq: &[(Zone, usize)]) -> Vec<Zone> {
    seq.iter().map(|s| s.0).collect()
}

/// The step where `zone` starts brackets the major true strain `eps1`: the
/// step before is below it, that step at or above.
fn brackets(path: &[((f64, f64), FldPoint)], seq: &[(Zone, usize)], zone: Zone, eps1: f64) {
    let k = seq
        .iter()
        .find(|(z, _)| *z == zone)
        .expect("zone reached")
        .1;
    let (before, at) = (path[k - 1].0.0, path[k].0.0);
    assert!(
        before < eps1 && eps1 <= at,
        "{zone:?} starts at major {at} (step before {before}); analytic {eps1}"
    );
    assert!(at - before < 1e-3, "steps of {}", at - before);
}

/// Plane strain (`ε2 = 0`): stretched at 0.02, marginal at
/// `ln(1 + FLD0 − 0.10)` = 0.2177, failure at `ln(1 + FLD0)` = 0.2951.
#[test]
fn plane_strain_path_fails_at_fld0() {
    let path = drive(1000.0, Some(0.0), 4.0e-3);
    let seq = sequence(&path);
    assert_eq!(zones_met(&seq), STRETCHED);
    assert!(path.iter().all(|((_, e2), _)| e2.abs() < 1e-9));
    brackets(&path, &seq, Zone::Safe, 0.02);
    brackets(&path, &seq, Zone::Marginal, (1.0 + FLD0 - 0.10_f64).ln());
    brackets(&path, &seq, Zone::Failure, (1.0 + FLD0).ln());
}

/// Equibiaxial stretching (`ε1 = ε2`): failure on the right branch,
/// `e = FLD0 / (1 − 0.6)` = 0.858 (true 0.6195).
#[test]
fn equibiaxial_path_fails_on_the_right_branch() {
    let path = drive(1000.0, Some(1000.0), 9.5e-3);
    let seq = sequence(&path);
    assert_eq!(zones_met(&seq), STRETCHED);
    assert!(path.iter().all(|((e1, e2), _)| (e1 - e2).abs() < 1e-9));
    brackets(
        &path,
        &seq,
        Zone::Marginal,
        (1.0 + (FLD0 - 0.10) / 0.4_f64).ln(),
    );
    brackets(&path, &seq, Zone::Failure, (1.0 + FLD0 / 0.4).ln());
}

/// Uniaxial tension (the width free): J2 plasticity draws the path to
/// `ε2 ≈ −ε1/2`, and failure comes on the left branch where the thickness
/// strain reaches the plane-strain one, `ε1 + ε2 = ln(1 + FLD0)`: at
/// `ε1 ≈ 2 ln(1 + FLD0)` = 0.590.
#[test]
fn uniaxial_path_fails_at_the_plane_strain_thickness_strain() {
    let path = drive(1000.0, None, 9.0e-3);
    let seq = sequence(&path);
    assert_eq!(zones_met(&seq), STRETCHED);
    let k = seq.iter().find(|s| s.0 == Zone::Failure).unwrap().1;
    let ((e1, e2), p) = path[k];
    let ((b1, b2), _) = path[k - 1];
    let eps0 = (1.0 + FLD0).ln();
    assert!(
        b1 + b2 < eps0 && eps0 <= e1 + e2,
        "thickness strain {} → {}",
        -(b1 + b2),
        -(e1 + e2)
    );
    assert!((e2 / e1 + 0.5).abs() < 0.01, "path ratio {}", e2 / e1);
    assert!(
        (e1 - 2.0 * eps0).abs() < 0.02 * 2.0 * eps0,
        "failure at {e1}"
    );
    assert!(p.margin <= 0.0);
}

/// A drawn flange (pulled along x, pushed in as much along y): the sheet
/// thickens between pure shear and uniaxial compression, `compression`,
/// and never comes near the curve.
#[test]
fn drawing_path_is_compression() {
    let path = drive(1000.0, Some(-1000.0), 3.0e-3);
    let seq = sequence(&path);
    assert_eq!(
        zones_met(&seq),
        [Zone::InsufficientStretch, Zone::Compression]
    );
    // Compression starts where the minor strain reaches −0.02.
    let k = seq[1].1;
    assert!(path[k - 1].0.1 > -0.02 && path[k].0.1 <= -0.02);
    // The limit rises faster than the major strain on the left: the margin
    // stays above three marginal bands all the way.
    assert!(path.iter().all(|(_, p)| p.margin > 0.3));
}

/// Compressed along y with x held: beyond uniaxial compression
/// (`ε1 < −ε2/2`), `wrinkling_tendency`, from a minor strain of −0.02.
#[test]
fn pure_compression_path_tends_to_wrinkle() {
    let path = drive(0.0, Some(-1000.0), 2.0e-3);
    let seq = sequence(&path);
    assert_eq!(
        zones_met(&seq),
        [Zone::InsufficientStretch, Zone::WrinklingTendency]
    );
    let k = seq[1].1;
    assert!(path[k - 1].0.1 > -0.02 && path[k].0.1 <= -0.02);
}
