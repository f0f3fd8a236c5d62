//! The press scheduler: a sequence of press steps that move rigid bodies (the tools)
//! by prescribed travel or velocity, by force control on their own rigid-body
//! degree of freedom, or hold them, and that switch contact pairs on and off.
//!
//! Step 1 of an explicit step (design.md): [`Press::advance`] places every tool
//! at `t_{n+1}` and gives its mid-step velocity `v_{n+1/2} = (x_{n+1} − x_n)/Δt`,
//! the time level of the blank's velocities. The scheduler knows tools only as
//! rigid bodies (pose and velocity); it does not know their geometry.
//!
//! Force control (a blankholder on gas springs, a cushion): the tool moves along
//! a unit `direction` only; its travel `s` obeys `m s̈ = F A(τ) + R·direction − c ṡ`,
//! where `R` is the force the blank exerts on the tool through contact (the
//! previous step's reaction), integrated by central difference like the blank.
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
    /// Force control: `force · A(τ)` (N) pushes the tool along the unit
    /// `direction`; its travel along `direction` is integrated with the contact
    /// reaction; the other degrees of freedom are held.
    Force {
        /// Unit direction of the applied force and of the free travel.
        direction: Vec3,
        /// Applied force (N), `≥ 0`.
        force: f64,
        /// Scale of the force in step time; `None`: constant 1.
        amplitude: Option<Amplitude>,
        /// Mass of the tool's free degree of freedom (tonne), `> 0`.
        mass: f64,
        /// Viscous damping of the free travel (N·s/mm), `≥ 0`.
        damping: f64,
    },
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
}

impl StepEnd {
    fn duration(&self) -> f64 {
        match *self {
            StepEnd::Duration(d) => d,
            StepEnd::Travel { max_duration, .. } => max_duration,
        }
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
    current: usize,
    step_start: f64,
    finished: bool,
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
            let field = |f: &str| format!("steps[{k}] ({}).{f}", s.name);
            let bad = |f: &str, value: f64, unit: &'static str, range: &'static str| {
                FemError::InvalidParameter {
                    field: field(f),
                    value,
                    unit,
                    range,
                }
            };
            let d = s.end.duration();
            if !(d.is_finite() && d > 0.0) {
                return Err(bad("duration", d, "s", "> 0 and finite"));
            }
            if let StepEnd::Travel { tool, distance, .. } = s.end {
                if tool >= n {
                    return Err(FemError::InvalidSetup(format!(
                        "{}: tool index {tool} out of range ({n} tools)",
                        field("end.tool")
                    )));
                }
                if !(distance.is_finite() && distance > 0.0) {
                    return Err(bad("end.travel", distance, "mm", "> 0 and finite"));
                }
            }
            for (tool, m) in &s.motions {
                if *tool >= n {
                    return Err(FemError::InvalidSetup(format!(
                        "{}: tool index {tool} out of range ({n} tools)",
                        field("motions")
                    )));
                }
                let tool_field =
                    |f: &str| format!("tools.{}.{f}", names.get(*tool).map_or("?", |s| s));
                let check_dir = |dir: &Vec3| -> Result<(), FemError> {
                    let norm = dir.norm();
                    if !(norm.is_finite() && (norm - 1.0).abs() < 1e-9) {
                        return Err(FemError::InvalidParameter {
                            field: field(&tool_field("direction")),
                            value: norm,
                            unit: "(length of the direction vector)",
                            range: "a unit vector",
                        });
                    }
                    Ok(())
                };
                let check_amp = |a: &Option<Amplitude>| -> Result<(), FemError> {
                    if let Some(a) = a {
                        a.validate()?;
                    }
                    Ok(())
                };
                if let Some((direction, amplitude)) = m.direction_and_amplitude() {
                    check_dir(direction)?;
                    check_amp(amplitude)?;
                }
                match m {
                    ToolMotion::Hold => {}
                    ToolMotion::Travel { distance, .. } => {
                        if !distance.is_finite() {
                            return Err(bad("travel", *distance, "mm", "finite"));
                        }
                    }
                    ToolMotion::Velocity { speed, .. } => {
                        if !speed.is_finite() {
                            return Err(bad("speed", *speed, "mm/s", "finite"));
                        }
                    }
                    ToolMotion::Force {
                        force,
                        mass,
                        damping,
                        ..
                    } => {
                        if !(force.is_finite() && *force >= 0.0) {
                            return Err(bad("force", *force, "N", ">= 0 and finite"));
                        }
                        if !(mass.is_finite() && *mass > 0.0) {
                            return Err(bad("mass", *mass, "tonne", "> 0 and finite"));
                        }
                        if !(damping.is_finite() && *damping >= 0.0) {
                            return Err(bad("damping", *damping, "N s/mm", ">= 0 and finite"));
                        }
                    }
                }
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
            current: 0,
            step_start: 0.0,
            finished: false,
        })
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

    /// Displacement of tool `i` from its initial pose (mm).
    pub fn displacement(&self, i: usize) -> Vec3 {
        self.poses[i].translation - self.initial[i].translation
    }

    /// Whether contact pair `pair` is active in the current step.
    pub fn pair_active(&self, pair: usize) -> bool {
        match &self.steps[self.current].active_pairs {
            None => true,
            Some(list) => list.contains(&pair),
        }
    }

    /// Total nominal duration of the programme (s): the sum of the steps'
    /// durations (upper bounds for travel-ended steps).
    pub fn nominal_duration(&self) -> f64 {
        self.steps.iter().map(|s| s.end.duration()).sum()
    }

    /// Move every tool to time `t_next` (s), `dt = t_next − t_n`. `reactions[i]`
    /// is the force (N) the blank exerted on tool `i` in the last step (read by
    /// force-controlled tools). Returns the step that began, if one did.
    ///
    /// # Errors
    /// A non-finite or non-positive `dt`.
    pub fn advance(
        &mut self,
        t_next: f64,
        dt: f64,
        reactions: &[Vec3],
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
                StepEnd::Duration(_) => false,
            };
            if t_next <= end_time * (1.0 + 1e-14) && !travel_done {
                break;
            }
            // Finish the step: place prescribed tools at its end; start the next.
            let t_end = if travel_done { t_next - dt } else { end_time };
            self.place(t_end - self.step_start, 0.0, reactions, false);
            if self.current + 1 == self.steps.len() {
                self.finished = true;
                for v in &mut self.velocities {
                    *v = RigidVelocity::default();
                }
                return Ok(change);
            }
            self.current += 1;
            self.step_start = t_end.max(self.step_start);
            self.step_start_pose.clone_from(&self.poses);
            change = Some(StepChange {
                step: self.current,
                time: self.step_start,
            });
        }
        self.place(t_next - self.step_start, dt, reactions, true);
        Ok(change)
    }

    /// Place the tools at step time `tau`; with `dt > 0` also set their
    /// mid-step velocities and integrate force-controlled travel.
    fn place(&mut self, tau: f64, dt: f64, reactions: &[Vec3], integrate: bool) {
        let step = &self.steps[self.current];
        let duration = step.end.duration();
        for i in 0..self.poses.len() {
            let motion = step
                .motions
                .iter()
                .find(|(t, _)| *t == i)
                .map(|(_, m)| m)
                .unwrap_or(&ToolMotion::Hold);
            let old = self.poses[i].translation;
            let start = self.step_start_pose[i].translation;
            let new = match motion {
                ToolMotion::Hold => old,
                ToolMotion::Travel {
                    direction,
                    distance,
                    amplitude,
                } => {
                    let a = match amplitude {
                        Some(a) => a.value(tau),
                        None => Amplitude::SmoothStep {
                            t0: 0.0,
                            t1: duration,
                        }
                        .value(tau),
                    };
                    start + direction * (distance * a)
                }
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
                ToolMotion::Force {
                    direction,
                    force,
                    amplitude,
                    mass,
                    damping,
                } => {
                    if integrate && dt > 0.0 {
                        let a_t = amplitude.as_ref().map_or(1.0, |a| a.value(tau));
                        let r = reactions.get(i).copied().unwrap_or_else(Vec3::zeros);
                        let f = force * a_t + r.dot(direction) - damping * self.free_speed[i];
                        self.free_speed[i] += dt * f / mass;
                        old + direction * (self.free_speed[i] * dt)
                    } else {
                        old
                    }
                }
            };
            if dt > 0.0 {
                self.velocities[i] = RigidVelocity {
                    linear: (new - old) / dt,
                    angular: Vec3::zeros(),
                };
            }
            self.poses[i].translation = new;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("tool{i}")).collect()
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
            p.advance(t, dt, &[Vec3::zeros()]).unwrap();
            vmax = vmax.max(p.velocity(0).linear.norm());
        }
        assert!(!p.finished());
        t += dt;
        p.advance(t, dt, &[Vec3::zeros()]).unwrap();
        assert!((p.displacement(0).z + 40.0).abs() < 1e-9);
        assert!(p.velocity(0).linear.norm() < 1e-3 * vmax);
        // Peak speed of the smooth step: 15/8 · distance / duration.
        assert!((vmax - 15.0 / 8.0 * 40.0 / 0.01).abs() < 1e-3 * vmax);
        p.advance(t + dt, dt, &[Vec3::zeros()]).unwrap();
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
                    force: f,
                    amplitude: None,
                    mass: m,
                    damping: c,
                },
            )],
            active_pairs: Some(vec![1]),
        }];
        let mut p = Press::new(&names(1), &[RigidPose::default()], steps).unwrap();
        let dt = 1e-5;
        let mut r = Vec3::zeros();
        for n in 1..5000 {
            p.advance(n as f64 * dt, dt, &[r]).unwrap();
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
            if let Some(c) = p.advance(n as f64 * dt, dt, &[Vec3::zeros()]).unwrap() {
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
                force: 1.0,
                amplitude: None,
                mass: 0.0,
                damping: 0.0,
            },
        ));
        let e = Press::new(&names(1), &[RigidPose::default()], bad).unwrap_err();
        assert!(e.to_string().contains("steps[1] (dwell).mass"), "{e}");
        let e = Press::new(&names(1), &[RigidPose::default()], vec![]).unwrap_err();
        assert!(e.to_string().contains("no steps"), "{e}");
    }
}
