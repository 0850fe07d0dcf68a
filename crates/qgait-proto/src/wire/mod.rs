//! Message bytes (postcard, no framing): [`encode_message`] and [`decode_message`].
//!
//! - `encode.rs`: the hand-written encoders of a [`PoseFrame`] and a [`Status`] (every other
//!   message goes through postcard's serialiser);
//! - `decode.rs`: the decoders of the message bodies (one for each body with values to check,
//!   one for the plain ones), and the hub's entry points
//!   ([`decode_packet`], [`decode_hub_message`]);
//! - `varint.rs`: postcard's `u32` varint, and its deserialiser one field at a time.
//!
//! Decoding reads the message tag, the protocol version and the joint and model fields as raw
//! bytes, so that an unknown tag, version, joint or model is reported as its own
//! [`DecodeError`] instead of a generic postcard error. The layout is postcard's (documented in
//! `docs/protocol.md`); the tests hold the hand-written parts to postcard itself.

mod decode;
mod encode;
mod varint;

pub use decode::{decode_hub_message, decode_node_message, decode_packet, HubMessage, NodeMessage};
pub use encode::PoseFrameParts;
pub(crate) use encode::{
    encode_pose_frame_message, encode_pose_frame_parts_message, encode_pose_velocities_message,
    encode_raw_imu_status_message, encode_segment_orientation_message, encode_status_message,
};

use crate::{DecodeError, EncodeError, Message, ModelId, MAX_MESSAGE_LEN};

/// Encodes `msg` as postcard bytes (no CRC, no framing) into `out`, returning the used part.
///
/// At most [`MAX_MESSAGE_LEN`] bytes are written. Fails if `out` is too small, or if a
/// [`PoseFrame`](crate::PoseFrame) does not have exactly `model.required_joints().len()`
/// angles.
pub fn encode_message<'a>(msg: &Message, out: &'a mut [u8]) -> Result<&'a mut [u8], EncodeError> {
    if let Message::PoseFrame(frame) = msg {
        return encode_pose_frame_message(frame, out);
    }
    postcard::to_slice(msg, out).map_err(|_| EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    })
}

/// Decodes one message from its postcard bytes (no CRC, no framing). Every byte must be used.
// Never inlined: with a single caller (a device's benchmark) the compiler would inline all the
// decoders there, and the joint-angle fast path at its head costs twice as much inlined.
#[inline(never)]
pub fn decode_message(bytes: &[u8]) -> Result<Message, DecodeError> {
    if let Some(packet) = decode_packet(bytes) {
        return packet.map(Message::JointAngle);
    }
    let (tag, body) = varint::take::<u32>(bytes)?;
    match tag {
        0 => decode::joint_angle(body).map(Message::JointAngle),
        1 => decode::pose_frame(body).map(Message::PoseFrame),
        2 => decode::plain(body).map(Message::Status),
        3 => decode::config(body).map(Message::Config),
        4 => decode::subject_leg(body).map(Message::SubjectLeg),
        5 => decode::subject_knee(body).map(Message::SubjectKnee),
        6 => decode::subject_config(body).map(Message::SubjectConfig),
        7 => decode::segment_orientation(body).map(Message::SegmentOrientation),
        8 => decode::imu_config(body).map(Message::ImuConfig),
        crate::CHAIN_TABLE_TAG => decode::chain_table(body).map(Message::ChainTable),
        crate::CHAIN_TABLE_CONFIG_TAG => {
            decode::chain_table_config(body).map(Message::ChainTableConfig)
        }
        crate::RAW_IMU_SAMPLE_TAG => decode::raw_imu_sample(body).map(Message::RawImuSample),
        crate::RAW_IMU_CONFIG_TAG => decode::raw_imu_config(body).map(Message::RawImuConfig),
        crate::RAW_IMU_STATUS_TAG => decode::plain(body).map(Message::RawImuStatus),
        crate::VELOCITY_CONFIG_TAG => decode::plain(body).map(Message::VelocityConfig),
        crate::POSE_VELOCITIES_TAG => decode::plain(body).map(Message::PoseVelocities),
        unknown => Err(DecodeError::UnknownMessage(unknown)),
    }
}

/// Returns `Err((expected, got))` unless `count` is the number of joints `model` takes.
fn check_angle_count(model: ModelId, count: usize) -> Result<(), (u8, u8)> {
    let expected = model.required_joints().len();
    if count == expected {
        Ok(())
    } else {
        // Both are <= MAX_POSE_ANGLES (heapless capacity), so they fit a u8.
        Err((expected as u8, count.min(u8::MAX as usize) as u8))
    }
}
