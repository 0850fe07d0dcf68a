//! Maximum encoded sizes, computed from worst-case postcard encodings.
//!
//! postcard writes `u8` and `bool` as 1 byte, `f32` as 4 bytes, an `Option` tag as 1 byte, and
//! `u16`, `u32` and lengths as LEB128 varints of at most 3, 5 and 5 bytes (7 bits per byte). A message tag and
//! every enum value of this protocol fit one byte.

use crate::{cobs, point, segment, JointId, MAX_CHAIN_TABLE_BYTES, MAX_KNEE_KNOTS};

/// Worst-case bytes of a postcard `u32` varint.
const VARINT_U32: usize = 5;
/// Worst-case bytes of a postcard `u16` varint.
const VARINT_U16: usize = 3;
/// Bytes of an `f32`.
const F32: usize = 4;
/// Bytes of the message tag (tags < 128 are one varint byte).
const TAG: usize = 1;

/// Largest postcard encoding of a [`JointAngle`](crate::JointAngle) message, tag included:
/// tag, version, node, joint, seq, timestamp_us, angle, quality.
pub const JOINT_ANGLE_MAX_LEN: usize = TAG + 1 + 1 + 1 + VARINT_U32 + VARINT_U32 + F32 + 1;

/// Largest postcard encoding of a [`PoseFrame`](crate::PoseFrame) message, tag included:
/// tag, seq, timestamp_us, model, angle count (1 byte, <= 17), 17 angles, 8 points of 3, 3
/// distances, flags.
pub const POSE_FRAME_MAX_LEN: usize = TAG
    + VARINT_U32
    + VARINT_U32
    + 1
    + 1
    + JointId::COUNT * F32
    + point::COUNT * 3 * F32
    + 3 * F32
    + 1;

/// Number of `u32` counters in a [`Status`](crate::Status).
pub const STATUS_COUNTERS: usize = 20;

/// Largest postcard encoding of a [`Status`](crate::Status) message, tag included.
pub const STATUS_MAX_LEN: usize = TAG + STATUS_COUNTERS * VARINT_U32;

/// Largest postcard encoding of a [`Config`](crate::Config) message, tag included:
/// tag, model, option tag, 2 x 4 lengths, missing policy, reorder window, request_status.
pub const CONFIG_MAX_LEN: usize = TAG + 1 + 1 + 2 * segment::COUNT * F32 + 1 + 1 + 1;

/// Largest postcard encoding of a [`SubjectLeg`](crate::SubjectLeg) message, tag included:
/// tag, upload, leg, 11 vectors of 3 `f32` (hip centre, 3 hip axes, ankle, subtalar and MTP
/// centres and axes, toe tip).
pub const SUBJECT_LEG_MAX_LEN: usize = TAG + 1 + 1 + 11 * 3 * F32;

/// Largest postcard encoding of a [`SubjectKnee`](crate::SubjectKnee) message, tag included:
/// tag, upload, leg, direction, knot count (1 byte, <= 12), 12 knots of 2 `f32`.
pub const SUBJECT_KNEE_MAX_LEN: usize = TAG + 1 + 1 + 1 + 1 + MAX_KNEE_KNOTS * 2 * F32;

/// Largest postcard encoding of a [`SubjectConfig`](crate::SubjectConfig) message, tag
/// included: tag, upload, missing policy, reorder window, request_status.
pub const SUBJECT_CONFIG_MAX_LEN: usize = TAG + 1 + 1 + 1 + 1;

/// Worst-case bytes of a postcard `i16` (zigzag varint).
const VARINT_I16: usize = 3;

/// Largest postcard encoding of a [`SegmentOrientation`](crate::SegmentOrientation) message,
/// tag included: tag, version, node, segment, seq, timestamp_us, 4 Q14 components, quality.
pub const SEGMENT_ORIENTATION_MAX_LEN: usize =
    TAG + 1 + 1 + 1 + VARINT_U32 + VARINT_U32 + 4 * VARINT_I16 + 1;

/// Largest postcard encoding of an [`ImuConfig`](crate::ImuConfig) message, tag included:
/// tag, mode, segments, calibrate, 3 `f32`, option tag, base, axis, request_status.
pub const IMU_CONFIG_MAX_LEN: usize = TAG + 1 + 1 + 1 + 3 * F32 + 1 + 1 + 1 + 1;

/// Largest postcard encoding of a [`ChainTable`](crate::ChainTable) message, tag included:
/// tag, upload, `at` (a `u16` varint), byte count, the bytes.
pub const CHAIN_TABLE_MAX_LEN: usize = TAG + 1 + VARINT_U16 + 2 + MAX_CHAIN_TABLE_BYTES;

/// Largest postcard encoding of a [`ChainTableConfig`](crate::ChainTableConfig) message, tag
/// included: tag, upload, `len` (a `u16` varint), `crc` (a `u32` varint), the knee's sign,
/// missing policy, reorder window, request_status.
pub const CHAIN_TABLE_CONFIG_MAX_LEN: usize = TAG + 1 + VARINT_U16 + VARINT_U32 + 1 + 1 + 1 + 1;

/// Largest postcard encoding of a [`RawImuSample`](crate::RawImuSample) message, tag
/// included: tag, version, node, segment, seq, timestamp_us, 3 gyroscope and 3 accelerometer
/// counts, the magnetometer's option tag and 3 counts.
pub const RAW_IMU_SAMPLE_MAX_LEN: usize = TAG
    + 1
    + 1
    + 1
    + VARINT_U32
    + VARINT_U32
    + 3 * VARINT_I16
    + 3 * VARINT_I16
    + 1
    + 3 * VARINT_I16;

/// Largest postcard encoding of a [`RawImuConfig`](crate::RawImuConfig) message, tag included:
/// tag, segments, fusion, rate (a `u16` varint), output_every, 3 `f32` sensitivities,
/// request_status.
pub const RAW_IMU_CONFIG_MAX_LEN: usize = TAG + 1 + 1 + VARINT_U16 + 1 + 3 * F32 + 1;

/// Largest postcard encoding of a [`RawImuStatus`](crate::RawImuStatus) message, tag included.
pub const RAW_IMU_STATUS_MAX_LEN: usize = TAG + crate::RAW_IMU_STATUS_COUNTERS * VARINT_U32;

/// Largest postcard encoding of a [`VelocityConfig`](crate::VelocityConfig) message, tag
/// included: tag, enabled, period_us (a `u32` varint), request_status.
pub const VELOCITY_CONFIG_MAX_LEN: usize = TAG + 1 + VARINT_U32 + 1;

/// Largest postcard encoding of a [`PoseVelocities`](crate::PoseVelocities) message, tag
/// included: tag, seq, dt_us, 8 × 3 `f32` velocities.
pub const POSE_VELOCITIES_MAX_LEN: usize =
    TAG + VARINT_U32 + VARINT_U32 + 3 * crate::point::COUNT * F32;

const fn max(a: usize, b: usize) -> usize {
    if a > b {
        a
    } else {
        b
    }
}

/// Largest postcard encoding of any [`Message`](crate::Message) (no CRC, no framing).
pub const MAX_MESSAGE_LEN: usize = max(
    max(
        max(
            max(JOINT_ANGLE_MAX_LEN, POSE_FRAME_MAX_LEN),
            max(STATUS_MAX_LEN, CONFIG_MAX_LEN),
        ),
        max(
            max(
                max(SUBJECT_LEG_MAX_LEN, SUBJECT_KNEE_MAX_LEN),
                max(SUBJECT_CONFIG_MAX_LEN, CHAIN_TABLE_MAX_LEN),
            ),
            max(
                CHAIN_TABLE_CONFIG_MAX_LEN,
                max(SEGMENT_ORIENTATION_MAX_LEN, IMU_CONFIG_MAX_LEN),
            ),
        ),
    ),
    max(
        max(
            RAW_IMU_SAMPLE_MAX_LEN,
            max(RAW_IMU_CONFIG_MAX_LEN, RAW_IMU_STATUS_MAX_LEN),
        ),
        max(VELOCITY_CONFIG_MAX_LEN, POSE_VELOCITIES_MAX_LEN),
    ),
);

/// Bytes of the CRC-32C appended to the message before COBS.
pub const CRC_LEN: usize = 4;

/// Largest frame on the wire: COBS of (message + CRC), plus the 0x00 delimiter.
pub const MAX_FRAME_LEN: usize = cobs::max_encoded_len(MAX_MESSAGE_LEN + CRC_LEN) + 1;

/// Largest frame carrying a [`JointAngle`](crate::JointAngle), delimiter included.
pub const JOINT_ANGLE_MAX_FRAME_LEN: usize =
    cobs::max_encoded_len(JOINT_ANGLE_MAX_LEN + CRC_LEN) + 1;

/// Smallest decoded frame that can hold a message: a tag byte plus the CRC.
pub const MIN_PAYLOAD_LEN: usize = TAG + CRC_LEN;
