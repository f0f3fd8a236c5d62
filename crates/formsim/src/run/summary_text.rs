//! What `formsim run` prints at the end: [`Summary`] as text, one headline
//! per line (the run, where its time went, the energy balance, the forming
//! figures, the sections, the tools, the closed-form checks), then its
//! warnings. Every figure is one of `summary.json`'s.

use super::summary::Summary;
use super::tools_report::delivered_lines;
use std::fmt;

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self;
        writeln!(
            f,
            "{}: {} + {}, {} {} shells, {} increments in {:.1} s ({:.3e} element cycles/s, {} threads)",
            s.scene,
            s.law,
            s.formulation,
            s.elements,
            s.element,
            s.increments,
            s.wall_time_s,
            s.element_cycles_per_s,
            s.threads
        )?;
        if !s.description.is_empty() {
            writeln!(f, "  {}", s.description)?;
        }
        writeln!(
            f,
            "  time: {}; after the loop {:.2} s (final snapshot, frames index)",
            s.timing.line(s.wall_time_s),
            s.timing.final_output,
        )?;
        self.fmt_energy(f)?;
        if s.stroke != 0.0 {
            writeln!(
                f,
                "  stroke {:.2} mm, punch force max {:.1} kN, thinning max {:.1} %, friction/internal {:.3}, friction share {:.3}",
                s.stroke,
                1e-3 * s.punch_force_max,
                100.0 * s.thinning_max,
                s.friction_to_internal,
                s.friction_energy_share
            )?;
        }
        for (name, sec) in &s.sections {
            writeln!(
                f,
                "  {name}: major max {:.4}, minor min {:.4}, thinning max {:.1} %{}",
                sec.major_max,
                sec.minor_min,
                100.0 * sec.thinning_max,
                sec.minor_at_punch_edge
                    .map_or(String::new(), |m| format!(", minor at punch edge {m:.4}"))
            )?;
        }
        for line in delivered_lines(&s.tools) {
            writeln!(f, "  {line}")?;
        }
        if let Some(fld) = &s.formability {
            let z = |k: &str| fld.end.zones.get(k).copied().unwrap_or(0);
            let w = &fld.end.worst;
            writeln!(
                f,
                "  formability: {} failure, {} marginal, {} safe elements; smallest margin {:.4} ({} strain) at element {} ({:.1}, {:.1}): major {:.4}, minor {:.4}",
                z("failure"),
                z("marginal"),
                z("safe"),
                fld.end.margin_min,
                fld.curve.measure,
                w.element,
                w.at[0],
                w.at[1],
                w.major,
                w.minor
            )?;
        }
        if let Some(b) = &s.springback {
            writeln!(
                f,
                "  springback ({}): displacement max {:.3} mm at node {} ({:.1}, {:.1}, {:.1}); {} in {} increments ({:.2e} s), residual {:.2e} of {:.2e} N; fixed {}",
                b.method,
                b.displacement_max_mm,
                b.displacement_max_node,
                b.displacement_max_at[0],
                b.displacement_max_at[1],
                b.displacement_max_at[2],
                if b.settled { "at rest" } else { "NOT at rest" },
                b.increments,
                b.duration_s,
                b.residual_n,
                b.residual_start_n,
                if b.fixed.is_empty() {
                    "nothing".to_string()
                } else {
                    b.fixed.join(", ")
                }
            )?;
        }
        if let Some(i) = s.springback.as_ref().and_then(|b| b.implicit.as_ref()) {
            writeln!(
                f,
                "  springback static solve: {} increments, {} iterations, {} cut-backs{}, {} factorisations ({}); {} equations, factor {:.1} MiB; {:.2} s (assembly {:.2}, factorisation {:.2}, solves {:.2})",
                i.increments,
                i.iterations,
                i.cutbacks,
                if i.exact_fallback {
                    ", then the exact tangent"
                } else {
                    ""
                },
                i.factorisations.iter().sum::<usize>(),
                if i.tangent == "exact" {
                    "exact tangent"
                } else {
                    "symmetric part of the tangent"
                },
                i.equations,
                i.factor_mib,
                i.time_s,
                i.assembly_s,
                i.symbolic_s + i.numeric_s,
                i.solve_s
            )?;
        }
        for (name, p) in &s.profiles {
            writeln!(f, "  profile {name}: {}", p.line())?;
        }
        self.fmt_checks(f)?;
        if f.alternate() {
            return Ok(());
        }
        for w in &s.warnings {
            writeln!(f, "  warning: {w}")?;
        }
        Ok(())
    }
}

impl Summary {
    /// The energy line: the ledger at the end and the quasi-static measure.
    fn fmt_energy(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (s, e) = (self, &self.energy);
        writeln!(
            f,
            "  energy (mJ): internal {:.1}, plastic {:.1}, friction {:.1}, kinetic {:.2}, hourglass {:.2}, external work {:.1}; balance error {:.2e}; max while forming: kinetic/external work {:.3}{}, kinetic/internal {:.3}",
            e.internal,
            e.plastic,
            e.friction,
            e.kinetic,
            e.hourglass,
            e.external_work,
            e.balance_error_rel,
            s.kinetic_to_work_max,
            if s.regime == "dynamic" {
                " (dynamic scene: not checked)"
            } else {
                ""
            },
            s.kinetic_to_internal_max
        )
    }

    /// The reference check's line, for the scenes that have one.
    fn fmt_checks(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(r) = &self.reference {
            writeln!(f, "  {}", r.line())?;
        }
        Ok(())
    }
}
