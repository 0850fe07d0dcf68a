//! Physiological ranges of the joint angles, used to flag implausible inputs.
//!
//! The ranges are the coordinate ranges of OpenSim's gait2392 model, widened by
//! [`MARGIN`] so that a good IMU estimate near the end of a range is never flagged. An angle
//! outside its range is still used (the pose is computed and sent with
//! [`FrameFlags::OUT_OF_RANGE`](qgait_proto::FrameFlags::OUT_OF_RANGE)); an angle that is not a
//! finite number is rejected.

use qgait_proto::JointId;

/// Tolerance added to both ends of every range (radians, 10 degrees).
pub const MARGIN: f32 = 0.174_532_93;

const DEG: f32 = core::f32::consts::PI / 180.0;

/// The range `(min, max)` of `joint` in radians, before [`MARGIN`].
pub fn range(joint: JointId) -> (f32, f32) {
    let (lo, hi) = match joint {
        JointId::PelvisTilt | JointId::PelvisList | JointId::PelvisRotation => (-90.0, 90.0),
        JointId::HipFlexionR | JointId::HipFlexionL => (-30.0, 120.0),
        JointId::HipAdductionR | JointId::HipAdductionL => (-50.0, 30.0),
        JointId::HipRotationR | JointId::HipRotationL => (-40.0, 40.0),
        JointId::KneeAngleR | JointId::KneeAngleL => (-120.0, 10.0),
        JointId::AnkleAngleR | JointId::AnkleAngleL => (-40.0, 30.0),
        JointId::SubtalarAngleR | JointId::SubtalarAngleL => (-20.0, 20.0),
        JointId::MtpAngleR | JointId::MtpAngleL => (-30.0, 30.0),
    };
    (lo * DEG, hi * DEG)
}

/// Whether `angle` (radians) lies in the range of `joint`, margin included.
#[inline]
pub fn in_range(joint: JointId, angle: f32) -> bool {
    let (lo, hi) = range(joint);
    angle >= lo - MARGIN && angle <= hi + MARGIN
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knee_hyperextension_beyond_the_margin_is_out_of_range() {
        assert!(in_range(JointId::KneeAngleR, -1.5));
        assert!(in_range(JointId::KneeAngleL, 20.0 * DEG - 1e-4));
        assert!(!in_range(JointId::KneeAngleL, 25.0 * DEG));
        assert!(!in_range(JointId::KneeAngleR, f32::NAN));
    }

    #[test]
    fn every_range_is_ordered_and_contains_zero() {
        for j in JointId::ALL {
            let (lo, hi) = range(j);
            assert!(lo < 0.0 && 0.0 < hi, "{j}");
        }
    }
}
