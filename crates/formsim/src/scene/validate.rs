//! Range and name checks of a typed scene: every error names the key, the
//! value, the unit and the accepted range. What the engine crates check again
//! when the model is built (tool geometry, friction parameters) is left to
//! them; their errors are mapped to the key in [`super::build()`].

use super::LoadedScene;
use super::SceneError;
use super::estimate::{self, MeshSize};
use super::schema::{
    AmplitudeSpec, Boundary, HardeningSpec, MassScalingKind, MeshSpec, Motion, Step,
};

/// Largest blank thickness accepted (mm).
pub const THICKNESS_MAX: f64 = 1e3;
/// Largest side of a generated blank accepted (mm).
pub const SIZE_MAX: f64 = 1e5;
/// Largest Young's modulus accepted (MPa).
pub const YOUNGS_MODULUS_MAX: f64 = 1e7;
/// Largest density accepted (tonne/mm³).
pub const DENSITY_MAX: f64 = 1e-3;

/// Check `loaded.scene`.
///
/// # Errors
/// The first key out of range, with its line.
pub fn validate(loaded: &LoadedScene) -> Result<(), SceneError> {
    header(loaded)?;
    blank(loaded)?;
    material(loaded)?;
    tools_and_contact(loaded)?;
    super::drawbeads::validate(loaded)?;
    press(loaded)?;
    solver(loaded)?;
    boundary_and_loads(loaded)?;
    outputs(loaded)?;
    crate::formability::Formability::from_scene(loaded)?;
    guards(loaded)
}

/// A value as a message shows it: plain between 1e-4 and 1e6, else in
/// exponent form (`1e300`, not three hundred digits).
pub(super) fn number(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) || !v.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// The error of one key, and the two range checks every section uses.
struct Keys<'a>(&'a LoadedScene);

impl Keys<'_> {
    fn err<T>(&self, key: &str, message: String) -> Result<T, SceneError> {
        Err(self.0.key_error(key, message))
    }

    fn positive(&self, key: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            self.err(key, format!("{} {unit}: must be finite and > 0", number(v)))
        }
    }

    /// `v` in `(0, max]`: a bound well beyond any sheet, tool or metal, so
    /// that a slip of a key (`1e300`) is named here instead of as the
    /// infinite mass or step it would make downstream.
    fn physical(
        &self,
        key: &str,
        v: f64,
        unit: &str,
        max: f64,
        why: &str,
    ) -> Result<(), SceneError> {
        self.positive(key, v, unit)?;
        if v <= max {
            Ok(())
        } else {
            self.err(
                key,
                format!(
                    "{} {unit}: must be at most {max:e} {unit} ({why})",
                    number(v)
                ),
            )
        }
    }

    fn non_negative(&self, key: &str, v: f64, unit: &str) -> Result<(), SceneError> {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            self.err(key, format!("{v} {unit}: must be finite and >= 0"))
        }
    }
}

/// The scene's name (the output folder), its kind and its units.
fn header(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // A preset or a registered reference check.
    if let Err(message) = super::kind::resolve(&s.scene.kind) {
        return keys.err("scene.kind", message);
    }
    // The name is the default output folder `results/NAME`, which a run
    // replaces: one plain path component only.
    if !is_plain_name(&s.scene.name) {
        return keys.err(
            "scene.name",
            format!(
                "\"{}\": must be letters, digits, `-`, `_` or `.` (not only dots): it names the output folder results/NAME",
                s.scene.name
            ),
        );
    }

    // Units: formsim computes in one consistent system and says so in every scene.
    let u = &s.scene.units;
    for (key, given, want) in [
        ("scene.units.length", &u.length, "mm"),
        ("scene.units.force", &u.force, "N"),
        ("scene.units.stress", &u.stress, "MPa"),
        ("scene.units.mass", &u.mass, "tonne"),
        ("scene.units.time", &u.time, "s"),
    ] {
        if given != want {
            return keys.err(
                key,
                format!("\"{given}\": formsim works in mm, N, MPa, tonne, s; write \"{want}\""),
            );
        }
    }
    Ok(())
}

/// `[blank]`: element, section and mesh.
fn blank(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // Blank.
    let b = &s.blank;
    shell_elements::kinds::ensure_linked();
    let Some(element) = shell_elements::kinds::element(&b.element) else {
        return keys.err(
            "blank.element",
            format!(
                "\"{}\" is not a registered element (registered: {})",
                b.element,
                shell_elements::kinds::names(
                    shell_elements::kinds::elements().iter().map(|k| k.name)
                )
            ),
        );
    };
    // The element's own keys, against its declared specs.
    if let Err(e) =
        plugins_api::Params(b.element_parameters.clone()).resolve(element.name, element.params)
    {
        return keys.err("blank.element_parameters", e.to_string());
    }
    keys.physical(
        "blank.thickness",
        b.thickness,
        "mm",
        THICKNESS_MAX,
        "a shell thicker than a metre is no sheet",
    )?;
    if !(1..=9).contains(&b.integration_points) {
        return keys.err(
            "blank.integration_points",
            format!("{}: must be in [1, 9]", b.integration_points),
        );
    }
    keys.non_negative("blank.hourglass", b.hourglass, "-")?;
    let max_drill = shell_elements::formulation::MAX_DRILLING;
    if !(b.drilling.is_finite() && (0.0..=max_drill).contains(&b.drilling)) {
        return keys.err(
            "blank.drilling",
            format!("{}: must be in [0, {max_drill}]", b.drilling),
        );
    }
    match &b.mesh {
        MeshSpec::Rectangle {
            size,
            divisions,
            origin,
        } => {
            for side in size {
                keys.physical(
                    "blank.mesh.size",
                    *side,
                    "mm",
                    SIZE_MAX,
                    "a blank larger than 100 m",
                )?;
            }
            let (nx, ny) = divisions.pair();
            for n in [nx, ny] {
                if !(1..=4096).contains(&n) {
                    return keys.err("blank.mesh.divisions", format!("{n}: must be in [1, 4096]"));
                }
            }
            if origin.iter().any(|v| !v.is_finite()) {
                return keys.err(
                    "blank.mesh.origin",
                    format!("{origin:?} mm: must be finite"),
                );
            }
        }
        MeshSpec::File { path, translate } => {
            let full = loaded.base_dir().join(path);
            use plugins_api::input_file::{InputFileError, MESH_LIMIT, check};
            match check(&full, MESH_LIMIT) {
                Ok(()) => {}
                Err(InputFileError::NotFound) => {
                    return keys.err(
                        "blank.mesh.path",
                        format!("\"{path}\": no such file ({})", full.display()),
                    );
                }
                Err(e) => {
                    return keys.err(
                        "blank.mesh.path",
                        format!("\"{path}\" ({}): {e}", full.display()),
                    );
                }
            }
            if translate.iter().any(|v| !v.is_finite()) {
                return keys.err(
                    "blank.mesh.translate",
                    format!("{translate:?} mm: must be finite"),
                );
            }
        }
        MeshSpec::WrappedStrip {
            radius,
            width,
            tail,
            angle_deg,
            element_size,
        } => {
            keys.positive("blank.mesh.radius", *radius, "mm")?;
            keys.positive("blank.mesh.width", *width, "mm")?;
            keys.positive("blank.mesh.tail", *tail, "mm")?;
            keys.positive("blank.mesh.element_size", *element_size, "mm")?;
            if !(*angle_deg > 0.0 && *angle_deg <= 180.0) {
                return keys.err(
                    "blank.mesh.angle_deg",
                    format!("{angle_deg} deg: must be in (0, 180]"),
                );
            }
        }
    }
    Ok(())
}

/// `[blank.material]`: elasticity, hardening, model and r-values.
fn material(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    let b = &s.blank;
    let m = &b.material;
    keys.physical(
        "blank.material.youngs_modulus",
        m.youngs_modulus,
        "MPa",
        YOUNGS_MODULUS_MAX,
        "ten times diamond's; is the unit MPa?",
    )?;
    keys.physical(
        "blank.material.density",
        m.density,
        "tonne/mm^3",
        DENSITY_MAX,
        "1e5 times steel's; is the unit tonne/mm^3?",
    )?;
    if !(m.poissons_ratio > -1.0 && m.poissons_ratio < 0.5) {
        return keys.err(
            "blank.material.poissons_ratio",
            format!("{}: must be in (-1, 0.5)", m.poissons_ratio),
        );
    }
    let model = super::schema::material_model(s);
    let kind = shell_elements::kinds::material(&model);
    match kind {
        None => {
            return keys.err(
                "blank.material.model",
                format!(
                    "\"{model}\" is not a registered material (registered: {})",
                    shell_elements::kinds::names(
                        shell_elements::kinds::materials().iter().map(|k| k.name)
                    )
                ),
            );
        }
        Some(k) if k.anisotropic != m.r_values.is_some() => {
            let why = if k.anisotropic {
                "needs blank.material.r_values = [r0, r45, r90]"
            } else {
                "is isotropic: remove blank.material.r_values (or use model = \"hill48\")"
            };
            return keys.err("blank.material.model", format!("\"{model}\" {why}"));
        }
        Some(_) => {}
    }
    let plugin = model == "plugin";
    let reads_hardening = kind.is_some_and(|k| k.hardening);
    match &m.hardening {
        Some(_) if plugin => keys.err(
            "blank.material.hardening",
            "not read by a plugin material: its hardening is in blank.material.parameters".into(),
        )?,
        Some(_) if !reads_hardening => keys.err(
            "blank.material.hardening",
            format!("not read by the \"{model}\" model (its keys: blank.material.parameters)"),
        )?,
        None if reads_hardening => keys.err(
            "blank.material.hardening",
            format!("missing: the \"{model}\" model needs a hardening curve"),
        )?,
        Some(h) => hardening(&keys, h)?,
        None if plugin => material_plugin(loaded)?,
        None => {}
    }
    if !plugin && m.plugin.is_some() {
        keys.err(
            "blank.material.plugin",
            format!("only read with model = \"plugin\" (the model is \"{model}\")"),
        )?;
    }
    if let Some(k) = kind.filter(|_| !plugin) {
        // The model's own keys, against its declared specs.
        if let Err(e) = plugins_api::Params(m.parameters.clone()).resolve(k.name, k.params) {
            return keys.err("blank.material.parameters", e.to_string());
        }
    }
    if let Some(r) = &m.r_values {
        for ((i, v), name) in r.iter().enumerate().zip(["r0", "r45", "r90"]) {
            if !(v.is_finite() && *v > 0.0) {
                return keys.err(
                    &format!("blank.material.r_values[{i}]"),
                    format!("{name} = {v} (-): must be finite and > 0"),
                );
            }
        }
    }
    Ok(())
}

/// `[blank.material.hardening]` of a built-in model.
fn hardening(keys: &Keys<'_>, spec: &HardeningSpec) -> Result<(), SceneError> {
    match spec {
        HardeningSpec::Swift { k, eps0, n } => {
            keys.positive("blank.material.hardening.k", *k, "MPa")?;
            keys.positive("blank.material.hardening.eps0", *eps0, "-")?;
            keys.non_negative("blank.material.hardening.n", *n, "-")?;
        }
        HardeningSpec::Table { eps_p, sigma_y } => {
            if eps_p.len() != sigma_y.len() || eps_p.is_empty() {
                return keys.err(
                    "blank.material.hardening",
                    format!(
                        "{} eps_p values and {} sigma_y values: need the same non-zero count",
                        eps_p.len(),
                        sigma_y.len()
                    ),
                );
            }
        }
        HardeningSpec::Perfect { sigma_y } => {
            keys.positive("blank.material.hardening.sigma_y", *sigma_y, "MPa")?;
        }
        HardeningSpec::Elastic => {}
    }
    Ok(())
}

/// A plugin material: the library opens, its parameters resolve, and the
/// elastic constants it reports are the sheet's.
fn material_plugin(loaded: &LoadedScene) -> Result<(), SceneError> {
    let m = &loaded.scene.blank.material;
    let keys = Keys(loaded);
    let Some(path) = &m.plugin else {
        return keys.err(
            "blank.material.plugin",
            "missing: model = \"plugin\" needs plugin = \"path/to/library\" (relative to the scene)"
                .into(),
        );
    };
    let full = loaded.base_dir().join(path);
    let params = plugins_api::Params(m.parameters.clone());
    let source = shell_elements::kinds::PluginSource {
        path: &full,
        params: &params,
    };
    shell_elements::kinds::plugin_material(source, m.youngs_modulus, m.poissons_ratio, m.density)
        .map(drop)
        .or_else(|e| keys.err("blank.material.plugin", e.to_string()))
}
/// `[tools]` and `[contact]`.
fn tools_and_contact(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // Tools and contact.
    let c = &s.contact;
    keys.positive("contact.penalty_scale", c.penalty_scale, "-")?;
    if !(0.0..=1.0).contains(&c.damping) {
        return keys.err(
            "contact.damping",
            format!("{}: must be in [0, 1]", c.damping),
        );
    }
    keys.non_negative("contact.search_margin", c.search_margin, "mm")?;
    for (i, p) in c.pairs.iter().enumerate() {
        if !s.tools.contains_key(&p.tool) {
            return keys.err(
                &format!("contact.pairs[{i}].tool"),
                format!("\"{}\": no [tools.{}] in the scene", p.tool, p.tool),
            );
        }
        if let Some(k) = p.penalty_scale {
            keys.positive(&format!("contact.pairs[{i}].penalty_scale"), k, "-")?;
        }
    }
    for (law, table) in &c.params {
        for (name, v) in table {
            if !v.is_finite() {
                return keys.err(
                    &format!("contact.params.{law}.{name}"),
                    format!("{v}: must be finite"),
                );
            }
        }
    }
    Ok(())
}

/// The press programme (`[[steps]]`).
fn press(loaded: &LoadedScene) -> Result<(), SceneError> {
    let s = &loaded.scene;
    // Press programme.
    for (i, step) in s.steps.iter().enumerate() {
        step_end(loaded, i, step)?;
        step_kind(loaded, i, step)?;
        for (j, motion) in step.motions.iter().enumerate() {
            step_motion(loaded, &format!("steps[{i}].motions[{j}]"), motion)?;
        }
        step_pairs(loaded, i, step)?;
    }
    Ok(())
}

/// How step `i` ends: a duration or an `until` on a tool's travel, exactly one.
fn step_end(loaded: &LoadedScene, i: usize, step: &Step) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    let key = |k: &str| format!("steps[{i}].{k}");
    match (step.duration, &step.until) {
        (Some(d), None) => keys.positive(&key("duration"), d, "s")?,
        (None, Some(u)) => {
            if !s.tools.contains_key(&u.tool) {
                return keys.err(&key("until.tool"), format!("\"{}\": no such tool", u.tool));
            }
            keys.positive(&key("until.distance"), u.distance, "mm")?;
            keys.positive(&key("until.max_duration"), u.max_duration, "s")?;
        }
        _ => {
            return keys.err(
                &format!("steps[{i}]"),
                format!(
                    "step \"{}\": give exactly one of duration or until",
                    step.name
                ),
            );
        }
    }
    Ok(())
}

/// What a springback step may say: a known method, a tolerance in (0, 1), a
/// duration, no motion; a press step none of the springback keys.
fn step_kind(loaded: &LoadedScene, i: usize, step: &Step) -> Result<(), SceneError> {
    use super::schema::{SPRINGBACK_METHODS, StepKind};
    let keys = Keys(loaded);
    let key = |k: &str| format!("steps[{i}].{k}");
    if step.kind == StepKind::Press {
        for (k, given) in [
            ("method", step.method.is_some()),
            ("tolerance", step.tolerance.is_some()),
        ] {
            if given {
                return keys.err(&key(k), "only read by a kind = \"springback\" step".into());
            }
        }
        return Ok(());
    }
    if let Some(m) = &step.method
        && !SPRINGBACK_METHODS.contains(&m.as_str())
    {
        return keys.err(
            &key("method"),
            format!(
                "\"{m}\": not a springback method (known: {})",
                SPRINGBACK_METHODS.join(", ")
            ),
        );
    }
    if step.springback_method() == "implicit"
        && let Some(element) = shell_elements::kinds::element(&loaded.scene.blank.element)
        && !element.static_form
    {
        return keys.err(
            &key("method"),
            format!(
                "\"implicit\" needs shells with a static form, and the {} shell has none (\"dynamic-relaxation\" works with every element)",
                element.name
            ),
        );
    }
    if let Some(t) = step.tolerance
        && !(t.is_finite() && t > 0.0 && t < 1.0)
    {
        return keys.err(&key("tolerance"), format!("{t}: must be in (0, 1)"));
    }
    if step.until.is_some() {
        return keys.err(&key("until"), "a springback step ends when the blank is at rest: give duration, the longest it may take".into());
    }
    if i + 1 != loaded.scene.steps.len() {
        return keys.err(
            &key("kind"),
            "a springback step must be the programme's last (the DOFs it fixes stay fixed; forming in stages after it is not supported)".into(),
        );
    }
    if !step.motions.is_empty() || step.pairs.is_some() {
        return keys.err(
            &key(if step.pairs.is_some() {
                "pairs"
            } else {
                "motions"
            }),
            "a springback step moves no tool and ends every contact pair".into(),
        );
    }
    Ok(())
}

/// One motion of a step (`prefix` is its key, `steps[i].motions[j]`): its
/// tool exists, its numbers are in range and its direction or axis is not zero.
fn step_motion(loaded: &LoadedScene, prefix: &str, motion: &Motion) -> Result<(), SceneError> {
    let keys = Keys(loaded);
    let mkey = |k: &str| format!("{prefix}.{k}");
    if !loaded.scene.tools.contains_key(motion.tool()) {
        return keys.err(
            &mkey("tool"),
            format!("\"{}\": no such tool", motion.tool()),
        );
    }
    if let Some((key, d)) = motion_values(loaded, prefix, motion)? {
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(n.is_finite() && n > 1e-12) {
            return keys.err(&mkey(key), format!("{d:?}: must be a non-zero vector"));
        }
    }
    Ok(())
}

/// The numbers of one motion (`prefix` is its key); returns the vector the
/// motion is along or about, and its key (`None` for a hold).
fn motion_values<'m>(
    loaded: &LoadedScene,
    prefix: &str,
    motion: &'m Motion,
) -> Result<Option<(&'static str, &'m [f64; 3])>, SceneError> {
    // The kinematic motions: (its number's key, value, unit), amplitude,
    // and the vector it runs along or about.
    let (number, amplitude, along) = match motion {
        Motion::Hold { .. } => return Ok(None),
        Motion::Force { direction, .. } => {
            force_motion(loaded, prefix, motion)?;
            return Ok(Some(("direction", direction)));
        }
        Motion::Travel {
            direction,
            distance,
            amplitude,
            ..
        } => (
            ("distance", distance, "mm"),
            amplitude,
            ("direction", direction),
        ),
        Motion::Velocity {
            direction,
            speed,
            amplitude,
            ..
        } => (
            ("speed", speed, "mm/s"),
            amplitude,
            ("direction", direction),
        ),
        Motion::Spin {
            axis,
            rate,
            amplitude,
            ..
        } => (("rate", rate, "rad/s"), amplitude, ("axis", axis)),
    };
    let (key, value, unit) = number;
    if !value.is_finite() {
        let message = format!("{value} {unit}: must be finite");
        return Keys(loaded).err(&format!("{prefix}.{key}"), message);
    }
    check_amplitude(
        loaded,
        &format!("{prefix}.amplitude"),
        amplitude.as_ref(),
        true,
    )?;
    Ok(Some(along))
}

/// The numbers of a force-controlled motion (`prefix` is its key): a force
/// or a force curve, mass, damping, relative damping, amplitude (other
/// motions have none of these: nothing to check).
fn force_motion(loaded: &LoadedScene, prefix: &str, motion: &Motion) -> Result<(), SceneError> {
    let Motion::Force {
        force,
        force_curve,
        amplitude,
        mass,
        damping,
        relative_damping,
        ..
    } = motion
    else {
        return Ok(());
    };
    let keys = Keys(loaded);
    let mkey = |k: &str| format!("{prefix}.{k}");
    match (force, force_curve) {
        (Some(f), None) => keys.non_negative(&mkey("force"), *f, "N")?,
        (None, Some(rows)) => check_force_curve(loaded, &mkey("force_curve"), rows)?,
        _ => {
            return keys.err(
                &mkey("force"),
                "give either `force` (N) or `force_curve` ([compression mm, force N] rows), not both or neither".into(),
            );
        }
    }
    keys.positive(&mkey("mass"), *mass, "tonne")?;
    keys.non_negative(&mkey("damping"), *damping, "N*s/mm")?;
    if !(0.0..=1.0).contains(relative_damping) {
        return keys.err(
            &mkey("relative_damping"),
            format!("{relative_damping}: must be in [0, 1] (fraction of critical)"),
        );
    }
    check_amplitude(loaded, &mkey("amplitude"), amplitude.as_ref(), true)
}

/// The tools whose pairs step `i` activates (`pairs`) exist.
fn step_pairs(loaded: &LoadedScene, i: usize, step: &Step) -> Result<(), SceneError> {
    let keys = Keys(loaded);
    if let Some(pairs) = &step.pairs {
        for (j, t) in pairs.iter().enumerate() {
            if !loaded.scene.tools.contains_key(t) {
                return keys.err(
                    &format!("steps[{i}].pairs[{j}]"),
                    format!("\"{t}\": no such tool"),
                );
            }
        }
    }
    Ok(())
}

/// `[solver]`.
fn solver(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // Solver.
    let sv = &s.solver;
    if !(sv.safety_factor > 0.0 && sv.safety_factor <= 1.0) {
        return keys.err(
            "solver.safety_factor",
            format!("{}: must be in (0, 1]", sv.safety_factor),
        );
    }
    if let Some(t) = sv.mass_scaling_dt {
        keys.positive("solver.mass_scaling_dt", t, "s")?;
    }
    let tol = sv.mass_scaling_tolerance;
    if !(tol > 0.0 && tol <= 0.1) {
        return keys.err(
            "solver.mass_scaling_tolerance",
            format!("{tol}: must be in (0, 0.1] (-)"),
        );
    }
    if sv.mass_scaling == MassScalingKind::Selective && sv.mass_scaling_dt.is_none() {
        return keys.err(
            "solver.mass_scaling",
            "\"selective\" needs solver.mass_scaling_dt, the step to reach (s)".into(),
        );
    }
    keys.non_negative("solver.damping", sv.damping, "1/s")?;
    if let Some(t) = sv.end_time {
        keys.positive("solver.end_time", t, "s")?;
    }
    if let Some(t) = sv.dt_max {
        keys.positive("solver.dt_max", t, "s")?;
    }
    if let Some(t) = sv.fixed_dt {
        keys.positive("solver.fixed_dt", t, "s")?;
        if sv.mass_scaling_dt.is_some() || sv.dt_max.is_some() {
            return keys.err(
                "solver.fixed_dt",
                format!("{t}: excludes solver.mass_scaling_dt and solver.dt_max"),
            );
        }
    }
    if s.steps.is_empty() && sv.end_time.is_none() {
        return keys.err(
            "solver.end_time",
            "required when the scene has no [[steps]]".into(),
        );
    }
    Ok(())
}

/// `[[boundary]]` and `[[loads]]`.
fn boundary_and_loads(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // Boundary conditions and loads.
    for (i, bc) in s.boundary.iter().enumerate() {
        let key = |k: &str| format!("boundary[{i}].{k}");
        match bc {
            Boundary::Symmetry { axis, .. } => {
                if axis_index(axis).is_none() {
                    return keys.err(
                        &key("axis"),
                        format!("\"{axis}\": must be \"x\", \"y\" or \"z\""),
                    );
                }
            }
            Boundary::Fixed { dofs, .. } => {
                for (j, d) in dofs.iter().enumerate() {
                    if dof_from_name(d).is_none() {
                        return keys.err(&format!("boundary[{i}].dofs[{j}]"), bad_dof(d));
                    }
                }
            }
            Boundary::Prescribed {
                dof,
                motion,
                value,
                amplitude,
                ..
            } => {
                if dof_from_name(dof).is_none() {
                    return keys.err(&key("dof"), bad_dof(dof));
                }
                if motion != "velocity" && motion != "displacement" {
                    return keys.err(
                        &key("motion"),
                        format!("\"{motion}\": must be \"velocity\" or \"displacement\""),
                    );
                }
                if !value.is_finite() {
                    return keys.err(&key("value"), format!("{value}: must be finite"));
                }
                check_amplitude(loaded, &key("amplitude"), amplitude.as_ref(), false)?;
            }
        }
    }
    for (i, load) in s.loads.iter().enumerate() {
        if dof_from_name(&load.dof).is_none() {
            return keys.err(&format!("loads[{i}].dof"), bad_dof(&load.dof));
        }
        if !load.total.is_finite() {
            return keys.err(
                &format!("loads[{i}].total"),
                format!("{}: must be finite", load.total),
            );
        }
        check_amplitude(
            loaded,
            &format!("loads[{i}].amplitude"),
            load.amplitude.as_ref(),
            false,
        )?;
    }

    for (i, sp) in s.springs.iter().enumerate() {
        let key = |k: &str| format!("springs[{i}].{k}");
        if !matches!(sp.dof.as_str(), "ux" | "uy" | "uz") {
            return keys.err(&key("dof"), format!("\"{}\": must be ux, uy or uz", sp.dof));
        }
        keys.positive(&key("stiffness"), sp.stiffness, "N/mm")?;
        if !sp.speed.is_finite() {
            return keys.err(&key("speed"), format!("{} mm/s: must be finite", sp.speed));
        }
        check_amplitude(loaded, &key("amplitude"), sp.amplitude.as_ref(), false)?;
    }
    Ok(())
}

/// `[output]`.
fn outputs(loaded: &LoadedScene) -> Result<(), SceneError> {
    let (s, keys) = (&loaded.scene, Keys(loaded));
    // Outputs.
    let o = &s.output;
    if let Some(t) = &o.stroke_tool
        && !s.tools.contains_key(t)
    {
        return keys.err("output.stroke_tool", format!("\"{t}\": no such tool"));
    }
    if !o.report_strokes.is_empty() && o.stroke_tool.is_none() {
        return keys.err(
            "output.stroke_tool",
            "required with output.report_strokes".into(),
        );
    }
    for (i, r) in o.report_strokes.iter().enumerate() {
        keys.positive(&format!("output.report_strokes[{i}]"), *r, "mm")?;
    }
    keys.positive("output.symmetry_factor", o.symmetry_factor, "-")?;
    if o.history_points < 2 {
        return keys.err(
            "output.history_points",
            format!("{}: must be >= 2", o.history_points),
        );
    }
    for (i, sec) in o.sections.iter().enumerate() {
        let d = [sec.to[0] - sec.from[0], sec.to[1] - sec.from[1]];
        if d[0].hypot(d[1]).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return keys.err(
                &format!("output.sections[{i}].to"),
                "the section has zero length".into(),
            );
        }
    }
    for (i, p) in o.profiles.iter().enumerate() {
        let key = |k: &str| format!("output.profiles[{i}].{k}");
        let d = [p.to[0] - p.from[0], p.to[1] - p.from[1]];
        if d[0].hypot(d[1]).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return keys.err(&key("to"), "the profile has zero length".into());
        }
        keys.positive(&key("web_to"), p.web_to, "mm")?;
        keys.positive(&key("shoulder_clear"), p.shoulder_clear, "mm")?;
        if p.flange_from.partial_cmp(&p.web_to) != Some(std::cmp::Ordering::Greater) {
            return keys.err(
                &key("flange_from"),
                format!(
                    "{} mm: must be beyond web_to = {} mm",
                    p.flange_from, p.web_to
                ),
            );
        }
        if o.profiles[..i].iter().any(|q| q.name == p.name) {
            return keys.err(
                &key("name"),
                format!("{:?}: a second profile of that name", p.name),
            );
        }
    }
    for (i, d) in o.draw_in.iter().enumerate() {
        if d.inward[0].hypot(d.inward[1]).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return keys.err(
                &format!("output.draw_in[{i}].inward"),
                "must be a non-zero vector".into(),
            );
        }
    }
    // What the scene's reference check needs: its table, and whatever else
    // it asks for (its kind is resolved in `header`; every table present
    // was resolved against its check's keys when the scene was read).
    if let Ok(Some(check)) = super::kind::resolve(&s.scene.kind) {
        let Some(table) = o.checks.get(check.key) else {
            let declared: Vec<&str> = check.keys.iter().map(|k| k.key()).collect();
            return keys.err(
                &format!("output.{}", check.key),
                format!(
                    "a {} scene needs [output.{}] {{ {} }}",
                    check.name,
                    check.key,
                    declared.join(", ")
                ),
            );
        };
        (check.needs)(loaded, table)?;
    }
    Ok(())
}

/// What cannot give a meaningful run although every key is in range: a
/// mass-scaling step too long for the press steps, a run larger than the
/// machine (a mesh file is counted when read, in [`super::build()`]).
fn guards(loaded: &LoadedScene) -> Result<(), SceneError> {
    estimate::check_mass_scaling_step(loaded)?;
    let size = MeshSize::of_spec(&loaded.scene).unwrap_or(MeshSize::NONE);
    estimate::check_size(loaded, &estimate::estimate(&loaded.scene, size))
}

fn check_amplitude(
    loaded: &LoadedScene,
    key: &str,
    a: Option<&AmplitudeSpec>,
    in_step: bool,
) -> Result<(), SceneError> {
    match a {
        None => Ok(()),
        Some(AmplitudeSpec::Named(n)) => match n.as_str() {
            "constant" => Ok(()),
            "smooth-step" | "slow-start" | "linear" if in_step => Ok(()),
            _ => Err(loaded.key_error(
                key,
                if in_step {
                    format!("\"{n}\": must be \"smooth-step\", \"slow-start\", \"linear\", \"constant\", a ramp or a table")
                } else {
                    format!("\"{n}\": must be \"constant\", a ramp {{ shape, t0, t1 }} or a table")
                },
            )),
        },
        Some(AmplitudeSpec::Ramp { shape, t0, t1 }) => {
            if !matches!(shape.as_str(), "smooth-step" | "slow-start" | "linear") {
                return Err(loaded.key_error(
                    key,
                    format!("shape \"{shape}\": must be \"smooth-step\", \"slow-start\" or \"linear\""),
                ));
            }
            if !(t0.is_finite() && t1.is_finite() && t1 > t0) {
                return Err(loaded.key_error(key, format!("t0 = {t0} s, t1 = {t1} s: need t1 > t0")));
            }
            Ok(())
        }
        Some(AmplitudeSpec::Table(rows)) => {
            if rows.is_empty() || rows.iter().any(|r| !r[0].is_finite() || !r[1].is_finite()) {
                return Err(loaded.key_error(key, "the table needs finite [t, A] rows"));
            }
            if rows.windows(2).any(|w| w[1][0] <= w[0][0]) {
                return Err(loaded.key_error(key, "table times must increase strictly"));
            }
            Ok(())
        }
    }
}

fn bad_dof(d: &str) -> String {
    format!("\"{d}\": must be one of ux, uy, uz, rx, ry, rz")
}

/// `"x" | "y" | "z"` → 0, 1, 2.
pub fn axis_index(axis: &str) -> Option<usize> {
    match axis {
        "x" => Some(0),
        "y" => Some(1),
        "z" => Some(2),
        _ => None,
    }
}

/// `ux` … `rz` → the DOF.
pub fn dof_from_name(name: &str) -> Option<fem_core::Dof> {
    fem_core::Dof::from_name(name)
}

/// Advice that does not stop a run: the blank's elements are longer than a
/// third of the smallest tool radius it bends over (`profile_radius`,
/// `shoulder_radius`, `radius`, the S-rail's `punch_shoulder` and `die_shoulder`), so the bending over it is coarsely resolved
/// (the square cup at 25 × 25, 3 mm elements over the 5 mm die shoulder and
/// the 8 mm punch radius: the largest OX major strain is 77 % (BT) and 82 %
/// (fully integrated) of the 100 × 100 value, docs/convergence.md).
pub fn warnings(loaded: &LoadedScene) -> Vec<String> {
    let s = &loaded.scene;
    let h = match &s.blank.mesh {
        MeshSpec::Rectangle {
            size, divisions, ..
        } => {
            let (nx, ny) = divisions.pair();
            (size[0] / nx as f64).max(size[1] / ny as f64)
        }
        MeshSpec::WrappedStrip { element_size, .. } => *element_size,
        MeshSpec::File { .. } => return Vec::new(),
    };
    let mut smallest: Option<(f64, String)> = None;
    for (tool, value) in &s.tools {
        let Some(table) = value.as_table() else {
            continue;
        };
        for key in [
            "profile_radius",
            "shoulder_radius",
            "radius",
            "punch_shoulder",
            "die_shoulder",
        ] {
            if let Some(r) = table
                .get(key)
                .and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)))
                && r > 0.0
                && smallest.as_ref().is_none_or(|(best, _)| r < *best)
            {
                smallest = Some((r, format!("tools.{tool}.{key}")));
            }
        }
    }
    match smallest {
        Some((r, key)) if h > r / 3.0 => {
            vec![format!(
                "blank.mesh: {h:.2} mm elements span more than a third of the {r} mm {key}: the bending over it is coarsely resolved (use at least {} elements per side)",
                match &s.blank.mesh {
                    MeshSpec::Rectangle { size, .. } =>
                        ((3.0 * size[0].max(size[1]) / r).ceil() as i64).to_string(),
                    _ => "finer".to_string(),
                }
            )]
        }
        _ => Vec::new(),
    }
}

/// A gas-spring curve, checked by [`fem_core::ForceLaw::validate`] (at least
/// one row, compressions finite and strictly increasing, forces finite and
/// `>= 0`), its error given under `key`.
fn check_force_curve(loaded: &LoadedScene, key: &str, rows: &[[f64; 2]]) -> Result<(), SceneError> {
    let motion = key.strip_suffix(".force_curve").unwrap_or(key);
    fem_core::ForceLaw::Compression(rows.iter().map(|r| (r[0], r[1])).collect())
        .validate(motion)
        .map_err(|e| loaded.key_error(key, e.to_string()))
}

/// Whether `name` can stand as one folder name: non-empty, letters, digits,
/// `-`, `_`, `.` only, and not `.` or `..` (or any run of dots alone).
pub fn is_plain_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'))
        && !name.chars().all(|c| c == '.')
}
