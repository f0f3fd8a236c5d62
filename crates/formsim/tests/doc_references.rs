//! Every file that the repository's documents, comments, CLI strings and
//! scenes refer to exists in the repository (a clone alone explains
//! everything it references).
//!
//! Scanned: `README.md`, `docs/**/*.md`, `crates/**/*.{rs,md,toml}`,
//! `scenes/**/*.toml`, `plugins/**/*.{rs,md,toml}`, `tests/**/*.{rs,toml}`
//! (no `target/`). Checked in each file:
//!
//! 1. relative Markdown links `[text](path)` (in `.md` files and in `//`
//!    comments of `.rs` files), resolved against the file's directory;
//! 2. repository paths written out: `docs/…`, `scenes/…`, `crates/…`,
//!    `plugins/…` and `tests/…` ending in a file extension, resolved against
//!    the repository root;
//! 3. bare document names such as `friction-math.md`, `design.md`,
//!    `style.md`: they must name a file in the same directory, in `docs/` or
//!    at the root;
//! 4. section citations `friction-math §N`, `benchmarks.md §N`,
//!    `architecture.md §N`: the document must have a heading `## N.`;
//! 5. nothing points outside the repository (`../shared/…`, `shared/docs`,
//!    `shared/data`).

use std::path::{Path, PathBuf};

/// The workspace root (two levels above this crate).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("workspace root")
}

/// Extensions scanned under each top-level entry.
const SCANNED: &[(&str, &[&str])] = &[
    ("README.md", &["md"]),
    ("docs", &["md"]),
    ("crates", &["rs", "md", "toml"]),
    ("scenes", &["toml"]),
    ("plugins", &["rs", "md", "toml"]),
    ("tests", &["rs", "toml"]),
];

/// Extensions that make a written-out path a file reference (rule 2).
const FILE_EXTENSIONS: &[&str] = &[
    "md", "rs", "toml", "csv", "png", "svg", "json", "inp", "msh",
];

/// Top-level directories whose written-out paths are checked (rule 2).
const ROOTED: &[&str] = &["docs/", "scenes/", "crates/", "plugins/", "tests/"];

/// Documents whose `§N` citations are checked (rule 4), as `docs/NAME.md`.
const SECTIONED: &[&str] = &["friction-math", "benchmarks", "architecture"];

/// Files that formsim writes (not repository files), named bare in docs.
const GENERATED: &[&str] = &["compare.md", "study.md"];

/// Placeholder names in paths that stand for any file (`scenes/NAME.toml`);
/// one-letter names are placeholders too (`scenes/x.toml` in a sample error).
const PLACEHOLDERS: &[&str] = &["NAME", "DIR", "LAW", "FILE", "SCENE", "PATH"];

fn is_placeholder(path: &str) -> bool {
    path.split('/').any(|part| {
        let stem = part.split('.').next().unwrap_or(part);
        stem.len() == 1 || PLACEHOLDERS.contains(&stem)
    })
}

/// A path that is a whole string literal of Rust code is data the code uses
/// (a file name in a test's temporary directory, say), not a citation.
fn is_string_literal(file: &Path, text: &str, offset: usize, token: &str) -> bool {
    file.extension().is_some_and(|e| e == "rs")
        && text[..offset].ends_with('"')
        && text[offset + token.len()..].starts_with('"')
}

/// `path` exists from the repository root, or from some crate's directory.
fn exists_in_repository(root: &Path, path: &str) -> bool {
    if root.join(path).exists() {
        return true;
    }
    std::fs::read_dir(root.join("crates"))
        .map(|dirs| {
            dirs.filter_map(Result::ok)
                .any(|d| d.path().join(path).exists())
        })
        .unwrap_or(false)
}

fn collect(path: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    if path.is_file() {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| extensions.contains(&e))
        {
            out.push(path.to_path_buf());
        }
        return;
    }
    let Ok(entries) = std::fs::read_dir(path) else {
        return;
    };
    let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name == "target" || name.starts_with('.') {
            continue;
        }
        collect(&p, extensions, out);
    }
}

/// The files scanned.
fn scanned_files(root: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for (entry, extensions) in SCANNED {
        collect(&root.join(entry), extensions, &mut files);
    }
    files
}

/// Characters that can belong to a path as written in prose or code.
fn is_path_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/')
}

/// Maximal runs of path characters, with their byte offsets, trailing
/// punctuation (a sentence's full stop) removed.
fn tokens(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices().chain([(text.len(), ' ')]) {
        match (is_path_char(c), start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                let token = text[s..i].trim_end_matches(['.', '/', '-']);
                if !token.is_empty() {
                    out.push((s, token));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

fn extension(token: &str) -> Option<&str> {
    let name = token.rsplit('/').next()?;
    let (stem, ext) = name.rsplit_once('.')?;
    (!stem.is_empty()).then_some(ext)
}

/// Targets of Markdown links `[text](target)` in `text` that look like
/// relative file paths (not URLs, anchors, or rustdoc intra-doc links).
fn markdown_links(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        rest = &rest[i + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split_whitespace().next().unwrap_or("");
        let path = target.split('#').next().unwrap_or("");
        let looks_like_path = !path.is_empty()
            && !target.contains("://")
            && !target.starts_with("mailto:")
            && !target.contains("::")
            && (path.contains('/') || extension(path).is_some());
        if looks_like_path {
            out.push(path);
        }
    }
    out
}

/// The text of `file` in which links are checked: all of a Markdown file,
/// the `//` comment lines of a Rust file, nothing else.
fn link_text(file: &Path, text: &str) -> String {
    match file.extension().and_then(|e| e.to_str()) {
        Some("md") => text.to_string(),
        Some("rs") => text
            .lines()
            .filter(|l| l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n"),
        _ => String::new(),
    }
}

/// Headings `## N.` of a document.
fn sections(doc: &Path) -> Vec<String> {
    std::fs::read_to_string(doc)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| l.strip_prefix("## "))
        .filter_map(|l| l.split_once('.').map(|(n, _)| n.trim().to_string()))
        .collect()
}

/// Every problem found in `text` (the contents of `file`), as messages.
fn problems(root: &Path, file: &Path, text: &str) -> Vec<String> {
    let rel = file
        .strip_prefix(root)
        .unwrap_or(file)
        .display()
        .to_string();
    let dir = file.parent().unwrap_or(root);
    let line_of = |offset: usize| text[..offset].matches('\n').count() + 1;
    let mut out = Vec::new();

    // 1. Relative Markdown links.
    for target in markdown_links(&link_text(file, text)) {
        if target.contains("shared/") {
            continue; // reported by rule 5 with its line
        }
        let base = if target.starts_with('/') { root } else { dir };
        if !base.join(target.trim_start_matches('/')).exists() {
            out.push(format!("{rel}: link to `{target}`, which does not exist"));
        }
    }

    for (offset, token) in tokens(text) {
        let line = line_of(offset);
        // 5. Nothing outside the repository.
        if token.contains("../shared")
            || token.contains("shared/docs")
            || token.contains("shared/data")
        {
            out.push(format!(
                "{rel}:{line}: `{token}` points outside the repository"
            ));
            continue;
        }
        let Some(ext) = extension(token) else {
            continue;
        };
        let path = token.trim_start_matches("./");
        if is_placeholder(path) || is_string_literal(file, text, offset, token) {
            continue;
        }
        // 2. Paths from the repository root (or from a crate's directory:
        //    `tests/x.rs` in a crate's own documentation).
        if ROOTED.iter().any(|p| path.starts_with(p)) {
            if FILE_EXTENSIONS.contains(&ext) && !exists_in_repository(root, path) {
                out.push(format!(
                    "{rel}:{line}: `{token}` does not exist in the repository"
                ));
            }
        } else if ext == "md" && !path.contains('/') && !GENERATED.contains(&path) {
            // 3. Bare document names.
            let found = [dir, &root.join("docs"), root]
                .iter()
                .any(|d| d.join(path).is_file());
            if !found {
                out.push(format!(
                    "{rel}:{line}: `{token}` names no file in {}, docs/ or the root",
                    dir.strip_prefix(root).unwrap_or(dir).display()
                ));
            }
        }
    }

    // 4. Section citations.
    for (offset, token) in tokens(text) {
        let name = token.trim_start_matches("docs/").trim_end_matches(".md");
        if !SECTIONED.contains(&name) || name.contains('/') {
            continue;
        }
        let after = text[offset + token.len()..].trim_start_matches('.');
        let Some(cited) = after.trim_start().strip_prefix('§') else {
            continue;
        };
        let number: String = cited.chars().take_while(char::is_ascii_digit).collect();
        if number.is_empty() {
            continue;
        }
        let doc = root.join("docs").join(format!("{name}.md"));
        if !sections(&doc).contains(&number) {
            out.push(format!(
                "{rel}:{}: `{name} §{number}`: docs/{name}.md has no section `## {number}.`",
                line_of(offset)
            ));
        }
    }
    out
}

#[test]
fn every_referenced_file_exists_in_the_repository() {
    let root = root();
    let files = scanned_files(&root);
    assert!(
        files.len() > 100 && files.iter().any(|f| f.ends_with("docs/friction-math.md")),
        "the scan found {} files: is the repository layout as expected?",
        files.len()
    );
    let mut all = Vec::new();
    // This file quotes broken references on purpose (the checker's own test).
    let own = root.join("crates/formsim/tests/doc_references.rs");
    for file in files.iter().filter(|f| **f != own) {
        let text = std::fs::read_to_string(file).unwrap_or_default();
        all.extend(problems(&root, file, &text));
    }
    assert!(
        all.is_empty(),
        "{} reference(s) to files that are not in the repository:\n{}",
        all.len(),
        all.join("\n")
    );
}

/// The checker itself finds each kind of broken reference (so a passing
/// scan means something), and accepts the good ones.
#[test]
fn the_checker_finds_broken_references() {
    let root = root();
    let doc = root.join("docs/example.md");
    let cases = [
        ("see [the maths](friction-math.md)", false),
        ("see [nothing](no-such-file.md)", true),
        ("see [up](../README.md#documents)", false),
        ("see docs/friction-math.md §4", false),
        ("see docs/friction-math.md §9", true),
        ("(friction-math §2) and friction-math §5.", false),
        ("friction-math §8", true),
        ("benchmarks.md §3, architecture.md §5", false),
        ("see docs/no-such.md.", true),
        ("see design.md", true),
        ("see style.md", true),
        ("read ../shared/docs/friction-math.md", true),
        ("scenes/square-cup.toml and scenes/nope.toml", true),
        (
            "a URL [x](https://example.invalid/a.md) is not checked",
            false,
        ),
        ("`tests/twisted_beam.rs` of shell-elements", false),
        ("`tests/no_such_test.rs`", true),
        ("any `scenes/NAME.toml`; compare's own `compare.md`", false),
        ("error: scenes/x.toml:30: blank.material.r_values", false),
    ];
    for (text, broken) in cases {
        let found = problems(&root, &doc, text);
        assert_eq!(!found.is_empty(), broken, "{text}: {found:?}");
    }
    // In Rust files, links count in comments only; rustdoc paths are not files.
    let rs = root.join("crates/formsim/src/lib.rs");
    assert!(problems(&root, &rs, "/// [`Foo`](crate::foo::Foo)").is_empty());
    assert!(!problems(&root, &rs, "/// [x](missing.md)").is_empty());
    // A whole string literal is data; a path inside a sentence is a citation.
    assert!(problems(&root, &rs, r#"let p = "docs/energy.csv";"#).is_empty());
    assert!(!problems(&root, &rs, r#""see docs/energy.csv""#).is_empty());
}
