//! Whole frames: message bytes + CRC-32C (little-endian) → COBS → 0x00.

use crate::crc::{self, crc32c};
use crate::wire::{
    encode_pose_frame_message, encode_pose_frame_parts_message, encode_pose_velocities_message,
    encode_raw_imu_status_message, encode_segment_orientation_message, encode_status_message,
    PoseFrameParts,
};
use crate::{
    cobs, decode_message, encode_message, DecodeError, EncodeError, Message, PoseFrame,
    PoseVelocities, RawImuStatus, SegmentOrientation, Status, CRC_LEN, MAX_MESSAGE_LEN,
    MIN_PAYLOAD_LEN,
};

/// Encodes `msg` as one complete frame into `out` and returns it, trailing 0x00 included.
///
/// An `out` of [`MAX_FRAME_LEN`](crate::MAX_FRAME_LEN) bytes always suffices.
pub fn encode_frame<'a>(msg: &Message, out: &'a mut [u8]) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| encode_message(msg, payload).map(|m| m.len()))
}

/// [`encode_frame`] of `Message::PoseFrame(frame)`, without building the [`Message`]: the same
/// bytes (the hub's path for every pose it sends).
pub fn encode_pose_frame<'a>(
    frame: &PoseFrame,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| {
        encode_pose_frame_message(frame, payload).map(|m| m.len())
    })
}

/// [`encode_pose_frame`] of the pose frame `parts` make, without building the [`PoseFrame`]:
/// the same bytes, its angles and points read where they are as they are written (the hub
/// sends each pose this way, straight from the sample and the kinematics' pose).
pub fn encode_pose_frame_parts<'a, A, P>(
    parts: &PoseFrameParts<A, P>,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError>
where
    A: Fn(usize) -> f32,
    P: Fn(usize) -> [f32; 3],
{
    encode_frame_with(out, |payload| {
        encode_pose_frame_parts_message(parts, payload).map(|m| m.len())
    })
}

/// [`encode_frame`] of `Message::Status(status)`, without building the [`Message`]: the same
/// bytes (the hub's path for its status frames, which links no other message's serialiser).
pub fn encode_status_frame<'a>(
    status: &Status,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| {
        encode_status_message(status, payload).map(|m| m.len())
    })
}

/// [`encode_frame`] of `Message::SegmentOrientation(packet)`, without building the
/// [`Message`]: the same bytes (a node's path, which links no other message's serialiser).
pub fn encode_segment_orientation_frame<'a>(
    packet: &SegmentOrientation,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| {
        encode_segment_orientation_message(packet, payload)
    })
}

/// [`encode_frame`] of `Message::RawImuStatus(status)`, without building the [`Message`]: the
/// same bytes.
pub fn encode_raw_imu_status_frame<'a>(
    status: &RawImuStatus,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| {
        encode_raw_imu_status_message(status, payload)
    })
}

/// [`encode_frame`] of `Message::PoseVelocities(velocities)`, without building the
/// [`Message`]: the same bytes (the hub's path, which links no message serialiser).
pub fn encode_pose_velocities_frame<'a>(
    velocities: &PoseVelocities,
    out: &'a mut [u8],
) -> Result<&'a [u8], EncodeError> {
    encode_frame_with(out, |payload| {
        encode_pose_velocities_message(velocities, payload)
    })
}

/// Frames the message `write` puts at the start of the slice it is given, which is `out`
/// after the first byte (the first code byte) when there is room for it: the message is
/// written once, in place, its CRC appended after it, and the whole COBS-encoded where it is.
/// Otherwise (an `out` too small for that, or a message too long for in-place COBS) through a
/// temporary buffer, which also reports the exact size needed.
fn encode_frame_with(
    out: &mut [u8],
    write: impl Fn(&mut [u8]) -> Result<usize, EncodeError>,
) -> Result<&[u8], EncodeError> {
    if let Some(len) = encode_frame_in_place(out, &write)? {
        return Ok(out.get(..len).unwrap_or(&[]));
    }
    let mut payload = [0u8; MAX_MESSAGE_LEN];
    let len = write(&mut payload)?;
    encode_raw_frame(payload.get(..len).unwrap_or(&[]), out)
}

/// The in-place path of [`encode_frame_with`]: `Ok(Some(frame length))`, `Ok(None)` if it does
/// not apply, or the message's own error (other than a short buffer).
fn encode_frame_in_place(
    out: &mut [u8],
    write: &impl Fn(&mut [u8]) -> Result<usize, EncodeError>,
) -> Result<Option<usize>, EncodeError> {
    let Some(message) = out.get_mut(1..) else {
        return Ok(None);
    };
    let len = match write(message) {
        Ok(len) => len,
        Err(EncodeError::BufferTooSmall { .. }) => return Ok(None),
        Err(e) => return Err(e),
    };
    let Some((body, tail)) = message.split_at_mut_checked(len) else {
        return Ok(None);
    };
    let Some(crc_slot) = tail.get_mut(..CRC_LEN) else {
        return Ok(None);
    };
    crc_slot.copy_from_slice(&crc32c(body).to_le_bytes());
    Ok(cobs::encode_in_place(out, len + CRC_LEN))
}

/// Frames arbitrary `payload` bytes: appends their CRC-32C, COBS-encodes, appends 0x00.
///
/// This is the framing of [`encode_frame`] without the message encoding: for tools and tests
/// that need frames with contents a [`Message`] cannot express (e.g. an unknown joint byte).
pub fn encode_raw_frame<'a>(payload: &[u8], out: &'a mut [u8]) -> Result<&'a [u8], EncodeError> {
    let needed = cobs::max_encoded_len(payload.len() + CRC_LEN) + 1;
    let crc = crc32c(payload).to_le_bytes();
    let bytes = payload.iter().copied().chain(crc);
    let len = cobs::encode(bytes, out).ok_or(EncodeError::BufferTooSmall { needed })?;
    *out.get_mut(len)
        .ok_or(EncodeError::BufferTooSmall { needed })? = 0;
    Ok(out.get(..=len).unwrap_or(&[]))
}

/// Decodes the COBS bytes of one frame, delimiter excluded, in place (`frame` is overwritten).
///
/// Checks, in order: COBS ([`DecodeError::Cobs`]), length ([`DecodeError::TooShort`]),
/// CRC ([`DecodeError::Crc`]), then the message ([`decode_message`]).
pub fn decode_frame(frame: &mut [u8]) -> Result<Message, DecodeError> {
    decode_message(check_frame(frame)?)
}

/// The checks of [`decode_frame`] before the message: COBS-decodes `frame` in place, checks
/// its length and CRC, and returns the message bytes (CRC excluded).
pub(crate) fn check_frame(frame: &mut [u8]) -> Result<&[u8], DecodeError> {
    let range = cobs::decode_in_place_unshifted(frame).map_err(|_| DecodeError::Cobs)?;
    let payload = frame.get(range).ok_or(DecodeError::Cobs)?;
    let len = payload.len();
    if len < MIN_PAYLOAD_LEN {
        return Err(DecodeError::TooShort);
    }
    // The message followed by its CRC leaves the register at the residue iff the CRC matches.
    if crc::update(crc::INIT, payload) != crc::RESIDUE {
        return Err(DecodeError::Crc);
    }
    Ok(payload.get(..len - CRC_LEN).unwrap_or(&[]))
}
