//! Whether this process was started by an MPI launcher (`mpirun`, `mpiexec`,
//! `srun`), read from the variables the launchers set. Compiled with or
//! without the `mpi` feature, so that a build without it can refuse to run
//! as one of several copies that would all write the same folder.

/// Variables that hold the number of processes of the job: Open MPI's
/// `mpirun`, and PMI-1/PMI-2 (MPICH's `mpiexec`, `srun --mpi=pmi2`).
const SIZE_VARIABLES: [&str; 2] = ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"];

/// Slurm's number of tasks of an `srun` step (any `--mpi`): counted only
/// above 1, since a batch script's own step is no MPI job.
const SLURM_STEP_SIZE: &str = "SLURM_STEP_NUM_TASKS";

/// Variables whose presence alone says an MPI launcher started this
/// process (PMIx sets a rank but no size).
const RANK_VARIABLES: [&str; 3] = ["OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"];

/// What the environment says about a launcher: `None` when no launcher
/// variable is set (a plain start), else the job's size when a size
/// variable holds a number (`Some(None)` when only a rank is known).
pub fn detect(var: &dyn Fn(&str) -> Option<String>) -> Option<Option<usize>> {
    let number = |v: &str| var(v).and_then(|s| s.trim().parse::<usize>().ok());
    let size = SIZE_VARIABLES
        .iter()
        .find_map(|v| number(v))
        .or_else(|| number(SLURM_STEP_SIZE).filter(|&n| n > 1));
    let launched = size.is_some() || RANK_VARIABLES.iter().any(|v| var(v).is_some());
    launched.then_some(size)
}

/// [`detect`] on this process's environment.
pub fn launched() -> Option<Option<usize>> {
    detect(&|v| std::env::var(v).ok())
}

/// The number of tasks of an `srun` step that gave its tasks no MPI
/// plugin (`--mpi=none`, Slurm's usual default): more than one task, and
/// none of the variables a PMI or PMIx plugin sets. An MPI library started
/// so cannot find its peers (Open MPI aborts in its initialisation).
pub fn srun_without_mpi(var: &dyn Fn(&str) -> Option<String>) -> Option<usize> {
    let tasks = var(SLURM_STEP_SIZE)?.trim().parse::<usize>().ok()?;
    let mpi = SIZE_VARIABLES
        .iter()
        .chain(&RANK_VARIABLES)
        .any(|v| var(v).is_some());
    (tasks > 1 && !mpi).then_some(tasks)
}

/// For a command that runs in one process: an error when a launcher started
/// several copies of this process, which would each do the whole work into
/// the same folder. `mpi_build` says whether this build has the MPI
/// executor (then only other commands are refused), for the message.
///
/// # Errors
/// The launcher says the job has more than one process.
pub fn single_copy(mpi_build: bool) -> Result<(), super::BatchError> {
    let why = if mpi_build {
        "only study, compare and identify share their runs over MPI: start this command as \
         one process"
    } else {
        "this build has no MPI executor: start one process, or build formsim with --features \
         mpi to share a study, comparison or identification over the ranks \
         (docs/scale-out.md)"
    };
    match launched() {
        Some(Some(n)) if n > 1 => Err(super::BatchError::Executor(format!(
            "started as {n} processes by an MPI launcher, but {why}"
        ))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |v| pairs.iter().find(|p| p.0 == v).map(|p| p.1.to_string())
    }

    #[test]
    fn srun_without_an_mpi_plugin_is_told_apart() {
        let none = [("SLURM_PROCID", "1"), ("SLURM_STEP_NUM_TASKS", "2")];
        assert_eq!(srun_without_mpi(&env(&none)), Some(2));
        let pmix = [("SLURM_STEP_NUM_TASKS", "2"), ("PMIX_RANK", "1")];
        assert_eq!(srun_without_mpi(&env(&pmix)), None);
        let pmi2 = [("SLURM_STEP_NUM_TASKS", "2"), ("PMI_SIZE", "2")];
        assert_eq!(srun_without_mpi(&env(&pmi2)), None);
        let script = [("SLURM_STEP_NUM_TASKS", "1")];
        assert_eq!(srun_without_mpi(&env(&script)), None);
    }

    #[test]
    fn a_plain_start_is_no_launch() {
        assert_eq!(detect(&env(&[("HOME", "/root")])), None);
    }

    #[test]
    fn mpirun_srun_and_pmix_are_recognised() {
        let ompi = [("OMPI_COMM_WORLD_SIZE", "3"), ("OMPI_COMM_WORLD_RANK", "1")];
        assert_eq!(detect(&env(&ompi)), Some(Some(3)));
        let srun = [("SLURM_PROCID", "0"), ("SLURM_STEP_NUM_TASKS", "8")];
        assert_eq!(detect(&env(&srun)), Some(Some(8)));
        // A batch script's own step: no MPI job.
        let script = [("SLURM_PROCID", "0"), ("SLURM_STEP_NUM_TASKS", "1")];
        assert_eq!(detect(&env(&script)), None);
        assert_eq!(detect(&env(&[("PMIX_RANK", "0")])), Some(None));
        assert_eq!(
            detect(&env(&[("PMI_SIZE", "x"), ("PMI_RANK", "0")])),
            Some(None)
        );
    }
}
