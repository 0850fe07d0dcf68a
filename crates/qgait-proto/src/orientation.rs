//! IMU orientation input: [`SegmentOrientation`] (a node's segment orientation, node to hub)
//! and [`ImuConfig`] (the hub's input mode, calibration and heading settings, host to hub).
//!
//! A node with on-sensor fusion (Xsens, Movella DOT, BNO08x) reports its own orientation as a
//! unit quaternion in its world frame. The quaternion travels as four Q14 integers (`w, x, y,
//! z`, value = integer / 16384), as BNO08x sensors deliver their rotation vector: 3 bytes at
//! most each on the wire (postcard's zigzag varint), and at most 0.0070 degrees of rotation
//! lost to the rounding ([`Q14_MAX_ANGLE_ERROR_RAD`], measured by the crate's tests).

use serde::{Deserialize, Serialize};
use strum::{EnumCount, FromRepr};

/// The scale of a Q14 quaternion component: the integer `16384` is `1.0`.
pub const Q14_ONE: f32 = 16384.0;

/// The largest rotation (radians) between a unit quaternion and its Q14 encoding decoded and
/// normalised: each component is rounded by at most 2^-15, so the quaternion moves by at most
/// 2^-14 and its rotation by at most twice that, 2^-13 rad (0.0070 degrees). The tests measure
/// the actual largest over a million random rotations: 0.0069 degrees (mean 0.0033).
pub const Q14_MAX_ANGLE_ERROR_RAD: f64 = 1.0 / 8192.0;

/// A body segment carrying an IMU node, in OpenSense's lower-body set (the kernel's
/// `imu::Segment`, same order).
///
/// On the wire it is one raw byte holding the discriminant; a byte with no matching segment is
/// reported as [`DecodeError::UnknownSegment`](crate::DecodeError::UnknownSegment).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    EnumCount,
    FromRepr,
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum SegmentId {
    /// The pelvis.
    Pelvis = 0,
    /// Right thigh.
    FemurR = 1,
    /// Right shank.
    TibiaR = 2,
    /// Right foot (heel bone).
    CalcnR = 3,
    /// Left thigh.
    FemurL = 4,
    /// Left shank.
    TibiaL = 5,
    /// Left foot.
    CalcnL = 6,
    /// The trunk.
    Torso = 7,
}

impl SegmentId {
    /// Number of segments.
    pub const COUNT: usize = <Self as EnumCount>::COUNT;

    /// Every segment, in discriminant order.
    pub const ALL: [SegmentId; Self::COUNT] = [
        SegmentId::Pelvis,
        SegmentId::FemurR,
        SegmentId::TibiaR,
        SegmentId::CalcnR,
        SegmentId::FemurL,
        SegmentId::TibiaL,
        SegmentId::CalcnL,
        SegmentId::Torso,
    ];

    /// The wire byte (the discriminant).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The segment of wire byte `index`, or `None`.
    pub const fn from_index(index: u8) -> Option<SegmentId> {
        Self::from_repr(index)
    }

    /// The bit of this segment in [`ImuConfig::segments`].
    pub const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// One segment's orientation in one sample, sent by an IMU node to the hub: the node's
/// sensor frame to its world frame, as its sensor fusion reports it (the hub's calibration
/// turns it into the segment's orientation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SegmentOrientation {
    /// Protocol version of the sender; [`PROTOCOL_VERSION`](crate::PROTOCOL_VERSION).
    pub version: u8,
    /// Id of the sending node.
    pub node: u8,
    /// The segment it is strapped to.
    pub segment: SegmentId,
    /// Sample sequence number, wrapping at `u32::MAX`: the segments of one sample share it.
    pub seq: u32,
    /// Sensor timestamp of the sample, microseconds (wraps after about 71.6 minutes).
    pub timestamp_us: u32,
    /// The unit quaternion `w, x, y, z`, Q14 (each component times 16384, rounded).
    pub q14: [i16; 4],
    /// [`QualityFlags`](crate::QualityFlags) bits.
    pub quality: u8,
}

impl SegmentOrientation {
    /// `q` (`w, x, y, z`, any norm up to 2) in Q14, each component rounded to the nearest
    /// integer (saturating at the `i16` range; NaN becomes 0).
    pub fn q14_of(q: [f64; 4]) -> [i16; 4] {
        q.map(|c| {
            let v = c * f64::from(Q14_ONE);
            // `as` saturates and maps NaN to 0; the rounding is half away from zero.
            (if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i16
        })
    }

    /// The quaternion `w, x, y, z` as decoded (not normalised).
    pub fn quaternion(&self) -> [f32; 4] {
        self.q14.map(|c| f32::from(c) / Q14_ONE)
    }
}

/// Where the hub's samples come from, and how it computes angles from orientations.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, FromRepr)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum InputMode {
    /// [`JointAngle`](crate::JointAngle) packets (the hub's default).
    JointAngles = 0,
    /// [`SegmentOrientation`] packets, angles by the kernel's closed form (each joint's
    /// relative rotation decomposed into its axes).
    OrientationsClosedForm = 1,
    /// [`SegmentOrientation`] packets, angles by the kernel's per-leg least squares
    /// (OpenSense's problem, Gauss-Newton warm-started from the previous sample).
    OrientationsLeastSquares = 2,
}

impl InputMode {
    /// Whether samples are made of [`SegmentOrientation`]s.
    pub const fn orientations(self) -> bool {
        !matches!(self, InputMode::JointAngles)
    }
}

/// An axis of a sensor's own frame, with its sign (OpenSense's `base_heading_axis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, FromRepr)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum HeadingAxisId {
    /// +x
    X = 0,
    /// -x
    NegX = 1,
    /// +y
    Y = 2,
    /// -y
    NegY = 3,
    /// +z
    Z = 4,
    /// -z
    NegZ = 5,
}

/// The heading correction of the calibration: which IMU's which axis points forward in the
/// calibration pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuHeading {
    /// OpenSense's `base_imu_label`.
    pub base: SegmentId,
    /// OpenSense's `base_heading_axis`.
    pub axis: HeadingAxisId,
}

/// The hub's input mode and IMU settings, sent by the host. The model stays the one
/// [`Config`](crate::Config) or [`SubjectConfig`](crate::SubjectConfig) set; the orientation
/// modes take a gait2392 model (generic or a subject's).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuConfig {
    /// Joint angles or segment orientations.
    pub mode: InputMode,
    /// The segments the nodes send, one bit per [`SegmentId`] ([`SegmentId::bit`]): a sample
    /// is complete when each of them arrived. At least the pelvis.
    pub segments: u8,
    /// `true`: the next complete orientation sample is the calibration pose (the subject
    /// standing in the model's default pose); it gives no pose frame.
    pub calibrate: bool,
    /// The rotation from the sensors' world frame to OpenSim's (y up), a space-fixed X-Y-Z
    /// sequence in radians (OpenSense's `sensor_to_opensim_rotations`; `(-pi/2, 0, 0)` for a
    /// z-up world).
    pub sensor_to_opensim: [f32; 3],
    /// The heading correction, or `None` (the subject then faced the world's x at calibration).
    pub heading: Option<ImuHeading>,
    /// `true` asks the hub to answer with a [`Status`](crate::Status) message.
    pub request_status: bool,
}

impl ImuConfig {
    /// All eight segments.
    pub const ALL_SEGMENTS: u8 = 0xff;
}
