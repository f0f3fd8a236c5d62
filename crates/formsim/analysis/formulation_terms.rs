//! Where the kinematic formulations differ on a forming scene
//! (docs/s-rail.md, "Why the formulations agree").
//!
//! Runs the scene once per formulation (convective, jaumann, lagrangian,
//! updated-lagrangian), every contact pair recording its friction stage
//! (`contact::ContactPair::record_friction`, which changes no bit of the
//! run). In the convective run, at every step and every touching point
//! that has a history `t_n`, it applies all four formulations' transports
//! to the very `t_n` and step kinematics the run saw and measures, in MPa:
//!
//! - `|t_n|`, the history traction, and `k_t |P Δu|`, the slip increment's
//!   term of the trial traction `t_tr = t* − k_t P Δu`;
//! - `|t*_c − t_n|`: how far convective's own transport (the normal's turn)
//!   moves the history;
//! - `|t*_f − t*_c|` for f = jaumann, lagrangian, updated-lagrangian: what
//!   the formulation's spin or frame rotation adds over convective's, also
//!   relative to `|t_n|` (≈ the angle in rad) and to `k_t |P Δu|`;
//! - the angle between the trial tractions of f and convective (deg): the
//!   direction a slipping point ends the step with.
//!
//! Points are grouped by pair and region: `arc-radius` (on a shoulder or
//! wall, `|n_z| < 0.98`, inside one of the S-rail's two arc sectors),
//! `straight-radius` (a shoulder or wall elsewhere) and `flat`. At the
//! report strokes it keeps each run's tractions and compares the four runs
//! point by point (angle between the tractions of f and convective at the
//! points touching on the arcs in both).
//!
//! Run (release; about 2 minutes for the S-rail medium mesh on 2 threads):
//!
//! ```text
//! cargo run --release -p formsim --example formulation_terms -- scenes/s-rail.toml
//! ```
//!
//! Options: `--set KEY=VALUE` (repeatable, as `formsim run`), `--strokes
//! 10,20,30,38` (mm of the stroke tool), `--k-t 1e5` (MPa/mm, the law's
//! stick stiffness), `--control KEY=VALUE`: a fifth run, convective with
//! that change too (e.g. `contact.params.ac.k_t=100000.1`, a perturbation
//! far below anything physical), compared like the others: the floor of
//! run-to-run differences of the tractions on this scene. The arc sectors are those of the S-rail reconstruction
//! (docs/s-rail.md): arc 1 about (60, 80), −90° to −60°; arc 2 about
//! (183.30, −33.56), 90° to 120°.

use std::collections::HashMap;
use std::path::PathBuf;

use contact::{ContactEffect, PointStatus};
use friction_laws::formulations::{Convective, Jaumann, Lagrangian, UpdatedLagrangian};
use plugins_api::{KinematicFormulation, Vec3};

const FORMULATIONS: [&str; 4] = ["convective", "jaumann", "lagrangian", "updated-lagrangian"];

/// A running summary of non-negative values: count, mean, max and
/// quantiles from a histogram of 40 bins per decade between 1e-14 and 1e6.
#[derive(Clone)]
struct Stat {
    n: u64,
    sum: f64,
    max: f64,
    zeros: u64,
    bins: Vec<u64>,
}

impl Stat {
    const PER_DECADE: f64 = 40.0;
    const LO: f64 = -14.0;
    const DECADES: f64 = 20.0;

    fn new() -> Self {
        Self {
            n: 0,
            sum: 0.0,
            max: 0.0,
            zeros: 0,
            bins: vec![0; (Self::PER_DECADE * Self::DECADES) as usize],
        }
    }

    fn add(&mut self, v: f64) {
        if !v.is_finite() {
            return;
        }
        self.n += 1;
        self.sum += v;
        self.max = self.max.max(v);
        if v <= 0.0 {
            self.zeros += 1;
            return;
        }
        let b = ((v.log10() - Self::LO) * Self::PER_DECADE).floor();
        let b = (b.max(0.0) as usize).min(self.bins.len() - 1);
        self.bins[b] += 1;
    }

    fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }

    /// The `q` quantile (bin centre; 6 % wide bins).
    fn quantile(&self, q: f64) -> f64 {
        if self.n == 0 {
            return 0.0;
        }
        let target = (q * self.n as f64).ceil() as u64;
        let mut seen = self.zeros;
        if seen >= target {
            return 0.0;
        }
        for (i, &c) in self.bins.iter().enumerate() {
            seen += c;
            if seen >= target {
                return 10f64.powf(Self::LO + (i as f64 + 0.5) / Self::PER_DECADE);
            }
        }
        self.max
    }

    fn line(&self, what: &str, unit: &str) -> String {
        format!(
            "    {what:<44} median {:>9.3e}  p90 {:>9.3e}  p99 {:>9.3e}  max {:>9.3e}  mean {:>9.3e} {unit}",
            self.quantile(0.5),
            self.quantile(0.9),
            self.quantile(0.99),
            self.max,
            self.mean()
        )
    }
}

/// The per-step terms of one group of points.
struct Terms {
    points: u64,
    slipping: u64,
    t_hist: Stat,
    slip_term: Stat,
    conv_turn: Stat,
    spin_angle: Stat,
    diff: [Stat; 3],
    diff_rel: [Stat; 3],
    diff_to_slip: [Stat; 3],
    trial_angle: [Stat; 3],
}

impl Terms {
    fn new() -> Self {
        let s = Stat::new;
        Self {
            points: 0,
            slipping: 0,
            t_hist: s(),
            slip_term: s(),
            conv_turn: s(),
            spin_angle: s(),
            diff: [s(), s(), s()],
            diff_rel: [s(), s(), s()],
            diff_to_slip: [s(), s(), s()],
            trial_angle: [s(), s(), s()],
        }
    }
}

/// Angle (deg) between two vectors; 0 when either is zero.
fn angle_deg(a: &Vec3, b: &Vec3) -> f64 {
    let (na, nb) = (a.norm(), b.norm());
    if na == 0.0 || nb == 0.0 {
        return 0.0;
    }
    a.cross(b).norm().atan2(a.dot(b)).to_degrees()
}

/// Whether the plan position `x` lies in one of the S-rail's arc sectors.
fn on_arc(x: &Vec3) -> bool {
    let sector = |c: (f64, f64), a0: f64, a1: f64| {
        let a = (x.y - c.1).atan2(x.x - c.0).to_degrees();
        a >= a0 && a <= a1
    };
    sector((60.0, 80.0), -90.0, -60.0) || sector((183.30, -33.56), 90.0, 120.0)
}

fn region(x: &Vec3, n: &Vec3) -> &'static str {
    if n.z.abs() >= 0.98 {
        "flat"
    } else if on_arc(x) {
        "arc-radius"
    } else {
        "straight-radius"
    }
}

/// Per report stroke, per pair name: node → (traction, normal) of the
/// points touching on the arcs' radii.
type Snapshot = HashMap<(usize, String), HashMap<u32, (Vec3, Vec3)>>;

struct Options {
    scene: PathBuf,
    sets: Vec<String>,
    strokes: Vec<f64>,
    k_t: f64,
    control: Option<String>,
}

fn options() -> Result<Options, String> {
    let mut args = std::env::args().skip(1);
    let mut o = Options {
        scene: PathBuf::new(),
        sets: Vec::new(),
        strokes: vec![10.0, 20.0, 30.0, 38.0],
        k_t: friction_laws::laws::DEFAULT_STICK_STIFFNESS,
        control: None,
    };
    let mut scene = None;
    while let Some(a) = args.next() {
        let mut value = |name: &str| args.next().ok_or(format!("{name}: a value is missing"));
        match a.as_str() {
            "--set" => o.sets.push(value("--set")?),
            "--control" => o.control = Some(value("--control")?),
            "--strokes" => {
                o.strokes = value("--strokes")?
                    .split(',')
                    .map(|s| s.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|e| format!("--strokes: {e}"))?;
            }
            "--k-t" => {
                o.k_t = value("--k-t")?.parse().map_err(|e| format!("--k-t: {e}"))?;
                if !(o.k_t.is_finite() && o.k_t > 0.0) {
                    return Err(format!("--k-t: {}: must be > 0 (MPa/mm)", o.k_t));
                }
            }
            s if s.starts_with("--") => return Err(format!("unknown option {s}")),
            s => scene = Some(PathBuf::from(s)),
        }
    }
    o.scene = scene
        .ok_or("usage: formulation_terms SCENE [--set K=V]... [--strokes 10,20] [--k-t 1e5]")?;
    Ok(o)
}

/// Run the scene with `formulation`; with `terms`, measure the per-step
/// terms. Returns the snapshots at the report strokes and the run's
/// summary figures (friction energy, mJ; wall s).
fn run(
    o: &Options,
    formulation: &str,
    extra: Option<&str>,
    mut terms: Option<&mut HashMap<(String, &'static str), Terms>>,
) -> Result<(Snapshot, f64, f64), String> {
    let mut sets = o.sets.clone();
    sets.push(format!("contact.formulation={formulation}"));
    sets.extend(extra.map(str::to_string));
    let loaded = formsim::scene::load(&o.scene, &sets).map_err(|e| e.to_string())?;
    let mut model = formsim::scene::build(&loaded).map_err(|e| e.to_string())?;
    let id = model.contact.ok_or("the scene has no contact")?;
    let stroke_tool = model
        .stroke
        .ok_or("the scene names no output.stroke_tool")?;
    {
        let c: &mut ContactEffect = model.solver.effect_mut(id).expect("contact effect");
        for i in 0..c.pairs().len() {
            c.record_friction(i, true).map_err(|e| e.to_string())?;
        }
    }
    let transports: [&dyn KinematicFormulation; 4] =
        [&Convective, &Jaumann, &Lagrangian, &UpdatedLagrangian];
    let mut snapshot = Snapshot::new();
    let mut next = 0;
    let started = std::time::Instant::now();
    let end = model.end_time;
    while model.solver.time() < end {
        model.solver.step_toward(end).map_err(|e| e.to_string())?;
        let c = model.contact().expect("contact effect");
        let stroke = model.press().map_or(0.0, |p| {
            p.displacement(stroke_tool.index)
                .dot(&stroke_tool.direction)
        });
        let x = &model.solver.state().x;
        let snap = next < o.strokes.len() && stroke >= o.strokes[next] - 1e-9;
        for p in c.pairs() {
            let name = p.name().to_string();
            let r = p.friction_record().expect("recording");
            if snap {
                let mut m = HashMap::new();
                for (i, &pk) in r.points.iter().enumerate() {
                    let node = p.nodes()[pk as usize];
                    let n = r.inputs[i].kin.n_new;
                    if region(&x[node as usize], &n) == "arc-radius"
                        && p.status[pk as usize] != PointStatus::Open
                    {
                        m.insert(node, (r.outputs[i].t, n));
                    }
                }
                snapshot.insert((next, name.clone()), m);
            }
            let Some(terms) = terms.as_deref_mut() else {
                continue;
            };
            for (i, &pk) in r.points.iter().enumerate() {
                let (h, input, out) = (&r.history[i], &r.inputs[i], &r.outputs[i]);
                let t_n = h.t;
                if t_n.norm() == 0.0 {
                    continue;
                }
                let kin = &input.kin;
                let n = kin.n_new;
                let node = p.nodes()[pk as usize];
                let g = terms
                    .entry((name.clone(), region(&x[node as usize], &n)))
                    .or_insert_with(Terms::new);
                let tangent = |v: Vec3| v - n * n.dot(&v);
                let star: Vec<Vec3> = transports
                    .iter()
                    .map(|f| tangent(f.transport(&t_n, kin)))
                    .collect();
                let slip = tangent(input.du) * o.k_t;
                g.points += 1;
                g.slipping += u64::from(!out.stick);
                g.t_hist.add(t_n.norm());
                g.slip_term.add(slip.norm());
                g.conv_turn.add((star[0] - t_n).norm());
                g.spin_angle
                    .add(plugins_api::kinematics::axial(&kin.vel_grad).dot(&n).abs() * kin.dt);
                let trial_c = star[0] - slip;
                for f in 0..3 {
                    let d = (star[f + 1] - star[0]).norm();
                    g.diff[f].add(d);
                    g.diff_rel[f].add(d / t_n.norm());
                    if slip.norm() > 0.0 {
                        g.diff_to_slip[f].add(d / slip.norm());
                    }
                    g.trial_angle[f].add(angle_deg(&(star[f + 1] - slip), &trial_c));
                }
            }
        }
        if snap {
            next += 1;
        }
    }
    Ok((
        snapshot,
        model.solver.ledger().friction,
        started.elapsed().as_secs_f64(),
    ))
}

fn main() {
    let o = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let mut terms = HashMap::new();
    let mut snaps = Vec::new();
    let mut names: Vec<String> = FORMULATIONS.iter().map(|s| s.to_string()).collect();
    let mut runs: Vec<(&str, Option<&str>)> = FORMULATIONS.iter().map(|f| (*f, None)).collect();
    if let Some(c) = &o.control {
        runs.push(("convective", Some(c.as_str())));
        names.push(format!("convective + {c}"));
    }
    for (k, (f, extra)) in runs.iter().enumerate() {
        let t = (k == 0).then_some(&mut terms);
        match run(&o, f, *extra, t) {
            Ok((s, friction, wall)) => {
                println!(
                    "{}: friction energy {:.1} J, {wall:.1} s",
                    names[k],
                    friction * 1e-3
                );
                snaps.push(s);
            }
            Err(e) => {
                eprintln!("error: {f}: {e}");
                std::process::exit(1);
            }
        }
    }
    println!(
        "\nPer-step terms at touching points with a history, in the convective run \
         (k_t = {:.3e} MPa/mm); the formulations' transports applied to the same t_n and kinematics:",
        o.k_t
    );
    let mut keys: Vec<_> = terms.keys().cloned().collect();
    keys.sort();
    for key in keys {
        let g = &terms[&key];
        println!(
            "\n  pair {}, {}: {} point-steps, {:.1} % slipping",
            key.0,
            key.1,
            g.points,
            100.0 * g.slipping as f64 / g.points.max(1) as f64
        );
        println!("{}", g.t_hist.line("|t_n|", "MPa"));
        println!("{}", g.slip_term.line("k_t |P du|", "MPa"));
        println!(
            "{}",
            g.conv_turn
                .line("|t*_conv - t_n| (the normal's turn)", "MPa")
        );
        println!(
            "{}",
            g.spin_angle
                .line("|w.n| dt (blank spin about n per step)", "rad")
        );
        for (f, name) in FORMULATIONS[1..].iter().enumerate() {
            println!(
                "{}",
                g.diff[f].line(&format!("|t*_{name} - t*_conv|"), "MPa")
            );
            println!("{}", g.diff_rel[f].line("  / |t_n|", "-"));
            println!("{}", g.diff_to_slip[f].line("  / k_t |P du|", "-"));
            println!("{}", g.trial_angle[f].line("  angle of the trials", "deg"));
        }
    }
    println!(
        "\nTraction direction against convective's, same node, points touching on the arcs' radii in both runs:"
    );
    for (si, s) in o.strokes.iter().enumerate() {
        let Some(conv) = snaps.first() else { break };
        let mut pairs: Vec<_> = conv
            .keys()
            .filter(|k| k.0 == si)
            .map(|k| k.1.clone())
            .collect();
        pairs.sort();
        for pair in pairs {
            let base = &conv[&(si, pair.clone())];
            if base.is_empty() {
                continue;
            }
            for (f, snap) in snaps.iter().enumerate().skip(1) {
                let Some(other) = snap.get(&(si, pair.clone())) else {
                    continue;
                };
                let (mut angle, mut mag) = (Stat::new(), Stat::new());
                let mut both = 0;
                for (node, (t, _)) in base {
                    if let Some((u, _)) = other.get(node)
                        && t.norm() > 0.0
                        && u.norm() > 0.0
                    {
                        both += 1;
                        angle.add(angle_deg(t, u));
                        mag.add((u.norm() - t.norm()).abs() / t.norm());
                    }
                }
                println!(
                    "  stroke {s} mm, pair {pair}, {}: {both} points (convective {}, {} {}); angle median {:.2e} p90 {:.2e} max {:.2e} deg; |t| rel. diff median {:.2e} max {:.2e}",
                    names[f],
                    base.len(),
                    names[f],
                    other.len(),
                    angle.quantile(0.5),
                    angle.quantile(0.9),
                    angle.max,
                    mag.quantile(0.5),
                    mag.max
                );
            }
        }
    }
}
