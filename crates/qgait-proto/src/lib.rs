#![doc = include_str!("../README.md")]
#![no_std]
#![warn(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

mod chain;
mod cobs;
mod counting;
mod crc;
mod decoder;
pub mod device_model;
mod error;
mod flags;
mod frame;
mod indices;
mod joint;
mod messages;
mod model;
mod orientation;
mod policy;
mod raw;
mod sizes;
mod subject;
mod velocity;
mod version;
mod wire;

pub use crate::chain::{
    ChainTable, ChainTableConfig, CHAIN_BODIES, CHAIN_TABLE_CONFIG_TAG, CHAIN_TABLE_TAG,
    MAX_CHAIN_DRIVES, MAX_CHAIN_SPLINES, MAX_CHAIN_TABLE_BYTES, MAX_CHAIN_WORDS,
};
pub use crate::crc::{crc32c, FRAME_CRC, FRAME_CRC_CHECK};
pub use crate::decoder::{Feed, FrameDecoder};
#[cfg(feature = "std")]
pub use crate::device_model::HubModel;
pub use crate::device_model::{ConfigError, Kinematics, PoseModels, SubjectParts};
pub use crate::error::{DecodeError, EncodeError, ErrorKind};
pub use crate::flags::{FrameFlags, QualityFlags};
pub use crate::frame::{
    decode_frame, encode_frame, encode_pose_frame, encode_pose_frame_parts,
    encode_pose_velocities_frame, encode_raw_frame, encode_raw_imu_status_frame,
    encode_segment_orientation_frame, encode_status_frame,
};
pub use crate::indices::{point, segment};
pub use crate::joint::JointId;
pub use crate::messages::{
    Config, JointAngle, Message, PoseFrame, Status, MAX_POSE_ANGLES, MAX_REORDER_WINDOW,
};
pub use crate::model::ModelId;
pub use crate::orientation::{
    segment_bit, HeadingAxisId, ImuConfig, ImuHeading, InputMode, SampleHeader, SegmentId,
    SegmentOrientation, WireByte, Q14_MAX_ANGLE_ERROR_RAD, Q14_ONE,
};
pub use crate::policy::MissingPolicy;
pub use crate::raw::{
    FusionMode, RawImuConfig, RawImuSample, RawImuStatus, RAW_IMU_CONFIG_TAG, RAW_IMU_SAMPLE_TAG,
    RAW_IMU_STATUS_COUNTERS, RAW_IMU_STATUS_TAG,
};
pub use crate::sizes::{
    CHAIN_TABLE_CONFIG_MAX_LEN, CHAIN_TABLE_MAX_LEN, CONFIG_MAX_LEN, CRC_LEN, IMU_CONFIG_MAX_LEN,
    JOINT_ANGLE_MAX_FRAME_LEN, JOINT_ANGLE_MAX_LEN, MAX_FRAME_LEN, MAX_MESSAGE_LEN,
    MIN_PAYLOAD_LEN, POSE_FRAME_MAX_LEN, POSE_VELOCITIES_MAX_LEN, RAW_IMU_CONFIG_MAX_LEN,
    RAW_IMU_SAMPLE_MAX_LEN, RAW_IMU_STATUS_MAX_LEN, SEGMENT_ORIENTATION_MAX_LEN, STATUS_MAX_LEN,
    SUBJECT_CONFIG_MAX_LEN, SUBJECT_KNEE_MAX_LEN, SUBJECT_LEG_MAX_LEN, VELOCITY_CONFIG_MAX_LEN,
};
pub use crate::subject::{
    KneeDirection, Leg, SubjectConfig, SubjectKnee, SubjectLeg, MAX_KNEE_KNOTS, SUBJECT_PARTS,
};
pub use crate::velocity::{
    backward_difference, PoseVelocities, VelocityConfig, MAX_VELOCITY_PERIOD_US,
    POSE_VELOCITIES_TAG, VELOCITY_CONFIG_TAG,
};
pub use crate::version::PROTOCOL_VERSION;
pub use crate::wire::{
    decode_hub_message, decode_message, decode_node_message, decode_packet, encode_message,
    HubMessage, NodeMessage, PoseFrameParts,
};

/// Largest COBS encoding (delimiter excluded) of `len` bytes: `len + ceil(len / 254)`, 1 if empty.
pub const fn cobs_max_encoded_len(len: usize) -> usize {
    cobs::max_encoded_len(len)
}
