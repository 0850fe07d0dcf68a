//! Segment lengths of a subject, per side.

use crate::{ModelError, Real, Side};

/// Lengths of one side (metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limb<T> {
    /// Lateral distance from the pelvis origin to this hip centre (the paper's `w`).
    pub pelvis_half_width: T,
    /// Hip centre to knee centre.
    pub femur: T,
    /// Knee centre to ankle centre.
    pub tibia: T,
    /// Ankle centre to the tip of the big toe.
    pub foot: T,
}

impl<T: Real> Limb<T> {
    /// gait2392's generic adult (1.8 m, 75 kg): 0.0835, 0.395846, 0.43, 0.214584 m (see
    /// `gait2392-geometry.md`: the femur is the hip-to-knee distance at knee angle 0, the foot the
    /// ankle-to-toe-tip distance).
    pub fn gait2392() -> Self {
        Self {
            pelvis_half_width: T::from_f64(0.0835),
            femur: T::from_f64(0.395846),
            tibia: T::from_f64(0.43),
            foot: T::from_f64(0.214584),
        }
    }
    /// The four lengths in the order pelvis half-width, femur, tibia, foot.
    pub fn to_array(self) -> [T; 4] {
        [self.pelvis_half_width, self.femur, self.tibia, self.foot]
    }
    /// From the four lengths in the order of [`to_array`](Self::to_array).
    pub fn from_array(a: [T; 4]) -> Self {
        Self {
            pelvis_half_width: a[0],
            femur: a[1],
            tibia: a[2],
            foot: a[3],
        }
    }
    /// Checks every length is finite and non-negative.
    pub fn validate(&self) -> Result<(), ModelError> {
        if self
            .to_array()
            .iter()
            .all(|v| v.is_finite() && *v >= T::ZERO)
        {
            Ok(())
        } else {
            Err(ModelError::BadLength)
        }
    }
    /// Converts to another precision.
    pub fn cast<U: Real>(self) -> Limb<U> {
        Limb::from_array(self.to_array().map(|v| U::from_f64(v.to_f64())))
    }
}

impl<T: Real> Default for Limb<T> {
    fn default() -> Self {
        Self::gait2392()
    }
}

/// A subject's lengths; left and right may differ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anthropometry<T> {
    /// Right side.
    pub right: Limb<T>,
    /// Left side.
    pub left: Limb<T>,
}

impl<T: Real> Anthropometry<T> {
    /// gait2392's generic adult on both sides.
    pub fn gait2392() -> Self {
        Self::symmetric(Limb::gait2392())
    }
    /// The same lengths on both sides.
    pub fn symmetric(limb: Limb<T>) -> Self {
        Self {
            right: limb,
            left: limb,
        }
    }
    /// One side.
    pub fn limb(&self, side: Side) -> &Limb<T> {
        match side {
            Side::Right => &self.right,
            Side::Left => &self.left,
        }
    }
    /// Converts to another precision.
    pub fn cast<U: Real>(self) -> Anthropometry<U> {
        Anthropometry {
            right: self.right.cast(),
            left: self.left.cast(),
        }
    }
}

impl<T: Real> Default for Anthropometry<T> {
    fn default() -> Self {
        Self::gait2392()
    }
}
