//! What a springback step reports: `summary.json`'s `springback` object and
//! `springback.csv`, the springback displacement of every node.
//!
//! The springback displacement is the motion of each node from the moment
//! the tools let go to the end of the step, less its least-squares fit by
//! the rigid-body modes the scene's own conditions left free: the field does
//! not depend on which nodes the 3-2-1 constraints chose
//! (`fem_core::relaxation`).

use serde::Serialize;

use crate::output::csv_text::CsvText;
use crate::scene::Model;
use crate::scene::schema::StepKind;
use fem_core::Vec3;

/// `summary.json`'s `springback`.
#[derive(Debug, Clone, Serialize)]
pub struct SpringbackSummary {
    /// The method (`dynamic-relaxation`).
    pub method: String,
    /// The residual force ratio at which the blank counts as at rest.
    pub tolerance: f64,
    /// Whether it came to rest (else the step ran to its duration).
    pub settled: bool,
    /// Explicit steps the relaxation took.
    pub increments: u64,
    /// Simulated time it took (s).
    pub duration_s: f64,
    /// Out-of-balance force when the tools let go (N).
    pub residual_start_n: f64,
    /// Out-of-balance force at the end (N).
    pub residual_n: f64,
    /// The DOFs fixed to remove the free rigid-body modes (`node 12 uz`).
    pub fixed: Vec<String>,
    /// Rigid-body modes the scene's own conditions left free (removed from
    /// the displacement by best fit).
    pub free_modes: usize,
    /// Largest springback displacement (mm).
    pub displacement_max_mm: f64,
    /// The node where it is (0-based), and its position when released (mm).
    pub displacement_max_node: usize,
    /// See `displacement_max_node`.
    pub displacement_max_at: [f64; 3],
    /// The static solve of the implicit method.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub implicit: Option<ImplicitSummary>,
}

/// `springback.implicit`: what the static Newton solve did.
#[derive(Debug, Clone, Serialize)]
pub struct ImplicitSummary {
    /// Load (release) increments converged.
    pub increments: usize,
    /// Newton iterations over them.
    pub iterations: usize,
    /// Increments cut back.
    pub cutbacks: usize,
    /// Whether the solve went over to the exact tangent (LU) after the
    /// symmetric part failed an increment at every cut-back allowed.
    pub exact_fallback: bool,
    /// Residual norms `‖R‖` of the last increment, one per iteration (N, N·mm).
    pub last_residuals: Vec<f64>,
    /// Equations of the linear systems (free DOFs).
    pub equations: usize,
    /// Stored values of the tangent and of its factor.
    pub matrix_nnz: usize,
    /// See `matrix_nnz`.
    pub factor_nnz: usize,
    /// Memory of the Cholesky factor (MiB): the factor of the symmetric
    /// part. An LU (counted in `factorisations`) holds more, which faer
    /// does not report.
    pub factor_mib: f64,
    /// Numeric factorisations by kind: `LLᵀ`, `LDLᵀ`, LU.
    pub factorisations: [usize; 3],
    /// The matrix factorised: `"exact"` (the consistent tangent) or
    /// `"symmetric part"` (`½ (K + Kᵀ)`, by Cholesky).
    pub tangent: String,
    /// A factor is kept for the next iteration while `‖R‖` falls to this
    /// fraction of the previous iteration's or less (0: a new one every
    /// iteration).
    pub reuse_contraction: f64,
    /// Convergence tolerances (relative): force, displacement, energy.
    pub tolerances: [f64; 3],
    /// Seconds: the whole solve, assembly of forces and tangents, symbolic
    /// analysis, numeric factorisations, triangular solves.
    pub time_s: f64,
    /// See `time_s`.
    pub assembly_s: f64,
    /// See `time_s`.
    pub symbolic_s: f64,
    /// See `time_s`.
    pub numeric_s: f64,
    /// See `time_s`.
    pub solve_s: f64,
}

impl ImplicitSummary {
    fn of(r: &fem_core::statics::SolveReport) -> Self {
        let (s, t) = (&r.system, &r.timing);
        Self {
            increments: r.increments.len(),
            iterations: r.iterations(),
            cutbacks: r.cutbacks,
            exact_fallback: r.exact_fallback,
            last_residuals: r
                .increments
                .last()
                .map(|i| i.residuals.clone())
                .unwrap_or_default(),
            equations: s.equations,
            matrix_nnz: s.matrix_nnz,
            factor_nnz: s.factor_nnz,
            factor_mib: s.factor_bytes as f64 / (1024.0 * 1024.0),
            factorisations: [s.llt, s.ldlt, s.lu],
            tangent: if r.settings.symmetrize {
                "symmetric part"
            } else {
                "exact"
            }
            .to_string(),
            reuse_contraction: r.settings.reuse_contraction,
            tolerances: [
                r.settings.force_tolerance,
                r.settings.displacement_tolerance,
                r.settings.energy_tolerance,
            ],
            time_s: t.total,
            assembly_s: t.assembly,
            symbolic_s: t.symbolic,
            numeric_s: t.numeric,
            solve_s: t.solve,
        }
    }
}

/// The springback step's report, when the scene has one and the run reached
/// it; with the springback displacement of every node.
pub fn summary(
    model: &Model,
    scene: &crate::scene::Scene,
) -> Option<(SpringbackSummary, Vec<Vec3>)> {
    let step = scene
        .steps
        .iter()
        .find(|s| s.kind == StepKind::Springback)?;
    let r = model.solver.springback()?;
    let d = r.displacement(&model.solver.state().x);
    let (node, max) =
        d.iter().map(|v| v.norm()).enumerate().fold(
            (0, 0.0),
            |(k, m), (i, v)| if v > m { (i, v) } else { (k, m) },
        );
    let at = r.x_release.get(node).copied().unwrap_or_default();
    let s = SpringbackSummary {
        method: step.springback_method().to_string(),
        tolerance: step.springback_tolerance(),
        settled: r.settled,
        increments: r.steps,
        duration_s: model.solver.time() - r.t_release,
        residual_start_n: r.residual_start,
        residual_n: r.residual,
        fixed: r
            .fixed
            .iter()
            .map(|(n, dof)| format!("node {n} {}", dof.name()))
            .collect(),
        free_modes: r.free_modes.len(),
        displacement_max_mm: max,
        displacement_max_node: node,
        displacement_max_at: [at.x, at.y, at.z],
        implicit: r.implicit.as_ref().map(ImplicitSummary::of),
    };
    Some((s, d))
}

/// `springback.csv`: node, its position when released (mm) and its
/// springback displacement (mm).
pub fn csv(path: &std::path::Path, model: &Model, d: &[Vec3]) -> std::io::Result<()> {
    let Some(r) = model.solver.springback() else {
        return Ok(());
    };
    let mut csv = CsvText::new();
    csv.record(["node", "x", "y", "z", "dx", "dy", "dz", "displacement"])?;
    for (i, (x, v)) in r.x_release.iter().zip(d).enumerate() {
        csv.record([
            i.to_string(),
            format!("{:.6e}", x.x),
            format!("{:.6e}", x.y),
            format!("{:.6e}", x.z),
            format!("{:.6e}", v.x),
            format!("{:.6e}", v.y),
            format!("{:.6e}", v.z),
            format!("{:.6e}", v.norm()),
        ])?;
    }
    csv.write_to(path)
}
