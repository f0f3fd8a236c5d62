//! Errors of tool construction and input reading: each names the patch (or file, tool, key) and the field.

use thiserror::Error;

/// Why a surface, tool, mesh or tool specification cannot be built.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NurbsError {
    /// A degree outside the supported range.
    #[error("patch {patch}: degree_{dir} = {value} is outside 1..={max}")]
    Degree {
        /// Patch index.
        patch: usize,
        /// Parameter direction, `u` or `v`.
        dir: char,
        /// Given degree.
        value: usize,
        /// Largest supported degree.
        max: usize,
    },
    /// A knot vector whose length does not match the control net.
    #[error(
        "patch {patch}: knots_{dir} has {len} values, expected {expected} (control points {count} + degree {degree} + 1)"
    )]
    KnotCount {
        /// Patch index.
        patch: usize,
        /// Parameter direction.
        dir: char,
        /// Given length.
        len: usize,
        /// Expected length.
        expected: usize,
        /// Control points in this direction.
        count: usize,
        /// Degree in this direction.
        degree: usize,
    },
    /// An inconsistent knot value.
    #[error("patch {patch}: knots_{dir}[{index}] = {value} {problem}")]
    Knot {
        /// Patch index.
        patch: usize,
        /// Parameter direction.
        dir: char,
        /// Knot index.
        index: usize,
        /// Knot value (parameter units).
        value: f64,
        /// What is wrong with it.
        problem: &'static str,
    },
    /// Too few control points, or a point count that does not match the net.
    #[error("patch {patch}: {field} has {len} entries, expected {expected}")]
    NetSize {
        /// Patch index.
        patch: usize,
        /// Field name (`points`, `weights`).
        field: &'static str,
        /// Given count.
        len: usize,
        /// Expected count.
        expected: usize,
    },
    /// A zero, negative or non-finite weight.
    #[error("patch {patch}: weights[{index}] = {value} must be finite and > 0")]
    Weight {
        /// Patch index.
        patch: usize,
        /// Control point index (u-major: `i_u * count_v + i_v`).
        index: usize,
        /// Given weight.
        value: f64,
    },
    /// A non-finite control point.
    #[error("patch {patch}: points[{index}] = ({x}, {y}, {z}) mm is not finite")]
    Point {
        /// Patch index.
        patch: usize,
        /// Control point index.
        index: usize,
        /// x (mm).
        x: f64,
        /// y (mm).
        y: f64,
        /// z (mm).
        z: f64,
    },
    /// A control net whose surface has no normal somewhere (collapsed edge, folded net).
    #[error(
        "patch {patch}: control net is degenerate at (u, v) = ({u}, {v}): S_u × S_v vanishes there, the normal is undefined"
    )]
    Degenerate {
        /// Patch index.
        patch: usize,
        /// Parameter u.
        u: f64,
        /// Parameter v.
        v: f64,
    },
    /// A builder parameter out of its range.
    #[error("tool `{tool}`: {key} = {value} {unit} {reason}")]
    Param {
        /// Tool name.
        tool: String,
        /// Parameter key as the spec spells it.
        key: String,
        /// Given value.
        value: f64,
        /// Unit of the value.
        unit: &'static str,
        /// Why it is refused.
        reason: String,
    },
    /// A tool without any surface.
    #[error("tool `{tool}` has no patches or facets")]
    Empty {
        /// Tool name.
        tool: String,
    },
    /// A mesh or spec file that cannot be read or parsed.
    #[error("{path}: {message}")]
    File {
        /// File path.
        path: String,
        /// What went wrong (line number where known).
        message: String,
    },
    /// An export file that cannot be written.
    #[error("{path}: cannot write: {message}")]
    Write {
        /// File path.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A tool specification that is not understood.
    #[error("tool spec: {message}")]
    Spec {
        /// What went wrong, naming the tool and key.
        message: String,
    },
}
