//! `ShellState`: the per-element state of the static shells — thickness,
//! stress and history at every through-thickness point, transverse shear,
//! hourglass and drilling forces — kept twice, committed and trial.

/// The state of every element of a [`StaticShells`](super::StaticShells)
/// set (one in-plane point per element, `points` through the thickness).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ShellState<H> {
    /// Through-thickness points per element.
    pub points: usize,
    /// Thickness (mm) per element.
    pub thickness: Vec<f64>,
    /// Stress `[σ_xx, σ_yy, σ_xy]` (MPa, co-rotational frame) per point,
    /// element-major, bottom to top.
    pub stress: Vec<[f64; 3]>,
    /// Material history per point, as `stress`.
    pub history: Vec<H>,
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa) per element.
    pub shear: Vec<[f64; 2]>,
    /// Hourglass generalised forces (N, N·mm) per element: membrane x, y,
    /// bending x, y, transverse.
    pub hourglass: Vec<[f64; 5]>,
    /// Drilling moments (N·mm) per element and node.
    pub drilling: Vec<[f64; 4]>,
}

impl<H: Copy> ShellState<H> {
    /// The points of element `e` (a range into `stress` and `history`).
    pub fn points_of(&self, e: usize) -> std::ops::Range<usize> {
        e * self.points..(e + 1) * self.points
    }
}
