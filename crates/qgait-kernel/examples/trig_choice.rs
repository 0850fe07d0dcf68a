//! Measures the f32 sine/cosine options for the device and what each costs in millimetres.
//!
//! `cargo run --release -p qgait-kernel --example trig_choice`
//!
//! Prints the max absolute error on [-pi, pi] of micromath's `sin`/`cos`, libm's `sinf`/`cosf`
//! and the kernel's half-angle polynomial, then the worst HAK toe error (gait2392 lengths,
//! 100,000 seeded random angle sets) when the quaternion chain's half-angle sine/cosine come from
//! each of them, against f64.

use micromath::F32Ext;
use qgait_kernel::{trig, Limb, Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

type SinCos = fn(f32) -> (f32, f32);

fn micromath_half(x: f32) -> (f32, f32) {
    let h = 0.5 * x;
    (F32Ext::sin(h), F32Ext::cos(h))
}

fn libm_half(x: f32) -> (f32, f32) {
    libm::sincosf(0.5 * x)
}

/// HAK's toe by quaternions with a chosen half-angle sine/cosine, in f32.
fn toe(limb: &Limb<f32>, q: [f32; 3], sc: SinCos) -> Vec3<f32> {
    let z = Vec3::unit_z();
    let quat = |a| {
        let (s, c) = sc(a);
        Quat::from_axis_half_sin_cos(z, s, c)
    };
    let q1 = quat(q[0]);
    let q12 = q1 * quat(q[1]);
    let q123 = q12 * quat(q[2]);
    q1.rotate(Vec3::new(0.0, -limb.femur, 0.0))
        + q12.rotate(Vec3::new(0.0, -limb.tibia, 0.0))
        + q123.rotate(Vec3::new(limb.foot, 0.0, 0.0))
}

fn main() {
    let options: [(&str, SinCos); 3] = [
        ("micromath sin/cos", micromath_half),
        ("libm sinf/cosf", libm_half),
        ("qgait half-angle polynomial", trig::half_angle_sin_cos_f32),
    ];
    println!("max abs error of (sin, cos)(x/2) for x in [-pi, pi]:");
    for (name, f) in options {
        let mut worst = 0.0f64;
        for i in 0..=1_000_000 {
            let x = (-core::f64::consts::PI + 2.0 * core::f64::consts::PI * i as f64 / 1e6) as f32;
            let (s, c) = f(x);
            let (es, ec) = libm::sincos(0.5 * x as f64);
            worst = worst.max((s as f64 - es).abs()).max((c as f64 - ec).abs());
        }
        println!("  {name:<28} {worst:.2e}");
    }
    let limb64 = Limb::<f64>::gait2392();
    let limb32 = Limb::<f32>::gait2392();
    println!("worst HAK toe error vs f64 over 100,000 random angle sets (gait2392 lengths):");
    for (name, f) in options {
        let mut rng = SmallRng::seed_from_u64(7);
        let mut worst = 0.0f64;
        for _ in 0..100_000 {
            let q: [f64; 3] = core::array::from_fn(|_| {
                rng.random_range(-core::f64::consts::PI..core::f64::consts::PI)
            });
            let exact = qgait_kernel::reference::hak_geometric(
                &limb64,
                &qgait_kernel::HakAngles::from_array(q),
            )
            .toe;
            worst = worst.max(exact.max_abs_diff(toe(&limb32, q.map(|v| v as f32), f).cast()));
        }
        println!("  {name:<28} {:.3} µm", worst * 1e6);
    }
}
