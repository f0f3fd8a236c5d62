//! The analytic references of the capstan, block and strip scenes.

mod mu;

pub use mu::{ReferenceError, coulomb_mu};
