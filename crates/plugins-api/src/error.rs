//! Errors of the friction core: every message names the field, the value and the unit.

use thiserror::Error;

/// Everything that can go wrong while building or running a friction model.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FrictionError {
    /// A parameter name that the component does not know.
    #[error("unknown parameter `{name}` for `{component}`; known: {known}")]
    UnknownParameter {
        /// Component (law) name.
        component: String,
        /// The offending key.
        name: String,
        /// Comma-separated list of valid keys.
        known: String,
    },
    /// A required parameter without a default was not given.
    #[error("missing parameter `{name}` ({unit}) for `{component}`: {doc}")]
    MissingParameter {
        /// Component (law) name.
        component: String,
        /// Parameter name.
        name: String,
        /// Unit of the parameter.
        unit: String,
        /// One-line description.
        doc: String,
    },
    /// A parameter outside its valid range (or not finite).
    #[error(
        "parameter `{name}` = {value} {unit} of `{component}` is out of range: must be {range}"
    )]
    ParameterOutOfRange {
        /// Component (law) name.
        component: String,
        /// Parameter name.
        name: String,
        /// Value given.
        value: f64,
        /// Unit of the parameter.
        unit: String,
        /// Human-readable valid range, e.g. `> 0`.
        range: String,
    },
    /// A combination of parameters that is invalid although each is in range.
    #[error("invalid parameters of `{component}`: {reason}")]
    InvalidParameters {
        /// Component (law) name.
        component: String,
        /// What is wrong.
        reason: String,
    },
    /// Non-finite or out-of-domain point input (NaN, infinity, negative pressure…).
    #[error("invalid point input `{field}` = {value} {unit}: {reason}")]
    InvalidInput {
        /// Field name, e.g. `p` or `du`.
        field: &'static str,
        /// Offending value (first bad component for vectors).
        value: f64,
        /// Unit.
        unit: &'static str,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A law or formulation produced a non-finite number or a negative `τ_c`.
    #[error("`{component}` returned {what} ({value}) at p = {p} MPa")]
    NonFiniteResult {
        /// Component that produced it.
        component: String,
        /// What was wrong, with its article (e.g. `a negative critical shear stress`).
        what: &'static str,
        /// The value.
        value: f64,
        /// Pressure at which it happened.
        p: f64,
    },
    /// A component name that is not registered.
    #[error("unknown {kind} `{name}`; known: {known}")]
    UnknownComponent {
        /// `law` or `formulation`.
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// Comma-separated known names.
        known: String,
    },
    /// Code inside a dynamic plugin panicked; the plugin caught the panic (it
    /// never unwinds into the host) and passed its message on.
    #[error("plugin {name} panicked: {message}; in {call} ({path})")]
    PluginPanicked {
        /// The plugin's law name.
        name: String,
        /// Path of the shared library.
        path: String,
        /// Which call panicked, e.g. `critical_shear at p = 150 MPa`.
        call: String,
        /// The panic's message, with where in the plugin's source it happened.
        message: String,
    },
    /// A dynamic plugin could not be loaded or misbehaved.
    #[error("plugin {path}: {reason}")]
    Plugin {
        /// Path of the shared library.
        path: String,
        /// What went wrong.
        reason: String,
    },
}
