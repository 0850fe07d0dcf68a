//! The serial line's side of a device, the same for the hub and the IMU node
//! (`qgait-node`): a read that never blocks and counts line errors, a frame written whole and
//! counted, and the schedule of unsolicited status frames.

use embedded_hal_nb::serial::{Error as LineError, ErrorKind as LineErrorKind};
use embedded_io::{Read, ReadReady, Write};
use qgait_proto::{FrameDecoder, Status};

use crate::counters::bump;

/// Reads into `rx` what the port has, without blocking: `Some(n)` for `n` bytes read (0 after
/// a line error, which is counted in `status`), `None` when the port has nothing.
///
/// An overrun counts as such; any other line error (parity, noise, line framing) as a
/// framing error: the frame's CRC or COBS check would fail too.
#[inline(always)]
pub fn read_some<S>(serial: &mut S, rx: &mut [u8], status: &mut Status) -> Option<usize>
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

/// Takes the data bytes of `rx[*pos..n]` from `*pos` on into `decoder`, straight into its
/// buffer, and moves `*pos` past them: `true` if a 0x00 ends them (`*pos` then past it too),
/// after which [`FrameDecoder::end_frame`] gives the frame; `false` if they run to `n`, the
/// frame going on in the next read. An oversize frame is counted in `status` once.
#[inline(always)]
pub fn frame_end(
    decoder: &mut FrameDecoder,
    rx: &[u8],
    pos: &mut usize,
    n: usize,
    status: &mut Status,
) -> bool {
    let (run, oversize) = decoder.push_run(rx.get(*pos..n).unwrap_or_default());
    if let Some(error) = oversize {
        status.count_decode_error(&error);
    }
    *pos += run;
    if *pos >= n {
        return false;
    }
    *pos += 1;
    true
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

    #[test]
    fn a_zero_period_is_never_due() {
        let s = StatusSchedule::new(0, 0);
        assert!(!s.due(0));
        assert!(!s.due(u32::MAX));
    }
}
