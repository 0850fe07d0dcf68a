//! The PHAK kernel in f32 on the Cortex-M4F against f64 values computed by the same kernel on
//! the host at build time (`build.rs`), the FPU's square root, and the stack paint.

use qgait_firmware::stack;
use qgait_kernel::metrics::distances;
use qgait_kernel::trig::sqrt_f32;
use qgait_kernel::{Anthropometry, Limb, Phak, PhakAngles};

mod expected {
    include!(concat!(env!("OUT_DIR"), "/kernel_cases.rs"));
}

/// Largest accepted distance between an f32 point and its f64 value (metres): 5 µm, well
/// under IMU-derived accuracy, about 40 f32 ulps of a 1 m coordinate.
const POINT_TOLERANCE_M: f64 = 5e-6;

fn phak(subject: usize) -> Phak<f32> {
    let legs = expected::SUBJECTS[subject];
    let a = Anthropometry {
        right: Limb::from_array(legs[0]),
        left: Limb::from_array(legs[1]),
    };
    let Ok(model) = Phak::new(&a) else {
        defmt::panic!("Phak::new refused subject {=usize}", subject);
    };
    model
}

/// Every case: each f32 point within POINT_TOLERANCE_M of the f64 point (largest error logged).
pub fn f32_points_match_host_f64() {
    let models = [phak(0), phak(1)];
    let mut worst = 0.0f64;
    for (subject, angles, points, _) in expected::CASES {
        let pose = models[*subject].fk(&PhakAngles::from_array(*angles));
        for (got, want) in pose.points().iter().zip(points) {
            let got = got.to_array();
            for k in 0..3 {
                worst = worst.max((f64::from(got[k]) - want[k]).abs());
            }
        }
    }
    defmt::info!(
        "kernel f32 vs f64: largest point error {=f64} m over {=usize} cases",
        worst,
        expected::CASES.len()
    );
    defmt::assert!(
        worst <= POINT_TOLERANCE_M,
        "largest f32 point error {=f64} m",
        worst
    );
}

/// Every case: knee, ankle and toe distances within 2 * POINT_TOLERANCE_M of the f64 values.
pub fn f32_distances_match_host_f64() {
    let models = [phak(0), phak(1)];
    let mut worst = 0.0f64;
    for (subject, angles, _, want) in expected::CASES {
        let got = distances(&models[*subject].fk(&PhakAngles::from_array(*angles))).to_array();
        for k in 0..3 {
            worst = worst.max((f64::from(got[k]) - want[k]).abs());
        }
    }
    defmt::assert!(
        worst <= 2.0 * POINT_TOLERANCE_M,
        "largest f32 distance error {=f64} m",
        worst
    );
}

/// The cases really exercise the model: the toe moves by more than 10 cm between cases.
pub fn cases_are_not_degenerate() {
    let toe_x = expected::CASES.iter().map(|c| c.2[3][0]);
    let (lo, hi) = toe_x.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    defmt::assert!(
        hi - lo > 0.1,
        "spread of toe_r.x over the cases {=f64} m",
        hi - lo
    );
}

/// The kernel's `sqrt_f32` (the FPU's `vsqrt.f32` here) is correctly rounded: for 20,000
/// positive floats spread over every exponent, no neighbouring `f32` squares closer to `x`
/// (compared in f64, where the squares of floats are exact); and the IEEE special cases.
pub fn sqrt_f32_is_correctly_rounded() {
    let mut bits = 0x2545_F491u32;
    for _ in 0..20_000 {
        bits = bits.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        let x = f32::from_bits(bits & 0x7f7f_ffff); // positive and finite
        let y = sqrt_f32(x);
        let miss = |r: f32| (f64::from(r) * f64::from(r) - f64::from(x)).abs();
        let (below, above) = (
            f32::from_bits(y.to_bits().saturating_sub(1)),
            f32::from_bits(y.to_bits() + 1),
        );
        defmt::assert!(
            miss(y) <= miss(below) && miss(y) <= miss(above),
            "sqrt_f32({=f32}) = {=f32} is not the nearest float",
            x,
            y
        );
    }
    let special = [
        (0.0f32, 0.0f32),
        (1.0, 1.0),
        (4.0, 2.0),
        (f32::INFINITY, f32::INFINITY),
    ];
    for (x, want) in special {
        defmt::assert!(sqrt_f32(x) == want, "sqrt_f32({=f32})", x);
    }
    defmt::assert!(sqrt_f32(-1.0).is_nan() && sqrt_f32(f32::NAN).is_nan());
}

/// The stack paint is in place below the deepest use so far, so `stack::peak` can measure.
pub fn stack_paint_is_measurable() {
    let (peak, size) = (stack::peak(), stack::size());
    defmt::info!("test stack peak {=u32} bytes", peak);
    defmt::assert!(
        peak > 0 && peak < size,
        "stack peak {=u32} of {=u32} bytes",
        peak,
        size
    );
}
