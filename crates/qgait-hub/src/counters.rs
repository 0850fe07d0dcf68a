//! The hub's counters: every [`Status`](qgait_proto::Status) counter wraps. Which counter a
//! decode error goes to is the protocol's
//! [`Status::count_decode_error`](qgait_proto::Status::count_decode_error).

/// Adds one to a wrapping counter.
pub fn bump(counter: &mut u32) {
    *counter = counter.wrapping_add(1);
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
