//! The built-in friction laws of friction-math §3.

/// Names of the laws this module registers (referenced by `ensure_linked`).
pub const REGISTERED: &[&str] = &[];
