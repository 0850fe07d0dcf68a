//! A minimal on-target test harness: runs named tests, logs each result through defmt, ends
//! with the plain line `N passed, M failed` (which CI counts) and exits with status 0 only if
//! every test passed.

use crate::board;

/// Why a test failed.
#[derive(Debug, Clone, Copy, PartialEq, defmt::Format)]
pub struct Failure {
    /// The condition or quantity that failed.
    pub what: &'static str,
    /// Source line of the failed check.
    pub line: u32,
    /// A measured value, when there is one (e.g. an error above its tolerance).
    pub value: Option<f64>,
}

/// Counts results; [`finish`](Harness::finish) reports and exits.
#[derive(Debug, Default)]
pub struct Harness {
    passed: u32,
    failed: u32,
}

impl Harness {
    /// An empty harness.
    pub const fn new() -> Self {
        Harness {
            passed: 0,
            failed: 0,
        }
    }

    /// Runs one test and records its result.
    pub fn run<E: Into<Failure>>(&mut self, name: &str, test: impl FnOnce() -> Result<(), E>) {
        match test() {
            Ok(()) => {
                self.passed += 1;
                defmt::info!("test {=str} ... ok", name);
            }
            Err(e) => {
                self.failed += 1;
                let f: Failure = e.into();
                defmt::error!(
                    "test {=str} ... FAILED: {=str} (line {=u32}, value {})",
                    name,
                    f.what,
                    f.line,
                    f.value
                );
            }
        }
    }

    /// Prints the summary line and ends the run: status 0 if nothing failed, 1 otherwise.
    pub fn finish(self) -> ! {
        defmt::println!("{=u32} passed, {=u32} failed", self.passed, self.failed);
        board::exit(if self.failed == 0 && self.passed > 0 {
            0
        } else {
            1
        })
    }
}
