//! Building the model of a checked scene: mesh, shells, tools, press, contact
//! pairs, boundary conditions and loads, assembled on one [`Solver`]. Only
//! what the scene asks for is built (docs/architecture.md §5: a scene pays for its effects).

use super::LoadedScene;
use super::SceneError;
use super::schema::{AmplitudeSpec, Boundary, HardeningSpec, MassScalingKind, Motion, Scene};
use super::validate::{axis_index, dof_from_name};
use crate::components::{LawSource, point_integrator};
use contact::{BlankGeometry, ContactEffect, ContactPair, FRICTIONLESS, PairSpec, PenaltySettings};
use fem_core::{
    Amplitude, BoundaryCondition, Dofs, EffectId, Mesh, MotionKind, NodalLoad, Press, PressStep,
    ReleaseMethod, Solver, SolverSettings, StepEnd, ToolMotion, Vec3,
};
use plugins_api::{Params, TangentMode, ToolSurface};
pub use shell_elements::ShellView;
use shell_elements::kinds::{self, MaterialRequest, ShellRequest};
use shell_elements::{Hardening, Section};

/// The shell effect that holds the blank, with its element and material.
pub type ShellHandle = shell_elements::kinds::Shells;

/// The tool whose travel is the stroke.
#[derive(Debug, Clone, Copy)]
pub struct StrokeTool {
    /// Tool index.
    pub index: usize,
    /// Unit direction of its travel.
    pub direction: Vec3,
}

/// The built model.
pub struct Model {
    /// The solver with every effect added (not yet initialised).
    pub solver: Solver,
    /// The blank's shells.
    pub shells: ShellHandle,
    /// The contact effect, when the scene has tools.
    pub contact: Option<EffectId>,
    /// Tool names, in tool-index order.
    pub tool_names: Vec<String>,
    /// The initial mesh.
    pub mesh: Mesh,
    /// Initial thickness (mm).
    pub thickness0: f64,
    /// Start of the run (s): 0, or the time of the initial state.
    pub start_time: f64,
    /// End of the run (s).
    pub end_time: f64,
    /// Stroke tool, if the scene names one.
    pub stroke: Option<StrokeTool>,
    /// Law and formulation of the first pair (for reports).
    pub law: String,
    /// See `law`.
    pub formulation: String,
    /// The file's node and element numbers, when the blank mesh was read
    /// from a file (messages name nodes and elements by them).
    pub file_ids: Option<super::blank_mesh::FileIds>,
    /// The state the blank starts from (`blank.initial_state`).
    pub initial_state: Option<InitialState>,
    /// `solver.land_on_step_ends`.
    pub land_on_step_ends: bool,
    /// The forming limit curve and zones of `[formability]`, if any.
    pub formability: Option<crate::formability::Formability>,
}

/// A state file the run starts from, read and checked against the model.
#[derive(Debug, Clone)]
pub struct InitialState {
    /// Its path (resolved against the scene's directory).
    pub path: std::path::PathBuf,
    /// Its checksum ([`crate::state_file::checksum`]).
    pub checksum: String,
    /// Its content.
    pub file: crate::state_file::StateFile,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("elements", &self.mesh.quads.len())
            .field("tools", &self.tool_names)
            .field("end_time", &self.end_time)
            .field(
                "initial_state",
                &self
                    .initial_state
                    .as_ref()
                    .map(|s| s.path.display().to_string()),
            )
            .finish()
    }
}

impl Model {
    /// Set the solver up: from the initial state when the scene gives one
    /// ([`fem_core::Solver::resume`]; the notes say what of the state is
    /// dropped), else afresh ([`fem_core::Solver::initialize`], no notes).
    ///
    /// # Errors
    /// The solver's set-up failed, or refused the state.
    pub fn set_up(&mut self) -> Result<(fem_core::SetupReport, Vec<String>), fem_core::FemError> {
        match &self.initial_state {
            Some(s) => self.solver.resume(&s.file.resume),
            None => Ok((self.solver.initialize()?, Vec::new())),
        }
    }

    /// The blank's shells.
    pub fn shells(&self) -> &dyn ShellView {
        self.shells
            .view(&self.solver)
            .expect("the model's shells are in its solver")
    }

    /// The contact effect.
    pub fn contact(&self) -> Option<&ContactEffect> {
        self.contact.and_then(|id| self.solver.effect(id))
    }

    /// The press that moves the tools (the solver's press stage).
    pub fn press(&self) -> Option<&Press> {
        self.solver.press()
    }
}

/// The blank's material and shells, added to `solver`: the material model
/// and the element resolved through the registry
/// (`shell_elements::kinds`; `formsim components` lists them).
fn add_shells(
    loaded: &LoadedScene,
    solver: &mut Solver,
    mesh: &Mesh,
) -> Result<ShellHandle, SceneError> {
    let s: &Scene = &loaded.scene;
    let m = &s.blank.material;
    let hardening = m
        .hardening
        .as_ref()
        .map(hardening_curve)
        .transpose()
        .map_err(|e| loaded.key_error("blank.material.hardening", e.to_string()))?;
    let plugin_path = m.plugin.as_ref().map(|p| loaded.base_dir().join(p));
    let plugin_params = plugins_api::Params(m.parameters.clone());
    let section = Section::new(s.blank.thickness)
        .and_then(|sec| sec.with_rule(shell_elements::RuleKind::Gauss, s.blank.integration_points))
        .and_then(|sec| sec.with_hourglass(s.blank.hourglass))
        .map_err(|e| loaded.key_error("blank", e.to_string()))?;
    let model = super::schema::material_model(s);
    let kind = kinds::material(&model).expect("validated: a registered material model");
    let rolling_angle = match m.r_values {
        Some(_) => Some(
            super::material::rolling_angle(mesh)
                .map_err(|e| loaded.key_error("blank.material.r_values", e.to_string()))?,
        ),
        None => None,
    };
    let own = if kind.name == "plugin" {
        Vec::new()
    } else {
        plugins_api::Params(m.parameters.clone())
            .resolve(kind.name, kind.params)
            .map_err(|e| loaded.key_error("blank.material.parameters", e.to_string()))?
    };
    let b = &s.blank;
    let element = kinds::element(&b.element).expect("validated: a registered element");
    let element_params = plugins_api::Params(b.element_parameters.clone())
        .resolve(element.name, element.params)
        .map_err(|e| loaded.key_error("blank.element_parameters", e.to_string()))?;
    let request = MaterialRequest {
        model: &model,
        young: m.youngs_modulus,
        poisson: m.poissons_ratio,
        density: m.density,
        hardening,
        r_values: m.r_values,
        rolling_angle,
        params: &own,
        plugin: plugin_path.as_deref().map(|path| kinds::PluginSource {
            path,
            params: &plugin_params,
        }),
        shells: ShellRequest {
            name: "blank",
            element: &b.element,
            element_params: &element_params,
            nodes: &mesh.nodes,
            quads: &mesh.quads,
            section,
            warping_correction: b.warping_correction,
            drilling: b.drilling,
        },
    };
    kinds::add_blank(&request, solver).map_err(|e| {
        // The element and the model were checked against the registries;
        // what is left is the mesh's elements or the material's values.
        let key = match e {
            shell_elements::ShellError::BadElement { .. } => "blank",
            _ => "blank.material",
        };
        loaded.key_error(key, e.to_string())
    })
}

/// The hardening curve of `[blank.material.hardening]`.
fn hardening_curve(spec: &HardeningSpec) -> Result<Hardening, shell_elements::ShellError> {
    match spec {
        HardeningSpec::Swift { k, eps0, n } => Hardening::swift(*k, *eps0, *n),
        HardeningSpec::Table { eps_p, sigma_y } => Hardening::table(
            &eps_p
                .iter()
                .zip(sigma_y)
                .map(|(a, b)| (*a, *b))
                .collect::<Vec<_>>(),
        ),
        HardeningSpec::Perfect { sigma_y } => Hardening::swift(*sigma_y, 1.0, 0.0),
        HardeningSpec::Elastic => Hardening::swift(1e30, 1.0, 0.0),
    }
}

/// Build the model of `loaded`.
///
/// # Errors
/// Errors of the engine crates (mesh, material, tools, friction law, press),
/// each attached to the scene key it comes from.
pub fn build(loaded: &LoadedScene) -> Result<Model, SceneError> {
    let s: &Scene = &loaded.scene;
    let (mesh, file_ids) = super::blank_mesh::build_mesh(loaded)?;
    let settings = SolverSettings {
        safety_factor: s.solver.safety_factor,
        mass_scaling_dt: s.solver.mass_scaling_dt,
        mass_scaling: match s.solver.mass_scaling {
            MassScalingKind::Conventional => fem_core::MassScaling::Conventional,
            MassScalingKind::Selective => fem_core::MassScaling::Selective {
                tolerance: s.solver.mass_scaling_tolerance,
            },
        },
        damping: s.solver.damping,
        dt_max: s.solver.dt_max,
        fixed_dt: s.solver.fixed_dt,
        ..SolverSettings::default()
    };
    let mut solver =
        Solver::new(&mesh, settings).map_err(|e| loaded.key_error("solver", e.to_string()))?;
    let shells = add_shells(loaded, &mut solver, &mesh)?;
    let (tool_names, tools) = build_tools(loaded)?;
    let press = press_programme(loaded, &tool_names, &tools, &pair_entries(s))?;
    let end_time = s
        .solver
        .end_time
        .or_else(|| press.as_ref().map(Press::nominal_duration))
        .expect("validated: end_time or steps");
    let (contact, law, formulation) = if tools.is_empty() {
        (None, s.contact.law.clone(), s.contact.formulation.clone())
    } else {
        if let Some(press) = press {
            solver
                .set_press(press)
                .map_err(|e| loaded.key_error("steps", e.to_string()))?;
        }
        let (id, law, formulation) = add_contact(loaded, &mut solver, &mesh, tools, &tool_names)?;
        (Some(id), law, formulation)
    };
    add_boundary_and_loads(loaded, &mut solver, &mesh)?;
    let stroke = stroke_tool(loaded, &tool_names)?;
    let formability = crate::formability::Formability::from_scene(loaded)?;
    let initial_state = initial_state(loaded, &mesh)?;
    // A stage goes on from the time its state was saved at.
    let start_time = initial_state.as_ref().map_or(0.0, |s| s.file.resume.time);
    let end_time = start_time + end_time;
    let mut mesh = mesh;
    if let Some(st) = &initial_state {
        // Draw-in and displacements count from where the first stage began.
        mesh.nodes.clone_from(&st.file.resume.nodes.x0);
    }
    Ok(Model {
        solver,
        shells,
        contact,
        tool_names,
        mesh,
        thickness0: s.blank.thickness,
        start_time,
        end_time,
        stroke,
        law,
        formulation,
        file_ids,
        formability,
        initial_state,
        land_on_step_ends: s.solver.land_on_step_ends,
    })
}

/// The state of `blank.initial_state`, read and checked against the
/// scene's element, material and mesh (`None` without the key).
fn initial_state(loaded: &LoadedScene, mesh: &Mesh) -> Result<Option<InitialState>, SceneError> {
    let Some(rel) = &loaded.scene.blank.initial_state else {
        return Ok(None);
    };
    let key = "blank.initial_state";
    let path = loaded.base_dir().join(rel);
    let (file, checksum) = crate::state_file::read(&path).map_err(|e| loaded.key_error(key, e))?;
    let material = super::schema::material_model(&loaded.scene);
    file.check_model(&crate::state_file::ModelKey {
        element: &loaded.scene.blank.element,
        material: &material,
        nodes: mesh.nodes.len(),
        quads: &mesh.quads,
    })
    .map_err(|e| loaded.key_error(key, format!("{}: {e}", path.display())))?;
    Ok(Some(InitialState {
        path,
        checksum,
        file,
    }))
}

/// The scene's tools, boxed for the contact effect.
type Tools = Vec<Box<dyn ToolSurface>>;

/// The tools, in the table's key order, with their names.
fn build_tools(loaded: &LoadedScene) -> Result<(Vec<String>, Tools), SceneError> {
    let s: &Scene = &loaded.scene;
    let base = loaded.base_dir();
    let mut tool_names = Vec::new();
    let mut tools: Tools = Vec::new();
    for (name, value) in &s.tools {
        let key = format!("tools.{name}");
        let table = value
            .as_table()
            .ok_or_else(|| loaded.key_error(&key, "must be a table [tools.NAME]"))?;
        let tool = tools_nurbs::spec::build_tool(name, table, base)
            .map_err(|e| loaded.key_error(&key, e.to_string()))?;
        tool_names.push(name.clone());
        tools.push(Box::new(tool));
    }
    Ok((tool_names, tools))
}

/// The index of the tool named `name`.
fn index_of(tool_names: &[String], name: &str) -> Option<usize> {
    tool_names.iter().position(|n| n == name)
}

/// The press programme (`[[steps]]`): `None` for a scene without steps.
fn press_programme(
    loaded: &LoadedScene,
    tool_names: &[String],
    tools: &[Box<dyn ToolSurface>],
    entries: &[super::schema::PairEntry],
) -> Result<Option<Press>, SceneError> {
    let s: &Scene = &loaded.scene;
    let mut press_steps = Vec::new();
    for step in &s.steps {
        let (end, duration) = step_end(step, tool_names);
        let mut motions = Vec::new();
        for motion in &step.motions {
            let tool = index_of(tool_names, motion.tool()).expect("validated");
            motions.push((tool, tool_motion(motion, duration)));
        }
        let active_pairs = step.pairs.as_ref().map(|tools_on| {
            entries
                .iter()
                .enumerate()
                .filter(|(_, e)| tools_on.contains(&e.tool))
                .map(|(k, _)| k)
                .collect()
        });
        press_steps.push(PressStep {
            name: step.name.clone(),
            end,
            motions,
            active_pairs,
        });
    }
    if press_steps.is_empty() {
        return Ok(None);
    }
    let poses: Vec<_> = tools.iter().map(|t| t.pose()).collect();
    Press::new(tool_names, &poses, press_steps)
        .map(Some)
        .map_err(|e| loaded.key_error("steps", e.to_string()))
}

/// How a press step ends, and its duration (the longest, for a travel).
fn step_end(step: &super::schema::Step, tool_names: &[String]) -> (StepEnd, f64) {
    use super::schema::StepKind;
    if step.kind == StepKind::Springback {
        let d = step.duration.expect("validated");
        return (
            StepEnd::Settled {
                tolerance: step.springback_tolerance(),
                max_duration: d,
                method: match step.springback_method() {
                    "implicit" => ReleaseMethod::Implicit,
                    _ => ReleaseMethod::DynamicRelaxation,
                },
            },
            d,
        );
    }
    match (step.duration, &step.until) {
        (Some(d), _) => (StepEnd::Duration(d), d),
        (None, Some(u)) => (
            StepEnd::Travel {
                tool: index_of(tool_names, &u.tool).expect("validated"),
                distance: u.distance,
                max_duration: u.max_duration,
            },
            u.max_duration,
        ),
        (None, None) => unreachable!("validated"),
    }
}

/// A tool's motion in a press step of `duration` (s).
fn tool_motion(motion: &Motion, duration: f64) -> ToolMotion {
    let amp = |a: &Option<AmplitudeSpec>| a.as_ref().map(|a| step_amplitude(a, duration));
    match motion {
        Motion::Hold { .. } => ToolMotion::Hold,
        Motion::Travel {
            direction,
            distance,
            amplitude,
            ..
        } => ToolMotion::Travel {
            direction: unit(direction),
            distance: *distance,
            amplitude: amp(amplitude),
        },
        Motion::Velocity {
            direction,
            speed,
            amplitude,
            ..
        } => ToolMotion::Velocity {
            direction: unit(direction),
            speed: *speed,
            amplitude: amp(amplitude),
        },
        Motion::Spin {
            axis,
            rate,
            amplitude,
            ..
        } => ToolMotion::Spin {
            axis: unit(axis),
            rate: *rate,
            amplitude: amp(amplitude),
        },
        Motion::Force {
            direction,
            amplitude,
            mass,
            damping,
            relative_damping,
            ..
        } => ToolMotion::Force {
            direction: unit(direction),
            force: motion.force_law().expect("validated: force or force_curve"),
            amplitude: amp(amplitude),
            mass: *mass,
            damping: *damping,
            relative_damping: *relative_damping,
        },
    }
}

/// The contact effect: one pair per entry of `[contact]` and the tools (the
/// solver's press moves them); also the first pair's law and formulation
/// (for reports).
fn add_contact(
    loaded: &LoadedScene,
    solver: &mut Solver,
    mesh: &Mesh,
    tools: Vec<Box<dyn ToolSurface>>,
    tool_names: &[String],
) -> Result<(EffectId, String, String), SceneError> {
    let s: &Scene = &loaded.scene;
    let n_nodes = mesh.nodes.len();
    let geometry = BlankGeometry::new(n_nodes, &mesh.quads)
        .map_err(|e| loaded.key_error("blank.mesh", e.to_string()))?;
    let m = &s.blank.material;
    let bulk = m.youngs_modulus / (3.0 * (1.0 - 2.0 * m.poissons_ratio));
    let mut pairs = Vec::new();
    let mut names = (s.contact.law.clone(), s.contact.formulation.clone());
    for (k, entry) in pair_entries(s).iter().enumerate() {
        let (pair, law, formulation) =
            contact_pair(loaded, k, entry, tool_names, &geometry, mesh, bulk)?;
        if k == 0 {
            names = (law, formulation);
        }
        pairs.push(pair);
    }
    let mut effect = ContactEffect::new(tools, pairs, geometry, vec![s.blank.thickness; n_nodes])
        .map_err(|e| loaded.key_error("contact", e.to_string()))?;
    if !s.drawbeads.is_empty() {
        effect = effect
            .with_drawbeads(super::drawbeads::specs(loaded, tool_names))
            .map_err(|e| loaded.key_error("drawbeads", e.to_string()))?;
    }
    Ok((solver.add_effect(effect), names.0, names.1))
}

/// Pair `k` of `[contact]`, with the law and formulation it reports.
fn contact_pair(
    loaded: &LoadedScene,
    k: usize,
    entry: &super::schema::PairEntry,
    tool_names: &[String],
    geometry: &BlankGeometry,
    mesh: &Mesh,
    bulk: f64,
) -> Result<(ContactPair, String, String), SceneError> {
    let s: &Scene = &loaded.scene;
    let key = if s.contact.pairs.is_empty() {
        "contact".to_string()
    } else {
        format!("contact.pairs[{k}]")
    };
    let law = entry.law.clone().unwrap_or_else(|| s.contact.law.clone());
    let formulation = entry
        .formulation
        .clone()
        .unwrap_or_else(|| s.contact.formulation.clone());
    let (source, params_key) = match &s.contact.plugin {
        Some(p) if entry.law.is_none() => (
            LawSource::Plugin(loaded.base_dir().join(p)),
            "plugin".to_string(),
        ),
        _ => (LawSource::Named(law.clone()), law.clone()),
    };
    let frictionless = matches!(&source, LawSource::Named(n) if n == FRICTIONLESS);
    let law_name = match &source {
        LawSource::Named(n) => n.clone(),
        LawSource::Plugin(p) => p.display().to_string(),
    };
    let formulation_name = if frictionless {
        "none".to_string()
    } else {
        formulation.clone()
    };
    let mut params = Params::new();
    if let Some(table) = s.contact.params.get(&params_key) {
        for (name, v) in table {
            params.set(name, *v);
        }
    }
    let tool = index_of(tool_names, &entry.tool).expect("validated");
    let spec = pair_spec(s, entry, tool, bulk);
    let pair = if frictionless {
        if let Some((name, _)) = params.0.iter().next() {
            return Err(loaded.key_error(
                &format!("contact.params.{FRICTIONLESS}.{name}"),
                "a frictionless pair takes no parameters",
            ));
        }
        ContactPair::frictionless(&spec, geometry, &mesh.nodes)
    } else {
        let mut formulation_params = Params::new();
        if let Some(table) = s.contact.params.get(&formulation) {
            for (name, v) in table {
                formulation_params.set(name, *v);
            }
        }
        let integrator = point_integrator(
            &source,
            &params,
            &formulation,
            &formulation_params,
            TangentMode::None,
        )
        .map_err(|e| {
            let message = e.to_string();
            // A parameter error of the formulation names it as `NAME`.
            let formulation_param =
                !formulation_params.0.is_empty() && message.contains(&format!("`{formulation}`"));
            let at = if formulation_param {
                format!("contact.params.{formulation}")
            } else {
                law_error_key(s, entry, &key, &params_key, &message)
            };
            loaded.key_error(&at, message)
        })?;
        ContactPair::new(&spec, integrator, geometry, &mesh.nodes)
    };
    let pair = pair.map_err(|e| loaded.key_error(&key, e.to_string()))?;
    Ok((pair, law_name, formulation_name))
}

/// The scene key a friction law's error belongs to: the law (or plugin),
/// the formulation, or the law's parameters.
fn law_error_key(
    s: &Scene,
    entry: &super::schema::PairEntry,
    key: &str,
    params_key: &str,
    message: &str,
) -> String {
    if message.contains("unknown law") || message.contains("plugin") {
        if entry.law.is_some() {
            format!("{key}.law")
        } else if s.contact.plugin.is_some() {
            "contact.plugin".to_string()
        } else {
            "contact.law".to_string()
        }
    } else if message.contains("formulation") {
        if entry.formulation.is_some() {
            format!("{key}.formulation")
        } else {
            "contact.formulation".to_string()
        }
    } else {
        format!("contact.params.{params_key}")
    }
}

/// Boundary conditions, nodal loads and anchor springs.
fn add_boundary_and_loads(
    loaded: &LoadedScene,
    solver: &mut Solver,
    mesh: &Mesh,
) -> Result<(), SceneError> {
    let s: &Scene = &loaded.scene;
    for (i, bc) in s.boundary.iter().enumerate() {
        let key = format!("boundary[{i}]");
        let condition = match bc {
            Boundary::Symmetry { set, axis } => BoundaryCondition::Symmetry {
                set: set.clone(),
                axis: axis_index(axis).expect("validated"),
            },
            Boundary::Fixed { set, dofs } => BoundaryCondition::Fixed {
                set: set.clone(),
                dofs: Dofs::of(
                    &dofs
                        .iter()
                        .map(|d| dof_from_name(d).expect("validated"))
                        .collect::<Vec<_>>(),
                ),
            },
            Boundary::Prescribed {
                set,
                dof,
                motion,
                value,
                amplitude,
            } => BoundaryCondition::Prescribed {
                set: set.clone(),
                dof: dof_from_name(dof).expect("validated"),
                kind: if motion == "velocity" {
                    MotionKind::Velocity
                } else {
                    MotionKind::Displacement
                },
                value: *value,
                amplitude: amplitude
                    .as_ref()
                    .map_or(Amplitude::Constant, |a| step_amplitude(a, 1.0)),
            },
        };
        solver
            .add_boundary_condition(&condition)
            .map_err(|e| loaded.key_error(&key, e.to_string()))?;
    }
    for (i, load) in s.loads.iter().enumerate() {
        let key = format!("loads[{i}]");
        let count = mesh
            .node_set(&load.set)
            .map_err(|e| loaded.key_error(&format!("{key}.set"), e.to_string()))?
            .len();
        solver
            .add_load(&NodalLoad {
                set: load.set.clone(),
                dof: dof_from_name(&load.dof).expect("validated"),
                value: load.total / count.max(1) as f64,
                amplitude: load
                    .amplitude
                    .as_ref()
                    .map_or(Amplitude::Constant, |a| step_amplitude(a, 1.0)),
            })
            .map_err(|e| loaded.key_error(&key, e.to_string()))?;
    }
    for (i, sp) in s.springs.iter().enumerate() {
        let key = format!("springs[{i}]");
        let nodes = mesh
            .node_set(&sp.set)
            .map_err(|e| loaded.key_error(&format!("{key}.set"), e.to_string()))?;
        let axis = dof_from_name(&sp.dof).expect("validated") as usize;
        let springs = fem_core::AnchorSprings::new(
            &key,
            &mesh.nodes,
            nodes,
            axis,
            sp.stiffness,
            sp.speed,
            sp.amplitude.as_ref().map(|a| step_amplitude(a, 1.0)),
        )
        .map_err(|e| loaded.key_error(&key, e.to_string()))?;
        solver.add_effect(springs);
    }
    Ok(())
}

/// The stroke tool (`output.stroke_tool`): its first travel or velocity direction.
fn stroke_tool(
    loaded: &LoadedScene,
    tool_names: &[String],
) -> Result<Option<StrokeTool>, SceneError> {
    let s: &Scene = &loaded.scene;
    Ok(match &s.output.stroke_tool {
        None => None,
        Some(name) => {
            let index = index_of(tool_names, name).expect("validated");
            let direction = s
                .steps
                .iter()
                .flat_map(|st| &st.motions)
                .find_map(|m| match m {
                    Motion::Travel {
                        tool, direction, ..
                    }
                    | Motion::Velocity {
                        tool, direction, ..
                    } if tool == name => Some(unit(direction)),
                    _ => None,
                })
                .ok_or_else(|| {
                    loaded.key_error(
                        "output.stroke_tool",
                        format!("\"{name}\" never travels in [[steps]]: no stroke direction"),
                    )
                })?;
            Some(StrokeTool { index, direction })
        }
    })
}

/// A pair's settings: its name (or `TOOL-blank`), tool, penalty and search margin.
fn pair_spec(s: &Scene, entry: &super::schema::PairEntry, tool: usize, bulk: f64) -> PairSpec {
    let name = entry
        .name
        .clone()
        .unwrap_or_else(|| format!("{}-blank", entry.tool));
    let mut spec = PairSpec::new(&name, tool, bulk);
    spec.penalty = PenaltySettings {
        scale: entry.penalty_scale.unwrap_or(s.contact.penalty_scale),
        damping: s.contact.damping,
    };
    spec.search_margin = s.contact.search_margin;
    spec
}

/// The contact pairs: as listed, or one per tool.
fn pair_entries(s: &Scene) -> Vec<super::schema::PairEntry> {
    if s.contact.pairs.is_empty() {
        s.tools
            .keys()
            .map(|t| super::schema::PairEntry {
                tool: t.clone(),
                name: None,
                law: None,
                formulation: None,
                penalty_scale: None,
            })
            .collect()
    } else {
        s.contact.pairs.clone()
    }
}

fn unit(d: &[f64; 3]) -> Vec3 {
    Vec3::new(d[0], d[1], d[2]).normalize()
}

/// A step amplitude (`duration`: the step's length, for the named shapes).
fn step_amplitude(a: &AmplitudeSpec, duration: f64) -> Amplitude {
    match a {
        AmplitudeSpec::Named(n) => match n.as_str() {
            "smooth-step" => Amplitude::SmoothStep {
                t0: 0.0,
                t1: duration,
            },
            "linear" => Amplitude::Linear {
                t0: 0.0,
                t1: duration,
            },
            "slow-start" => Amplitude::SlowStart {
                t0: 0.0,
                t1: duration,
            },
            _ => Amplitude::Constant,
        },
        AmplitudeSpec::Ramp { shape, t0, t1 } => {
            if shape == "linear" {
                Amplitude::Linear { t0: *t0, t1: *t1 }
            } else if shape == "slow-start" {
                Amplitude::SlowStart { t0: *t0, t1: *t1 }
            } else {
                Amplitude::SmoothStep { t0: *t0, t1: *t1 }
            }
        }
        AmplitudeSpec::Table(rows) => Amplitude::Table(rows.iter().map(|r| (r[0], r[1])).collect()),
    }
}
