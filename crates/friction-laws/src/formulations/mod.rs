//! The built-in kinematic formulations of friction-math §4.

/// Names of the formulations this module registers (referenced by `ensure_linked`).
pub const REGISTERED: &[&str] = &[];
