//! End-to-end tests of `formsim tools`: export to VTU/OBJ, projection CSV, bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn formsim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_formsim"))
        .args(args)
        .output()
        .expect("formsim runs")
}

fn spec() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/tools/square-cup-tools.toml")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// `formsim tools kinds` lists the registry (linked into the binary): every
/// built-in kind once, each with its summary, and an unknown kind in a scene
/// names them all.
#[test]
fn tools_kinds_lists_the_registered_kinds() {
    let o = formsim(&["tools", "kinds"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    let names = [
        "blankholder",
        "cylinder",
        "die",
        "mesh",
        "plane",
        "punch",
        "s-rail-blankholder",
        "s-rail-die",
        "s-rail-punch",
    ];
    for name in names {
        let lines = out
            .lines()
            .filter(|l| l.split_whitespace().next() == Some(name))
            .count();
        assert_eq!(lines, 1, "{name}\n{out}");
    }
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[tools.t]\nkind = \"cone\"\n").unwrap();
    let o = formsim(&[
        "tools",
        "export",
        bad.to_str().unwrap(),
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let e = text(&o);
    assert!(
        e.contains("unknown kind `cone`") && names.iter().all(|n| e.contains(n)),
        "{e}"
    );
}

#[test]
fn tools_export_writes_vtu_and_obj_for_every_tool() {
    let dir = tempfile::tempdir().unwrap();
    let o = formsim(&[
        "tools",
        "export",
        spec().to_str().unwrap(),
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    for name in ["punch", "die", "blankholder"] {
        let vtu = std::fs::read_to_string(dir.path().join(format!("{name}.vtu"))).unwrap();
        assert!(vtu.contains("<UnstructuredGrid>") && vtu.contains("Name=\"normal\""));
        let obj = std::fs::read_to_string(dir.path().join(format!("{name}.obj"))).unwrap();
        assert!(obj.lines().any(|l| l.starts_with("f ")));
    }
}

/// Points above the punch nose (facing down at z = 0.78) and beside the die
/// shoulder: distances and curvature as drawn (docs/benchmarks.md §1 sizes).
#[test]
fn tools_project_writes_the_documented_columns() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.csv");
    std::fs::write(&input, "id,x,y,z\n1,5,5,-1.22\n2,0,0,0.0\n").unwrap();
    let out = dir.path().join("out.csv");
    let o = formsim(&[
        "tools",
        "project",
        spec().to_str().unwrap(),
        "--tool",
        "punch",
        "--points",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "px,py,pz,nx,ny,nz,distance,k1,k2,patch,u,v"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2);
    // Below the downward nose: 2 mm and 0.78 mm, normal -z, flat.
    assert!(
        (rows[0][6] - 2.0).abs() < 1e-12
            && (rows[0][5] + 1.0).abs() < 1e-14
            && rows[0][7].abs() < 1e-12
    );
    assert!((rows[1][6] - 0.78).abs() < 1e-12);
}

#[test]
fn tools_bad_input_gives_one_line_errors_and_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.csv");
    let good = dir.path().join("good.csv");
    std::fs::write(&good, "x,y,z\n1,2,3\n").unwrap();
    let cases: [(&str, &str, &str); 4] = [
        ("punch", "x,y\n1,2\n", "missing column `z`"),
        ("punch", "x,y,z\n1,NaN,3\n", "y = NaN mm is not finite"),
        ("punch", "x,y,z\n1,abc,3\n", "y = `abc` is not a number"),
        ("anvil", "x,y,z\n1,2,3\n", "unknown tool `anvil`"),
    ];
    for (tool, csv, expect) in cases {
        let input = dir.path().join("in.csv");
        std::fs::write(&input, csv).unwrap();
        let o = formsim(&[
            "tools",
            "project",
            spec().to_str().unwrap(),
            "--tool",
            tool,
            "--points",
            input.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(expect), "{err}");
    }
    // A spec with an unknown key names the tool and the key.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[tools.punch]\nkind = \"punch\"\nradius = 3.0\n").unwrap();
    let o = formsim(&[
        "tools",
        "export",
        bad.to_str().unwrap(),
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("tool `punch`") && err.contains("radius"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
}
