//! End-to-end tests of the `formsim` command line: friction-point, laws, bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn formsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .output()
        .expect("formsim runs")
}

fn history() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/point-histories/die-shoulder.csv")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
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

/// A plugin law that panics inside `critical_shear` is reported by the host with
/// the panic message and a non-zero exit; the host does not crash.
#[test]
fn a_panicking_plugin_is_reported_and_exits_nonzero() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let release = !cfg!(debug_assertions);
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root)
        .args(["build", "-q", "-p", "test-panicky"]);
    if release {
        cmd.arg("--release");
    }
    assert!(cmd.status().unwrap().success());
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| root.join("target"), PathBuf::from);
    let lib = target
        .join(if release { "release" } else { "debug" })
        .join(format!(
            "{}test_panicky{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        ));
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
    assert!(!o.status.success(), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    let last = err.lines().last().unwrap_or_default();
    assert!(
        last.starts_with("error: ") && last.contains("deliberate panic"),
        "{err}"
    );
    assert!(
        last.contains("die-shoulder.csv:"),
        "the failing line of the history is named: {err}"
    );
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
