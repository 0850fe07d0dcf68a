//! 3-vectors: positions, offsets and rotation axes.

use core::ops::{Add, AddAssign, Mul, Neg, Sub};

use crate::Real;

/// A 3-vector in metres (positions, offsets) or unitless (axes). Axes as OpenSim: x forward,
/// y up, z right.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Vec3<T> {
    /// Forward (anterior) component.
    pub x: T,
    /// Upward (superior) component.
    pub y: T,
    /// Rightward (lateral for the right leg) component.
    pub z: T,
}

impl<T: Real> Vec3<T> {
    /// `(x, y, z)`.
    pub const fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }
    /// The zero vector.
    #[inline(always)]
    pub fn zero() -> Self {
        Self::new(T::ZERO, T::ZERO, T::ZERO)
    }
    /// Unit vector along x.
    pub fn unit_x() -> Self {
        Self::new(T::ONE, T::ZERO, T::ZERO)
    }
    /// Unit vector along y.
    pub fn unit_y() -> Self {
        Self::new(T::ZERO, T::ONE, T::ZERO)
    }
    /// Unit vector along z.
    pub fn unit_z() -> Self {
        Self::new(T::ZERO, T::ZERO, T::ONE)
    }
    /// From `f64` components.
    pub fn from_f64(v: [f64; 3]) -> Self {
        Self::new(T::from_f64(v[0]), T::from_f64(v[1]), T::from_f64(v[2]))
    }
    /// Components as an array `[x, y, z]`.
    pub fn to_array(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }
    /// Converts to another precision (through `f64`).
    pub fn cast<U: Real>(self) -> Vec3<U> {
        Vec3::new(
            U::from_f64(self.x.to_f64()),
            U::from_f64(self.y.to_f64()),
            U::from_f64(self.z.to_f64()),
        )
    }
    /// Dot product.
    #[inline(always)]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product (right-handed).
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Euclidean length.
    pub fn norm(self) -> T {
        self.dot(self).sqrt()
    }
    /// Euclidean distance between two points (the paper's Eqs 18-20).
    pub fn distance(a: Self, b: Self) -> T {
        (a - b).norm()
    }
    /// This vector scaled to unit length (NaN components for the zero vector).
    pub fn normalized(self) -> Self {
        self * (T::ONE / self.norm())
    }
    /// Largest absolute component difference, for tolerance checks.
    pub fn max_abs_diff(self, o: Self) -> T {
        let d = self - o;
        d.x.abs().max(d.y.abs()).max(d.z.abs())
    }
}

impl<T: Real> Add for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<T: Real> AddAssign for Vec3<T> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<T: Real> Sub for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<T: Real> Neg for Vec3<T> {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<T: Real> Mul<T> for Vec3<T> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}
