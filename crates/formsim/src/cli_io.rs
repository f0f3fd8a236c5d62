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

/// Whether to draw progress bars: not asked to be quiet, and standard error
/// is a terminal.
pub fn bars_wanted(quiet: bool) -> bool {
    !quiet && io::IsTerminal::is_terminal(&io::stderr())
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
