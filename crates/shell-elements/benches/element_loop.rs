//! Cost of the shell element loop per element per cycle (BT with 5
//! points in plastic flow, aim ≤ 0.25 µs single core) and the fully
//! integrated shell; plus the 1- vs 2-thread element loop on a 2,500- and a
//! 10,000-element blank.
//!
//! Each iteration is one `ShellSet::add_forces` call (gather, stress update at
//! every point, forces, hourglass, energies, serial scatter) on a flat blank
//! of 1 mm steel squares driven by a biaxial stretch-and-bend velocity field;
//! the set is pre-strained so that every point is in plastic flow.
//!
//! On a shared machine (this one is a virtual machine whose host runs other
//! work) the wall time of a cycle varies by up to 1.6× with the host's load.
//! `bt_5pt_plastic_2500_fastest_cycle` therefore reports, for each sample,
//! its fastest cycle: the minimum is the robust estimator of a benchmark's
//! cost in a noisy environment, interference only ever adding time (Chen &
//! Revels 2016, "Robust benchmarking in noisy environments",
//! arXiv:1608.04295). `…_median_cycle` reports each sample's median cycle
//! (half the cycles faster, half slower: the typical cycle, load included
//! but not its outliers), and `bt_5pt_plastic_2500` is the plain mean.
//!
//! The Hill'48 cases run the same blank, velocity field and pre-strain in
//! the square cup steel's Hill'48 material: `hill48` through its four-lane
//! return (`Hill48PlaneStress::update_points_x4`), `hill48_by_lane` through
//! the default lane-by-lane path of the scalar update
//! (`update_points_by_lane`, the [`ByLane`] wrapper), so that one run
//! compares J2, Hill'48 and Hill'48 before its lane kernel.
//! Run: `cargo bench -p shell-elements --bench element_loop`
//! (`-- element_loop_1thread` for these cases alone).

use criterion::{Bencher, Criterion, Throughput, criterion_group, criterion_main};
use fem_core::{Effect, Forces, NodalState, StepContext, Vec3, rectangle};
use shell_elements::material::{Hill48PlaneStress, PointUpdate};
use shell_elements::{
    BelytschkoTsay, FullyIntegrated, Hardening, J2PlaneStress, Material, Section, ShellFormulation,
    ShellSet,
};
use std::time::{Duration, Instant};

struct Blank<F: ShellFormulation, M: Material = J2PlaneStress> {
    set: ShellSet<F, M>,
    state: NodalState,
    forces: Forces,
    ctx: StepContext<'static>,
}

fn blank<F: ShellFormulation>(form: F, n: usize, parallel_min: usize) -> Blank<F> {
    let mat = J2PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
    )
    .unwrap();
    blank_of(form, mat, n, parallel_min)
}

/// The square cup steel's Hill'48 material (r = 1.79 / 1.51 / 2.27,
/// rolling direction along the elements' e1).
fn hill48() -> Hill48PlaneStress {
    Hill48PlaneStress::new(
        206_000.0,
        0.3,
        7.85e-9,
        Hardening::swift(565.32, 0.007117, 0.2589).unwrap(),
        [1.79, 1.51, 2.27],
    )
    .unwrap()
}

/// `M` with the trait's default four-lane path (`update_points_by_lane`:
/// lane by lane through `M`'s one-element update) instead of its own lane
/// kernel; everything else is `M`'s.
#[derive(Clone)]
struct ByLane<M>(M);

impl<M: Material> Material for ByLane<M> {
    type History = M::History;
    fn name(&self) -> &'static str {
        self.0.name()
    }
    fn density(&self) -> f64 {
        self.0.density()
    }
    fn young(&self) -> f64 {
        self.0.young()
    }
    fn poisson(&self) -> f64 {
        self.0.poisson()
    }
    fn shear_modulus(&self) -> f64 {
        self.0.shear_modulus()
    }
    fn initial_history(&self) -> M::History {
        self.0.initial_history()
    }
    fn update(&self, s: &mut [f64; 3], h: &mut M::History, de: [f64; 3]) -> PointUpdate {
        self.0.update(s, h, de)
    }
    #[inline(always)]
    fn update_points<const N: usize>(
        &self,
        s: &mut [[f64; 3]; N],
        h: &mut [M::History; N],
        de: &[[f64; 3]; N],
    ) -> [PointUpdate; N] {
        self.0.update_points(s, h, de)
    }
    fn plastic_strain(&self, h: &M::History) -> f64 {
        self.0.plastic_strain(h)
    }
    fn flow_stress(&self, h: &M::History) -> f64 {
        self.0.flow_stress(h)
    }
    fn equivalent_stress(&self, s: &[f64; 3]) -> f64 {
        self.0.equivalent_stress(s)
    }
}

fn blank_of<F: ShellFormulation, M: Material>(
    form: F,
    mat: M,
    n: usize,
    parallel_min: usize,
) -> Blank<F, M> {
    let mesh = rectangle(n as f64, n as f64, n, n).unwrap();
    let set = ShellSet::from_mesh(
        "blank",
        &mesh,
        "all",
        Section::new(0.78).unwrap(),
        form,
        mat,
    )
    .unwrap()
    .with_parallel_min(parallel_min);
    let mut state = NodalState::at_rest(&mesh.nodes);
    let l = n as f64;
    for (i, p) in mesh.nodes.iter().enumerate() {
        // Strain rate 1 /s biaxial (1 : 0.5) plus a bending rotation rate.
        state.v[i] = Vec3::new(p.x - 0.5 * l, 0.5 * (p.y - 0.5 * l), 0.0);
        state.w[i] = Vec3::new(0.0, -2.0 * (p.x - 0.5 * l) / l, 0.0);
    }
    let forces = Forces::zeros(mesh.nodes.len());
    // Δt = 2e-5 s: membrane strain increments of 2e-5 per cycle.
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
    b
}

impl<F: ShellFormulation, M: Material> Blank<F, M> {
    fn cycle(&mut self) {
        self.forces.clear();
        self.set
            .add_forces(
                &self.ctx,
                &self.state,
                &mut self.forces,
                &mut fem_core::FieldAccess::none(),
            )
            .unwrap();
    }
    fn plastic_fraction(&self) -> f64 {
        let np = self.set.points_per_element();
        let ipp = F::IN_PLANE_POINTS;
        let n5 = np / ipp;
        let mut plastic = 0;
        for e in 0..self.set.len() {
            for p in 0..ipp {
                for k in 0..n5 {
                    plastic += (self.set.plastic_strain(e, p, k) > 0.0) as usize;
                }
            }
        }
        plastic as f64 / (self.set.len() * np) as f64
    }
}

/// Each sample's fastest cycle, as the sample's time per iteration.
fn fastest_cycle<F: ShellFormulation, M: Material>(b: &mut Bencher, blank: &mut Blank<F, M>) {
    b.iter_custom(|iters| {
        let mut fastest = Duration::MAX;
        for _ in 0..iters {
            let t = Instant::now();
            blank.cycle();
            fastest = fastest.min(t.elapsed());
        }
        fastest * iters as u32
    })
}

/// Each sample's median cycle, as the sample's time per iteration.
fn median_cycle<F: ShellFormulation, M: Material>(b: &mut Bencher, blank: &mut Blank<F, M>) {
    b.iter_custom(|iters| {
        let mut times = Vec::with_capacity(iters as usize);
        for _ in 0..iters {
            let t = Instant::now();
            blank.cycle();
            times.push(t.elapsed());
        }
        times.sort_unstable();
        times[times.len() / 2] * iters as u32
    })
}

fn single_thread(c: &mut Criterion) {
    let mut g = c.benchmark_group("element_loop_1thread");
    let mut bt = blank(BelytschkoTsay::default(), 50, usize::MAX);
    eprintln!(
        "BT plastic fraction of points: {:.3}",
        bt.plastic_fraction()
    );
    g.throughput(Throughput::Elements(2500));
    g.bench_function("bt_5pt_plastic_2500", |b| b.iter(|| bt.cycle()));
    g.bench_function("bt_5pt_plastic_2500_fastest_cycle", |b| {
        fastest_cycle(b, &mut bt)
    });
    g.bench_function("bt_5pt_plastic_2500_median_cycle", |b| {
        median_cycle(b, &mut bt)
    });
    let mut hill = blank_of(BelytschkoTsay::default(), hill48(), 50, usize::MAX);
    eprintln!(
        "BT Hill'48 plastic fraction of points: {:.3}",
        hill.plastic_fraction()
    );
    g.bench_function("bt_5pt_plastic_2500_hill48_fastest_cycle", |b| {
        fastest_cycle(b, &mut hill)
    });
    g.bench_function("bt_5pt_plastic_2500_hill48_median_cycle", |b| {
        median_cycle(b, &mut hill)
    });
    let mut by_lane = blank_of(BelytschkoTsay::default(), ByLane(hill48()), 50, usize::MAX);
    g.bench_function("bt_5pt_plastic_2500_hill48_by_lane_fastest_cycle", |b| {
        fastest_cycle(b, &mut by_lane)
    });
    g.bench_function("bt_5pt_plastic_2500_hill48_by_lane_median_cycle", |b| {
        median_cycle(b, &mut by_lane)
    });
    let mut fi = blank(FullyIntegrated::default(), 50, usize::MAX);
    eprintln!(
        "FI plastic fraction of points: {:.3}",
        fi.plastic_fraction()
    );
    g.bench_function("fully_integrated_5pt_plastic_2500", |b| {
        b.iter(|| fi.cycle())
    });
    g.finish();
}

fn threads(c: &mut Criterion) {
    let mut g = c.benchmark_group("element_loop_threads");
    for n in [50usize, 100] {
        g.throughput(Throughput::Elements((n * n) as u64));
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut bt = blank(BelytschkoTsay::default(), n, 0);
            g.bench_function(format!("bt_{}_elements_{threads}_threads", n * n), |b| {
                pool.install(|| b.iter(|| bt.cycle()))
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(Duration::from_secs(3)).warm_up_time(Duration::from_secs(1));
    targets = single_thread, threads
}
criterion_main!(benches);
