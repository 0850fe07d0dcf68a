//! The firmware's cargo runner. Running QEMU (mps2-an386, semihosting, defmt decoded
//! in-process, always under a timeout) lives in the emulation harness (`qgait_emulate::qemu`),
//! shared with `qgait emulate` and the end-to-end tests.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use qgait_emulate::qemu::Qemu;

/// Longest a firmware run may take before it is killed and counted as failed.
pub const TIMEOUT: Duration = Duration::from_secs(60);

/// Exit status reported when QEMU had to be killed.
pub const TIMEOUT_EXIT_CODE: u8 = 124;

/// The cargo runner: the application ELF gets the UART session, anything else (tests) runs
/// to its semihosting exit.
pub fn run_elf(elf: &Path) -> Result<ExitCode, String> {
    if elf.file_stem().is_some_and(|s| s == "qgait-firmware") {
        return crate::session::run(elf).map(|report| {
            if report.passed() {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        });
    }
    let finished = Qemu::start(elf, None)?.wait(TIMEOUT);
    Ok(match finished.code {
        Some(code) => ExitCode::from(u8::try_from(code).unwrap_or(1)),
        None => ExitCode::from(TIMEOUT_EXIT_CODE),
    })
}
