//! The S-rail reconstruction (`scenes/s-rail.toml`) end to end on a coarse
//! mesh: the single-action press (the die closes onto blank and holder, the
//! holder pushes up with 10 kN under force control, the die draws over the
//! fixed punch) runs, balances its energy, the holder delivers its force, and
//! summary.json carries the sections I–E and D–J and the keys listed below.

mod common;

use formsim::run::RunResult;

/// The S-rail on 35 × 14 shells (10 mm), drawn 8 mm in 10 ms (stroke 9 mm
/// with the 1 mm approach), reported at 5 and 9 mm.
fn coarse_s_rail() -> (tempfile::TempDir, RunResult) {
    common::run_scene(
        "s-rail",
        &[
            "blank.mesh.divisions=[35, 14]",
            "solver.mass_scaling_dt=2e-6",
            "steps[2].duration=1e-2",
            "steps[2].motions[1].distance=8.0",
            "output.report_strokes=[5.0, 9.0]",
            "output.frames=2",
            "output.plots=false",
        ],
    )
}

/// Completes; energy balance below 1 %; the holder delivers its 10 kN within
/// 1 % in the mean of the draw step; sections I–E and D–J have rows and
/// finite extremes; summary.json has sections.{IE,DJ}.{major_max, minor_min,
/// thinning_max}, thinning_max, friction_energy_share, friction_to_internal
/// and the tools block, at the end and in each state.
#[test]
fn s_rail_coarse_runs_end_to_end() {
    let (dir, r) = coarse_s_rail();
    let s = &r.summary;
    assert_eq!(s.status, formsim::run::Status::Completed);
    assert!((s.stroke - 9.0).abs() < 1e-6, "stroke {}", s.stroke);
    assert!(
        s.description.contains("reconstruction"),
        "{}",
        s.description
    );
    assert!(s.energy.balance_error_rel < 0.01, "balance {:?}", s.energy);
    let draw = &s.tools["blankholder"].steps["draw"];
    let error = draw.delivered_error.expect("force-controlled holder");
    assert!(
        error.abs() < 0.01,
        "holder delivers {} N, prescribed {:?} ({:+.2} %)",
        draw.force_along.mean,
        draw.force_prescribed,
        100.0 * error
    );
    // The die pushes down on the blank: its force is the "punch force".
    assert!(s.punch_force_max > 10_000.0, "{}", s.punch_force_max);

    for name in ["IE", "DJ"] {
        let rows = &r.last.curves[name];
        assert!(rows.len() >= 10, "{name}: {} rows", rows.len());
        let sec = &s.sections[name];
        for v in [sec.major_max, sec.minor_min, sec.thinning_max] {
            assert!(v.is_finite(), "{name}: {sec:?}");
        }
    }

    let text = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let states: Vec<&serde_json::Value> = ["5", "9"].iter().map(|k| &json["states"][k]).collect();
    for (at, v) in std::iter::once(("end", &json)).chain(["5", "9"].into_iter().zip(states)) {
        for name in ["IE", "DJ"] {
            for key in ["major_max", "minor_min", "thinning_max"] {
                let x = v["sections"][name][key].as_f64();
                assert!(x.is_some_and(f64::is_finite), "{at}: sections.{name}.{key}");
            }
        }
        for key in [
            "thinning_max",
            "friction_energy_share",
            "friction_to_internal",
        ] {
            let x = v[key].as_f64();
            assert!(x.is_some_and(f64::is_finite), "{at}: {key}");
        }
        for tool in ["blankholder", "die", "punch"] {
            assert!(v["tools"][tool]["steps"].is_object(), "{at}: tools.{tool}");
        }
        assert!(v["draw_in"]["I"].as_f64().is_some(), "{at}: draw_in.I");
    }
    assert!(json["friction_to_internal"].as_f64().unwrap() > 0.0);
    assert!(
        json["tools"]["blankholder"]["steps"]["draw"]["delivered_error"]
            .as_f64()
            .is_some()
    );
}
