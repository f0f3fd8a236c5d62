//! Errors of contact set-up and of a contact step: each names the pair, the node or the field.

use thiserror::Error;

/// Everything contact can refuse or fail at.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ContactError {
    /// A set-up value out of range.
    #[error("contact pair `{pair}`: `{field}` = {value} {unit} is out of range: must be {range}")]
    OutOfRange {
        /// Contact pair name.
        pair: String,
        /// Field name as in the scene.
        field: &'static str,
        /// Value given.
        value: f64,
        /// Unit.
        unit: &'static str,
        /// What is allowed.
        range: &'static str,
    },
    /// The blank mesh handed to contact is inconsistent.
    #[error("contact: blank mesh: {0}")]
    Mesh(String),
    /// A tool query failed (a non-finite node position).
    #[error("contact pair `{pair}`, node {node}: {source}")]
    Tool {
        /// Contact pair name.
        pair: String,
        /// Blank node index.
        node: usize,
        /// The tool's error.
        source: Box<plugins_api::ToolError>,
    },
    /// The friction model refused a point (non-finite input or a plugin error).
    #[error("contact pair `{pair}`, node {node}: friction: {source}")]
    Friction {
        /// Contact pair name.
        pair: String,
        /// Blank node index.
        node: usize,
        /// The friction core's error.
        source: Box<plugins_api::FrictionError>,
    },
    /// The pair refers to a tool that is not there.
    #[error("contact pair `{pair}`: tool index {tool} out of range ({count} tools)")]
    NoSuchTool {
        /// Contact pair name.
        pair: String,
        /// Tool index.
        tool: usize,
        /// Number of tools given.
        count: usize,
    },
}
