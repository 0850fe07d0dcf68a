//! The scalar trait the kernel is generic over, implemented for `f32` and `f64`.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::trig;

/// A real number type the kernel computes in: `f32` on the device, `f64` on the host.
///
/// The one method that differs in substance between the two is
/// [`half_angle_sin_cos`](Real::half_angle_sin_cos), the only transcendental function on the
/// forward-kinematics hot path (one call per joint angle): `f64` calls `libm` (correctly rounded
/// to within 1 ulp), `f32` evaluates a minimax polynomial (see [`crate::trig`]).
pub trait Real:
    Copy
    + PartialEq
    + PartialOrd
    + Default
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + 'static
{
    /// 0
    const ZERO: Self;
    /// 1
    const ONE: Self;
    /// 2
    const TWO: Self;
    /// 1/2
    const HALF: Self;
    /// Converts from `f64` (rounding to nearest for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts from `f32` (exact for both implementations): for values that are exact in
    /// `f32` (small integers, Q14 fractions), so that the device's path has no `f64` arithmetic.
    fn from_f32(x: f32) -> Self;
    /// Converts to `f64` (exact for both implementations).
    fn to_f64(self) -> f64;
    /// The nearest integer, halfway cases away from zero (libm's `round`/`roundf`).
    fn round(self) -> Self;
    /// Square root (NaN for negative input).
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// `true` unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// The smaller of two values (the other one if either is NaN).
    fn min(self, other: Self) -> Self;
    /// The larger of two values (the other one if either is NaN).
    fn max(self, other: Self) -> Self;
    /// `if self < other { if_less } else { otherwise }` (lane by lane for lane arrays; NaN
    /// compares false). The only comparison the evaluator makes (spline intervals).
    fn lt_select(self, other: Self, if_less: Self, otherwise: Self) -> Self;
    /// Accurate `(sin x, cos x)` (libm in both precisions). Used by the reference methods and
    /// metrics, not on the quaternion hot path.
    fn sin_cos(self) -> (Self, Self);
    /// `(sin(x/2), cos(x/2))` up to a common sign: exactly what a rotation quaternion about a
    /// unit axis needs (`q` and `-q` are the same rotation). NaN or infinite `x` gives NaN.
    fn half_angle_sin_cos(self) -> (Self, Self);
}

/// `Real` for a primitive float: everything but the functions that differ by precision.
macro_rules! impl_real {
    ($t:ident, round: $round:path, sqrt: $sqrt:path, sin_cos: $sin_cos:path, half_angle_sin_cos: $half:expr) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn from_f32(x: f32) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn round(self) -> Self {
                $round(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline(always)]
            fn abs(self) -> Self {
                $t::abs(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                $t::is_finite(self)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                $t::min(self, other)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                $t::max(self, other)
            }
            #[inline(always)]
            fn lt_select(self, other: Self, if_less: Self, otherwise: Self) -> Self {
                if self < other {
                    if_less
                } else {
                    otherwise
                }
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                $sin_cos(self)
            }
            #[inline(always)]
            fn half_angle_sin_cos(self) -> (Self, Self) {
                let half: fn($t) -> ($t, $t) = $half;
                half(self)
            }
        }
    };
}

// f64 (the host): libm throughout.
impl_real!(f64, round: libm::round, sqrt: libm::sqrt, sin_cos: libm::sincos, half_angle_sin_cos: |x| libm::sincos(0.5 * x));
// f32 (the device): the FPU's square root and the kernel's half-angle polynomial (see `trig`).
impl_real!(f32, round: libm::roundf, sqrt: trig::sqrt_f32, sin_cos: libm::sincosf, half_angle_sin_cos: trig::half_angle_sin_cos_f32);
