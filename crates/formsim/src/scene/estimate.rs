//! What a run of a scene will need — memory, disk for the VTK frames,
//! increments, wall time, mass added by mass scaling — and the guards that
//! refuse a scene whose run cannot be meaningful (docs/scene-format.md,
//! "Guards and estimates").
//!
//! The sizes come from the scene alone (a generated mesh's node and element
//! counts follow from its keys), so that a scene too large for the machine
//! is refused before anything large is allocated; a mesh file is counted
//! once read. The added mass needs the built model ([`added_mass_warnings`]
//! reads its set-up report).

use super::schema::{MeshSpec, Scene, material_model};
use super::{LoadedScene, SceneError};
use fem_core::{Mesh, SetupReport};

/// A mass-scaling step must leave at least this many increments in the
/// shortest press step (without `[[steps]]`: in the run, `solver.end_time`).
/// Larger steps jump over the motions they should follow: 1 s on the 4 ms
/// block on a plane ran one increment and added 5.7e14 % mass. The square
/// cups' shortest step (1e-4 s) takes 200 increments of their 5e-7 s.
pub const MIN_INCREMENTS_PER_STEP: f64 = 100.0;

/// Mass scaling that adds more than this at set-up, in % of the physical
/// mass, is warned about. The shipped square cups (5e-7 s on 1.5 mm shells,
/// and the documented 2.5e-7 s on the 100 × 100 mesh) add 295.6 % (steel)
/// and 304.8 % (aluminium) at set-up, and the steel cup's kinetic energy
/// stays below 4 % of its internal energy while forming; 1000 %
/// (eleven times the mass, a step 3.3 times the stable one) is well beyond
/// them, where inertia starts to shape the result.
pub const ADDED_MASS_WARNING_PERCENT: f64 = 1000.0;

/// Hard cap on the memory of a run (bytes), whatever the machine has:
/// 32 GiB, about ten million shells (the square cup at 3,200 × 3,200).
pub const MEMORY_CAP: f64 = 32.0 * GIB;

/// Memory assumed available (bytes) where `/proc/meminfo` does not give
/// `MemAvailable` (not Linux): 8 GiB.
pub const MEMORY_FALLBACK: f64 = 8.0 * GIB;

/// Hard cap on the VTK frames a run writes (bytes): 64 GiB (the square cup
/// at 2,000 × 2,000 writes its 21 frames in about 19 GiB).
pub const FRAMES_DISK_CAP: f64 = 64.0 * GIB;

/// Longest estimated wall time of a run (s) formsim starts without
/// `--allow-long`: 24 hours. The shipped scenes take seconds to minutes; an
/// estimate of days is nearly always a slip of a key (a mass-scaling step of
/// 1e-15 s, a press step of 1e6 s), so it is refused up front, naming the
/// key, unless the user says the run is meant ([`allow_long_runs`]).
pub const RUN_TIME_MAX_S: f64 = 86_400.0;

/// Set by `--allow-long`: runs longer than [`RUN_TIME_MAX_S`] are accepted.
static ALLOW_LONG: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Accept (or refuse again) runs whose estimate exceeds [`RUN_TIME_MAX_S`]
/// for the rest of the process (`formsim --allow-long`).
pub fn allow_long_runs(allow: bool) {
    ALLOW_LONG.store(allow, std::sync::atomic::Ordering::Relaxed);
}

/// Wall time of one element in one increment (µs), everything included
/// (shells, contact, output), Belytschko–Tsay. Measured with
/// `formsim run scenes/square-cup.toml` (2 threads, the host otherwise
/// idle): 30,200 increments × 2,500 elements in 15.2 s,
/// `element_cycles_per_s` = 4.954e6.
pub const MICROSECONDS_PER_ELEMENT_CYCLE: f64 = 0.20;

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// Memory of the program and the tools, whatever the mesh (bytes; the
/// 4 × 4 cup peaks at 7.8 MB).
const BASE_BYTES: f64 = 8.0e6;
/// Per node: coordinates, state, forces, masses, contact geometry and
/// coupling (bytes).
const NODE_BYTES: f64 = 1100.0;
/// Per node and contact pair: projection, friction state, search arrays (bytes).
const PAIR_NODE_BYTES: f64 = 400.0;
/// Per element, besides its integration points: connectivity, thickness,
/// hourglass, drilling, result slots, contact geometry, output buffers (bytes).
const ELEMENT_BYTES: f64 = 900.0;
/// Per integration point: the stress `[f64; 3]` and the J2 history (bytes).
const POINT_BYTES: f64 = 40.0;
/// One VTK frame, per node and per element (bytes; the 50 × 50 cup's frame
/// is 603 kB).
const FRAME_NODE_BYTES: f64 = 107.0;
/// See [`FRAME_NODE_BYTES`].
const FRAME_ELEMENT_BYTES: f64 = 130.0;

/// Node and element counts of the blank and its smallest element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshSize {
    /// Nodes (a float: an estimate may exceed any integer type).
    pub nodes: f64,
    /// Elements.
    pub elements: f64,
    /// Smallest characteristic length, area / longest side (mm): what the
    /// shells' stable time step is proportional to.
    pub min_length: f64,
}

impl MeshSize {
    /// No mesh (a mesh file not read yet): only the histories count.
    pub const NONE: MeshSize = MeshSize {
        nodes: 0.0,
        elements: 0.0,
        min_length: f64::INFINITY,
    };

    /// The counts of a generated mesh from its keys (`None` for a file):
    /// a rectangle of `nx × ny` has `(nx+1)(ny+1)` nodes and `nx ny`
    /// elements of `min(lx/nx, ly/ny)`; a wrapped strip has three nodes
    /// across and one row per `element_size` along the strip.
    pub fn of_spec(scene: &Scene) -> Option<MeshSize> {
        match &scene.blank.mesh {
            MeshSpec::Rectangle {
                size, divisions, ..
            } => {
                let (nx, ny) = divisions.pair();
                let (nx, ny) = (nx as f64, ny as f64);
                Some(MeshSize {
                    nodes: (nx + 1.0) * (ny + 1.0),
                    elements: nx * ny,
                    min_length: (size[0] / nx).min(size[1] / ny),
                })
            }
            MeshSpec::WrappedStrip {
                radius,
                width,
                tail,
                angle_deg,
                element_size,
            } => Some(strip_size(
                radius + 0.5 * scene.blank.thickness,
                *width,
                *tail,
                angle_deg.to_radians(),
                *element_size,
            )),
            MeshSpec::File { .. } => None,
        }
    }

    /// The counts of a mesh at hand.
    pub fn of_mesh(mesh: &Mesh) -> MeshSize {
        let min_length = mesh
            .quads
            .iter()
            .map(|q| {
                let p = q.map(|n| mesh.nodes[n as usize]);
                let area = 0.5 * (p[2] - p[0]).cross(&(p[3] - p[1])).norm();
                let longest = (0..4)
                    .map(|k| (p[(k + 1) % 4] - p[k]).norm())
                    .fold(0.0, f64::max);
                area / longest
            })
            .fold(f64::INFINITY, f64::min);
        MeshSize {
            nodes: mesh.nodes.len() as f64,
            elements: mesh.quads.len() as f64,
            min_length,
        }
    }
}

/// [`fem_core::wrapped_strip`]'s counts: tails of `round(tail/h)`
/// elements, an arc of `ceil(r θ / h)`, two elements across.
fn strip_size(r: f64, width: f64, tail: f64, angle: f64, h: f64) -> MeshSize {
    let (n1, na) = fem_core::wrapped_strip_segments(r, tail, angle, h);
    let rows = 2.0 * n1 + na + 1.0;
    let chord = 2.0 * r * (0.5 * angle / na).sin();
    MeshSize {
        nodes: 3.0 * rows,
        elements: 2.0 * (rows - 1.0),
        min_length: (tail / n1).min(chord).min(0.5 * width),
    }
}

/// Where the time step of the estimate comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepSource {
    /// `solver.mass_scaling_dt`.
    MassScaling,
    /// The shells' stable step, estimated.
    Stable,
    /// `solver.dt_max`.
    DtMax,
    /// `solver.fixed_dt`.
    Fixed,
}

impl StepSource {
    /// The scene key that sets the step, and how `scene check` names it.
    pub fn key_and_name(self) -> (&'static str, &'static str) {
        match self {
            Self::MassScaling => ("solver.mass_scaling_dt", "mass scaling"),
            Self::Stable => ("solver.safety_factor", "estimated stable step"),
            Self::DtMax => ("solver.dt_max", "dt_max"),
            Self::Fixed => ("solver.fixed_dt", "fixed step"),
        }
    }
}

/// What a run of a scene needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The blank's size.
    pub mesh: MeshSize,
    /// Memory of the model and its state (bytes).
    pub model_bytes: f64,
    /// Memory of the history rows (`output.history_points`, bytes).
    pub history_bytes: f64,
    /// VTK frames written to disk (bytes).
    pub frames_bytes: f64,
    /// End of the run (s).
    pub end_time: f64,
    /// Time step (s).
    pub dt: f64,
    /// Where `dt` comes from.
    pub dt_source: StepSource,
    /// Increments, `end_time / dt`.
    pub increments: f64,
    /// Expected wall time (s) at [`MICROSECONDS_PER_ELEMENT_CYCLE`].
    pub run_time_s: f64,
}

impl Estimate {
    /// Memory of the run (bytes).
    pub fn memory_bytes(&self) -> f64 {
        self.model_bytes + self.history_bytes
    }
}

/// End of the run (s): `solver.end_time`, else the sum of the step
/// durations (an `until` step counted at its `max_duration`).
pub fn end_time(scene: &Scene) -> f64 {
    scene.solver.end_time.unwrap_or_else(|| {
        scene
            .steps
            .iter()
            .map(|s| {
                s.duration
                    .or(s.until.as_ref().map(|u| u.max_duration))
                    .unwrap_or(0.0)
            })
            .sum()
    })
}

/// The shells' stable time step estimated from the smallest element (s):
/// `safety × L_min / c` with `c = sqrt(E / (ρ (1 − ν²)))` (contact and
/// force-controlled tools can only make it smaller).
pub fn stable_dt(scene: &Scene, mesh: &MeshSize) -> f64 {
    let m = &scene.blank.material;
    let c = (m.youngs_modulus / (m.density * (1.0 - m.poissons_ratio.powi(2)))).sqrt();
    scene.solver.safety_factor * mesh.min_length / c
}

/// The time step a run takes: `fixed_dt` (the engine runs at it, with no
/// safety factor and no mass scaling), else the mass-scaling step, else the
/// estimated stable step, bounded by `dt_max`.
fn time_step(scene: &Scene, mesh: &MeshSize) -> (f64, StepSource) {
    let sv = &scene.solver;
    if let Some(dt) = sv.fixed_dt {
        return (dt, StepSource::Fixed);
    }
    let (dt, source) = match sv.mass_scaling_dt {
        Some(t) => (t, StepSource::MassScaling),
        None => (stable_dt(scene, mesh), StepSource::Stable),
    };
    match sv.dt_max {
        Some(m) if m < dt => (m, StepSource::DtMax),
        _ => (dt, source),
    }
}

/// Contact pairs of the scene: as listed, else one per tool.
fn pair_count(scene: &Scene) -> f64 {
    if scene.contact.pairs.is_empty() {
        scene.tools.len() as f64
    } else {
        scene.contact.pairs.len() as f64
    }
}

/// Memory of one history sample (bytes): the energies' row and the tools'
/// row (`tools.csv`) with one state per tool.
pub fn history_row_bytes(tools: usize) -> f64 {
    use std::mem::size_of;
    (size_of::<crate::records::HistoryRow>()
        + size_of::<crate::records::ToolRow>()
        + tools * size_of::<crate::records::ToolState>()) as f64
}

/// Estimate what a run of `scene` on a blank of `mesh` needs.
///
/// Memory: `8 MB + nodes × (1100 + 400 × pairs) + elements × (900 + 40 ×
/// in-plane points × points through the thickness) + history_points ×`
/// [`history_row_bytes`], fitted to the peak memory of short runs of the
/// square cup at 200, 400 and 800 divisions (both elements, 5 and 9 points)
/// and of the block on a plane at 400 (within 25 %).
pub fn estimate(scene: &Scene, mesh: MeshSize) -> Estimate {
    let element = shell_elements::kinds::element(&scene.blank.element);
    let material = shell_elements::kinds::material(&material_model(scene));
    let ip = element.map_or(1, |k| k.in_plane_points) as f64;
    let points = ip * scene.blank.integration_points as f64;
    let model_bytes = BASE_BYTES
        + mesh.nodes * (NODE_BYTES + PAIR_NODE_BYTES * pair_count(scene))
        + mesh.elements * (ELEMENT_BYTES + POINT_BYTES * points);
    let row = history_row_bytes(scene.tools.len());
    let history_bytes = (scene.output.history_points as f64 + 2.0) * row;
    let end = end_time(scene);
    let (dt, dt_source) = time_step(scene, &mesh);
    let increments = (end / dt).ceil();
    let frames = (scene.output.frames as f64).min(increments);
    let frame_bytes = mesh.nodes * FRAME_NODE_BYTES + mesh.elements * FRAME_ELEMENT_BYTES;
    let formulation = plugins_api::registry::formulation(&scene.contact.formulation);
    let cost = element.map_or(1.0, |k| k.relative_cost)
        * material.map_or(1.0, |k| k.relative_cost)
        * formulation.map_or(1.0, |f| f.relative_cost);
    Estimate {
        mesh,
        model_bytes,
        history_bytes,
        frames_bytes: if frames > 0.0 {
            (frames + 1.0) * frame_bytes
        } else {
            0.0
        },
        end_time: end,
        dt,
        dt_source,
        increments,
        run_time_s: increments * mesh.elements * cost * MICROSECONDS_PER_ELEMENT_CYCLE * 1e-6,
    }
}

/// The memory a run may take (bytes) and where the figure comes from:
/// `MemAvailable` of `/proc/meminfo` (else [`MEMORY_FALLBACK`]), at most
/// [`MEMORY_CAP`].
pub fn memory_limit() -> (f64, &'static str) {
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| mem_available(&text));
    match available {
        Some(b) if b < MEMORY_CAP => (b, "available (MemAvailable)"),
        Some(_) => (MEMORY_CAP, "formsim's cap"),
        None => (MEMORY_FALLBACK, "assumed available (no /proc/meminfo)"),
    }
}

/// `MemAvailable` of a `/proc/meminfo` text (bytes).
fn mem_available(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// `1.5 GiB`, `230 MiB`, `12 kiB`.
pub fn format_bytes(b: f64) -> String {
    if b >= GIB {
        format!("{:.1} GiB", b / GIB)
    } else if b >= 1024.0 * 1024.0 {
        format!("{:.0} MiB", b / (1024.0 * 1024.0))
    } else {
        format!("{:.0} kiB", b / 1024.0)
    }
}

/// The key and value that make the mesh as large as it is.
fn mesh_key(scene: &Scene) -> (&'static str, String) {
    match &scene.blank.mesh {
        MeshSpec::Rectangle { divisions, .. } => {
            let (nx, ny) = divisions.pair();
            ("blank.mesh.divisions", format!("[{nx}, {ny}]"))
        }
        MeshSpec::WrappedStrip { element_size, .. } => {
            ("blank.mesh.element_size", format!("{element_size} mm"))
        }
        MeshSpec::File { path, .. } => ("blank.mesh.path", format!("\"{path}\"")),
    }
}

/// Refuse a run larger than the machine: memory above [`memory_limit`]
/// (naming `output.history_points` when the history rows are the larger
/// part, else the mesh's key), frames above [`FRAMES_DISK_CAP`] (naming
/// `output.frames`), and then a run longer than [`check_run_time`] accepts.
///
/// # Errors
/// One line: the key, its value, the estimate and the limit.
pub fn check_size(loaded: &LoadedScene, est: &Estimate) -> Result<(), SceneError> {
    check_size_within(loaded, est, memory_limit())?;
    check_run_time(loaded, est)
}

fn check_size_within(
    loaded: &LoadedScene,
    est: &Estimate,
    (limit, what): (f64, &str),
) -> Result<(), SceneError> {
    let s = &loaded.scene;
    let need = est.memory_bytes();
    if need > limit {
        let (key, value, part) = if est.history_bytes > est.model_bytes {
            let n = s.output.history_points;
            ("output.history_points", n.to_string(), "history rows")
        } else {
            let (key, value) = mesh_key(s);
            (key, value, "model")
        };
        return Err(loaded.key_error(
            key,
            format!(
                "{value}: a run needs about {} of memory ({} nodes, {} elements; {} of {part}), more than the {} {what}",
                format_bytes(need),
                est.mesh.nodes,
                est.mesh.elements,
                format_bytes(est.history_bytes.max(est.model_bytes)),
                format_bytes(limit),
            ),
        ));
    }
    if est.frames_bytes > FRAMES_DISK_CAP {
        return Err(loaded.key_error(
            "output.frames",
            format!(
                "{}: the VTK frames of a run would take about {} of disk ({:.0} frames of {} elements), more than the {} cap",
                s.output.frames,
                format_bytes(est.frames_bytes),
                (s.output.frames as f64).min(est.increments) + 1.0,
                est.mesh.elements,
                format_bytes(FRAMES_DISK_CAP),
            ),
        ));
    }
    Ok(())
}

/// Refuse a run whose estimated wall time exceeds [`RUN_TIME_MAX_S`] unless
/// [`allow_long_runs`] was called, naming the key that sets the step and
/// the one that sets the end.
///
/// # Errors
/// One line: the step's key and value, the end's key and value, the
/// increments, the estimate and the bound.
pub fn check_run_time(loaded: &LoadedScene, est: &Estimate) -> Result<(), SceneError> {
    if est.run_time_s <= RUN_TIME_MAX_S || ALLOW_LONG.load(std::sync::atomic::Ordering::Relaxed) {
        return Ok(());
    }
    let s = &loaded.scene;
    // The end's key: `solver.end_time`, else the longest press step.
    let end_key = match s.solver.end_time {
        Some(_) => "solver.end_time".to_string(),
        None => s
            .steps
            .iter()
            .map(|st| {
                st.duration
                    .or(st.until.as_ref().map(|u| u.max_duration))
                    .unwrap_or(0.0)
            })
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map_or("steps".to_string(), |(k, _)| format!("steps[{k}].duration")),
    };
    let (step_key, step_name) = est.dt_source.key_and_name();
    // A step the scene sets is the likelier slip; the estimated stable step
    // is not a key, so then the end is.
    let key = match est.dt_source {
        StepSource::Stable => end_key.clone(),
        _ => step_key.to_string(),
    };
    Err(loaded.key_error(
        &key,
        format!(
            "the run would take about {} ({:.3e} increments of {:.3e} s ({step_name}) to {:.4e} s ({end_key}) on {:.0} elements at {MICROSECONDS_PER_ELEMENT_CYCLE} µs each), more than {}: check the step and the end time, or pass --allow-long to run it",
            format_duration(est.run_time_s),
            est.increments,
            est.dt,
            est.end_time,
            est.mesh.elements,
            format_duration(RUN_TIME_MAX_S),
        ),
    ))
}

/// Refuse a mass-scaling step that leaves fewer than
/// [`MIN_INCREMENTS_PER_STEP`] increments in the shortest press step (or in
/// `solver.end_time`, also when it ends the run before the steps do).
///
/// # Errors
/// One line naming `solver.mass_scaling_dt`, its value, the step it is
/// compared with and the largest value accepted.
pub fn check_mass_scaling_step(loaded: &LoadedScene) -> Result<(), SceneError> {
    let s = &loaded.scene;
    let Some(dt) = s.solver.mass_scaling_dt else {
        return Ok(());
    };
    let steps = s.steps.iter().map(|st| {
        let d = st.duration.or(st.until.as_ref().map(|u| u.max_duration));
        (
            format!("press step \"{}\"", st.name),
            d.unwrap_or(f64::INFINITY),
        )
    });
    let end = s
        .solver
        .end_time
        .map(|t| ("solver.end_time".to_string(), t));
    let Some((what, shortest)) = steps.chain(end).min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return Ok(());
    };
    let largest = shortest / MIN_INCREMENTS_PER_STEP;
    if dt <= largest * (1.0 + 1e-9) {
        return Ok(());
    }
    Err(loaded.key_error(
        "solver.mass_scaling_dt",
        format!(
            "{} s: more than 1/{MIN_INCREMENTS_PER_STEP} of {what} ({} s), at most {} s: fewer than {MIN_INCREMENTS_PER_STEP} increments cannot follow it",
            seconds(dt),
            seconds(shortest),
            seconds(largest),
        ),
    ))
}

/// The warning about mass scaling that adds more than
/// [`ADDED_MASS_WARNING_PERCENT`] at set-up (empty otherwise); the same
/// line that `scene check` prints, for a run's `summary.json` `warnings`.
pub fn added_mass_warnings(scene: &Scene, report: &SetupReport) -> Vec<String> {
    match scene.solver.mass_scaling_dt {
        Some(dt) if report.added_mass_percent > ADDED_MASS_WARNING_PERCENT => vec![format!(
            "solver.mass_scaling_dt: {} s adds {:.0} % to the physical mass ({:.3e} of {:.3e} tonne) at set-up, more than {ADDED_MASS_WARNING_PERCENT} %: inertia may dominate the result (compare the kinetic and internal energies, or lower the step)",
            seconds(dt),
            report.added_mass_percent,
            report.added_mass,
            report.physical_mass
        )],
        _ => Vec::new(),
    }
}

/// The lines `scene check` prints about a built and initialised model:
/// its mass and what mass scaling adds, then the estimate of the run
/// (memory against the limit, frames on disk, increments, wall time).
pub fn report_lines(scene: &Scene, est: &Estimate, setup: &SetupReport) -> Vec<String> {
    let scaling = match scene.solver.mass_scaling_dt {
        Some(dt) => format!(
            "mass scaling (dt = {} s) adds {:.1} % ({:.3e} tonne) at set-up",
            seconds(dt),
            setup.added_mass_percent,
            setup.added_mass
        ),
        None => "no mass scaling".to_string(),
    };
    let (limit, what) = memory_limit();
    let (_, step) = est.dt_source.key_and_name();
    let springback = scene
        .steps
        .iter()
        .any(|s| s.kind == super::schema::StepKind::Springback);
    vec![
        format!(
            "mass        {:.4e} tonne; {scaling}; first step {:.3e} s",
            setup.physical_mass, setup.dt_initial
        ),
        format!(
            "estimate    memory {} ({} {what}), frames {} on disk",
            format_bytes(est.memory_bytes()),
            format_bytes(limit),
            format_bytes(est.frames_bytes),
        ),
        format!(
            "estimate    {}{:.0} increments of {:.3e} s ({step}) to {:.4e} s; wall time {} at {MICROSECONDS_PER_ELEMENT_CYCLE} µs per element and increment{}",
            if springback { "at most " } else { "" },
            est.increments,
            est.dt,
            est.end_time,
            format_duration(est.run_time_s),
            if springback {
                " (a springback step ends when the blank is at rest, usually well before its duration)"
            } else {
                ""
            },
        ),
    ]
}

/// A time in seconds as written in scenes: `0.004`, `5e-7`, `1`.
fn seconds(t: f64) -> String {
    if (1e-3..1e4).contains(&t.abs()) {
        format!("{t}")
    } else {
        format!("{t:e}")
    }
}

/// `under 1 s`, `42 s`, `12 min`, `3.5 h`, `2.1 days`.
fn format_duration(s: f64) -> String {
    if s < 1.0 {
        "under 1 s".to_string()
    } else if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 172_800.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86_400.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The documented size of a history sample (docs/scene-format.md:
    /// 224 + 40 × tools bytes) is the size of the rows the run keeps.
    #[test]
    fn history_sample_size_is_the_documented_one() {
        assert_eq!(history_row_bytes(0), 224.0);
        assert_eq!(history_row_bytes(3), 224.0 + 3.0 * 40.0);
    }

    /// A Hill'48 blank's run time is estimated at its registered relative
    /// cost (`shell_elements::kinds`) times J2's, all else equal.
    #[test]
    fn hill_blanks_cost_more_per_element_cycle() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let iso = super::super::load(&root.join("square-cup.toml"), &[]).unwrap();
        let hill = super::super::load(&root.join("square-cup-hill.toml"), &[]).unwrap();
        let mesh = |l: &LoadedScene| MeshSize::of_spec(&l.scene).unwrap();
        let (a, b) = (
            estimate(&iso.scene, mesh(&iso)),
            estimate(&hill.scene, mesh(&hill)),
        );
        let hill48 = shell_elements::kinds::material("hill48").unwrap();
        assert!(hill48.relative_cost > 1.0);
        assert!((b.run_time_s / a.run_time_s / hill48.relative_cost - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_formulation_s_relative_cost_scales_the_estimate() {
        let convective = cup(&[]);
        let jaumann = cup(&["contact.formulation=jaumann"]);
        let size = MeshSize::of_spec(&convective.scene).unwrap();
        let (a, b) = (
            estimate(&convective.scene, size),
            estimate(&jaumann.scene, size),
        );
        let cost = plugins_api::registry::formulation("jaumann")
            .unwrap()
            .relative_cost;
        assert!(cost > 1.0);
        assert!((b.run_time_s / a.run_time_s / cost - 1.0).abs() < 1e-12);
    }

    #[test]
    fn mem_available_reads_kib() {
        let text = "MemTotal:       24000000 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(mem_available(text), Some(2048.0 * 1024.0));
        assert_eq!(mem_available("MemTotal: 1 kB\n"), None);
    }

    #[test]
    fn strip_counts_match_the_generator() {
        let (r, w, tail, angle, h) = (20.05, 4.0, 20.0, 90f64.to_radians(), 1.0);
        let m = fem_core::wrapped_strip(r, w, tail, angle, h).unwrap();
        let est = strip_size(r, w, tail, angle, h);
        assert_eq!(est.nodes, m.nodes.len() as f64);
        assert_eq!(est.elements, m.quads.len() as f64);
        let exact = MeshSize::of_mesh(&m).min_length;
        assert!(
            (est.min_length / exact - 1.0).abs() < 1e-6,
            "{est:?} {exact}"
        );
    }

    #[test]
    fn rectangle_counts_match_the_generator() {
        let m = fem_core::rectangle(75.0, 30.0, 50, 20).unwrap();
        let exact = MeshSize::of_mesh(&m);
        assert_eq!(exact.nodes, 51.0 * 21.0);
        assert_eq!(exact.elements, 1000.0);
        assert!((exact.min_length - 1.5).abs() < 1e-12);
    }

    fn cup(sets: &[&str]) -> LoadedScene {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/square-cup.toml");
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        crate::scene::load(&path, &sets).unwrap()
    }

    #[test]
    fn the_cup_estimate_and_the_key_blamed_against_a_small_limit() {
        let loaded = cup(&[]);
        let est = estimate(&loaded.scene, MeshSize::of_spec(&loaded.scene).unwrap());
        assert_eq!(est.increments, 30201.0);
        assert_eq!(est.dt_source, StepSource::MassScaling);
        let mib = est.memory_bytes() / (1024.0 * 1024.0);
        assert!(
            (10.0..25.0).contains(&mib),
            "{mib} MiB (measured peak 18.6 MiB)"
        );
        check_size_within(&loaded, &est, (1.0 * GIB, "test")).unwrap();
        let e = check_size_within(&loaded, &est, (1e6, "test")).unwrap_err();
        assert!(
            e.to_string()
                .contains("blank.mesh.divisions: [50, 50]: a run needs"),
            "{e}"
        );
        let loaded = cup(&["output.history_points=1000000"]);
        let est = estimate(&loaded.scene, MeshSize::of_spec(&loaded.scene).unwrap());
        let e = check_size_within(&loaded, &est, (1e7, "test")).unwrap_err();
        assert!(
            e.to_string().contains("output.history_points: 1000000"),
            "{e}"
        );
    }

    #[test]
    fn without_mass_scaling_the_step_is_the_stable_one() {
        let loaded = cup(&["solver.dt_max=1"]);
        let mut scene = loaded.scene.clone();
        scene.solver.mass_scaling_dt = None;
        let est = estimate(&scene, MeshSize::of_spec(&scene).unwrap());
        assert_eq!(est.dt_source, StepSource::Stable);
        // 0.9 × 1.5 mm / 5.37e6 mm/s.
        assert!((est.dt / 2.514e-7 - 1.0).abs() < 1e-3, "{}", est.dt);
        scene.solver.dt_max = Some(1e-7);
        let est = estimate(&scene, MeshSize::of_spec(&scene).unwrap());
        assert_eq!((est.dt, est.dt_source), (1e-7, StepSource::DtMax));
    }

    #[test]
    fn format_bytes_picks_the_unit() {
        assert_eq!(format_bytes(3.0 * GIB), "3.0 GiB");
        assert_eq!(format_bytes(5.0 * 1024.0 * 1024.0), "5 MiB");
        assert_eq!(format_bytes(2048.0), "2 kiB");
    }
}
