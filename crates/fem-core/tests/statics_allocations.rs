//! The Newton loop does not allocate: allocations during a solve scale
//! with the increments (one residual history copied into each increment's
//! report), not with the iterations or the line-search trials.

mod statics_common;

use fem_core::Dof;
use fem_core::statics::{NewtonSettings, StaticSolver};
use statics_common::{APEX, H, truss_with_midpoints};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting allocations and reallocations.
struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// The von Mises truss with mid-span nodes (`statics_common`) pushed
/// through its snap-through in increments of 0.05, down to 2.2 h:
/// compressed, the tangent is indefinite (`LDLᵀ`), in tension definite
/// (`LLᵀ`); line searches, about 4 iterations per increment, and a cut-back
/// near the singular state at 2 h. The allocations made by `solve` must not
/// exceed 2 per increment, plus the reports' vectors growing (2 log₂ of
/// the increments + 2), plus 6 per cut-back (its reason's strings), and
/// must be fewer than half the iterations: none happens per iteration.
/// Tolerance: exact count bounds.
#[test]
fn newton_iterations_do_not_allocate() {
    let mut problem = truss_with_midpoints();
    problem
        .prescribe(&[APEX as u32], Dof::Uz, -2.2 * H)
        .unwrap();
    let settings = NewtonSettings {
        initial_increment: 0.05,
        max_increment: 0.05,
        ..Default::default()
    };
    let mut solver = StaticSolver::new(problem, settings).unwrap();
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    let report = solver.solve().unwrap();
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
    let increments = report.increments.len();
    let growth = 2 * (increments as f64).log2().ceil() as usize + 2;
    let bound = 2 * increments + growth + 6 * report.cutbacks;
    println!(
        "{allocations} allocations for {increments} increments, {} iterations \
         ({} LLt, {} LDLt), {} cut-backs; bound {bound}",
        report.iterations(),
        report.system.llt,
        report.system.ldlt,
        report.cutbacks
    );
    assert!(report.system.ldlt > 0 && report.system.llt > 0);
    assert!(report.iterations() >= 3 * increments);
    assert!(allocations <= bound);
    assert!(2 * allocations < report.iterations());
}
