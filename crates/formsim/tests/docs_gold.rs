//! The headline tables of `docs/` are the gold files (`tests/gold/*.json`):
//! every `<!-- gold:NAME -->` … `<!-- /gold:NAME -->` block of `docs/*.md`
//! is the table generated from `tests/gold/NAME.json`, and every gold file
//! has a block somewhere. With `FORMSIM_BLESS=1` the test rewrites the
//! blocks instead of failing. And the checks the tests run against the gold
//! files fail when they must.

// Each test binary that includes the gold checks uses a part of them.
#[allow(dead_code)]
#[path = "common/gold.rs"]
mod gold;

use gold::{Gold, GoldFile, Tolerance};
use std::ops::Range;
use std::path::PathBuf;

/// Every gold file, in the order of their names.
fn gold_files() -> Vec<GoldFile> {
    let mut stems: Vec<String> = std::fs::read_dir(gold::dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    stems.sort();
    assert!(!stems.is_empty(), "no gold file in tests/gold");
    stems.iter().map(|c| GoldFile::read(c)).collect()
}

/// Every `docs/*.md`, with its text.
fn docs() -> Vec<(PathBuf, String)> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(gold::root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p, text)
        })
        .collect()
}

/// The gold blocks of `text`: each case and the byte range from its opening
/// marker to the end of its closing marker; an opening marker with no
/// closing one is an error.
fn blocks(text: &str) -> Result<Vec<(String, Range<usize>)>, String> {
    const OPEN: &str = "<!-- gold:";
    let mut found = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find(OPEN).map(|i| i + from) {
        let name_end = text[i..]
            .find(" -->")
            .map(|j| i + j)
            .ok_or_else(|| format!("an unterminated marker at byte {i}"))?;
        let case = text[i + OPEN.len()..name_end].to_string();
        let close = format!("<!-- /gold:{case} -->");
        let end = text[name_end..]
            .find(&close)
            .map(|j| name_end + j + close.len())
            .ok_or_else(|| format!("`<!-- gold:{case} -->` has no `{close}`"))?;
        found.push((case, i..end));
        from = end;
    }
    Ok(found)
}

/// Every gold block of `docs/*.md` is its gold file's table, and every gold
/// file has a block (`FORMSIM_BLESS=1` rewrites the blocks that differ).
#[test]
fn docs_gold_tables_match_the_gold_files() {
    let bless = std::env::var("FORMSIM_BLESS").is_ok_and(|v| v == "1");
    let files = gold_files();
    let mut failures = Vec::new();
    let mut shown = std::collections::BTreeSet::new();
    for (path, text) in docs() {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let found = match blocks(&text) {
            Ok(found) => found,
            Err(e) => {
                failures.push(format!("docs/{name}: {e}"));
                continue;
            }
        };
        let mut out = String::new();
        let mut at = 0;
        for (case, range) in found {
            out += &text[at..range.start];
            at = range.end;
            let Some(file) = files.iter().find(|f| f.case == case) else {
                failures.push(format!(
                    "docs/{name}: `<!-- gold:{case} -->` names no file tests/gold/{case}.json"
                ));
                out += &text[range];
                continue;
            };
            shown.insert(case.clone());
            let table = file.table();
            if text[range.clone()] != table && !bless {
                failures.push(format!(
                    "docs/{name}: the gold table of {case} differs from tests/gold/{case}.json; \
                     it should read (or run with FORMSIM_BLESS=1):\n{table}"
                ));
            }
            out += &table;
        }
        out += &text[at..];
        if bless && out != text {
            std::fs::write(&path, out).unwrap();
            eprintln!("rewrote the gold tables of docs/{name}");
        }
    }
    for f in &files {
        if !shown.contains(&f.case) {
            failures.push(format!(
                "tests/gold/{0}.json has no table in docs/: put `<!-- gold:{0} -->` and \
                 `<!-- /gold:{0} -->` where it belongs and run with FORMSIM_BLESS=1",
                f.case
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// How far from `gold` a value must be to fail `tolerance`: twice the bound
/// (1 where the bound is 0).
fn outside(gold: f64, tolerance: Tolerance) -> f64 {
    let bound = match tolerance {
        Tolerance::Rel(r) => r * gold.abs(),
        Tolerance::Abs(a) => a,
    };
    if bound > 0.0 { 2.0 * bound } else { 1.0 }
}

/// The checks against the gold files can fail: for every file, every figure
/// at its gold value passes; moved by twice its tolerance each fails, named
/// with the value, the gold value, the tolerance and the source; a figure
/// never checked fails, and so does a name the file lacks or a NaN.
#[test]
fn gold_checks_fail_outside_tolerance_and_on_unchecked_figures() {
    for file in gold_files() {
        let case = file.case.as_str();
        let mut failures = Vec::new();
        let mut g = Gold::load(case);
        for (name, f) in &file.figures {
            g.check(&mut failures, name, f.value);
        }
        g.finish(&mut failures);
        assert!(failures.is_empty(), "{case}: {failures:#?}");

        let mut g = Gold::load(case);
        for (name, f) in &file.figures {
            let x = f.value + outside(f.value, f.tolerance);
            g.check(&mut failures, name, x);
            let last = failures.last().map_or("", String::as_str);
            for needle in [
                name.as_str(),
                &format!("{x:?}"),
                &format!("gold {:?}", f.value),
                &f.tolerance.text(),
                &f.source,
            ] {
                assert!(last.contains(needle), "{case}: `{needle}` not in `{last}`");
            }
        }
        g.finish(&mut failures);
        assert_eq!(failures.len(), file.figures.len(), "{case}: {failures:#?}");

        failures.clear();
        let mut g = Gold::load(case);
        let (first, _) = file.figures.first_key_value().unwrap();
        g.check(&mut failures, first, f64::NAN);
        g.check(&mut failures, "no-such-figure", 0.0);
        g.finish(&mut failures);
        assert_eq!(
            failures.len(),
            file.figures.len() + 1,
            "{case}: {failures:#?}"
        );
        assert!(
            failures
                .iter()
                .any(|l| l.contains("no gold figure `no-such-figure`"))
        );
        assert_eq!(
            failures
                .iter()
                .filter(|l| l.contains("was never checked"))
                .count(),
            file.figures.len() - 1,
            "{case}"
        );

        // A part holds the figures `PART.*`, named without the prefix.
        if let Some((part, _)) = first.split_once('.') {
            let prefix = format!("{part}.");
            let mut failures = Vec::new();
            let mut g = Gold::part(case, part);
            g.finish(&mut failures);
            let names = file.figures.keys().filter(|k| k.starts_with(&prefix));
            assert_eq!(failures.len(), names.count(), "{case}: {failures:#?}");
            assert!(failures.iter().all(|l| l.contains(&format!("[{part}]"))));
        }
    }
}

/// `summary` with `value` at the dotted `key`.
fn put(summary: &mut serde_json::Value, key: &str, value: f64) {
    let mut at = summary;
    for k in key.split('.') {
        at = at
            .as_object_mut()
            .unwrap()
            .entry(k)
            .or_insert(serde_json::json!({}));
    }
    *at = serde_json::json!(value);
}

/// A `summary.json` figure is read by its dotted key (each figure passes
/// with its gold value at its key), and a key the summary lacks is a
/// failure, not a pass.
#[test]
fn gold_summary_keys_are_read_and_missing_ones_fail() {
    for file in gold_files() {
        let case = file.case.as_str();
        let keyed: Vec<(&str, &str, f64)> = file
            .figures
            .iter()
            .filter_map(|(n, f)| f.summary_key.as_deref().map(|k| (n.as_str(), k, f.value)))
            .collect();
        let unkeyed = || file.figures.iter().filter(|(_, f)| f.summary_key.is_none());
        for &(name, key, value) in &keyed {
            // Every key at some figure's gold value, this figure's last (two
            // figures may read one key: an analytic and a regression value).
            let mut summary = serde_json::json!({});
            for &(_, k, v) in &keyed {
                put(&mut summary, k, v);
            }
            put(&mut summary, key, value);
            let (mut failures, mut g) = (Vec::new(), Gold::load(case));
            g.check_summary(&mut failures, &summary);
            for (n, f) in unkeyed() {
                g.check(&mut failures, n, f.value);
            }
            g.finish(&mut failures);
            assert!(
                !failures.iter().any(|l| l.contains(&format!(": {name} = "))
                    || l.contains("no number")
                    || l.contains("never checked")),
                "{case}: {name}: {failures:#?}"
            );
        }

        let (mut failures, mut g) = (Vec::new(), Gold::load(case));
        g.check_summary(&mut failures, &serde_json::json!({}));
        for (n, f) in unkeyed() {
            g.check(&mut failures, n, f.value);
        }
        g.finish(&mut failures);
        assert_eq!(failures.len(), keyed.len(), "{case}: {failures:#?}");
        assert!(
            failures
                .iter()
                .all(|l| l.contains("summary.json has no number"))
        );
    }
}
