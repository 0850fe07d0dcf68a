//! The hub's counters: every [`Status`](qgait_proto::Status) counter wraps. Which counter a
//! decode error goes to is the protocol's
//! [`Status::count_decode_error`](qgait_proto::Status::count_decode_error).

use embedded_hal_nb::serial::ErrorKind as LineErrorKind;
use qgait_proto::Status;

use crate::assembly::PacketOutcome;

/// Adds one to a wrapping counter.
pub fn bump(counter: &mut u32) {
    *counter = counter.wrapping_add(1);
}

/// Counts a line error the serial port reported: an overrun as such; parity, noise and line
/// framing as a framing error (the frame's CRC or COBS check fails too).
#[inline(always)]
pub fn count_line_error(status: &mut Status, kind: LineErrorKind) {
    match kind {
        LineErrorKind::Overrun => bump(&mut status.uart_overruns),
        _ => bump(&mut status.framing_errors),
    }
}

/// Whether a periodic status is due at `now_ms`, the last one sent at `last_ms`, one every
/// `period_ms` (0: never).
#[inline(always)]
pub fn status_due(now_ms: u32, last_ms: u32, period_ms: u32) -> bool {
    period_ms != 0 && now_ms.wrapping_sub(last_ms) >= period_ms
}

/// Counts what the reorder window did with a packet (joint angle or segment orientation):
/// late and duplicate packets have their counters; stored ones are counted when their sample
/// leaves the window.
pub fn count_outcome(status: &mut Status, outcome: PacketOutcome) {
    match outcome {
        PacketOutcome::Late => bump(&mut status.late_packets),
        PacketOutcome::Duplicate => bump(&mut status.duplicate_packets),
        PacketOutcome::Stored | PacketOutcome::Resynced | PacketOutcome::NotRequired => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_wrap() {
        let mut c = u32::MAX;
        bump(&mut c);
        assert_eq!(c, 0);
    }
}
