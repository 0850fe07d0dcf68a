//! One run of the hub firmware under QEMU with a byte stream fed into its UART0: QEMU's UART is
//! connected to a Unix socket that this process binds, a thread writes the stream while this
//! one reads what the hub sends back, until the `Status` that answers the closing request.
//!
//! # Flow control
//!
//! The input is written as fast as the socket takes it: the emulated line is flow-controlled
//! end to end, so the hub takes bytes at the pace it consumes them, whatever it makes of them
//! (a damaged sample, which it answers with nothing, holds nothing up), and no byte is lost
//! however slowly the emulated CPU runs on a loaded machine:
//!
//! 1. QEMU's CMSDK UART model has a one-byte receive buffer and takes a host byte only when it
//!    is empty;
//! 2. behind QEMU's character multiplexer ([`Qemu::start_buffered`]) up to 32 more bytes wait
//!    ready for it (so the UART takes its next byte the moment the firmware reads one, several
//!    times faster than a round trip through QEMU's I/O thread per byte), and QEMU reads the
//!    socket only as far as that buffer has room;
//! 3. the firmware's receive interrupt moves bytes into its receive ring, and when the ring is
//!    full it leaves the next byte in the UART and stops until the application has read some
//!    (firmware `board/cmsdk_uart.rs`), so a hub busy writing a frame holds the line back
//!    instead of overrunning its ring (`uart_overruns` stays 0);
//! 4. so the socket fills and this process's writes block until the hub has read more.
//!
//! The session ends with [`closing_frames`], which start with a 0x00, so that noise at the end
//! of the stream (a burst of non-zero bytes runs into whatever frame follows) is a damaged frame
//! of its own and cannot swallow the closing request. The socket is kept open until QEMU has
//! been stopped, or the tail of the output would be lost.

use crate::EmulateError;
use std::io::{Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use qgait_proto::{FrameDecoder, Message, Status};

use crate::faults::{accepted, Accounting};
use crate::push_frame;
use crate::qemu::{escape, Echo, Qemu};

/// Bytes written to the socket at a time (between checks of the stop flag).
const CHUNK: usize = 4096;

/// Writes all of `input` (escaped for the multiplexer), blocking while the line is held back
/// (see the module docs), until done or `stop`; `written` counts the bytes the socket took.
fn write_input(
    mut w: UnixStream,
    input: &[u8],
    written: &AtomicUsize,
    stop: &AtomicBool,
) -> Result<(), EmulateError> {
    for chunk in input.chunks(CHUNK) {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        w.write_all(&escape(chunk))
            .map_err(EmulateError::io("writing to the UART socket"))?;
        written.fetch_add(chunk.len(), Ordering::Relaxed);
    }
    Ok(())
}

/// Limits of a session.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// The whole session (QEMU is stopped and the run fails after it).
    pub total: Duration,
    /// Longest time with no sign that the hub is consuming the input (the line taking more
    /// bytes, a pose frame, a status with higher counts): a hub that hangs or stops reading
    /// fails after this, however long the stream.
    pub stall: Duration,
    /// Longest wait for QEMU to connect to the socket.
    pub connect: Duration,
    /// After the first status that shows every input frame consumed, how long to wait for a
    /// later one (the answer to the closing request may follow a periodic status).
    pub grace: Duration,
}

impl Limits {
    /// Limits for a stream of `bytes` bytes: 30 s plus 1 ms per 10 bytes in all (QEMU's UART
    /// moves a byte in 10-40 µs on a busy 2-core machine, about 55 µs at a load average of 12),
    /// 20 s without progress.
    pub fn for_stream(bytes: usize) -> Limits {
        Limits {
            total: Duration::from_secs(30) + Duration::from_millis(bytes as u64 / 10),
            stall: Duration::from_secs(20),
            connect: Duration::from_secs(10),
            grace: Duration::from_millis(500),
        }
    }
}

/// What the input will make the hub count once it has consumed it all (the hub uses the same
/// decoder as the host, so these are exact).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InputCounts {
    /// Joint-angle packets with a usable angle and orientation packets with a unit-length
    /// quaternion (`packets_accepted`; what `accepted` says).
    pub accepted: u32,
    /// Frames the decoder rejects (the sum of the hub's decode-error counters).
    pub rejected: u32,
}

impl InputCounts {
    /// Counts `input` with the protocol's decoder.
    pub fn of(input: &[u8]) -> InputCounts {
        let mut c = InputCounts::default();
        for result in FrameDecoder::new().feed(input) {
            match result {
                Ok(ref m @ (Message::JointAngle(_) | Message::SegmentOrientation(_))) => {
                    c.accepted += u32::from(accepted(m))
                }
                // What a node fusing its own sensor takes (`qgait-node`; a hub counts it as
                // malformed, which the caller reports as a disagreement).
                Ok(Message::RawImuSample(_)) => c.accepted += 1,
                // A message only a hub sends is `malformed` at a hub, well-formed or not.
                Ok(Message::PoseFrame(_) | Message::Status(_)) => c.rejected += 1,
                Ok(_) => {}
                Err(_) => c.rejected += 1,
            }
        }
        c
    }

    /// What `status` shows counted.
    pub fn counted_by(s: &Status) -> InputCounts {
        InputCounts {
            accepted: s.packets_accepted,
            rejected: Accounting::decode_errors(s),
        }
    }

    /// Whether `status` shows all of it consumed: as many frames counted, accepted or
    /// rejected, as the input has (a hub that takes a message otherwise than expected, such as
    /// one built without the `imu` feature counting segment orientations as malformed, has
    /// still consumed them; the counts then disagree, which the caller reports).
    pub fn consumed_by(&self, s: &Status) -> bool {
        let got = Self::counted_by(s);
        u64::from(got.accepted) + u64::from(got.rejected)
            >= u64::from(self.accepted) + u64::from(self.rejected)
    }
}

/// The frames that end a session: a 0x00 (so that line noise just before cannot swallow them),
/// then `configuration` (the last `Config`, `SubjectConfig` or `ChainTableConfig` sent, or a
/// node's `RawImuConfig`, asking for its status) with its
/// reorder window
/// changed, which makes the hub close (and count) the samples still open in its window, and
/// a status request.
pub fn closing_frames(configuration: &Message) -> Result<Vec<u8>, EmulateError> {
    let toggle = |w: u8| if w == 1 { 2 } else { 1 };
    let closing = match configuration {
        Message::Config(c) => Message::Config(qgait_proto::Config {
            reorder_window: toggle(c.reorder_window),
            request_status: true,
            ..*c
        }),
        Message::SubjectConfig(c) => Message::SubjectConfig(qgait_proto::SubjectConfig {
            reorder_window: toggle(c.reorder_window),
            request_status: true,
            ..*c
        }),
        Message::ChainTableConfig(c) => Message::ChainTableConfig(qgait_proto::ChainTableConfig {
            reorder_window: toggle(c.reorder_window),
            request_status: true,
            ..c.clone()
        }),
        // A node's: the same settings (its fusion starts afresh, at the end), status asked.
        Message::RawImuConfig(c) => Message::RawImuConfig(qgait_proto::RawImuConfig {
            request_status: true,
            ..*c
        }),
        other => return Err(EmulateError::NotAConfiguration(other.tag())),
    };
    let mut out = vec![0u8];
    push_frame(&mut out, &closing);
    Ok(out)
}

/// What came back.
#[derive(Debug, Clone)]
pub struct SessionOutput {
    /// Every byte the hub sent on its UART.
    pub uart: Vec<u8>,
    /// The status answering the closing request (`None` if it never came).
    pub status: Option<Status>,
    /// The firmware's decoded defmt log.
    pub log: Vec<String>,
    /// Wall time from QEMU's start to the closing status.
    pub elapsed: Duration,
    /// Why the session did not end normally, if it did not.
    pub problem: Option<String>,
}

fn socket_path() -> PathBuf {
    static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir().join(format!("qgait-uart-{}-{n}.sock", std::process::id()))
}

fn accept(listener: &UnixListener, deadline: Instant) -> Result<UnixStream, EmulateError> {
    let setting = || EmulateError::io("setting up the UART socket");
    listener.set_nonblocking(true).map_err(setting())?;
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                stream.set_nonblocking(false).map_err(setting())?;
                return Ok(stream);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock && Instant::now() < deadline => {
                thread::sleep(Duration::from_millis(2))
            }
            Err(e) => return Err(EmulateError::NotConnected(e)),
        }
    }
}

/// Binds the UART socket, starts QEMU on it and accepts its connection.
fn connect(elf: &Path, echo: Echo, limits: &Limits) -> Result<(Qemu, UnixStream), EmulateError> {
    let socket = socket_path();
    let _ = std::fs::remove_file(&socket);
    let listener = UnixListener::bind(&socket)
        .map_err(EmulateError::io(format!("binding {}", socket.display())))?;
    let started = Qemu::start_buffered(elf, &socket, echo);
    let result = match started {
        Ok(qemu) => match accept(&listener, Instant::now() + limits.connect) {
            Ok(stream) => Ok((qemu, stream)),
            Err(e) => {
                qemu.stop();
                Err(e)
            }
        },
        Err(e) => Err(e),
    };
    let _ = std::fs::remove_file(&socket);
    result
}

/// Runs `elf`, writes `input` (which must end with [`closing_frames`]) into its UART and
/// collects the output until the status that answers the closing request. `expected` is
/// [`InputCounts::of`] the input.
pub fn run(
    elf: &Path,
    input: Vec<u8>,
    expected: InputCounts,
    echo: Echo,
    limits: Limits,
) -> Result<SessionOutput, EmulateError> {
    let started = Instant::now();
    let deadline = started + limits.total;
    let (qemu, mut stream) = connect(elf, echo, &limits)?;
    let writer = match (
        stream.try_clone(),
        stream.set_read_timeout(Some(Duration::from_millis(50))),
    ) {
        (Ok(w), Ok(())) => w,
        (Err(e), _) | (_, Err(e)) => {
            qemu.stop();
            return Err(EmulateError::Io {
                what: "setting up the UART socket".into(),
                error: e,
            });
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let written = Arc::new(AtomicUsize::new(0));
    let sender = {
        let (stop, written) = (stop.clone(), written.clone());
        thread::spawn(move || write_input(writer, &input, &written, &stop))
    };

    let mut uart = Vec::new();
    let mut decoder = FrameDecoder::new();
    let mut status = None;
    let mut done_at: Option<Instant> = None;
    let mut problem = None;
    let mut buf = [0u8; 4096];
    // Progress: input bytes the line took, frames consumed as the hub's status counts them.
    let (mut last_written, mut last_counted) = (0, 0u64);
    let mut progressed_at = started;
    loop {
        let now = Instant::now();
        if done_at.is_some_and(|t| now >= t + limits.grace) {
            break;
        }
        if now >= deadline {
            problem = Some(format!("no closing status within {:.0?}", limits.total));
            break;
        }
        let w = written.load(Ordering::Relaxed);
        if w != last_written {
            last_written = w;
            progressed_at = now;
        } else if now >= progressed_at + limits.stall {
            problem = Some(format!(
                "the hub consumed no input for {:.0?} (after {w} bytes written)",
                limits.stall
            ));
            break;
        }
        let n = match stream.read(&mut buf) {
            Ok(0) => {
                problem = Some("QEMU closed the UART (the firmware stopped?)".into());
                break;
            }
            Ok(n) => n,
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                continue
            }
            Err(e) => {
                problem = Some(format!("reading the UART socket: {e}"));
                break;
            }
        };
        uart.extend_from_slice(&buf[..n]);
        for message in decoder.feed(&buf[..n]).flatten() {
            match message {
                Message::PoseFrame(_) => progressed_at = Instant::now(),
                Message::Status(s) => {
                    let c = InputCounts::counted_by(&s);
                    let counted = u64::from(c.accepted) + u64::from(c.rejected);
                    if counted > last_counted {
                        last_counted = counted;
                        progressed_at = Instant::now();
                    }
                    if expected.consumed_by(&s) {
                        done_at.get_or_insert_with(Instant::now);
                        status = Some(s);
                    }
                }
                _ => {}
            }
        }
    }
    let elapsed = started.elapsed();
    // The firmware logs after sending a status: let that line through, then stop QEMU before
    // closing the socket.
    thread::sleep(Duration::from_millis(50));
    stop.store(true, Ordering::Relaxed);
    let finished = qemu.stop();
    drop(stream);
    if let Ok(Err(e)) = sender.join() {
        if problem.is_none() && status.is_none() {
            problem = Some(e.to_string());
        }
    }
    Ok(SessionOutput {
        uart,
        status,
        log: finished.log,
        elapsed,
        problem,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_proto::{Config, MissingPolicy, ModelId};

    #[test]
    fn input_counted_otherwise_than_expected_is_still_consumed() {
        let input = InputCounts {
            accepted: 10,
            rejected: 2,
        };
        // A hub without the `imu` feature: the orientations counted as malformed.
        let otherwise = Status {
            malformed: 12,
            ..Status::default()
        };
        assert!(input.consumed_by(&otherwise));
        assert_ne!(InputCounts::counted_by(&otherwise), input);
        let partway = Status {
            packets_accepted: 9,
            crc_errors: 2,
            ..Status::default()
        };
        assert!(!input.consumed_by(&partway));
    }

    #[test]
    fn the_closing_request_survives_noise_just_before_it() {
        let config = Message::Config(Config {
            model: ModelId::Phak,
            anthropometry: None,
            missing_policy: MissingPolicy::Drop,
            reorder_window: 4,
            request_status: false,
        });
        // A stream that ends with a burst of non-zero noise, no delimiter after it.
        let mut input = vec![0u8];
        input.extend((1..=40u8).map(|i| i.wrapping_mul(37) | 1));
        input.extend(closing_frames(&config).unwrap());
        let results: Vec<_> = FrameDecoder::new().feed(&input).collect();
        assert_eq!(results.len(), 2, "{results:?}");
        assert!(
            results[0].is_err(),
            "the noise is a damaged frame of its own"
        );
        let Ok(Message::Config(c)) = &results[1] else {
            panic!("{results:?}")
        };
        assert!(c.request_status && c.reorder_window != 4, "{c:?}");
        let counts = InputCounts::of(&input);
        assert_eq!((counts.accepted, counts.rejected), (0, 1));
    }

    #[test]
    fn a_message_only_a_hub_sends_counts_as_one_the_hub_rejects() {
        let status = Message::Status(qgait_proto::Status::default());
        let mut input = Vec::new();
        push_frame(&mut input, &status);
        let p = crate::packet(1, 0, qgait_proto::JointId::KneeAngleR, 0.1);
        push_frame(&mut input, &Message::JointAngle(p));
        let counts = InputCounts::of(&input);
        assert_eq!((counts.accepted, counts.rejected), (1, 1));
    }
}
