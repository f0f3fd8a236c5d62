//! Profiling driver for the Belytschko–Tsay element loop: the benchmark's
//! 2,500-element plastic blank, 300 warm-up cycles, then `N` measured cycles
//! (default 100), each in a call of `measured_cycles`, which is what to count with
//! `valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*measured_cycles*'`.
//! Run: `cargo run --release -p shell-elements --example profile_bt [N] [elastic]`.
//! It prints the wall time per element per cycle and the fastest cycles'
//! (minimum, 10th percentile, median): on a shared machine the minimum is
//! the loop's cost without interference.

use fem_core::{Effect, Forces, NodalState, StepContext, Vec3, rectangle};
use shell_elements::{BelytschkoTsay, Hardening, J2PlaneStress, Section, ShellSet};

struct Blank {
    set: ShellSet<BelytschkoTsay, J2PlaneStress>,
    state: NodalState,
    forces: Forces,
    ctx: StepContext<'static>,
}

impl Blank {
    fn cycle(&mut self) {
        self.forces.clear();
        self.set
            .add_forces(
                &self.ctx,
                &self.state,
                &mut self.forces,
                &mut fem_core::FieldAccess::none(),
            )
            .expect("element loop");
    }
}

#[inline(never)]
fn measured_cycles(b: &mut Blank, n: usize) {
    for _ in 0..n {
        b.cycle();
    }
}

fn main() {
    let cycles: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100)
        .max(1);
    // `elastic` as the second argument: the same blank with a flow stress
    // no point reaches (to measure the kernel without the return mapping).
    let elastic = std::env::args().nth(2).as_deref() == Some("elastic");
    let n = 50;
    let mesh = rectangle(n as f64, n as f64, n, n).expect("mesh");
    let mat = J2PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(if elastic { 1e9 } else { 565.32 }, 0.007117, 0.2589).expect("swift"),
    )
    .expect("material");
    let set = ShellSet::from_mesh(
        "blank",
        &mesh,
        "all",
        Section::new(0.78).expect("section"),
        BelytschkoTsay::default(),
        mat,
    )
    .expect("set")
    .with_parallel_min(usize::MAX);
    let mut state = NodalState::at_rest(&mesh.nodes);
    let l = n as f64;
    for (i, p) in mesh.nodes.iter().enumerate() {
        state.v[i] = Vec3::new(p.x - 0.5 * l, 0.5 * (p.y - 0.5 * l), 0.0);
        state.w[i] = Vec3::new(0.0, -2.0 * (p.x - 0.5 * l) / l, 0.0);
    }
    let forces = Forces::zeros(mesh.nodes.len());
    let ctx = StepContext {
        time: 0.0,
        dt: 2e-5,
        step: 1,
        press: None,
    };
    let mut b = Blank {
        set,
        state,
        forces,
        ctx,
    };
    for _ in 0..300 {
        b.cycle();
    }
    // Each cycle timed on its own: on a shared machine the fastest cycles
    // (minimum, 10th percentile) are the element loop's cost without
    // interference, the wall total includes it.
    let mut per_cycle = Vec::with_capacity(cycles);
    let t0 = std::time::Instant::now();
    for _ in 0..cycles {
        let t = std::time::Instant::now();
        measured_cycles(&mut b, 1);
        per_cycle.push(t.elapsed().as_secs_f64());
    }
    let el = t0.elapsed().as_secs_f64();
    let ne = b.set.len();
    per_cycle.sort_by(f64::total_cmp);
    let us = |s: f64| s / ne as f64 * 1e6;
    // `PROFILE_BT_DISTRIBUTION=1`: the per-cycle times' 0, 5, …, 100 %
    // quantiles on standard error.
    if std::env::var_os("PROFILE_BT_DISTRIBUTION").is_some() {
        let v: Vec<String> = (0..=20)
            .map(|i| format!("{:.3}", us(per_cycle[(per_cycle.len() - 1) * i / 20])))
            .collect();
        eprintln!("{}", v.join(" "));
    }
    let pick = |q: f64| us(per_cycle[((per_cycle.len() - 1) as f64 * q) as usize]);
    let f: f64 = b
        .forces
        .f
        .iter()
        .map(|f| f.x.abs() + f.y.abs() + f.z.abs())
        .sum();
    let ep: f64 = (0..ne).map(|e| b.set.plastic_strain(e, 0, 0)).sum::<f64>() / ne as f64;
    println!(
        "{cycles} cycles × {ne} elements: {:.3} µs/element/cycle (wall), fastest cycles {:.3} (min) {:.3} (10 %) {:.3} (median); checksum |f| = {f:.9e}, mean ε_p(bottom) = {ep:.12e}, t(0) = {:.12}",
        el / (cycles * ne) as f64 * 1e6,
        pick(0.0),
        pick(0.1),
        pick(0.5),
        b.set.thickness(0)
    );
}
