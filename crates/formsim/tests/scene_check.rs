//! Scene files: the ready scenes load and build; bad input gives one error
//! naming the file, the line (when the key is in the file) and the key.

use formsim::scene::{self, SceneError};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn cup() -> PathBuf {
    root().join("scenes/square-cup.toml")
}

/// The cup scene with one line replaced, parsed from text.
fn cup_with(from: &str, to: &str) -> Result<scene::LoadedScene, SceneError> {
    let text = std::fs::read_to_string(cup()).unwrap();
    assert!(text.contains(from), "the scene has `{from}`");
    scene::parse(&text.replacen(from, to, 1), &cup(), &[])
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn ready_scenes_load_and_build() {
    for name in ["square-cup", "square-cup-al", "capstan", "block-on-plane"] {
        let path = root().join(format!("scenes/{name}.toml"));
        let loaded = scene::load(&path, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
        let model = scene::build(&loaded).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!model.mesh.quads.is_empty(), "{name}");
        assert!(model.end_time > 0.0, "{name}");
    }
    let loaded = scene::load(&cup(), &[]).unwrap();
    let model = scene::build(&loaded).unwrap();
    assert_eq!(model.mesh.quads.len(), 2500);
    assert_eq!(model.tool_names, ["blankholder", "die", "punch"]);
    assert_eq!(model.contact().unwrap().pairs().len(), 3);
}

#[test]
fn overrides_change_any_value() {
    let sets = [
        "blank.mesh.divisions=25".to_string(),
        "contact.law=wvs".to_string(),
        "contact.formulation=jaumann".to_string(),
    ];
    let loaded = scene::load(&cup(), &sets).unwrap();
    let model = scene::build(&loaded).unwrap();
    assert_eq!(model.mesh.quads.len(), 625);
    assert_eq!(
        (model.law.as_str(), model.formulation.as_str()),
        ("wvs", "jaumann")
    );
    let pair = &model.contact().unwrap().pairs()[0];
    assert_eq!(pair.friction_model(), ("wvs", "jaumann"));
}

/// The shells' drilling coefficient and warping correction are scene keys,
/// checked for range and type; both elements take the warping correction.
#[test]
fn drilling_and_warping_options_are_checked() {
    let load = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        scene::load(&cup(), &sets).and_then(|l| scene::build(&l).map(|_| ()))
    };
    load(&[
        "blank.mesh.divisions=4",
        "blank.drilling=0.01",
        "blank.warping_correction=true",
    ])
    .unwrap();
    let e = load(&["blank.drilling=0.5"]).unwrap_err().to_string();
    assert!(
        e.contains("blank.drilling: 0.5: must be in [0, 0.1]"),
        "{e}"
    );
    let e = load(&["blank.drilling=-1e-3"]).unwrap_err().to_string();
    assert!(e.contains("blank.drilling"), "{e}");
    // Both elements have the warping correction.
    load(&[
        "blank.mesh.divisions=4",
        "blank.element=fully-integrated",
        "blank.warping_correction=true",
    ])
    .unwrap();
    let e = load(&["blank.warping_correction=2"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("warping_correction"), "{e}");
}

#[test]
fn unknown_key_names_its_line() {
    let text = std::fs::read_to_string(cup()).unwrap();
    let line = line_of(&text, "hourglass = 0.05");
    let e = cup_with("hourglass = 0.05", "hourglas = 0.05")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("square-cup.toml:{line}: blank.hourglas")),
        "{e}"
    );
    assert!(e.contains("unknown field"), "{e}");
}

#[test]
fn wrong_type_and_out_of_range_name_key_value_and_unit() {
    let text = std::fs::read_to_string(cup()).unwrap();
    let line = line_of(&text, "youngs_modulus");
    let e = cup_with("youngs_modulus = 206000.0", "youngs_modulus = \"steel\"")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!(":{line}: blank.material.youngs_modulus")),
        "{e}"
    );
    let e = cup_with("youngs_modulus = 206000.0", "youngs_modulus = -1.0")
        .unwrap_err()
        .to_string();
    assert!(e.contains("-1 MPa: must be finite and > 0"), "{e}");
    let e = cup_with("poissons_ratio = 0.30", "poissons_ratio = 0.7")
        .unwrap_err()
        .to_string();
    assert!(e.contains("blank.material.poissons_ratio: 0.7"), "{e}");
    let e = cup_with("length = \"mm\"", "length = \"m\"")
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene.units.length"), "{e}");
    let e = cup_with("distance = 39.99", "distance = nan")
        .unwrap_err()
        .to_string();
    assert!(e.contains("steps[2].motions[1].distance"), "{e}");
}

#[test]
fn bad_names_point_at_the_key() {
    let e = scene::load(&cup(), &["contact.law=coulomb".into()])
        .and_then(|l| scene::build(&l).map(|_| ()))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("(value from --set): contact.law: unknown law `coulomb`"),
        "{e}"
    );
    let e = scene::load(&cup(), &["output.stroke_tool=ram".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("output.stroke_tool: \"ram\": no such tool"),
        "{e}"
    );
    let e = scene::load(&cup(), &["steps[7].duration=1".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--set steps[7].duration=1: index [7] past the end"),
        "{e}"
    );
}

#[test]
fn syntax_error_names_the_line() {
    let text = "[scene]\nname = \"x\"\nunits = { length = \"mm\" \n";
    let e = scene::parse(text, Path::new("bad.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("bad.toml:3:"), "{e}");
}

#[test]
fn cli_scene_check_summarises_and_bad_input_exits_1_with_one_line() {
    let exe = env!("CARGO_BIN_EXE_formsim");
    let ok = std::process::Command::new(exe)
        .args(["scene", "check"])
        .arg(cup())
        .output()
        .unwrap();
    assert!(ok.status.success());
    let text = String::from_utf8_lossy(&ok.stdout);
    assert!(text.contains("2500 belytschko-tsay shells"), "{text}");
    assert!(text.contains("punch travels 39.99 mm"), "{text}");
    let bad = std::process::Command::new(exe)
        .args(["run", "--quiet", "--out", "/nonexistent-dir-never-written"])
        .arg(cup())
        .args(["--set", "blank.material.density=0"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(1));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("blank.material.density: 0 tonne/mm^3: must be finite and > 0"),
        "{err}"
    );
}

/// Square cup at 25 × 25 (3 mm elements over the 5 mm die shoulder) is
/// coarse with either shell (docs/convergence.md: OX major strain 77–82 % of
/// the 100 × 100 value); 50 × 50 is not: the check warns for the first (both
/// elements) and not for the second.
#[test]
fn coarse_mesh_over_small_radius_warns() {
    let coarse = scene::load(&cup(), &["blank.mesh.divisions=25".into()]).unwrap();
    let w = scene::validate::warnings(&coarse);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("tools.die.shoulder_radius") && w[0].contains("at least 45"),
        "{w:?}"
    );
    let base = scene::load(&cup(), &[]).unwrap();
    assert!(scene::validate::warnings(&base).is_empty());
    let fi = scene::load(
        &cup(),
        &[
            "blank.mesh.divisions=25".into(),
            "blank.element=fully-integrated".into(),
        ],
    )
    .unwrap();
    assert_eq!(scene::validate::warnings(&fi).len(), 1);
}

// ----- guards -----------------------------------------------------------------

/// `formsim scene check SCENE --set …`: exit code, stdout, stderr, wall time.
fn check_cli(scene: &Path, sets: &[&str]) -> (Option<i32>, String, String, f64) {
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"));
    cmd.args(["scene", "check"]).arg(scene);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let started = std::time::Instant::now();
    let out = cmd.output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        started.elapsed().as_secs_f64(),
    )
}

/// A refused scene: exit 1 and one line on stderr containing every `needle`.
fn assert_refused(scene: &Path, sets: &[&str], needles: &[&str]) -> f64 {
    let (code, _, err, secs) = check_cli(scene, sets);
    assert_eq!(code, Some(1), "{sets:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` not in: {err}");
    }
    secs
}

#[test]
fn shipped_scenes_check_with_estimates_and_no_warnings() {
    for name in ["square-cup", "square-cup-al", "capstan", "block-on-plane"] {
        let (code, out, err, _) = check_cli(&root().join(format!("scenes/{name}.toml")), &[]);
        assert_eq!(code, Some(0), "{name}: {err}");
        assert!(!out.contains("warning"), "{name}: {out}");
        assert!(out.contains("estimate    memory"), "{out}");
        assert!(out.contains("increments of"), "{out}");
    }
    let (_, out, _, _) = check_cli(&cup(), &[]);
    assert!(
        out.contains("mass scaling (dt = 5e-7 s) adds 295.6 %"),
        "{out}"
    );
    assert!(
        out.contains("30201 increments of 5.000e-7 s (mass scaling)"),
        "{out}"
    );
}

/// A mass-scaling step of 1 s on the 4 ms block ran one increment and
/// reported success; 1e-5 s on the cup is a tenth of its first step.
#[test]
fn mass_scaling_step_longer_than_a_hundredth_of_a_step_is_refused() {
    let block = root().join("scenes/block-on-plane.toml");
    assert_refused(
        &block,
        &["solver.mass_scaling_dt=1.0"],
        &[
            "solver.mass_scaling_dt: 1 s",
            "solver.end_time (0.004 s), at most 4e-5 s",
        ],
    );
    assert_refused(
        &cup(),
        &["solver.mass_scaling_dt=1e-5"],
        &[
            "solver.mass_scaling_dt: 1e-5 s",
            "press step \"punch contact\" (1e-4 s)",
        ],
    );
    // A hundredth of the first step is accepted.
    let (code, _, err, _) = check_cli(&cup(), &["solver.mass_scaling_dt=1e-6"]);
    assert_eq!(code, Some(0), "{err}");
}

/// 1e-6 s on the cup adds about 1,480 % at set-up: `scene check` and the run
/// warn (the run as it starts), naming the key and the percentage, and the
/// run keeps the same line in `summary.json`'s `warnings`; `--quiet` prints
/// errors only.
#[test]
fn large_added_mass_warns_at_check_and_before_the_run() {
    let (code, out, _, _) = check_cli(&cup(), &["solver.mass_scaling_dt=1e-6"]);
    assert_eq!(code, Some(0));
    let warning = out
        .lines()
        .find(|l| l.contains("warning"))
        .unwrap_or_else(|| panic!("no warning: {out}"));
    let expected = "solver.mass_scaling_dt: 1e-6 s adds 1482 %";
    assert!(warning.contains(expected), "{warning}");

    let run = |quiet: bool| {
        let out_dir =
            std::env::temp_dir().join(format!("formsim-guards-run-{}-{quiet}", std::process::id()));
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"));
        cmd.arg("run");
        if quiet {
            cmd.arg("--quiet");
        }
        let run = cmd
            .arg("--out")
            .arg(&out_dir)
            .arg(cup())
            .args(["--set", "solver.mass_scaling_dt=1e-6"])
            .args(["--set", "solver.end_time=1e-4"])
            .args(["--set", "output.plots=false"])
            .args(["--set", "output.frames=0"])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr).to_string();
        let stdout = String::from_utf8_lossy(&run.stdout).to_string();
        assert!(run.status.success(), "{err}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
                .unwrap();
        std::fs::remove_dir_all(&out_dir).ok();
        (err, stdout, summary)
    };
    let (err, stdout, summary) = run(false);
    assert!(err.contains(expected), "{err}");
    assert!(stdout.contains(&format!("warning: {expected}")), "{stdout}");
    let kept = summary["warnings"].as_array().unwrap();
    assert!(
        kept.iter()
            .any(|w| w.as_str().unwrap().starts_with(expected)),
        "{kept:?}"
    );
    let (err, stdout, _) = run(true);
    assert!(err.is_empty(), "--quiet printed: {err}");
    assert!(!stdout.contains("warning"), "--quiet printed: {stdout}");
}

/// 4096 × 4096 shells took 82 s and 16 GB to check; 1e9 history rows
/// aborted on a 168 GB allocation. Both are refused from the scene alone,
/// before anything is built, naming the key (the bound of 10 s on the whole
/// process is far below what building the mesh took, and far above a
/// process start on a busy machine).
#[test]
fn runs_larger_than_the_machine_are_refused_fast() {
    let secs = assert_refused(
        &cup(),
        &["blank.mesh.divisions=4096"],
        &[
            "blank.mesh.divisions: [4096, 4096]: a run needs about",
            "16785409 nodes, 16777216 elements",
        ],
    );
    assert!(secs < 10.0, "{secs} s");
    let secs = assert_refused(
        &cup(),
        &["output.history_points=1000000000"],
        &["output.history_points: 1000000000", "of history rows"],
    );
    assert!(secs < 10.0, "{secs} s");
    assert_refused(
        &cup(),
        &["blank.mesh.divisions=400", "output.frames=1000000000"],
        &["output.frames: 1000000000", "of disk"],
    );
    assert_refused(
        &root().join("scenes/capstan.toml"),
        &["blank.mesh.element_size=1e-6"],
        &["blank.mesh.element_size: 0.000001 mm"],
    );
}

/// A scene over a mesh file in a fresh directory: (scene path, mesh path).
fn file_scene(name: &str, mesh: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("formsim-guards-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[scene]\nname = \"mesh-file\"\n\
         units = { length = \"mm\", force = \"N\", stress = \"MPa\", mass = \"tonne\", time = \"s\" }\n\
         [blank]\nmesh = { kind = \"file\", path = \"mesh.inp\" }\nthickness = 1.0\n\
         [blank.material]\nyoungs_modulus = 206000.0\npoissons_ratio = 0.3\n\
         density = 7.85e-9\nhardening = { kind = \"elastic\" }\n\
         [solver]\nend_time = 1.0e-3\n",
    )
    .unwrap();
    let path = dir.join("mesh.inp");
    std::fs::write(&path, mesh).unwrap();
    (scene, path)
}

/// Two shells, 17 and 18, over nodes 3, 4, 5, 9 and 4, 6, 7, 5.
const STRIP: &str = "*NODE\n3, 0, 0, 0\n4, 1, 0, 0\n5, 1, 1, 0\n9, 0, 1, 0\n\
                     6, 2, 0, 0\n7, 2, 1, 0\n*ELEMENT, TYPE=S4R\n17, 3, 4, 5, 9\n18, 4, 6, 7, 5\n";

#[test]
fn mesh_files_without_shells_or_with_bad_elements_are_refused_at_check() {
    let (scene, mesh) = file_scene("mesh", STRIP);
    let (code, out, err, _) = check_cli(&scene, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("6 nodes, 2 belytschko-tsay shells"), "{out}");

    // Empty: passed the check, then failed the run on the time step.
    std::fs::write(&mesh, "** nothing\n").unwrap();
    assert_refused(
        &scene,
        &[],
        &["blank.mesh.path: mesh.inp: no shell elements"],
    );
    // Zero area: named at the mesh file, not blamed on `solver`.
    std::fs::write(
        &mesh,
        STRIP
            .replace("5, 1, 1, 0", "5, 0.5, 0, 0")
            .replace("9, 0, 1, 0", "9, 0.2, 0, 0"),
    )
    .unwrap();
    assert_refused(
        &scene,
        &[],
        &[
            "blank.mesh.path: mesh.inp: element 17 has zero area",
            "nodes 3, 4, 5, 9",
        ],
    );
    std::fs::write(&mesh, STRIP.replace("17, 3, 4, 5, 9", "17, 3, 4, 4, 9")).unwrap();
    assert_refused(
        &scene,
        &[],
        &[
            "blank.mesh.path: mesh.inp: element 17 has zero area: node 4 appears twice (nodes 3, 4, 4, 9)",
        ],
    );
    // NaN coordinates and missing nodes: the reader names file and line.
    std::fs::write(&mesh, STRIP.replace("6, 2, 0, 0", "6, nan, 0, 0")).unwrap();
    assert_refused(
        &scene,
        &[],
        &[
            "blank.mesh.path: ",
            "mesh.inp:6: node 6: coordinate `nan` is not finite",
        ],
    );
    std::fs::write(&mesh, STRIP.replace("18, 4, 6, 7, 5", "18, 4, 6, 8, 5")).unwrap();
    assert_refused(
        &scene,
        &[],
        &[
            "blank.mesh.path: ",
            "mesh.inp:10: element 18: node id 8 is not defined",
        ],
    );
    std::fs::remove_dir_all(scene.parent().unwrap()).unwrap();
}

/// A generated mesh gets the same element check (a rectangle whose
/// elements' area underflows to zero).
#[test]
fn generated_meshes_with_zero_area_are_refused() {
    assert_refused(
        &cup(),
        &["blank.mesh.size=[1e-200, 1e-200]"],
        &[
            "blank.mesh: rectangle: element 0 has zero area",
            "nodes 0, 1, 52, 51",
        ],
    );
}

/// Every setting that can move a result is visible at `scene check`: with
/// `--resolved` every key prints with its resolved value, defaults included
/// (the holder's dashpot, 0; the hourglass coefficient) and overrides
/// applied.
#[test]
fn scene_check_resolved_prints_every_setting_with_its_default() {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(["scene", "check", cup().to_str().unwrap(), "--resolved"])
        .args(["--set", "contact.penalty_scale=0.2"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{text}");
    for line in [
        "steps[2].motions[0].damping = 0.0",
        "steps[2].motions[0].relative_damping = 0.0",
        "steps[2].motions[0].mass = 0.01",
        "blank.hourglass = 0.05",
        "contact.penalty_scale = 0.2",
    ] {
        assert!(
            text.lines().any(|l| l.trim() == line),
            "{line} missing:\n{text}"
        );
    }
}

/// A force motion takes `force` or `force_curve`, never both; a curve's
/// compressions must increase; a scene with a gas-spring curve builds.
#[test]
fn force_motion_takes_force_or_a_curve() {
    let sets = vec!["steps[2].motions[0].force_curve=[[0.0, 4900.0], [2.0, 6000.0]]".to_string()];
    let e = scene::load(&cup(), &sets).unwrap_err().to_string();
    assert!(
        e.contains("steps[2].motions[0].force") && e.contains("not both"),
        "{e}"
    );

    let text = std::fs::read_to_string(cup()).unwrap();
    let draw = "force = 4900.0 },";
    assert_eq!(text.matches(draw).count(), 1);
    let dir = tempfile::tempdir().unwrap();
    let write = |curve: &str| {
        let path = dir.path().join("cup.toml");
        std::fs::write(
            &path,
            text.replace(draw, &format!("force_curve = {curve} }},")),
        )
        .unwrap();
        path
    };
    let good = scene::load(&write("[[0.0, 4900.0], [2.0, 6000.0]]"), &[]).unwrap();
    scene::build(&good).unwrap();
    let e = scene::load(&write("[[0.0, 4900.0], [0.0, 6000.0]]"), &[])
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("force_curve[1][0]"), "{e}");
}

/// The element and the material resolve through the registry
/// (`shell_elements::kinds`): an unregistered name, or a material whose
/// r-values do not fit it, is one line naming the key and listing the
/// registered names; `model` chosen explicitly builds the same shells as
/// the default choice.
#[test]
fn element_and_material_resolve_through_the_registry() {
    let load = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        scene::load(&cup(), &sets)
    };
    let cases = [
        (
            &["blank.element=bt"][..],
            "blank.element",
            "belytschko-tsay, fully-integrated",
        ),
        (
            &["blank.material.model=vumat"][..],
            "blank.material.model",
            "hill48, j2",
        ),
        (
            &["blank.material.model=hill48"][..],
            "blank.material.model",
            "needs blank.material.r_values",
        ),
        (
            &[
                "blank.material.model=j2",
                "blank.material.r_values=[1.5, 1.2, 2.0]",
            ][..],
            "blank.material.model",
            "isotropic",
        ),
    ];
    for (sets, key, says) in cases {
        let e = load(sets).unwrap_err().to_string();
        assert!(e.contains(key) && e.contains(says), "{sets:?}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
    for (sets, material) in [
        (
            &["blank.mesh.divisions=4", "blank.material.model=j2"][..],
            "j2",
        ),
        (
            &[
                "blank.mesh.divisions=4",
                "blank.material.r_values=[1.5, 1.2, 2.0]",
            ][..],
            "hill48",
        ),
    ] {
        let model = scene::build(&load(sets).unwrap()).unwrap();
        assert_eq!(model.shells.material, material);
        assert_eq!(model.shells.element, "belytschko-tsay");
    }
}

/// A run estimated at more than 24 hours is refused up front, naming the
/// key that sets the step (`solver.mass_scaling_dt=1e-15`) or, with the
/// estimated stable step, the press step that sets the
/// end (a 1e6 s step); `--allow-long` lets the estimate through.
#[test]
fn absurd_run_times_are_refused_unless_allowed() {
    assert_refused(
        &cup(),
        &["solver.mass_scaling_dt=1e-15"],
        &[
            "solver.mass_scaling_dt: the run would take about 87384",
            "days",
            "--allow-long",
        ],
    );
    assert_refused(
        &root().join("scenes/strip-draw.toml"),
        &["steps[2].duration=1e6"],
        &["steps[2].duration: the run would take about", "days"],
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(["--allow-long", "scene", "check"])
        .arg(cup())
        .args(["--set", "solver.mass_scaling_dt=1e-15"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(text.contains("87384.3 days"), "{text}");
}

/// With `solver.fixed_dt` the estimate counts the fixed step: the dt-limit
/// case runs 11,873 increments of 3.369e-7 s, and its estimate said 9,547
/// of the estimated stable step (4.19e-7 s) before.
#[test]
fn estimate_counts_the_fixed_step() {
    let (code, out, err, _) = check_cli(&root().join("scenes/hard/dt-limit.toml"), &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("11873 increments of 3.369e-7 s (fixed step)"),
        "{out}"
    );
}

/// A value far beyond any sheet or metal is named at its key, not as the
/// infinite mass or step it makes downstream (`blank.thickness=1e300`, not
/// "node 0: lumped rotational inertia = inf").
#[test]
fn absurd_physical_values_name_their_key() {
    for (set, needle) in [
        (
            "blank.thickness=1e300",
            "blank.thickness: 1e300 mm: must be at most 1e3 mm",
        ),
        (
            "blank.material.youngs_modulus=1e300",
            "blank.material.youngs_modulus: 1e300 MPa: must be at most 1e7 MPa",
        ),
        (
            "blank.material.density=1e300",
            "blank.material.density: 1e300 tonne/mm^3: must be at most",
        ),
        (
            "blank.mesh.size=[1e300, 10]",
            "blank.mesh.size: 1e300 mm: must be at most",
        ),
    ] {
        assert_refused(&root().join("scenes/strip-draw.toml"), &[set], &[needle]);
    }
}

/// Selective mass scaling's keys are checked with one line naming the
/// key: a tolerance outside (0, 0.1], and `"selective"` without the step
/// it should reach.
#[test]
fn selective_mass_scaling_keys_are_checked() {
    let cup = cup();
    let (code, _, err, _) = check_cli(
        &cup,
        &[
            "solver.mass_scaling=\"selective\"",
            "solver.mass_scaling_tolerance=0.5",
        ],
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("solver.mass_scaling_tolerance: 0.5: must be in (0, 0.1]"),
        "{err}"
    );
    let (code, _, err, _) = check_cli(
        &cup,
        &[
            "solver.mass_scaling=\"selective\"",
            "solver.mass_scaling_dt=",
        ],
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("solver.mass_scaling: \"selective\" needs solver.mass_scaling_dt"),
        "{err}"
    );
    let (code, out, err, _) = check_cli(&cup, &["solver.mass_scaling=\"selective\""]);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("mass scaling"), "{out}");
}

/// `[formability]`'s keys and curve files are checked when the scene is
/// read, each in one line naming the key; `scene check` prints the curve.
#[test]
fn formability_keys_and_curve_files_are_checked() {
    let cup = cup();
    let refused = |sets: &[&str], want: &str| {
        let (code, _, err, _) = check_cli(&cup, sets);
        assert_eq!(code, Some(1), "{sets:?}: {err}");
        assert!(err.contains(want), "{sets:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    refused(
        &["formability.margin=1.5"],
        "formability.margin: 1.5: must be a strain in [0, 1)",
    );
    refused(
        &["formability.curve=\"table\""],
        "formability.file: required with curve = \"table\"",
    );
    refused(
        &["formability.measure=\"true\""],
        "formability.measure: only with curve = \"table\"",
    );
    refused(
        &["blank.material.hardening={kind=\"perfect\", sigma_y=200.0}"],
        "formability.n: required: Keeler–Brazier needs the sheet's hardening exponent",
    );
    let dir = std::env::temp_dir().join(format!("formsim-flc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let missing = dir.join("absent.csv").display().to_string();
    refused(
        &[
            "formability.curve=\"table\"",
            "formability.measure=\"true\"",
            &format!("formability.file=\"{missing}\""),
        ],
        "formability.file: ",
    );
    let bad = write("bad.csv", "minor,major\n-0.2,0.4\n0.0,0.3\n-0.1,0.35\n");
    refused(
        &[
            "formability.curve=\"table\"",
            "formability.measure=\"true\"",
            &format!("formability.file=\"{bad}\""),
        ],
        "row 3: minor strain -0.1 must be larger than the row before's 0",
    );
    let words = write("words.csv", "minor,major\n-0.2,0.4\n0.0,zero\n");
    refused(
        &[
            "formability.curve=\"table\"",
            "formability.measure=\"true\"",
            &format!("formability.file=\"{words}\""),
        ],
        "line 3: `0.0,zero` is not two numbers",
    );
    let good = write(
        "good.csv",
        "# measured\nminor,major\n-0.2,0.45\n0.0,0.28\n0.2,0.38\n",
    );
    let (code, out, err, _) = check_cli(
        &cup,
        &[
            "formability.curve=\"table\"",
            "formability.measure=\"true\"",
            &format!("formability.file=\"{good}\""),
        ],
    );
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("formability table curve (true strain), plane-strain limit 0.2800"),
        "{out}"
    );
    let (code, out, err, _) = check_cli(&cup, &[]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains(
            "formability keeler-brazier curve (engineering strain), plane-strain limit 0.3432"
        ),
        "{out}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
