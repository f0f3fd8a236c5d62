//! Parameter schemas (name, unit, default, valid range, one-line doc) and user values.

use std::collections::BTreeMap;

use crate::FrictionError;

/// A `KEY=VALUE` assignment (`--param`) that cannot be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AssignmentError {
    /// No `=` in the text.
    #[error("parameter `{0}` is not of the form KEY=VALUE")]
    NotKeyValue(String),
    /// The value is not a number.
    #[error("parameter `{key}`: `{value}` is not a number")]
    NotANumber {
        /// The key as given.
        key: String,
        /// The value text as given.
        value: String,
    },
}

/// One parameter of a component, as `formsim laws` prints it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// Key as typed in scenes and on the command line (`mu`, `k_t`, …).
    pub name: &'static str,
    /// Unit in the scene unit system (mm, N, MPa, tonne, s); `-` if dimensionless.
    pub unit: &'static str,
    /// Default value; `None` makes the parameter required.
    pub default: Option<f64>,
    /// Lower bound.
    pub min: f64,
    /// Whether the lower bound itself is excluded (`> min` rather than `≥ min`).
    pub min_exclusive: bool,
    /// Upper bound (inclusive); `f64::INFINITY` for none.
    pub max: f64,
    /// One-line description.
    pub doc: &'static str,
}

impl ParamSpec {
    /// A required parameter with range `[min, max]`.
    #[must_use]
    pub const fn required(
        name: &'static str,
        unit: &'static str,
        min: f64,
        max: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: None,
            min,
            min_exclusive: false,
            max,
            doc,
        }
    }

    /// A parameter with a default value and range `[min, max]`.
    #[must_use]
    pub const fn optional(
        name: &'static str,
        unit: &'static str,
        default: f64,
        min: f64,
        max: f64,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            unit,
            default: Some(default),
            min,
            min_exclusive: false,
            max,
            doc,
        }
    }

    /// The same parameter with an exclusive lower bound (`> min`).
    #[must_use]
    pub const fn exclusive_min(mut self) -> Self {
        self.min_exclusive = true;
        self
    }

    /// The valid range as text: `> 0`, `>= 0 and <= 1`, `any finite value`.
    #[must_use]
    pub fn range_text(&self) -> String {
        let lo = if self.min == f64::NEG_INFINITY {
            None
        } else if self.min_exclusive {
            Some(format!("> {}", self.min))
        } else {
            Some(format!(">= {}", self.min))
        };
        let hi = (self.max != f64::INFINITY).then(|| format!("<= {}", self.max));
        match (lo, hi) {
            (Some(l), Some(h)) => format!("{l} and {h}"),
            (Some(l), None) => l,
            (None, Some(h)) => h,
            (None, None) => "any finite value".to_string(),
        }
    }

    /// `value` itself if it is finite and inside the range, else the error
    /// naming the parameter of `component`, its value, unit and valid range.
    ///
    /// # Errors
    /// [`FrictionError::ParameterOutOfRange`].
    pub fn check(&self, component: &str, value: f64) -> Result<f64, FrictionError> {
        if self.accepts(value) {
            Ok(value)
        } else {
            Err(FrictionError::ParameterOutOfRange {
                component: component.to_string(),
                name: self.name.to_string(),
                value,
                unit: self.unit.to_string(),
                range: self.range_text(),
            })
        }
    }

    /// Whether `value` is finite and inside the range.
    #[must_use]
    pub fn accepts(&self, value: f64) -> bool {
        value.is_finite()
            && (if self.min_exclusive {
                value > self.min
            } else {
                value >= self.min
            })
            && value <= self.max
    }
}

/// Parameter values given by a user (scene, command line), by key.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params(pub BTreeMap<String, f64>);

impl Params {
    /// No values given: every default applies.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Builder-style insertion.
    #[must_use]
    pub fn with(mut self, key: &str, value: f64) -> Self {
        self.0.insert(key.to_string(), value);
        self
    }

    /// Set one value.
    pub fn set(&mut self, key: &str, value: f64) {
        self.0.insert(key.to_string(), value);
    }

    /// Parse `KEY=VALUE` (as given to `--param`).
    ///
    /// # Errors
    /// [`AssignmentError`], naming the malformed text.
    pub fn parse_assignment(text: &str) -> Result<(String, f64), AssignmentError> {
        let (key, value) = text
            .split_once('=')
            .ok_or_else(|| AssignmentError::NotKeyValue(text.to_string()))?;
        let (key, value) = (key.trim(), value.trim());
        let number: f64 = value.parse().map_err(|_| AssignmentError::NotANumber {
            key: key.to_string(),
            value: value.to_string(),
        })?;
        Ok((key.to_string(), number))
    }

    /// Check the values against `specs` and return one value per spec, in order
    /// (given value or default).
    ///
    /// # Errors
    /// Unknown key, missing required parameter, or value out of range (non-finite
    /// included), each naming the parameter, its unit and range.
    pub fn resolve(&self, component: &str, specs: &[ParamSpec]) -> Result<Vec<f64>, FrictionError> {
        for key in self.0.keys() {
            if !specs.iter().any(|s| s.name == key) {
                return Err(FrictionError::UnknownParameter {
                    component: component.to_string(),
                    name: key.clone(),
                    known: if specs.is_empty() {
                        "none, it takes no parameters".to_string()
                    } else {
                        specs.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
                    },
                });
            }
        }
        specs
            .iter()
            .map(|spec| {
                let value = match (self.0.get(spec.name), spec.default) {
                    (Some(v), _) => *v,
                    (None, Some(d)) => d,
                    (None, None) => {
                        return Err(FrictionError::MissingParameter {
                            component: component.to_string(),
                            name: spec.name.to_string(),
                            unit: spec.unit.to_string(),
                            doc: spec.doc.to_string(),
                        });
                    }
                };
                spec.check(component, value)
            })
            .collect()
    }
}

/// Check `values` against `specs` (count, finiteness and range of each value),
/// as [`Params::resolve`] does: for builders that receive values in schema
/// order (typed law constructors, the plugin loader).
///
/// # Errors
/// [`FrictionError::InvalidParameters`] for a wrong number of values;
/// [`FrictionError::ParameterOutOfRange`] naming the first offending parameter,
/// its value, unit and valid range.
pub fn check_values(law: &str, specs: &[ParamSpec], values: &[f64]) -> Result<(), FrictionError> {
    if values.len() != specs.len() {
        return Err(FrictionError::InvalidParameters {
            component: law.to_string(),
            reason: format!(
                "expected {} parameter values ({}), got {}",
                specs.len(),
                specs.iter().map(|s| s.name).collect::<Vec<_>>().join(", "),
                values.len()
            ),
        });
    }
    for (spec, &value) in specs.iter().zip(values) {
        spec.check(law, value)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECS: [ParamSpec; 2] = [
        ParamSpec::required("mu", "-", 0.0, 10.0, "friction coefficient"),
        ParamSpec::optional("k_t", "MPa/mm", 1e5, 0.0, f64::INFINITY, "stick stiffness")
            .exclusive_min(),
    ];

    #[test]
    fn defaults_fill_in_and_order_follows_specs() {
        let v = Params::new().with("mu", 0.1).resolve("ac", &SPECS).unwrap();
        assert_eq!(v, vec![0.1, 1e5]);
    }

    #[test]
    fn errors_name_the_parameter_unit_and_range() {
        let e = Params::new()
            .with("mu", 0.1)
            .with("k_t", 0.0)
            .resolve("ac", &SPECS)
            .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("k_t") && text.contains("MPa/mm") && text.contains("> 0"),
            "{text}"
        );
        let e = Params::new().resolve("ac", &SPECS).unwrap_err().to_string();
        assert!(e.contains("missing parameter `mu`"), "{e}");
        let e = Params::new()
            .with("muu", 1.0)
            .resolve("ac", &SPECS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("muu") && e.contains("known: mu, k_t"), "{e}");
        let e = Params::new()
            .with("mu", f64::NAN)
            .resolve("ac", &SPECS)
            .unwrap_err()
            .to_string();
        assert!(e.contains("NaN"), "{e}");
    }

    #[test]
    fn assignment_parsing() {
        assert_eq!(
            Params::parse_assignment("mu=0.1").unwrap(),
            ("mu".into(), 0.1)
        );
        assert!(Params::parse_assignment("mu").is_err());
        assert_eq!(
            Params::parse_assignment("mu=abc").unwrap_err().to_string(),
            "parameter `mu`: `abc` is not a number"
        );
    }
}
