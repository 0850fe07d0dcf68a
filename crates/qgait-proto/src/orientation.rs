//! IMU orientation input: [`SegmentOrientation`] (a node's segment orientation, node to hub)
//! and [`ImuConfig`] (the hub's input mode, calibration and heading settings, host to hub).
//!
//! A node with on-sensor fusion (Xsens, Movella DOT, BNO08x) reports its own orientation as a
//! unit quaternion in its world frame. The quaternion travels as four Q14 integers (`w, x, y,
//! z`, value = integer / 16384), as BNO08x sensors deliver their rotation vector: 3 bytes at
//! most each on the wire (postcard's zigzag varint), and at most 0.0070 degrees of rotation
//! lost to the rounding ([`Q14_MAX_ANGLE_ERROR_RAD`], measured by the crate's tests).

use serde::{Deserialize, Serialize};
use strum::FromRepr;

/// The scale of a Q14 quaternion component: the integer `16384` is `1.0`.
pub const Q14_ONE: f32 = 16384.0;

/// The largest rotation (radians) between a unit quaternion and its Q14 encoding decoded and
/// normalised: each component is rounded by at most 2^-15, so the quaternion moves by at most
/// 2^-14 and its rotation by at most twice that, 2^-13 rad (0.0070 degrees). The tests measure
/// the actual largest over a million random rotations: 0.0069 degrees (mean 0.0033).
pub const Q14_MAX_ANGLE_ERROR_RAD: f64 = 1.0 / 8192.0;

/// A body segment carrying an IMU node, in OpenSense's lower-body set: the kernel's
/// [`Segment`](qgait_kernel::imu::Segment), under the protocol's name. On the wire it is one
/// byte, its [`WireByte`]; a byte with no segment is reported as
/// [`DecodeError::UnknownSegment`](crate::DecodeError::UnknownSegment).
pub use qgait_kernel::imu::Segment as SegmentId;

/// An axis of a sensor's own frame, with its sign (OpenSense's `base_heading_axis`): the
/// kernel's [`HeadingAxis`](qgait_kernel::imu::HeadingAxis), under the protocol's name. On the
/// wire it is one byte, its [`WireByte`].
pub use qgait_kernel::imu::HeadingAxis as HeadingAxisId;

/// The protocol's stable numbering of a value the kernel defines: the byte that stands for it
/// on the wire, in the hand-written encoders and decoders and in postcard's (docs/protocol.md
/// section 4.7 for segments, 4.8 for heading axes). Human-readable formats (JSON) write the
/// variant's name instead.
pub trait WireByte: Copy + Sized {
    /// The value's byte on the wire.
    fn wire_byte(self) -> u8;

    /// The value of wire byte `byte`, or `None`.
    fn from_wire_byte(byte: u8) -> Option<Self>;
}

/// [`WireByte`] of `$type` from its table of values and bytes, both ways (two matches the
/// compiler turns into a range check and the identity where the numbering is the kernel's
/// order, as it is today).
macro_rules! wire_bytes {
    ($type:ident { $($value:ident = $byte:literal,)* }) => {
        impl WireByte for $type {
            fn wire_byte(self) -> u8 {
                match self {
                    $($type::$value => $byte,)*
                }
            }

            fn from_wire_byte(byte: u8) -> Option<Self> {
                match byte {
                    $($byte => Some($type::$value),)*
                    _ => None,
                }
            }
        }
    };
}

// protocol.md 4.7's table of segment ids, and 4.8's of heading axes.
wire_bytes!(SegmentId { Pelvis = 0, FemurR = 1, TibiaR = 2, CalcnR = 3,
    FemurL = 4, TibiaL = 5, CalcnL = 6, Torso = 7, });
wire_bytes!(HeadingAxisId { X = 0, NegX = 1, Y = 2, NegY = 3, Z = 4, NegZ = 5, });

/// The bit of `segment` in a set of segments on the wire ([`ImuConfig::segments`],
/// [`RawImuConfig::segments`](crate::RawImuConfig::segments)): bit `i` for wire byte `i`.
pub fn segment_bit(segment: SegmentId) -> u8 {
    1 << segment.wire_byte()
}

/// serde of a [`WireByte`] field: its wire byte in a binary format (postcard), the kernel's own
/// serde (the variant's name) in a human-readable one.
pub(crate) mod wire_byte {
    use serde::{de::Error, Deserialize, Deserializer, Serialize, Serializer};

    use super::WireByte;

    pub(crate) fn serialize<T: WireByte + Serialize, S: Serializer>(
        value: &T,
        serializer: S,
    ) -> Result<S::Ok, S::Error> {
        if serializer.is_human_readable() {
            value.serialize(serializer)
        } else {
            serializer.serialize_u8(value.wire_byte())
        }
    }

    pub(crate) fn deserialize<'de, T: WireByte + Deserialize<'de>, D: Deserializer<'de>>(
        deserializer: D,
    ) -> Result<T, D::Error> {
        if deserializer.is_human_readable() {
            T::deserialize(deserializer)
        } else {
            let byte = u8::deserialize(deserializer)?;
            T::from_wire_byte(byte).ok_or_else(|| D::Error::custom("unknown wire byte"))
        }
    }
}

/// The fields a node's sample starts with, in this order on the wire:
/// [`SegmentOrientation`] and [`RawImuSample`](crate::RawImuSample) share them (postcard writes
/// a nested struct's fields in place, so the header adds no byte of its own).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SampleHeader {
    /// Protocol version of the sender; [`PROTOCOL_VERSION`](crate::PROTOCOL_VERSION).
    pub version: u8,
    /// Id of the sending node.
    pub node: u8,
    /// The segment the node is strapped to.
    #[serde(with = "wire_byte")]
    pub segment: SegmentId,
    /// Sample number, wrapping at `u32::MAX`: the segments of one sample (from nodes sampling
    /// in step) share it. A raw node's ([`RawImuSample`](crate::RawImuSample)) is one more per
    /// sample at the configured rate, samples it knows it lost (e.g. to a FIFO overflow)
    /// included (protocol.md 4.7, 4.10).
    pub seq: u32,
    /// Sensor timestamp of the sample, microseconds (wraps after about 71.6 minutes).
    pub timestamp_us: u32,
}

impl SampleHeader {
    /// The header of this protocol version ([`PROTOCOL_VERSION`](crate::PROTOCOL_VERSION)).
    pub const fn new(node: u8, segment: SegmentId, seq: u32, timestamp_us: u32) -> Self {
        SampleHeader {
            version: crate::PROTOCOL_VERSION,
            node,
            segment,
            seq,
            timestamp_us,
        }
    }
}

/// One segment's orientation in one sample, sent by an IMU node to the hub: the node's
/// sensor frame to its world frame, as its sensor fusion reports it (the hub's calibration
/// turns it into the segment's orientation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SegmentOrientation {
    /// Sender, segment, sample number and time.
    pub header: SampleHeader,
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

/// The heading correction of the calibration: which IMU's which axis points forward in the
/// calibration pose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ImuHeading {
    /// OpenSense's `base_imu_label`.
    #[serde(with = "wire_byte")]
    pub base: SegmentId,
    /// OpenSense's `base_heading_axis`.
    #[serde(with = "wire_byte")]
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
    /// The segments the nodes send, one bit per [`SegmentId`] ([`segment_bit`]): a sample
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

    /// OpenSense's IMU tutorial settings in `mode` for all eight segments: the sensors' z-up
    /// world turned to OpenSim's by `(-pi/2, 0, 0)`, the heading from the torso IMU's z axis.
    pub const fn opensense_tutorial(mode: InputMode, calibrate: bool) -> Self {
        ImuConfig {
            mode,
            segments: Self::ALL_SEGMENTS,
            calibrate,
            sensor_to_opensim: [-core::f32::consts::FRAC_PI_2, 0.0, 0.0],
            heading: Some(ImuHeading {
                base: SegmentId::Torso,
                axis: HeadingAxisId::Z,
            }),
            request_status: false,
        }
    }
}
