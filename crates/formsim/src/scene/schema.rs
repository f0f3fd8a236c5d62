//! The scene file's schema: every table and key of `docs/scene-format.md`, as
//! serde structures (unknown keys are errors). Ranges are checked afterwards by
//! [`super::validate::validate`]; building the model is [`super::build()`]'s work.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A whole scene file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `[scene]`: name, kind, units.
    pub scene: Meta,
    /// `[blank]`: mesh, thickness, element, material.
    pub blank: Blank,
    /// `[tools.NAME]`: rigid tools, keys of `docs/tools.md`.
    #[serde(default)]
    pub tools: toml::Table,
    /// `[contact]`: friction law, formulation, parameters, pairs.
    #[serde(default)]
    pub contact: Contact,
    /// `[[steps]]`: the press programme.
    #[serde(default)]
    pub steps: Vec<Step>,
    /// `[solver]`: time step, mass scaling, damping, end time.
    #[serde(default)]
    pub solver: SolverSection,
    /// `[[boundary]]`: symmetry planes, fixed and prescribed DOFs on node sets.
    #[serde(default)]
    pub boundary: Vec<Boundary>,
    /// `[[loads]]`: nodal forces on node sets.
    #[serde(default)]
    pub loads: Vec<Load>,
    /// `[[springs]]`: springs from node sets to anchors dragged along an axis.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub springs: Vec<AnchorSpring>,
    /// `[[drawbeads]]`: drawbeads as equivalent line forces on tools.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub drawbeads: Vec<super::drawbeads::DrawbeadEntry>,
    /// `[output]`: what to write.
    #[serde(default)]
    pub output: Output,
    /// `[formability]`: the forming limit curve the run's strains are
    /// read against (none without the table).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formability: Option<crate::formability::settings::FormabilitySection>,
}

/// `[scene]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    /// Name used in reports and `summary.json`.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// `generic` (default), `square-cup` or a registered reference check
    /// (`capstan`, `block-on-plane`, `strip-draw`): [`super::kind::resolve`].
    #[serde(default = "default_kind")]
    pub kind: String,
    /// The unit system; formsim computes in mm, N, MPa, tonne, s only.
    pub units: Units,
    /// `"quasi-static"` (default: the run warns when its kinetic energy
    /// exceeds 5 % of the external work while forming) or `"dynamic"` (a
    /// scene dynamic by design: an impact, a flight, an oscillator; the
    /// quasi-static check does not apply).
    #[serde(default)]
    pub regime: Regime,
}

/// Whether a scene is meant to be quasi-static (`scene.regime`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// Inertia should not matter: the kinetic-energy check applies.
    #[default]
    QuasiStatic,
    /// Dynamic by design: the kinetic-energy check does not apply.
    Dynamic,
}

impl Regime {
    /// The name as written in a scene.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::QuasiStatic => "quasi-static",
            Self::Dynamic => "dynamic",
        }
    }
}

fn default_kind() -> String {
    "generic".into()
}

/// `[scene.units]`: must be mm, N, MPa, tonne, s (stated so that every scene says it).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Units {
    /// `"mm"`.
    pub length: String,
    /// `"N"`.
    pub force: String,
    /// `"MPa"`.
    pub stress: String,
    /// `"tonne"`.
    pub mass: String,
    /// `"s"`.
    pub time: String,
}

/// `[blank]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Blank {
    /// `[blank.mesh]`: generator or file.
    pub mesh: MeshSpec,
    /// Initial thickness (mm).
    pub thickness: f64,
    /// A registered shell element (`formsim components`):
    /// `belytschko-tsay` (default) or `fully-integrated`.
    #[serde(default = "default_element")]
    pub element: String,
    /// The element's own keys, by the names it declares (`formsim
    /// components` lists them); the built-in elements have none.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub element_parameters: BTreeMap<String, f64>,
    /// Through-thickness integration points (default 5).
    #[serde(default = "default_points")]
    pub integration_points: usize,
    /// Hourglass coefficient of the Belytschko–Tsay shell (default 0.05).
    #[serde(default = "default_hourglass")]
    pub hourglass: f64,
    /// Drilling coefficient γ of both shells: a penalty `γ G t A` on the nodal
    /// rotation about the normal relative to the element's in-plane spin
    /// (default 1e-3, range [0, 0.1]; docs/shells.md).
    #[serde(default = "default_drilling")]
    pub drilling: f64,
    /// Warping correction of either shell (after Belytschko–Wong–Chiang:
    /// fibres along the warped surface's nodal normals, twisted metric;
    /// default on; docs/shells.md).
    #[serde(default = "default_warping_correction")]
    pub warping_correction: bool,
    /// `[blank.material]`.
    pub material: Material,
    /// A state file saved by `formsim run --save-state` (relative to the
    /// scene file): the blank starts from it (docs/stages.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial_state: Option<String>,
}

fn default_points() -> usize {
    5
}
fn default_hourglass() -> f64 {
    0.05
}
fn default_drilling() -> f64 {
    shell_elements::formulation::DEFAULT_DRILLING
}

fn default_warping_correction() -> bool {
    shell_elements::BelytschkoTsay::default().warping_correction
}

fn default_element() -> String {
    "belytschko-tsay".into()
}

/// `[blank.mesh]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MeshSpec {
    /// A structured rectangle in the plane `z = origin.z`, corner at `origin`;
    /// node sets `x0`, `x1`, `y0`, `y1` (edges), `all`.
    Rectangle {
        /// `[lx, ly]` (mm).
        size: [f64; 2],
        /// Elements per side: one number for both, or `[nx, ny]`.
        divisions: Divisions,
        /// Corner of the rectangle (mm); default `[0, 0, 0]`.
        #[serde(default)]
        origin: [f64; 3],
    },
    /// An Abaqus `.inp` or Gmsh `.msh` file, relative to the scene file.
    File {
        /// Path of the mesh file.
        path: String,
        /// Translation applied to every node (mm).
        #[serde(default)]
        translate: [f64; 3],
    },
    /// A strip wrapped over a drum of axis `y` through the origin: a horizontal
    /// tail on top (pull end, set `pull`, at `x = tail`), an arc of `angle_deg`
    /// over the drum, a straight tail leaving it (hold end, set `hold`); set
    /// `centre` is the strip's centre line. Mid-surface at `radius + t/2`.
    WrappedStrip {
        /// Drum radius (mm).
        radius: f64,
        /// Strip width (mm), three nodes across.
        width: f64,
        /// Length of each straight tail (mm).
        tail: f64,
        /// Wrap angle (degrees), in (0, 180].
        angle_deg: f64,
        /// Target element length along the strip (mm).
        element_size: f64,
    },
}

/// Elements per side of a rectangle.
#[derive(Debug, Clone, Copy, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Divisions {
    /// The same number along x and y.
    Both(i64),
    /// `[nx, ny]`.
    Each([i64; 2]),
}

impl Divisions {
    /// `(nx, ny)`.
    pub fn pair(self) -> (i64, i64) {
        match self {
            Divisions::Both(n) => (n, n),
            Divisions::Each([a, b]) => (a, b),
        }
    }
}

/// `[blank.material]`: elastic–plastic under plane stress, isotropic (J2)
/// or, with `r_values`, Hill'48 anisotropic.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus (MPa).
    pub youngs_modulus: f64,
    /// Poisson's ratio (-).
    pub poissons_ratio: f64,
    /// Density (tonne/mm³).
    pub density: f64,
    /// `[blank.material.hardening]` (along the rolling direction with
    /// `r_values`); required by the built-in models, refused with a plugin
    /// (whose hardening is in `parameters`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hardening: Option<HardeningSpec>,
    /// Hill'48 plane-stress anisotropy: Lankford coefficients `[r0, r45,
    /// r90]` (-) at 0°, 45°, 90° to the rolling direction, which is global x
    /// projected onto the blank. Absent: isotropic J2 (von Mises).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r_values: Option<[f64; 3]>,
    /// A registered material model (`formsim components`): `j2`, `hill48`
    /// or `plugin`. Absent: `plugin` with `plugin`, `hill48` with
    /// `r_values`, else `j2`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// A user material's shared library (model `plugin`), relative to the scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plugin: Option<String>,
    /// The user material's parameters, by the names of its schema
    /// (`formsim plugin check PATH` lists them); `youngs_modulus`,
    /// `poissons_ratio` and `density` are passed on from above unless set here.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, f64>,
}

/// The material model a scene asks for: `blank.material.model`, else
/// `plugin` with a plugin, `hill48` with r-values and `j2` without.
pub fn material_model(scene: &Scene) -> String {
    let m = &scene.blank.material;
    match (&m.model, &m.plugin, m.r_values) {
        (Some(name), _, _) => name.clone(),
        (None, Some(_), _) => "plugin".into(),
        (None, None, Some(_)) => "hill48".into(),
        (None, None, None) => "j2".into(),
    }
}

/// Hardening curve `σ_y(ε_p)`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum HardeningSpec {
    /// Swift: `σ_y = k (eps0 + ε_p)^n` (MPa).
    Swift {
        /// `K` (MPa).
        k: f64,
        /// `ε0` (-).
        eps0: f64,
        /// `n` (-).
        n: f64,
    },
    /// Piecewise linear through `(ε_p, σ_y)` points.
    Table {
        /// Plastic strains (-), increasing from 0.
        eps_p: Vec<f64>,
        /// Flow stresses (MPa).
        sigma_y: Vec<f64>,
    },
    /// Perfectly plastic at `sigma_y` (MPa).
    Perfect {
        /// Yield stress (MPa).
        sigma_y: f64,
    },
    /// Elastic only (no yield).
    Elastic,
}

/// `[contact]`: the defaults of every pair, and the pairs.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Contact {
    /// Friction law by name (`ac`, `wvs`, `wh`, `levanov` or a linked plugin).
    #[serde(default = "default_law")]
    pub law: String,
    /// A dynamic plugin (shared library, relative to the scene) instead of `law`.
    #[serde(default)]
    pub plugin: Option<String>,
    /// Kinematic formulation (`convective`, `jaumann`, `lagrangian`, `updated-lagrangian`).
    #[serde(default = "default_formulation")]
    pub formulation: String,
    /// Law parameters per law name: `[contact.params.ac] mu = 0.144`, …; the
    /// table of the active law is used (the plugin's: `[contact.params.plugin]`).
    #[serde(default)]
    pub params: BTreeMap<String, BTreeMap<String, f64>>,
    /// Penalty scale factor `s` in `k = s K A / d` (-); default 0.1.
    #[serde(default = "default_penalty_scale")]
    pub penalty_scale: f64,
    /// Normal damping as a fraction of critical (-); default 0.
    #[serde(default)]
    pub damping: f64,
    /// Projection margin beyond half the thickness (mm); default 1.
    #[serde(default = "default_margin")]
    pub search_margin: f64,
    /// `[[contact.pairs]]`.
    #[serde(default)]
    pub pairs: Vec<PairEntry>,
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            law: default_law(),
            plugin: None,
            formulation: default_formulation(),
            params: BTreeMap::new(),
            penalty_scale: default_penalty_scale(),
            damping: 0.0,
            search_margin: default_margin(),
            pairs: Vec::new(),
        }
    }
}

fn default_law() -> String {
    "ac".into()
}
fn default_formulation() -> String {
    "convective".into()
}
fn default_penalty_scale() -> f64 {
    0.1
}
fn default_margin() -> f64 {
    1.0
}

/// `[[contact.pairs]]`: the blank against one tool.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PairEntry {
    /// Tool name (a `[tools.NAME]`).
    pub tool: String,
    /// Pair name; default `TOOL-blank`.
    #[serde(default)]
    pub name: Option<String>,
    /// Law of this pair instead of `contact.law`.
    #[serde(default)]
    pub law: Option<String>,
    /// Formulation of this pair instead of `contact.formulation`.
    #[serde(default)]
    pub formulation: Option<String>,
    /// Penalty scale of this pair instead of `contact.penalty_scale`.
    #[serde(default)]
    pub penalty_scale: Option<f64>,
}

/// A time amplitude: `"smooth-step"`, `"linear"` (over the press step; not
/// for boundary conditions and loads, which run on absolute time),
/// `"constant"`, a ramp `{ shape = "smooth-step" | "linear", t0, t1 }`, or a
/// table `[[t, A], …]` (t in s from the start of the step, or of the run for
/// boundary conditions and loads).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum AmplitudeSpec {
    /// A named shape over the step.
    Named(String),
    /// Piecewise linear.
    Table(Vec<[f64; 2]>),
    /// A ramp from 0 at `t0` to 1 at `t1`.
    Ramp {
        /// `"smooth-step"` or `"linear"`.
        shape: String,
        /// Start (s).
        t0: f64,
        /// End (s).
        t1: f64,
    },
}

/// `[[steps]]`: one press step.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// Name for reports.
    pub name: String,
    /// `"press"` (the default: tools move, contact on) or `"springback"`
    /// (the tools let go and the blank comes to rest).
    #[serde(default, skip_serializing_if = "StepKind::is_press")]
    pub kind: StepKind,
    /// Springback: `"dynamic-relaxation"` (the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<String>,
    /// Springback: the residual force ratio at which the blank is at rest
    /// (default 1e-5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Duration (s), the longest a springback step may take; or give `until`.
    #[serde(default)]
    pub duration: Option<f64>,
    /// End when a tool has travelled a distance.
    #[serde(default)]
    pub until: Option<TravelEnd>,
    /// Tool motions; unlisted tools hold.
    #[serde(default)]
    pub motions: Vec<Motion>,
    /// Tools whose contact pairs are active in this step; default all.
    #[serde(default)]
    pub pairs: Option<Vec<String>>,
}

impl Step {
    /// A springback step's method, its default filled in.
    pub fn springback_method(&self) -> &str {
        self.method.as_deref().unwrap_or(SPRINGBACK_METHODS[0])
    }

    /// A springback step's residual force ratio, its default filled in.
    pub fn springback_tolerance(&self) -> f64 {
        self.tolerance.unwrap_or(SPRINGBACK_TOLERANCE)
    }
}

/// What a press step does.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StepKind {
    /// Tools move as the step's motions say; contact as `pairs` says.
    #[default]
    Press,
    /// The tools let go of the blank (contact ends, they hold) and the blank
    /// comes to rest at its springback shape.
    Springback,
}

impl StepKind {
    fn is_press(&self) -> bool {
        *self == StepKind::Press
    }
}

/// The springback methods a `kind = "springback"` step may name.
/// The first is the default.
pub const SPRINGBACK_METHODS: [&str; 2] = ["implicit", "dynamic-relaxation"];

/// A springback step's residual force ratio when it gives none.
pub const SPRINGBACK_TOLERANCE: f64 = 1e-5;

/// `until = { tool, distance, max_duration }`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TravelEnd {
    /// Tool name.
    pub tool: String,
    /// Travel (mm).
    pub distance: f64,
    /// Upper bound of the step's duration (s).
    pub max_duration: f64,
}

/// `[[steps.motions]]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Motion {
    /// Stay put.
    Hold {
        /// Tool name.
        tool: String,
    },
    /// Travel a distance along a direction over the step.
    Travel {
        /// Tool name.
        tool: String,
        /// Direction (normalised by formsim).
        direction: [f64; 3],
        /// Distance (mm).
        distance: f64,
        /// Shape of the travel over the step; default `"smooth-step"`.
        #[serde(default)]
        amplitude: Option<AmplitudeSpec>,
    },
    /// Move at a speed along a direction.
    Velocity {
        /// Tool name.
        tool: String,
        /// Direction (normalised by formsim).
        direction: [f64; 3],
        /// Speed (mm/s).
        speed: f64,
        /// Scale of the speed; default `"constant"`.
        #[serde(default)]
        amplitude: Option<AmplitudeSpec>,
    },
    /// Turn about an axis through the tool's origin at a rate.
    Spin {
        /// Tool name.
        tool: String,
        /// Axis of the rotation (normalised by formsim), right-handed.
        axis: [f64; 3],
        /// Rotation rate (rad/s).
        rate: f64,
        /// Scale of the rate; default `"constant"`.
        #[serde(default)]
        amplitude: Option<AmplitudeSpec>,
    },
    /// Force control on the tool's own rigid-body DOF along `direction`.
    Force {
        /// Tool name.
        tool: String,
        /// Direction of the force and of the free travel.
        direction: [f64; 3],
        /// Constant force (N) on the model (a quarter model carries a quarter
        /// of the press force); give this or `force_curve`.
        #[serde(default)]
        force: Option<f64>,
        /// Gas-spring curve: `[compression mm, force N]` rows, the compression
        /// being the travel against `direction` since the start (docs/contact.md).
        #[serde(default)]
        force_curve: Option<Vec<[f64; 2]>>,
        /// Scale of the force; default `"constant"`.
        #[serde(default)]
        amplitude: Option<AmplitudeSpec>,
        /// Mass of the free DOF (tonne); default 0.01.
        #[serde(default = "default_tool_mass")]
        mass: f64,
        /// Absolute dashpot on the free DOF (N·s/mm); default 0 (none). A
        /// dashpot subtracts `damping × speed` from the delivered force.
        #[serde(default)]
        damping: f64,
        /// Damping of the tool's motion relative to the blank under it, as a
        /// fraction of critical (-, [0, 1]); default 0 (docs/contact.md).
        #[serde(default)]
        relative_damping: f64,
    },
}

fn default_tool_mass() -> f64 {
    0.01
}

impl Motion {
    /// The force law of a `force` motion (`None` for other motions, or when
    /// neither or both of `force` and `force_curve` are given).
    pub fn force_law(&self) -> Option<fem_core::ForceLaw> {
        match self {
            Motion::Force {
                force: Some(f),
                force_curve: None,
                ..
            } => Some(fem_core::ForceLaw::Constant(*f)),
            Motion::Force {
                force: None,
                force_curve: Some(rows),
                ..
            } => Some(fem_core::ForceLaw::Compression(
                rows.iter().map(|r| (r[0], r[1])).collect(),
            )),
            _ => None,
        }
    }
}

impl Motion {
    /// One line for reports: `punch travels 40 mm along [0, 0, -1] (smooth-step)`.
    pub fn describe(&self) -> String {
        let amp = |a: &Option<AmplitudeSpec>, default: &str| match a {
            None => default.to_string(),
            Some(AmplitudeSpec::Named(n)) => n.clone(),
            Some(AmplitudeSpec::Ramp { shape, t0, t1 }) => format!("{shape} {t0}..{t1} s"),
            Some(AmplitudeSpec::Table(rows)) => format!("table of {} points", rows.len()),
        };
        match self {
            Motion::Hold { tool } => format!("{tool} holds"),
            Motion::Travel {
                tool,
                direction,
                distance,
                amplitude,
            } => format!(
                "{tool} travels {distance} mm along {direction:?} ({})",
                amp(amplitude, "smooth-step")
            ),
            Motion::Velocity {
                tool,
                direction,
                speed,
                amplitude,
            } => format!(
                "{tool} moves at {speed} mm/s along {direction:?} ({})",
                amp(amplitude, "constant")
            ),
            Motion::Spin {
                tool,
                axis,
                rate,
                amplitude,
            } => format!(
                "{tool} turns at {rate} rad/s about {axis:?} ({})",
                amp(amplitude, "constant")
            ),
            Motion::Force {
                tool,
                direction,
                force,
                force_curve,
                amplitude,
                mass,
                damping,
                relative_damping,
            } => {
                let what = match (force, force_curve) {
                    (Some(f), _) => format!("{f} N"),
                    (None, Some(rows)) => format!("a gas-spring curve of {} rows", rows.len()),
                    _ => "no force".to_string(),
                };
                format!(
                    "{tool} pushed with {what} along {direction:?} ({}), mass {mass} t, dashpot {damping} N*s/mm, relative damping {relative_damping}",
                    amp(amplitude, "constant")
                )
            }
        }
    }

    /// The tool it moves.
    pub fn tool(&self) -> &str {
        match self {
            Motion::Hold { tool }
            | Motion::Travel { tool, .. }
            | Motion::Velocity { tool, .. }
            | Motion::Spin { tool, .. }
            | Motion::Force { tool, .. } => tool,
        }
    }
}

/// `[solver]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// Time-step safety factor (-); default 0.9.
    #[serde(default = "default_safety")]
    pub safety_factor: f64,
    /// Fixed-time-step mass scaling: the step to run at (s); default none.
    #[serde(default)]
    pub mass_scaling_dt: Option<f64>,
    /// How `mass_scaling_dt` is reached: `"conventional"` (default: mass
    /// added to the nodes) or `"selective"` (inertia added to the shells'
    /// deformation modes only).
    #[serde(default)]
    pub mass_scaling: MassScalingKind,
    /// Selective scaling's mass-solve tolerance, `|f − (M + ΔM) a| / |f|`
    /// (-); default 1e-4.
    #[serde(default = "default_mass_scaling_tolerance")]
    pub mass_scaling_tolerance: f64,
    /// Mass-proportional damping (1/s); default 0.
    #[serde(default)]
    pub damping: f64,
    /// End of the run (s); default the press programme's nominal duration.
    #[serde(default)]
    pub end_time: Option<f64>,
    /// Upper bound of the time step (s).
    #[serde(default)]
    pub dt_max: Option<f64>,
    /// A fixed time step (s): no safety factor, no mass scaling; the run
    /// stops, naming the element or node, where the stable limit falls below it.
    #[serde(default)]
    pub fixed_dt: Option<f64>,
    /// Land on the end of every press step of fixed duration, as a run
    /// ending there does (default off; docs/stages.md): a single run then
    /// takes the same steps as the same programme formed in stages.
    #[serde(default)]
    pub land_on_step_ends: bool,
}

impl Default for SolverSection {
    fn default() -> Self {
        Self {
            safety_factor: default_safety(),
            mass_scaling_dt: None,
            mass_scaling: MassScalingKind::default(),
            mass_scaling_tolerance: default_mass_scaling_tolerance(),
            damping: 0.0,
            end_time: None,
            dt_max: None,
            fixed_dt: None,
            land_on_step_ends: false,
        }
    }
}

fn default_safety() -> f64 {
    0.9
}

fn default_mass_scaling_tolerance() -> f64 {
    fem_core::MassScaling::DEFAULT_TOLERANCE
}

/// `solver.mass_scaling`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MassScalingKind {
    /// Mass added to the lumped nodal masses.
    #[default]
    Conventional,
    /// Inertia added to the elements' deformation modes only.
    Selective,
}

/// `[[boundary]]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Boundary {
    /// Symmetry plane with normal `axis` (`"x"`, `"y"`, `"z"`) through a node set.
    Symmetry {
        /// Node set.
        set: String,
        /// Normal of the plane.
        axis: String,
    },
    /// Fixed DOFs (`ux uy uz rx ry rz`).
    Fixed {
        /// Node set.
        set: String,
        /// DOF names.
        dofs: Vec<String>,
    },
    /// Prescribed velocity or displacement of one DOF.
    Prescribed {
        /// Node set.
        set: String,
        /// DOF name.
        dof: String,
        /// `"velocity"` or `"displacement"`.
        motion: String,
        /// Magnitude (mm/s or mm; rad/s or rad).
        value: f64,
        /// Time function over the run; default `"constant"`.
        #[serde(default)]
        amplitude: Option<AmplitudeSpec>,
    },
}

/// `[[loads]]`: a force on every node of a set.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Load {
    /// Node set.
    pub set: String,
    /// DOF name (`ux` … `rz`).
    pub dof: String,
    /// Total force (N) or moment (N·mm) over the set, shared equally by its nodes.
    pub total: f64,
    /// Time function over the run (absolute time); default `"constant"`.
    #[serde(default)]
    pub amplitude: Option<AmplitudeSpec>,
}

/// `[[springs]]`: springs along one axis from every node of a set to an
/// anchor dragged at a speed (a mass on a spring pulled over a plane).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AnchorSpring {
    /// Node set.
    pub set: String,
    /// Axis: `ux`, `uy` or `uz`.
    pub dof: String,
    /// Total stiffness (N/mm), shared equally by the set's nodes.
    pub stiffness: f64,
    /// Anchor speed (mm/s) along the axis.
    pub speed: f64,
    /// Scale of the speed over the run (absolute time); default `"constant"`.
    #[serde(default)]
    pub amplitude: Option<AmplitudeSpec>,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// VTK frames over the run (0: none); default 20.
    #[serde(default = "default_frames")]
    pub frames: usize,
    /// Rows of `energy.csv` and `punch_force.csv` over the run; default 400.
    #[serde(default = "default_history")]
    pub history_points: usize,
    /// The tool whose travel is the stroke and whose force is the punch force.
    #[serde(default)]
    pub stroke_tool: Option<String>,
    /// Strokes (mm) at which the state is reported in `summary.json`.
    #[serde(default)]
    pub report_strokes: Vec<f64>,
    /// Multiplier from the model to the full part (4 for a quarter model).
    #[serde(default = "one")]
    pub symmetry_factor: f64,
    /// `[[output.sections]]`: lines in the initial blank.
    #[serde(default)]
    pub sections: Vec<SectionLine>,
    /// `[[output.draw_in]]`: edge points whose inward travel is reported.
    #[serde(default)]
    pub draw_in: Vec<DrawIn>,
    /// `[[output.profiles]]`: channel cross-sections whose shape measures
    /// (θ1, θ2, ρ) are reported formed and after springback.
    #[serde(default)]
    pub profiles: Vec<ProfileLine>,
    /// PNG plots; default true.
    #[serde(default = "yes")]
    pub plots: bool,
    /// Kinetic/internal is tracked once the stroke exceeds this (mm); default 1.
    #[serde(default = "one")]
    pub forming_starts_at: f64,
    /// Initial distance from a section's start at which its minor strain is
    /// reported as `minor_at_punch_edge` (mm; square cup: 27, where the punch
    /// profile radius starts).
    #[serde(default)]
    pub punch_edge_distance: Option<f64>,
    /// `[output.KEY]`: the tables of the reference checks, by `KEY`, each
    /// resolved against the keys its check declares
    /// ([`super::check_table`]); read from the scene's TOML apart from the
    /// keys above, and written out with them.
    #[serde(flatten, skip_deserializing)]
    pub checks: BTreeMap<String, super::check_table::CheckTable>,
}

impl Output {
    /// `[output]`'s own keys, the fields above: any other key of `[output]`
    /// is a reference check's table.
    pub const OWN_KEYS: [&'static str; 11] = [
        "frames",
        "history_points",
        "stroke_tool",
        "report_strokes",
        "symmetry_factor",
        "sections",
        "draw_in",
        "profiles",
        "plots",
        "forming_starts_at",
        "punch_edge_distance",
    ];
}

impl Default for Output {
    fn default() -> Self {
        Self {
            frames: default_frames(),
            history_points: default_history(),
            stroke_tool: None,
            report_strokes: Vec::new(),
            symmetry_factor: 1.0,
            sections: Vec::new(),
            draw_in: Vec::new(),
            profiles: Vec::new(),
            plots: true,
            forming_starts_at: 1.0,
            punch_edge_distance: None,
            checks: BTreeMap::new(),
        }
    }
}

fn default_frames() -> usize {
    20
}
fn default_history() -> usize {
    400
}
fn one() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}

/// `[[output.sections]]`: elements whose initial centroid lies within half an
/// element of the segment `from → to` (x, y in mm), ordered by distance from `from`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SectionLine {
    /// Name (`OD`, `OX`, …): the CSV is `sections/NAME.csv`.
    pub name: String,
    /// Start `[x, y]` (mm).
    pub from: [f64; 2],
    /// End `[x, y]` (mm).
    pub to: [f64; 2],
}

/// `[[output.profiles]]`: the nodes of the initial blank along the segment
/// `from → to` (x, y in mm), read as a channel's cross-section in the
/// vertical plane of the segment (`run::profile` in the code; the shape
/// measures in docs/springback.md).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileLine {
    /// Name: the CSV is `profiles/NAME.csv`.
    pub name: String,
    /// Start `[x, y]` (mm).
    pub from: [f64; 2],
    /// End `[x, y]` (mm).
    pub to: [f64; 2],
    /// Formed points up to this horizontal distance from `from` are the web (mm).
    pub web_to: f64,
    /// Formed points from this horizontal distance on are the flange (mm).
    pub flange_from: f64,
    /// Wall points lie more than this below the flange and above the web (mm):
    /// the shoulders' bends stay out of the fits.
    pub shoulder_clear: f64,
}

/// `[[output.draw_in]]`: the node nearest `at` (initial x, y); its draw-in is
/// its displacement along the unit `inward` direction (mm).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DrawIn {
    /// Name (`DX`, `DY`, `DD`).
    pub name: String,
    /// Initial position `[x, y]` (mm).
    pub at: [f64; 2],
    /// Inward direction `[x, y]` (normalised by formsim).
    pub inward: [f64; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`Output::OWN_KEYS`] are the keys serde reads into [`Output`]: the
    /// list its unknown-key error gives.
    #[test]
    fn own_keys_are_the_fields_of_output() {
        let e = toml::from_str::<Output>("nosuch = 1")
            .unwrap_err()
            .to_string();
        let listed = e
            .split_once("expected one of")
            .map(|(_, list)| list)
            .unwrap_or_else(|| panic!("{e}"));
        let fields: Vec<&str> = listed.split('`').skip(1).step_by(2).collect();
        assert_eq!(fields, Output::OWN_KEYS, "{e}");
    }
}
