//! The energy ledger (kinetic, internal, hourglass, contact, friction, damping, external work, balance error) and a history recorder.
//!
//! # Definitions
//!
//! The ledger of a step is evaluated at the time `t_n` the step starts from
//! (one step behind the positions it produced), because central difference
//! only knows the kinetic energy at `t_n` once `v_{n+1/2}` is computed:
//!
//! - `kinetic = ½ Σ m |v̄_n|² + ½ Σ I |w̄_n|²` with the mid-step velocity
//!   `v̄_n = (v_{n-1/2} + v_{n+1/2})/2` (`>= 0`).
//! - `integration = −⅛ Σ m |v_{n+1/2} − v_{n-1/2}|² − ⅛ Σ I |…|²` (`<= 0`):
//!   `kinetic + integration = ½ Σ m v_{n-1/2}·v_{n+1/2}` is the product form
//!   of the kinetic energy that central difference conserves exactly for a
//!   linear undamped system at constant `Δt` (Hughes, *The Finite Element
//!   Method*, §9.3). It is bounded and does not accumulate; it is of order
//!   `(ω Δt)²/4` of the energy in a mode of frequency `ω`, so it is tiny for
//!   smooth motion and large only for content near the stability limit.
//!   Where the step changes, `integration` also holds the step-change term:
//!   the effects book their forces' work with the trapezoidal rule and
//!   central difference with the rule below, and the two differ by
//!   `¼ (Δt_{k+1/2} − Δt_{k-1/2}) F_k·(v_{k-1/2} − v_{k+1/2})` per force
//!   sample (exact; zero at a constant step). Without it a block landing on a
//!   tool, which shortens the step its contact springs limit, left 0.4 % of
//!   the external work unbalanced per landing.
//! - `internal`, `hourglass`, `plastic`, `contact`, `friction`, `bead`: the sum of
//!   the effects' [`EnergyTally`](crate::EnergyTally) at `t_n`.
//! - `damping`: energy dissipated by dynamic-relaxation damping (`>= 0`).
//! - `external_loads`: work of the nodal loads; `external_prescribed`: work
//!   of the reactions at prescribed DOFs (fixed DOFs do no work). A force
//!   `F` (load, reaction, damping force) does the work
//!   `½ v_{k-1/2}·(Δt̄_k F_k + Δt̄_{k-1} F_{k-1})` over `[t_{k-1}, t_k]`,
//!   with `Δt̄_k = (Δt_{k-1/2} + Δt_{k+1/2})/2`: the same rule by which
//!   central difference changes the product-form kinetic energy, so a
//!   linear system balances to round-off (at a varying `Δt` too, with the
//!   step-change term of `integration` for the effects' trapezoidal rule).
//! - `external_mass_scaling`: the kinetic energy `½ Δm |v_{n+1/2}|²` that
//!   mass added during the run (fixed-step mass scaling) gives the moving
//!   nodes, booked as work so that the balance stays closed.
//! - `external_tools`: work the effects' own external agents do on the model,
//!   summed from the effects' [`EnergyTally::external`](crate::EnergyTally)
//!   (rigid tools moved by the press push the blank through contact).
//! - `external = external_loads + external_prescribed + external_mass_scaling + external_tools`.
//!
//! `E_total(t_0)` includes `integration(t_0) = −⅛ Σ Δt² |f_0|²/m`, non-zero
//! when the run starts under load (a suddenly applied load); the later
//! energies are measured against it.
//!
//! - `kinetic_added`: with selective mass scaling ([`crate::selective_mass`]),
//!   the energy the added inertia takes up: the work of its inertia force
//!   `ΔM a` by the loads' rule (zero otherwise).
//!
//! - `bead`: energy dissipated by drawbeads' restraint (`>= 0`,
//!   docs/drawbeads.md).
//!
//! Balance (energies that count: kinetic, kinetic_added, integration, internal, hourglass,
//! contact, friction, bead, damping; `plastic` is part of `internal` and not added
//! again):
//!
//! ```text
//! E_total = kinetic + kinetic_added + integration + internal + hourglass
//!           + contact + friction + bead + damping
//! balance_abs   = E_total − E_total(t_0) − external
//! balance_error = |balance_abs| / max(|kinetic| + |integration| + |internal| + |hourglass|
//!                   + |contact| + |friction| + |bead| + |damping|, |external|, 1e-30)
//! ```

use std::io::Write;

/// All energies at one time (mJ = N·mm). See the module docs for the definitions.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyLedger {
    /// Time the ledger refers to, `t_n` (s).
    pub time: f64,
    /// Kinetic energy at `t_n` from the mid-step velocities, translational + rotational (mJ).
    pub kinetic: f64,
    /// Rotational part of `kinetic` (mJ).
    pub kinetic_rotational: f64,
    /// Energy taken up by the inertia selective mass scaling adds (mJ): the
    /// work of its inertia force `ΔM a`, booked by the loads' rule (about
    /// `½ v̄ᵀ ΔM v̄`; zero without selective scaling). Not part of `kinetic`.
    pub kinetic_added: f64,
    /// Central-difference correction (mJ): `kinetic + integration` is the
    /// product-form kinetic energy the scheme conserves (`<= 0` at a constant
    /// step), plus the step-change term (module docs).
    pub integration: f64,
    /// Internal energy, elastic + plastic, hourglass excluded (mJ).
    pub internal: f64,
    /// Hourglass energy (mJ).
    pub hourglass: f64,
    /// Plastic dissipation, part of `internal` (mJ).
    pub plastic: f64,
    /// Contact (penalty) energy (mJ).
    pub contact: f64,
    /// Frictional dissipation (mJ).
    pub friction: f64,
    /// Drawbead dissipation (mJ).
    pub bead: f64,
    /// Dissipation by dynamic-relaxation damping (mJ).
    pub damping: f64,
    /// Work of the nodal loads (mJ).
    pub external_loads: f64,
    /// Work of the reactions at prescribed DOFs (mJ).
    pub external_prescribed: f64,
    /// Kinetic energy given by mass added during the run (mJ).
    pub external_mass_scaling: f64,
    /// Work done by the effects' external agents, e.g. moving rigid tools (mJ).
    pub external_tools: f64,
    /// `external_loads + external_prescribed + external_mass_scaling + external_tools` (mJ).
    pub external: f64,
    /// `E_total − E_total(t_0) − external` (mJ).
    pub balance_abs: f64,
    /// Relative balance error (-), see the module docs.
    pub balance_error: f64,
}

impl EnergyLedger {
    /// `kinetic + kinetic_added + integration + internal + hourglass + contact + friction + bead + damping` (mJ).
    pub fn total(&self) -> f64 {
        self.kinetic
            + self.kinetic_added
            + self.integration
            + self.internal
            + self.hourglass
            + self.contact
            + self.friction
            + self.bead
            + self.damping
    }

    /// Fill `external`, `balance_abs` and `balance_error` given the total at `t_0`.
    pub fn close(&mut self, total0: f64) {
        self.external = self.external_loads
            + self.external_prescribed
            + self.external_mass_scaling
            + self.external_tools;
        self.balance_abs = self.total() - total0 - self.external;
        self.relative_balance();
    }

    /// The ledger of a run continued from a saved state (forming in
    /// stages): the energies this run accumulated since it started, plus
    /// those of the runs before (`before`, their ledger when the state was
    /// saved). The kinetic energy and the central-difference term are of
    /// now; the balance adds the earlier runs' own.
    pub fn carry(&mut self, before: &EnergyLedger) {
        self.kinetic_added += before.kinetic_added;
        self.internal += before.internal;
        self.hourglass += before.hourglass;
        self.plastic += before.plastic;
        self.contact += before.contact;
        self.friction += before.friction;
        self.bead += before.bead;
        self.damping += before.damping;
        self.external_loads += before.external_loads;
        self.external_prescribed += before.external_prescribed;
        self.external_mass_scaling += before.external_mass_scaling;
        self.external_tools += before.external_tools;
        self.external += before.external;
        self.balance_abs += before.balance_abs;
        self.relative_balance();
    }

    /// The fields of the ledger in a fixed order (a state file's words).
    pub fn to_words(&self) -> [f64; 19] {
        [
            self.time,
            self.kinetic,
            self.kinetic_rotational,
            self.kinetic_added,
            self.integration,
            self.internal,
            self.hourglass,
            self.plastic,
            self.contact,
            self.friction,
            self.bead,
            self.damping,
            self.external_loads,
            self.external_prescribed,
            self.external_mass_scaling,
            self.external_tools,
            self.external,
            self.balance_abs,
            self.balance_error,
        ]
    }

    /// The ledger of [`EnergyLedger::to_words`]' words.
    pub fn from_words(w: &[f64; 19]) -> Self {
        Self {
            time: w[0],
            kinetic: w[1],
            kinetic_rotational: w[2],
            kinetic_added: w[3],
            integration: w[4],
            internal: w[5],
            hourglass: w[6],
            plastic: w[7],
            contact: w[8],
            friction: w[9],
            bead: w[10],
            damping: w[11],
            external_loads: w[12],
            external_prescribed: w[13],
            external_mass_scaling: w[14],
            external_tools: w[15],
            external: w[16],
            balance_abs: w[17],
            balance_error: w[18],
        }
    }

    /// `balance_error` from `balance_abs` and the energies (module docs).
    fn relative_balance(&mut self) {
        let scale = (self.kinetic.abs()
            + self.kinetic_added.abs()
            + self.integration.abs()
            + self.internal.abs()
            + self.hourglass.abs()
            + self.contact.abs()
            + self.friction.abs()
            + self.bead.abs()
            + self.damping.abs())
        .max(self.external.abs())
        .max(1e-30);
        self.balance_error = self.balance_abs.abs() / scale;
    }
}

/// The columns of [`History::write_csv`].
const CSV_HEADER: [&str; 21] = [
    "step",
    "time_s",
    "dt_s",
    "energy_time_s",
    "kinetic_mJ",
    "kinetic_rotational_mJ",
    "integration_mJ",
    "internal_mJ",
    "hourglass_mJ",
    "plastic_mJ",
    "contact_mJ",
    "friction_mJ",
    "bead_mJ",
    "damping_mJ",
    "external_loads_mJ",
    "external_prescribed_mJ",
    "external_mass_scaling_mJ",
    "external_tools_mJ",
    "external_mJ",
    "balance_abs_mJ",
    "balance_error",
];

/// One row of a [`History`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HistoryRow {
    /// Step number.
    pub step: u64,
    /// Time of the state (s).
    pub time: f64,
    /// Time step just taken (s).
    pub dt: f64,
    /// Energies (at `energy.time`, one step behind `time`).
    pub energy: EnergyLedger,
}

/// A recorder of time, time step and energies, every `every`-th step and at
/// least every `interval` seconds of simulated time (whichever comes first).
#[derive(Debug, Clone, PartialEq)]
pub struct History {
    /// Record every this many steps (0: never by count).
    pub every: u64,
    /// Record at least every this much simulated time (s); 0: never by time.
    pub interval: f64,
    /// The rows recorded so far.
    pub rows: Vec<HistoryRow>,
    last_time: f64,
}

impl History {
    /// A recorder of every `every`-th step (1: all steps) and at least every `interval` s.
    pub fn new(every: u64, interval: f64) -> Self {
        Self {
            every,
            interval,
            rows: Vec::new(),
            last_time: f64::NEG_INFINITY,
        }
    }

    /// Record `report` if it is due; returns whether it was recorded.
    pub fn record(&mut self, report: &crate::StepReport) -> bool {
        let by_count = self.every > 0 && report.step.is_multiple_of(self.every);
        let by_time = self.interval > 0.0 && report.time - self.last_time >= self.interval;
        if by_count || by_time || self.rows.is_empty() {
            self.force_record(report);
            true
        } else {
            false
        }
    }

    /// Record `report` unconditionally (e.g. the last step of a run).
    pub fn force_record(&mut self, report: &crate::StepReport) {
        if self.rows.last().is_some_and(|r| r.step == report.step) {
            return;
        }
        self.last_time = report.time;
        self.rows.push(HistoryRow {
            step: report.step,
            time: report.time,
            dt: report.dt,
            energy: report.energy,
        });
    }

    /// Write the rows as CSV with a header line (energies in mJ, times in s):
    /// the step as an integer, every other number as `{:e}`, written with the
    /// `csv` crate (records ended by `\n`).
    ///
    /// # Errors
    /// I/O errors of `w`.
    pub fn write_csv<W: Write>(&self, w: W) -> std::io::Result<()> {
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(CSV_HEADER)?;
        for r in &self.rows {
            let e = &r.energy;
            let mut fields = vec![r.step.to_string()];
            fields.extend(
                [
                    r.time,
                    r.dt,
                    e.time,
                    e.kinetic,
                    e.kinetic_rotational,
                    e.integration,
                    e.internal,
                    e.hourglass,
                    e.plastic,
                    e.contact,
                    e.friction,
                    e.bead,
                    e.damping,
                    e.external_loads,
                    e.external_prescribed,
                    e.external_mass_scaling,
                    e.external_tools,
                    e.external,
                    e.balance_abs,
                    e.balance_error,
                ]
                .map(|v| format!("{v:e}")),
            );
            csv.write_record(&fields)?;
        }
        csv.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ledger goes through its words and back unchanged; carried on, the
    /// accumulated energies and the balance add, the kinetic energy is of
    /// now.
    #[test]
    fn a_ledger_round_trips_and_carries_on() {
        let mut a = EnergyLedger {
            time: 1.0,
            kinetic: 2.0,
            internal: 10.0,
            plastic: 8.0,
            friction: 3.0,
            external_tools: 15.0,
            ..Default::default()
        };
        a.close(0.0);
        assert_eq!(EnergyLedger::from_words(&a.to_words()), a);
        let mut b = EnergyLedger {
            kinetic: 1.0,
            internal: 5.0,
            external_tools: 4.0,
            ..Default::default()
        };
        b.close(2.0);
        let (b_abs, mut c) = (b.balance_abs, b);
        c.carry(&a);
        assert_eq!((c.kinetic, c.internal, c.plastic), (1.0, 15.0, 8.0));
        assert_eq!((c.external_tools, c.external), (19.0, 19.0));
        assert_eq!(c.balance_abs, a.balance_abs + b_abs);
    }

    /// The header, then per row the step and every number as `{:e}`, `,`
    /// between, `\n` after each line.
    #[test]
    fn write_csv_writes_the_header_and_each_row_as_formatted() {
        let mut h = History::new(1, 0.0);
        let energy = EnergyLedger {
            time: 0.5,
            kinetic: 1500.0,
            kinetic_rotational: -0.0,
            integration: -2.5e-12,
            internal: 0.1,
            balance_error: f64::NAN,
            ..EnergyLedger::default()
        };
        h.rows.push(HistoryRow {
            step: 42,
            time: 0.75,
            dt: 1e-7,
            energy,
        });
        let mut out = Vec::new();
        h.write_csv(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let mut lines = text.split_inclusive('\n');
        assert_eq!(
            lines.next().unwrap(),
            "step,time_s,dt_s,energy_time_s,kinetic_mJ,kinetic_rotational_mJ,integration_mJ,\
             internal_mJ,hourglass_mJ,plastic_mJ,contact_mJ,friction_mJ,bead_mJ,damping_mJ,\
             external_loads_mJ,external_prescribed_mJ,external_mass_scaling_mJ,external_tools_mJ,\
             external_mJ,balance_abs_mJ,balance_error\n"
        );
        assert_eq!(
            lines.next().unwrap(),
            "42,7.5e-1,1e-7,5e-1,1.5e3,-0e0,-2.5e-12,1e-1,0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,NaN\n"
        );
        assert_eq!(lines.next(), None);
    }
}
