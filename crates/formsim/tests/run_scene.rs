//! `formsim run` end to end on small versions of the ready scenes: every output
//! file is written, finite and consistent, and the block on a plane slides at `μN`.

mod common;

use common::{root, run_scene};
use formsim::run::RunResult;
use formsim::scene;

/// Block on a plane (docs/benchmarks.md §3): the friction force while sliding is
/// `μ N` = 0.2 × 100 N; tolerance 1 %.
#[test]
fn block_on_plane_slides_at_mu_n() {
    let (dir, r) = run_scene("block-on-plane", &[]);
    let b = r.summary.figures("block").expect("block result");
    assert!((b.analytic - 20.0).abs() < 1e-12);
    assert!(
        (b.value - b.analytic).abs() < 0.01 * b.analytic,
        "slip force {} N vs mu N = {} N",
        b.value,
        b.analytic
    );
    assert!(r.summary.energy.friction > 0.0);
    // summary.json has them as `block{slip_force, analytic}`, nothing else.
    let text = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        json["block"],
        serde_json::json!({"slip_force": b.value, "analytic": b.analytic})
    );
    assert!(json.get("capstan").is_none() && json.get("strip").is_none());
}

/// The block's reference reads μ from the active law: with `mu = 0.3` the
/// analytic slip force is 30 N and the block slides at it (1 %).
#[test]
fn block_reference_follows_the_contact_law() {
    let (_dir, r) = run_scene("block-on-plane", &["contact.params.ac.mu=0.3"]);
    let b = r.summary.figures("block").expect("block result");
    assert!((b.analytic - 30.0).abs() < 1e-12, "{}", b.analytic);
    assert!((b.value / b.analytic - 1.0).abs() < 0.01, "{}", b.value);
    // A law that is not Coulomb has no analytic reference, and says so.
    let (_dir, r) = run_scene(
        "block-on-plane",
        &[
            "contact.law=wvs",
            "contact.params.wvs={alpha=0.03, beta=0.144, nu=0.8}",
        ],
    );
    assert!(r.summary.reference.is_none());
    assert!(
        r.summary
            .warnings
            .iter()
            .any(|w| w.contains("no analytic reference")),
        "{:?}",
        r.summary.warnings
    );
}

/// Strip draw: a strip pulled between a force-controlled holder
/// (F = 1000 N) and a die that rises at a steady 20 mm/s, lifting strip and
/// holder. Coulomb friction on both faces: the draw force is `2μF` (1 %),
/// and the holder delivers `F` in the mean (0.5 %), over the averaging
/// window and over the whole draw step. With a dashpot of
/// 500 N·s/mm the holder would deliver `F + c v` ≈ 11 kN: the test fails.
#[test]
fn strip_draw_delivers_2_mu_f() {
    let check = |r: &RunResult| -> Result<(), String> {
        let s = r.summary.figures("strip").ok_or("no strip result")?;
        let get = |name| s.get(name).ok_or(format!("no {name}"));
        let (holder_force, holder_prescribed) = (get("holder_force")?, get("holder_prescribed")?);
        let draw = &r.summary.tools["holder"].steps["draw"];
        let step_error = draw.delivered_error.ok_or("no delivered force")?;
        if (holder_force / holder_prescribed - 1.0).abs() > 5e-3 || step_error.abs() > 5e-3 {
            return Err(format!(
                "holder delivers {} N (draw step {:+.3} %), prescribed {} N",
                holder_force,
                100.0 * step_error,
                holder_prescribed
            ));
        }
        if (s.value / s.analytic - 1.0).abs() > 1e-2 {
            return Err(format!(
                "draw force {} N vs 2 mu F = {} N",
                s.value, s.analytic
            ));
        }
        Ok(())
    };
    let (_dir, r) = run_scene("strip-draw", &[]);
    assert!((r.summary.figures("strip").unwrap().analytic - 300.0).abs() < 1e-9);
    check(&r).unwrap();
    let (_dir, old) = run_scene(
        "strip-draw",
        &[
            "steps[1].motions[0].damping=500",
            "steps[2].motions[0].damping=500",
            "steps[1].motions[0].relative_damping=0",
            "steps[2].motions[0].relative_damping=0",
        ],
    );
    let e = check(&old).expect_err("the old dashpot must fail the strip test");
    assert!(e.contains("holder delivers"), "{e}");
}

/// The square cup on a 10 × 10 quarter mesh drawn 5 mm: every output
/// file exists and reads back, summary.json carries every required key with
/// finite values, and the energy balance closes within 2 %.
#[test]
fn square_cup_coarse_writes_every_output() {
    let (dir, r) = run_scene(
        "square-cup",
        &[
            "blank.mesh.divisions=10",
            "steps[2].duration=3e-3",
            "steps[2].motions[1].distance=4.99",
            "output.report_strokes=[2.0, 5.0]",
            "output.frames=3",
        ],
    );
    let out = dir.path();
    assert!(
        (r.summary.stroke - 5.0).abs() < 1e-6,
        "stroke {}",
        r.summary.stroke
    );
    assert!(r.summary.punch_force_max > 0.0);
    assert!(
        r.summary.energy.balance_error_rel < 0.02,
        "{:?}",
        r.summary.energy
    );
    assert_eq!(r.summary.status, formsim::run::Status::Completed);

    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in [
        "scene",
        "law",
        "formulation",
        "elements",
        "increments",
        "wall_time_s",
        "element_cycles_per_s",
        "energy",
        "description",
        "friction_energy_share",
        "friction_to_internal",
        "kinetic_to_internal_max",
        "thinning_max",
        "punch_force_max",
        "stroke",
        "sections",
        "draw_in",
        "states",
    ] {
        assert!(json.get(key).is_some(), "summary.json lacks {key}");
    }
    for key in [
        "internal",
        "kinetic",
        "hourglass",
        "contact",
        "friction",
        "plastic",
        "external_work",
        "balance_error_rel",
    ] {
        assert!(
            json["energy"][key].as_f64().unwrap().is_finite(),
            "energy.{key}"
        );
    }
    check_timing(&json);
    assert!(json["sections"]["OD"]["major_max"].as_f64().is_some());
    assert!(json["sections"]["OD"]["minor_min"].as_f64().is_some());
    assert!(
        json["sections"]["OX"]["minor_at_punch_edge"]
            .as_f64()
            .is_some()
    );
    for d in ["DX", "DY", "DD"] {
        assert!(
            json["draw_in"][d].as_f64().unwrap().is_finite(),
            "draw_in.{d}"
        );
    }
    for s in ["2", "5"] {
        let st = &json["states"][s];
        assert!(st["punch_force"].as_f64().unwrap() > 0.0, "states.{s}");
        assert!(st["sections"]["OD"]["major_max"].as_f64().is_some());
        assert!(st["draw_in"]["DX"].as_f64().is_some());
        assert!(st["thinning_max"].as_f64().is_some());
        assert!(st["sections"]["OD"]["thinning_max"].as_f64().is_some());
        for key in ["friction_energy_share", "friction_to_internal"] {
            assert!(st[key].as_f64().unwrap().is_finite(), "states.{s}.{key}");
        }
        assert!(st["tools"]["punch"]["steps"]["draw"].is_object());
    }
    // Each section's thinning_max is the largest thinning of its CSV rows.
    for name in ["OD", "OX"] {
        let csv = std::fs::read_to_string(out.join(format!("sections/{name}.csv"))).unwrap();
        let largest = csv
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap())
            .fold(f64::NEG_INFINITY, f64::max);
        let reported = json["sections"][name]["thinning_max"].as_f64().unwrap();
        assert!(
            (reported - largest).abs() <= 1e-12 * largest.abs().max(1.0),
            "{name}"
        );
    }

    // Sections: one element per division, increasing distance, five columns.
    for name in ["OD", "OX", "OD_stroke2", "OX_stroke5"] {
        let csv = std::fs::read_to_string(out.join(format!("sections/{name}.csv"))).unwrap();
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows[0], "distance,major,minor,thickness_strain,thinning");
        assert_eq!(rows.len(), 11, "{name}");
    }
    // Histories.
    let energy = std::fs::read_to_string(out.join("energy.csv")).unwrap();
    assert!(energy.lines().count() > 100);
    let force = std::fs::read_to_string(out.join("punch_force.csv")).unwrap();
    assert!(force.starts_with("time,stroke,punch_force\n"));
    // VTK series: the pvd lists the frames and each reads back.
    let pvd = std::fs::read_to_string(out.join("blank.pvd")).unwrap();
    let frames: Vec<_> = std::fs::read_dir(out.join("vtk")).unwrap().collect();
    assert_eq!(frames.len(), 4);
    assert_eq!(pvd.matches("<DataSet").count(), 4);
    // Frame paths are relative to the .pvd, beside `vtk/`.
    assert!(pvd.contains("file=\"vtk/blank_0003.vtu\""), "{pvd}");
    let vtk = vtkio::Vtk::import(out.join("vtk/blank_0003.vtu")).unwrap();
    let text = format!("{vtk:?}");
    for field in [
        "contact_pressure",
        "friction_traction",
        "thinning",
        "major_strain",
        "von_mises_max",
        "fld_zone",
        "fld_margin",
    ] {
        assert!(text.contains(field), "frame lacks {field}");
    }
    // Formability: fld.csv holds every element, its counts per zone are the
    // summary's, its smallest margin the summary's; each report stroke has
    // its own diagram; the plot is drawn.
    let fld = &json["formability"];
    assert_eq!(fld["curve"]["kind"], "keeler-brazier");
    let csv = std::fs::read_to_string(out.join("fld.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 100);
    let zones = fld["zones"].as_object().unwrap();
    let counted: u64 = zones.values().map(|v| v.as_u64().unwrap()).sum();
    assert_eq!(counted, 100);
    for (zone, n) in zones {
        let in_csv = rows.iter().filter(|r| r[3] == zone).count() as u64;
        assert_eq!(in_csv, n.as_u64().unwrap(), "{zone}");
    }
    let least = rows
        .iter()
        .map(|r| r[4].parse::<f64>().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(least, fld["margin_min"].as_f64().unwrap());
    for s in ["2", "5"] {
        let least = json["states"][s]["formability"]["margin_min"]
            .as_f64()
            .unwrap();
        let csv = std::fs::read_to_string(out.join(format!("fld_stroke{s}.csv"))).unwrap();
        let in_csv = csv
            .lines()
            .skip(1)
            .map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(least, in_csv, "stroke {s}");
    }
    assert!(out.join("plots/fld.png").is_file());
    assert!(out.join("plots/fld_margin.png").is_file());
    // What each tool and pair did: the holder's per-step forces,
    // the pairs' dissipation, the resolved settings, tools.csv.
    let holder = &json["tools"]["blankholder"]["steps"]["draw"];
    for key in ["mean", "min", "max"] {
        assert!(holder["force_along"][key].as_f64().is_some(), "{key}");
        assert!(holder["force_total"][key].as_f64().is_some(), "{key}");
        assert!(holder["force_prescribed"][key].as_f64().is_some(), "{key}");
    }
    let prescribed = holder["force_prescribed"]["mean"].as_f64().unwrap();
    assert!((prescribed - 4900.0).abs() < 1e-9 * 4900.0, "{prescribed}");
    assert!(json["tools"]["punch"]["work"].as_f64().unwrap() > 0.0);
    let friction: f64 = json["pairs"]
        .as_object()
        .unwrap()
        .values()
        .map(|p| p["friction_dissipation"].as_f64().unwrap())
        .sum();
    // The ledger's energies are one explicit step behind the pairs' (fem-core's
    // energy ledger): one step of a few thousand, 1e-3.
    assert!(
        (friction - r.summary.energy.friction).abs() < 1e-3 * friction,
        "{friction} vs {}",
        r.summary.energy.friction
    );
    assert!(json["warnings"].is_array());
    assert_eq!(json["settings"]["blank"]["hourglass"].as_f64(), Some(0.05));
    assert_eq!(
        json["settings"]["steps"][2]["motions"][0]["damping"].as_f64(),
        Some(0.0)
    );
    let tools = std::fs::read_to_string(out.join("tools.csv")).unwrap();
    assert!(tools.starts_with(
        "time,stroke,blankholder_force,blankholder_force_total,blankholder_prescribed,blankholder_position,"
    ));
    assert!(tools.lines().count() > 100);
    // Plots.
    for png in ["strains", "energies", "punch_force", "thinning", "tools"] {
        let meta = std::fs::metadata(out.join(format!("plots/{png}.png"))).unwrap();
        assert!(meta.len() > 1000, "{png}.png");
    }
}

/// Hard case: the blank wraps 90° over the punch profile radius at the
/// largest mass-scaled time step formsim's cup scenes use (1e-6 s, twice the
/// default) on a coarse 25 × 25 quarter mesh drawn 20 mm in 6 ms. The wall
/// must turn down into the wall (an element on OX within 15° of vertical: the
/// 2 mm punch–die clearance and the 3 mm elements leave it a few degrees off;
/// 82° measured), every energy stays finite, and the balance error stays
/// below 2 %.
#[test]
fn wrap_90_over_punch_radius_at_largest_mass_scaled_step_stays_stable() {
    let sets: Vec<String> = [
        "blank.mesh.divisions=25",
        "solver.mass_scaling_dt=1e-6",
        "steps[2].duration=6e-3",
        "steps[2].motions[1].distance=19.99",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let loaded = scene::load(&root().join("scenes/square-cup.toml"), &sets).unwrap();
    let mut model = scene::build(&loaded).unwrap();
    model.solver.initialize().unwrap();
    let end = model.end_time;
    let mut worst_balance: f64 = 0.0;
    let mut dt_min = f64::INFINITY;
    while model.solver.time() < end * (1.0 - 1e-12) {
        let r = model.solver.step().unwrap();
        let e = &r.energy;
        for v in [
            e.internal,
            e.kinetic,
            e.contact,
            e.friction,
            e.external,
            e.hourglass,
        ] {
            assert!(v.is_finite(), "non-finite energy at t = {}", r.time);
        }
        if r.time > 2e-3 {
            worst_balance = worst_balance.max(e.balance_error);
        }
        dt_min = dt_min.min(r.dt);
    }
    let state = model.solver.state();
    // Steepest element along OX (the first row of elements, y in [0, h]).
    let mut steepest: f64 = 0.0;
    for e in 0..25 {
        let q = model.mesh.quads[e];
        let p: Vec<_> = q.iter().map(|&n| state.x[n as usize]).collect();
        let normal = (p[2] - p[0]).cross(&(p[3] - p[1])).normalize();
        steepest = steepest.max(normal.z.abs().acos().to_degrees());
    }
    eprintln!(
        "wrap: steepest OX element at {steepest:.1}° from horizontal, smallest dt {dt_min:.3e} s, worst balance {worst_balance:.2e}"
    );
    assert!(steepest > 75.0, "the wall is not wrapped: {steepest}°");
    assert!(worst_balance < 0.02, "balance error {worst_balance}");
    // Contact springs take part in mass scaling: the run keeps the target step.
    assert!(dt_min > 0.999e-6, "the step fell to {dt_min} s");
}

/// Levanov reads the blank's flow stress (friction-math §3): the shells hand
/// it to contact inside every step, the first included (shared fields), so
/// the law never sees σ_y = 0 when the holder closes on the blank.
#[test]
fn levanov_cup_reads_the_flow_stress_from_the_first_step() {
    let (_dir, r) = run_scene(
        "square-cup",
        &[
            "blank.mesh.divisions=8",
            "contact.law=levanov",
            "solver.end_time=1.5e-3",
            "output.frames=0",
            "output.plots=false",
        ],
    );
    assert_eq!(r.summary.law, "levanov");
    assert_eq!(r.summary.status, formsim::run::Status::Completed);
    assert!(r.summary.energy.balance_error_rel < 0.02);
}

/// summary.json's `timing`: every key present, finite and >= 0; the loop's
/// stages (press, elements, contact, engine, output) add up to its wall time and
/// contact's stages to contact's total, within 10 % (each stage is timed on
/// its own: a stage left out of the timers shows as a shortfall).
fn check_timing(json: &serde_json::Value) {
    let t = &json["timing"];
    let get = |v: &serde_json::Value, key: &str| {
        let s = v[key]
            .as_f64()
            .unwrap_or_else(|| panic!("timing.{key} missing in {t}"));
        assert!(s.is_finite() && s >= 0.0, "timing.{key} = {s}");
        s
    };
    let top: Vec<f64> = ["press", "elements", "engine", "output", "final_output"]
        .iter()
        .map(|k| get(t, k))
        .collect();
    let c = &t["contact"];
    let total = get(c, "total");
    let stages: f64 = [
        "geometry",
        "broad_phase",
        "projection",
        "normal",
        "friction",
        "scatter",
    ]
    .iter()
    .map(|k| get(c, k))
    .sum();
    let wall = json["wall_time_s"].as_f64().unwrap();
    let loop_sum = top[0] + top[1] + top[2] + top[3] + total;
    assert!(
        (loop_sum / wall - 1.0).abs() < 0.1,
        "stages sum to {loop_sum} s, the loop took {wall} s: {t}"
    );
    assert!(
        total > 0.0 && (stages / total - 1.0).abs() < 0.1,
        "contact stages sum to {stages} s of {total} s: {t}"
    );
}

/// The coarse cup of `square_cup_coarse_writes_every_output`, run once by
/// `formsim run` and once as a library user would: build the model and call
/// `Solver::run_until` with nothing else. The shells hand contact the
/// blank's thickness inside the solver's step (shared fields), so both give
/// the same bits: energies, thinning, punch force, increments. At the end,
/// the shared thickness field contact reads is the shells' current nodal thickness.
#[test]
fn formsim_run_and_solver_run_until_give_the_same_cup() {
    let sets = [
        "blank.mesh.divisions=10",
        "steps[2].duration=3e-3",
        "steps[2].motions[1].distance=4.99",
    ];
    let (_dir, r) = run_scene(
        "square-cup",
        &[&sets[..], &["output.frames=0", "output.plots=false"]].concat(),
    );
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let loaded = scene::load(&root().join("scenes/square-cup.toml"), &sets).unwrap();
    let mut model = scene::build(&loaded).unwrap();
    let (cid, stroke) = (model.contact.unwrap(), model.stroke.unwrap());
    let symmetry = loaded.scene.output.symmetry_factor;
    let mut force_max: f64 = 0.0;
    model
        .solver
        .run_until(model.end_time, &mut |s: &fem_core::Solver, _| {
            let c: &contact::ContactEffect = s.effect(cid).unwrap();
            force_max =
                force_max.max(-c.reactions()[stroke.index].dot(&stroke.direction) * symmetry);
            fem_core::Control::Continue
        })
        .unwrap();

    let e = model.solver.ledger();
    let s = &r.summary;
    let pairs = [
        ("internal", s.energy.internal, e.internal),
        ("kinetic", s.energy.kinetic, e.kinetic),
        ("hourglass", s.energy.hourglass, e.hourglass),
        ("contact", s.energy.contact, e.contact),
        ("friction", s.energy.friction, e.friction),
        ("plastic", s.energy.plastic, e.plastic),
        ("external", s.energy.external_work, e.external),
        ("balance", s.energy.balance_error_rel, e.balance_error),
        ("punch force max", s.punch_force_max, force_max),
    ];
    for (what, run, direct) in pairs {
        assert_eq!(run.to_bits(), direct.to_bits(), "{what}: {run} vs {direct}");
    }
    let shells = model.shells();
    let t0 = model.thickness0;
    let thinning = (0..shells.len())
        .map(|e| (t0 - shells.thickness(e)) / t0)
        .fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(s.thinning_max.to_bits(), thinning.to_bits());
    assert!(thinning > 0.0 && s.punch_force_max > 0.0);
    assert_eq!(s.increments, model.solver.steps());

    // What contact read in the last step: the shells' nodal mean thickness now.
    let mut sum = vec![0.0; model.mesh.nodes.len()];
    let mut valence = vec![0usize; sum.len()];
    for (e, q) in model.mesh.quads.iter().enumerate() {
        for &n in q {
            sum[n as usize] += shells.thickness(e);
            valence[n as usize] += 1;
        }
    }
    let nodal: Vec<f64> = sum
        .iter()
        .zip(&valence)
        .map(|(s, &v)| s * (1.0 / v as f64))
        .collect();
    assert_eq!(
        model.solver.field(fem_core::NodalField::THICKNESS).unwrap(),
        &nodal[..]
    );
}
