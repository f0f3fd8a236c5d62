//! Terminal output of the `formsim` binary.
//!
//! Every line for standard output goes through [`say!`], which returns
//! [`Failure::ClosedStdout`] when the reader has gone (`formsim laws | head
//! -1`: the write fails with `EPIPE`, since Rust ignores `SIGPIPE`). The
//! command then stops where it is and `main` exits 0 without a word, as a Unix
//! filter does; `println!` would panic instead. Messages for standard error go
//! through [`note!`], which never fails: if standard error is gone too, there
//! is nobody left to tell.
//!
//! Why not restore the default `SIGPIPE` action: that needs `unsafe` libc
//! calls (or a dependency), and the process would be killed at whatever write
//! hit the closed pipe, with exit status 141 instead of a deliberate stop.

use std::fmt;
use std::io::{self, Write};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Why a command stopped early.
#[derive(Debug)]
pub enum Failure {
    /// Something is wrong: one line for the user, exit status 1.
    Message(String),
    /// Standard output was closed by its reader: stop quietly, exit status 0.
    ClosedStdout,
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

/// A library error becomes a [`Failure::Message`] with its text.
macro_rules! failure_from {
    ($($t:ty),* $(,)?) => {
        $(impl From<$t> for Failure {
            fn from(e: $t) -> Self {
                Self::Message(e.to_string())
            }
        })*
    };
}

failure_from!(
    toml::ser::Error,
    formsim::run::out_dir::OutDirError,
    formsim::plot::PlotError,
    formsim::point_driver::PointError,
    formsim::tools_cli::ToolsError,
    formsim::compare::CompareError,
    formsim::batch::BatchError,
    formsim::study::StudyError,
    formsim::study::quantity::MeasureError,
);

/// What every command returns.
pub type Outcome = Result<ExitCode, Failure>;

/// Write one line to standard output.
///
/// # Errors
/// [`Failure::ClosedStdout`] on a broken pipe, a message for any other write error.
pub fn write_line(args: fmt::Arguments<'_>) -> Result<(), Failure> {
    let mut out = io::stdout().lock();
    match out.write_fmt(args).and_then(|()| out.write_all(b"\n")) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Err(Failure::ClosedStdout),
        Err(e) => Err(Failure::Message(format!(
            "cannot write to standard output: {e}"
        ))),
    }
}

/// Set by `--quiet` (see [`init_logs`]).
static QUIET: AtomicBool = AtomicBool::new(false);

/// Whether `--quiet` was given: errors only.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Whether to draw progress bars: not asked to be quiet, and standard error
/// is a terminal.
pub fn bars_wanted() -> bool {
    !QUIET.load(Ordering::Relaxed) && io::IsTerminal::is_terminal(&io::stderr())
}

/// Log to standard error through `tracing`: warnings by default, `-v` info
/// (the run's stages, press steps), `-vv` debug (the engine's set-up, mass
/// scaling), `-vvv` trace; `--quiet` errors only and no progress bars.
/// `RUST_LOG`, when set, chooses instead.
pub fn init_logs(verbose: u8, quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
    let level = match (quiet, verbose) {
        (true, _) => "error",
        (false, 0) => "warn",
        (false, 1) => "info",
        (false, 2) => "debug",
        _ => "trace",
    };
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(io::stderr)
        .with_ansi(io::IsTerminal::is_terminal(&io::stderr()))
        .with_target(true)
        .try_init();
}

/// Write one line to standard error, ignoring failure.
pub fn write_note(args: fmt::Arguments<'_>) {
    let _ = writeln!(io::stderr().lock(), "{args}");
}

/// `println!` for commands: returns early from the enclosing function with
/// [`Failure::ClosedStdout`] (or a write error) instead of panicking.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::cli_io::write_line(format_args!($($arg)*))?
    };
}

/// `eprintln!` that never panics.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::cli_io::write_note(format_args!($($arg)*))
    };
}

pub(crate) use {note, say};
