//! Reading what a hub sends, as it arrives, from a log file, standard input or a serial port
//! (`qgait decode` and `qgait verify`).
//!
//! A path naming a terminal device (a USB-serial hub such as `/dev/ttyACM0`, a pseudo-terminal)
//! is opened as a serial port with the [`serial2`] crate: raw, 8 data bits, no parity, 1 stop bit,
//! no flow control, at the baud rate asked for ([`DEFAULT_BAUD`], the hub's, by default), so it
//! needs no `stty` first. Anything else (a regular file, a pipe, `-` for standard input) is read
//! as it is. A read waits at most [`POLL`], so the end conditions are checked while a serial
//! port or a pipe is quiet.
//!
//! A reading ends ([`End`]) at the end of the input, after a number of pose frames, after a
//! time, after a time without a pose frame (once one came), on Ctrl-C or SIGTERM
//! ([`interrupt`]), or when the port fails (a hub unplugged). Every record decoded before the
//! end has been handed over whole; nothing is decoded past it (the reading stops at the
//! delimiter of the last frame counted). Memory is independent of the input's length: one
//! read buffer and the frame decoder.

use std::fs::File;
use std::io::{self, IsTerminal, Read};
use std::path::Path;
use std::time::{Duration, Instant};

use qgait_proto::Message;

use crate::log::{LogDecoder, Record};
use qgait_opensim::diagnostics::{Warning, WarningText};

/// The hub's baud rate (both boards' UARTs run at 115200 8N1).
pub const DEFAULT_BAUD: u32 = 115_200;

/// Longest wait of one read of a serial port.
pub const POLL: Duration = Duration::from_millis(100);

/// Bytes asked for per read.
const CHUNK: usize = 65_536;

/// Why a hub log cannot be opened or read; each names the input.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PortError {
    /// A file (or pipe) cannot be opened.
    #[error("{path}: cannot open")]
    Open {
        /// The path given.
        path: String,
        /// Why.
        #[source]
        error: io::Error,
    },
    /// `--baud 0`.
    #[error("{path}: a baud rate of 0 is not a rate")]
    ZeroBaud {
        /// The serial port.
        path: String,
    },
    /// A serial port cannot be opened at the rate asked for.
    #[error(
        "{path}: cannot open as a serial port at {rate} baud: {error}{}",
        if error.kind() == io::ErrorKind::PermissionDenied {
            " (on Linux, join the group that owns the port, usually `dialout`)"
        } else {
            ""
        }
    )]
    Serial {
        /// The serial port.
        path: String,
        /// The baud rate.
        rate: u32,
        /// Why.
        error: io::Error,
    },
    /// A serial port refuses a read timeout.
    #[error("{path}: cannot set a read timeout")]
    Timeout {
        /// The serial port.
        path: String,
        /// Why.
        #[source]
        error: io::Error,
    },
    /// A read failed (a hub unplugged, an I/O error).
    #[error("{path}: cannot read")]
    Read {
        /// The input.
        path: String,
        /// Why.
        #[source]
        error: io::Error,
    },
}

/// An opened hub log.
pub struct Input {
    name: String,
    source: Source,
}

enum Source {
    Stdin(io::Stdin),
    File(File),
    Serial(serial2::SerialPort),
}

/// Whether `path` is a terminal device (opened without waiting for a modem's carrier and
/// without becoming the controlling terminal), or a character device that cannot be opened
/// (so that opening it as a serial port says why, e.g. a missing group membership).
#[cfg(unix)]
fn is_terminal_device(path: &Path) -> bool {
    use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
    std::fs::metadata(path).is_ok_and(|m| m.file_type().is_char_device())
        && std::fs::OpenOptions::new()
            .read(true)
            .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
            .open(path)
            .map_or(true, |f| f.is_terminal())
}

/// Whether `path` is a serial port (`COM3`, `\\.\COM12`).
#[cfg(not(unix))]
fn is_terminal_device(path: &Path) -> bool {
    let name = path.to_string_lossy().to_ascii_uppercase();
    let name = name.strip_prefix(r"\\.\").unwrap_or(&name);
    name.strip_prefix("COM")
        .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

impl Input {
    /// Opens `path`: `-` is standard input, a terminal device a serial port at `baud` (default
    /// [`DEFAULT_BAUD`]), anything else a file. The warning says when `baud` does not apply.
    pub fn open(path: &str, baud: Option<u32>) -> Result<(Input, Option<Warning>), PortError> {
        let ignored = |what: &str| {
            baud.map(|b| {
                Warning::OptionIgnored(WarningText {
                    at: None,
                    detail: format!("--baud {b} ignored: {what} is not a serial port"),
                })
            })
        };
        if path == "-" {
            let input = Input {
                name: path.into(),
                source: Source::Stdin(io::stdin()),
            };
            return Ok((input, ignored("standard input")));
        }
        if !is_terminal_device(Path::new(path)) {
            let file = File::open(path).map_err(|error| PortError::Open {
                path: path.into(),
                error,
            })?;
            let input = Input {
                name: path.into(),
                source: Source::File(file),
            };
            return Ok((input, ignored(path)));
        }
        let rate = baud.unwrap_or(DEFAULT_BAUD);
        if rate == 0 {
            return Err(PortError::ZeroBaud { path: path.into() });
        }
        let mut port =
            serial2::SerialPort::open(path, rate).map_err(|error| PortError::Serial {
                path: path.into(),
                rate,
                error,
            })?;
        port.set_read_timeout(POLL)
            .map_err(|error| PortError::Timeout {
                path: path.into(),
                error,
            })?;
        Ok((
            Input {
                name: path.into(),
                source: Source::Serial(port),
            },
            None,
        ))
    }

    /// The path it was opened with.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether it is a serial port (data arrives live).
    pub fn is_serial(&self) -> bool {
        matches!(self.source, Source::Serial(_))
    }

    /// Reads some bytes: `Ok(Some(0))` at the end of a file, `Ok(None)` when nothing came for
    /// [`POLL`] (a serial port or a pipe).
    fn read(&mut self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        match &mut self.source {
            Source::Stdin(s) => {
                if !readable(s, POLL)? {
                    return Ok(None);
                }
                s.read(buf).map(Some)
            }
            Source::File(f) => {
                // (A named pipe can be quiet; a regular file is always readable.)
                if !readable(f, POLL)? {
                    return Ok(None);
                }
                f.read(buf).map(Some)
            }
            Source::Serial(p) => match p.read(buf) {
                Ok(0) => Err(io::Error::new(
                    io::ErrorKind::UnexpectedEof,
                    "the port hung up (unplugged?)",
                )),
                Ok(n) => Ok(Some(n)),
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
                    ) =>
                {
                    Ok(None)
                }
                Err(e) => Err(e),
            },
        }
    }
}

/// Whether `input` has something to read (or its end) within `timeout`, so that a quiet pipe
/// does not keep a reading from its end conditions.
#[cfg(unix)]
#[allow(unsafe_code)]
fn readable(input: &impl std::os::fd::AsRawFd, timeout: Duration) -> io::Result<bool> {
    let mut fd = libc::pollfd {
        fd: input.as_raw_fd(),
        events: libc::POLLIN,
        revents: 0,
    };
    // SAFETY: one valid pollfd, for the duration of the call.
    let n = unsafe { libc::poll(&mut fd, 1, timeout.as_millis() as libc::c_int) };
    if n < 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(n > 0)
}

/// Elsewhere a read just waits.
#[cfg(not(unix))]
fn readable<T>(_: &T, _: Duration) -> io::Result<bool> {
    Ok(true)
}

/// When to stop reading (besides the end of the input, Ctrl-C and SIGTERM).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Until {
    /// After this many pose frames.
    pub frames: Option<u64>,
    /// After this long.
    pub time: Option<Duration>,
    /// After this long without a pose frame, once one has come.
    pub idle: Option<Duration>,
}

/// Why a reading ended.
#[derive(Debug)]
pub enum End {
    /// The end of the file or of standard input.
    InputEnded,
    /// [`Until::frames`] pose frames came.
    Frames(u64),
    /// [`Until::time`] passed.
    Time(Duration),
    /// [`Until::idle`] passed without a pose frame.
    Idle(Duration),
    /// Ctrl-C or SIGTERM.
    Interrupted,
    /// The caller asked to stop (e.g. its output was closed).
    Stopped,
    /// A read failed (the error names the input).
    Failed(PortError),
}

impl End {
    /// What to tell the user, except at the end of the input (the usual end of a log file).
    pub fn describe(&self) -> Option<String> {
        match self {
            End::InputEnded | End::Stopped | End::Failed(_) => None,
            End::Frames(n) => Some(format!("stopped after {n} pose frames")),
            End::Time(t) => Some(format!("stopped after {:.1} s", t.as_secs_f64())),
            End::Idle(t) => Some(format!(
                "stopped: no pose frame for {:.1} s",
                t.as_secs_f64()
            )),
            End::Interrupted => Some("stopped: interrupted".into()),
        }
    }
}

/// What [`read_log`] hands over.
#[derive(Debug)]
#[allow(clippy::large_enum_variant)] // handed over by value, never stored
pub enum Event {
    /// A record, in arrival order.
    Record(Record),
    /// The records of a chunk read have all been handed over (also once per [`POLL`] while a
    /// serial port is quiet): time to flush output or refresh a display.
    Chunk,
}

/// Reads `input` until `until` or its end, decoding it with `decoder`, handing each
/// [`Event`] to `on_event`, which returns whether to go on (its answer to a record is
/// ignored).
pub fn read_log(
    input: &mut Input,
    decoder: &mut LogDecoder,
    until: Until,
    mut on_event: impl FnMut(Event) -> bool,
) -> End {
    let started = Instant::now();
    let mut last_pose: Option<Instant> = None;
    let mut poses = 0u64;
    let mut buf = vec![0u8; CHUNK];
    loop {
        if interrupt::requested() {
            return End::Interrupted;
        }
        let now = Instant::now();
        if let Some(t) = until.time.filter(|&t| now >= started + t) {
            return End::Time(t);
        }
        if let Some(t) = until
            .idle
            .filter(|&t| last_pose.is_some_and(|p| now >= p + t))
        {
            return End::Idle(t);
        }
        let n = match input.read(&mut buf) {
            Ok(Some(0)) => return End::InputEnded,
            Ok(Some(n)) => n,
            Ok(None) => {
                if !on_event(Event::Chunk) {
                    return End::Stopped;
                }
                continue;
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(error) => {
                return End::Failed(PortError::Read {
                    path: input.name().into(),
                    error,
                })
            }
        };
        let mut limit_reached = false;
        // One frame at most per piece: the limit on frames stops at a frame's delimiter.
        for piece in buf[..n].split_inclusive(|&b| b == 0) {
            decoder.feed(piece, |record| {
                if matches!(
                    record,
                    Record::Message {
                        message: Message::PoseFrame(_),
                        ..
                    }
                ) {
                    last_pose = Some(Instant::now());
                    poses += 1;
                }
                on_event(Event::Record(record));
            });
            if until.frames.is_some_and(|f| poses >= f) {
                limit_reached = true;
                break;
            }
        }
        if !on_event(Event::Chunk) {
            return End::Stopped;
        }
        if limit_reached {
            return End::Frames(poses);
        }
    }
}

/// Ctrl-C (SIGINT) and SIGTERM ask a reading to stop, so that what was decoded so far is
/// written out whole; a second one ends the process at once.
pub mod interrupt {
    use std::sync::atomic::{AtomicBool, Ordering};

    static REQUESTED: AtomicBool = AtomicBool::new(false);

    /// Whether a stop was asked for.
    pub fn requested() -> bool {
        REQUESTED.load(Ordering::SeqCst)
    }

    /// Installs the handler ([`ctrlc`], for SIGINT and SIGTERM; once per process, later calls
    /// do nothing): the first signal asks to stop, which the reading sees within a
    /// [`POLL`](super::POLL) (no read waits longer); a second ends the process at once
    /// (status 130). A program that has set its own handler keeps it.
    pub fn install() {
        static ONCE: std::sync::Once = std::sync::Once::new();
        ONCE.call_once(|| {
            let _ = ctrlc::set_handler(|| {
                if REQUESTED.swap(true, Ordering::SeqCst) {
                    std::process::exit(130);
                }
            });
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::packets::push_frame;
    use qgait_proto::{ModelId, PoseFrame, Status};

    fn pose(seq: u32) -> Message {
        Message::PoseFrame(PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: ModelId::Hak,
            angles: heapless::Vec::from_slice(&[0.0; 6]).unwrap(),
            points: [[0.5; 3]; 8],
            distances: [0.2; 3],
            flags: 0,
        })
    }

    #[test]
    fn a_limit_on_frames_stops_at_the_last_frames_delimiter() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.bin");
        let mut bytes = vec![0u8];
        for seq in 0..5 {
            push_frame(&mut bytes, &pose(seq));
            push_frame(&mut bytes, &Message::Status(Status::default()));
        }
        std::fs::write(&path, &bytes).unwrap();
        let name = path.to_str().unwrap();
        let (mut input, warning) = Input::open(name, Some(9600)).unwrap();
        assert!(!input.is_serial());
        assert_eq!(
            warning,
            Some(Warning::OptionIgnored(WarningText {
                at: None,
                detail: format!("--baud 9600 ignored: {name} is not a serial port"),
            }))
        );
        let mut decoder = LogDecoder::new();
        let mut seqs = Vec::new();
        let until = Until {
            frames: Some(3),
            ..Until::default()
        };
        let end = read_log(&mut input, &mut decoder, until, |e| {
            if let Event::Record(Record::Message {
                message: Message::PoseFrame(p),
                ..
            }) = e
            {
                seqs.push(p.seq);
            }
            true
        });
        assert!(matches!(end, End::Frames(3)), "{end:?}");
        assert_eq!(seqs, [0, 1, 2]);
        let counts = decoder.counts();
        assert_eq!(
            (counts.poses, counts.statuses, counts.unterminated),
            (3, 2, 0)
        );
        let (mut input, warning) = Input::open(name, None).unwrap();
        assert_eq!(warning, None);
        let end = read_log(&mut input, &mut LogDecoder::new(), Until::default(), |_| {
            true
        });
        assert!(matches!(end, End::InputEnded), "{end:?}");
        let e = Input::open(&format!("{name}.missing"), None).err().unwrap();
        assert!(
            matches!(&e, PortError::Open { path, error }
                if path.ends_with("log.bin.missing") && error.kind() == io::ErrorKind::NotFound),
            "{e:?}"
        );
        assert!(
            e.to_string().ends_with("log.bin.missing: cannot open"),
            "{e}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_baud_rate_of_0_is_refused_for_a_serial_port() {
        // The pseudo-terminal multiplexer is a terminal device on every Unix.
        let ptmx = "/dev/ptmx";
        if !Path::new(ptmx).exists() {
            eprintln!("skipped: no {ptmx}");
            return;
        }
        let e = Input::open(ptmx, Some(0)).err().unwrap();
        assert!(
            matches!(&e, PortError::ZeroBaud { path } if path == ptmx),
            "{e:?}"
        );
        assert_eq!(e.to_string(), "/dev/ptmx: a baud rate of 0 is not a rate");
    }
}
