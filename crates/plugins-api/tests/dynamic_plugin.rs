//! Dynamic plugins end to end: build the example plugin `exp-decay` (and the
//! misbehaving fixture `test-panicky`) as shared libraries, load them through
//! `plugins_api::loader`, and drive the loaded laws through the shared return
//! mapping (docs/friction-math.md §2). Also: the loader's errors for files that are
//! not plugins, or plugins of another ABI version.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, OnceLock};

use plugins_api::kinematics::rotate_minimal;
use plugins_api::loader::{PluginLibrary, take_last_error};
use plugins_api::return_mapping::{PointState, StepInput, TangentMode, step};
use plugins_api::{
    ABI_VERSION, FrictionError, FrictionLaw, KinematicFormulation, Params, PointNeeds, ShearInputs,
    StepKinematics, Vec3,
};

// ---------------------------------------------------------------- fixtures

mod support;
use support::{build_plugins, dylib_name};

/// Paths of the freshly built `exp-decay` and `test-panicky` libraries (one
/// `cargo build` per test binary).
fn plugins() -> &'static (PathBuf, PathBuf) {
    static BUILT: OnceLock<(PathBuf, PathBuf)> = OnceLock::new();
    BUILT.get_or_init(|| {
        let p = build_plugins(&["exp-decay", "test-panicky"]);
        (p[0].clone(), p[1].clone())
    })
}

fn scratch_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dynamic_plugin");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir
}

/// Compile a dependency-free `cdylib` from `source` with rustc: stand-ins for
/// foreign libraries and for plugins built against another ABI.
fn tiny_cdylib(stem: &str, source: &str) -> PathBuf {
    let dir = scratch_dir();
    let src = dir.join(format!("{stem}.rs"));
    let lib = dir.join(dylib_name(stem));
    std::fs::write(&src, source).expect("write source");
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let out = Command::new(rustc)
        .args([
            "--crate-type",
            "cdylib",
            "--edition",
            "2021",
            "--crate-name",
            stem,
            "-o",
        ])
        .arg(&lib)
        .arg(&src)
        .output()
        .expect("run rustc");
    assert!(
        out.status.success(),
        "rustc {stem}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    lib
}

fn exp_decay() -> PluginLibrary {
    PluginLibrary::open(&plugins().0).expect("open exp-decay")
}

/// Minimal `convective` formulation (friction-math §4): parallel transport by
/// the minimal rotation `n_old → n_new`, backward-Euler slip direction.
struct Convective;

impl KinematicFormulation for Convective {
    fn name(&self) -> &str {
        "convective"
    }
    fn needs(&self) -> PointNeeds {
        PointNeeds::NONE
    }
    fn transport(&self, t_old: &Vec3, kin: &StepKinematics) -> Vec3 {
        rotate_minimal(&kin.n_old, &kin.n_new, t_old)
    }
    fn slip_direction(&self, _: &plugins_api::DirectionInputs<'_>) -> Option<Vec3> {
        None
    }
}

/// The exp-decay law in closed form (plugins/exp-decay/src/lib.rs docs):
/// `μ(v) = μ_k + (μ_s - μ_k) exp(-d v)`; returns `(τ_c, ∂τ_c/∂p, ∂τ_c/∂v)`.
fn closed_form(mu_s: f64, mu_k: f64, d: f64, p: f64, v: f64) -> (f64, f64, f64) {
    let e = (-d * v).exp();
    let mu = mu_k + (mu_s - mu_k) * e;
    (mu * p, mu, -d * (mu_s - mu_k) * e * p)
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

fn inputs(p: f64, v: f64) -> ShearInputs {
    ShearInputs {
        p,
        omega: 0.0,
        sliding_speed: v,
        flow_stress: f64::NAN,
        temperature: f64::NAN,
    }
}

// ---------------------------------------------------------------- exp-decay

#[test]
fn exp_decay_plugin_describes_itself() {
    let lib = exp_decay();
    assert_eq!(lib.name(), "exp-decay");
    assert_eq!(lib.abi_version(), ABI_VERSION);
    assert!(lib.summary().contains("exp(-d |v|)"), "{}", lib.summary());
    assert_eq!(lib.needs(), PointNeeds::SLIDING_VELOCITY);
    assert!(!lib.work_dependent());
    let p = lib.params();
    let names: Vec<_> = p.iter().map(|s| s.name).collect();
    let units: Vec<_> = p.iter().map(|s| s.unit).collect();
    let defaults: Vec<_> = p.iter().map(|s| s.default).collect();
    assert_eq!(names, ["mu_s", "mu_k", "d", "k_t"]);
    assert_eq!(units, ["-", "-", "s/mm", "MPa/mm"]);
    assert_eq!(defaults, [None, None, Some(0.0), Some(1e5)]);
    assert_eq!(p[3].range_text(), "> 0");
    assert_eq!(p[0].range_text(), ">= 0");
}

/// Source: the closed form of the plugin (μ_k + (μ_s - μ_k) e^{-d|v|}) p.
/// Tolerance 1e-14 relative: the same formula evaluated on both sides of the
/// C boundary (only round-off may differ).
#[test]
fn exp_decay_critical_shear_matches_closed_form() {
    let (mu_s, mu_k, d) = (0.2, 0.12, 0.03);
    for (ms, mk) in [(mu_s, mu_k), (mu_k, mu_s)] {
        let params = Params::new().with("mu_s", ms).with("mu_k", mk).with("d", d);
        let law = exp_decay().build(&params).expect("build");
        assert_eq!(law.name(), "exp-decay");
        assert_eq!(law.stick_stiffness(), 1e5);
        assert_eq!(law.needs(), PointNeeds::SLIDING_VELOCITY);
        for &p in &[0.0, 0.3, 12.0, 480.0] {
            for &v in &[0.0, 0.5, 7.0, 60.0, 1e3] {
                let cs = law.critical_shear(&inputs(p, v));
                let (tau, dp, dv) = closed_form(ms, mk, d, p, v);
                assert!(
                    rel(cs.tau, tau) <= 1e-14 || (p == 0.0 && cs.tau == 0.0),
                    "tau p={p} v={v}: {} vs {tau}",
                    cs.tau
                );
                assert!(
                    rel(cs.dtau_dp, dp) <= 1e-14,
                    "dtau_dp p={p} v={v}: {} vs {dp}",
                    cs.dtau_dp
                );
                assert!(
                    rel(cs.dtau_dspeed, dv) <= 1e-14 || (p == 0.0 && cs.dtau_dspeed == 0.0),
                    "dtau_dv p={p} v={v}"
                );
                assert_eq!((cs.dtau_domega, cs.clamped), (0.0, false));
            }
        }
    }
    let stiff = exp_decay()
        .build(
            &Params::new()
                .with("mu_s", 0.1)
                .with("mu_k", 0.1)
                .with("k_t", 2.5e4),
        )
        .unwrap();
    assert_eq!(stiff.stick_stiffness(), 2.5e4);
}

/// Source: docs/friction-math.md §2 (radial return) with the exp-decay `τ_c`.
/// A point on a flat tool (n = e_z, p = 50 MPa) is dragged with a speed that
/// ramps from 0 to 80 mm/s over a slowly turning direction. Checks per step,
/// to 1e-12 relative (round-off of a handful of operations on O(10) MPa):
/// stick steps give `t = t_n - k_T Δu`; slip steps give `|t| = μ(v) p` with
/// `v = |Δu|/Δt`, `t ∥ t_tr`, `Δγ = (|t_tr| - τ_c)/k_T`, `ΔD = τ_c Δγ ≥ 0`,
/// `∂t/∂p = μ(v) φ_tr` (consistent tangent); and `ω` is the sum of the `ΔD`.
#[test]
fn exp_decay_slipping_history_through_return_mapping() {
    let (mu_s, mu_k, d, k_t) = (0.2, 0.12, 0.03, 1e5);
    let params = Params::new()
        .with("mu_s", mu_s)
        .with("mu_k", mu_k)
        .with("d", d);
    let law = exp_decay().build(&params).expect("build");
    let n = Vec3::z();
    let dt = 1e-3;
    let p = 50.0;
    let mut state = PointState::default();
    let (mut sticks, mut slips, mut omega_sum) = (0, 0, 0.0);
    for i in 0..80 {
        let v = 80.0 * (f64::from(i) / 40.0).min(1.0);
        let angle = 0.01 * f64::from(i);
        let du = Vec3::new(angle.cos(), angle.sin(), 0.0) * (v * dt);
        let input = StepInput::new(p, du, StepKinematics::simple(dt, n, n));
        let before = state;
        let out = step(
            &law,
            &Convective,
            TangentMode::Consistent,
            &mut state,
            &input,
        )
        .expect("step");
        let (tau, dtau_dp, _) = closed_form(mu_s, mu_k, d, p, du.norm() / dt);
        assert!(
            rel(out.tau_c, tau) <= 1e-12,
            "step {i}: tau_c {} vs {tau}",
            out.tau_c
        );
        let t_tr = before.t - k_t * du;
        if out.stick {
            sticks += 1;
            assert!(
                (out.t - t_tr).norm() <= 1e-12 * t_tr.norm().max(1.0),
                "step {i}: stick traction"
            );
            assert!(out.t.norm() <= tau * (1.0 + 1e-12));
            assert_eq!(out.dissipation, 0.0);
        } else {
            slips += 1;
            let phi = t_tr / t_tr.norm();
            assert!(
                rel(out.t.norm(), tau) <= 1e-12,
                "step {i}: |t| = {} vs {tau}",
                out.t.norm()
            );
            assert!(
                (out.t / out.t.norm() - phi).norm() <= 1e-12,
                "step {i}: t not along t_tr"
            );
            assert!(
                rel(out.dgamma, (t_tr.norm() - tau) / k_t) <= 1e-12,
                "step {i}: dgamma"
            );
            assert!(out.dissipation >= 0.0 && rel(out.dissipation, tau * out.dgamma) <= 1e-12);
            assert!(
                (out.dt_dp - phi * dtau_dp).norm() <= 1e-12 * dtau_dp,
                "step {i}: dt/dp"
            );
            assert!(
                out.t.dot(&du) < 0.0,
                "step {i}: friction must oppose the slip"
            );
            if i % 10 == 5 {
                check_tangent_by_central_differences(&*law, &before, &input, &out.tangent);
            }
        }
        assert!(state.omega >= before.omega, "step {i}: omega decreased");
        omega_sum += out.dissipation;
    }
    assert!(rel(state.omega, omega_sum) <= 1e-12);
    assert!(sticks >= 1 && slips >= 30, "sticks {sticks}, slips {slips}");
    // Velocity weakening shows: final |t| is near μ_k p, well below μ_s p.
    let mu_end = state.t.norm() / p;
    assert!(mu_end < 0.13 && mu_end > mu_k, "mu at 80 mm/s = {mu_end}");
}

/// friction-math §2/§5: the consistent tangent `∂t/∂Δu_T` (which for this law
/// carries the velocity term `φ ⊗ (Δu/|Δu|) ∂τ_c/∂v / Δt`) against central
/// differences of the return mapping, step `1e-6 |Δu|`. Tolerance 1e-6 of the
/// tangent's norm: truncation is O(h²) and round-off ~1e-9 at this step.
fn check_tangent_by_central_differences(
    law: &dyn FrictionLaw,
    before: &PointState,
    input: &StepInput,
    tangent: &plugins_api::Mat3,
) {
    let h = 1e-6 * input.du.norm();
    let traction = |du: Vec3| {
        let mut s = *before;
        let x = StepInput { du, ..*input };
        step(law, &Convective, TangentMode::None, &mut s, &x)
            .expect("perturbed step")
            .t
    };
    for j in 0..3 {
        let e = Vec3::ith(j, h);
        let fd = (traction(input.du + e) - traction(input.du - e)) / (2.0 * h);
        let col: Vec3 = tangent.column(j).into_owned();
        assert!(
            (fd - col).norm() <= 1e-6 * tangent.norm(),
            "tangent column {j}: fd {fd:?} vs {col:?}"
        );
    }
}

#[test]
fn exp_decay_parameter_errors_name_the_parameter() {
    let lib = exp_decay();
    let e = lib
        .build_dynamic(&Params::new().with("mu_k", 0.1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("missing parameter `mu_s`"), "{e}");
    let e = lib
        .build_dynamic(&Params::new().with("mu_s", 0.1).with("mu_k", -0.1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`mu_k` = -0.1") && e.contains(">= 0"), "{e}");
    let e = lib
        .build_dynamic(
            &Params::new()
                .with("mu_s", 0.1)
                .with("mu_k", 0.1)
                .with("k_t", 0.0),
        )
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`k_t`") && e.contains("MPa/mm") && e.contains("> 0"),
        "{e}"
    );
    let e = lib
        .build_dynamic(&Params::new().with("mu", 0.1))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unknown parameter `mu`") && e.contains("mu_s, mu_k, d, k_t"),
        "{e}"
    );
}

/// A law keeps its library loaded after the `PluginLibrary` is dropped, and
/// evaluates concurrently from several threads (Send + Sync through the table).
#[test]
fn laws_outlive_their_library_handle_and_run_on_many_threads() {
    let law = {
        let lib = exp_decay();
        lib.build_dynamic(
            &Params::new()
                .with("mu_s", 0.3)
                .with("mu_k", 0.1)
                .with("d", 0.1),
        )
        .unwrap()
    };
    let law = Arc::new(law);
    let handles: Vec<_> = (0..4)
        .map(|k| {
            let law = Arc::clone(&law);
            std::thread::spawn(move || {
                (0..1000)
                    .map(|i| {
                        let v = f64::from(k * 1000 + i) * 0.01;
                        rel(
                            law.critical_shear(&inputs(20.0, v)).tau,
                            closed_form(0.3, 0.1, 0.1, 20.0, v).0,
                        )
                    })
                    .fold(0.0, f64::max)
            })
        })
        .collect();
    for h in handles {
        assert!(h.join().unwrap() <= 1e-14);
    }
    assert!(law.last_error().is_none());
}

// ---------------------------------------------------------------- loader errors

#[test]
fn missing_file_is_reported_clearly() {
    let path = scratch_dir().join("no_such_plugin.so");
    let e = PluginLibrary::open(&path).unwrap_err();
    assert!(matches!(e, FrictionError::Plugin { .. }));
    let text = e.to_string();
    assert!(
        text.contains("no_such_plugin.so") && text.contains("file not found"),
        "{text}"
    );
}

#[test]
fn file_that_is_not_a_shared_library_is_reported_clearly() {
    let path = scratch_dir().join("not_a_library.so");
    std::fs::write(&path, "mu = 0.1\n").unwrap();
    let text = PluginLibrary::open(&path).unwrap_err().to_string();
    assert!(
        text.contains("not_a_library.so") && text.contains("cannot be loaded as a shared library"),
        "{text}"
    );
    let text = PluginLibrary::open(scratch_dir()).unwrap_err().to_string();
    assert!(text.contains("is a directory"), "{text}");
}

#[test]
fn shared_library_without_the_entry_symbol_is_not_a_plugin() {
    let lib = tiny_cdylib(
        "not_a_plugin",
        "#[no_mangle] pub extern \"C\" fn formsim_unrelated() -> i32 { 7 }\n",
    );
    let text = PluginLibrary::open(&lib).unwrap_err().to_string();
    assert!(
        text.contains(
            "is not a formsim friction plugin: symbol `formsim_friction_plugin_v1` not found"
        ),
        "{text}"
    );
}

/// A table whose `abi_version` is not ours, behind the v1 symbol: what a plugin
/// built against another `plugins-api` looks like. The real loader path
/// (dlopen, dlsym, entry call, version check) refuses it.
#[test]
fn abi_version_mismatch_is_refused_by_the_loader() {
    let source = r#"
#[repr(C)]
pub struct Head { abi_version: u32, rest: [usize; 4] }
static TABLE: Head = Head { abi_version: 999, rest: [0; 4] };
#[no_mangle]
pub extern "C" fn formsim_friction_plugin_v1() -> *const Head { &TABLE }
"#;
    let lib = tiny_cdylib("future_plugin", source);
    let text = PluginLibrary::open(&lib).unwrap_err().to_string();
    let expected = format!(
        "plugin ABI version 999, this formsim expects {ABI_VERSION}: rebuild the plugin against plugins-api {}",
        env!("CARGO_PKG_VERSION")
    );
    assert!(text.contains(&expected), "{text}");
}

/// A plugin of another major version exports another symbol; the loader says so.
#[test]
fn other_major_version_symbol_is_named() {
    let source = "#[no_mangle] pub extern \"C\" fn formsim_friction_plugin_v2() -> *const u32 { static V: u32 = 2; &V }\n";
    let lib = tiny_cdylib("v2_plugin", source);
    let text = PluginLibrary::open(&lib).unwrap_err().to_string();
    assert!(
        text.contains("symbol `formsim_friction_plugin_v1` not found")
            && text.contains("exports `formsim_friction_plugin_v2`")
            && text.contains("major version 2"),
        "{text}"
    );
}

// ---------------------------------------------------------------- panics

/// A panic inside the plugin's `critical_shear` becomes `PluginPanicked` from
/// the return mapping (state untouched), naming the plugin, the panic's message
/// and where it came from, not a NaN result; the process survives and the law
/// keeps working.
#[test]
fn panic_in_critical_shear_is_an_error_not_a_crash() {
    let lib = PluginLibrary::open(&plugins().1).expect("open test-panicky");
    let law = lib
        .build_dynamic(&Params::new().with("mu", 0.1).with("panic_above_p", 100.0))
        .unwrap();
    let n = Vec3::z();
    let kin = StepKinematics::simple(1e-3, n, n);
    let du = Vec3::new(1e-2, 0.0, 0.0);
    let mut state = PointState::default();
    let ok = step(
        &law,
        &Convective,
        TangentMode::None,
        &mut state,
        &StepInput::new(50.0, du, kin),
    )
    .unwrap();
    assert!(!ok.stick && rel(ok.t.norm(), 0.1 * 50.0) <= 1e-14);

    let before = state;
    let _ = take_last_error();
    let err = step(
        &law,
        &Convective,
        TangentMode::None,
        &mut state,
        &StepInput::new(150.0, du, kin),
    )
    .unwrap_err();
    assert!(
        matches!(err, FrictionError::PluginPanicked { ref call, .. } if call == "critical_shear at p = 150 MPa"),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.starts_with(
            "plugin test-panicky panicked: test-panicky: deliberate panic at p = 150 MPa > panic_above_p = 100 MPa (at plugins/test-panicky/src/lib.rs:"
        ) && text.contains("; in critical_shear at p = 150 MPa (")
            && !text.contains("NaN")
            && !text.contains("non-finite"),
        "{text}"
    );
    assert_eq!(state, before, "state must be unchanged on error");
    assert_eq!(law.last_error().as_deref(), Some(text.as_str()));
    // The return mapping took the failure: it is reported once.
    assert_eq!(take_last_error(), None);

    let again = step(
        &law,
        &Convective,
        TangentMode::None,
        &mut state,
        &StepInput::new(50.0, du, kin),
    )
    .unwrap();
    assert!(rel(again.t.norm(), 0.1 * 50.0) <= 1e-14);
}

#[test]
fn panic_or_rejection_while_building_is_reported() {
    let lib = PluginLibrary::open(&plugins().1).expect("open test-panicky");
    let e = lib
        .build_dynamic(&Params::new().with("create_mode", 2.0))
        .unwrap_err();
    assert!(matches!(e, FrictionError::PluginPanicked { .. }), "{e:?}");
    let text = e.to_string();
    assert!(
        text.starts_with(
            "plugin test-panicky panicked: test-panicky: deliberate panic while building (at "
        ) && text.contains("; in create ("),
        "{text}"
    );
    let e = lib
        .build_dynamic(&Params::new().with("create_mode", 1.0))
        .unwrap_err();
    assert!(
        matches!(e, FrictionError::InvalidParameters { .. }),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("create_mode = 1 rejects these values"),
        "{e}"
    );
}

/// Set in the child process of `thousands_of_panics_print_nothing`.
const PANIC_CHILD: &str = "FORMSIM_TEST_PANIC_CHILD";

/// The child's work: 10 000 `critical_shear` calls that panic in the plugin,
/// each one caught; prints one line at the end.
#[test]
fn panicking_child() {
    if std::env::var_os(PANIC_CHILD).is_none() {
        return;
    }
    let lib = PluginLibrary::open(&plugins().1).expect("open test-panicky");
    let law = lib
        .build_dynamic(&Params::new().with("panic_above_p", 1.0))
        .unwrap();
    let failed = (0..10_000)
        .filter(|i| {
            law.critical_shear(&inputs(2.0 + f64::from(*i), 0.0))
                .tau
                .is_nan()
        })
        .count();
    println!("failed {failed}");
}

/// A plugin that panics at every call does not flood standard error: the
/// plugin's panic hook stays silent for the panics its shims catch (all
/// 10 000 of them here). The calls run in a child
/// process (this test binary, filtered to `panicking_child`), whose whole
/// standard error is counted.
#[test]
fn thousands_of_panics_print_nothing() {
    plugins();
    let out = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "panicking_child",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(PANIC_CHILD, "1")
        .output()
        .expect("run the child");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("failed 10000"), "{stdout}");
    assert!(
        stderr.lines().count() < 20 && !stderr.contains("panicked"),
        "{} lines of stderr: {}",
        stderr.lines().count(),
        stderr.chars().take(2000).collect::<String>()
    );
}
