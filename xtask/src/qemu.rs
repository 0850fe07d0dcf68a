//! Running a firmware ELF on QEMU's mps2-an386 (Cortex-M4F) with semihosting, its defmt log
//! decoded from QEMU's stdout, always under a timeout.

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, Command, ExitCode, Stdio};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use crate::defmt_log;

/// Longest a firmware run may take before it is killed and counted as failed.
pub const TIMEOUT: Duration = Duration::from_secs(60);

/// Exit status reported when QEMU had to be killed.
pub const TIMEOUT_EXIT_CODE: u8 = 124;

/// A running QEMU and the thread decoding its log.
pub struct Qemu {
    child: Child,
    log: JoinHandle<Vec<String>>,
}

/// How a run ended, with the decoded log lines.
pub struct Finished {
    /// QEMU's exit status (the firmware's semihosting exit code), `None` if it was killed.
    pub code: Option<i32>,
    /// Every decoded log line.
    pub log: Vec<String>,
}

impl Qemu {
    /// Starts `elf`; UART0 is connected to the Unix socket `uart_socket` (QEMU connects to it
    /// as a client, so bind it first) or to nothing.
    pub fn start(elf: &Path, uart_socket: Option<&Path>) -> Result<Qemu, String> {
        let bytes = std::fs::read(elf).map_err(|e| format!("reading {}: {e}", elf.display()))?;
        let table = defmt_log::table(&bytes)?;
        let mut cmd = Command::new("qemu-system-arm");
        cmd.args(["-M", "mps2-an386", "-display", "none", "-monitor", "none", "-nodefaults"])
            .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
            .arg(elf);
        if let Some(socket) = uart_socket {
            cmd.arg("-chardev").arg(format!("socket,id=u0,path={}", socket.display())).args(["-serial", "chardev:u0"]);
        }
        cmd.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped());
        let mut child = cmd.spawn().map_err(|e| format!("starting qemu-system-arm (is it installed?): {e}"))?;
        let stdout = child.stdout.take().ok_or("no QEMU stdout")?;
        let stderr = child.stderr.take().ok_or("no QEMU stderr")?;
        thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                // Harmless: the board's Ethernet controller has no network.
                if !line.contains("has no peer") {
                    eprintln!("{line}");
                }
            }
        });
        let log = thread::spawn(move || {
            let mut lines = Vec::new();
            defmt_log::decode_stream(&table, stdout, |l| lines.push(l.to_string()));
            lines
        });
        Ok(Qemu { child, log })
    }

    /// Waits for QEMU to exit, killing it after `timeout`.
    pub fn wait(mut self, timeout: Duration) -> Finished {
        let deadline = Instant::now() + timeout;
        let code = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break status.code(),
                Ok(None) if Instant::now() < deadline => thread::sleep(Duration::from_millis(5)),
                _ => {
                    eprintln!("xtask: QEMU still running after {timeout:?}: killed");
                    break None;
                }
            }
        };
        self.finish(code)
    }

    /// Stops QEMU (the application firmware never exits by itself).
    pub fn stop(self) -> Finished {
        self.finish(None)
    }

    fn finish(mut self, code: Option<i32>) -> Finished {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let log = self.log.join().unwrap_or_default();
        Finished { code, log }
    }
}

/// The cargo runner: the application ELF gets the UART session, anything else (tests) runs
/// to its semihosting exit.
pub fn run_elf(elf: &Path) -> Result<ExitCode, String> {
    if elf.file_stem().is_some_and(|s| s == "qgait-firmware") {
        return crate::session::run(elf).map(|report| if report.passed() { ExitCode::SUCCESS } else { ExitCode::FAILURE });
    }
    let finished = Qemu::start(elf, None)?.wait(TIMEOUT);
    Ok(match finished.code {
        Some(code) => ExitCode::from(u8::try_from(code).unwrap_or(1)),
        None => ExitCode::from(TIMEOUT_EXIT_CODE),
    })
}
