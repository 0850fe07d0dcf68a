//! Physiological ranges of the 17 gait2392 coordinates, in [`COORDINATES`] order: what counts as
//! a plausible joint angle. The hub flags a sample with an angle outside its range (widened by
//! [`MARGIN_DEG`]); the host warns about such angles in a motion file. HAK and PHAK use the
//! ranges of the coordinates they share with gait2392.
//!
//! Degrees: pelvis tilt, list and rotation -90..90; hip flexion -30..120, adduction -50..30,
//! rotation -40..40; knee -120..10 (OpenSim's `knee_angle`, < 0 flexion, the limits of
//! gait2392's model file); ankle -40..30; subtalar -20..20; MTP -30..30.
//!
//! A model whose knee flexes with positive angles (Rajagopal's walker knee,
//! [`KneeFlexion::Positive`]) has the knee's range mirrored: 120° of flexion is `knee_angle`
//! +120° there. [`KneeFlexion::of`] tells which a model is from its forward kinematics, and
//! [`in_model_range`] checks an angle against the model's range.

use super::gait2392::COORDINATES;
#[cfg(doc)]
use super::gait2392::POINTS;
use crate::{Real, Vec3};

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
    // One leg, hip to MTP, as each side's coordinates follow the pelvis's three.
    const LEG: [(f64, f64); 7] = [
        HIP_FLEXION,
        HIP_ADDUCTION,
        HIP_ROTATION,
        KNEE,
        ANKLE,
        SUBTALAR,
        MTP,
    ];
    let mut out = [PELVIS; 17];
    let mut i = 0;
    while i < 7 {
        out[3 + i] = LEG[i];
        out[10 + i] = LEG[i];
        i += 1;
    }
    out
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

/// Which sign of `knee_angle` flexes a model's knee.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[repr(u8)]
pub enum KneeFlexion {
    /// Negative angles: gait2392 and its family, HAK and PHAK (the ranges of [`RANGES_DEG`]).
    #[default]
    Negative,
    /// Positive angles: Rajagopal's walker knee (the knee's range mirrored).
    Positive,
}

/// `knee_angle_r` and `knee_angle_l` in [`COORDINATES`].
pub const KNEES: [usize; 2] = [6, 13];

/// `ankle_r` in [`POINTS`].
const ANKLE_R: usize = 2;

impl KneeFlexion {
    /// The knee flexion of a model with forward kinematics `fk` (the 12 points of [`POINTS`]
    /// for the 17 coordinates of [`COORDINATES`]): flexion moves the ankle backwards (-x) from
    /// the straight knee. Evaluates `fk` twice, at `knee_angle_r` = ±0.5 rad, every other
    /// coordinate 0: the right knee's sign stands for both (the two legs of every OpenSim model
    /// qgait imports are mirror images, and so flex alike).
    pub fn of<T: Real>(fk: impl Fn(&[T; 17]) -> [Vec3<T>; 12]) -> KneeFlexion {
        let ankle_x = |v: f64| {
            let mut q = [T::ZERO; 17];
            q[KNEES[0]] = T::from_f64(v);
            fk(&q)[ANKLE_R].x
        };
        if ankle_x(0.5) < ankle_x(-0.5) {
            KneeFlexion::Positive
        } else {
            KneeFlexion::Negative
        }
    }

    /// Whether coordinate `index` is held in the opposite sign to gait2392's: a knee of
    /// [`Positive`](Self::Positive) (its range mirrored).
    #[inline]
    pub fn mirrors(self, index: usize) -> bool {
        self == KneeFlexion::Positive && (index == KNEES[0] || index == KNEES[1])
    }

    /// `angle` of coordinate `index` as gait2392's signs hold it: negated where
    /// [`mirrors`](Self::mirrors), anything else as it is.
    #[inline]
    pub fn in_gait2392_signs<T: Real>(self, index: usize, angle: T) -> T {
        if self.mirrors(index) {
            -angle
        } else {
            angle
        }
    }
}

/// Whether `angle` (radians) lies in the range of coordinate `index` for a model whose knee
/// flexes with `knee` angles (the knee's range mirrored for [`KneeFlexion::Positive`]), margin
/// included; false for NaN and infinities.
///
/// # Panics
/// If `index` is not below 17.
#[inline]
pub fn in_model_range<T: RangeScalar>(index: usize, angle: T, knee: KneeFlexion) -> bool {
    in_range(index, knee.in_gait2392_signs(index, angle))
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

    #[test]
    fn the_knees_and_the_ankle_are_named_so() {
        use crate::models::gait2392::POINTS;
        assert_eq!(
            KNEES.map(|i| COORDINATES[i]),
            ["knee_angle_r", "knee_angle_l"]
        );
        assert_eq!(POINTS[ANKLE_R], "ankle_r");
    }

    #[test]
    fn a_positive_flexion_knee_has_the_mirrored_range_and_nothing_else_changes() {
        let deg = |d: f64| d.to_radians();
        for knee in KNEES {
            assert!(in_model_range(knee, deg(125.0), KneeFlexion::Positive));
            assert!(!in_model_range(knee, deg(-25.0), KneeFlexion::Positive));
            assert!(!in_model_range(knee, deg(125.0), KneeFlexion::Negative));
            assert!(in_model_range(knee, deg(-125.0), KneeFlexion::Negative));
            assert!(!in_model_range(knee, f64::NAN, KneeFlexion::Positive));
        }
        let ankle = index("ankle_angle_r").unwrap();
        assert!(in_model_range(ankle, deg(-45.0), KneeFlexion::Positive));
        assert!(!in_model_range(ankle, deg(45.0), KneeFlexion::Positive));
    }

    #[test]
    fn the_knee_flexion_of_a_model_is_where_its_flexed_knee_puts_the_ankle() {
        // A straight leg down the y axis; the knee bends it in the sagittal plane, the ankle
        // moving backwards with `sign * knee_angle_r` > 0.
        let leg = |sign: f64| {
            move |q: &[f64; 17]| {
                let mut points = [Vec3::new(0.0, 0.0, 0.0); 12];
                let a = sign * q[KNEES[0]];
                points[ANKLE_R] = Vec3::new(-0.4 * a.sin(), -0.4 * a.cos(), 0.0);
                points
            }
        };
        assert_eq!(KneeFlexion::of(leg(1.0)), KneeFlexion::Positive);
        assert_eq!(KneeFlexion::of(leg(-1.0)), KneeFlexion::Negative);
    }
}
