//! One new component of each registered kind, added in this file alone and
//! run from a scene: a friction law, a kinematic formulation, a material and
//! a shell element (each with declared parameters) and a tool kind. Nothing else in the
//! workspace names them; `inventory` registers them at link time and the
//! scene resolves every one through its registry.
//!
//! Reference: the block on a plane (`scenes/block-on-plane.toml`,
//! docs/benchmarks.md §3) slides at the friction force `μ N`; with the law
//! below at μ = 0.3 and N = 100 N that is 30 N, within 1 % (the tolerance of
//! the shipped block's own test).

use fem_core::Solver;
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
