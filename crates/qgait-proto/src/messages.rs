//! The messages: [`JointAngle`], [`PoseFrame`], [`Status`], [`Config`] and the top-level
//! [`Message`] enum that is put on the wire (the subject-model messages are in `subject.rs`).
//!
//! The serde derives exist for host-side convenience (JSON logs and the like). The wire bytes
//! are defined by [`encode_message`](crate::encode_message) /
//! [`decode_message`](crate::decode_message); decode with those (or
//! [`FrameDecoder`](crate::FrameDecoder)) to get precise [`DecodeError`](crate::DecodeError)s.

use serde::{Deserialize, Serialize};

use crate::{
    point, segment, ChainTable, ChainTableConfig, ImuConfig, JointId, MissingPolicy, ModelId,
    PoseVelocities, RawImuConfig, RawImuSample, RawImuStatus, SegmentOrientation, SubjectConfig,
    SubjectKnee, SubjectLeg, VelocityConfig,
};

/// The deepest reorder window a hub supports (samples): a `Config` or `SubjectConfig` asks for
/// `1..=MAX_REORDER_WINDOW`.
pub const MAX_REORDER_WINDOW: u8 = 8;

/// One joint angle of one sample, sent by an IMU node to the hub.
///
/// One packet carries exactly one joint; a node measuring several joints sends one packet per
/// joint per sample, all with the same `seq` and `timestamp_us`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JointAngle {
    /// Protocol version of the sender; [`PROTOCOL_VERSION`](crate::PROTOCOL_VERSION) for this crate.
    pub version: u8,
    /// Id of the sending node.
    pub node: u8,
    /// Which joint coordinate this is.
    pub joint: JointId,
    /// Sample sequence number, wrapping at `u32::MAX`. Packets with the same `seq` belong to the
    /// same sample.
    pub seq: u32,
    /// Sensor timestamp of the sample, microseconds (wraps after about 71.6 minutes).
    pub timestamp_us: u32,
    /// The angle, radians, OpenSim sign convention.
    pub angle: f32,
    /// [`QualityFlags`](crate::QualityFlags) bits.
    pub quality: u8,
}

impl JointAngle {
    /// The largest angle magnitude a hub uses, radians (2¹⁶, about 10,000 turns): an `f32`
    /// that large is 0.008 rad coarse, and the hub's half-angle sine and cosine reduce exactly
    /// only up to about 4·10⁵ rad (protocol.md 8.3).
    pub const MAX_ANGLE: f32 = 65_536.0;

    /// Whether a hub uses this packet's angle: a number of magnitude at most
    /// [`MAX_ANGLE`](Self::MAX_ANGLE) (not NaN, not infinite).
    #[inline(always)]
    pub fn usable(&self) -> bool {
        self.angle.abs() <= Self::MAX_ANGLE
    }
}

/// Maximum number of input angles in a [`PoseFrame`]: one per [`JointId`].
pub const MAX_POSE_ANGLES: usize = JointId::COUNT;

/// One computed pose, sent by the hub.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PoseFrame {
    /// Sample sequence number (the `seq` of the [`JointAngle`]s it was computed from).
    pub seq: u32,
    /// Sensor time of that sample, microseconds: the `timestamp_us` of its packets (wraps after
    /// about 71.6 minutes, as theirs).
    pub timestamp_us: u32,
    /// The model used.
    pub model: ModelId,
    /// The input angles actually used (radians), in `model.required_joints()` order, so the host
    /// can recompute the pose. Its length must equal `model.required_joints().len()`:
    /// encoding or decoding anything else is an error.
    pub angles: heapless::Vec<f32, MAX_POSE_ANGLES>,
    /// Joint positions (metres, ground axes x forward, y up, z right, origin the pelvis origin),
    /// in the order of the [`point`] indices: hip, knee, ankle, toe of the right leg, then the left.
    pub points: [[f32; 3]; point::COUNT],
    /// Distances between the legs (metres): knee-knee, ankle-ankle, toe-toe.
    pub distances: [f32; 3],
    /// [`FrameFlags`](crate::FrameFlags) bits.
    pub flags: u8,
}

/// Counters of the hub, sent on request (see [`Config::request_status`]) or periodically.
/// Every counter wraps at `u32::MAX`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Status {
    /// Well-formed [`JointAngle`] packets accepted (their angle [`usable`](JointAngle::usable)),
    /// and, with the orientation input, segment orientations of unit length.
    pub packets_accepted: u32,
    /// Frames rejected for a CRC mismatch.
    pub crc_errors: u32,
    /// Frames rejected for bad COBS or too short to hold a message.
    pub framing_errors: u32,
    /// Frames longer than [`MAX_FRAME_LEN`](crate::MAX_FRAME_LEN).
    pub oversize_frames: u32,
    /// Packets of an unknown protocol version or unknown message tag.
    pub unknown_version: u32,
    /// Packets naming an unknown joint or segment.
    pub unknown_joint: u32,
    /// Angles outside their physiological range (used), or not
    /// [`usable`](JointAngle::usable) (dropped).
    pub out_of_range: u32,
    /// Samples completed (a pose was computed).
    pub samples_completed: u32,
    /// Samples dropped because joints were missing.
    pub samples_incomplete: u32,
    /// Frames sent by the hub.
    pub frames_sent: u32,
    /// UART receive overruns (bytes lost in hardware).
    pub uart_overruns: u32,
    /// Milliseconds since the hub started (wraps after about 49.7 days).
    pub uptime_ms: u32,
    /// Packets that arrived after their sample had left the reorder window.
    pub late_packets: u32,
    /// Packets for a (sample, joint) already received.
    pub duplicate_packets: u32,
    /// Frames with a good CRC whose contents could not be decoded (bad postcard encoding,
    /// unknown model, wrong angle count), and messages the hub does not take (those only a hub
    /// sends; the chain messages without chain support; the raw IMU messages).
    pub malformed: u32,
    /// Configurations the hub could not use and ignored, keeping the one in force: a reorder
    /// window outside `1..=`[`MAX_REORDER_WINDOW`], a [`Config`] with unusable segment lengths
    /// (or lengths with gait2392), a [`SubjectConfig`](crate::SubjectConfig) whose model is
    /// incomplete or refused by the kernel.
    pub config_rejected: u32,
    /// [`SegmentOrientation`] packets whose quaternion is not finite or whose norm is farther
    /// than the kernel's `imu::UNIT_TOLERANCE` (0.1) from 1: dropped (nearer, it is normalised).
    pub orientation_not_unit: u32,
    /// Orientation samples completed before the first calibration (or with an orientation
    /// model the kernel cannot solve): dropped, no pose frame.
    pub uncalibrated_samples: u32,
    /// Calibration poses taken ([`ImuConfig::calibrate`]).
    pub calibrations: u32,
    /// Calibration poses refused (the heading's base IMU missing, its heading axis vertical):
    /// the calibration in force stays, and the next complete sample is tried.
    pub calibration_rejected: u32,
}

/// Configuration sent by the host to the hub.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// The model to compute poses with.
    pub model: ModelId,
    /// Segment lengths (metres) of the right leg (`[0]`) and the left leg (`[1]`), each indexed
    /// by the [`segment`] constants; `None` keeps the hub's current HAK and PHAK lengths
    /// (gait2392's until a `Config` sets others, kept through other models).
    pub anthropometry: Option<[[f32; segment::COUNT]; 2]>,
    /// What to do with incomplete samples.
    pub missing_policy: MissingPolicy,
    /// How many samples the hub waits for late packets before closing a sample:
    /// `1..=`[`MAX_REORDER_WINDOW`]; a hub rejects (and counts) a configuration with another.
    pub reorder_window: u8,
    /// `true` asks the hub to answer with a [`Status`] message.
    pub request_status: bool,
}

/// Every message of the protocol. The variant order is the wire tag (0 to 15): new variants
/// are only ever appended, existing ones never change.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Message {
    /// Tag 0: node to hub.
    JointAngle(JointAngle),
    /// Tag 1: hub out.
    PoseFrame(PoseFrame),
    /// Tag 2: hub out.
    Status(Status),
    /// Tag 3: host to hub.
    Config(Config),
    /// Tag 4: host to hub, a part of a subject model.
    SubjectLeg(SubjectLeg),
    /// Tag 5: host to hub, a part of a subject model.
    SubjectKnee(SubjectKnee),
    /// Tag 6: host to hub, switch to a subject model.
    SubjectConfig(SubjectConfig),
    /// Tag 7: node to hub, a segment's orientation.
    SegmentOrientation(SegmentOrientation),
    /// Tag 8: host to hub, the input mode and IMU settings.
    ImuConfig(ImuConfig),
    /// Tag 9 ([`CHAIN_TABLE_TAG`](crate::CHAIN_TABLE_TAG)): host to hub, bytes of a chain's
    /// table.
    ChainTable(ChainTable),
    /// Tag 10 ([`CHAIN_TABLE_CONFIG_TAG`](crate::CHAIN_TABLE_CONFIG_TAG)): host to hub, switch
    /// to a chain's table.
    ChainTableConfig(ChainTableConfig),
    /// Tag 11 ([`RAW_IMU_SAMPLE_TAG`](crate::RAW_IMU_SAMPLE_TAG)): node to the receiver that
    /// fuses it, a raw IMU sample.
    RawImuSample(RawImuSample),
    /// Tag 12 ([`RAW_IMU_CONFIG_TAG`](crate::RAW_IMU_CONFIG_TAG)): host to the receiver that
    /// fuses raw samples, its settings.
    RawImuConfig(RawImuConfig),
    /// Tag 13 ([`RAW_IMU_STATUS_TAG`](crate::RAW_IMU_STATUS_TAG)): the raw input's counters,
    /// to the host.
    RawImuStatus(RawImuStatus),
    /// Tag 14 ([`VELOCITY_CONFIG_TAG`](crate::VELOCITY_CONFIG_TAG)): host to hub, the points'
    /// velocities on or off.
    VelocityConfig(VelocityConfig),
    /// Tag 15 ([`POSE_VELOCITIES_TAG`](crate::POSE_VELOCITIES_TAG)): hub out, the velocities
    /// of a pose frame's points.
    PoseVelocities(PoseVelocities),
}

/// `Status`'s counters' names, in wire order.
const STATUS_NAMES: [&str; crate::sizes::STATUS_COUNTERS] = [
    "packets_accepted",
    "crc_errors",
    "framing_errors",
    "oversize_frames",
    "unknown_version",
    "unknown_joint",
    "out_of_range",
    "samples_completed",
    "samples_incomplete",
    "frames_sent",
    "uart_overruns",
    "uptime_ms",
    "late_packets",
    "duplicate_packets",
    "malformed",
    "config_rejected",
    "orientation_not_unit",
    "uncalibrated_samples",
    "calibrations",
    "calibration_rejected",
];

// Every field of `Status` is a `u32` counter in `counters()`: a counter added to `Status`
// changes its size and stops the build here until it is added there (and to `STATUS_NAMES`).
const _: () = assert!(core::mem::size_of::<Status>() == 4 * crate::sizes::STATUS_COUNTERS);

impl Status {
    /// Every counter, in wire order (the struct's declaration order).
    #[inline]
    pub fn counters(&self) -> [u32; crate::sizes::STATUS_COUNTERS] {
        [
            self.packets_accepted,
            self.crc_errors,
            self.framing_errors,
            self.oversize_frames,
            self.unknown_version,
            self.unknown_joint,
            self.out_of_range,
            self.samples_completed,
            self.samples_incomplete,
            self.frames_sent,
            self.uart_overruns,
            self.uptime_ms,
            self.late_packets,
            self.duplicate_packets,
            self.malformed,
            self.config_rejected,
            self.orientation_not_unit,
            self.uncalibrated_samples,
            self.calibrations,
            self.calibration_rejected,
        ]
    }

    /// Every counter with its field name, in wire order.
    pub fn named_counters(&self) -> [(&'static str, u32); crate::sizes::STATUS_COUNTERS] {
        let counters = self.counters();
        core::array::from_fn(|i| (STATUS_NAMES[i], counters[i]))
    }
}

impl Message {
    /// The wire tag of this message (its variant index).
    pub const fn tag(&self) -> u32 {
        match self {
            Message::JointAngle(_) => 0,
            Message::PoseFrame(_) => 1,
            Message::Status(_) => 2,
            Message::Config(_) => 3,
            Message::SubjectLeg(_) => 4,
            Message::SubjectKnee(_) => 5,
            Message::SubjectConfig(_) => 6,
            Message::SegmentOrientation(_) => 7,
            Message::ImuConfig(_) => 8,
            Message::ChainTable(_) => crate::CHAIN_TABLE_TAG,
            Message::ChainTableConfig(_) => crate::CHAIN_TABLE_CONFIG_TAG,
            Message::RawImuSample(_) => crate::RAW_IMU_SAMPLE_TAG,
            Message::RawImuConfig(_) => crate::RAW_IMU_CONFIG_TAG,
            Message::RawImuStatus(_) => crate::RAW_IMU_STATUS_TAG,
            Message::VelocityConfig(_) => crate::VELOCITY_CONFIG_TAG,
            Message::PoseVelocities(_) => crate::POSE_VELOCITIES_TAG,
        }
    }
}

impl From<JointAngle> for Message {
    fn from(m: JointAngle) -> Self {
        Message::JointAngle(m)
    }
}

impl From<PoseFrame> for Message {
    fn from(m: PoseFrame) -> Self {
        Message::PoseFrame(m)
    }
}

impl From<Status> for Message {
    fn from(m: Status) -> Self {
        Message::Status(m)
    }
}

impl From<Config> for Message {
    fn from(m: Config) -> Self {
        Message::Config(m)
    }
}

impl From<SubjectLeg> for Message {
    fn from(m: SubjectLeg) -> Self {
        Message::SubjectLeg(m)
    }
}

impl From<SubjectKnee> for Message {
    fn from(m: SubjectKnee) -> Self {
        Message::SubjectKnee(m)
    }
}

impl From<ChainTable> for Message {
    fn from(m: ChainTable) -> Self {
        Message::ChainTable(m)
    }
}

impl From<ChainTableConfig> for Message {
    fn from(m: ChainTableConfig) -> Self {
        Message::ChainTableConfig(m)
    }
}

impl From<SubjectConfig> for Message {
    fn from(m: SubjectConfig) -> Self {
        Message::SubjectConfig(m)
    }
}

impl From<SegmentOrientation> for Message {
    fn from(m: SegmentOrientation) -> Self {
        Message::SegmentOrientation(m)
    }
}

impl From<ImuConfig> for Message {
    fn from(m: ImuConfig) -> Self {
        Message::ImuConfig(m)
    }
}

impl From<RawImuSample> for Message {
    fn from(m: RawImuSample) -> Self {
        Message::RawImuSample(m)
    }
}

impl From<RawImuConfig> for Message {
    fn from(m: RawImuConfig) -> Self {
        Message::RawImuConfig(m)
    }
}

impl From<RawImuStatus> for Message {
    fn from(m: RawImuStatus) -> Self {
        Message::RawImuStatus(m)
    }
}

impl From<VelocityConfig> for Message {
    fn from(m: VelocityConfig) -> Self {
        Message::VelocityConfig(m)
    }
}

impl From<PoseVelocities> for Message {
    fn from(m: PoseVelocities) -> Self {
        Message::PoseVelocities(m)
    }
}
