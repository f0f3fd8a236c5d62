//! Gold files: the headline figures of a benchmark in `tests/gold/NAME.json`
//! (repository root), each with its value, unit, tolerance and source, and
//! the checks the tests run against them.
//!
//! A test loads a file ([`Gold::load`]), or the figures of one part of it
//! ([`Gold::part`]: `hard-cases.json` holds `PART.FIGURE` for every hard
//! case), compares every figure it measures ([`Gold::check`], and
//! [`Gold::check_summary`] for the figures read from `summary.json` by their
//! `summary_key`), then calls [`Gold::finish`]: every figure outside its
//! tolerance, named with its value, the gold value, the tolerance and the
//! source, and every figure the test never checked (a gold file must not go
//! stale), fail the test together. `FORMSIM_GOLD_PRINT=1` prints every
//! value checked, in full.
//!
//! The same files generate the tables of `docs/` between
//! `<!-- gold:NAME -->` markers ([`GoldFile::table`], `docs_gold.rs`).

use serde::Deserialize;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A gold file as stored.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoldFile {
    /// The case's name: the file's stem.
    pub case: String,
    /// The command whose results the figures are (run from the repository's root).
    pub command: String,
    /// The test or tests that compare against the figures.
    pub checked_by: String,
    /// How the regression tolerances were measured.
    pub tolerance_basis: String,
    /// The figures by name.
    pub figures: BTreeMap<String, Figure>,
}

/// One figure of a gold file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure {
    /// The gold value.
    pub value: f64,
    /// Its unit (`-` for a ratio).
    pub unit: String,
    /// How far a measured value may be from it.
    pub tolerance: Tolerance,
    /// Where the value comes from: an analytic or published reference, or
    /// `regression: ...` (this program's own result).
    pub source: String,
    /// The figure's dotted key in `summary.json`, when it is read from there.
    #[serde(default)]
    pub summary_key: Option<String>,
}

/// A tolerance, relative to the gold value or absolute (in its unit).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum Tolerance {
    /// `|x − gold| ≤ rel × |gold|`.
    Rel(f64),
    /// `|x − gold| ≤ abs`.
    Abs(f64),
}

impl Tolerance {
    /// Whether `x` is within the tolerance of `gold` (never for a NaN).
    pub fn admits(self, gold: f64, x: f64) -> bool {
        let bound = match self {
            Self::Rel(r) => r * gold.abs(),
            Self::Abs(a) => a,
        };
        (x - gold).abs() <= bound
    }

    /// As the docs' tables show it: `rel 1e-6` or `abs 0.005`.
    pub fn text(self) -> String {
        match self {
            Self::Rel(r) => format!("rel {r:?}"),
            Self::Abs(a) => format!("abs {a:?}"),
        }
    }
}

/// The repository's root (this module is also included on its own, by
/// `docs_gold.rs`, so it does not lean on `common`).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The directory of the gold files.
pub fn dir() -> PathBuf {
    root().join("tests/gold")
}

impl GoldFile {
    /// Read `tests/gold/NAME.json` for `case` = NAME; panics naming the file
    /// if it does not read or its `case` is not its name.
    pub fn read(case: &str) -> Self {
        let path = dir().join(format!("{case}.json"));
        let text =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let file: Self =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!(file.case, case, "{}: `case`", path.display());
        for (name, f) in &file.figures {
            let t = match f.tolerance {
                Tolerance::Rel(t) | Tolerance::Abs(t) => t,
            };
            assert!(
                f.value.is_finite() && t.is_finite() && t >= 0.0 && !f.source.is_empty(),
                "{}: figure {name}: a finite value, a tolerance >= 0 and a source",
                path.display()
            );
        }
        file
    }

    /// The Markdown block the docs carry between `<!-- gold:NAME -->` and
    /// `<!-- /gold:NAME -->` (markers included).
    pub fn table(&self) -> String {
        let mut s = format!("<!-- gold:{} -->\n", self.case);
        s += &format!(
            "Gold figures of `{}` (`tests/gold/{}.json`, checked by {}; generated from the file, \
             `FORMSIM_BLESS=1 cargo test --release -p formsim --test docs_gold` rewrites this table):\n\n",
            self.command, self.case, self.checked_by
        );
        s += "| figure | value | unit | tolerance | source |\n|---|---:|---|---|---|\n";
        for (name, f) in &self.figures {
            let key = f
                .summary_key
                .as_ref()
                .map_or(String::new(), |k| format!(" (`{k}`)"));
            s += &format!(
                "| {name}{key} | {:?} | {} | {} | {} |\n",
                f.value,
                f.unit,
                f.tolerance.text(),
                f.source.replace('|', "\\|")
            );
        }
        s += &format!("\n{}\n", self.tolerance_basis);
        s += &format!("<!-- /gold:{} -->", self.case);
        s
    }
}

/// The figures a test compares against, and which of them it has checked.
#[derive(Debug)]
pub struct Gold {
    /// What the failures name: the file, and the part if any.
    label: String,
    /// The figures by name (within the part).
    figures: BTreeMap<String, Figure>,
    /// Names checked so far.
    checked: BTreeSet<String>,
    /// Whether [`Gold::finish`] was called.
    finished: bool,
}

impl Gold {
    /// Every figure of the gold file `case` (`tests/gold/NAME.json`).
    pub fn load(case: &str) -> Self {
        let file = GoldFile::read(case);
        Self {
            label: format!("tests/gold/{case}.json"),
            figures: file.figures,
            checked: BTreeSet::new(),
            finished: false,
        }
    }

    /// The figures `PART.FIGURE` of the gold file `case`, named `FIGURE`
    /// (panics if there is none: a test must have something to compare).
    pub fn part(case: &str, part: &str) -> Self {
        let file = GoldFile::read(case);
        let prefix = format!("{part}.");
        let figures: BTreeMap<String, Figure> = file
            .figures
            .into_iter()
            .filter_map(|(k, f)| k.strip_prefix(&prefix).map(|n| (n.to_string(), f)))
            .collect();
        assert!(
            !figures.is_empty(),
            "tests/gold/{case}.json has no figure `{prefix}*`"
        );
        Self {
            label: format!("tests/gold/{case}.json [{part}]"),
            figures,
            checked: BTreeSet::new(),
            finished: false,
        }
    }

    /// Compare the measured `value` of figure `name` with its gold value;
    /// a figure outside its tolerance, or a name the file lacks, adds a
    /// line to `failures`. With `FORMSIM_GOLD_PRINT=1` every value checked
    /// is printed in full (what a gold value is taken from).
    pub fn check(&mut self, failures: &mut Vec<String>, name: &str, value: f64) {
        if std::env::var("FORMSIM_GOLD_PRINT").is_ok_and(|v| v == "1") {
            eprintln!("gold {}: {name} = {value:?}", self.label);
        }
        let Some(f) = self.figures.get(name) else {
            failures.push(format!("{}: no gold figure `{name}`", self.label));
            return;
        };
        self.checked.insert(name.to_string());
        if !f.tolerance.admits(f.value, value) {
            let off = if f.value == 0.0 {
                String::new()
            } else {
                format!(" ({:+.3e} relative)", value / f.value - 1.0)
            };
            failures.push(format!(
                "{}: {name} = {value:?} {}, gold {:?} {}{off}, tolerance {}, source: {}",
                self.label,
                f.unit,
                f.value,
                f.unit,
                f.tolerance.text(),
                f.source
            ));
        }
    }

    /// [`Gold::check`] every figure that has a `summary_key` against that
    /// dotted key of `summary` (`summary.json` as a value); a key missing
    /// or not a number is a failure.
    pub fn check_summary(&mut self, failures: &mut Vec<String>, summary: &serde_json::Value) {
        let keyed: Vec<(String, String)> = self
            .figures
            .iter()
            .filter_map(|(n, f)| f.summary_key.clone().map(|k| (n.clone(), k)))
            .collect();
        for (name, key) in keyed {
            let value = key
                .split('.')
                .try_fold(summary, |v, k| v.get(k))
                .and_then(serde_json::Value::as_f64);
            match value {
                Some(v) => self.check(failures, &name, v),
                None => {
                    self.checked.insert(name.clone());
                    failures.push(format!(
                        "{}: {name}: summary.json has no number at `{key}`",
                        self.label
                    ));
                }
            }
        }
    }

    /// Add every figure never checked to `failures` (the file would go
    /// stale); call once, after the checks.
    pub fn finish(&mut self, failures: &mut Vec<String>) {
        self.finished = true;
        for name in self.figures.keys() {
            if !self.checked.contains(name) {
                failures.push(format!(
                    "{}: gold figure `{name}` was never checked",
                    self.label
                ));
            }
        }
    }
}

impl Drop for Gold {
    fn drop(&mut self) {
        if !self.finished && !std::thread::panicking() {
            panic!("{}: Gold::finish was not called", self.label);
        }
    }
}

/// Assert that every part (`PART` of the figure names `PART.FIGURE`) of
/// the gold file `case` is named as the string literal `"PART"` in
/// `source`, the text of the test file that checks the parts: no figure
/// goes unchecked because its test was removed or renamed.
pub fn assert_parts_named(case: &str, source: &str) {
    let file = GoldFile::read(case);
    let parts: BTreeSet<&str> = file
        .figures
        .keys()
        .map(|k| k.split_once('.').map_or(k.as_str(), |(p, _)| p))
        .collect();
    for part in parts {
        assert!(
            source.contains(&format!("\"{part}\"")),
            "tests/gold/{case}.json: part `{part}` is checked by no test of the file that checks it"
        );
    }
}

/// Fail with every line of `failures`, if any (at the caller's line).
#[track_caller]
pub fn assert_none(failures: &[String]) {
    assert!(
        failures.is_empty(),
        "{} gold figure(s) failed:\n  {}",
        failures.len(),
        failures.join("\n  ")
    );
}

/// Compare `figures` (name, value) with the figures `PART.*` of
/// the case's gold file: every figure outside its tolerance, and every gold
/// figure of the part not given, fail together (at the caller's line).
#[track_caller]
pub fn check_part(case: &str, part: &str, figures: &[(&str, f64)]) {
    let mut g = Gold::part(case, part);
    let mut failures = Vec::new();
    for &(name, value) in figures {
        g.check(&mut failures, name, value);
    }
    g.finish(&mut failures);
    assert_none(&failures);
}
