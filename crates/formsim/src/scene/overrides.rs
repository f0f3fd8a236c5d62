//! `--set KEY=VALUE`: overriding any scene value from the command line.
//!
//! `KEY` is a dotted path (`contact.law`, `blank.mesh.divisions`,
//! `steps[2].duration`, `contact.params.wvs.nu`); `VALUE` is read as a TOML
//! value (`0.2`, `50`, `[25, 25]`, `true`, `"text"`), and as a bare string when
//! it is not one (`wvs`). Intermediate tables are created; array entries must exist.
//! An empty value (`KEY=`) removes the key, so that its default applies
//! (`--set solver.mass_scaling_dt=`: no mass scaling).

use super::SceneError;
use super::locate::{Segment, split_path};
use toml::{Table, Value};

/// Parse `KEY=VALUE`.
///
/// # Errors
/// No `=`, an empty key, or a key with an empty segment (`blank..thickness`).
pub fn parse_assignment(text: &str) -> Result<(String, Value), SceneError> {
    let bad = |message: &str| SceneError::Override {
        assignment: text.to_string(),
        message: message.to_string(),
    };
    let (key, value) = text
        .split_once('=')
        .ok_or_else(|| bad("expected KEY=VALUE"))?;
    let key = key.trim();
    if key.is_empty() {
        return Err(bad("empty key"));
    }
    if key.split('.').any(|part| part.trim().is_empty()) {
        return Err(bad(
            "empty segment in the key (a leading, trailing or doubled `.`)",
        ));
    }
    let value = value.trim();
    let parsed = toml::from_str::<Table>(&format!("v = {value}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(value.to_string()));
    Ok((key.to_string(), parsed))
}

/// Apply one override to the scene table.
///
/// # Errors
/// A path through a value that is not a table or array, or an index past the end.
pub fn apply(
    table: &mut Table,
    key: &str,
    value: Value,
    assignment: &str,
) -> Result<(), SceneError> {
    let segments = split_path(key);
    if segments.is_empty() {
        return Err(SceneError::Override {
            assignment: assignment.to_string(),
            message: "empty key".into(),
        });
    }
    let mut root = Value::Table(std::mem::take(table));
    let result = set_in(&mut root, &segments, value).map_err(|e| SceneError::Override {
        assignment: assignment.to_string(),
        message: e.to_string(),
    });
    if let Value::Table(t) = root {
        *table = t;
    }
    result
}

/// Why an override's path cannot be followed (the message of
/// [`SceneError::Override`]).
#[derive(Debug, thiserror::Error)]
enum PathError {
    /// An index past the end of an array.
    #[error("index [{index}] past the end ({len} entries)")]
    PastEnd { index: usize, len: usize },
    /// An empty value on an array entry (only keys can be removed).
    #[error("an array entry ([{index}]) cannot be removed")]
    RemoveEntry { index: usize },
    /// A key inside a value that is not a table.
    #[error("cannot set `{key}` inside a {kind}")]
    NotTable { key: String, kind: &'static str },
    /// An index into a value that is not an array.
    #[error("cannot index [{index}] into a {kind}")]
    NotArray { index: usize, kind: &'static str },
}

fn set_in(node: &mut Value, path: &[Segment], value: Value) -> Result<(), PathError> {
    let (first, rest) = path.split_first().expect("non-empty path");
    let child: &mut Value = match (first, node) {
        (Segment::Key(k), Value::Table(t)) => {
            if rest.is_empty() {
                if value.as_str() == Some("") {
                    t.remove(k);
                } else {
                    t.insert(k.clone(), value);
                }
                return Ok(());
            }
            t.entry(k.clone())
                .or_insert_with(|| Value::Table(Table::new()))
        }
        (Segment::Index(i), Value::Array(a)) => {
            let n = a.len();
            let slot = a
                .get_mut(*i)
                .ok_or(PathError::PastEnd { index: *i, len: n })?;
            if rest.is_empty() {
                if value.as_str() == Some("") {
                    return Err(PathError::RemoveEntry { index: *i });
                }
                *slot = value;
                return Ok(());
            }
            slot
        }
        (Segment::Key(k), other) => {
            return Err(PathError::NotTable {
                key: k.clone(),
                kind: other.type_str(),
            });
        }
        (Segment::Index(i), other) => {
            return Err(PathError::NotArray {
                index: *i,
                kind: other.type_str(),
            });
        }
    };
    set_in(child, rest, value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_nested_keys_arrays_and_bare_strings() {
        let mut t: Table =
            toml::from_str("[contact]\nlaw = \"ac\"\n[[steps]]\nduration = 1.0\n").unwrap();
        for a in [
            "contact.law=wvs",
            "contact.params.wvs.nu=0.8",
            "steps[0].duration=2e-3",
            "blank.mesh.divisions=[25, 25]",
        ] {
            let (k, v) = parse_assignment(a).unwrap();
            apply(&mut t, &k, v, a).unwrap();
        }
        assert_eq!(t["contact"]["law"].as_str(), Some("wvs"));
        assert_eq!(t["contact"]["params"]["wvs"]["nu"].as_float(), Some(0.8));
        assert_eq!(t["steps"][0]["duration"].as_float(), Some(2e-3));
        assert_eq!(
            t["blank"]["mesh"]["divisions"].as_array().map(Vec::len),
            Some(2)
        );
        let (k, v) = parse_assignment("steps[3].duration=1").unwrap();
        let e = apply(&mut t, &k, v, "steps[3].duration=1")
            .unwrap_err()
            .to_string();
        assert!(e.contains("past the end"), "{e}");
        assert!(parse_assignment("novalue").is_err());
    }

    #[test]
    fn an_empty_value_removes_the_key() {
        let mut t: Table = toml::from_str(
            "[solver]\nmass_scaling_dt = 5e-7\nsafety_factor = 0.9\n[[steps]]\nduration = 1.0\n",
        )
        .unwrap();
        let (k, v) = parse_assignment("solver.mass_scaling_dt=").unwrap();
        apply(&mut t, &k, v, "solver.mass_scaling_dt=").unwrap();
        assert!(t["solver"].get("mass_scaling_dt").is_none());
        assert_eq!(t["solver"]["safety_factor"].as_float(), Some(0.9));
        let (k, v) = parse_assignment("steps[0]=").unwrap();
        let e = apply(&mut t, &k, v, "steps[0]=").unwrap_err().to_string();
        assert!(e.contains("cannot be removed"), "{e}");
    }

    /// `blank..thickness` once set a key named "" inside `blank`; a key with
    /// an empty segment is refused, naming it.
    #[test]
    fn an_empty_path_segment_is_refused() {
        for a in [
            "blank..thickness=1",
            ".blank=1",
            "blank.=1",
            "steps[0]. .duration=1",
        ] {
            let e = parse_assignment(a).unwrap_err().to_string();
            assert!(e.contains("empty segment"), "{a}: {e}");
            assert!(e.contains(a.split('=').next().unwrap()), "{a}: {e}");
        }
    }
}
