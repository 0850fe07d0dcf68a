//! Error types: [`DecodeError`] (with its payload-free [`ErrorKind`]) and [`EncodeError`].

use core::fmt;

/// Why a frame or message could not be decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DecodeError {
    /// More than [`MAX_FRAME_LEN`](crate::MAX_FRAME_LEN)` - 1` bytes arrived without a 0x00
    /// delimiter. Reported once; the decoder then discards bytes up to the next 0x00.
    Oversize,
    /// Framing error: the COBS encoding is invalid (a code byte points past the end of the
    /// frame). Typical of a truncated frame or a corrupted code byte.
    Cobs,
    /// The frame decodes to fewer bytes than a message tag plus the CRC.
    TooShort,
    /// The CRC-32C of the payload does not match the last 4 bytes of the frame.
    Crc,
    /// The CRC is good but the message tag is not one this version knows (sent by a newer
    /// protocol version).
    UnknownMessage(u32),
    /// A [`JointAngle`](crate::JointAngle) carries this protocol version, not
    /// [`PROTOCOL_VERSION`](crate::PROTOCOL_VERSION).
    UnknownVersion(u8),
    /// A [`JointAngle`](crate::JointAngle) names this joint byte, which is no
    /// [`JointId`](crate::JointId).
    UnknownJoint(u8),
    /// A [`SegmentOrientation`](crate::SegmentOrientation) or an
    /// [`ImuConfig`](crate::ImuConfig) names this segment byte, which is no
    /// [`SegmentId`](crate::SegmentId).
    UnknownSegment(u8),
    /// A message names this model byte, which is no [`ModelId`](crate::ModelId).
    UnknownModel(u8),
    /// A [`PoseFrame`](crate::PoseFrame) has `got` angles where its model takes `expected`.
    AngleCount {
        /// `model.required_joints().len()`.
        expected: u8,
        /// Angles in the frame.
        got: u8,
    },
    /// The CRC is good but the body is not a valid postcard encoding of the message (bad varint,
    /// bad bool or option tag, unknown enum value, too few or too many bytes).
    Malformed,
}

/// The kind of a [`DecodeError`], without its payload: handy as a counter index (ordered as
/// declared: the decoder's stages, framing first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorKind {
    /// [`DecodeError::Oversize`].
    Oversize,
    /// [`DecodeError::Cobs`].
    Cobs,
    /// [`DecodeError::TooShort`].
    TooShort,
    /// [`DecodeError::Crc`].
    Crc,
    /// [`DecodeError::UnknownMessage`].
    UnknownMessage,
    /// [`DecodeError::UnknownVersion`].
    UnknownVersion,
    /// [`DecodeError::UnknownJoint`].
    UnknownJoint,
    /// [`DecodeError::UnknownSegment`].
    UnknownSegment,
    /// [`DecodeError::UnknownModel`].
    UnknownModel,
    /// [`DecodeError::AngleCount`].
    AngleCount,
    /// [`DecodeError::Malformed`].
    Malformed,
}

impl DecodeError {
    /// The kind of this error, without its payload.
    pub const fn kind(&self) -> ErrorKind {
        match self {
            DecodeError::Oversize => ErrorKind::Oversize,
            DecodeError::Cobs => ErrorKind::Cobs,
            DecodeError::TooShort => ErrorKind::TooShort,
            DecodeError::Crc => ErrorKind::Crc,
            DecodeError::UnknownMessage(_) => ErrorKind::UnknownMessage,
            DecodeError::UnknownVersion(_) => ErrorKind::UnknownVersion,
            DecodeError::UnknownJoint(_) => ErrorKind::UnknownJoint,
            DecodeError::UnknownSegment(_) => ErrorKind::UnknownSegment,
            DecodeError::UnknownModel(_) => ErrorKind::UnknownModel,
            DecodeError::AngleCount { .. } => ErrorKind::AngleCount,
            DecodeError::Malformed => ErrorKind::Malformed,
        }
    }
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::Oversize => write!(
                f,
                "frame longer than {} bytes without a 0x00 delimiter",
                crate::MAX_FRAME_LEN
            ),
            DecodeError::Cobs => f.write_str("invalid COBS framing (truncated or corrupted frame)"),
            DecodeError::TooShort => f.write_str("frame too short to hold a message and its CRC"),
            DecodeError::Crc => f.write_str("CRC-32C mismatch"),
            DecodeError::UnknownMessage(t) => write!(f, "unknown message tag {t}"),
            DecodeError::UnknownVersion(v) => write!(
                f,
                "unknown protocol version {v} (this decoder speaks {})",
                crate::PROTOCOL_VERSION
            ),
            DecodeError::UnknownJoint(j) => write!(f, "unknown joint id {j}"),
            DecodeError::UnknownSegment(s) => write!(f, "unknown segment id {s}"),
            DecodeError::UnknownModel(m) => write!(f, "unknown model id {m}"),
            DecodeError::AngleCount { expected, got } => {
                write!(f, "pose frame has {got} angles, its model takes {expected}")
            }
            DecodeError::Malformed => f.write_str("malformed message body"),
        }
    }
}

impl core::error::Error for DecodeError {}

/// Why a message could not be encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EncodeError {
    /// The output buffer is smaller than the encoding; `needed` is a length that suffices
    /// ([`MAX_FRAME_LEN`](crate::MAX_FRAME_LEN) or [`MAX_MESSAGE_LEN`](crate::MAX_MESSAGE_LEN)
    /// always do for messages).
    BufferTooSmall {
        /// Bytes that suffice.
        needed: usize,
    },
    /// A [`PoseFrame`](crate::PoseFrame) has `got` angles where its model takes `expected`.
    AngleCount {
        /// `model.required_joints().len()`.
        expected: u8,
        /// Angles in the frame.
        got: u8,
    },
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EncodeError::BufferTooSmall { needed } => {
                write!(f, "output buffer too small: {needed} bytes needed")
            }
            EncodeError::AngleCount { expected, got } => {
                write!(f, "pose frame has {got} angles, its model takes {expected}")
            }
        }
    }
}

impl core::error::Error for EncodeError {}
