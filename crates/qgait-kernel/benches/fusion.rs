//! Host throughput of orientation estimation: the kernel's VQF (`fusion::Vqf<f64>`), 9D and 6D,
//! over a run of samples of a sensor in motion.
//!
//! `cargo bench -p qgait-kernel --bench fusion` (criterion; medians in target/criterion).
//! Element throughput = updates: criterion prints updates per second per core.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait_kernel::fusion::Vqf;
use qgait_kernel::{Quat, Vec3};
use std::hint::black_box;

/// Samples per iteration (14.3 s at BROAD's 285.7 Hz).
const RUN: usize = 4096;
/// BROAD's sampling period, s.
const TS: f64 = 0.0035;

/// A sensor turning about the vertical at 100 °/s while it tilts back and forth by ±0.5 rad
/// about a tilted axis at 0.5 Hz: (gyr rad/s, acc m/s², mag µT) in the sensor frame.
fn samples() -> Vec<([f64; 3], [f64; 3], [f64; 3])> {
    let axis = Vec3::new(0.3, 0.5, 0.8).normalized();
    let up = Vec3::new(0.0, 0.0, 1.0);
    let (turn, tilt, amplitude) = (100f64.to_radians(), std::f64::consts::PI, 0.5);
    (0..RUN)
        .map(|k| {
            let t = k as f64 * TS;
            let tilt_q = Quat::from_axis_angle(axis, amplitude * (tilt * t).sin());
            let q = Quat::from_axis_angle(up, turn * t) * tilt_q;
            let w = tilt_q.conj().rotate(up * turn) + axis * (amplitude * tilt * (tilt * t).cos());
            (
                w.to_array(),
                q.conj().rotate(Vec3::new(0.0, 0.0, 9.81)).to_array(),
                q.conj().rotate(Vec3::new(0.0, 19.3, -39.5)).to_array(),
            )
        })
        .collect()
}

fn bench_vqf(c: &mut Criterion) {
    let input = samples();
    let mut group = c.benchmark_group("vqf_f64");
    group.throughput(Throughput::Elements(RUN as u64));
    for nine_d in [true, false] {
        let mut vqf = Vqf::<f64>::new_default(TS);
        // Past the filters' running-mean start and the first acceptance of the field.
        for _ in 0..3 {
            for (g, a, m) in &input {
                vqf.update(*g, *a, nine_d.then_some(*m));
            }
        }
        let name = if nine_d { "update_9d" } else { "update_6d" };
        group.bench_function(name, |b| {
            b.iter(|| {
                for (g, a, m) in black_box(&input) {
                    vqf.update(*g, *a, nine_d.then_some(*m));
                    black_box(if nine_d { vqf.quat_9d() } else { vqf.quat_6d() });
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_vqf);
criterion_main!(benches);
