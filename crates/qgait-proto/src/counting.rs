//! [`Status::count_decode_error`]: which [`Status`] counter each [`DecodeError`] goes to.

use crate::{DecodeError, Status};

impl Status {
    /// Adds one (wrapping) to the counter of `error`:
    ///
    /// | error | counter |
    /// | --- | --- |
    /// | `Crc` | `crc_errors` |
    /// | `Cobs`, `TooShort` | `framing_errors` |
    /// | `Oversize` | `oversize_frames` |
    /// | `UnknownVersion`, `UnknownMessage` | `unknown_version` |
    /// | `UnknownJoint`, `UnknownSegment` | `unknown_joint` |
    /// | `UnknownModel`, `AngleCount`, `Malformed` | `malformed` |
    pub fn count_decode_error(&mut self, error: &DecodeError) {
        let counter = match error {
            DecodeError::Crc => &mut self.crc_errors,
            DecodeError::Cobs | DecodeError::TooShort => &mut self.framing_errors,
            DecodeError::Oversize => &mut self.oversize_frames,
            DecodeError::UnknownVersion(_) | DecodeError::UnknownMessage(_) => {
                &mut self.unknown_version
            }
            DecodeError::UnknownJoint(_) | DecodeError::UnknownSegment(_) => {
                &mut self.unknown_joint
            }
            DecodeError::UnknownModel(_)
            | DecodeError::AngleCount { .. }
            | DecodeError::Malformed => &mut self.malformed,
        };
        *counter = counter.wrapping_add(1);
    }
}
