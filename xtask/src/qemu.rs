//! The firmware's cargo runner. Running QEMU (mps2-an386, semihosting, defmt decoded
//! in-process, always under a timeout) lives in the emulation harness (`qgait_emulate::qemu`),
//! shared with `qgait emulate` and the end-to-end tests.

use anyhow::anyhow;
use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use qgait_emulate::qemu::Qemu;

/// Longest a firmware run may take before it is killed and counted as failed.
pub const TIMEOUT: Duration = Duration::from_secs(60);

/// Exit status reported when QEMU had to be killed.
pub const TIMEOUT_EXIT_CODE: u8 = 124;

/// The cargo runner: the application ELF gets the UART session, anything else (tests) runs
/// to its semihosting exit; a defmt-test ELF's run is counted (see [`DefmtTestRun`]) and
/// fails unless every test passed.
pub fn run_elf(elf: &Path) -> anyhow::Result<ExitCode> {
    if elf.file_stem().is_some_and(|s| s == "qgait-firmware") {
        return crate::session::run(elf).map(|report| {
            if report.passed() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        });
    }
    let finished = Qemu::start(elf, None)
        .map_err(|e| anyhow!("{e}"))?
        .wait(TIMEOUT);
    let summary = defmt_test_summary(&finished.log, finished.code);
    if let Some(run) = &summary {
        for line in run.lines() {
            println!("{line}");
        }
    }
    Ok(match (finished.code, summary.map(|run| run.passed_all)) {
        (_, Some(true)) => ExitCode::SUCCESS,
        // A defmt-test run that exited with 0 before its end.
        (Some(0), Some(false)) => ExitCode::FAILURE,
        (Some(code), _) => ExitCode::from(u8::try_from(code).unwrap_or(1)),
        (None, _) => ExitCode::from(TIMEOUT_EXIT_CODE),
    })
}

/// What the log of a `defmt-test` run says. defmt-test prints ``(k/N) running `name`...`` (or
/// `ignoring`) before each test and `all tests passed!` after the last, then exits with
/// status 0, but prints no count; a failing test panics (the firmware's panic handler exits
/// with 101) or hangs (QEMU is killed after [`TIMEOUT`]), and the tests after it do not run.
#[derive(Debug, PartialEq)]
struct DefmtTestRun {
    passed: u32,
    /// The test being run when the run ended early, if it did.
    failed: Option<String>,
    /// Tests after the failed one, which did not run.
    not_run: u32,
    /// Tests marked `#[ignore]`.
    ignored: u32,
    /// Every test passed, the run ended with `all tests passed!` and exit status 0.
    passed_all: bool,
    /// QEMU's exit status (`None`: killed after the timeout).
    code: Option<i32>,
}

impl DefmtTestRun {
    /// What the runner prints after the log: the failure if any, then the plain line
    /// `N passed, M failed` that CI counts.
    fn lines(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(name) = &self.failed {
            let how = match self.code {
                Some(0) => "exited before its end".to_string(),
                Some(code) => format!("failed, exit status {code}"),
                None => format!("did not finish within {} s", TIMEOUT.as_secs()),
            };
            lines.push(format!("xtask: on-target test `{name}` {how}"));
        }
        if self.not_run > 0 {
            lines.push(format!(
                "xtask: {} on-target tests after it did not run",
                self.not_run
            ));
        }
        if self.ignored > 0 {
            lines.push(format!("xtask: {} on-target tests ignored", self.ignored));
        }
        lines.push(format!(
            "{} passed, {} failed",
            self.passed,
            u32::from(self.failed.is_some())
        ));
        lines
    }
}

/// Counts a `defmt-test` run from its decoded `log` and exit `code`; `None` if the log has no
/// defmt-test progress line (not a defmt-test ELF).
fn defmt_test_summary(log: &[String], code: Option<i32>) -> Option<DefmtTestRun> {
    // ``(k/N) running `name`...``: number, total, whether it runs, name.
    let progress = |line: &str| -> Option<(u32, u32, bool, String)> {
        let (k, rest) = line.strip_prefix('(')?.split_once('/')?;
        let (n, rest) = rest.split_once(") ")?;
        let (verb, rest) = rest.split_once(" `")?;
        let name = rest.strip_suffix("`...")?;
        let running = match verb {
            "running" => true,
            "ignoring" => false,
            _ => return None,
        };
        Some((k.parse().ok()?, n.parse().ok()?, running, name.to_string()))
    };
    let started: Vec<_> = log.iter().filter_map(|l| progress(l)).collect();
    let (last_k, total, last_running, last_name) = started.last()?.clone();
    let ran = started.iter().filter(|s| s.2).count() as u32;
    let ignored = started.len() as u32 - ran;
    let passed_all =
        code == Some(0) && last_k == total && log.iter().any(|l| l == "all tests passed!");
    Some(if passed_all {
        DefmtTestRun {
            passed: ran,
            failed: None,
            not_run: 0,
            ignored,
            passed_all,
            code,
        }
    } else {
        DefmtTestRun {
            passed: ran - u32::from(last_running),
            failed: Some(last_name),
            not_run: total.saturating_sub(last_k),
            ignored,
            passed_all,
            code,
        }
    })
}

#[cfg(test)]
mod tests {
    use super::{defmt_test_summary, DefmtTestRun};

    fn log(lines: &[&str]) -> Vec<String> {
        lines.iter().map(|l| l.to_string()).collect()
    }

    #[test]
    fn a_complete_run_counts_every_test() {
        let l = log(&[
            "(1/3) running `a`...",
            "INFO  kernel f32 vs f64: largest point error 4.7e-7 m",
            "(2/3) ignoring `b`...",
            "(3/3) running `c`...",
            "all tests passed!",
        ]);
        let run = defmt_test_summary(&l, Some(0)).unwrap();
        assert!(run.passed_all);
        assert_eq!(
            (run.passed, run.failed.as_deref(), run.ignored),
            (2, None, 1)
        );
        assert_eq!(run.lines().last().unwrap(), "2 passed, 0 failed");
    }

    #[test]
    fn a_failed_test_ends_the_run_and_is_named() {
        let l = log(&[
            "(1/4) running `a`...",
            "(2/4) running `b`...",
            "ERROR panicked at 'assertion failed: worst <= POINT_TOLERANCE_M'",
            "ERROR panic at tests/on_target.rs:12",
        ]);
        let run = defmt_test_summary(&l, Some(101)).unwrap();
        assert_eq!(
            run,
            DefmtTestRun {
                passed: 1,
                failed: Some("b".into()),
                not_run: 2,
                ignored: 0,
                passed_all: false,
                code: Some(101),
            }
        );
        let lines = run.lines();
        assert_eq!(
            lines[0],
            "xtask: on-target test `b` failed, exit status 101"
        );
        assert_eq!(lines.last().unwrap(), "1 passed, 1 failed");
    }

    #[test]
    fn a_hang_or_an_early_exit_is_a_failure() {
        let l = log(&["(1/2) running `a`...", "(2/2) running `b`..."]);
        let hung = defmt_test_summary(&l, None).unwrap();
        assert!(!hung.passed_all);
        assert_eq!(hung.failed.as_deref(), Some("b"));
        assert!(hung.lines()[0].contains("did not finish"));
        // Status 0 without defmt-test's closing line: a test ended the run itself.
        let early = defmt_test_summary(&l, Some(0)).unwrap();
        assert!(!early.passed_all);
        assert_eq!(early.lines().last().unwrap(), "1 passed, 1 failed");
    }

    #[test]
    fn other_elfs_have_no_summary() {
        let l = log(&[
            "INFO  bench: fk.phak 1234 instructions",
            "5 passed, 0 failed",
        ]);
        assert_eq!(defmt_test_summary(&l, Some(0)), None);
    }
}
