//! Why an emulation could not run: one error type for the crate.

use std::io;
use std::path::PathBuf;
use std::process::ExitStatus;

/// Why QEMU, the firmware or a session could not do what was asked.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EmulateError {
    /// An operating-system step failed: what was being done, and why.
    #[error("{what}: {error}")]
    Io {
        /// What was being done (`reading firmware.elf`, `binding /tmp/x.sock`, ...).
        what: String,
        /// The operating system's reason.
        error: io::Error,
    },
    /// QEMU could not be started.
    #[error("starting {program}: {error} (install it: `apt-get install qemu-system-arm`, or `cargo xtask demo` does it)")]
    QemuNotStarted {
        /// The program.
        program: &'static str,
        /// The operating system's reason.
        error: io::Error,
    },
    /// QEMU started but did not connect to the UART socket in time.
    #[error("QEMU did not connect to the UART socket: {0}")]
    NotConnected(io::Error),
    /// QEMU did not name the pseudo-terminal it made for UART0.
    #[error("QEMU did not say which pseudo-terminal it made for UART0")]
    NoPseudoTerminal,
    /// The ELF has no defmt table, or it cannot be read.
    #[error("{elf}: {problem}")]
    DefmtTable {
        /// The ELF.
        elf: String,
        /// What is wrong with its table.
        problem: String,
    },
    /// The firmware ELF named is not there.
    #[error("{0}: no such firmware ELF")]
    NoElf(PathBuf),
    /// No ELF at the default path and no firmware sources to build it from.
    #[error("no firmware ELF at {0} and no firmware/ to build it from: give --elf PATH")]
    NothingToBuild(PathBuf),
    /// Building the firmware failed.
    #[error("building the firmware failed ({status}); build it by hand: {command}")]
    BuildFailed {
        /// cargo's exit status.
        status: ExitStatus,
        /// The command to run by hand.
        command: String,
    },
    /// The build ran but left no ELF where it should be.
    #[error("the firmware build did not produce {0}: give --elf PATH")]
    BuildProducedNothing(PathBuf),
    /// A session must end on a configuration message (`Config` or `SubjectConfig`).
    #[error("not a configuration message: tag {0}")]
    NotAConfiguration(u32),
    /// A stream meant to hold joint-angle packets only holds something else.
    #[error("byte {offset}: {problem}")]
    Stream {
        /// Where in the stream.
        offset: usize,
        /// What was found.
        problem: String,
    },
}

impl EmulateError {
    /// An I/O error while doing `what`.
    pub fn io(what: impl Into<String>) -> impl FnOnce(io::Error) -> Self {
        let what = what.into();
        move |error| Self::Io { what, error }
    }
}
