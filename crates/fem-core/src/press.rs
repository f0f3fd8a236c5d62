//! The press scheduler: a sequence of press steps that move rigid bodies (the tools)
//! by prescribed travel or velocity, by force control on their own rigid-body
//! degree of freedom, or hold them, and that switch contact pairs on and off.
//!
//! Step 1 of an explicit step (docs/architecture.md §3): [`Press::advance`] places every tool
//! at `t_{n+1}` and gives its mid-step velocity `v_{n+1/2} = (x_{n+1} − x_n)/Δt`,
//! the time level of the blank's velocities. The scheduler knows tools only as
//! rigid bodies (pose and velocity); it does not know their geometry.
//!
//! Force control (a blankholder on gas springs, a cushion): the tool moves along
//! a unit `direction` only; its travel `s` obeys `m s̈ = F A(τ) + R·direction − c ṡ`,
//! where `R` is the force the blank exerts on the tool through contact (the
//! previous step's reaction), integrated by central difference like the blank.
//! `F` is constant or a table of the tool's compression (a gas-spring curve,
//! [`ForceLaw`]). Over any interval `T` the tool delivers to the blank, in the
//! mean, `F̄ − c ṡ̄ − m Δṡ / T`: with the dashpot `c = 0` (the default) the
//! delivered force is the prescribed one up to the change of the tool's
//! momentum, whatever its steady speed. A dashpot `c > 0` is an explicit
//! option and biases a steadily moving tool by `c ṡ` (docs/contact.md).
//!
//! Double action (square cup: holder force-controlled, punch travels), single
//! action (S-rail: the die travels onto holder and blank, then on over a fixed
//! punch) and triple action (close the holders, move the die, form) are each a
//! list of [`PressStep`]s.

use plugins_api::{RigidPose, RigidVelocity, Vec3};

use crate::{Amplitude, FemError};

/// How one tool moves during a press step (`τ` is the time since the step began).
#[derive(Debug, Clone, PartialEq)]
pub enum ToolMotion {
    /// Stay where the previous step left the tool, at rest.
    Hold,
    /// Travel `distance` (mm) along the unit `direction`, shaped by `amplitude`
    /// (a function of `τ` from 0 to 1; the default is a C² smooth step over the
    /// step's duration).
    Travel {
        /// Unit direction of travel (global frame).
        direction: Vec3,
        /// Distance to travel over the step (mm).
        distance: f64,
        /// Shape of the travel in step time; `None`: smooth step over the duration.
        amplitude: Option<Amplitude>,
    },
    /// Move at `speed · A(τ)` (mm/s) along the unit `direction`.
    Velocity {
        /// Unit direction (global frame).
        direction: Vec3,
        /// Speed (mm/s).
        speed: f64,
        /// Scale of the speed in step time; `None`: constant 1.
        amplitude: Option<Amplitude>,
    },
    /// Turn about the unit `axis` through the tool's origin (its pose's
    /// translation) at `rate · A(τ)` (rad/s), the translation held.
    Spin {
        /// Unit axis of the rotation (global frame).
        axis: Vec3,
        /// Rotation rate (rad/s), right-handed about `axis`.
        rate: f64,
        /// Scale of the rate in step time; `None`: constant 1.
        amplitude: Option<Amplitude>,
    },
    /// Force control: `F · A(τ)` (N) pushes the tool along the unit
    /// `direction`; its travel along `direction` is integrated with the contact
    /// reaction; the other degrees of freedom are held.
    Force {
        /// Unit direction of the applied force and of the free travel.
        direction: Vec3,
        /// Applied force `F` (N): constant or a function of the compression.
        force: ForceLaw,
        /// Scale of the force in step time; `None`: constant 1.
        amplitude: Option<Amplitude>,
        /// Mass of the tool's free degree of freedom (tonne), `> 0`.
        mass: f64,
        /// Absolute viscous dashpot on the free travel (N·s/mm), `≥ 0`. It
        /// subtracts `damping · ṡ` from the delivered force whenever the tool
        /// moves: `0` for a gas spring or a cushion that delivers its force.
        damping: f64,
        /// Damping of the tool bouncing on the blank, as a fraction `ζ ∈ [0, 1]`
        /// of critical damping of the tool's mass `m` on its contact springs
        /// `K` ([`ToolLoad::stiffness`]): the force `(2ζ/ω) d(R·direction)/dt`
        /// with `ω = √(K/m)`, i.e. a damper `2ζ√(K m)` on the rate at which
        /// the tool presses into the blank. It is a time derivative, so its
        /// mean over any interval is `(2ζ/ω) ΔR / T`: no bias of a steady
        /// motion, whatever the tool's speed.
        relative_damping: f64,
    },
}

/// The force of a force-controlled tool before its amplitude.
#[derive(Debug, Clone, PartialEq)]
pub enum ForceLaw {
    /// A constant force (N), `≥ 0`.
    Constant(f64),
    /// A gas-spring or cushion curve: `(compression, force)` rows (mm, N),
    /// compression strictly increasing, forces `≥ 0`; linear between rows and
    /// constant beyond the ends. The compression is the tool's travel against
    /// its force `direction` since the start of the programme,
    /// `c = −(x − x₀)·direction`: a holder pushed down whose springs are
    /// compressed as the flange lifts it, or a cushion pushed down by the die.
    Compression(Vec<(f64, f64)>),
}

impl ForceLaw {
    /// The force (N) at compression `c` (mm); NaN for a NaN compression.
    pub fn value(&self, c: f64) -> f64 {
        match self {
            ForceLaw::Constant(f) => *f,
            ForceLaw::Compression(rows) => crate::amplitude::table_value(rows, c),
        }
    }

    /// Check the values: a finite force `≥ 0`; a non-empty table with strictly
    /// increasing finite compressions and finite forces `≥ 0`. `field` names
    /// the scene key in the error.
    pub fn validate(&self, field: &str) -> Result<(), FemError> {
        let bad = |f: String, value: f64, unit: &'static str, range: &'static str| {
            FemError::InvalidParameter {
                field: f,
                value,
                unit,
                range,
            }
        };
        match self {
            ForceLaw::Constant(f) => {
                if !(f.is_finite() && *f >= 0.0) {
                    return Err(bad(format!("{field}.force"), *f, "N", ">= 0 and finite"));
                }
            }
            ForceLaw::Compression(rows) => {
                if rows.is_empty() {
                    return Err(FemError::InvalidSetup(format!(
                        "{field}.force_curve: the table is empty; give [compression mm, force N] rows"
                    )));
                }
                for (k, &(c, f)) in rows.iter().enumerate() {
                    if !c.is_finite() || (k > 0 && c <= rows[k - 1].0) {
                        return Err(bad(
                            format!("{field}.force_curve[{k}][0]"),
                            c,
                            "mm",
                            "finite and strictly increasing",
                        ));
                    }
                    if !(f.is_finite() && f >= 0.0) {
                        return Err(bad(
                            format!("{field}.force_curve[{k}][1]"),
                            f,
                            "N",
                            ">= 0 and finite",
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

impl ToolMotion {
    /// The unit direction and the amplitude of a moving tool (`None` when it holds).
    pub fn direction_and_amplitude(&self) -> Option<(&Vec3, &Option<Amplitude>)> {
        match self {
            ToolMotion::Hold => None,
            ToolMotion::Travel {
                direction,
                amplitude,
                ..
            }
            | ToolMotion::Velocity {
                direction,
                amplitude,
                ..
            }
            | ToolMotion::Spin {
                axis: direction,
                amplitude,
                ..
            }
            | ToolMotion::Force {
                direction,
                amplitude,
                ..
            } => Some((direction, amplitude)),
        }
    }
}

/// When a press step ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepEnd {
    /// After this time (s).
    Duration(f64),
    /// When `tool` has travelled `distance` (mm) since the step began, or after
    /// `max_duration` (s), whichever comes first.
    Travel {
        /// Tool index.
        tool: usize,
        /// Travel (mm), `> 0`.
        distance: f64,
        /// Upper bound on the step's duration (s).
        max_duration: f64,
    },
    /// A springback step: every contact pair ends and the tools hold, the
    /// solver removes the blank's free rigid-body modes and relaxes it
    /// (dynamic relaxation, [`crate::Solver`]); the step ends when the
    /// out-of-balance force has fallen to `tolerance` times its value when
    /// the tools let go, or after `max_duration` (s).
    Settled {
        /// Residual force ratio at which the blank is at rest, in (0, 1).
        tolerance: f64,
        /// Upper bound on the step's duration (s).
        max_duration: f64,
        /// How the blank is brought to rest.
        method: ReleaseMethod,
    },
}

/// How a springback step ([`StepEnd::Settled`]) brings the blank to rest.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReleaseMethod {
    /// Explicit steps with adaptive damping (`crate::relaxation`).
    #[default]
    DynamicRelaxation,
    /// A static Newton solve of the stress release as the tools let go
    /// (`crate::statics`), the explicit steps after it only confirming
    /// the rest; every effect with forces then needs a static form
    /// ([`crate::Effect::static_form`]).
    Implicit,
}

impl StepEnd {
    fn duration(&self) -> f64 {
        match *self {
            StepEnd::Duration(d) => d,
            StepEnd::Travel { max_duration, .. } | StepEnd::Settled { max_duration, .. } => {
                max_duration
            }
        }
    }
}

impl PressStep {
    /// Whether this is a springback step ([`StepEnd::Settled`]).
    pub fn is_release(&self) -> bool {
        matches!(self.end, StepEnd::Settled { .. })
    }
}

/// One step of the press programme.
#[derive(Debug, Clone, PartialEq)]
pub struct PressStep {
    /// Name for reports (`close holder`, `draw`, …).
    pub name: String,
    /// When the step ends.
    pub end: StepEnd,
    /// Motions of the tools that move; unlisted tools hold.
    pub motions: Vec<(usize, ToolMotion)>,
    /// Contact pairs active during the step (indices); `None`: all.
    pub active_pairs: Option<Vec<usize>>,
}

/// What the blank did to a tool in the last step, read by force control.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ToolLoad {
    /// Force the blank exerted on the tool (N).
    pub force: Vec3,
    /// Normal contact stiffness of the blank points touching the tool (N/mm).
    pub stiffness: f64,
}

/// Where a step change happened, reported by [`Press::advance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepChange {
    /// Index of the step that began.
    pub step: usize,
    /// Its start time (s).
    pub time: f64,
}

/// The press: its programme and the rigid-body state of every tool.
#[derive(Debug, Clone)]
pub struct Press {
    steps: Vec<PressStep>,
    names: Vec<String>,
    initial: Vec<RigidPose>,
    poses: Vec<RigidPose>,
    velocities: Vec<RigidVelocity>,
    /// Pose of each tool when the current step began.
    step_start_pose: Vec<RigidPose>,
    /// Mid-step speed of each force-controlled travel (mm/s).
    free_speed: Vec<f64>,
    /// Force (N) applied to each force-controlled tool in the last advance
    /// (`F A(τ)`, along its direction); `None` for other tools.
    applied: Vec<Option<f64>>,
    /// The last reaction along each force-controlled tool's direction (N),
    /// for the rate relative damping reads.
    last_reaction: Vec<Option<f64>>,
    current: usize,
    step_start: f64,
    finished: bool,
    /// The solver found the blank at rest in the current springback step.
    settled: bool,
}

impl Press {
    /// A press for tools named `names` at their initial `poses`, running `steps`.
    ///
    /// # Errors
    /// An empty programme, a tool index out of range, a non-unit direction, a
    /// non-positive duration, distance or mass, a negative force or damping,
    /// a bad amplitude: each naming the step and the field.
    pub fn new(
        names: &[String],
        poses: &[RigidPose],
        steps: Vec<PressStep>,
    ) -> Result<Self, FemError> {
        if steps.is_empty() {
            return Err(FemError::InvalidSetup(
                "press: the programme has no steps; give at least one [[steps]] entry".into(),
            ));
        }
        let n = poses.len();
        for (k, s) in steps.iter().enumerate() {
            let keys = StepKeys { k, step: s };
            keys.check_end(n)?;
            for (tool, m) in &s.motions {
                if *tool >= n {
                    return Err(FemError::InvalidSetup(format!(
                        "{}: tool index {tool} out of range ({n} tools)",
                        keys.field("motions")
                    )));
                }
                keys.check_motion(names, *tool, m)?;
            }
        }
        Ok(Self {
            steps,
            names: names.to_vec(),
            initial: poses.to_vec(),
            poses: poses.to_vec(),
            velocities: vec![RigidVelocity::default(); n],
            step_start_pose: poses.to_vec(),
            free_speed: vec![0.0; n],
            applied: vec![None; n],
            last_reaction: vec![None; n],
            current: 0,
            step_start: 0.0,
            finished: false,
            settled: false,
        })
    }

    /// Each tool's rigid-body state, with `loads` the last step's loads on
    /// the tools (index: tool), to continue in another run.
    pub fn save_tools(&self, loads: &[ToolLoad]) -> Vec<crate::ToolResume> {
        (0..self.names.len())
            .map(|i| crate::ToolResume {
                name: self.names[i].clone(),
                initial: self.initial[i],
                pose: self.poses[i],
                velocity: self.velocities[i],
                free_speed: self.free_speed[i],
                applied: self.applied[i],
                last_reaction: self.last_reaction[i],
                load: loads.get(i).copied().unwrap_or_default(),
            })
            .collect()
    }

    /// Start every tool named in `saved` where a run left it (pose, velocity,
    /// force-control state), before the first step; `loads` (index: tool)
    /// takes their last loads. Returns one line per saved tool not in this
    /// press.
    pub fn resume_tools(
        &mut self,
        saved: &[crate::ToolResume],
        loads: &mut [ToolLoad],
    ) -> Vec<String> {
        let mut notes = Vec::new();
        for t in saved {
            let Some(i) = self.names.iter().position(|n| *n == t.name) else {
                notes.push(format!(
                    "tool `{}` of the initial state is not in this press: its pose is dropped",
                    t.name
                ));
                continue;
            };
            self.initial[i] = t.initial;
            self.poses[i] = t.pose;
            self.step_start_pose[i] = t.pose;
            self.velocities[i] = t.velocity;
            self.free_speed[i] = t.free_speed;
            self.applied[i] = t.applied;
            self.last_reaction[i] = t.last_reaction;
            if let Some(l) = loads.get_mut(i) {
                *l = t.load;
            }
        }
        notes
    }

    /// Start the programme at `time` (s) instead of 0, before the first
    /// advance (a run continuing from a saved state).
    pub fn start_at(&mut self, time: f64) {
        self.step_start = time;
    }

    /// Tool names, in index order.
    pub fn tool_names(&self) -> &[String] {
        &self.names
    }

    /// The programme.
    pub fn steps(&self) -> &[PressStep] {
        &self.steps
    }

    /// Index of the current step.
    pub fn current_step(&self) -> usize {
        self.current
    }

    /// Whether the last step has ended.
    pub fn finished(&self) -> bool {
        self.finished
    }

    /// Current pose of tool `i`.
    pub fn pose(&self, i: usize) -> RigidPose {
        self.poses[i]
    }

    /// Mid-step velocity of tool `i`.
    pub fn velocity(&self, i: usize) -> RigidVelocity {
        self.velocities[i]
    }

    /// Displacement of tool `i` from its initial pose when the current step
    /// began (mm).
    pub fn step_start_displacement(&self, i: usize) -> Vec3 {
        self.step_start_pose[i].translation - self.initial[i].translation
    }

    /// Displacement of tool `i` from its initial pose (mm).
    pub fn displacement(&self, i: usize) -> Vec3 {
        self.poses[i].translation - self.initial[i].translation
    }

    /// The force (N) applied to tool `i` along its direction in the last
    /// advance, `F A(τ)`, if the tool is force-controlled in the current step.
    pub fn applied_force(&self, i: usize) -> Option<f64> {
        self.applied[i]
    }

    /// The momentum (tonne·mm/s) of force-controlled tool `i` along its
    /// direction, `m v` at the last advance's mid-step speed; `None` when the
    /// tool is not force-controlled in the current step.
    pub fn momentum(&self, i: usize) -> Option<f64> {
        match self.motion(self.current, i) {
            ToolMotion::Force { mass, .. } => Some(mass * self.free_speed[i]),
            _ => None,
        }
    }

    /// The unit direction of tool `i`'s motion in the current step, if it moves.
    pub fn direction(&self, i: usize) -> Option<Vec3> {
        self.motion(self.current, i)
            .direction_and_amplitude()
            .map(|(d, _)| *d)
    }

    /// The unit direction of the first motion of tool `i` in the programme
    /// (its press axis), if it ever moves.
    pub fn first_direction(&self, i: usize) -> Option<Vec3> {
        (0..self.steps.len())
            .find_map(|k| self.motion(k, i).direction_and_amplitude().map(|(d, _)| *d))
    }

    fn motion(&self, step: usize, i: usize) -> &ToolMotion {
        self.steps[step]
            .motions
            .iter()
            .find(|(t, _)| *t == i)
            .map_or(&ToolMotion::Hold, |(_, m)| m)
    }

    /// Whether the current step is a springback step that is still running.
    pub fn releasing(&self) -> bool {
        !self.finished && self.steps[self.current].is_release()
    }

    /// End the current springback step at the next [`Press::advance`]: the
    /// solver found the blank at rest. No effect in other steps.
    pub fn mark_settled(&mut self) {
        if self.steps[self.current].is_release() {
            self.settled = true;
        }
    }

    /// Whether contact pair `pair` is active in the current step (none is in
    /// a springback step).
    pub fn pair_active(&self, pair: usize) -> bool {
        if self.steps[self.current].is_release() {
            return false;
        }
        match &self.steps[self.current].active_pairs {
            None => true,
            Some(list) => list.contains(&pair),
        }
    }

    /// The end times (s) of the press steps of fixed duration from the
    /// current one on, up to the first step that ends otherwise (by travel,
    /// or at rest).
    pub fn step_ends(&self) -> Vec<f64> {
        let mut t = self.step_start;
        let mut ends = Vec::new();
        for s in &self.steps[self.current..] {
            let StepEnd::Duration(d) = s.end else { break };
            // The same sum as `advance`'s `step_start + duration`.
            t += d;
            ends.push(t);
        }
        ends
    }

    /// Total nominal duration of the programme (s): the sum of the steps'
    /// durations (upper bounds for travel-ended steps).
    pub fn nominal_duration(&self) -> f64 {
        self.steps.iter().map(|s| s.end.duration()).sum()
    }

    /// Move every tool to time `t_next` (s), `dt = t_next − t_n`. `loads[i]`
    /// is what the blank did to tool `i` in the last step (read by
    /// force-controlled tools). Returns the step that began, if one did.
    ///
    /// # Errors
    /// A non-finite or non-positive `dt`.
    pub fn advance(
        &mut self,
        t_next: f64,
        dt: f64,
        loads: &[ToolLoad],
    ) -> Result<Option<StepChange>, FemError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(FemError::InvalidParameter {
                field: "press: time step".into(),
                value: dt,
                unit: "s",
                range: "> 0 and finite",
            });
        }
        let mut change = None;
        if self.finished {
            for v in &mut self.velocities {
                *v = RigidVelocity::default();
            }
            return Ok(None);
        }
        // Step transitions (possibly several tiny steps within one Δt).
        loop {
            let step = &self.steps[self.current];
            let end_time = self.step_start + step.end.duration();
            let travel_done = match step.end {
                StepEnd::Travel { tool, distance, .. } => {
                    (self.poses[tool].translation - self.step_start_pose[tool].translation).norm()
                        >= distance * (1.0 - 1e-12)
                }
                StepEnd::Settled { .. } => self.settled,
                StepEnd::Duration(_) => false,
            };
            if t_next <= end_time * (1.0 + 1e-14) && !travel_done {
                break;
            }
            // Finish the step: place prescribed tools at its end; start the next.
            let t_end = if travel_done { t_next - dt } else { end_time };
            self.place(t_end - self.step_start, 0.0, loads, false);
            if self.current + 1 == self.steps.len() {
                self.finished = true;
                for v in &mut self.velocities {
                    *v = RigidVelocity::default();
                }
                return Ok(change);
            }
            self.current += 1;
            self.settled = false;
            self.step_start = t_end.max(self.step_start);
            self.step_start_pose.clone_from(&self.poses);
            change = Some(StepChange {
                step: self.current,
                time: self.step_start,
            });
        }
        self.place(t_next - self.step_start, dt, loads, true);
        Ok(change)
    }

    /// Place the tools at step time `tau`; with `dt > 0` also set their
    /// mid-step velocities and integrate force-controlled travel.
    fn place(&mut self, tau: f64, dt: f64, loads: &[ToolLoad], integrate: bool) {
        let duration = self.steps[self.current].end.duration();
        for i in 0..self.poses.len() {
            let old = self.poses[i].translation;
            let (new, angular) = self.move_tool(i, tau, dt, duration, loads, integrate);
            if dt > 0.0 {
                self.velocities[i] = RigidVelocity {
                    linear: (new - old) / dt,
                    angular,
                };
            }
            self.poses[i].translation = new;
        }
    }

    /// Tool `i`'s position at step time `tau` under its motion in the current
    /// step (of `duration`) and its angular velocity: force-controlled travel
    /// integrated (with `integrate`), force control reset for other motions.
    fn move_tool(
        &mut self,
        i: usize,
        tau: f64,
        dt: f64,
        duration: f64,
        loads: &[ToolLoad],
        integrate: bool,
    ) -> (Vec3, Vec3) {
        let motion = self.steps[self.current]
            .motions
            .iter()
            .find(|(t, _)| *t == i)
            .map(|(_, m)| m)
            .unwrap_or(&ToolMotion::Hold);
        if !matches!(motion, ToolMotion::Force { .. }) {
            // Force control starts afresh (at rest, no reaction rate)
            // whenever a later step takes it up again.
            self.applied[i] = None;
            self.last_reaction[i] = None;
            self.free_speed[i] = 0.0;
        }
        match motion {
            ToolMotion::Force {
                direction,
                force,
                amplitude,
                mass,
                damping,
                relative_damping,
            } if integrate && dt > 0.0 => {
                let control = ForceControl {
                    direction,
                    force,
                    amplitude,
                    mass: *mass,
                    damping: *damping,
                    relative_damping: *relative_damping,
                };
                let tool = FreeTravel {
                    applied: &mut self.applied[i],
                    last_reaction: &mut self.last_reaction[i],
                    speed: &mut self.free_speed[i],
                };
                let old = self.poses[i].translation;
                let load = loads.get(i).copied().unwrap_or_default();
                let new = control.travel(tool, old, self.initial[i].translation, load, tau, dt);
                (new, Vec3::zeros())
            }
            _ => {
                let start = self.step_start_pose[i].translation;
                kinematic_move(motion, &mut self.poses[i], start, duration, tau, dt)
            }
        }
    }
}

/// The position at step time `tau` of a tool at `pose` (at `start` when the
/// step, of `duration`, began) under a prescribed `motion`, and its angular
/// velocity; turns a spinning tool's pose. A force-controlled tool holds here
/// (its travel is integrated by [`ForceControl::travel`]).
fn kinematic_move(
    motion: &ToolMotion,
    pose: &mut RigidPose,
    start: Vec3,
    duration: f64,
    tau: f64,
    dt: f64,
) -> (Vec3, Vec3) {
    let old = pose.translation;
    let mut angular = Vec3::zeros();
    let new = match motion {
        ToolMotion::Hold | ToolMotion::Force { .. } => old,
        ToolMotion::Spin {
            axis,
            rate,
            amplitude,
        } => {
            if dt > 0.0 {
                angular = spin(pose, axis, *rate, amplitude, tau, dt);
            }
            old
        }
        ToolMotion::Travel {
            direction,
            distance,
            amplitude,
        } => start + direction * (distance * travel_amplitude(amplitude, duration, tau)),
        ToolMotion::Velocity {
            direction,
            speed,
            amplitude,
        } => {
            if dt > 0.0 {
                let a = amplitude.as_ref().map_or(1.0, |a| a.value(tau - 0.5 * dt));
                old + direction * (speed * a * dt)
            } else {
                old
            }
        }
    };
    (new, angular)
}

/// Turn `pose` over the step `dt` ending at step time `tau` at the mid-step
/// rate `rate · A(τ − dt/2)` about the unit `axis`; the angular velocity.
fn spin(
    pose: &mut RigidPose,
    axis: &Vec3,
    rate: f64,
    amplitude: &Option<Amplitude>,
    tau: f64,
    dt: f64,
) -> Vec3 {
    let a = amplitude.as_ref().map_or(1.0, |a| a.value(tau - 0.5 * dt));
    let angular = axis * (rate * a);
    let turn = plugins_api::nalgebra::Rotation3::from_scaled_axis(angular * dt);
    pose.rotation = turn.matrix() * pose.rotation;
    angular
}

/// The travel's amplitude at step time `tau`: its own, else a smooth step
/// over the step's `duration`.
fn travel_amplitude(amplitude: &Option<Amplitude>, duration: f64, tau: f64) -> f64 {
    match amplitude {
        Some(a) => a.value(tau),
        None => Amplitude::SmoothStep {
            t0: 0.0,
            t1: duration,
        }
        .value(tau),
    }
}

/// The parameters of a [`ToolMotion::Force`], borrowed for [`ForceControl::travel`].
struct ForceControl<'a> {
    direction: &'a Vec3,
    force: &'a ForceLaw,
    amplitude: &'a Option<Amplitude>,
    mass: f64,
    damping: f64,
    relative_damping: f64,
}

/// One force-controlled tool's state in [`Press`], as [`ForceControl::travel`] updates it.
struct FreeTravel<'a> {
    /// The force applied in the last advance (N).
    applied: &'a mut Option<f64>,
    /// The last reaction along the direction (N).
    last_reaction: &'a mut Option<f64>,
    /// The mid-step speed of the free travel (mm/s).
    speed: &'a mut f64,
}

impl ForceControl<'_> {
    /// Integrate the free travel of a tool at `old` (initially at `origin`)
    /// over `dt` to step time `tau` under the blank's `load`; its new position.
    fn travel(
        &self,
        tool: FreeTravel<'_>,
        old: Vec3,
        origin: Vec3,
        load: ToolLoad,
        tau: f64,
        dt: f64,
    ) -> Vec3 {
        let direction = self.direction;
        let a_t = self.amplitude.as_ref().map_or(1.0, |a| a.value(tau));
        let compression = -(old - origin).dot(direction);
        let applied = self.force.value(compression) * a_t;
        *tool.applied = Some(applied);
        let speed = *tool.speed;
        let reaction = load.force.dot(direction);
        let mut f = applied + reaction - self.damping * speed;
        let last = tool.last_reaction.replace(reaction);
        if let Some(last) = last
            && self.relative_damping > 0.0
            && load.stiffness > 0.0
        {
            let omega = (load.stiffness / self.mass).sqrt();
            f += 2.0 * self.relative_damping / omega * (reaction - last) / dt;
        }
        *tool.speed += dt * f / self.mass;
        old + direction * (*tool.speed * dt)
    }
}

/// The scene keys of press step `k`, for the errors of [`Press::new`].
struct StepKeys<'a> {
    k: usize,
    step: &'a PressStep,
}

impl StepKeys<'_> {
    /// The key of field `f` of the step, `steps[k] (name).f`.
    fn field(&self, f: &str) -> String {
        format!("steps[{}] ({}).{f}", self.k, self.step.name)
    }

    /// An out-of-range value of field `f` of the step.
    fn bad(&self, f: &str, value: f64, unit: &'static str, range: &'static str) -> FemError {
        FemError::InvalidParameter {
            field: self.field(f),
            value,
            unit,
            range,
        }
    }

    /// Check the step's end: a positive finite duration; a travel end's tool
    /// index (`n` tools) and positive finite distance.
    fn check_end(&self, n: usize) -> Result<(), FemError> {
        let d = self.step.end.duration();
        if !(d.is_finite() && d > 0.0) {
            return Err(self.bad("duration", d, "s", "> 0 and finite"));
        }
        if let StepEnd::Travel { tool, distance, .. } = self.step.end {
            if tool >= n {
                return Err(FemError::InvalidSetup(format!(
                    "{}: tool index {tool} out of range ({n} tools)",
                    self.field("end.tool")
                )));
            }
            if !(distance.is_finite() && distance > 0.0) {
                return Err(self.bad("end.travel", distance, "mm", "> 0 and finite"));
            }
        }
        if let StepEnd::Settled { tolerance, .. } = self.step.end {
            if !(tolerance.is_finite() && tolerance > 0.0 && tolerance < 1.0) {
                return Err(self.bad("tolerance", tolerance, "-", "in (0, 1)"));
            }
            if !self.step.motions.is_empty() {
                return Err(FemError::InvalidSetup(format!(
                    "{}: a springback step moves no tool (the tools let go of the blank)",
                    self.field("motions")
                )));
            }
        }
        Ok(())
    }

    /// Check the motion `m` of tool `tool` (in range) in the step: its unit
    /// direction, amplitude and values.
    fn check_motion(&self, names: &[String], tool: usize, m: &ToolMotion) -> Result<(), FemError> {
        let tool_field = |f: &str| format!("tools.{}.{f}", names.get(tool).map_or("?", |s| s));
        if let Some((direction, amplitude)) = m.direction_and_amplitude() {
            let norm = direction.norm();
            if !(norm.is_finite() && (norm - 1.0).abs() < 1e-9) {
                return Err(FemError::InvalidParameter {
                    field: self.field(&tool_field("direction")),
                    value: norm,
                    unit: "(length of the direction vector)",
                    range: "a unit vector",
                });
            }
            if let Some(a) = amplitude {
                a.validate()?;
            }
        }
        match m {
            ToolMotion::Hold => {}
            ToolMotion::Travel { distance, .. } => {
                if !distance.is_finite() {
                    return Err(self.bad("travel", *distance, "mm", "finite"));
                }
            }
            ToolMotion::Velocity { speed, .. } => {
                if !speed.is_finite() {
                    return Err(self.bad("speed", *speed, "mm/s", "finite"));
                }
            }
            ToolMotion::Spin { rate, .. } => {
                if !rate.is_finite() {
                    return Err(self.bad("rate", *rate, "rad/s", "finite"));
                }
            }
            ToolMotion::Force {
                force,
                mass,
                damping,
                relative_damping,
                ..
            } => {
                force.validate(&self.field(&tool_field("motion")))?;
                if !(0.0..=1.0).contains(relative_damping) {
                    return Err(self.bad("relative_damping", *relative_damping, "-", "[0, 1]"));
                }
                if !(mass.is_finite() && *mass > 0.0) {
                    return Err(self.bad("mass", *mass, "tonne", "> 0 and finite"));
                }
                if !(damping.is_finite() && *damping >= 0.0) {
                    return Err(self.bad("damping", *damping, "N s/mm", ">= 0 and finite"));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("tool{i}")).collect()
    }

    /// A spin turns the tool about its axis through its origin by the rate's
    /// integral (a constant rate for 90° over 1,000 steps: the pose's
    /// rotation is the rotation by 90° about the axis to 1e-12; the
    /// translation does not move), at the angular velocity `axis × rate`
    /// while it turns and at rest after the programme.
    #[test]
    fn spin_turns_about_the_axis_by_the_rate_integral() {
        let axis = Vec3::new(1.0, 2.0, 2.0) / 3.0;
        let rate = std::f64::consts::FRAC_PI_2 / 0.01;
        let steps = vec![PressStep {
            name: "turn".into(),
            end: StepEnd::Duration(0.01),
            motions: vec![(
                0,
                ToolMotion::Spin {
                    axis,
                    rate,
                    amplitude: None,
                },
            )],
            active_pairs: None,
        }];
        let start = RigidPose {
            translation: Vec3::new(5.0, -3.0, 1.0),
            ..RigidPose::default()
        };
        let mut p = Press::new(&names(1), &[start], steps).unwrap();
        let dt = 1e-5;
        for n in 1..=1000 {
            p.advance(n as f64 * dt, dt, &[ToolLoad::default()])
                .unwrap();
            if n == 500 {
                let w = p.velocity(0).angular;
                assert!((w - axis * rate).norm() < 1e-12 * rate, "{w:?}");
            }
        }
        let expected =
            plugins_api::nalgebra::Rotation3::from_scaled_axis(axis * std::f64::consts::FRAC_PI_2);
        let pose = p.pose(0);
        assert!(
            (pose.rotation - expected.matrix()).norm() < 1e-12,
            "{pose:?}"
        );
        assert_eq!(pose.translation, start.translation);
    }

    /// A smooth-step travel reaches its distance exactly, at rest (definition of
    /// the C² smooth step; tolerance 1e-12 mm).
    #[test]
    fn travel_reaches_target_at_rest() {
        let steps = vec![PressStep {
            name: "draw".into(),
            end: StepEnd::Duration(0.01),
            motions: vec![(
                0,
                ToolMotion::Travel {
                    direction: -Vec3::z(),
                    distance: 40.0,
                    amplitude: None,
                },
            )],
            active_pairs: None,
        }];
        let mut p = Press::new(&names(1), &[RigidPose::default()], steps).unwrap();
        let dt = 1e-5;
        let mut t = 0.0;
        let mut vmax: f64 = 0.0;
        for _ in 0..999 {
            t += dt;
            p.advance(t, dt, &[ToolLoad::default()]).unwrap();
            vmax = vmax.max(p.velocity(0).linear.norm());
        }
        assert!(!p.finished());
        t += dt;
        p.advance(t, dt, &[ToolLoad::default()]).unwrap();
        assert!((p.displacement(0).z + 40.0).abs() < 1e-9);
        assert!(p.velocity(0).linear.norm() < 1e-3 * vmax);
        // Peak speed of the smooth step: 15/8 · distance / duration.
        assert!((vmax - 15.0 / 8.0 * 40.0 / 0.01).abs() < 1e-3 * vmax);
        p.advance(t + dt, dt, &[ToolLoad::default()]).unwrap();
        assert!(p.finished());
    }

    /// Force control against a linear spring reaction `R = -k s` settles at
    /// `s = F/k` (statics; tolerance 1e-6 relative).
    #[test]
    fn force_controlled_tool_settles_on_a_spring() {
        let (f, k, m, c) = (4900.0, 1.0e5, 1e-3, 2.0 * (1.0e5f64 * 1e-3).sqrt());
        let steps = vec![PressStep {
            name: "clamp".into(),
            end: StepEnd::Duration(0.1),
            motions: vec![(
                0,
                ToolMotion::Force {
                    direction: -Vec3::z(),
                    force: ForceLaw::Constant(f),
                    amplitude: None,
                    mass: m,
                    damping: c,
                    relative_damping: 0.0,
                },
            )],
            active_pairs: Some(vec![1]),
        }];
        let mut p = Press::new(&names(1), &[RigidPose::default()], steps).unwrap();
        let dt = 1e-5;
        let mut r = Vec3::zeros();
        for n in 1..5000 {
            p.advance(
                n as f64 * dt,
                dt,
                &[ToolLoad {
                    force: r,
                    ..ToolLoad::default()
                }],
            )
            .unwrap();
            // The spring pushes back up, proportional to the downward travel.
            r = Vec3::z() * (k * -p.displacement(0).z);
        }
        assert!((-p.displacement(0).z - f / k).abs() < 1e-6 * f / k);
        assert!(p.pair_active(1) && !p.pair_active(0));
    }

    /// A travel-ended step stops at its travel and hands over to the next step;
    /// the programme's errors name the step and field.
    #[test]
    fn travel_end_and_errors() {
        let steps = vec![
            PressStep {
                name: "approach".into(),
                end: StepEnd::Travel {
                    tool: 0,
                    distance: 1.0,
                    max_duration: 1.0,
                },
                motions: vec![(
                    0,
                    ToolMotion::Velocity {
                        direction: Vec3::x(),
                        speed: 100.0,
                        amplitude: None,
                    },
                )],
                active_pairs: None,
            },
            PressStep {
                name: "dwell".into(),
                end: StepEnd::Duration(1e-3),
                motions: vec![],
                active_pairs: None,
            },
        ];
        let mut p = Press::new(&names(1), &[RigidPose::default()], steps.clone()).unwrap();
        let dt = 1e-4;
        let mut began = None;
        for n in 1..200 {
            if let Some(c) = p
                .advance(n as f64 * dt, dt, &[ToolLoad::default()])
                .unwrap()
            {
                began = Some(c);
            }
        }
        let c = began.expect("the dwell step began");
        assert_eq!(c.step, 1);
        assert!(
            (p.displacement(0).x - 1.0).abs() < 1e-9,
            "{}",
            p.displacement(0).x
        );
        assert!((c.time - 0.01).abs() < 1.5 * dt, "{}", c.time);

        let mut bad = steps;
        bad[1].motions.push((
            0,
            ToolMotion::Force {
                direction: Vec3::z(),
                force: ForceLaw::Constant(1.0),
                amplitude: None,
                mass: 0.0,
                damping: 0.0,
                relative_damping: 0.0,
            },
        ));
        let e = Press::new(&names(1), &[RigidPose::default()], bad).unwrap_err();
        assert!(e.to_string().contains("steps[1] (dwell).mass"), "{e}");
        let e = Press::new(&names(1), &[RigidPose::default()], vec![]).unwrap_err();
        assert!(e.to_string().contains("no steps"), "{e}");
    }

    /// A force-controlled tool of mass `m` pressing down with `F` on a support
    /// spring `k` whose surface rises at `v`; returns the force delivered to
    /// the support over the second half of `T`: (mean, min, max).
    fn rising_support(damping: f64, relative_damping: f64) -> (f64, f64, f64) {
        let (f, k, m, v) = (4900.0, 2.0e6, 0.01, 20.0);
        let steps = vec![PressStep {
            name: "draw".into(),
            end: StepEnd::Duration(0.05),
            motions: vec![(
                0,
                ToolMotion::Force {
                    direction: -Vec3::z(),
                    force: ForceLaw::Constant(f),
                    amplitude: None,
                    mass: m,
                    damping,
                    relative_damping,
                },
            )],
            active_pairs: None,
        }];
        let mut p = Press::new(&names(1), &[RigidPose::default()], steps).unwrap();
        let dt = 1e-6;
        let mut load = ToolLoad::default();
        let (mut sum, mut time, mut lo, mut hi) = (0.0, 0.0, f64::INFINITY, 0.0f64);
        for n in 1..=50_000 {
            let t = n as f64 * dt;
            p.advance(t, dt, &[load]).unwrap();
            // The support's surface starts at the tool (z = 0) and rises.
            let pen = (v * t - p.displacement(0).z).max(0.0);
            let delivered = k * pen;
            load = ToolLoad {
                force: Vec3::z() * delivered,
                stiffness: if pen > 0.0 { k } else { 0.0 },
            };
            if n > 25_000 {
                sum += delivered * dt;
                time += dt;
                lo = lo.min(delivered);
                hi = hi.max(delivered);
            }
        }
        (sum / time, lo, hi)
    }

    /// Force control delivers its force, in the mean, to a support that
    /// pushes the tool back at a steady speed (momentum balance: the mean
    /// delivered force is `F − c ṡ − m Δṡ/T`); a 500 N·s/mm dashpot
    /// would add `c v` = 10 kN to the prescribed 4.9 kN. Relative damping quiets
    /// the bounce without biasing the mean: 0.5 % of `F`. Undamped, the
    /// bounce excited by the sudden start persists (amplitude ≈ 5 kN at
    /// ω = √(k/m)), and its momentum `m Δṡ / T` alone moves a window's mean
    /// by up to ≈ 0.6 %: 1 %.
    #[test]
    fn force_control_delivers_its_force_on_a_rising_support() {
        let f = 4900.0;
        let (mean, lo, hi) = rising_support(0.0, 0.0);
        assert!((mean / f - 1.0).abs() < 1e-2, "undamped: mean {mean}");
        let (mean_rel, lo_rel, hi_rel) = rising_support(0.0, 0.5);
        assert!(
            (mean_rel / f - 1.0).abs() < 5e-3,
            "relative: mean {mean_rel}"
        );
        assert!(hi_rel - lo_rel < 0.01 * f, "relative: {lo_rel}..{hi_rel}");
        assert!(hi - lo > hi_rel - lo_rel, "undamped {lo}..{hi}");
        let (mean_dashpot, ..) = rising_support(500.0, 0.0);
        assert!(
            (mean_dashpot - (f + 500.0 * 20.0)).abs() < 5e-3 * f,
            "dashpot: mean {mean_dashpot}"
        );
    }

    /// A gas-spring curve is linear between its rows and constant beyond.
    #[test]
    fn force_curve_interpolates_and_holds_its_ends() {
        let law = ForceLaw::Compression(vec![(0.0, 1000.0), (10.0, 2000.0), (20.0, 2500.0)]);
        assert_eq!(law.value(-5.0), 1000.0);
        assert_eq!(law.value(5.0), 1500.0);
        assert_eq!(law.value(15.0), 2250.0);
        assert_eq!(law.value(30.0), 2500.0);
        let bad = ForceLaw::Compression(vec![(0.0, 1.0), (0.0, 2.0)]);
        let e = bad.validate("steps[1]").unwrap_err().to_string();
        assert!(e.contains("force_curve[1][0]"), "{e}");
        assert!(ForceLaw::Compression(vec![]).validate("s").is_err());
        assert!(ForceLaw::Constant(-1.0).validate("s").is_err());
    }
}
