//! The `[output.KEY]` table of a reference check: the keys the check
//! declares ([`TableKey`]: name, unit or what it names, default, range, one
//! line of doc) and the table a scene gives, resolved against them
//! ([`CheckTable`]).
//!
//! `[output]`'s own keys ([`super::schema::Output::OWN_KEYS`]) are read by
//! the typed scene; every other table in `[output]` is a reference check's.
//! [`take_tables`] lifts those out of the scene's TOML before the typed scene
//! is read, and [`resolve_all`] resolves each against the keys of the
//! registered check ([`super::kind::ReferenceCheck`]) whose `key` it is. A
//! table no check claims, a key the check does not declare, a value of the
//! wrong type or out of range: each is one line naming the key.

use super::kind::ReferenceCheck;
use super::schema::Output;
use super::validate::number;
use plugins_api::ParamSpec;
use serde::Serialize;
use std::collections::BTreeMap;

/// One key of a reference check's `[output.KEY]` table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TableKey {
    /// A number, with its unit, default and range.
    Number(ParamSpec),
    /// A name: of a node set, a tool, a DOF.
    Name(NameSpec),
}

/// A key whose value is a name (a TOML string).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NameSpec {
    /// The key as written in the table.
    pub key: &'static str,
    /// What the value names (`node set`, `tool`, `DOF`).
    pub names: &'static str,
    /// Default value; `None` makes the key required.
    pub default: Option<&'static str>,
    /// The accepted values; empty: any name.
    pub one_of: &'static [&'static str],
    /// One-line description.
    pub doc: &'static str,
}

impl NameSpec {
    /// A required key naming a `names` (`node set`, `tool`, …).
    #[must_use]
    pub const fn required(key: &'static str, names: &'static str, doc: &'static str) -> Self {
        Self {
            key,
            names,
            default: None,
            one_of: &[],
            doc,
        }
    }

    /// The same key, accepting only `values`.
    #[must_use]
    pub const fn one_of(mut self, values: &'static [&'static str]) -> Self {
        self.one_of = values;
        self
    }

    /// The same key, `default` when the table does not give it.
    #[must_use]
    pub const fn or(mut self, default: &'static str) -> Self {
        self.default = Some(default);
        self
    }
}

impl TableKey {
    /// The key as written in the table.
    #[must_use]
    pub const fn key(&self) -> &'static str {
        match self {
            Self::Number(p) => p.name,
            Self::Name(n) => n.key,
        }
    }

    /// Its unit (`N`, `s`, `-`), or what it names (`node set`).
    #[must_use]
    pub const fn unit(&self) -> &'static str {
        match self {
            Self::Number(p) => p.unit,
            Self::Name(n) => n.names,
        }
    }

    /// Its one line of doc.
    #[must_use]
    pub const fn doc(&self) -> &'static str {
        match self {
            Self::Number(p) => p.doc,
            Self::Name(n) => n.doc,
        }
    }

    /// Its default as written in a scene (`"ux"`, `0.5`), or `required`.
    #[must_use]
    pub fn default_text(&self) -> String {
        match self {
            Self::Number(ParamSpec {
                default: Some(d), ..
            }) => format!("{d}"),
            Self::Name(NameSpec {
                default: Some(d), ..
            }) => format!("\"{d}\""),
            _ => "required".to_string(),
        }
    }

    /// What it accepts: `> 0`, `ux, uy or uz`, `a name`.
    #[must_use]
    pub fn range_text(&self) -> String {
        match self {
            Self::Number(p) => p.range_text(),
            Self::Name(n) => match n.one_of {
                [] => format!("a {}", n.names),
                [only] => (*only).to_string(),
                [first @ .., last] => format!("{} or {last}", first.join(", ")),
            },
        }
    }

    /// `value` as this key reads it, or the message of why it cannot.
    fn read(&self, value: &toml::Value) -> Result<TableValue, String> {
        match (self, value) {
            (Self::Number(p), toml::Value::Float(_) | toml::Value::Integer(_)) => {
                // An integer reads as the float it names, as serde reads it.
                let v = match value {
                    toml::Value::Integer(i) => *i as f64,
                    _ => value.as_float().unwrap_or(f64::NAN),
                };
                if p.accepts(v) {
                    Ok(TableValue::Number(v))
                } else {
                    Err(format!(
                        "{} {}: must be {}",
                        number(v),
                        p.unit,
                        finite_and(p)
                    ))
                }
            }
            (Self::Number(p), other) => {
                Err(format!("{}: expected a number in {}", shown(other), p.unit))
            }
            (Self::Name(n), toml::Value::String(s)) => {
                if n.one_of.is_empty() || n.one_of.contains(&s.as_str()) {
                    Ok(TableValue::Name(s.clone()))
                } else {
                    Err(format!("\"{s}\": must be {}", self.range_text()))
                }
            }
            (Self::Name(n), other) => Err(format!(
                "{}: expected a string, the {}'s name",
                shown(other),
                n.names
            )),
        }
    }

    /// The value when the table does not give the key.
    fn default_value(&self) -> Option<TableValue> {
        match self {
            Self::Number(p) => p.default.map(TableValue::Number),
            Self::Name(n) => n.default.map(|d| TableValue::Name(d.to_string())),
        }
    }
}

/// `finite and > 0`, or `finite` for a number of any finite value.
fn finite_and(p: &ParamSpec) -> String {
    if p.min == f64::NEG_INFINITY && p.max == f64::INFINITY {
        "finite".to_string()
    } else {
        format!("finite and {}", p.range_text())
    }
}

/// A TOML value in a one-line message: a scalar as written, with its type;
/// an array or a table by its type alone.
fn shown(v: &toml::Value) -> String {
    let article = |t: &str| {
        if t.starts_with(['a', 'e', 'i', 'o', 'u']) {
            "an"
        } else {
            "a"
        }
    };
    let t = v.type_str();
    match v {
        toml::Value::Array(_) | toml::Value::Table(_) => format!("{} {t}", article(t)),
        scalar => format!("{scalar} ({} {t})", article(t)),
    }
}

/// A value of a resolved table.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TableValue {
    /// A number, in its key's unit.
    Number(f64),
    /// A name.
    Name(String),
}

/// A reference check's `[output.KEY]` table, resolved against the check's
/// keys: every declared key with its value, given or default.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct CheckTable(BTreeMap<&'static str, TableValue>);

impl CheckTable {
    /// The number under `key` (`None` for a key the check did not declare
    /// as a number).
    #[must_use]
    pub fn number(&self, key: &str) -> Option<f64> {
        match self.0.get(key)? {
            TableValue::Number(v) => Some(*v),
            TableValue::Name(_) => None,
        }
    }

    /// The name under `key` (`None` for a key the check did not declare as
    /// a name).
    #[must_use]
    pub fn name(&self, key: &str) -> Option<&str> {
        match self.0.get(key)? {
            TableValue::Name(s) => Some(s),
            TableValue::Number(_) => None,
        }
    }
}

/// What is wrong in a check's table: the dotted key and the message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TableError {
    /// `output.TABLE` or `output.TABLE.KEY`.
    pub key: String,
    /// What is wrong, naming the value and the unit or type expected.
    pub message: String,
}

/// `table`, the value of `[output.NAME]`, resolved against `keys`.
///
/// # Errors
/// A value that is not a table, a key `keys` does not declare, a required
/// key missing, a value of the wrong type, out of range or not one of the
/// accepted names.
pub fn resolve(
    name: &str,
    table: &toml::Value,
    keys: &[TableKey],
) -> Result<CheckTable, TableError> {
    let at = |key: Option<&str>, message: String| TableError {
        key: match key {
            Some(k) => format!("output.{name}.{k}"),
            None => format!("output.{name}"),
        },
        message,
    };
    let key_list = || {
        keys.iter()
            .map(TableKey::key)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let toml::Value::Table(given) = table else {
        return Err(at(
            None,
            format!("{}: expected a table {{ {} }}", shown(table), key_list()),
        ));
    };
    if let Some(unknown) = given.keys().find(|k| !keys.iter().any(|s| s.key() == *k)) {
        return Err(at(
            Some(unknown),
            format!("unknown key in [output.{name}] (its keys: {})", key_list()),
        ));
    }
    let mut resolved = BTreeMap::new();
    for spec in keys {
        let value = match given.get(spec.key()) {
            Some(v) => spec.read(v).map_err(|m| at(Some(spec.key()), m))?,
            None => spec.default_value().ok_or_else(|| {
                at(
                    Some(spec.key()),
                    format!(
                        "missing from [output.{name}]: {} ({}), {}",
                        spec.key(),
                        spec.unit(),
                        spec.doc()
                    ),
                )
            })?,
        };
        resolved.insert(spec.key(), value);
    }
    Ok(CheckTable(resolved))
}

/// Lift the reference checks' tables out of `scene`, the scene's TOML:
/// every entry of `[output]` that is not one of its own keys and is a table
/// or the `key` of one of `checks` (whatever its type, so that a value that
/// is not a table is named as such).
pub fn take_tables(scene: &mut toml::Table, checks: &[&ReferenceCheck]) -> toml::Table {
    let Some(toml::Value::Table(output)) = scene.get_mut("output") else {
        return toml::Table::new();
    };
    let theirs: Vec<String> = output
        .iter()
        .filter(|(k, v)| {
            !Output::OWN_KEYS.contains(&k.as_str())
                && (v.is_table() || checks.iter().any(|c| c.key == k.as_str()))
        })
        .map(|(k, _)| k.clone())
        .collect();
    theirs
        .into_iter()
        .filter_map(|k| output.remove(&k).map(|v| (k, v)))
        .collect()
}

/// Each table of `taken` ([`take_tables`]) resolved against the keys of the
/// check of `checks` whose `key` it is.
///
/// # Errors
/// A table that no check claims (naming the tables there are), or the first
/// error of [`resolve`].
pub fn resolve_all(
    taken: &toml::Table,
    checks: &[&ReferenceCheck],
) -> Result<BTreeMap<String, CheckTable>, TableError> {
    taken
        .iter()
        .map(|(name, table)| {
            let check = checks.iter().find(|c| c.key == name).ok_or_else(|| {
                let claimed: Vec<String> = checks
                    .iter()
                    .map(|c| format!("[output.{}] of {}", c.key, c.name))
                    .collect();
                TableError {
                    key: format!("output.{name}"),
                    message: format!(
                        "no registered reference check reads [output.{name}] (the checks' tables: {})",
                        if claimed.is_empty() {
                            "none registered".to_string()
                        } else {
                            claimed.join(", ")
                        }
                    ),
                }
            })?;
            Ok((name.clone(), resolve(name, table, check.keys)?))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const KEYS: &[TableKey] = &[
        TableKey::Name(NameSpec::required("pull_set", "node set", "the set pulled")),
        TableKey::Name(
            NameSpec::required("pull_dof", "DOF", "the DOF pulled")
                .one_of(&["ux", "uy", "uz"])
                .or("ux"),
        ),
        TableKey::Number(
            ParamSpec::required("hold_force", "N", 0.0, f64::INFINITY, "the holding load")
                .exclusive_min(),
        ),
        TableKey::Number(ParamSpec::optional(
            "average_from",
            "s",
            0.0,
            0.0,
            f64::INFINITY,
            "start of the mean",
        )),
    ];

    fn table(text: &str) -> toml::Value {
        toml::Value::Table(toml::from_str(text).unwrap())
    }

    fn error(text: &str) -> TableError {
        resolve("capstan", &table(text), KEYS).unwrap_err()
    }

    /// Given values are read (an integer as its float), defaults fill in.
    #[test]
    fn values_resolve_with_defaults() {
        let t = resolve(
            "capstan",
            &table("pull_set = \"pull\"\nhold_force = 200"),
            KEYS,
        )
        .unwrap();
        assert_eq!(t.name("pull_set"), Some("pull"));
        assert_eq!(t.name("pull_dof"), Some("ux"));
        assert_eq!(t.number("hold_force"), Some(200.0));
        assert_eq!(t.number("average_from"), Some(0.0));
        assert_eq!(t.number("pull_set"), None);
        assert_eq!(t.name("hold_force"), None);
        assert_eq!(t.number("nosuch"), None);
    }

    /// Each error is one line at the key, naming the value and the unit or
    /// type expected.
    #[test]
    fn errors_name_the_key_value_and_unit() {
        for (text, key, says) in [
            (
                "pull_set = \"p\"\nhold_force = 1\nhold = 2",
                "output.capstan.hold",
                "unknown key in [output.capstan] (its keys: pull_set, pull_dof, hold_force, average_from)",
            ),
            (
                "pull_set = \"p\"\nhold_force = \"heavy\"",
                "output.capstan.hold_force",
                "\"heavy\" (a string): expected a number in N",
            ),
            (
                "pull_set = 3\nhold_force = 1",
                "output.capstan.pull_set",
                "3 (an integer): expected a string, the node set's name",
            ),
            (
                "pull_set = \"p\"\nhold_force = 0.0",
                "output.capstan.hold_force",
                "0 N: must be finite and > 0",
            ),
            (
                "pull_set = \"p\"\nhold_force = nan",
                "output.capstan.hold_force",
                "NaN N: must be finite and > 0",
            ),
            (
                "pull_set = \"p\"\nhold_force = 1\npull_dof = \"rx\"",
                "output.capstan.pull_dof",
                "\"rx\": must be ux, uy or uz",
            ),
            (
                "pull_set = \"p\"",
                "output.capstan.hold_force",
                "missing from [output.capstan]: hold_force (N), the holding load",
            ),
            (
                "pull_set = [\"p\"]\nhold_force = 1",
                "output.capstan.pull_set",
                "an array: expected a string",
            ),
        ] {
            let e = error(text);
            assert_eq!(e.key, key, "{text}");
            assert!(e.message.contains(says), "{text}: {}", e.message);
            assert!(!e.message.contains('\n'), "{}", e.message);
        }
        let e = resolve("capstan", &toml::Value::Integer(5), KEYS).unwrap_err();
        assert_eq!(e.key, "output.capstan");
        assert!(
            e.message.contains(
                "5 (an integer): expected a table { pull_set, pull_dof, hold_force, average_from }"
            ),
            "{}",
            e.message
        );
    }

    /// The listing's texts of a key.
    #[test]
    fn keys_describe_themselves() {
        assert_eq!(KEYS[0].default_text(), "required");
        assert_eq!(KEYS[0].range_text(), "a node set");
        assert_eq!(KEYS[1].default_text(), "\"ux\"");
        assert_eq!(KEYS[1].range_text(), "ux, uy or uz");
        assert_eq!(KEYS[2].range_text(), "> 0");
        assert_eq!(KEYS[3].default_text(), "0");
        assert_eq!(KEYS[2].unit(), "N");
        assert_eq!(KEYS[0].unit(), "node set");
    }
}
