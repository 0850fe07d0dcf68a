//! The hub's counters: every [`Status`] counter wraps. Which counter a
//! decode error goes to is the protocol's
//! [`Status::count_decode_error`](qgait_proto::Status::count_decode_error).

use qgait_proto::Status;

use crate::assembly::PacketOutcome;

/// Adds one to a wrapping counter.
pub fn bump(counter: &mut u32) {
    *counter = counter.wrapping_add(1);
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
