//! The rows a run records at every history sample: the energies and the
//! punch force ([`HistoryRow`]: `energy.csv`, `punch_force.csv`) and the
//! tools ([`ToolRow`]: `tools.csv`). The run fills them
//! ([`crate::run`]); the estimate of a scene counts their memory
//! ([`crate::scene::estimate`]).

/// One row of the histories (`energy.csv`, `punch_force.csv`).
#[derive(Debug, Clone, Copy, Default)]
pub struct HistoryRow {
    /// Time (s).
    pub time: f64,
    /// Stroke (mm).
    pub stroke: f64,
    /// Punch force, full-model equivalent (N).
    pub punch_force: f64,
    /// Energies at this time.
    pub energy: fem_core::EnergyLedger,
    /// Time step (s).
    pub dt: f64,
}

impl HistoryRow {
    /// The row of `energy.csv`: time, stroke, step, then the energies
    /// (internal, kinetic, hourglass, plastic, contact, friction, drawbead
    /// dissipation, external work, balance error).
    pub fn energy_row(&self) -> [f64; 12] {
        let e = &self.energy;
        [
            self.time,
            self.stroke,
            self.dt,
            e.internal,
            e.kinetic,
            e.hourglass,
            e.plastic,
            e.contact,
            e.friction,
            e.bead,
            e.external,
            e.balance_error,
        ]
    }

    /// Whether every number of the row is finite.
    pub fn is_finite(&self) -> bool {
        self.punch_force.is_finite() && self.energy_row().iter().all(|v| v.is_finite())
    }
}

/// One tool's state at a history sample: force on the blank along the tool's
/// press axis and in total (N), the prescribed force (N; NaN when the tool is
/// not force-controlled, written as an empty cell) and the position along
/// the axis from the initial pose (mm).
#[derive(Debug, Clone, Copy)]
pub struct ToolState {
    /// Force on the blank along the press axis (N).
    pub force: f64,
    /// Magnitude of the force on the blank (N).
    pub force_total: f64,
    /// Prescribed force (N), `None` unless force-controlled now.
    pub prescribed: Option<f64>,
    /// Position along the press axis from the initial pose (mm).
    pub position: f64,
}

/// One row of `tools.csv`.
#[derive(Debug, Clone)]
pub struct ToolRow {
    /// Time (s).
    pub time: f64,
    /// Stroke (mm).
    pub stroke: f64,
    /// Per tool, in index order.
    pub tools: Vec<ToolState>,
}
