//! Mapping of every event of the pipeline to a [`Status`] counter.

use qgait_proto::{DecodeError, ErrorKind, Status};

/// Adds one to a wrapping counter.
pub fn bump(counter: &mut u32) {
    *counter = counter.wrapping_add(1);
}

/// Counts a frame the decoder rejected in the matching [`Status`] field.
pub fn count_decode_error(status: &mut Status, error: &DecodeError) {
    let counter = match error.kind() {
        ErrorKind::Crc => &mut status.crc_errors,
        ErrorKind::Cobs | ErrorKind::TooShort => &mut status.framing_errors,
        ErrorKind::Oversize => &mut status.oversize_frames,
        ErrorKind::UnknownMessage | ErrorKind::UnknownVersion => &mut status.unknown_version,
        ErrorKind::UnknownJoint => &mut status.unknown_joint,
        // UnknownModel, AngleCount, Malformed, and kinds added by later protocol versions.
        _ => &mut status.malformed,
    };
    bump(counter);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_decode_error_lands_in_its_counter() {
        let mut s = Status::default();
        count_decode_error(&mut s, &DecodeError::Crc);
        count_decode_error(&mut s, &DecodeError::Cobs);
        count_decode_error(&mut s, &DecodeError::TooShort);
        count_decode_error(&mut s, &DecodeError::Oversize);
        count_decode_error(&mut s, &DecodeError::UnknownVersion(9));
        count_decode_error(&mut s, &DecodeError::UnknownMessage(9));
        count_decode_error(&mut s, &DecodeError::UnknownJoint(99));
        count_decode_error(&mut s, &DecodeError::UnknownModel(7));
        count_decode_error(&mut s, &DecodeError::Malformed);
        let expected = Status {
            crc_errors: 1,
            framing_errors: 2,
            oversize_frames: 1,
            unknown_version: 2,
            unknown_joint: 1,
            malformed: 2,
            ..Status::default()
        };
        assert_eq!(s, expected);
    }

    #[test]
    fn counters_wrap() {
        let mut c = u32::MAX;
        bump(&mut c);
        assert_eq!(c, 0);
    }
}
