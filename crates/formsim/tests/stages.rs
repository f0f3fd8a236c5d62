//! Forming in stages (docs/stages.md): a run continued from a saved state
//! takes the steps the single run takes, and a state that does not fit the
//! scene is refused with one line naming what differs.

use formsim::run::{RunOptions, RunResult, run_staged};
use formsim::scene;
use formsim::state_file::{self, StateFile};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The coarse cup of `run_scene.rs` (10 × 10 quarter mesh), each draw of
/// 20 mm over 3 ms, landing on every press step's end.
const COARSE: [&str; 2] = ["blank.mesh.divisions=10", "solver.land_on_step_ends=true"];

fn load(path: &Path, sets: &[String]) -> scene::LoadedScene {
    let mut all: Vec<String> = COARSE.iter().map(|s| s.to_string()).collect();
    all.extend(sets.iter().cloned());
    scene::load(path, &all).unwrap()
}

fn run(path: &Path, sets: &[String], out: &Path, save: &Path) -> RunResult {
    let loaded = load(path, sets);
    let options = RunOptions {
        out: out.to_path_buf(),
        progress: Default::default(),
    };
    run_staged(&loaded, &options, Some(save)).unwrap()
}

/// The two stages in one scene: stage 1 with stage 2's press step appended.
fn single_scene(dir: &Path) -> PathBuf {
    let s1 = std::fs::read_to_string(root().join("scenes/square-cup-stage1.toml")).unwrap();
    let s2 = std::fs::read_to_string(root().join("scenes/square-cup-stage2.toml")).unwrap();
    let steps = &s2[s2.find("[[steps]]").unwrap()..s2.find("[solver]").unwrap()];
    let path = dir.join("square-cup-40.toml");
    std::fs::write(&path, format!("{s1}\n{steps}")).unwrap();
    path
}

/// Largest `|a − b|` over two arrays of the same length.
fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn flat(v: &[fem_core::Vec3]) -> Vec<f64> {
    fem_core::resume::flatten(v)
}

/// Every nodal field and every effect array of two states: the largest
/// difference, relative to the largest value of the field.
fn largest_state_difference(a: &StateFile, b: &StateFile) -> (f64, String) {
    let (ra, rb) = (&a.resume, &b.resume);
    let mut fields: Vec<(String, Vec<f64>, Vec<f64>)> = vec![
        ("x".into(), flat(&ra.nodes.x), flat(&rb.nodes.x)),
        ("v".into(), flat(&ra.nodes.v), flat(&rb.nodes.v)),
        ("w".into(), flat(&ra.nodes.w), flat(&rb.nodes.w)),
        ("f".into(), flat(&ra.forces.f), flat(&rb.forces.f)),
        ("mass".into(), ra.nodes.mass.clone(), rb.nodes.mass.clone()),
    ];
    for ((name, sa), (_, sb)) in ra.effects.iter().zip(&rb.effects) {
        for ((key, va), (_, vb)) in sa.entries().iter().zip(sb.entries()) {
            fields.push((format!("{name}.{key}"), va.clone(), vb.clone()));
        }
    }
    let mut worst = (0.0, String::new());
    for (name, va, vb) in fields {
        let scale = va.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
        let d = max_diff(&va, &vb) / scale;
        if d >= worst.0 {
            worst = (d, name);
        }
    }
    worst
}

/// Round-off bound of the staged cup against the single run (relative to
/// each field's largest value): the continuation is exact by construction
/// (the same state, the same time arithmetic), so anything above a few
/// ulps means a piece of state was lost (losing only the contact regions'
/// warm start, for one, grows to 4e-5 in the punch force by the end).
const ROUND_OFF: f64 = 1e-12;

/// The square cup drawn 40 mm in one run and 20 + 20 mm in two runs, the
/// second from the state the first saved (`scenes/square-cup-stage1.toml`,
/// `square-cup-stage2.toml`): the punch force history, draw-in, thinning
/// and every final nodal and point field agree to round-off (measured:
/// bit for bit).
#[test]
fn square_cup_40_mm_in_one_run_equals_20_plus_20_mm_in_two() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let draw = |k: usize| format!("steps[{k}].duration=3e-3");
    let single = run(
        &single_scene(d),
        &[draw(2), draw(3)],
        &d.join("single"),
        &d.join("single.state"),
    );
    let stage1 = d.join("stage1.state");
    run(
        &root().join("scenes/square-cup-stage1.toml"),
        &[draw(2)],
        &d.join("s1"),
        &stage1,
    );
    let staged = run(
        &root().join("scenes/square-cup-stage2.toml"),
        &[draw(0), format!("blank.initial_state={}", stage1.display())],
        &d.join("s2"),
        &d.join("staged.state"),
    );
    let (a, b) = (&single.summary, &staged.summary);
    assert!((a.stroke - 40.0).abs() < 1e-9 && (b.stroke - 40.0).abs() < 1e-9);
    let rel = |x: f64, y: f64| (x - y).abs() / x.abs().max(1e-300);
    assert!(
        rel(single.last.punch_force, staged.last.punch_force) <= ROUND_OFF,
        "{} {}",
        single.last.punch_force,
        staged.last.punch_force
    );
    assert!(rel(a.punch_force_max, b.punch_force_max) <= ROUND_OFF);
    assert!(rel(a.thinning_max, b.thinning_max) <= ROUND_OFF);
    for (k, v) in &a.draw_in {
        assert!(
            rel(*v, b.draw_in[k]) <= ROUND_OFF,
            "draw-in {k}: {v} {}",
            b.draw_in[k]
        );
    }
    // The second stage's force history is the single run's from 20 mm on,
    // wherever both sampled the same instant (the start and the end at least).
    let mut common = 0;
    for h in &staged.history {
        if let Some(s) = single.history.iter().find(|s| s.time == h.time) {
            common += 1;
            let (f, g) = (s.punch_force, h.punch_force);
            assert!(rel(f, g) <= ROUND_OFF, "{} s: {f} {g}", h.time);
        }
    }
    assert!(common >= 2, "{common} common samples");
    // The energy ledger carries on: the staged run's energies are the
    // single run's, to the one step by which the saved ledger lags the
    // state (its work is a few 1e-4 of the whole here); the balance closes.
    let (ea, eb) = (&a.energy, &b.energy);
    for (what, x, y) in [
        ("external work", ea.external_work, eb.external_work),
        ("internal", ea.internal, eb.internal),
        ("plastic", ea.plastic, eb.plastic),
        ("friction", ea.friction, eb.friction),
    ] {
        assert!(rel(x, y) < 1e-3, "{what}: single {x}, staged {y}");
    }
    assert!(eb.balance_error_rel < 1e-4, "{:?}", eb);
    let (sa, _) = state_file::read(&d.join("single.state")).unwrap();
    let (sb, _) = state_file::read(&d.join("staged.state")).unwrap();
    let (worst, field) = largest_state_difference(&sa, &sb);
    assert!(
        worst <= ROUND_OFF,
        "largest difference {worst:e} in {field}"
    );
    // summary.json records the state it started from and the one it saved.
    let started = b.initial_state.as_ref().unwrap();
    assert_eq!(Path::new(&started.path), stage1);
    assert_eq!(started.checksum.len(), 16);
    assert!(b.saved_state.is_some() && a.initial_state.is_none());
}

/// A saved coarse stage 1 (stopped early: 0.5 ms of its draw) in `dir`.
fn saved_state(dir: &Path) -> PathBuf {
    let path = dir.join("stage1.state");
    run(
        &root().join("scenes/square-cup-stage1.toml"),
        &[
            "steps[2].duration=5e-4".into(),
            "steps[2].motions[1].distance=1.0".into(),
        ],
        &dir.join("s1"),
        &path,
    );
    path
}

/// The error of building stage 2 from `state` with `sets`: one line.
fn refusal(state: &Path, sets: &[&str]) -> String {
    let mut all = vec![format!("blank.initial_state={}", state.display())];
    all.extend(sets.iter().map(|s| s.to_string()));
    let loaded = load(&root().join("scenes/square-cup-stage2.toml"), &all);
    let e = scene::build(&loaded).unwrap_err().to_string();
    assert!(!e.trim_end().contains('\n'), "one line: {e}");
    assert!(e.contains("blank.initial_state"), "names the key: {e}");
    e
}

/// Bytes of `state` with `f` applied, written next to it as `name`.
fn altered(state: &Path, name: &str, f: impl Fn(&mut Vec<u8>)) -> PathBuf {
    let mut bytes = std::fs::read(state).unwrap();
    f(&mut bytes);
    let path = state.with_file_name(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// What `file`'s own model looks like with `quads`.
fn key<'a>(file: &'a StateFile, quads: &'a [[u32; 4]]) -> state_file::ModelKey<'a> {
    state_file::ModelKey {
        element: &file.element,
        material: &file.material,
        nodes: file.nodes(),
        quads,
    }
}

/// Each refusal names what differs: not a state file, another format
/// version, another formsim version, a truncated file, another element
/// formulation, material kind, node count, element count or connectivity.
#[test]
fn states_that_do_not_fit_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let state = saved_state(dir.path());
    // The saved state itself builds.
    let all = vec![format!("blank.initial_state={}", state.display())];
    scene::build(&load(&root().join("scenes/square-cup-stage2.toml"), &all)).unwrap();

    let magic = altered(&state, "magic.state", |b| b[0] = b'X');
    assert!(refusal(&magic, &[]).contains("not a formsim state file"));
    let format = altered(&state, "format.state", |b| b[8] = 99);
    let e = refusal(&format, &[]);
    assert!(
        e.contains("format version 99") && e.contains("reads version 1"),
        "{e}"
    );
    // The formsim version string starts after magic (8), format (4) and its length (8).
    let version = altered(&state, "version.state", |b| b[20] = b'9');
    let e = refusal(&version, &[]);
    assert!(
        e.contains("saved by formsim 9") && e.contains(env!("CARGO_PKG_VERSION")),
        "{e}"
    );
    let cut = altered(&state, "cut.state", |b| b.truncate(b.len() / 2));
    assert!(refusal(&cut, &[]).contains("truncated or damaged"));
    let missing = dir.path().join("none.state");
    assert!(refusal(&missing, &[]).contains("none.state"));

    let e = refusal(&state, &["blank.element=\"fully-integrated\""]);
    assert!(
        e.contains("element `belytschko-tsay` in the state, `fully-integrated` in the scene"),
        "{e}"
    );
    let e = refusal(&state, &["blank.material.r_values=[1.0, 1.2, 1.4]"]);
    assert!(
        e.contains("material model") && e.contains("in the state"),
        "{e}"
    );
    let e = refusal(&state, &["blank.mesh.divisions=[10, 9]"]);
    assert!(
        e.contains("121 nodes in the state, 110 in the scene's mesh"),
        "{e}"
    );

    // Same node count, other elements or connectivity: checked on the file.
    let (file, _) = state_file::read(&state).unwrap();
    let mut quads = file.quads.clone();
    file.check_model(&key(&file, &quads)).unwrap();
    quads[5].rotate_left(1);
    let e = file.check_model(&key(&file, &quads)).unwrap_err();
    assert!(e.starts_with("element 5 has nodes"), "{e}");
    quads.pop();
    let e = file.check_model(&key(&file, &quads)).unwrap_err();
    assert!(
        e.contains("100 elements in the state, 99 in the scene's mesh"),
        "{e}"
    );
}

/// `formsim scene check` names the state a scene starts from.
#[test]
fn scene_check_reports_the_initial_state() {
    let dir = tempfile::tempdir().unwrap();
    let state = saved_state(dir.path());
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(["scene", "check"])
        .arg(root().join("scenes/square-cup-stage2.toml"))
        .args(["--set", "blank.mesh.divisions=10", "--set"])
        .arg(format!("blank.initial_state={}", state.display()))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("initial"))
        .unwrap();
    assert!(
        line.contains("stage1.state") && line.contains("121 nodes"),
        "{line}"
    );
}
