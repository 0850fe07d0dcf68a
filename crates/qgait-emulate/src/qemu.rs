//! Running a firmware ELF on QEMU's mps2-an386 (Cortex-M4F) with semihosting, its defmt log
//! decoded from QEMU's stdout, always under a timeout. The one QEMU runner of the project:
//! `qgait emulate`, the end-to-end tests and the xtask runner all use it.

use crate::EmulateError;
use std::io::{self, BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use crate::defmt_log;

/// The QEMU executable.
pub const QEMU: &str = "qemu-system-arm";

/// The escape (command) key of QEMU's character multiplexer, set with `-echr` (default 0x01,
/// which COBS frames are full of).
pub const ESCAPE: u8 = 0x1c;

/// `bytes` as the multiplexer of [`Qemu::start_buffered`] must receive them: each [`ESCAPE`]
/// doubled (the multiplexer turns "escape, escape" into one escape byte for the UART).
pub fn escape(bytes: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(bytes.len() + bytes.len() / 128);
    for &b in bytes {
        out.push(b);
        if b == ESCAPE {
            out.push(b);
        }
    }
    out
}

/// Where decoded log lines go as they arrive (they are also kept in [`Finished::log`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Echo {
    /// Printed on standard output.
    Stdout,
    /// Printed on standard error, each line prefixed with `device: `.
    Stderr,
    /// Only kept.
    Quiet,
}

/// A running QEMU and the thread decoding its log.
pub struct Qemu {
    child: Child,
    log: Option<JoinHandle<Vec<String>>>,
    /// The devices QEMU redirected character devices to (`-serial pty`), as it announces them.
    redirected: mpsc::Receiver<String>,
}

/// Where UART0 goes.
enum Uart<'a> {
    None,
    /// A Unix socket, behind the multiplexer or not.
    Socket(&'a Path, bool),
    /// A pseudo-terminal QEMU makes.
    Pty,
}

/// What QEMU prints first on stdout (before the firmware's defmt output) for `-serial pty`:
/// `char device redirected to /dev/pts/3 (label serial0)`.
const REDIRECTED: &str = "char device redirected to ";

/// How a run ended, with the decoded log lines.
#[derive(Debug, Clone)]
pub struct Finished {
    /// QEMU's exit status (the firmware's semihosting exit code), `None` if it was killed.
    pub code: Option<i32>,
    /// Every decoded log line.
    pub log: Vec<String>,
}

/// Whether `qemu-system-arm` can be started (`--version` answers).
pub fn available() -> bool {
    Command::new(QEMU)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

impl Qemu {
    /// Starts `elf` with its log printed on stdout; UART0 is connected to the Unix socket
    /// `uart_socket` (QEMU connects to it as a client, so bind it first) or to nothing.
    pub fn start(elf: &Path, uart_socket: Option<&Path>) -> Result<Qemu, EmulateError> {
        Self::start_with(elf, uart_socket, Echo::Stdout)
    }

    /// [`start`](Self::start) with the log going to `echo`.
    fn start_with(
        elf: &Path,
        uart_socket: Option<&Path>,
        echo: Echo,
    ) -> Result<Qemu, EmulateError> {
        let uart = uart_socket.map_or(Uart::None, |s| Uart::Socket(s, false));
        Self::launch(elf, uart, &[], echo)
    }

    /// Starts `elf` with no UART and extra QEMU arguments (e.g. `-icount shift=0,align=off` to
    /// count instructions).
    pub fn start_with_args(elf: &Path, args: &[&str], echo: Echo) -> Result<Qemu, EmulateError> {
        Self::launch(elf, Uart::None, args, echo)
    }

    /// [`start`](Self::start) with the log going to `echo`, and QEMU's multiplexer between the socket and UART0: it
    /// keeps up to 32 bytes ready for the UART, which then takes its next byte the moment the
    /// firmware reads one, instead of waiting for QEMU's I/O thread each time (several times
    /// faster). The multiplexer reads [`ESCAPE`] as a command key: send every input byte
    /// through [`escape`]. It reads the socket only as far as its buffer has room, so the line
    /// stays flow-controlled (see [`session`](crate::session)).
    pub fn start_buffered(
        elf: &Path,
        uart_socket: &Path,
        echo: Echo,
    ) -> Result<Qemu, EmulateError> {
        Self::launch(elf, Uart::Socket(uart_socket, true), &[], echo)
    }

    /// Starts `elf` with UART0 on a pseudo-terminal (`-serial pty`) and returns it with the
    /// terminal's path (e.g. `/dev/pts/3`): a program reading the hub from a serial port reads
    /// it there, through a real tty. QEMU has the master side and reads it only while the
    /// firmware's UART can take a byte (so a writer is held back, nothing is lost); what the
    /// hub sends while no one has the terminal open is dropped.
    pub fn start_pty(elf: &Path, echo: Echo) -> Result<(Qemu, PathBuf), EmulateError> {
        let qemu = Self::launch(elf, Uart::Pty, &[], echo)?;
        match qemu.redirected.recv_timeout(Duration::from_secs(10)) {
            Ok(path) => Ok((qemu, PathBuf::from(path))),
            Err(_) => {
                qemu.stop();
                Err(EmulateError::NoPseudoTerminal)
            }
        }
    }

    fn launch(elf: &Path, uart: Uart, extra: &[&str], echo: Echo) -> Result<Qemu, EmulateError> {
        let bytes =
            std::fs::read(elf).map_err(EmulateError::io(format!("reading {}", elf.display())))?;
        let table = defmt_log::table(&elf.display().to_string(), &bytes)?;
        let mut cmd = Command::new(QEMU);
        cmd.args([
            "-M",
            "mps2-an386",
            "-display",
            "none",
            "-monitor",
            "none",
            "-nodefaults",
        ])
        .args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(elf);
        match uart {
            Uart::None => {}
            Uart::Socket(socket, mux) => {
                let suffix = if mux { ",mux=on" } else { "" };
                cmd.arg("-chardev")
                    .arg(format!("socket,id=u0,path={}{suffix}", socket.display()))
                    .args(["-serial", "chardev:u0"]);
                if mux {
                    cmd.args(["-echr", &ESCAPE.to_string()]);
                }
            }
            Uart::Pty => {
                cmd.args(["-serial", "pty"]);
            }
        }
        cmd.args(extra);
        cmd.stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        let mut child = cmd.spawn().map_err(|error| EmulateError::QemuNotStarted {
            program: QEMU,
            error,
        })?;
        let stdout = child.stdout.take().expect("stdout is piped");
        let stderr = child.stderr.take().expect("stderr is piped");
        thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                // Harmless: the board's Ethernet controller has no network.
                if !line.contains("has no peer") {
                    eprintln!("{line}");
                }
            }
        });
        let (redirect_tx, redirected) = mpsc::channel();
        let pty = matches!(uart, Uart::Pty);
        let log = thread::spawn(move || {
            let mut kept = Vec::new();
            let mut stdout = BufReader::new(stdout);
            // The announcement of the pseudo-terminal, if it is there, then the defmt stream.
            let mut head = Vec::new();
            let mut byte = [0u8];
            while pty && matches!(stdout.read(&mut byte), Ok(1)) {
                head.push(byte[0]);
                let prefix = REDIRECTED.as_bytes();
                if !(prefix.starts_with(&head) || head.starts_with(prefix)) {
                    break;
                }
                if byte[0] == b'\n' {
                    let line = String::from_utf8_lossy(&head[prefix.len()..]).into_owned();
                    let path = line.split(" (").next().unwrap_or(&line).trim_end();
                    let _ = redirect_tx.send(path.to_string());
                    head.clear();
                    break;
                }
            }
            defmt_log::decode_stream(&table, io::Cursor::new(head).chain(stdout), |l| {
                match echo {
                    Echo::Stdout => println!("{l}"),
                    Echo::Stderr => eprintln!("device: {l}"),
                    Echo::Quiet => {}
                }
                kept.push(l.to_string());
            });
            kept
        });
        Ok(Qemu {
            child,
            log: Some(log),
            redirected,
        })
    }

    /// Waits for QEMU to exit, killing it after `timeout`.
    pub fn wait(mut self, timeout: Duration) -> Finished {
        let deadline = Instant::now() + timeout;
        let code = loop {
            match self.child.try_wait() {
                Ok(Some(status)) => break status.code(),
                Ok(None) if Instant::now() < deadline => thread::sleep(Duration::from_millis(5)),
                _ => {
                    eprintln!("QEMU still running after {timeout:?}: killed");
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
        let log = self
            .log
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        Finished { code, log }
    }
}

impl Drop for Qemu {
    /// Never leaves QEMU running, whatever path dropped it (an error, a panic).
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
