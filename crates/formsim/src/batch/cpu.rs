//! CPU time of the threads a job runs on.
//!
//! Several jobs run at once in one process (`--jobs`), so the process's CPU
//! time is not a job's. Each job runs inside its own rayon pool; the CPU
//! time of that pool's threads, read on each of them, is the job's.

/// CPU seconds used so far by the threads of the current rayon pool (the
/// global pool outside any), read on each thread; 0 where the clock cannot
/// be read.
pub fn pool_seconds() -> f64 {
    rayon::broadcast(|_| {
        cpu_time::ThreadTime::try_now().map_or(0.0, |t| t.as_duration().as_secs_f64())
    })
    .into_iter()
    .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pool_counts_the_work_of_its_threads() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (before, after) = pool.install(|| {
            let before = pool_seconds();
            let spin = |_: rayon::BroadcastContext<'_>| {
                let t = std::time::Instant::now();
                let mut x = 0u64;
                while t.elapsed().as_secs_f64() < 0.05 {
                    x = x.wrapping_add(std::hint::black_box(1));
                }
                x
            };
            rayon::broadcast(spin);
            (before, pool_seconds())
        });
        // Two threads spinning 50 ms each: about 0.1 s of CPU (a loaded
        // machine may deschedule them, never add to it beyond the wall).
        assert!(after - before > 0.03, "{before} → {after}");
        assert!(after - before < 1.0, "{before} → {after}");
    }
}
