//! Physiological ranges of the joint angles, used to flag implausible inputs.
//!
//! The ranges are the kernel's ([`qgait_kernel::models::ranges`]), widened by
//! [`MARGIN`] so that a good IMU estimate near the end of a range is never flagged, the knee's
//! mirrored for a model whose knee flexes with positive angles (an uploaded Rajagopal chain:
//! [`KneeFlexion::Positive`]). An angle
//! outside its range is still used (the pose is computed and sent with
//! [`FrameFlags::OUT_OF_RANGE`](qgait_proto::FrameFlags::OUT_OF_RANGE)); an angle the hub
//! cannot use (not finite, or beyond [`JointAngle::MAX_ANGLE`](qgait_proto::JointAngle::MAX_ANGLE))
//! is rejected before.

use qgait_kernel::models::ranges::{self, KneeFlexion};
use qgait_proto::JointId;

/// Tolerance added to both ends of every range (radians, [`ranges::MARGIN_DEG`]).
pub const MARGIN: f32 = (ranges::MARGIN_DEG * core::f64::consts::PI / 180.0) as f32;

const DEG: f32 = core::f32::consts::PI / 180.0;

/// The range `(min, max)` of `joint` in radians, before [`MARGIN`] (the kernel's
/// [`ranges::RANGES_DEG`]; joint ids are the kernel's coordinate indices).
pub fn range(joint: JointId) -> (f32, f32) {
    let (lo, hi) = ranges::RANGES_DEG[joint.index() as usize];
    (lo as f32 * DEG, hi as f32 * DEG)
}

/// Whether `angle` (radians) lies in the range of `joint` for a model whose knee flexes with
/// `knee` angles, margin included.
#[inline]
pub fn in_range(joint: JointId, angle: f32, knee: KneeFlexion) -> bool {
    ranges::in_model_range(joint.index() as usize, angle, knee)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn knee_hyperextension_beyond_the_margin_is_out_of_range() {
        let n = KneeFlexion::Negative;
        assert!(in_range(JointId::KneeAngleR, -1.5, n));
        assert!(in_range(JointId::KneeAngleL, 20.0 * DEG - 1e-4, n));
        assert!(!in_range(JointId::KneeAngleL, 25.0 * DEG, n));
        assert!(!in_range(JointId::KneeAngleR, f32::NAN, n));
    }

    #[test]
    fn a_knee_flexing_with_positive_angles_has_the_mirrored_range() {
        let p = KneeFlexion::Positive;
        for knee in [JointId::KneeAngleR, JointId::KneeAngleL] {
            assert!(in_range(knee, 1.5, p));
            assert!(in_range(knee, -20.0 * DEG + 1e-4, p));
            assert!(!in_range(knee, -25.0 * DEG, p));
        }
        assert!(!in_range(JointId::AnkleAngleR, 45.0 * DEG, p));
        assert!(in_range(JointId::HipFlexionR, 100.0 * DEG, p));
    }

    #[test]
    fn joint_ids_are_the_kernels_coordinate_indices() {
        for j in JointId::ALL {
            assert_eq!(
                qgait_kernel::models::gait2392::COORDINATES[j.index() as usize],
                j.name()
            );
        }
    }

    #[test]
    fn every_range_is_ordered_and_contains_zero() {
        for j in JointId::ALL {
            let (lo, hi) = range(j);
            assert!(lo < 0.0 && 0.0 < hi, "{j}");
        }
    }
}
