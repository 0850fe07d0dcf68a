//! Physiological ranges of the 17 gait2392 coordinates, in [`COORDINATES`] order: what counts as
//! a plausible joint angle. The hub flags a sample with an angle outside its range (widened by
//! [`MARGIN_DEG`]); the host warns about such angles in a motion file. HAK and PHAK use the
//! ranges of the coordinates they share with gait2392.
//!
//! Degrees: pelvis tilt, list and rotation -90..90; hip flexion -30..120, adduction -50..30,
//! rotation -40..40; knee -120..10 (OpenSim's `knee_angle`, < 0 flexion, the limits of
//! gait2392's model file); ankle -40..30; subtalar -20..20; MTP -30..30.

use super::gait2392::COORDINATES;
use crate::Real;

/// `(min, max)` of each coordinate in degrees, [`COORDINATES`] order.
pub const RANGES_DEG: [(f64, f64); 17] = {
    const PELVIS: (f64, f64) = (-90.0, 90.0);
    const HIP_FLEXION: (f64, f64) = (-30.0, 120.0);
    const HIP_ADDUCTION: (f64, f64) = (-50.0, 30.0);
    const HIP_ROTATION: (f64, f64) = (-40.0, 40.0);
    const KNEE: (f64, f64) = (-120.0, 10.0);
    const ANKLE: (f64, f64) = (-40.0, 30.0);
    const SUBTALAR: (f64, f64) = (-20.0, 20.0);
    const MTP: (f64, f64) = (-30.0, 30.0);
    [
        PELVIS,
        PELVIS,
        PELVIS,
        HIP_FLEXION,
        HIP_ADDUCTION,
        HIP_ROTATION,
        KNEE,
        ANKLE,
        SUBTALAR,
        MTP,
        HIP_FLEXION,
        HIP_ADDUCTION,
        HIP_ROTATION,
        KNEE,
        ANKLE,
        SUBTALAR,
        MTP,
    ]
};

/// Tolerance added to both ends of every range (degrees), so that a good estimate near the end
/// of a range is never flagged.
pub const MARGIN_DEG: f64 = 10.0;

const RAD_PER_DEG: f64 = core::f64::consts::PI / 180.0;

/// The accepted interval of each coordinate in radians, margin included.
const ACCEPTED_RAD: [[f64; 2]; 17] = {
    let mut out = [[0.0; 2]; 17];
    let mut i = 0;
    while i < 17 {
        out[i] = [
            (RANGES_DEG[i].0 - MARGIN_DEG) * RAD_PER_DEG,
            (RANGES_DEG[i].1 + MARGIN_DEG) * RAD_PER_DEG,
        ];
        i += 1;
    }
    out
};

/// The same in `f32`, rounded at compile time (no `f64` arithmetic on the device).
const ACCEPTED_RAD_F32: [[f32; 2]; 17] = {
    let mut out = [[0.0; 2]; 17];
    let mut i = 0;
    while i < 17 {
        out[i] = [ACCEPTED_RAD[i][0] as f32, ACCEPTED_RAD[i][1] as f32];
        i += 1;
    }
    out
};

/// A scalar with its own table of accepted intervals (`f32`, `f64`).
pub trait RangeScalar: Real {
    /// The accepted interval `(min, max)` of coordinate `index` in radians, margin included.
    ///
    /// # Panics
    /// If `index` is not below 17.
    fn accepted(index: usize) -> (Self, Self);
}

impl RangeScalar for f64 {
    fn accepted(index: usize) -> (f64, f64) {
        let [lo, hi] = ACCEPTED_RAD[index];
        (lo, hi)
    }
}

impl RangeScalar for f32 {
    fn accepted(index: usize) -> (f32, f32) {
        let [lo, hi] = ACCEPTED_RAD_F32[index];
        (lo, hi)
    }
}

/// The index of a coordinate in [`COORDINATES`] by its OpenSim name.
pub fn index(name: &str) -> Option<usize> {
    COORDINATES.iter().position(|c| *c == name)
}

/// Whether `angle` (radians) lies in the range of coordinate `index`, margin included (false
/// for NaN and infinities).
///
/// # Panics
/// If `index` is not below 17.
#[inline]
pub fn in_range<T: RangeScalar>(index: usize, angle: T) -> bool {
    let (lo, hi) = T::accepted(index);
    angle >= lo && angle <= hi
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_range_is_ordered_and_contains_zero() {
        for (name, (lo, hi)) in COORDINATES.iter().zip(RANGES_DEG) {
            assert!(lo < 0.0 && 0.0 < hi, "{name}");
        }
    }

    #[test]
    fn the_margin_widens_both_ends_and_non_finite_is_out() {
        let knee = index("knee_angle_r").unwrap();
        assert!(in_range(knee, (-129.9f64).to_radians()));
        assert!(!in_range(knee, (-130.1f64).to_radians()));
        assert!(in_range(knee, 19.9f32.to_radians()));
        assert!(!in_range(knee, 25f32.to_radians()));
        assert!(!in_range(knee, f64::NAN));
        assert!(!in_range(knee, f64::INFINITY));
        assert!(!in_range(knee, 1e300f64));
        assert_eq!(index("lumbar_extension"), None);
    }
}
