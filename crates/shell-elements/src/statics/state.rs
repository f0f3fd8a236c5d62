//! `ShellState`: the per-element state of the static shells — thickness,
//! stress and history at every integration point, transverse shear per
//! in-plane point, hourglass and drilling forces — kept twice, committed
//! and trial.

/// The state of every element of a [`StaticShells`](super::StaticShells)
/// set: `in_plane` in-plane points per element (1 for Belytschko–Tsay, 4
/// for the fully integrated shell), each with `points` through the
/// thickness.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ShellState<H> {
    /// In-plane points per element.
    pub in_plane: usize,
    /// Through-thickness points per in-plane point.
    pub points: usize,
    /// Hourglass generalised forces per element.
    pub hourglass_vars: usize,
    /// Thickness (mm) per element.
    pub thickness: Vec<f64>,
    /// Stress `[σ_xx, σ_yy, σ_xy]` (MPa, co-rotational frame) per point,
    /// element-major, then in-plane point, then bottom to top.
    pub stress: Vec<[f64; 3]>,
    /// Material history per point, as `stress`.
    pub history: Vec<H>,
    /// Transverse shear stresses `[τ_xz, τ_yz]` (MPa) per in-plane point,
    /// element-major.
    pub shear: Vec<[f64; 2]>,
    /// Hourglass generalised forces (N, N·mm), `hourglass_vars` per
    /// element (Belytschko–Tsay: membrane x, y, bending x, y, transverse).
    pub hourglass: Vec<f64>,
    /// Drilling moments (N·mm) per element and node.
    pub drilling: Vec<[f64; 4]>,
}

impl<H: Copy> ShellState<H> {
    /// The through-thickness points of in-plane point `p` of element `e`
    /// (a range into `stress` and `history`).
    pub fn points_of(&self, e: usize, p: usize) -> std::ops::Range<usize> {
        let first = (e * self.in_plane + p) * self.points;
        first..first + self.points
    }

    /// Index of in-plane point `p` of element `e` into `shear`.
    pub fn in_plane_index(&self, e: usize, p: usize) -> usize {
        e * self.in_plane + p
    }

    /// The hourglass forces of element `e` (a range into `hourglass`).
    pub fn hourglass_of(&self, e: usize) -> std::ops::Range<usize> {
        e * self.hourglass_vars..(e + 1) * self.hourglass_vars
    }
}
