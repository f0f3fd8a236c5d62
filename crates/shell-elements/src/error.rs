//! `ShellError`: what can be wrong with a shell set-up (parameters, thickness, element geometry).

use thiserror::Error;

/// Errors raised while building materials, sections or shell sets.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ShellError {
    /// A material or section parameter outside its valid range (or not finite).
    #[error("parameter `{field}` = {value} {unit} is out of range: must be {range}")]
    InvalidParameter {
        /// Field name, e.g. `poisson` or `swift.n`.
        field: &'static str,
        /// Value given.
        value: f64,
        /// Unit (`-` for dimensionless).
        unit: &'static str,
        /// Valid range in words, e.g. `in [0, 0.5)`.
        range: &'static str,
    },
    /// A tabulated hardening curve that is not usable.
    #[error("hardening table row {row}: {reason} (eps_p = {eps_p}, sigma_y = {sigma_y} MPa)")]
    BadTable {
        /// 0-based row index.
        row: usize,
        /// What is wrong.
        reason: &'static str,
        /// Plastic strain of the row (-).
        eps_p: f64,
        /// Flow stress of the row (MPa).
        sigma_y: f64,
    },
    /// A material or element choice that is not registered or does not fit
    /// the values given (the message says which and lists the choices).
    #[error("{0}")]
    InvalidInput(String),
    /// An element that cannot be used (zero area, inverted or non-convex corner, bad node index).
    #[error("element {element}: {reason} ({measure} = {value})")]
    BadElement {
        /// Element index within the set, 0-based.
        element: usize,
        /// What is wrong.
        reason: &'static str,
        /// Name of the measured quantity, with its unit.
        measure: &'static str,
        /// Its value.
        value: f64,
    },
}

impl From<ShellError> for fem_core::FemError {
    fn from(e: ShellError) -> Self {
        match e {
            ShellError::BadElement {
                element,
                reason,
                measure,
                value,
            } => fem_core::FemError::BadElement {
                element,
                reason: reason.to_string(),
                measure,
                value,
            },
            other => fem_core::FemError::InvalidSetup(other.to_string()),
        }
    }
}

/// Check that `value` is finite and satisfies `ok`, else name the field.
pub(crate) fn check(
    field: &'static str,
    value: f64,
    unit: &'static str,
    range: &'static str,
    ok: bool,
) -> Result<(), ShellError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(ShellError::InvalidParameter {
            field,
            value,
            unit,
            range,
        })
    }
}
