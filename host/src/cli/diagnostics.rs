//! The one channel through which the CLI shows warnings and notes: on standard error, or not at
//! all with `--quiet` (errors are always shown, by `main`).

use std::fmt::Display;

use qgait_opensim::diagnostics::Warning;

/// Shows warnings (`warning: ...`) and notes (`note: ...`) unless quiet.
#[derive(Debug, Clone, Copy)]
pub struct Diagnostics {
    quiet: bool,
}

impl Diagnostics {
    /// Shown unless `quiet`.
    pub fn new(quiet: bool) -> Self {
        Self { quiet }
    }

    /// Whether nothing but errors is shown.
    pub fn quiet(&self) -> bool {
        self.quiet
    }

    /// Shows warnings about input that was accepted anyway.
    pub fn warn(&self, warnings: impl IntoIterator<Item = Warning>) {
        if !self.quiet {
            for w in warnings {
                eprintln!("warning: {w}");
            }
        }
    }

    /// Shows notes (how something was read or chosen).
    pub fn notes<T: Display>(&self, notes: impl IntoIterator<Item = T>) {
        if !self.quiet {
            for n in notes {
                eprintln!("note: {n}");
            }
        }
    }

    /// Shows one line of what was done (`wrote 14 files to out/`).
    pub fn done(&self, what: impl Display) {
        if !self.quiet {
            eprintln!("{what}");
        }
    }
}
