//! Bit constants for [`JointAngle::quality`](crate::JointAngle::quality) and
//! [`PoseFrame::flags`](crate::PoseFrame::flags).

/// Bits of [`JointAngle::quality`](crate::JointAngle::quality). `0` means a good sample.
/// Bits not listed here are reserved: senders write 0, receivers ignore them.
#[derive(Debug, Clone, Copy)]
pub struct QualityFlags;

impl QualityFlags {
    /// The node's sensor fusion reports low confidence in this angle.
    pub const LOW_CONFIDENCE: u8 = 1 << 0;
    /// A sensor saturated (gyro or accelerometer at full scale) during this sample.
    pub const SATURATED: u8 = 1 << 1;
    /// The node has not been calibrated (angle offsets unknown).
    pub const UNCALIBRATED: u8 = 1 << 2;
    /// Magnetic disturbance detected (heading-dependent angles less reliable).
    pub const MAG_DISTURBED: u8 = 1 << 3;
    /// Every bit defined above.
    pub const ALL: u8 =
        Self::LOW_CONFIDENCE | Self::SATURATED | Self::UNCALIBRATED | Self::MAG_DISTURBED;
}

/// Bits of [`PoseFrame::flags`](crate::PoseFrame::flags). `0` means every joint of the sample
/// arrived in time and was in range. Bits not listed here are reserved: senders write 0,
/// receivers ignore them.
#[derive(Debug, Clone, Copy)]
pub struct FrameFlags;

impl FrameFlags {
    /// At least one required joint was missing from the sample.
    pub const MISSING: u8 = 1 << 0;
    /// At least one angle was held from an earlier sample (missing-joint policy `HoldLast`).
    pub const HELD: u8 = 1 << 1;
    /// At least one angle was outside its physiological range.
    pub const OUT_OF_RANGE: u8 = 1 << 2;
    /// Every bit defined above.
    pub const ALL: u8 = Self::MISSING | Self::HELD | Self::OUT_OF_RANGE;
}
