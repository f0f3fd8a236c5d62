//! Drawbeads on the strip draw (docs/drawbeads.md): a straight bead on the
//! holder across the 10 mm wide strip of `scenes/strip-draw.toml`.

#[allow(dead_code)]
mod common;

use common::{root, run_loaded};
use formsim::run::RunResult;
use formsim::scene;

/// Width of the strip of `scenes/strip-draw.toml` (mm).
const WIDTH: f64 = 10.0;

/// The strip draw with `beads` (TOML `[[drawbeads]]` tables) appended, and `sets`.
fn strip_with(beads: &str, sets: &[&str]) -> (tempfile::TempDir, RunResult) {
    let path = root().join("scenes/strip-draw.toml");
    let text = std::fs::read_to_string(&path).unwrap() + beads;
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    run_loaded(&scene::parse(&text, &path, &sets).unwrap())
}

/// A straight bead on the holder's face (z = 1) across the strip at `x`,
/// longer than the strip is wide, with `F_t` and `F_n` (N/mm).
fn bead_at(x: f64, f_t: f64, f_n: f64) -> String {
    format!(
        "\n[[drawbeads]]\nname = \"bead\"\ntool = \"holder\"\npoints = [[{x}, -8.0, 1.0], [{x}, 8.0, 1.0]]\n\
         restraining_force = {f_t}\nnormal_force = {f_n}\n"
    )
}

/// The mean draw force of a run from `output.strip.average_from` on (N).
fn draw_force(r: &RunResult) -> f64 {
    r.summary.figures("strip").expect("strip result").value
}

/// Strip drawn through a bead under the holder: the steady draw force is
/// the holder's friction (the same scene without the bead, `2 μ F` = 300 N)
/// plus `F_t w` = 20 N/mm × 10 mm = 200 N, within 1 % (the equivalent
/// drawbead model's definition: the bead restrains with `F_t` per unit
/// length of bead over the sheet; docs/drawbeads.md). The bead's summary
/// gives the same force, its engaged length is the strip's width, and its
/// dissipation is what the bead's force did over the slip.
#[test]
fn strip_through_a_bead_needs_f_t_w_on_top_of_the_holder_friction() {
    let (_d, plain) = strip_with("", &[]);
    let holder = draw_force(&plain);
    let f_t = 20.0;
    let (_d, beaded) = strip_with(&bead_at(0.0, f_t, 0.0), &[]);
    let expected = holder + f_t * WIDTH;
    let measured = draw_force(&beaded);
    assert!(
        (measured / expected - 1.0).abs() < 0.01,
        "draw force {measured} N with the bead vs holder {holder} N + F_t w {} N",
        f_t * WIDTH
    );
    let b = &beaded.summary.beads["bead"];
    eprintln!("holder {holder} N, with the bead {measured} N (expected {expected} N); {b:?}");
    assert!((b.length_engaged / WIDTH - 1.0).abs() < 1e-6, "{b:?}");
    assert!(
        (b.restraining_force / (f_t * WIDTH) - 1.0).abs() < 0.01,
        "{b:?}"
    );
    // The ledger is one step behind the bead's own sum.
    let ledger = beaded.summary.energy.bead;
    assert!(
        b.dissipation > 0.0 && (ledger / b.dissipation - 1.0).abs() < 1e-2,
        "{ledger} mJ vs {b:?}"
    );
    assert!(
        beaded.summary.energy.balance_error_rel < 0.02,
        "{:?}",
        beaded.summary.energy
    );
}

/// The clamping force `F_n` pushes the strip onto the die and takes as much
/// off the holder's contact, which delivers `F` in total: the holder's
/// friction becomes `μ (2F − F_n w)`, i.e. the plain draw force times
/// `(2F − F_n w) / 2F` (F = 1000 N, `F_n w` = 200 N: × 0.9), plus `F_t w`; 1 %.
/// The bead lies mid-element (x = 1.25 mm); on a node line (x = 0) the
/// push, shared by two element columns, sets the force-controlled holder
/// bouncing and it delivers 5 % more than F (draw force +3 %): a known limit.
#[test]
fn a_bead_clamping_force_unloads_the_holder_contact() {
    let (_d, plain) = strip_with("", &[]);
    let (f_t, f_n, f) = (10.0, 20.0, 1000.0);
    let (_d, beaded) = strip_with(&bead_at(1.25, f_t, f_n), &[]);
    let expected = draw_force(&plain) * (2.0 * f - f_n * WIDTH) / (2.0 * f) + f_t * WIDTH;
    let measured = draw_force(&beaded);
    eprintln!(
        "plain {} N, with the bead {measured} N (expected {expected} N); {:?}; {:?}",
        draw_force(&plain),
        beaded.summary.beads["bead"],
        beaded.summary.figures("strip")
    );
    assert!(
        (measured / expected - 1.0).abs() < 0.01,
        "draw force {measured} N vs {expected} N"
    );
    let b = &beaded.summary.beads["bead"];
    assert!((b.normal_force / (f_n * WIDTH) - 1.0).abs() < 1e-6, "{b:?}");
}

/// A bead 0.4 mm inside the strip's trailing end (x = −20 mm): the end
/// passes it once the strip has travelled 0.4 mm (about 4.3 ms into the
/// run); from 4.8 ms on the draw force is the holder's alone (the same
/// window without the bead) within 1 %, and the bead ends with no force and
/// no engaged length, after having held the strip (its largest force
/// `F_t` times the width it crossed).
#[test]
fn a_bead_the_strip_has_left_stops_acting() {
    let late = ["output.strip.average_from=4.8e-3"];
    let (_d, plain) = strip_with("", &late);
    let f_t = 20.0;
    let (_d, beaded) = strip_with(&bead_at(-19.6, f_t, 0.0), &late);
    let (holder, measured) = (draw_force(&plain), draw_force(&beaded));
    eprintln!("holder {holder} N, after the bead {measured} N");
    assert!(
        (measured / holder - 1.0).abs() < 0.01,
        "draw force {measured} N after the strip left the bead vs the holder's {holder} N"
    );
    let b = &beaded.summary.beads["bead"];
    assert_eq!(b.length_engaged, 0.0, "{b:?}");
    assert_eq!(b.restraining_force, 0.0, "{b:?}");
    assert!((b.length_engaged_max / WIDTH - 1.0).abs() < 1e-6, "{b:?}");
    assert!(b.restraining_force_max > 0.99 * f_t * WIDTH, "{b:?}");
}
