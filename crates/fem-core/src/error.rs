//! Errors of the explicit engine: every message names the node, element or field, the value and the unit.

use thiserror::Error;

/// Everything that can go wrong while building a mesh, setting up or running the explicit solver.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FemError {
    /// A quad refers to a node index that does not exist.
    #[error("element {element}: node index {node} is out of range (mesh has {n_nodes} nodes)")]
    NodeOutOfRange {
        /// Element (quad) index, 0-based.
        element: usize,
        /// Offending node index.
        node: u64,
        /// Number of nodes in the mesh.
        n_nodes: usize,
    },
    /// A quad lists the same node twice.
    #[error("element {element}: node {node} appears twice in its connectivity")]
    DuplicateNode {
        /// Element (quad) index, 0-based.
        element: usize,
        /// The repeated node index.
        node: u32,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node}: coordinate {axis} = {value} mm is not finite")]
    NonFiniteCoordinate {
        /// Node index, 0-based.
        node: usize,
        /// `x`, `y` or `z`.
        axis: &'static str,
        /// The value.
        value: f64,
    },
    /// A quad with (nearly) zero area, inverted or non-convex corners, or too much distortion.
    #[error("element {element}: {reason} ({measure} = {value})")]
    BadElement {
        /// Element (quad) index, 0-based.
        element: usize,
        /// What is wrong, e.g. `zero area`, `inverted or non-convex at node 17`.
        reason: String,
        /// Name of the measured quantity, with its unit.
        measure: &'static str,
        /// Its value.
        value: f64,
    },
    /// A node or element set name that the mesh does not hold.
    #[error("unknown {kind} `{name}`; known: {known}")]
    UnknownSet {
        /// `node set` or `element set`.
        kind: &'static str,
        /// The requested name.
        name: String,
        /// Comma-separated list of the sets that exist.
        known: String,
    },
    /// A set refers to an index that does not exist.
    #[error("{kind} `{name}`: index {index} is out of range (mesh has {len})")]
    SetOutOfRange {
        /// `node set` or `element set`.
        kind: &'static str,
        /// Set name.
        name: String,
        /// Offending index.
        index: u64,
        /// Number of nodes or elements.
        len: usize,
    },
    /// A mesh file that cannot be read or parsed.
    #[error("{file}:{line}: {message}")]
    Parse {
        /// File path as given.
        file: String,
        /// 1-based line number (0 when the file could not be opened).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A setting or parameter outside its valid range (or not finite).
    #[error("parameter `{field}` = {value} {unit} is out of range: must be {range}")]
    InvalidParameter {
        /// Field name, e.g. `safety_factor`.
        field: String,
        /// Value given.
        value: f64,
        /// Unit (`-` for dimensionless).
        unit: &'static str,
        /// Human-readable valid range, e.g. `in (0, 1]`.
        range: &'static str,
    },
    /// An inconsistent set-up that no single parameter explains.
    #[error("invalid set-up: {0}")]
    InvalidSetup(String),
    /// The static solve of an implicit springback failed (an effect without
    /// a static form, a singular system, no convergence after the last
    /// cut-back): the model stays at its last converged increment.
    #[error("implicit springback: {0}")]
    ImplicitSpringback(String),
    /// A fixed time step ([`SolverSettings::fixed_dt`](crate::SolverSettings::fixed_dt))
    /// is above the stable limit at some step: the run stops before the
    /// step that would go unstable.
    #[error(
        "the fixed time step {dt:e} s is above the stable limit {stable:.4e} s of {location} \
         at step {step} (t = {time:.4e} s); lower `fixed_dt` below the limit"
    )]
    StepAboveStableLimit {
        /// Time reached (s).
        time: f64,
        /// Step number.
        step: u64,
        /// The fixed step (s).
        dt: f64,
        /// The stable limit (s), without safety factor.
        stable: f64,
        /// What limits it: an element of an effect, or a node and the
        /// effects that stiffen it together.
        location: String,
    },
    /// The stable time step collapsed (below the floor or not finite) during a run.
    #[error(
        "time step collapsed at t = {time} s (step {step}): dt = {dt:e} s < floor {floor:e} s, \
         limited by element {element} of `{effect}` ({what})"
    )]
    TimeStepCollapse {
        /// Time reached (s).
        time: f64,
        /// Step number.
        step: u64,
        /// The collapsed time step (s), safety factor included.
        dt: f64,
        /// The floor it fell under (s).
        floor: f64,
        /// Name of the effect that limits it.
        effect: String,
        /// Index of the limiting element within that effect.
        element: usize,
        /// The effect's cause (e.g. `element length`, `negative Jacobian`).
        what: &'static str,
    },
    /// A nodal force, moment or velocity became NaN or infinite.
    #[error("node {node}: {field} is not finite at t = {time} s (step {step})")]
    NonFiniteState {
        /// Node index, 0-based.
        node: usize,
        /// Which quantity (`force (N)`, `moment (N·mm)`, …).
        field: &'static str,
        /// Time (s).
        time: f64,
        /// Step number.
        step: u64,
    },
    /// An effect failed during a step for a reason of its own (a contact point
    /// the friction model refused, a tool query at a non-finite position).
    #[error("`{effect}`: {message}")]
    Effect {
        /// Effect name.
        effect: String,
        /// What happened, naming the pair, node or field.
        message: String,
    },
    /// An effect reports an error at one of its elements (e.g. a shell inverted during the run).
    #[error("`{effect}` element {element}: {message}")]
    Element {
        /// Effect name.
        effect: String,
        /// Element index within the effect.
        element: usize,
        /// What happened, with values and units.
        message: String,
    },
}
