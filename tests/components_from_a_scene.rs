//! One new component of each registered kind, added in this file alone and
//! run from a scene: a friction law, a kinematic formulation, a material and
//! a shell element (each with declared parameters), a tool kind, and a
//! reference check with its own `[output.KEY]` table. Nothing else in the
//! workspace names them; `inventory` registers them at link time and the
//! scene resolves every one through its registry.
//!
//! Reference: the block on a plane (`scenes/block-on-plane.toml`,
//! docs/benchmarks.md §3) slides at the friction force `μ N`; with the law
//! below at μ = 0.3 and N = 100 N that is 30 N, within 1 % (the tolerance of
//! the shipped block's own test). The check below measures the same slide as
//! an apparent friction coefficient, `F / N`, against the law's μ, within
//! the same 1 %.

use fem_core::Solver;
use formsim::run::reference_checks::{
    AVERAGE_FROM, CheckTable, Figures, PULL_DOF_SPEC, PULL_SET, PullMean, PulledEnd,
    ReferenceCheck, Sampler, TableKey,
};
use formsim::scene::kind::needs_nothing_else;
use formsim::scene::{LoadedScene, Model, SceneError};
use friction_laws::formulations::Convective;
use plugins_api::law::LawDescription;
use plugins_api::registry::{FormulationEntry, LawEntry};
use plugins_api::{
    CriticalShear, DirectionInputs, FrictionError, FrictionLaw, KinematicFormulation, ParamSpec,
    PointNeeds, ShearInputs, StepKinematics, Vec3,
};
use shell_elements::kinds::{
    ElementKind, MaterialKind, MaterialRequest, Shells, add_set, add_shells, with_builtin_material,
};
use shell_elements::{
    BelytschkoTsay, ElementResult, ElementState, Hardening, J2PlaneStress, Material, Section,
    ShellError, ShellFormulation, V3,
};
use tools_nurbs::builders::primitives;
use tools_nurbs::kinds::{Request, ToolKey, ToolKind};
use tools_nurbs::{NurbsError, Tool};

// ----- a friction law: Amontons–Coulomb under another name -------------------

/// `τ_c = μ p`.
struct TestCoulomb {
    mu: f64,
}

impl FrictionLaw for TestCoulomb {
    fn name(&self) -> &str {
        "test-coulomb"
    }
    fn stick_stiffness(&self) -> f64 {
        1e4
    }
    fn critical_shear(&self, x: &ShearInputs) -> CriticalShear {
        CriticalShear {
            tau: self.mu * x.p,
            dtau_dp: self.mu,
            ..CriticalShear::default()
        }
    }
}

const LAW_PARAMS: &[ParamSpec] = &[ParamSpec::required(
    "mu",
    "-",
    0.0,
    2.0,
    "friction coefficient",
)];

fn build_law(values: &[f64]) -> Result<Box<dyn FrictionLaw>, FrictionError> {
    Ok(Box::new(TestCoulomb { mu: values[0] }))
}

inventory::submit! {
    LawEntry {
        description: LawDescription {
            name: "test-coulomb",
            summary: "tau_c = mu p (a test's law)",
            params: LAW_PARAMS,
        },
        build: build_law,
    }
}

// ----- a formulation: convective, history scaled by a declared parameter -------

/// The convective transport scaled by `keep` (1 keeps the history whole).
struct TestKeep {
    keep: f64,
}

impl KinematicFormulation for TestKeep {
    fn name(&self) -> &str {
        "test-keep"
    }
    fn needs(&self) -> PointNeeds {
        Convective.needs()
    }
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        Convective.transport(t_old, kin) * self.keep
    }
    fn slip_direction(&self, x: &DirectionInputs<'_>) -> Option<Vec3> {
        Convective.slip_direction(x)
    }
    fn backward_euler(&self) -> bool {
        true
    }
}

const FORMULATION_PARAMS: &[ParamSpec] = &[ParamSpec::optional(
    "keep",
    "-",
    1.0,
    0.0,
    1.0,
    "share of the history traction carried into the step",
)];

fn build_formulation(values: &[f64]) -> Result<Box<dyn KinematicFormulation>, FrictionError> {
    Ok(Box::new(TestKeep { keep: values[0] }))
}

inventory::submit! {
    FormulationEntry {
        name: "test-keep",
        summary: "convective with the history scaled by keep (a test's formulation)",
        params: FORMULATION_PARAMS,
        relative_cost: 1.0,
        build: build_formulation,
    }
}

// ----- a tool kind: a square plane of one size key -----------------------------

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SquareKeys {
    side: f64,
}

fn build_square(r: Request<'_>) -> Result<Tool, NurbsError> {
    let (name, place) = (r.name, r.place);
    let k: SquareKeys = r.params()?;
    Ok(Tool::Nurbs(primitives::plane(
        name, k.side, k.side, &place,
    )?))
}

inventory::submit! {
    ToolKind {
        name: "test-square",
        summary: "a square plane (a test's tool kind)",
        keys: &[ToolKey::required("side", "mm", "> 0", "side of the square")],
        default_facing: tools_nurbs::builders::Facing::Up,
        build: build_square,
    }
}

// ----- a material: perfectly plastic J2 with a key of its own ---------------------

const MATERIAL_PARAMS: &[ParamSpec] = &[ParamSpec::required(
    "yield_stress",
    "MPa",
    1.0,
    1e4,
    "the constant flow stress",
)];

fn make_material(r: &MaterialRequest<'_>) -> Result<J2PlaneStress, ShellError> {
    let perfect = Hardening::swift(r.params[0], 1.0, 0.0)?;
    J2PlaneStress::new(r.young, r.poisson, r.density, perfect)
}

fn build_material(r: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    add_shells(&r.shells, make_material(r)?, "test-perfect", solver)
}

inventory::submit! {
    MaterialKind {
        name: "test-perfect",
        summary: "perfectly plastic plane-stress J2: yield_stress (MPa) (a test's material)",
        anisotropic: false,
        hardening: false,
        params: MATERIAL_PARAMS,
        relative_cost: 1.0,
        build: build_material,
    }
}

// ----- an element: Belytschko–Tsay element by element, its drilling a key of its own -----

/// The one-point shell computed one element at a time (the default
/// four-element kernel), with the drilling coefficient it declares.
#[derive(Clone)]
struct TestBt(BelytschkoTsay);

impl ShellFormulation for TestBt {
    const NAME: &'static str = "test-bt";
    const IN_PLANE_POINTS: usize = BelytschkoTsay::IN_PLANE_POINTS;
    const HOURGLASS_VARS: usize = BelytschkoTsay::HOURGLASS_VARS;

    fn drilling(&self) -> f64 {
        self.0.drilling()
    }

    fn compute<M: Material>(
        &self,
        mat: &M,
        sec: &Section,
        x: &[V3; 4],
        v: &[V3; 4],
        w: &[V3; 4],
        dt: f64,
        st: ElementState<'_, M::History>,
    ) -> ElementResult {
        self.0.compute(mat, sec, x, v, w, dt, st)
    }
}

const ELEMENT_PARAMS: &[ParamSpec] = &[ParamSpec::optional(
    "gamma",
    "-",
    1e-3,
    0.0,
    0.1,
    "drilling coefficient",
)];

/// The element with the request's material: this file's own material, or a
/// built-in one.
fn add_element(r: &MaterialRequest<'_>, solver: &mut Solver) -> Result<Shells, ShellError> {
    let form = TestBt(BelytschkoTsay::default().with_drilling(r.shells.element_params[0])?);
    match r.model {
        "test-perfect" => add_set(
            &r.shells,
            form,
            make_material(r)?,
            "test-bt",
            "test-perfect",
            solver,
        ),
        _ => with_builtin_material(r, form, "test-bt", solver),
    }
}

inventory::submit! {
    ElementKind {
        name: "test-bt",
        summary: "Belytschko–Tsay one element at a time: gamma (-) (a test's element)",
        in_plane_points: 1,
        relative_cost: 1.0,
        params: ELEMENT_PARAMS,
        add: Some(add_element),
        static_form: false,
    }
}

// ----- a reference check: the apparent friction coefficient, with its own table ---

/// `[output.apparent_mu]`: the pulled end (`pull_dof` by default `ux`) and
/// the normal force.
const APPARENT_MU_KEYS: &[TableKey] = &[
    PULL_SET,
    TableKey::Name(PULL_DOF_SPEC.or("ux")),
    TableKey::Number(
        ParamSpec::required(
            "normal_force",
            "N",
            0.0,
            f64::INFINITY,
            "the normal force pressing the block on the plane",
        )
        .exclusive_min(),
    ),
    AVERAGE_FROM,
];

/// The mean pull over the normal force.
struct ApparentMu {
    pull: PullMean,
    normal_force: f64,
}

impl Sampler for ApparentMu {
    fn sample(&mut self, loaded: &LoadedScene, model: &Model) -> Result<(), SceneError> {
        self.pull.sample(loaded, model).map(drop)
    }

    fn sampled(&self) -> bool {
        self.pull.samples() > 0
    }

    fn figures(&self, mu: f64) -> Option<Figures> {
        Some(Figures {
            value: self.pull.mean() / self.normal_force,
            analytic: mu,
            more: vec![("slip_force", self.pull.mean())],
        })
    }
}

fn start_apparent_mu(_: &LoadedScene, table: &CheckTable, _: &Model) -> Option<Box<dyn Sampler>> {
    Some(Box::new(ApparentMu {
        pull: PullMean::new(&PulledEnd::of(table)?),
        normal_force: table.number("normal_force")?,
    }))
}

fn apparent_mu_line(f: &Figures) -> String {
    format!(
        "apparent mu: F/N = {:.4}, mu = {:.4} ({:+.2} %)",
        f.value,
        f.analytic,
        f.deviation_percent()
    )
}

inventory::submit! {
    ReferenceCheck {
        name: "test-apparent-mu",
        summary: "block pulled over a plane: F/N against the law's mu (a test's check); [output.apparent_mu]",
        key: "apparent_mu",
        keys: APPARENT_MU_KEYS,
        value_key: "mu_apparent",
        needs: needs_nothing_else,
        start: start_apparent_mu,
        line: apparent_mu_line,
    }
}

// ----- the scene -------------------------------------------------------------------

/// `scenes/block-on-plane.toml` with its plane tool of the test's kind,
/// written into `dir`.
fn block_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("scenes/block-on-plane.toml")).unwrap();
    let plane = "kind = \"plane\"\nlength = 100.0\nwidth = 100.0";
    assert!(text.contains(plane), "the block's plane tool changed");
    let text = text.replace(plane, "kind = \"test-square\"\nside = 100.0");
    let elastic = "hardening = { kind = \"elastic\" }";
    assert!(text.contains(elastic), "the block's material changed");
    let text = text.replace(
        elastic,
        "model = \"test-perfect\"\nparameters = { yield_stress = 250.0 }",
    );
    std::fs::create_dir_all(dir).unwrap();
    let scene = dir.join("block.toml");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// [`block_scene`] of the test's check: its kind, and its table in place of
/// the block's, written into `dir`.
fn apparent_mu_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let scene = block_scene(dir);
    let text = std::fs::read_to_string(&scene).unwrap();
    let kind = "kind = \"block-on-plane\"";
    let table = "block = { pull_set = \"all\", pull_dof = \"ux\", normal_force = 100.0, average_from = 3.0e-3 }";
    assert!(
        text.contains(kind) && text.contains(table),
        "the block's kind or table changed"
    );
    let text = text.replace(kind, "kind = \"test-apparent-mu\"").replace(
        table,
        "\n[output.apparent_mu]\npull_set = \"all\"\nnormal_force = 100.0\naverage_from = 3.0e-3",
    );
    std::fs::write(&scene, text).unwrap();
    scene
}

/// The material's declared key is required and checked against its range
/// when the scene is read, at its key.
#[test]
fn a_registered_material_checks_its_declared_key() {
    let dir = std::env::temp_dir().join(format!("formsim-yield-{}", std::process::id()));
    let scene = block_scene(&dir);
    for (set, says) in [
        (
            "blank.material.parameters={}",
            "missing parameter `yield_stress` (MPa)",
        ),
        (
            "blank.material.parameters.yield_stress=-1.0",
            "`yield_stress` = -1 MPa of `test-perfect` is out of range",
        ),
        ("blank.material.parameters.k=1.0", "unknown parameter `k`"),
    ] {
        let e = formsim::scene::load(&scene, &[set.to_string()]).expect_err(set);
        let m = e.to_string();
        assert!(
            m.contains("blank.material.parameters") && m.contains(says),
            "{set}: {m}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The formulation's declared parameter is read from the scene and checked
/// against its range, with the error at its key.
#[test]
fn a_registered_formulation_checks_its_declared_parameter() {
    let dir = std::env::temp_dir().join(format!("formsim-keep-{}", std::process::id()));
    let scene = block_scene(&dir);
    let sets = [
        "contact.formulation=\"test-keep\"".to_string(),
        "contact.params.test-keep.keep=2.0".to_string(),
    ];
    let loaded = formsim::scene::load(&scene, &sets).unwrap_or_else(|e| panic!("{e}"));
    let Err(e) = formsim::scene::build(&loaded) else {
        panic!("keep = 2 is out of range, and the model was built");
    };
    let _ = std::fs::remove_dir_all(&dir);
    let m = e.to_string();
    assert!(
        m.contains("contact.params.test-keep") && m.contains("keep"),
        "{m}"
    );
}

/// The block on a plane with every component swapped for the ones above.
#[test]
fn block_on_plane_with_a_new_component_of_each_kind_slides_at_mu_n() {
    let dir = std::env::temp_dir().join(format!("formsim-components-{}", std::process::id()));
    let scene = block_scene(&dir);
    let sets: Vec<String> = [
        "contact.law=\"test-coulomb\"",
        "contact.params.test-coulomb.mu=0.3",
        "contact.formulation=\"test-keep\"",
        "contact.params.test-keep.keep=1.0",
        "blank.element=\"test-bt\"",
        "blank.element_parameters.gamma=1e-3",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let loaded = formsim::scene::load(&scene, &sets).unwrap_or_else(|e| panic!("{e}"));
    let r = formsim::run::run(
        &loaded,
        &formsim::run::RunOptions {
            out: dir.join("out"),
            progress: formsim::run::Progress::Hidden,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    let s = &r.summary;
    assert_eq!(s.law, "test-coulomb");
    assert_eq!(s.formulation, "test-keep");
    assert_eq!(s.element, "test-bt");
    let b = s.figures("block").expect("the block's check");
    assert!((b.analytic - 30.0).abs() < 1e-9, "mu N = {} N", b.analytic);
    assert!(
        (b.value / b.analytic - 1.0).abs() < 0.01,
        "slip force {} N against mu N = {} N",
        b.value,
        b.analytic
    );
}

/// The element's declared key is checked at its key when the scene is read,
/// and the element pairs with a built-in material as well as with this
/// file's own.
#[test]
fn a_registered_element_checks_its_key_and_pairs_with_a_built_in_material() {
    let dir = std::env::temp_dir().join(format!("formsim-element-{}", std::process::id()));
    let scene = block_scene(&dir);
    let element = "blank.element=\"test-bt\"".to_string();
    for (set, says) in [
        (
            "blank.element_parameters.gamma=0.5",
            "`gamma` = 0.5 - of `test-bt` is out of range",
        ),
        ("blank.element_parameters.k=1.0", "unknown parameter `k`"),
    ] {
        let e = formsim::scene::load(&scene, &[element.clone(), set.to_string()]).expect_err(set);
        let m = e.to_string();
        assert!(
            m.contains("blank.element_parameters") && m.contains(says),
            "{set}: {m}"
        );
    }
    let j2 = [
        element,
        "blank.material.model=\"j2\"".to_string(),
        "blank.material.parameters={}".to_string(),
        "blank.material.hardening={kind=\"elastic\"}".to_string(),
    ];
    let loaded = formsim::scene::load(&scene, &j2).unwrap_or_else(|e| panic!("{e}"));
    let model = formsim::scene::build(&loaded).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    let h = model.shells;
    assert_eq!((h.element, h.material), ("test-bt", "j2"));
}

/// A springback step's implicit method needs shells with a static form;
/// the registered element has none (`static_form: false`), so a scene that
/// asks for it with this element is refused at `steps[i].method`, in one
/// line naming the element and the method that works with every element.
#[test]
fn a_registered_element_without_a_static_form_is_refused_the_implicit_springback() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let scene = root.join("scenes/square-cup-springback.toml");
    let element = "blank.element=\"test-bt\"".to_string();
    let e = formsim::scene::load(&scene, std::slice::from_ref(&element)).expect_err(&element);
    let m = e.to_string();
    assert!(
        m.contains("steps[3].method")
            && m.contains("the test-bt shell has none")
            && m.contains("dynamic-relaxation"),
        "{m}"
    );
    assert_eq!(m.lines().count(), 1, "{m}");
    let relaxed = [
        element,
        "steps[3].method=\"dynamic-relaxation\"".to_string(),
    ];
    formsim::scene::load(&scene, &relaxed).unwrap_or_else(|e| panic!("{e}"));
}

/// The check's table is read against the keys it declares: an unknown key
/// names the table and the key at its line, a mistyped value names the key
/// and the unit, a scene of its kind without it names the table, and a
/// table no check reads lists the registered ones, the test's among them.
#[test]
fn a_registered_check_reads_its_declared_table() {
    let dir = std::env::temp_dir().join(format!("formsim-table-{}", std::process::id()));
    let scene = apparent_mu_scene(&dir);
    let text = std::fs::read_to_string(&scene).unwrap();
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("normal_force"))
        .unwrap();
    let typo = text.replace("normal_force = 100.0", "normal_forc = 100.0");
    let e = formsim::scene::parse(&typo, &scene, &[]).expect_err("an unknown key");
    let m = e.to_string();
    assert!(
        m.contains(&format!(
            ":{line}: output.apparent_mu.normal_forc: unknown key in [output.apparent_mu]"
        )),
        "{m}"
    );
    for (set, says) in [
        (
            "output.apparent_mu.normal_force=\"heavy\"",
            "output.apparent_mu.normal_force: \"heavy\" (a string): expected a number in N",
        ),
        (
            "output.apparent_mu.normal_force=0",
            "output.apparent_mu.normal_force: 0 N: must be finite and > 0",
        ),
        (
            "output.apparent_mu=",
            "output.apparent_mu: a test-apparent-mu scene needs [output.apparent_mu] { pull_set, pull_dof, normal_force, average_from }",
        ),
        (
            "output.apparent_muu.pull_set=\"all\"",
            "[output.apparent_mu] of test-apparent-mu",
        ),
    ] {
        let e = formsim::scene::load(&scene, &[set.to_string()]).expect_err(set);
        let m = e.to_string();
        assert!(m.contains(says) && !m.contains('\n'), "{set}: {m}");
    }
    let loaded = formsim::scene::load(&scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    let table = &loaded.scene.output.checks["apparent_mu"];
    assert_eq!(table.name("pull_dof"), Some("ux"), "the declared default");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The test's check on the block with every component of this file: its
/// figure, `F / N`, is the law's μ = 0.3 within 1 %, and `summary.json`
/// carries it under the check's key.
#[test]
fn a_registered_check_measures_the_apparent_mu() {
    let dir = std::env::temp_dir().join(format!("formsim-apparent-{}", std::process::id()));
    let scene = apparent_mu_scene(&dir);
    let sets: Vec<String> = [
        "contact.law=\"test-coulomb\"",
        "contact.params.test-coulomb.mu=0.3",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let loaded = formsim::scene::load(&scene, &sets).unwrap_or_else(|e| panic!("{e}"));
    let out = dir.join("out");
    let r = formsim::run::run(
        &loaded,
        &formsim::run::RunOptions {
            out: out.clone(),
            progress: formsim::run::Progress::Hidden,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let f = r.summary.figures("apparent_mu").expect("the test's check");
    assert!((f.analytic - 0.3).abs() < 1e-12, "mu = {}", f.analytic);
    assert!(
        (f.value / f.analytic - 1.0).abs() < 0.01,
        "F/N = {} against mu = {}",
        f.value,
        f.analytic
    );
    let slip = f.get("slip_force").expect("its further figure");
    assert!(
        (slip / 100.0 - f.value).abs() < 1e-12,
        "slip force {slip} N"
    );
    assert!(
        json.contains("\"apparent_mu\": {") && json.contains("\"mu_apparent\": "),
        "{json}"
    );
}
