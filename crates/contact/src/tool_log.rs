//! What each tool did, press step by press step: the force it delivered to the
//! blank (along its direction of motion and in total), the force prescribed to
//! a force-controlled tool, its travel and the work it did through contact.
//!
//! Sampled once per explicit step, weighted by the step's `Δt`, so that the
//! means are time means over the press step; nothing allocates after the first
//! sample of a press step.

use plugins_api::Vec3;

/// The time integral and extremes of one sampled quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampled {
    /// `∫ q dt` over the samples (unit of `q` × s).
    pub integral: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
}

impl Default for Sampled {
    fn default() -> Self {
        Self {
            integral: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Sampled {
    /// Add a sample `q` held over `dt` (s).
    pub fn add(&mut self, q: f64, dt: f64) {
        self.integral += q * dt;
        self.min = self.min.min(q);
        self.max = self.max.max(q);
    }

    /// Time mean over `duration` (s); 0 for an empty interval.
    pub fn mean(&self, duration: f64) -> f64 {
        if duration > 0.0 {
            self.integral / duration
        } else {
            0.0
        }
    }

    /// `(mean, min, max)`, with zeros when nothing was sampled.
    pub fn mean_min_max(&self, duration: f64) -> (f64, f64, f64) {
        if self.min <= self.max {
            (self.mean(duration), self.min, self.max)
        } else {
            (0.0, 0.0, 0.0)
        }
    }
}

/// What one tool did over one press step.
#[derive(Clone, Debug, PartialEq)]
pub struct ToolStepLog {
    /// Index of the press step (0 without a press).
    pub step: usize,
    /// Time sampled (s).
    pub duration: f64,
    /// Unit direction the forces are resolved along: the tool's direction of
    /// motion in the step, else its first direction in the programme, else −z
    /// (the press axis).
    pub direction: Vec3,
    /// Force the tool exerted on the blank along `direction` (N).
    pub along: Sampled,
    /// Magnitude of the force the tool exerted on the blank (N).
    pub total: Sampled,
    /// Force prescribed to a force-controlled tool, `F A(τ)` (N).
    pub applied: Option<Sampled>,
    /// Travel along `direction` since the start of the programme when the
    /// step began and at its last sample (mm).
    pub travel: (f64, f64),
    /// Work the tool did on the blank through contact (N·mm).
    pub work: f64,
    /// A force-controlled tool's momentum along `direction` at the step's
    /// first and last sample (tonne·mm/s): its change over the step's
    /// duration is the mean force that went into the tool's own
    /// acceleration.
    pub momentum: Option<(f64, f64)>,
}

/// One explicit step's sample of one tool.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ToolSample {
    pub step: usize,
    pub dt: f64,
    pub direction: Vec3,
    /// Force on the blank (N).
    pub force: Vec3,
    pub applied: Option<f64>,
    /// Displacement from the initial pose (mm).
    pub displacement: Vec3,
    /// Displacement from the initial pose when the press step began (mm).
    pub step_start: Vec3,
    /// Work through contact in this explicit step (N·mm).
    pub work: f64,
    /// A force-controlled tool's momentum along its direction (tonne·mm/s).
    pub momentum: Option<f64>,
}

impl ToolStepLog {
    fn start(s: &ToolSample) -> Self {
        let travel = s.step_start.dot(&s.direction);
        Self {
            step: s.step,
            duration: 0.0,
            direction: s.direction,
            along: Sampled::default(),
            total: Sampled::default(),
            applied: None,
            travel: (travel, travel),
            work: 0.0,
            momentum: s.momentum.map(|p| (p, p)),
        }
    }

    fn add(&mut self, s: &ToolSample) {
        self.duration += s.dt;
        self.along.add(s.force.dot(&self.direction), s.dt);
        self.total.add(s.force.norm(), s.dt);
        if let Some(a) = s.applied {
            self.applied
                .get_or_insert_with(Sampled::default)
                .add(a, s.dt);
        }
        self.travel.1 = s.displacement.dot(&self.direction);
        self.work += s.work;
        if let (Some(p), Some(m)) = (s.momentum, self.momentum.as_mut()) {
            m.1 = p;
        }
    }
}

/// Append `s` to the log of one tool: to its current press step's entry, or
/// to a new entry when the press step changed.
pub(crate) fn record(log: &mut Vec<ToolStepLog>, s: &ToolSample) {
    if log.last().is_none_or(|l| l.step != s.step) {
        log.push(ToolStepLog::start(s));
    }
    if let Some(l) = log.last_mut() {
        l.add(s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Means are time means; a new press step starts a new entry; the work
    /// and the travel follow the samples.
    #[test]
    fn log_averages_over_time_and_splits_by_press_step() {
        let mut log = Vec::new();
        let sample = |step, dt, f: f64, z: f64| ToolSample {
            step,
            dt,
            direction: -Vec3::z(),
            force: Vec3::new(3.0, 0.0, -f),
            applied: Some(100.0),
            displacement: Vec3::new(0.0, 0.0, z),
            step_start: Vec3::new(0.0, 0.0, if step == 0 { 0.5 } else { -1.0 }),
            work: 1.0,
            momentum: Some(z * 2.0),
        };
        record(&mut log, &sample(0, 1.0, 10.0, 0.0));
        record(&mut log, &sample(0, 3.0, 20.0, -1.0));
        record(&mut log, &sample(1, 2.0, 5.0, -2.0));
        assert_eq!(log.len(), 2);
        let l = &log[0];
        assert_eq!(l.duration, 4.0);
        assert_eq!(l.along.mean(l.duration), (10.0 + 60.0) / 4.0);
        assert_eq!((l.along.min, l.along.max), (10.0, 20.0));
        assert_eq!(l.total.max, (9.0f64 + 400.0).sqrt());
        assert_eq!(l.applied.unwrap().mean(l.duration), 100.0);
        assert_eq!(l.travel, (-0.5, 1.0));
        assert_eq!(l.work, 2.0);
        assert_eq!(l.momentum, Some((0.0, -2.0)));
        assert_eq!(log[1].step, 1);
        assert_eq!(log[1].momentum, Some((-4.0, -4.0)));
        assert_eq!(Sampled::default().mean_min_max(0.0), (0.0, 0.0, 0.0));
    }
}
