//! Every `formsim` command of README.md runs: the test reads the README's
//! `sh` blocks, takes each `cargo run --release -p formsim -- …` and
//! `formsim …` line (continuations joined, comments dropped), and runs it
//! through the built binary from the repository root on a coarse, short
//! variant: the square cup and its variants on a 6 × 6 mesh for 0.2 ms, the
//! S-rail on 14 × 6 for 1 ms, identify at its smallest budget. Outputs go to
//! a temporary folder (`DIR`, `results/…`, `out/…`); `SCENE` is the square
//! cup; `target/release/lib*.so` are the plugins built here. A renamed
//! option, a moved file or a command that stopped working fails it.
//! `cargo test` and `cargo bench` lines are not run.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// The command lines of the README's `sh` blocks, continuations joined and
/// comments dropped.
fn readme_commands() -> Vec<String> {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let mut lines = Vec::new();
    let mut in_sh = false;
    let mut pending = String::new();
    for line in text.lines() {
        if line.starts_with("```") {
            in_sh = line.trim() == "```sh";
            continue;
        }
        if !in_sh {
            continue;
        }
        let line = strip_comment(line);
        let (body, continued) = match line.trim_end().strip_suffix('\\') {
            Some(b) => (b, true),
            None => (line.trim_end(), false),
        };
        pending.push_str(body.trim());
        pending.push(' ');
        if !continued {
            let cmd = pending.trim().to_string();
            if !cmd.is_empty() {
                lines.push(cmd);
            }
            pending.clear();
        }
    }
    lines
}

/// `line` without a `#` comment (a `#` after white space, outside quotes).
fn strip_comment(line: &str) -> &str {
    let mut quoted = false;
    let mut prev_space = true;
    for (i, c) in line.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted && prev_space => return &line[..i],
            _ => {}
        }
        prev_space = c.is_whitespace();
    }
    line
}

/// Split a command line as a shell would (double quotes only).
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    let mut any = false;
    for c in line.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                any = true;
            }
            c if c.is_whitespace() && !quoted => {
                if any {
                    out.push(std::mem::take(&mut word));
                    any = false;
                }
            }
            c => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        out.push(word);
    }
    out
}

/// The release plugins the README's plugin commands name, built here.
fn release_plugins() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo)
        .args(["build", "--release", "-p", "exp-decay", "-p", "j2-voce"])
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    std::env::var_os("CARGO_TARGET_DIR")
        .map_or_else(|| root().join("target"), |d| root().join(d))
        .join("release")
}

/// The coarse overrides for a command that runs `scene`.
fn coarse(command: &str, scene: &str) -> Vec<String> {
    let mut sets = vec!["output.frames=0", "output.plots=false"];
    if scene.contains("s-rail") {
        sets.extend(["blank.mesh.divisions=[14, 6]", "solver.end_time=1e-3"]);
    } else if scene.contains("u-channel") {
        // 4 mm shells (the middle-line section then has no element): the
        // first 0.2 ms only.
        sets.extend([
            "blank.mesh.divisions=[44, 2]",
            "solver.mass_scaling_dt=6.0e-7",
            "output.sections=[]",
            "solver.end_time=2e-4",
        ]);
    } else if scene.contains("square-cup") {
        sets.push("blank.mesh.divisions=6");
        if command != "identify" {
            sets.push("solver.end_time=2e-4");
        }
    }
    sets.iter()
        .flat_map(|s| ["--set".to_string(), s.to_string()])
        .collect()
}

#[test]
fn every_readme_command_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let plugins = release_plugins();
    let commands = readme_commands();
    let mut ran = 0;
    for (n, line) in commands.iter().enumerate() {
        let mut w = words(line);
        if w.first().is_some_and(|c| c == "cargo") {
            match w.iter().position(|x| x == "--") {
                Some(i) if w[..i].iter().any(|x| x == "formsim") => {
                    w.drain(..=i);
                }
                // `cargo test`, `cargo bench`: not a formsim command.
                _ => continue,
            }
        } else if w.first().is_some_and(|c| c == "formsim") {
            w.remove(0);
        } else {
            continue;
        }
        let out_dir = tmp.path().join(format!("cmd{n}"));
        let args: Vec<String> = w
            .into_iter()
            .map(|a| match a.as_str() {
                "DIR" => out_dir.display().to_string(),
                "SCENE" => "scenes/square-cup.toml".into(),
                _ if a.starts_with("results/") || a.starts_with("out/") => {
                    out_dir.join(&a).display().to_string()
                }
                _ if a.starts_with("target/release/") => plugins
                    .join(a.trim_start_matches("target/release/"))
                    .display()
                    .to_string(),
                _ => a,
            })
            .collect();
        let command = args.first().cloned().unwrap_or_default();
        let mut extra = Vec::new();
        if let Some(scene) = args.iter().find(|a| a.ends_with(".toml"))
            && matches!(command.as_str(), "run" | "compare" | "study" | "identify")
        {
            extra = coarse(&command, scene);
        }
        if command == "identify" {
            extra.extend(["--max-evaluations".into(), "3".into()]);
        }
        // `run` without `--out` writes `results/NAME` in the repository.
        if command == "run" && !args.iter().any(|a| a == "--out") {
            extra.extend(["--out".into(), out_dir.display().to_string()]);
        }
        let started = std::time::Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_formsim"))
            .args(&args)
            .args(&extra)
            .arg("-q")
            .current_dir(root())
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "README command `{line}` (run as {args:?} {extra:?}) failed:\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
        eprintln!("{:5.1} s  {line}", started.elapsed().as_secs_f64());
        ran += 1;
    }
    // Every formsim line of the README (26 today) is run; a README with
    // fewer means the parser lost some.
    assert!(ran >= 20, "only {ran} README commands found");
}
