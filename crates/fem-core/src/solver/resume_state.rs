//! Forming in stages: the solver's state taken out after a run
//! ([`Solver::save_resume`]) and put into a new solver in place of its set-up
//! ([`Solver::resume`]), so that the next step is the one the first run
//! would have taken (see [`crate::resume`]).

use super::Solver;
use crate::{FemError, SetupReport, SolverResume, StateArrays};

impl Solver {
    /// The state the next step reads: nodes, forces `f_n`, time steps, the
    /// press's tools and every effect's [`Effect::save_state`](crate::Effect::save_state).
    /// Meaningful after [`Solver::initialize`] (and any steps).
    pub fn save_resume(&self) -> SolverResume {
        let effects = self
            .effects
            .iter()
            .map(|e| {
                let mut arrays = StateArrays::default();
                e.save_state(&mut arrays);
                (e.name().to_string(), arrays)
            })
            .collect();
        SolverResume {
            nodes: self.state.clone(),
            forces: self.forces.clone(),
            time: self.time,
            dt_prev: self.dt_prev,
            dt_next: self.dt_next,
            dt_floor: self.dt_floor,
            physical_mass: self.physical_mass,
            added_mass: self.added_mass,
            tools: self
                .press
                .as_ref()
                .map_or_else(Vec::new, |p| p.save_tools(&self.tool_loads)),
            effects,
            ledger: self.ledger,
        }
    }

    /// Set up from a saved state instead of [`Solver::initialize`]: the
    /// fields shared, the constraints sorted, then the nodes, forces, time,
    /// time steps, tools (by name) and effects (by name) taken from `saved`
    /// (the press programme starts at the saved time); no
    /// forces are computed, so the first step is the saved run's next one.
    /// Returns the set-up report and one line per part of the state dropped
    /// (an effect or tool not in this model, a contact pair renamed).
    ///
    /// # Errors
    /// Already set up; another node count; selective mass scaling (its
    /// mass solve is not saved); an effect refusing its state (one line
    /// naming the effect and what differs).
    pub fn resume(&mut self, saved: &SolverResume) -> Result<(SetupReport, Vec<String>), FemError> {
        let refuse = |m: String| FemError::InvalidSetup(format!("initial state: {m}"));
        if self.setup.is_some() {
            return Err(refuse("the solver is already set up".into()));
        }
        if saved.nodes.len() != self.state.len() {
            return Err(refuse(format!(
                "{} nodes in the state, {} in the model",
                saved.nodes.len(),
                self.state.len()
            )));
        }
        if matches!(
            self.settings.mass_scaling,
            crate::MassScaling::Selective { .. }
        ) {
            return Err(refuse(
                "selective mass scaling cannot continue from a saved state; use conventional mass scaling".into(),
            ));
        }
        self.initialized = true;
        self.share_fields()?;
        self.constraints.sort_by_key(|c| (c.node, c.dof));
        self.reactions = vec![0.0; self.constraints.len()];
        let mut notes = Vec::new();
        for e in &mut self.effects {
            let name = e.name().to_string();
            match saved.effects.iter().find(|(n, _)| *n == name) {
                Some((_, arrays)) => e
                    .restore_state(arrays, &mut notes)
                    .map_err(|m| refuse(format!("{name}: {m}")))?,
                None => notes.push(format!("`{name}` has no saved state: it starts afresh")),
            }
        }
        for (name, _) in &saved.effects {
            if !self.effects.iter().any(|e| e.name() == name) {
                notes.push(format!(
                    "the state of `{name}` is dropped: no such effect here"
                ));
            }
        }
        if let Some(p) = self.press.as_mut() {
            notes.extend(p.resume_tools(&saved.tools, &mut self.tool_loads));
            p.start_at(saved.time);
        }
        self.time = saved.time;
        self.state.clone_from(&saved.nodes);
        self.forces.clone_from(&saved.forces);
        self.dt_prev = saved.dt_prev;
        self.dt_next = saved.dt_next;
        self.dt_floor = saved.dt_floor;
        self.carried = Some(saved.ledger);
        self.physical_mass = saved.physical_mass;
        self.added_mass = saved.added_mass;
        let report = SetupReport {
            physical_mass: self.physical_mass,
            added_mass: self.added_mass,
            added_mass_percent: 100.0 * self.added_mass / self.physical_mass.max(f64::MIN_POSITIVE),
            dt_initial: self.dt_next,
            limit: None,
            massless_nodes: self.state.mass.iter().filter(|&&m| m == 0.0).count(),
        };
        self.timing.reset();
        self.setup = Some(report);
        Ok((report, notes))
    }
}
