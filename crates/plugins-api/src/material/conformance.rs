//! The conformance suite of a user material, at point level, through the
//! same table calls the engine makes ([`DynamicMaterial::update`]).
//!
//! Scales: `E`, `ν` as the material reports them, `σ_0` its initial flow
//! stress, `ε_y = σ_0/E`. The checks, in report order ([`CHECKS`]):
//!
//! 1. `elastic`: from a virgin point, increments of `0.1 ε_y` (uniaxial
//!    stress, equibiaxial, shear) give plane-stress Hooke's law with the
//!    reported `E`, `ν` (relative 1e-9), `Δε_zz = -ν/(1-ν)(Δε_xx+Δε_yy)`,
//!    no dissipation.
//! 2. `yield-surface`: along uniaxial tension in x (σ_yy = 0 held by
//!    iterating Δε_yy) to `6 ε_y`, `σ_xx` equals the reported flow stress after
//!    every plastic step (relative 1e-6: the contract's definition of the
//!    flow stress); after uniaxial, equibiaxial and shear loading the point
//!    is on its surface: a small reversed increment is elastic (Hooke,
//!    relative 1e-6, no dissipation) and a small further one dissipates.
//! 3. `incompressibility`: in every step of those paths the volume change is
//!    the elastic one, `Δε_xx+Δε_yy+Δε_zz = (1-2ν)/E (Δσ_xx+Δσ_yy)` (to 1e-6
//!    of the increment).
//! 4. `rotation`: a zero increment (what the co-rotational frame sees of a
//!    rigid rotation) leaves the stress and the state unchanged with no
//!    dissipation; for a material that declares itself isotropic, a loading
//!    history turned by 30° and 90° gives the turned stresses, the same
//!    plastic strain and dissipation (relative 1e-8).
//! 5. `dissipation`: ≥ 0 (to round-off) in every step of every path,
//!    including 200 random increments.
//! 6. `edge-cases`: a huge increment (30 % strain in one step), a tiny one
//!    (1e-14 ε_y) and a zero one from a virgin point give finite results.
//! 7. `non-finite-input`: NaN or infinity in the increment, the stress or the
//!    state is refused with an error, not a panic, leaving the point unchanged.
//! 8. `determinism`: the random history twice gives bitwise identical results.
//! 9. `batch`: eight points in one call give, bit for bit, what eight single
//!    calls give.
//!
//! A panic inside the plugin is caught in the plugin and reported as the
//! failure of the check that was running, with its message and location;
//! the suite itself never panics on a misbehaving material.

use std::cell::OnceCell;
use std::fmt;

use super::PointResult;
use super::loader::DynamicMaterial;

/// Names of the checks, in report order.
pub const CHECKS: [&str; 9] = [
    "elastic",
    "yield-surface",
    "incompressibility",
    "rotation",
    "dissipation",
    "edge-cases",
    "non-finite-input",
    "determinism",
    "batch",
];

/// The outcome of one check.
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialCheck {
    /// One of [`CHECKS`].
    pub check: &'static str,
    /// Whether it passed.
    pub passed: bool,
    /// What was checked and, on failure, the first violation with its values.
    pub detail: String,
}

/// All results of [`check_material`].
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialReport {
    /// The material under test.
    pub subject: String,
    /// One result per check, in the order of [`CHECKS`].
    pub results: Vec<MaterialCheck>,
}

impl MaterialReport {
    /// Whether every check passed.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.results.iter().all(|r| r.passed)
    }
}

impl fmt::Display for MaterialReport {
    /// One line per check (`PASS`/`FAIL`, check, detail), then `N passed,
    /// M failed`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows = self.results.iter();
        let rows = rows.map(|r| (r.passed, format!("{:<18} {}", r.check, r.detail)));
        let title = format!("conformance of `{}` (docs/materials.md)", self.subject);
        crate::conformance::write_report(f, &title, rows)
    }
}

/// Run the suite on `material`. Never panics on a misbehaving material.
#[must_use]
pub fn check_material(material: &DynamicMaterial) -> MaterialReport {
    let subject = format!("{} ({})", material.name(), material.path());
    let results = match Probe::new(material) {
        Ok(probe) => {
            let checks: [fn(&Probe<'_>) -> Outcome; 9] = [
                elastic,
                yield_surface,
                incompressibility,
                rotation,
                dissipation,
                edge_cases,
                non_finite_input,
                determinism,
                batch,
            ];
            CHECKS
                .iter()
                .zip(checks)
                .map(|(check, run)| verdict(check, run(&probe)))
                .collect()
        }
        Err(why) => CHECKS
            .iter()
            .map(|check| verdict(check, Err(format!("not run: {why}"))))
            .collect(),
    };
    MaterialReport { subject, results }
}

fn verdict(check: &'static str, outcome: Outcome) -> MaterialCheck {
    let (passed, detail) = match outcome {
        Ok(d) => (true, d),
        Err(d) => (false, d),
    };
    MaterialCheck {
        check,
        passed,
        detail,
    }
}

/// `Ok(what was checked)` or `Err(the first violation)`.
type Outcome = Result<String, String>;

/// One point's stress and state.
#[derive(Clone, Debug, PartialEq)]
struct Point {
    s: [f64; 3],
    state: Vec<f64>,
}

/// The material and its scales.
struct Probe<'a> {
    m: &'a DynamicMaterial,
    young: f64,
    nu: f64,
    sigma0: f64,
    virgin: Point,
    /// The three loading paths of [`Probe::paths`], run once for the checks
    /// that read them.
    runs: OnceCell<Result<Vec<Vec<Step>>, String>>,
}

impl<'a> Probe<'a> {
    fn new(m: &'a DynamicMaterial) -> Result<Self, String> {
        let mut state = vec![0.0; m.n_state()];
        let sigma0 = m.initial_state(&mut state).map_err(|e| e.to_string())?;
        let e = m.elastic();
        Ok(Self {
            m,
            young: e.young,
            nu: e.poisson,
            sigma0,
            virgin: Point { s: [0.0; 3], state },
            runs: OnceCell::new(),
        })
    }

    fn eps_y(&self) -> f64 {
        self.sigma0 / self.young
    }

    /// One step of one point.
    fn step(&self, p: &Point, deps: [f64; 3]) -> Result<(Point, PointResult), String> {
        let mut q = p.clone();
        let mut r = [PointResult::default()];
        self.m
            .update(
                &[deps],
                std::slice::from_mut(&mut q.s),
                &mut q.state,
                &mut r,
            )
            .map_err(|e| e.to_string())?;
        Ok((q, r[0]))
    }

    /// One step of uniaxial stress along x: Δε_yy found (secant) so that
    /// σ_yy = 0 to 1e-10 σ_0, Δγ = 0. Returns the increment used.
    fn uniaxial(&self, p: &Point, dx: f64) -> Result<(Point, PointResult, [f64; 3]), String> {
        let tol = 1e-10 * self.sigma0;
        let mut a = -self.nu * dx;
        let (mut pa, mut ra) = self.step(p, [dx, a, 0.0])?;
        let mut b = -0.5 * dx;
        for _ in 0..60 {
            if pa.s[1].abs() <= tol {
                return Ok((pa, ra, [dx, a, 0.0]));
            }
            let (pb, rb) = self.step(p, [dx, b, 0.0])?;
            let slope = (pb.s[1] - pa.s[1]) / (b - a);
            let next = if slope.is_finite() && slope != 0.0 {
                b - pb.s[1] / slope
            } else {
                0.5 * (a + b)
            };
            (a, pa, ra) = (b, pb, rb);
            b = next;
        }
        Err(format!(
            "could not hold σ_yy = 0 under Δε_xx = {dx:e} (σ_yy = {:e} MPa after 60 secant steps)",
            pa.s[1]
        ))
    }

    /// Plane-stress Hooke's law of an increment.
    fn hooke(&self, d: [f64; 3]) -> [f64; 3] {
        let c = self.young / (1.0 - self.nu * self.nu);
        let g = self.young / (2.0 * (1.0 + self.nu));
        [
            c * (d[0] + self.nu * d[1]),
            c * (d[1] + self.nu * d[0]),
            g * d[2],
        ]
    }

    /// The loading paths used by several checks: (name, increment, steps);
    /// `uniaxial` holds σ_yy = 0.
    fn paths(&self) -> [(&'static str, [f64; 3], usize); 3] {
        let e = 0.2 * self.eps_y();
        [
            ("uniaxial", [e, 0.0, 0.0], 30),
            ("equibiaxial", [e, e, 0.0], 30),
            ("shear", [0.0, 0.0, 2.0 * e], 30),
        ]
    }

    /// The runs of the three loading paths ([`Probe::paths`], in order),
    /// computed the first time a check asks.
    fn runs(&self) -> Result<&[Vec<Step>], String> {
        self.runs
            .get_or_init(|| {
                self.paths()
                    .iter()
                    .map(|&(name, inc, steps)| self.run_path(inc, steps, name == "uniaxial"))
                    .collect()
            })
            .as_deref()
            .map_err(Clone::clone)
    }

    /// Run a path from a virgin point; every step's (before, after, increment, result).
    fn run_path(&self, inc: [f64; 3], steps: usize, uniaxial: bool) -> Result<Vec<Step>, String> {
        let mut p = self.virgin.clone();
        let mut out = Vec::with_capacity(steps);
        for _ in 0..steps {
            let (q, r, d) = if uniaxial {
                self.uniaxial(&p, inc[0])?
            } else {
                let (q, r) = self.step(&p, inc)?;
                (q, r, inc)
            };
            out.push(Step {
                before: p,
                after: q.clone(),
                deps: d,
                r,
            });
            p = q;
        }
        Ok(out)
    }

    /// A reproducible random history of `n` increments (up to `ε_y` each).
    fn random_increments(&self, seed: u64, n: usize) -> Vec<[f64; 3]> {
        let mut x = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        let mut next = move || {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let e = self.eps_y();
        (0..n)
            .map(|_| [next() * e, next() * e, next() * e])
            .collect()
    }
}

/// One step of a path.
struct Step {
    before: Point,
    after: Point,
    deps: [f64; 3],
    r: PointResult,
}

fn rel(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}

fn elastic(p: &Probe<'_>) -> Outcome {
    let e = 0.1 * p.eps_y();
    let cases = [
        ("uniaxial stress", [e, -p.nu * e, 0.0]),
        ("equibiaxial", [e, e, 0.0]),
        ("shear", [0.0, 0.0, 2.0 * e]),
    ];
    for (name, d) in cases {
        let (q, r) = p.step(&p.virgin, d)?;
        let want = p.hooke(d);
        let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let dzz = -p.nu / (1.0 - p.nu) * (d[0] + d[1]);
        for c in 0..3 {
            if rel(q.s[c], want[c], scale) > 1e-9 {
                return Err(format!(
                    "{name} increment {d:?}: σ = {:?} MPa, Hooke's law with the reported E = {} MPa, ν = {} gives {want:?}",
                    q.s, p.young, p.nu
                ));
            }
        }
        if rel(r.deps_zz, dzz, e) > 1e-9 || r.dissipation.abs() > 1e-12 * p.sigma0 * e {
            return Err(format!(
                "{name} increment {d:?}: Δε_zz = {:e} (elastic: {dzz:e}), dissipation {:e} MPa (elastic: 0)",
                r.deps_zz, r.dissipation
            ));
        }
    }
    Ok(format!(
        "plane-stress Hooke's law, E = {} MPa, ν = {}, to 1e-9 (uniaxial, equibiaxial, shear at 0.1 σ_0/E)",
        p.young, p.nu
    ))
}

fn yield_surface(p: &Probe<'_>) -> Outcome {
    let runs = p.runs()?;
    let path = &runs[0];
    let mut plastic = 0;
    for (k, s) in path.iter().enumerate() {
        if s.r.dissipation > 0.0 {
            plastic += 1;
            if rel(s.after.s[0], s.r.flow_stress, s.r.flow_stress) > 1e-6 {
                return Err(format!(
                    "uniaxial tension, step {k}: σ_xx = {} MPa but the reported flow stress is {} MPa",
                    s.after.s[0], s.r.flow_stress
                ));
            }
        }
    }
    if plastic == 0 {
        return Err("uniaxial tension to 6 σ_0/E never yielded (no dissipation)".into());
    }
    let small = 0.01 * p.eps_y();
    for ((name, inc, _), at) in p.paths().into_iter().zip(runs) {
        let end = &at[at.len() - 1].after;
        let norm = inc.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let d = inc.map(|x| x / norm * small);
        let back = d.map(|x| -x);
        let (q, r) = p.step(end, back)?;
        let want = p.hooke(back);
        let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if (0..3).any(|c| rel(q.s[c] - end.s[c], want[c], scale) > 1e-6) || r.dissipation > 0.0 {
            return Err(format!(
                "{name}: a small reversed increment {back:?} after loading is not elastic (Δσ = {:?} MPa, Hooke: {want:?}; dissipation {:e})",
                [q.s[0] - end.s[0], q.s[1] - end.s[1], q.s[2] - end.s[2]],
                r.dissipation
            ));
        }
        let (_, r) = p.step(end, d)?;
        if r.dissipation <= 0.0 {
            return Err(format!(
                "{name}: a small further increment {d:?} after loading does not dissipate: the point is inside its yield surface"
            ));
        }
    }
    Ok(format!(
        "σ_xx = flow stress to 1e-6 in {plastic} plastic uniaxial steps; on the surface after uniaxial, equibiaxial and shear loading"
    ))
}

fn incompressibility(p: &Probe<'_>) -> Outcome {
    let c = (1.0 - 2.0 * p.nu) / p.young;
    let mut n = 0;
    for ((name, _, _), run) in p.paths().into_iter().zip(p.runs()?) {
        for (k, s) in run.iter().enumerate() {
            let d = s.deps;
            let vol = d[0] + d[1] + s.r.deps_zz;
            let elastic = c * (s.after.s[0] - s.before.s[0] + s.after.s[1] - s.before.s[1]);
            let size = d.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            if (vol - elastic).abs() > 1e-6 * size {
                return Err(format!(
                    "{name}, step {k}: volume change {vol:e} but the elastic part is {elastic:e} (increment {d:?}, Δε_zz = {:e})",
                    s.r.deps_zz
                ));
            }
            n += usize::from(s.r.dissipation > 0.0);
        }
    }
    Ok(format!(
        "volume change elastic to 1e-6 of the increment in {n} plastic steps"
    ))
}

/// `[ε_xx, ε_yy, γ_xy]` or `[σ_xx, σ_yy, σ_xy]` (`shear_factor` 2 or 1 for
/// engineering or tensor shear) turned by `angle` in the plane.
fn turn(v: [f64; 3], angle: f64, shear_factor: f64) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let xy = v[2] / shear_factor;
    let xx = c * c * v[0] + s * s * v[1] - 2.0 * s * c * xy;
    let yy = s * s * v[0] + c * c * v[1] + 2.0 * s * c * xy;
    let sxy = s * c * (v[0] - v[1]) + (c * c - s * s) * xy;
    [xx, yy, shear_factor * sxy]
}

fn rotation(p: &Probe<'_>) -> Outcome {
    let loaded = &p.runs()?[0];
    let end = &loaded[loaded.len() - 1].after;
    let (q, r) = p.step(end, [0.0; 3])?;
    let moved = (0..3).any(|c| rel(q.s[c], end.s[c], p.sigma0) > 1e-9)
        || q.state
            .iter()
            .zip(&end.state)
            .any(|(a, b)| (a - b).abs() > 1e-9 * (1.0 + b.abs()));
    if moved || r.dissipation.abs() > 1e-12 * p.sigma0 {
        return Err(format!(
            "a zero increment (a rigid rotation, as the co-rotational frame sees it) changed the point: σ {:?} → {:?} MPa, dissipation {:e}",
            end.s, q.s, r.dissipation
        ));
    }
    if !p.m.isotropic() {
        return Ok("zero increment changes nothing; turned histories not checked: the plugin declares an anisotropic response".into());
    }
    let e = 0.2 * p.eps_y();
    let inc = [e, -0.3 * e, 0.7 * e];
    let reference = p.run_path(inc, 25, false)?;
    let last = &reference[reference.len() - 1];
    let work: f64 = reference.iter().map(|s| s.r.dissipation).sum();
    for deg in [30.0_f64, 90.0] {
        let a = deg.to_radians();
        let turned = p.run_path(turn(inc, a, 2.0), 25, false)?;
        let t = &turned[turned.len() - 1];
        let want = turn(last.after.s, a, 1.0);
        let w: f64 = turned.iter().map(|s| s.r.dissipation).sum();
        if (0..3).any(|c| rel(t.after.s[c], want[c], p.sigma0) > 1e-8)
            || rel(w, work, work.abs().max(1e-300)) > 1e-8
            || rel(
                t.r.plastic_strain,
                last.r.plastic_strain,
                last.r.plastic_strain.max(1e-300),
            ) > 1e-8
        {
            return Err(format!(
                "a history turned by {deg}°: σ = {:?} MPa, the turned reference {want:?}; dissipation {w:e} vs {work:e}; plastic strain {:e} vs {:e}",
                t.after.s, t.r.plastic_strain, last.r.plastic_strain
            ));
        }
    }
    Ok("zero increment changes nothing; histories turned by 30° and 90° give turned stresses, same dissipation and plastic strain (1e-8)".into())
}

fn dissipation(p: &Probe<'_>) -> Outcome {
    let mut steps = 0;
    let mut check = |name: &str, k: usize, s: &Step| {
        steps += 1;
        let size = s.deps.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if s.r.dissipation < -1e-12 * p.sigma0 * size {
            return Err(format!(
                "{name}, step {k}: dissipation {:e} MPa < 0 (increment {:?})",
                s.r.dissipation, s.deps
            ));
        }
        Ok(())
    };
    for ((name, _, _), run) in p.paths().into_iter().zip(p.runs()?) {
        for (k, s) in run.iter().enumerate() {
            check(name, k, s)?;
        }
    }
    let mut pt = p.virgin.clone();
    for (k, d) in p.random_increments(1, 200).into_iter().enumerate() {
        let (q, r) = p.step(&pt, d)?;
        let s = Step {
            before: pt,
            after: q.clone(),
            deps: d,
            r,
        };
        check("random history", k, &s)?;
        pt = q;
    }
    Ok(format!(
        "≥ 0 in {steps} steps (three loading paths and 200 random increments)"
    ))
}

fn edge_cases(p: &Probe<'_>) -> Outcome {
    let cases = [
        ("a huge increment", [0.3, -0.15, 0.1]),
        ("a tiny increment", [1e-14 * p.eps_y(), 0.0, 0.0]),
        ("a zero increment", [0.0; 3]),
    ];
    for (name, d) in cases {
        let (q, r) = p
            .step(&p.virgin, d)
            .map_err(|e| format!("{name} {d:?}: {e}"))?;
        if name == "a zero increment" && (q != p.virgin || r.dissipation != 0.0) {
            return Err(format!(
                "a zero increment from a virgin point changed it: σ = {:?} MPa, dissipation {:e}",
                q.s, r.dissipation
            ));
        }
    }
    Ok("finite results for a 30 % strain step, a 1e-14 ε_y step and a zero step".into())
}

fn non_finite_input(p: &Probe<'_>) -> Outcome {
    let base = p.virgin.clone();
    let d = [0.1 * p.eps_y(), 0.0, 0.0];
    let mut cases: Vec<(&str, [f64; 3], Point)> = vec![
        ("NaN in Δε_xx", [f64::NAN, 0.0, 0.0], base.clone()),
        ("+∞ in Δγ_xy", [0.0, 0.0, f64::INFINITY], base.clone()),
    ];
    let mut bad_stress = base.clone();
    bad_stress.s[1] = f64::NAN;
    cases.push(("NaN in σ_yy", d, bad_stress));
    if !base.state.is_empty() {
        let mut bad_state = base.clone();
        bad_state.state[0] = f64::NAN;
        cases.push(("NaN in state[0]", d, bad_state));
    }
    for (name, deps, pt) in &cases {
        let mut q = pt.clone();
        let mut r = [PointResult::default()];
        let result = p.m.update(
            &[*deps],
            std::slice::from_mut(&mut q.s),
            &mut q.state,
            &mut r,
        );
        match result {
            Ok(()) => {
                return Err(format!(
                    "{name}: accepted (σ = {:?} MPa); it must be refused with an error",
                    q.s
                ));
            }
            Err(e) if e.to_string().contains("panicked") => {
                return Err(format!(
                    "{name}: the plugin panicked instead of refusing: {e}"
                ));
            }
            Err(_) => {
                let same =
                    q.s.iter()
                        .zip(&pt.s)
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                        && q.state
                            .iter()
                            .zip(&pt.state)
                            .all(|(a, b)| a.to_bits() == b.to_bits());
                if !same {
                    return Err(format!("{name}: refused, but the point was changed"));
                }
            }
        }
    }
    Ok(format!(
        "{} cases refused with an error, the point unchanged",
        cases.len()
    ))
}

/// The random history from a virgin point: every step's stress, state and result.
fn random_run(p: &Probe<'_>, seed: u64) -> Result<Vec<(Point, PointResult)>, String> {
    let mut pt = p.virgin.clone();
    let mut out = Vec::new();
    for d in p.random_increments(seed, 200) {
        let (q, r) = p.step(&pt, d)?;
        out.push((q.clone(), r));
        pt = q;
    }
    Ok(out)
}

fn bits(run: &[(Point, PointResult)]) -> Vec<u64> {
    run.iter()
        .flat_map(|(q, r)| {
            q.s.iter()
                .chain(&q.state)
                .chain(&[r.deps_zz, r.dissipation, r.plastic_strain, r.flow_stress])
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        })
        .collect()
}

fn determinism(p: &Probe<'_>) -> Outcome {
    let a = bits(&random_run(p, 2)?);
    let b = bits(&random_run(p, 2)?);
    match a.iter().zip(&b).position(|(x, y)| x != y) {
        None => Ok(format!(
            "200 random steps twice: {} values bitwise identical",
            a.len()
        )),
        Some(i) => Err(format!(
            "the same history twice differs at value {i}: {:e} vs {:e}",
            f64::from_bits(a[i]),
            f64::from_bits(b[i])
        )),
    }
}

fn batch(p: &Probe<'_>) -> Outcome {
    const N: usize = 8;
    let k = p.m.n_state();
    let histories: Vec<Vec<[f64; 3]>> = (0..N)
        .map(|i| p.random_increments(10 + i as u64, 40))
        .collect();
    let mut stress = vec![[0.0; 3]; N];
    let mut state: Vec<f64> = (0..N).flat_map(|_| p.virgin.state.clone()).collect();
    let mut single: Vec<Point> = vec![p.virgin.clone(); N];
    for step in 0..40 {
        let deps: Vec<[f64; 3]> = histories.iter().map(|h| h[step]).collect();
        let mut r = [PointResult::default(); N];
        p.m.update(&deps, &mut stress, &mut state, &mut r)
            .map_err(|e| e.to_string())?;
        for i in 0..N {
            let (q, ri) = p.step(&single[i], deps[i])?;
            let same =
                q.s.iter()
                    .zip(&stress[i])
                    .all(|(a, b)| a.to_bits() == b.to_bits())
                    && q.state
                        .iter()
                        .zip(&state[i * k..(i + 1) * k])
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                    && ri == r[i];
            if !same {
                return Err(format!(
                    "step {step}, point {i}: one call of {N} points gives σ = {:?} MPa, a call of its own {:?}",
                    stress[i], q.s
                ));
            }
            single[i] = q;
        }
    }
    Ok(format!(
        "{N} points × 40 steps in batches equal single calls bit for bit"
    ))
}
