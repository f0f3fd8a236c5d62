//! Fuzzed inputs: property-based tests over what a user hands
//! formsim — scene overrides (`--set KEY=VALUE`), blank mesh files (`.inp`,
//! `.msh`), tool mesh files (STL, OBJ), point histories (`friction-point`'s
//! CSV) and friction-law parameters. Each input must load, or be refused with
//! a one-line error; never a panic, a hang or a multi-line message.
//!
//! The cases come from a fixed seed, so CI runs the same ones every time;
//! `FORMSIM_FUZZ_CASES=N` (default 1000 per property) and
//! `FORMSIM_FUZZ_SEED=S` (any integer) run more, or others:
//!
//! ```text
//! FORMSIM_FUZZ_CASES=20000 FORMSIM_FUZZ_SEED=7 cargo test --release -p formsim --test fuzz_inputs
//! ```

use formsim::scene;
use plugins_api::{Params, registry};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A runner with the fixed (or chosen) seed and case count.
fn runner() -> TestRunner {
    let cases = std::env::var("FORMSIM_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000);
    let seed: u64 = std::env::var("FORMSIM_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_261_125);
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

/// An error a user reads: one line, not empty.
fn one_line(what: &str, e: &str) -> Result<(), TestCaseError> {
    prop_assert!(
        !e.trim().is_empty() && !e.contains('\n'),
        "{what}: not a one-line error: {e:?}"
    );
    Ok(())
}

/// Load `path` with `sets` and build its model: Ok, or a one-line error.
fn load_and_build(path: &Path, sets: &[String]) -> Result<(), TestCaseError> {
    match scene::load(path, sets) {
        Err(e) => one_line("load", &e.to_string()),
        Ok(loaded) => match scene::build(&loaded) {
            Err(e) => one_line("build", &e.to_string()),
            Ok(_) => Ok(()),
        },
    }
}

/// Values that break naive parsers and range checks, as TOML text.
fn nasty_value() -> impl Strategy<Value = String> {
    let fixed = prop::sample::select(vec![
        "0",
        "-1",
        "1",
        "2",
        "3",
        "-0.0",
        "1e-300",
        "1e300",
        "-1e300",
        "nan",
        "inf",
        "-inf",
        "1e9",
        "9223372036854775807",
        "-9223372036854775808",
        "\"\"",
        "\"x\"",
        "\"ac\"",
        "\"jaumann\"",
        "[]",
        "[0.0]",
        "[1.0, 2.0]",
        "[[0.0, 1.0]]",
        "[1, 2, 3]",
        "{}",
        "{ a = 1 }",
        "true",
        "false",
        "0.5",
        "1e-12",
    ])
    .prop_map(String::from);
    prop_oneof![
        3 => fixed,
        1 => any::<f64>().prop_map(|v| format!("{v:e}")),
        1 => (-5i64..300).prop_map(|v| v.to_string()),
        1 => "[a-z0-9\\[\\]{}=,.\"-]{0,12}",
    ]
}

/// The keys of a scene as resolved, plus a few that are not there.
fn keys_of(path: &Path) -> Vec<String> {
    let loaded = scene::load(path, &[]).unwrap();
    let mut keys: Vec<String> = scene::resolved::dotted_lines(&loaded.scene)
        .unwrap()
        .iter()
        .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.to_string()))
        .collect();
    keys.extend(
        [
            "nosuch",
            "blank.nosuch",
            "steps[9].duration",
            "steps[0].motions[7].force",
            "tools.nosuch.kind",
            "contact.params.nosuch.mu",
            "output.strip",
            "blank.mesh.divisions",
            "blank.mesh",
            "",
            "=",
            "steps[",
        ]
        .map(String::from),
    );
    keys
}

/// Load and build `scene` with one or two random overrides: Ok or a
/// one-line error.
fn fuzz_overrides(scene_file: &str) {
    let path = root().join(scene_file);
    let keys = keys_of(&path);
    let pair = (prop::sample::select(keys), nasty_value()).prop_map(|(k, v)| format!("{k}={v}"));
    let sets = prop::collection::vec(pair, 1..3);
    runner()
        .run(&sets, |sets| load_and_build(&path, &sets))
        .unwrap();
}

#[test]
fn fuzz_block_scene_overrides() {
    fuzz_overrides("scenes/block-on-plane.toml");
}

#[test]
fn fuzz_strip_scene_overrides() {
    fuzz_overrides("scenes/strip-draw.toml");
}

/// Lines an `.inp` or `.msh` file is made of, shuffled with noise.
fn mesh_text(keywords: &'static [&'static str]) -> impl Strategy<Value = String> {
    let line = prop_oneof![
        3 => prop::sample::select(keywords.to_vec()).prop_map(String::from),
        4 => prop::collection::vec(
            prop_oneof![(-3i64..12).prop_map(|v| v.to_string()), any::<f64>().prop_map(|v| v.to_string())],
            0..6,
        )
        .prop_map(|v| v.join(", ")),
        1 => "[ -~]{0,20}",
    ];
    prop::collection::vec(line, 0..24).prop_map(|l| l.join("\n"))
}

/// A scene over the blank mesh `file` (relative to the scene).
fn scene_with_mesh(file: &str) -> String {
    format!(
        r#"
[scene]
name = "fuzz"
units = {{ length = "mm", force = "N", stress = "MPa", mass = "tonne", time = "s" }}
[blank]
mesh = {{ kind = "file", path = "{file}" }}
thickness = 1.0
[blank.material]
youngs_modulus = 206000.0
poissons_ratio = 0.3
density = 7.85e-9
hardening = {{ kind = "elastic" }}
[solver]
end_time = 1.0e-4
"#
    )
}

fn fuzz_mesh_file(name: &str, keywords: &'static [&'static str]) {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.toml");
    std::fs::write(&scene_path, scene_with_mesh(name)).unwrap();
    let mesh_path = dir.path().join(name);
    runner()
        .run(&mesh_text(keywords), |text| {
            std::fs::write(&mesh_path, &text).unwrap();
            load_and_build(&scene_path, &[])
        })
        .unwrap();
}

#[test]
fn fuzz_abaqus_inp_meshes() {
    fuzz_mesh_file(
        "blank.inp",
        &[
            "*NODE",
            "*Node",
            "*ELEMENT, TYPE=S4R",
            "*ELEMENT, TYPE=S4R, ELSET=blank",
            "*ELEMENT, TYPE=C3D8",
            "*NSET, NSET=x0",
            "*ELSET, ELSET=e",
            "** comment",
            "1, 0.0, 0.0, 0.0",
            "2, 1.0, 0.0, 0.0",
            "3, 1.0, 1.0, 0.0",
            "4, 0.0, 1.0, 0.0",
            "1, 1, 2, 3, 4",
            "2, 1, 1, 3, 4",
            "*END",
        ],
    );
}

#[test]
fn fuzz_gmsh_msh_meshes() {
    fuzz_mesh_file(
        "blank.msh",
        &[
            "$MeshFormat",
            "2.2 0 8",
            "4.1 0 8",
            "$EndMeshFormat",
            "$Nodes",
            "4",
            "1 0 0 0",
            "2 1 0 0",
            "3 1 1 0",
            "4 0 1 0",
            "$EndNodes",
            "$Elements",
            "1",
            "1 3 2 0 1 1 2 3 4",
            "$EndElements",
            "$PhysicalNames",
        ],
    );
}

/// A scene whose one tool is the mesh `file`.
fn scene_with_tool(file: &str) -> String {
    format!(
        r#"
[scene]
name = "fuzz"
units = {{ length = "mm", force = "N", stress = "MPa", mass = "tonne", time = "s" }}
[blank]
mesh = {{ kind = "rectangle", size = [10.0, 10.0], divisions = 2, origin = [0.0, 0.0, 0.5] }}
thickness = 1.0
[blank.material]
youngs_modulus = 206000.0
poissons_ratio = 0.3
density = 7.85e-9
hardening = {{ kind = "elastic" }}
[tools.plate]
kind = "mesh"
file = "{file}"
[solver]
end_time = 1.0e-4
"#
    )
}

fn fuzz_tool_file(name: &str, content: impl Strategy<Value = Vec<u8>>) {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("scene.toml");
    std::fs::write(&scene_path, scene_with_tool(name)).unwrap();
    let tool_path = dir.path().join(name);
    runner()
        .run(&content, |bytes| {
            std::fs::write(&tool_path, &bytes).unwrap();
            load_and_build(&scene_path, &[])
        })
        .unwrap();
}

#[test]
fn fuzz_stl_tools() {
    // Binary STL: an 80-byte header, a count, then 50-byte triangles (some
    // cases with the count off, some truncated), and ASCII STL text.
    let f32s = prop::collection::vec(any::<f32>(), 12);
    let triangle = f32s.prop_map(|v| {
        let mut b: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        b.extend([0, 0]);
        b
    });
    let binary = (0u32..6, prop::collection::vec(triangle, 0..5), 0usize..3).prop_map(
        |(count, tris, cut)| {
            let mut b = vec![b' '; 80];
            b.extend(count.to_le_bytes());
            for t in tris {
                b.extend(t);
            }
            b.truncate(b.len().saturating_sub(cut));
            b
        },
    );
    let ascii = mesh_text(&[
        "solid s",
        "facet normal 0 0 1",
        "outer loop",
        "vertex 0 0 0",
        "vertex 1 0 0",
        "vertex 0 1 0",
        "vertex 0 0 0",
        "endloop",
        "endfacet",
        "endsolid s",
    ])
    .prop_map(String::into_bytes);
    fuzz_tool_file(
        "tool.stl",
        prop_oneof![binary, ascii, prop::collection::vec(any::<u8>(), 0..200)],
    );
}

#[test]
fn fuzz_obj_tools() {
    let text = mesh_text(&[
        "v 0 0 0",
        "v 1 0 0",
        "v 0 1 0",
        "v 1 1 0",
        "f 1 2 3",
        "f 1 2 3 4",
        "f 1/1/1 2/2/2 3/3/3",
        "f -1 -2 -3",
        "f 1 1 2",
        "vn 0 0 1",
        "# comment",
        "o plate",
    ]);
    fuzz_tool_file("tool.obj", text.prop_map(String::into_bytes));
}

#[test]
fn fuzz_point_histories() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let text = mesh_text(&[
        "t,p,du_x,du_y,du_z,n_x,n_y,n_z",
        "t,p,du_x,du_y,du_z,n_x,n_y,n_z,sigma_y,temperature",
        "# comment",
        "1e-3,10,0.01,0,0,0,0,1",
        "2e-3,0,0.01,0,0,0,0,1",
        "2e-3,10,0.01,0,0,0,0,1",
        "3e-3,-1,0,0,0,0,0,1",
        "4e-3,10,0,0,0,0,0,0",
        "5e-3,10,0,0,0,0,0,2",
    ]);
    runner()
        .run(&text, |text| {
            std::fs::write(&path, &text).unwrap();
            if let Err(e) = formsim::history::read(&path) {
                one_line("history", &e.to_string())?;
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn fuzz_law_parameters() {
    friction_laws::ensure_linked();
    let names: Vec<String> = registry::laws()
        .iter()
        .map(|l| l.description.name.to_string())
        .chain(["nosuch".to_string()])
        .collect();
    let param_names = vec![
        "mu", "alpha", "beta", "nu", "a0", "a1", "a2", "mu_min", "m", "c", "k_t", "p0", "x",
    ];
    let value = prop_oneof![
        3 => prop::sample::select(vec![
            0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 1e300, f64::NAN, f64::INFINITY, f64::NEG_INFINITY,
        ]),
        2 => any::<f64>(),
    ];
    let params = prop::collection::vec((prop::sample::select(param_names), value), 0..5);
    let text = "[ -~]{0,24}";
    runner()
        .run(
            &(prop::sample::select(names), params, text),
            |(name, params, text)| {
                let mut p = Params::new();
                for (k, v) in &params {
                    p.set(k, *v);
                }
                if let Err(e) = registry::build_law(&name, &p) {
                    one_line("build_law", &e.to_string())?;
                }
                if let Err(e) = Params::parse_assignment(&text) {
                    one_line("parse_assignment", &e.to_string())?;
                }
                Ok(())
            },
        )
        .unwrap();
}

/// Run the binary with `args`; it must exit within 20 s (a FIFO or
/// /dev/zero read as a file would hang forever or grow to gigabytes), non-zero,
/// with one error line containing `needle`.
fn refused_at_once(args: &[&std::ffi::OsStr], needle: &str) {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let started = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed().as_secs() > 20 {
            child.kill().ok();
            panic!("{args:?}: still running after 20 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: `{needle}` not in {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
}

/// Every file formsim reads, as a special file (a FIFO, a character
/// device, a directory) or as a file over its size limit (a sparse file:
/// no disk), is refused at once with one line: the scene, a blank mesh, a
/// tool mesh, a tool spec, a points CSV, a point history, measurements and
/// a plugin library.
#[test]
fn special_and_oversized_files_are_refused_at_once() {
    use plugins_api::input_file::{MESH_LIMIT, TEXT_LIMIT};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("fifo");
    assert!(
        std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let sparse = |name: &str, len: u64| {
        let p = d.join(name);
        std::fs::File::create(&p).unwrap().set_len(len).unwrap();
        p
    };
    let big_text = sparse("big.toml", TEXT_LIMIT + 1);
    let big_inp = sparse("big.inp", MESH_LIMIT + 1);
    let big_stl = sparse("big.stl", MESH_LIMIT + 1);
    let zero = PathBuf::from("/dev/zero");
    let scene = root().join("scenes/strip-draw.toml");
    let al = root().join("scenes/square-cup-al.toml");
    let spec = root().join("scenes/tools/square-cup-tools.toml");
    let os = |s: &str| std::ffi::OsString::from(s);
    let cases: Vec<(&str, PathBuf, &str)> = vec![
        ("scene", fifo.clone(), "FIFO"),
        ("scene", zero.clone(), "character device"),
        ("scene", d.to_path_buf(), "directory"),
        ("scene", big_text.clone(), "more than the"),
        ("mesh", fifo.clone(), "FIFO"),
        ("mesh", big_inp.clone(), "more than the"),
        ("tool", zero.clone(), "character device"),
        ("tool", big_stl.clone(), "more than the"),
        ("spec", fifo.clone(), "FIFO"),
        ("points", zero.clone(), "character device"),
        ("history", fifo.clone(), "FIFO"),
        ("history", big_text.clone(), "more than the"),
        ("measurements", zero.clone(), "character device"),
        ("measurements", big_text.clone(), "more than the"),
        ("plugin", fifo.clone(), "FIFO"),
        ("plugin", zero.clone(), "character device"),
    ];
    for (kind, path, needle) in cases {
        let p = path.as_os_str().to_owned();
        let args: Vec<std::ffi::OsString> = match kind {
            "scene" => vec![os("scene"), os("check"), p],
            "mesh" | "tool" => {
                let link = d.join(if kind == "mesh" { "m.inp" } else { "t.stl" });
                std::fs::remove_file(&link).ok();
                std::os::unix::fs::symlink(&path, &link).unwrap();
                let text = if kind == "mesh" {
                    scene_with_mesh("m.inp")
                } else {
                    scene_with_tool("t.stl")
                };
                let s = d.join(format!("{kind}.toml"));
                std::fs::write(&s, text).unwrap();
                vec![os("scene"), os("check"), s.into_os_string()]
            }
            "spec" => vec![
                os("tools"),
                os("export"),
                p,
                os("--out"),
                d.join("x").into(),
            ],
            "points" => vec![
                os("tools"),
                os("project"),
                spec.clone().into(),
                os("--tool"),
                os("punch"),
                os("--points"),
                p,
                os("--out"),
                d.join("p.csv").into(),
            ],
            "history" => vec![
                os("friction-point"),
                os("--law"),
                os("ac"),
                os("--param"),
                os("mu=0.1"),
                os("--history"),
                p,
                os("--out"),
                d.join("h.csv").into(),
            ],
            "measurements" => vec![
                os("identify"),
                al.clone().into(),
                os("--measurements"),
                p,
                os("--fit"),
                os("contact.params.ac.mu=0.05..0.3"),
                os("--out"),
                d.join("id").into(),
            ],
            "plugin" => {
                let mut set = os("contact.plugin=");
                set.push(&p);
                vec![
                    os("scene"),
                    os("check"),
                    scene.clone().into(),
                    os("--set"),
                    set,
                ]
            }
            _ => unreachable!(),
        };
        let args: Vec<&std::ffi::OsStr> = args.iter().map(|a| a.as_os_str()).collect();
        refused_at_once(&args, needle);
    }
}

/// The option grammar of `study`, `identify` and `compare`: `--vary
/// KEY=V1,V2`, `--reference KEY=V`, `--quantities` names (`KEY`,
/// `SECTION[@STROKE]:COLUMN`), `--fit KEY=LO..HI[:START]` and `--case
/// NAME:KEY=VALUE;…`, from fragments of valid options and nasty text: each
/// parses, or is refused with one line, never a panic.
#[test]
fn fuzz_study_identify_and_compare_options() {
    let piece = prop_oneof![
        Just("contact.params.ac.mu".to_string()),
        Just("blank.mesh.divisions".to_string()),
        Just("=".to_string()),
        Just("..".to_string()),
        Just(":".to_string()),
        Just("@".to_string()),
        Just(",".to_string()),
        Just(";".to_string()),
        Just(".".to_string()),
        Just("OD".to_string()),
        Just("major".to_string()),
        Just("default".to_string()),
        nasty_value(),
        "[ -~]{0,12}",
    ];
    let text = proptest::collection::vec(piece, 0..8).prop_map(|v| v.concat());
    runner()
        .run(&text, |t| {
            if let Err(e) = formsim::study::Knob::parse(&t) {
                one_line("--vary", &e.to_string())?;
            }
            if let Err(e) = formsim::study::parse_reference(&t) {
                one_line("--reference", &e.to_string())?;
            }
            for q in t.split(',') {
                if let Err(e) = formsim::study::quantity::parse(q) {
                    one_line("--quantities", &e.to_string())?;
                }
            }
            if let Err(e) = formsim::identify::params::FitParam::parse(&t) {
                one_line("--fit", &e.to_string())?;
            }
            if let Err(e) = formsim::compare::Case::parse(&t) {
                one_line("--case", &e.to_string())?;
            }
            Ok(())
        })
        .unwrap();
}
