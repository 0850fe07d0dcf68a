//! A device's end of the serial line, the same for the hub and the IMU node (`qgait-node`):
//! the [`Line`] (port, clock, frame decoder, counters, status schedule, receive buffer), the
//! [`poll`] that reads what the port has and hands it to the device ([`LineDevice`]), a read
//! that never blocks and counts line errors, a frame written whole and counted.

use embedded_hal_nb::serial::{Error as LineError, ErrorKind as LineErrorKind};
use embedded_io::{ErrorType, Read, ReadReady, Write};
use qgait_proto::{encode_status_frame, FrameDecoder, Status};

use crate::clock::Clock;
use crate::counters::bump;

/// A serial port as the hub and the node take it: `embedded-io` reads that can say whether
/// they would block, and writes; its errors classify themselves as `embedded-hal-nb` serial
/// errors do (an overrun is counted as such, any other line error as a framing error).
pub trait SerialPort: Read + ReadReady + Write + ErrorType<Error: LineError> {}

impl<T: Read + ReadReady + Write + ErrorType<Error: LineError>> SerialPort for T {}

/// What one poll did ([`Hub::poll`](crate::Hub::poll), the node's `poll`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PollSummary {
    /// Bytes read from the serial port.
    pub bytes: u32,
    /// Frames written (poses or orientations, and status).
    pub frames_sent: u32,
    /// Whether one of them was a status frame (periodic or requested).
    pub status_sent: bool,
}

/// A device's end of the serial line: its port and clock, the frames being received, its
/// counters and status schedule, and the bytes of the last read (`RX` of them at most).
pub struct Line<S, C, const RX: usize> {
    /// The serial port.
    pub serial: S,
    /// The device's millisecond clock.
    pub clock: C,
    /// The frame being received.
    pub decoder: FrameDecoder,
    /// The counters (their `uptime_ms` is filled in by [`status`](Line::status)).
    pub status: Status,
    /// When the next unsolicited status is due.
    pub schedule: StatusSchedule,
    /// The bytes of the last read, handled before the next.
    pub rx: [u8; RX],
}

impl<S, C: Clock, const RX: usize> Line<S, C, RX> {
    /// A line with nothing received, a status every `status_period_ms` (0: only on request).
    pub fn new(serial: S, clock: C, status_period_ms: u32) -> Self {
        let now = clock.now_ms();
        Line {
            serial,
            clock,
            decoder: FrameDecoder::new(),
            status: Status::default(),
            schedule: StatusSchedule::new(now, status_period_ms),
            rx: [0; RX],
        }
    }

    /// The counters, with the current uptime.
    pub fn status(&self) -> Status {
        Status {
            uptime_ms: self.schedule.uptime_ms(self.clock.now_ms()),
            ..self.status
        }
    }

    /// Sends the counters as a `Status` frame, encoded in `tx` (a status counts itself in
    /// `frames_sent`), and notes it in the schedule. A `tx` too short for a status (which the
    /// devices' buffers rule out) sends nothing.
    pub fn send_status(&mut self, tx: &mut [u8])
    where
        S: Write,
    {
        self.schedule.sent_at(self.clock.now_ms());
        let mut status = self.status();
        status.frames_sent = status.frames_sent.wrapping_add(1);
        if let Ok(frame) = encode_status_frame(&status, tx) {
            write_frame(&mut self.serial, &mut self.status, frame);
        }
    }

    /// Takes the data bytes of the receive buffer's first `n` from `*pos` on into the decoder,
    /// straight into its buffer, and moves `*pos` past them: `true` if a 0x00 ends them
    /// (`*pos` then past it too), after which [`FrameDecoder::end_frame`] gives the frame;
    /// `false` if they run to `n`, a frame's start staying in the decoder until the next read.
    /// An oversize frame is counted once.
    #[inline(always)]
    pub fn frame_end(&mut self, pos: &mut usize, n: usize) -> bool {
        // No further than the buffer, whatever `n` a caller gives.
        let n = n.min(RX);
        if *pos >= n {
            return false;
        }
        let (run, oversize) = self
            .decoder
            .push_run(self.rx.get(*pos..n).unwrap_or_default());
        if let Some(error) = oversize {
            self.status.count_decode_error(&error);
        }
        *pos += run;
        if *pos >= n {
            return false;
        }
        *pos += 1;
        true
    }

    /// The next frame in the receive buffer's first `n` bytes, from `*pos` on, as
    /// [`frame_end`](Self::frame_end) finds it: `None` if there is none, else `Some` of the
    /// frame's message if its checks (COBS, CRC) pass, `Some(None)` if it was empty or failed
    /// them (the failure counted).
    #[inline(always)]
    pub fn next_frame(&mut self, pos: &mut usize, n: usize) -> Option<Option<&[u8]>> {
        if !self.frame_end(pos, n) {
            return None;
        }
        match self.decoder.end_frame() {
            None => Some(None),
            Some(Ok(message)) => Some(Some(message)),
            Some(Err(error)) => {
                self.status.count_decode_error(&error);
                Some(None)
            }
        }
    }
}

/// A device on a [`Line`], as [`poll`] drives it: the hub and the IMU node. Its methods are
/// `poll`'s steps, public because the node is another crate; an application calls the
/// device's own `poll`.
pub trait LineDevice<S, C, const RX: usize> {
    /// Its line.
    fn line(&mut self) -> &mut Line<S, C, RX>;
    /// Handles the first `n` bytes of the line's receive buffer (`n` ≤ `RX`).
    fn on_bytes(&mut self, n: usize);
    /// Sends its status now (noting it in the line's schedule).
    fn send_status(&mut self);
}

/// Reads what the device's port has, at most `max_bytes` in reads of at most `RX`, hands
/// each read to the device, then has it send its periodic status if due. A line error is
/// counted and the reads go on (it is not a byte).
#[inline(always)]
pub fn poll<D, S, C, const RX: usize>(device: &mut D, max_bytes: usize) -> PollSummary
where
    D: LineDevice<S, C, RX>,
    S: SerialPort,
    C: Clock,
{
    let line = device.line();
    let sent_before = line.status.frames_sent;
    let statuses_before = line.schedule.sent();
    let mut bytes = 0;
    while bytes < max_bytes {
        let line = device.line();
        let want = RX.min(max_bytes - bytes);
        let Some(n) = read_some(&mut line.serial, &mut line.rx[..want], &mut line.status) else {
            break;
        };
        bytes += n;
        device.on_bytes(n);
    }
    let line = device.line();
    if line.schedule.due(line.clock.now_ms()) {
        device.send_status();
    }
    let line = device.line();
    PollSummary {
        bytes: bytes as u32,
        frames_sent: line.status.frames_sent.wrapping_sub(sent_before),
        status_sent: line.schedule.sent() != statuses_before,
    }
}

/// Reads into `rx` what the port has, without blocking: `Some(n)` for `n` bytes read (0 after
/// a line error, which is counted in `status`), `None` when the port has nothing.
///
/// An overrun counts as such; any other line error (parity, noise, line framing) as a
/// framing error: the frame's CRC or COBS check would fail too.
#[inline(always)]
fn read_some<S>(serial: &mut S, rx: &mut [u8], status: &mut Status) -> Option<usize>
where
    S: Read + ReadReady,
    S::Error: LineError,
{
    // Only what is there: `read` would block on an empty port.
    if !matches!(serial.read_ready(), Ok(true)) {
        return None;
    }
    match serial.read(rx) {
        // Nothing after all (a port at its end): as if nothing was ready.
        Ok(0) => None,
        Ok(n) => Some(n.min(rx.len())),
        Err(e) => {
            match e.kind() {
                LineErrorKind::Overrun => bump(&mut status.uart_overruns),
                _ => bump(&mut status.framing_errors),
            }
            Some(0)
        }
    }
}

/// Writes `frame`, in one `write` call if the port takes it all (a UART driver does); counts
/// it in `status.frames_sent` if the whole frame went out. A write that fails, or takes
/// nothing, ends the frame there (uncounted): the receiver's decoder drops the partial frame
/// at the next 0x00.
pub fn write_frame<S: Write>(serial: &mut S, status: &mut Status, mut frame: &[u8]) {
    while !frame.is_empty() {
        match serial.write(frame) {
            Ok(n) if n > 0 => frame = frame.get(n..).unwrap_or_default(),
            _ => return,
        }
    }
    bump(&mut status.frames_sent);
}

/// When a device last sent its status, how often it sends one unasked, and since when it
/// has been up (all in its clock's wrapping milliseconds).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StatusSchedule {
    started_ms: u32,
    last_ms: u32,
    period_ms: u32,
    sent: u32,
}

impl StatusSchedule {
    /// Started at `now_ms`, a status every `period_ms` (0: only on request).
    pub const fn new(now_ms: u32, period_ms: u32) -> Self {
        StatusSchedule {
            started_ms: now_ms,
            last_ms: now_ms,
            period_ms,
            sent: 0,
        }
    }

    /// Whether the periodic status is due at `now_ms`.
    #[inline(always)]
    pub fn due(&self, now_ms: u32) -> bool {
        self.period_ms != 0 && now_ms.wrapping_sub(self.last_ms) >= self.period_ms
    }

    /// Milliseconds up at `now_ms`.
    pub fn uptime_ms(&self, now_ms: u32) -> u32 {
        now_ms.wrapping_sub(self.started_ms)
    }

    /// Notes a status sent at `now_ms` (periodic or requested): the next periodic one is a
    /// period later.
    pub fn sent_at(&mut self, now_ms: u32) {
        self.last_ms = now_ms;
        self.sent = self.sent.wrapping_add(1);
    }

    /// Statuses sent (wrapping), to tell whether a poll sent one.
    pub fn sent(&self) -> u32 {
        self.sent
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_status_is_due_a_period_after_the_last() {
        let mut s = StatusSchedule::new(u32::MAX - 10, 100);
        assert!(!s.due(u32::MAX - 10));
        assert!(!s.due(88));
        assert!(s.due(89), "the period counts across the clock's wrap");
        s.sent_at(89);
        assert!(!s.due(188));
        assert!(s.due(189));
        assert_eq!(s.sent(), 1);
        assert_eq!(s.uptime_ms(89), 100);
    }

    use crate::ManualClock;
    use qgait_proto::{decode_message, Message, MAX_FRAME_LEN};

    /// A line whose receive buffer holds `bytes`, with `()` as its port.
    fn line_holding(bytes: &[u8]) -> Line<(), ManualClock, 256> {
        let mut line = Line::new((), ManualClock::new(0), 0);
        line.rx[..bytes.len()].copy_from_slice(bytes);
        line
    }

    #[test]
    fn frames_come_whole_and_failed_ones_are_counted() {
        let mut good = [0; MAX_FRAME_LEN];
        let sent = Status {
            frames_sent: 7,
            ..Status::default()
        };
        let good = encode_status_frame(&sent, &mut good).unwrap();
        // A good frame, an empty one, a damaged copy of the good one, and half of the good one.
        let mut bytes = [0u8; 256];
        let mut len = 0;
        for part in [good, &[0][..], good, &good[..good.len() / 2]] {
            bytes[len..len + part.len()].copy_from_slice(part);
            len += part.len();
        }
        let damaged = good.len() + 1 + 2;
        bytes[damaged] ^= 0x40;
        let mut line = line_holding(&bytes[..len]);
        let mut pos = 0;
        let first = line.next_frame(&mut pos, len).unwrap().unwrap();
        assert_eq!(decode_message(first), Ok(Message::Status(sent)));
        assert_eq!(pos, good.len());
        assert_eq!(
            line.next_frame(&mut pos, len),
            Some(None),
            "the empty frame"
        );
        assert_eq!(
            line.next_frame(&mut pos, len),
            Some(None),
            "the damaged frame"
        );
        assert_eq!(
            line.status.crc_errors + line.status.framing_errors + line.status.malformed,
            1
        );
        assert_eq!(line.next_frame(&mut pos, len), None, "half a frame waits");
        assert_eq!(pos, len);
        // Its other half, in the next read, completes it.
        let rest = &good[good.len() / 2..];
        line.rx[..rest.len()].copy_from_slice(rest);
        let mut pos = 0;
        let last = line.next_frame(&mut pos, rest.len()).unwrap().unwrap();
        assert_eq!(decode_message(last), Ok(Message::Status(sent)));
        assert_eq!(line.next_frame(&mut pos, rest.len()), None);
    }

    #[test]
    fn frames_end_within_the_buffer_whatever_the_count() {
        let mut line: Line<(), ManualClock, 8> = Line::new((), ManualClock::new(0), 0);
        line.rx = [0x55; 8];
        let mut pos = 0;
        assert!(!line.frame_end(&mut pos, usize::MAX));
        assert_eq!(pos, 8);
        assert_eq!(line.next_frame(&mut pos, usize::MAX), None);
    }

    #[test]
    fn a_zero_period_is_never_due() {
        let s = StatusSchedule::new(0, 0);
        assert!(!s.due(0));
        assert!(!s.due(u32::MAX));
    }
}
