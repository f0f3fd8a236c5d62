//! The built-in shell elements: their registrations and the makers that
//! turn a [`ShellRequest`] into their formulations (listed in `builtin.rs`).

use super::{ElementKind, ShellRequest};
use crate::{BelytschkoTsay, FullyIntegrated, ShellError};

/// The Belytschko–Tsay shell of `r`'s warping correction and drilling.
pub(super) fn belytschko_tsay(r: &ShellRequest<'_>) -> Result<BelytschkoTsay, ShellError> {
    BelytschkoTsay {
        warping_correction: r.warping_correction,
        ..BelytschkoTsay::default()
    }
    .with_drilling(r.drilling)
}

/// The fully integrated shell of `r`'s warping correction and drilling.
pub(super) fn fully_integrated(r: &ShellRequest<'_>) -> Result<FullyIntegrated, ShellError> {
    FullyIntegrated {
        warping_correction: r.warping_correction,
        ..FullyIntegrated::default()
    }
    .with_drilling(r.drilling)
}

inventory::submit! {
    ElementKind {
        name: "belytschko-tsay",
        summary: "one-point Belytschko–Tsay shell with hourglass control and an optional warping correction",
        in_plane_points: 1,
        relative_cost: 1.0,
        params: &[],
        add: None,
        static_form: true,
    }
}

inventory::submit! {
    ElementKind {
        name: "fully-integrated",
        summary: "2 × 2 fully integrated shell with assumed transverse shear (no hourglass modes)",
        in_plane_points: 4,
        // Measured on the square cup (its first 3 ms, 6,000 increments,
        // `--set solver.end_time=3e-3`, 2 threads): 2.830e6 against 5.277e6
        // element cycles/s for Belytschko–Tsay.
        relative_cost: 1.9,
        params: &[],
        add: None,
        static_form: true,
    }
}

/// Referenced from [`super::ensure_linked`] so that this file's
/// registrations are linked.
pub(super) fn ensure_linked() {}
