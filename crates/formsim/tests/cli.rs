//! End-to-end tests of the `formsim` command line: friction-point, laws, bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod cli_support;
use cli_support::{formsim, text};

fn history() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/point-histories/die-shoulder.csv")
}

fn read_rows(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

#[test]
fn friction_point_runs_every_builtin_law_and_formulation_on_the_shipped_history() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &[&str]); 4] = [
        ("ac", &["mu=0.144"]),
        ("wvs", &["alpha=0.03", "beta=0.144", "nu=0.8"]),
        ("wh", &["a0=0.1448", "a1=-8.757e-5"]),
        ("levanov", &["m=0.2"]),
    ];
    let hist = history();
    for (law, params) in cases {
        for formulation in ["convective", "jaumann", "lagrangian", "updated-lagrangian"] {
            let out = dir.path().join(format!("{law}-{formulation}.csv"));
            let mut args = vec!["friction-point", "--law", law, "--formulation", formulation];
            for p in params {
                args.extend(["--param", p]);
            }
            args.extend([
                "--history",
                hist.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ]);
            let o = formsim(&args);
            assert!(o.status.success(), "{law}/{formulation}: {}", text(&o));
            let (header, rows) = read_rows(&out);
            assert_eq!(
                header.join(","),
                "t,t_x,t_y,t_z,stick,dgamma,dissipation,omega,mu_eff"
            );
            assert_eq!(rows.len(), 1200);
            assert!(
                rows.iter().flatten().all(|v| v.is_finite()),
                "{law}/{formulation}: non-finite output"
            );
            // Dissipation is cumulative and ω is its running sum: both monotone.
            assert!(
                rows.windows(2)
                    .all(|w| w[1][6] >= w[0][6] && w[1][7] >= w[0][7])
            );
            // The point slips while drawn over the shoulder: some slip, some stick.
            assert!(rows.iter().any(|r| r[4] == 0.0) && rows.iter().any(|r| r[4] == 1.0));
        }
    }
}

#[test]
fn friction_point_plots_the_traction_history() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p.csv");
    let hist = history();
    let o = formsim(&[
        "friction-point",
        "--law",
        "ac",
        "--param",
        "mu=0.144",
        "--history",
        hist.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--plot",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let png = std::fs::read(dir.path().join("p.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert!(
        png.len() > 10_000,
        "plot suspiciously small: {} bytes",
        png.len()
    );
}

#[test]
fn bad_input_gives_one_clear_line_and_a_nonzero_exit() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    let out = out.to_str().unwrap();
    let hist = history();
    let hist = hist.to_str().unwrap();
    let expect_error = |args: &[&str], needles: &[&str]| {
        let o = formsim(args);
        assert!(!o.status.success(), "{args:?} should fail");
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        for n in needles {
            assert!(err.contains(n), "{args:?}: `{n}` not in `{err}`");
        }
        assert!(!err.contains("panicked"), "{err}");
    };
    expect_error(
        &[
            "friction-point",
            "--law",
            "coulomb",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["unknown law `coulomb`", "ac", "wvs", "wh", "levanov"],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "ac",
            "--formulation",
            "eulerian",
            "--history",
            hist,
            "--out",
            out,
        ],
        &[
            "unknown formulation `eulerian`",
            "jaumann",
            "updated-lagrangian",
        ],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "ac",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["missing parameter `mu`"],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "ac",
            "--param",
            "mu=-1",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["`mu`", "-1", ">= 0"],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "wvs",
            "--param",
            "alpha=0.03",
            "--param",
            "beta=0.1",
            "--param",
            "nu=0",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["`nu`", "> 0"],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "ac",
            "--param",
            "mu=0.1",
            "--param",
            "k_t=0",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["`k_t`", "MPa/mm"],
    );
    expect_error(
        &[
            "friction-point",
            "--law",
            "ac",
            "--param",
            "mux=0.1",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["unknown parameter `mux`"],
    );
    // Malformed histories: (file text, law and parameter, expected words).
    let bad = dir.path().join("bad.csv");
    let cases: [(&str, [&str; 2], &[&str]); 3] = [
        (
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,1,0,0,0,0,0,1\n0.2,inf,0,0,0,0,0,1\n",
            ["ac", "mu=0.1"],
            &["bad.csv:3", "`p`", "inf"],
        ),
        (
            "t,p,du_x,du_y,du_z,n_x,n_y\n0.1,1,0,0,0,0,0\n",
            ["ac", "mu=0.1"],
            &["bad.csv:1", "`n_z`"],
        ),
        // Levanov needs the flow stress: a history without it is refused, naming the column.
        (
            "t,p,du_x,du_y,du_z,n_x,n_y,n_z\n0.1,1,0.01,0,0,0,0,1\n",
            ["levanov", "m=0.2"],
            &["bad.csv:2", "sigma_y"],
        ),
    ];
    for (text, [law, param], needles) in cases {
        std::fs::write(&bad, text).unwrap();
        let bad = bad.to_str().unwrap();
        expect_error(
            &[
                "friction-point",
                "--law",
                law,
                "--param",
                param,
                "--history",
                bad,
                "--out",
                out,
            ],
            needles,
        );
    }
    expect_error(
        &[
            "friction-point",
            "--plugin",
            "/nonexistent/libnothing.so",
            "--param",
            "mu=0.1",
            "--history",
            hist,
            "--out",
            out,
        ],
        &["/nonexistent/libnothing.so"],
    );
}

#[test]
fn laws_lists_schemas_and_describe_shows_one() {
    let o = formsim(&["laws"]);
    assert!(o.status.success(), "{}", text(&o));
    let s = text(&o);
    for needle in [
        "ac",
        "wvs",
        "wh",
        "levanov",
        "convective",
        "jaumann",
        "lagrangian",
        "updated-lagrangian",
        "k_t",
        "MPa/mm",
        "flow_stress",
    ] {
        assert!(
            s.contains(needle),
            "`{needle}` missing from `formsim laws`:\n{s}"
        );
    }
    let o = formsim(&["laws", "--describe", "wvs"]);
    assert!(
        o.status.success() && text(&o).contains("nu"),
        "{}",
        text(&o)
    );
    let o = formsim(&["laws", "--describe", "nope"]);
    assert!(!o.status.success() && text(&o).contains("unknown law or formulation `nope`"));
}

#[test]
fn laws_check_runs_the_conformance_suite() {
    let o = formsim(&["laws", "check", "ac"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("0 failed"), "{}", text(&o));
}

/// The test-panicky plugin, built for this profile (once per test binary).
fn panicky_plugin() -> &'static Path {
    static BUILT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    BUILT.get_or_init(|| cli_support::plugin("test-panicky"))
}

/// What every report of the panicking plugin must say, and must not: the
/// plugin panicked, with its message; not a NaN the host never computed.
fn assert_reports_the_panic(o: &Output, message: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{}", text(o));
    assert!(
        text(o).contains(&format!("plugin test-panicky panicked: {message}")),
        "{}",
        text(o)
    );
    assert!(
        !text(o).contains("returned a non-finite") && !text(o).contains("returned NaN"),
        "{}",
        text(o)
    );
    assert!(
        err.lines().count() < 20 && !err.contains("thread '"),
        "{} lines of stderr: {}",
        err.lines().count(),
        err.chars().take(2000).collect::<String>()
    );
}

/// A plugin law that panics inside `critical_shear` is reported by the host
/// once, as `plugin test-panicky panicked: MESSAGE`, with the failing line of
/// the history; the host does not crash and the plugin prints nothing.
#[test]
fn a_panicking_plugin_is_reported_and_exits_nonzero() {
    let lib = panicky_plugin();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.csv");
    let hist = history();
    let o = formsim(&[
        "friction-point",
        "--plugin",
        lib.to_str().unwrap(),
        "--param",
        "panic_above_p=20",
        "--history",
        hist.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_reports_the_panic(&o, "test-panicky: deliberate panic at p = 20.");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    let last = err.lines().last().unwrap_or_default();
    assert!(last.starts_with("error: "), "{err}");
    assert!(
        last.contains("die-shoulder.csv:") && last.contains("in critical_shear at p = 20."),
        "the failing line of the history and the call are named: {err}"
    );
}

/// `formsim plugin check` calls the panicking law thousands of times (every
/// check, every formulation): standard error stays quiet (it held one panic
/// message per call before) and the report says `panicked`, not `NaN`.
#[test]
fn plugin_check_of_a_panicking_plugin_is_quiet_and_says_panicked() {
    let o = formsim(&[
        "plugin",
        "check",
        panicky_plugin().to_str().unwrap(),
        "--param",
        "panic_above_p=10",
    ]);
    assert_reports_the_panic(&o, "test-panicky: deliberate panic at p = ");
}

/// A forming run whose friction law panics at every contact point (on both
/// cores) stops with one line on standard error naming the plugin's panic.
#[test]
fn a_run_with_a_panicking_plugin_stops_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/block-on-plane.toml");
    let plugin = format!("contact.plugin={}", panicky_plugin().display());
    let o = formsim(&[
        "run",
        scene.to_str().unwrap(),
        "--quiet",
        "--out",
        dir.path().join("run").to_str().unwrap(),
        "--set",
        &plugin,
        "--set",
        "contact.params.plugin.panic_above_p=0.01",
    ]);
    assert_reports_the_panic(&o, "test-panicky: deliberate panic at p = ");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
}

/// `formsim COMMAND | head -1`: the reader closes the pipe, the next write
/// fails with `EPIPE`. formsim stops quietly with status 0, not with a panic
/// (status 101). The read end is closed before formsim writes anything, so the
/// very first line already meets the closed pipe (no race with the pipe buffer);
/// the second case reads one line first, as `head -1` does.
#[test]
fn a_closed_stdout_stops_quietly_without_a_panic() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    for read_first_line in [false, true] {
        for args in [
            &["laws"][..],
            &["laws", "--describe", "wvs"],
            &["laws", "check", "ac"],
        ] {
            let mut child = Command::new(env!("CARGO_BIN_EXE_formsim"))
                .args(args)
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .expect("formsim starts");
            let stdout = child.stdout.take().expect("piped stdout");
            if read_first_line {
                let mut line = String::new();
                BufReader::new(stdout).read_line(&mut line).unwrap();
                assert!(!line.is_empty(), "{args:?}: no first line");
            } else {
                drop(stdout);
            }
            let o = child.wait_with_output().expect("formsim ends");
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(
                o.status.code() == Some(0) && !err.contains("panicked") && err.is_empty(),
                "{args:?} (first line read: {read_first_line}): {:?}, stderr: {err}",
                o.status
            );
        }
    }
}

/// `--threads N` sets the simulation's worker threads (any command, before
/// or after it), recorded in `summary.json`; 0 and a non-number are refused
/// with one line naming the option.
#[test]
fn threads_option_sets_and_records_the_worker_threads() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/block-on-plane.toml");
    for (before, n) in [(true, "1"), (false, "2")] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("run");
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ];
        if before {
            args.splice(0..0, ["--threads", n]);
        } else {
            args.extend(["--threads", n]);
        }
        let o = formsim(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
        assert!(
            summary.contains(&format!("\"threads\": {n}")),
            "{n}: {summary}"
        );
    }
    for bad in ["0", "two"] {
        let o = formsim(&["--threads", bad, "laws"]);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--threads"), "{bad}: {err}");
    }
}

/// Log levels: `-v` logs the run's stages and press steps to standard
/// error, the default logs none of them, `-q` (before or after the
/// command) none either; `RUST_LOG` overrides the flags.
#[test]
fn verbose_and_quiet_choose_the_log_level() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/block-on-plane.toml");
    let run = |flags: &[&str], rust_log: Option<&str>| {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("run");
        let mut args: Vec<&str> = flags.to_vec();
        args.extend([
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_formsim"));
        cmd.args(&args).env_remove("RUST_LOG");
        if let Some(l) = rust_log {
            cmd.env("RUST_LOG", l);
        }
        let o = cmd.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let verbose = run(&["-v"], None);
    assert!(
        verbose.contains("INFO") && verbose.contains("set-up done"),
        "{verbose}"
    );
    for quiet in [run(&[], None), run(&["-q"], None)] {
        assert!(!quiet.contains("INFO"), "{quiet}");
    }
    let debug = run(&["-q"], Some("fem_core=debug"));
    assert!(
        debug.contains("DEBUG") && debug.contains("set-up"),
        "{debug}"
    );
}

/// `formsim components` lists every registry, none empty.
#[test]
fn components_lists_every_registry() {
    let o = formsim(&["components"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    for (head, member) in [
        ("Friction laws", "  ac "),
        ("Kinematic formulations", "  jaumann "),
        ("Materials", "  hill48 "),
        ("Shell elements", "  fully-integrated "),
        ("Tool kinds", "  s-rail-die "),
        ("Scene kinds", "  strip-draw "),
    ] {
        assert!(out.contains(head) && out.contains(member), "{out}");
    }
    // Each reference check's table keys, with unit, default and range.
    let keys = |check: &str| {
        out.lines()
            .skip_while(|l| !l.starts_with(&format!("  {check} ")))
            .skip(1)
            .take_while(|l| l.starts_with("    "))
            .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
            .collect::<Vec<_>>()
    };
    let capstan = keys("capstan");
    assert_eq!(capstan.len(), 5, "{out}");
    assert!(
        capstan[2].starts_with("hold_force [N] required > 0 "),
        "{capstan:?}"
    );
    assert!(
        capstan[1].starts_with("pull_dof [DOF] \"ux\" ux, uy or uz "),
        "{capstan:?}"
    );
    let strip = keys("strip-draw");
    assert!(
        strip
            .iter()
            .any(|l| l.starts_with("holder [tool] required a tool ")),
        "{strip:?}"
    );
}

/// `formsim` with `srun`'s variables of a 2-task step (`--mpi=none`) and
/// `args`, from the repository's root.
fn as_two_srun_tasks(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .env("SLURM_STEP_NUM_TASKS", "2")
        .env("SLURM_PROCID", "0")
        .args(args)
        .output()
        .unwrap()
}

/// Two copies of a command that runs in one process would each do the
/// whole work into one folder: a launcher's second copy is refused in one
/// line, before anything is written, in every build.
#[test]
fn a_run_started_as_two_launcher_tasks_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = as_two_srun_tasks(&[
        "run",
        "scenes/block-on-plane.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(
        t.contains("started as 2 processes by an MPI launcher"),
        "{t}"
    );
    assert_eq!(t.trim().lines().count(), 1, "{t}");
    assert!(!out.exists());
}

/// Without the MPI executor a study under a launcher is refused too, and the
/// line says how to get the executor; with it, `srun` without an MPI plugin
/// is told before MPI starts (which would abort in its initialisation).
#[test]
fn a_study_as_two_srun_tasks_says_what_to_do() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("study");
    let o = as_two_srun_tasks(&[
        "study",
        "scenes/block-on-plane.toml",
        "--vary",
        "blank.mesh.divisions=2",
        "--quantities",
        "punch_force_max",
        "--out",
        out.to_str().unwrap(),
    ]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    let said = if cfg!(feature = "mpi") {
        "srun started 2 tasks with no MPI plugin, so MPI cannot join them: pass --mpi=pmix"
    } else {
        "this build has no MPI executor: start one process, or build formsim with --features mpi"
    };
    assert!(t.contains(said), "{t}");
    assert_eq!(t.trim().lines().count(), 1, "{t}");
    assert!(!out.exists());
}
