//! Single-precision trigonometry for the device: one half-angle sine/cosine pair per joint angle.
//!
//! Neither ready-made option fits a Cortex-M4F: micromath's `sin`/`cos` are documented at 2e-3
//! (measured 1.1e-3 rad, about 1 mm at the end of a 1 m leg, 100 times the 10 µm budget) and
//! libm's `sinf`/`cosf` are accurate but cost about 2,400 instructions each there (they work in
//! software `f64`). This module reduces the half angle to `[-pi/2, pi/2]` and evaluates two
//! minimax polynomials (fitted by a Remez exchange on absolute error):
//!
//! | function | form | max abs error of the polynomial on \[-pi/2, pi/2\] |
//! |---|---|---|
//! | sin r | r (s0 + s1 r² + ... + s4 r⁸), degree 9 | 3.3e-9 |
//! | cos r | c0 + c1 r² + ... + c4 r⁸, degree 8 | 4.7e-8 |
//!
//! Both are at or below `f32` rounding (6e-8 near 1), so `f32` evaluation error dominates; the
//! measured end-to-end effect on joint positions is stated in the crate docs. Cost: one
//! multiply for the reduction, a rounding by the 1.5·2²³ trick (no branch, no libm), two
//! multiply-adds for the Cody-Waite subtraction and nine multiply-adds for the polynomials.

/// sin r ≈ r·(S0 + S1 r² + S2 r⁴ + S3 r⁶ + S4 r⁸) on |r| ≤ pi/2.
#[allow(clippy::excessive_precision)] // the fitted values, as printed by the fit
const S: [f32; 5] = [
    0.999_999_976_59,
    -0.166_666_476_347,
    0.008_332_899_823_59,
    -0.000_198_008_977_769,
    2.590_488_527_52e-6,
];
/// cos r ≈ C0 + C1 r² + C2 r⁴ + C3 r⁶ + C4 r⁸ on |r| ≤ pi/2.
#[allow(clippy::excessive_precision)]
const C: [f32; 5] = [
    0.999_999_953_465,
    -0.499_999_053_46,
    0.041_663_584_677_8,
    -0.001_385_370_422_74,
    2.315_393_022_46e-5,
];

/// `1/pi`.
const FRAC_1_PI: f32 = core::f32::consts::FRAC_1_PI;
/// `pi` split in two (Cody-Waite): `PI_HI` has 8 significant bits, so `k * PI_HI` and
/// `h - k * PI_HI` are exact for `|k|` up to 2¹⁶ (`|x|` up to about 4·10⁵ rad); `PI_LO` is the
/// rest.
const PI_HI: f32 = 3.140_625;
#[allow(clippy::excessive_precision)]
const PI_LO: f32 = 9.676_535_897_932_e-4;
/// Adding then subtracting 1.5·2²³ rounds an `f32` of magnitude below 2²² to the nearest integer.
const ROUND_MAGIC: f32 = 12_582_912.0;

/// `(sin(x/2), cos(x/2))` up to a common sign (the sign of `cos` is always >= 0).
///
/// Exact reduction for |x| up to about 4·10⁵ rad (2¹⁶ half turns of the half angle); beyond,
/// the reduction loses accuracy, and past about 2.6·10⁷ rad (where the rounding trick stops
/// rounding) the result is not a rotation at all. An `f32` angle that large is too coarse to
/// mean anything: a hub does not use angles beyond 2¹⁶ rad
/// (`qgait_proto::JointAngle::MAX_ANGLE`). NaN or infinite `x` gives NaN.
#[inline(always)]
pub fn half_angle_sin_cos_f32(x: f32) -> (f32, f32) {
    half_angle_sin_cos_f32_with(x, |a, b, c| a * b + c)
}

/// [`half_angle_sin_cos_f32`] with the polynomials' multiply-adds `a * b + c` done by
/// `mul_add` (the batch path's FMA levels pass a fused multiply-add).
#[inline(always)]
pub fn half_angle_sin_cos_f32_with(x: f32, mul_add: impl Fn(f32, f32, f32) -> f32) -> (f32, f32) {
    let h = 0.5 * x;
    // k = round(h / pi), r = h - k pi in [-pi/2, pi/2]; sin and cos of r equal those of h up
    // to the common factor (-1)^k, which leaves the rotation unchanged.
    let k = (h * FRAC_1_PI + ROUND_MAGIC) - ROUND_MAGIC;
    let r = (h - k * PI_HI) - k * PI_LO;
    let r2 = r * r;
    let s = r * mul_add(
        mul_add(mul_add(mul_add(S[4], r2, S[3]), r2, S[2]), r2, S[1]),
        r2,
        S[0],
    );
    let c = mul_add(
        mul_add(mul_add(mul_add(C[4], r2, C[3]), r2, C[2]), r2, C[1]),
        r2,
        C[0],
    );
    (s, c)
}

/// sin r ≈ r·(S0 + S1 r² + ... + S7 r¹⁴) on |r| ≤ pi/2, max abs error 9.0e-17.
#[allow(clippy::excessive_precision)]
const S64: [f64; 8] = [
    0.99999999999999903148,
    -0.16666666666664780921,
    0.0083333333332262362609,
    -0.00019841269813956764991,
    2.7557315528923127002e-6,
    -2.5051824648397510033e-8,
    1.6046620394624211675e-10,
    -7.3576602010859069852e-13,
];
/// cos r ≈ C0 + C1 r² + ... + C8 r¹⁶ on |r| ≤ pi/2, max abs error 3.9e-18.
#[allow(clippy::excessive_precision)]
const C64: [f64; 9] = [
    0.99999999999999999609,
    -0.49999999999999974308,
    0.041666666666663887903,
    -0.0013888888888773170724,
    0.000024801587277443752432,
    -2.7557316393520385221e-7,
    2.0876561959489896669e-9,
    -1.1462904884850754078e-11,
    4.6090072378156206649e-14,
];

/// `(sin(x/2), cos(x/2))` up to a common sign, in `f64`, without branches or library calls, so
/// that a loop over many angles vectorises (the batch path; the scalar `f64` path uses libm).
/// Same reduction as [`half_angle_sin_cos_f32`]; polynomial errors 9e-17 and 4e-18, below
/// `f64` rounding. Valid for |x| below about 2⁵⁰; NaN or infinite `x` gives NaN.
#[inline(always)]
pub fn half_angle_sin_cos_f64(x: f64) -> (f64, f64) {
    half_angle_sin_cos_f64_with(x, |a, b, c| a * b + c)
}

/// [`half_angle_sin_cos_f64`] with the polynomials' multiply-adds `a * b + c` done by
/// `mul_add` (the batch path's FMA levels pass a fused multiply-add).
#[inline(always)]
pub fn half_angle_sin_cos_f64_with(x: f64, mul_add: impl Fn(f64, f64, f64) -> f64) -> (f64, f64) {
    const ROUND_MAGIC_64: f64 = 6_755_399_441_055_744.0; // 1.5·2⁵²
    const PI_HI_64: f64 = 3.140_625;
    #[allow(clippy::excessive_precision)]
    const PI_LO_64: f64 = 9.676_535_897_932_384_626_4e-4;
    let h = 0.5 * x;
    let k = (h * core::f64::consts::FRAC_1_PI + ROUND_MAGIC_64) - ROUND_MAGIC_64;
    let r = (h - k * PI_HI_64) - k * PI_LO_64;
    let r2 = r * r;
    let mut s = S64[7];
    for c in S64[..7].iter().rev() {
        s = mul_add(s, r2, *c);
    }
    let mut c = C64[8];
    for k in C64[..8].iter().rev() {
        c = mul_add(c, r2, *k);
    }
    (r * s, c)
}

/// Correctly rounded `f32` square root (IEEE 754). Not on the forward-kinematics path: only
/// the three inter-limb distances of a frame use it. On Arm hard-float targets (the
/// Cortex-M4F) it is the FPU's `vsqrt.f32` (5 instructions with the call, against 81 for
/// libm's software `sqrtf`); elsewhere libm, which compiles to the SSE/NEON instruction.
#[inline(always)]
pub fn sqrt_f32(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
    {
        vfp::sqrt(x)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf")))]
    {
        libm::sqrtf(x)
    }
}

/// The FPU's square root. Stable Rust cannot name the `s` registers in inline assembly on
/// Arm (the `vfp2` target feature is unstable there), so it is a two-instruction function
/// that takes and returns its `f32` in `s0`, as the hard-float calling convention does.
#[cfg(all(target_arch = "arm", target_abi = "eabihf"))]
#[allow(unsafe_code)]
mod vfp {
    core::arch::global_asm!(
        ".section .text.qgait_kernel_vsqrt_f32,\"ax\",%progbits",
        ".global qgait_kernel_vsqrt_f32",
        ".type qgait_kernel_vsqrt_f32,%function",
        // Every Arm hard-float FPU (VFPv2 and later, FPv4-SP of the Cortex-M4F) has vsqrt.f32;
        // the directive only tells the assembler so.
        ".fpu fpv4-sp-d16",
        ".thumb_func",
        "qgait_kernel_vsqrt_f32:",
        "vsqrt.f32 s0, s0",
        "bx lr",
        ".size qgait_kernel_vsqrt_f32, . - qgait_kernel_vsqrt_f32",
    );

    extern "C" {
        fn qgait_kernel_vsqrt_f32(x: f32) -> f32;
    }

    #[inline(always)]
    pub(super) fn sqrt(x: f32) -> f32 {
        // SAFETY: the function above reads s0, writes s0 and returns: no memory, no stack,
        // nothing beyond what the hard-float ABI lets a callee clobber.
        unsafe { qgait_kernel_vsqrt_f32(x) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_angle_matches_libm_within_polynomial_error() {
        let mut max_err = 0.0f64;
        let n = 200_000;
        for i in 0..=n {
            let x = -8.0 * core::f64::consts::PI
                + 16.0 * core::f64::consts::PI * (i as f64) / (n as f64);
            let (s, c) = half_angle_sin_cos_f32(x as f32);
            let (es, ec) = libm::sincos(0.5 * (x as f32) as f64);
            // compare up to the common sign
            let sign = if (c as f64) * ec + (s as f64) * es < 0.0 {
                -1.0
            } else {
                1.0
            };
            max_err = max_err
                .max((sign * s as f64 - es).abs())
                .max((sign * c as f64 - ec).abs());
        }
        assert!(max_err < 3e-7, "max error {max_err}");
    }

    #[test]
    fn f64_polynomial_matches_libm_to_rounding() {
        let mut max_err = 0.0f64;
        let n = 200_000;
        for i in 0..=n {
            let x = -8.0 * core::f64::consts::PI
                + 16.0 * core::f64::consts::PI * (i as f64) / (n as f64);
            let (s, c) = half_angle_sin_cos_f64(x);
            let (es, ec) = libm::sincos(0.5 * x);
            let sign = if c * ec + s * es < 0.0 { -1.0 } else { 1.0 };
            max_err = max_err
                .max((sign * s - es).abs())
                .max((sign * c - ec).abs());
        }
        assert!(max_err < 1e-15, "max error {max_err}");
        assert!(
            half_angle_sin_cos_f64(f64::NAN).0.is_nan()
                && half_angle_sin_cos_f64(f64::INFINITY).1.is_nan()
        );
    }

    #[test]
    fn non_finite_gives_nan() {
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (s, c) = half_angle_sin_cos_f32(x);
            assert!(s.is_nan() && c.is_nan(), "{x}: {s} {c}");
        }
    }

    #[test]
    fn sqrt_is_correctly_rounded_on_samples() {
        for x in [0.0f32, 1.0, 2.0, 0.25, 1e-8, 3.5e4] {
            assert_eq!(sqrt_f32(x), libm::sqrtf(x));
        }
        assert!(sqrt_f32(-1.0).is_nan());
    }
}
