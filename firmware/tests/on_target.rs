//! On-target tests, run under QEMU by `cargo test --release` (see README): the kernel in f32
//! on the Cortex-M4F against f64 values computed on the host at build time (PHAK here,
//! gait2392 and a subject model sent to the hub in `on_target/gait2392.rs`), the UART receive
//! ring's block read (`on_target/rx_ring.rs`), and the hub's
//! shared scenario checks (sample assembly, error counting, configuration) on the target.
//! Ends with the line `N passed, M failed`.

#![no_std]
#![no_main]

use cortex_m_rt::entry;
use qgait_firmware::selftest::{Failure, Harness};
use qgait_firmware::stack;
use qgait_kernel::metrics::distances;
use qgait_kernel::trig::sqrt_f32;
use qgait_kernel::{Anthropometry, Limb, Phak, PhakAngles};

#[path = "on_target/gait2392.rs"]
mod gait2392;
#[path = "on_target/rx_ring.rs"]
mod rx_ring;

mod expected {
    include!(concat!(env!("OUT_DIR"), "/kernel_cases.rs"));
}

/// Largest accepted distance between an f32 point and its f64 value (metres): 5 µm, well
/// under IMU-derived accuracy, about 40 f32 ulps of a 1 m coordinate.
const POINT_TOLERANCE_M: f64 = 5e-6;

fn phak(subject: usize) -> Result<Phak<f32>, Failure> {
    let legs = expected::SUBJECTS[subject];
    let a = Anthropometry {
        right: Limb::from_array(legs[0]),
        left: Limb::from_array(legs[1]),
    };
    Phak::new(&a).map_err(|_| Failure {
        what: "Phak::new refused the subject",
        line: line!(),
        value: None,
    })
}

/// Every case: each f32 point within POINT_TOLERANCE_M of the f64 point (largest error logged).
fn kernel_f32_points_match_host_f64() -> Result<(), Failure> {
    let models = [phak(0)?, phak(1)?];
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
    if worst <= POINT_TOLERANCE_M {
        Ok(())
    } else {
        Err(Failure {
            what: "largest f32 point error (m)",
            line: line!(),
            value: Some(worst),
        })
    }
}

/// Every case: knee, ankle and toe distances within 2 * POINT_TOLERANCE_M of the f64 values.
fn kernel_f32_distances_match_host_f64() -> Result<(), Failure> {
    let models = [phak(0)?, phak(1)?];
    let mut worst = 0.0f64;
    for (subject, angles, _, want) in expected::CASES {
        let got = distances(&models[*subject].fk(&PhakAngles::from_array(*angles))).to_array();
        for k in 0..3 {
            worst = worst.max((f64::from(got[k]) - want[k]).abs());
        }
    }
    if worst <= 2.0 * POINT_TOLERANCE_M {
        Ok(())
    } else {
        Err(Failure {
            what: "largest f32 distance error (m)",
            line: line!(),
            value: Some(worst),
        })
    }
}

/// The cases really exercise the model: the toe moves by more than 10 cm between cases.
fn kernel_cases_are_not_degenerate() -> Result<(), Failure> {
    let toe_x = expected::CASES.iter().map(|c| c.2[3][0]);
    let (lo, hi) = toe_x.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    if hi - lo > 0.1 {
        Ok(())
    } else {
        Err(Failure {
            what: "spread of toe_r.x over the cases (m)",
            line: line!(),
            value: Some(hi - lo),
        })
    }
}

/// The kernel's `sqrt_f32` (the FPU's `vsqrt.f32` here) is correctly rounded: for 20,000
/// positive floats spread over every exponent, no neighbouring `f32` squares closer to `x`
/// (compared in f64, where the squares of floats are exact); and the IEEE special cases.
fn sqrt_f32_is_correctly_rounded() -> Result<(), Failure> {
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
        if !(miss(y) <= miss(below) && miss(y) <= miss(above)) {
            return Err(Failure {
                what: "sqrt_f32 not the nearest float, at x",
                line: line!(),
                value: Some(f64::from(x)),
            });
        }
    }
    let special = [
        (0.0f32, 0.0f32),
        (1.0, 1.0),
        (4.0, 2.0),
        (f32::INFINITY, f32::INFINITY),
    ];
    for (x, want) in special {
        if sqrt_f32(x) != want {
            return Err(Failure {
                what: "sqrt_f32 of a special value",
                line: line!(),
                value: Some(f64::from(x)),
            });
        }
    }
    if !(sqrt_f32(-1.0).is_nan() && sqrt_f32(f32::NAN).is_nan()) {
        return Err(Failure {
            what: "sqrt_f32 of a negative or NaN is not NaN",
            line: line!(),
            value: None,
        });
    }
    Ok(())
}

/// The stack paint is in place below the deepest use so far, so stack::peak can measure.
fn stack_paint_is_measurable() -> Result<(), Failure> {
    let (peak, size) = (stack::peak(), stack::size());
    if peak > 0 && peak < size {
        Ok(())
    } else {
        Err(Failure {
            what: "stack peak (bytes)",
            line: line!(),
            value: Some(f64::from(peak)),
        })
    }
}

#[entry]
fn main() -> ! {
    let mut h = Harness::new();
    h.run(
        "kernel_f32_points_match_host_f64",
        kernel_f32_points_match_host_f64,
    );
    h.run(
        "kernel_f32_distances_match_host_f64",
        kernel_f32_distances_match_host_f64,
    );
    h.run(
        "kernel_cases_are_not_degenerate",
        kernel_cases_are_not_degenerate,
    );
    h.run(
        "sqrt_f32_is_correctly_rounded",
        sqrt_f32_is_correctly_rounded,
    );
    h.run(
        "gait2392_f32_points_match_host_f64",
        gait2392::gait2392_f32_points_match_host_f64,
    );
    h.run(
        "subject_model_on_the_hub_matches_host_f64",
        gait2392::subject_model_on_the_hub_matches_host_f64,
    );
    h.run(
        "rx_ring_block_read_wraps_around",
        rx_ring::rx_ring_block_read_wraps_around,
    );
    h.run(
        "rx_ring_errors_come_after_the_bytes_before_them",
        rx_ring::rx_ring_errors_come_after_the_bytes_before_them,
    );
    for (name, check) in qgait_hub::checks::ALL {
        h.run(name, || {
            check().map_err(|f| Failure {
                what: f.what,
                line: f.line,
                value: None,
            })
        });
    }
    h.run("stack_paint_is_measurable", stack_paint_is_measurable);
    defmt::info!("test stack peak {=u32} bytes", stack::peak());
    h.finish()
}
