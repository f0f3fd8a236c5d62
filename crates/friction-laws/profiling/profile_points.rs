//! Drive one law × formulation pairing through `step_batch` for profiling, on
//! the inputs of the `point_updates` benchmark (states carried from step to
//! step, as the benchmark does).
//!
//! Usage: `profile_points [LAW|all] [FORMULATION] [POINTS] [STEPS] [time]`
//! (defaults: `ac convective 4096 50`; `all` runs every pairing; `time` skips
//! the digest and prints the wall time of the `step_batch` calls alone).
//!
//! Instructions per update: run under
//! `valgrind --tool=callgrind --toggle-collect='*step_batch*'` and divide the
//! collected instructions by `POINTS × STEPS`. The printed digest hashes the
//! bits of every output and state, so that a change of the hot path can be
//! checked to give bit-identical results.

use friction_laws::builtin::{self, FORMULATION_NAMES, LAW_NAMES};
use plugins_api::{PointState, StepOutput, TangentMode};

#[path = "../benches/support/mod.rs"]
mod support;

/// FNV-1a over 64-bit words.
fn mix(hash: &mut u64, word: u64) {
    for byte in word.to_le_bytes() {
        *hash ^= u64::from(byte);
        *hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
}

fn run(
    law: &str,
    formulation: &str,
    points: usize,
    steps: usize,
    time_only: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let integrator = builtin::integrator(
        law,
        &builtin::benchmark_params(law),
        formulation,
        TangentMode::None,
    )?;
    let inputs = support::inputs(points);
    let mut states = vec![PointState::default(); points];
    let mut outputs = vec![StepOutput::default(); points];
    let mut sticks = 0usize;
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    if time_only {
        let start = std::time::Instant::now();
        for _ in 0..steps {
            integrator.step_batch(&mut states, std::hint::black_box(&inputs), &mut outputs)?;
        }
        let seconds = start.elapsed().as_secs_f64();
        println!(
            "{law}/{formulation}: {points} points x {steps} steps in {seconds:.3} s: {:.2} M updates/s",
            (points * steps) as f64 / seconds / 1e6
        );
        return Ok(());
    }
    for _ in 0..steps {
        integrator.step_batch(&mut states, std::hint::black_box(&inputs), &mut outputs)?;
        for o in &outputs {
            sticks += usize::from(o.stick);
            for x in o.t.iter().chain(o.slip.iter()).chain(o.dt_dp.iter()) {
                mix(&mut hash, x.to_bits());
            }
            for x in o.tangent.iter() {
                mix(&mut hash, x.to_bits());
            }
            for x in [o.tau_c, o.dgamma, o.dissipation] {
                mix(&mut hash, x.to_bits());
            }
            mix(
                &mut hash,
                u64::from(o.open) | u64::from(o.stick) << 1 | u64::from(o.clamped) << 2,
            );
        }
    }
    for s in &states {
        for x in s.t.iter().chain([s.p, s.omega].iter()) {
            mix(&mut hash, x.to_bits());
        }
    }
    println!(
        "{law}/{formulation}: {points} points x {steps} steps, stick share {:.3}, digest {hash:016x}",
        sticks as f64 / (points * steps) as f64
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let law = args.get(1).map_or("ac", String::as_str);
    let formulation = args.get(2).map_or("convective", String::as_str);
    let points: usize = args.get(3).map_or(Ok(4096), |s| s.parse())?;
    let steps: usize = args.get(4).map_or(Ok(50), |s| s.parse())?;
    let time_only = args.get(5).is_some_and(|s| s == "time");
    if law == "all" {
        for law in LAW_NAMES {
            for formulation in FORMULATION_NAMES {
                run(law, formulation, points, steps, time_only)?;
            }
        }
        Ok(())
    } else {
        run(law, formulation, points, steps, time_only)
    }
}
