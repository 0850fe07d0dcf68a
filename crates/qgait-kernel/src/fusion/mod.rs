//! Orientation estimation from raw inertial data: [`Vqf`], a port of VQF (Laidig and Seel,
//! *Information Fusion* 91:187-204, 2023) generic over `f32` and `f64`, and BROAD's error
//! metric ([`OrientationError`], [`ErrorRms`]).
//!
//! VQF estimates a sensor's orientation from gyroscope and accelerometer samples (6D) and, with
//! a magnetometer, also its heading (9D): strapdown integration of the bias-corrected angular
//! rate, an inclination correction from the low-pass filtered specific force, a heading
//! correction from the magnetometer that is held while the field is disturbed (its norm or dip
//! departs from a reference), and a Kalman filter of the gyroscope bias that runs in motion and,
//! more tightly, at rest (detected from the angular rate and specific force).
//!
//! Frames, as VQF and BROAD: a quaternion `(w, x, y, z)` maps sensor-frame coordinates into
//! the earth frame, `v_E = q ⊗ (0, v_S) ⊗ q*`. The 9D earth frame is ENU (x east, y magnetic
//! north, z up); the 6D one has z up and the heading of the start, drifting with the gyroscope.
//!
//! ```
//! use qgait_kernel::fusion::Vqf;
//! let mut vqf = Vqf::<f32>::new_default(0.01); // 100 Hz
//! for _ in 0..500 {
//!     // At rest, level, facing magnetic north.
//!     vqf.update([0.0; 3], [0.0, 0.0, 9.81], Some([0.0, 20.0, -40.0]));
//! }
//! let q = vqf.quat_9d();
//! assert!((q[0].abs() - 1.0).abs() < 1e-3);
//! ```

mod metric;
mod vqf;

pub use metric::{ErrorRms, OrientationError};
pub use vqf::{Vqf, VqfParams};

use crate::Real;

/// The scalar functions VQF needs beyond [`Real`], and how each precision keeps the state of
/// its low-pass filters.
///
/// `f64` is the reference's arithmetic (`vqf_real_t = double`): the filter state and
/// coefficients in `f64`, libm's `atan2` and `asin`.
///
/// `f32` (the device) stores the filter state in `f32` too (`Acc = f32`). The reference keeps
/// it in `double` whatever `vqf_real_t` is, because the filters' poles are close to 1; on a
/// Cortex-M4F software `double` would cost more than the rest of the update. The measured
/// effect of `f32` state on a whole BROAD trial is in the crate's README.
pub trait FusionReal: Real {
    /// The machine epsilon (the reference's `EPS`).
    const EPSILON: Self;
    /// The type of the low-pass filters' state and coefficients.
    type Acc: Copy + core::fmt::Debug;
    /// `atan2(self, x)`.
    fn atan2(self, x: Self) -> Self;
    /// `asin(self)`.
    fn asin(self) -> Self;
    /// A filter coefficient (or NaN) in the state's type.
    fn acc_coeff(x: f64) -> Self::Acc;
    /// 0 in the state's type.
    fn acc_zero() -> Self::Acc;
    /// `true` for NaN.
    fn acc_is_nan(a: Self::Acc) -> bool;
    /// `a + x`.
    fn acc_add(a: Self::Acc, x: Self) -> Self::Acc;
    /// `a` as `Self`.
    fn acc_value(a: Self::Acc) -> Self;
    /// `a / b` as `Self`.
    fn acc_div(a: Self::Acc, b: Self::Acc) -> Self;
    /// One step of a second-order filter in transposed direct form II (`a0` = 1):
    /// `y = b0 x + s0; s0 = b1 x - a1 y + s1; s1 = b2 x - a2 y`.
    fn filter_step(
        x: Self,
        b: &[Self::Acc; 3],
        a: &[Self::Acc; 2],
        state: &mut [Self::Acc],
    ) -> Self;
    /// The state of the filter in steady state for a constant input `x0` (scipy's
    /// `lfilter_zi`).
    fn filter_initial_state(
        x0: Self,
        b: &[Self::Acc; 3],
        a: &[Self::Acc; 2],
        state: &mut [Self::Acc],
    );
}

macro_rules! impl_fusion_real {
    ($t:ident, atan2: $atan2:path, asin: $asin:path) => {
        impl FusionReal for $t {
            const EPSILON: Self = $t::EPSILON;
            type Acc = $t;
            #[inline(always)]
            fn atan2(self, x: Self) -> Self {
                $atan2(self, x)
            }
            #[inline(always)]
            fn asin(self) -> Self {
                $asin(self)
            }
            #[inline(always)]
            fn acc_coeff(x: f64) -> Self::Acc {
                x as $t
            }
            #[inline(always)]
            fn acc_zero() -> Self::Acc {
                0.0
            }
            #[inline(always)]
            fn acc_is_nan(a: Self::Acc) -> bool {
                a.is_nan()
            }
            #[inline(always)]
            fn acc_add(a: Self::Acc, x: Self) -> Self::Acc {
                a + x
            }
            #[inline(always)]
            fn acc_value(a: Self::Acc) -> Self {
                a
            }
            #[inline(always)]
            fn acc_div(a: Self::Acc, b: Self::Acc) -> Self {
                a / b
            }
            #[inline(always)]
            fn filter_step(
                x: Self,
                b: &[Self::Acc; 3],
                a: &[Self::Acc; 2],
                state: &mut [Self::Acc],
            ) -> Self {
                let y = b[0] * x + state[0];
                state[0] = b[1] * x - a[0] * y + state[1];
                state[1] = b[2] * x - a[1] * y;
                y
            }
            #[inline(always)]
            fn filter_initial_state(
                x0: Self,
                b: &[Self::Acc; 3],
                a: &[Self::Acc; 2],
                state: &mut [Self::Acc],
            ) {
                state[0] = x0 * (1.0 - b[0]);
                state[1] = x0 * (b[2] - a[1]);
            }
        }
    };
}

impl_fusion_real!(f64, atan2: libm::atan2, asin: libm::asin);
impl_fusion_real!(f32, atan2: libm::atan2f, asin: libm::asinf);
