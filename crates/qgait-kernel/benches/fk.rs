//! Host throughput of forward kinematics: per model (HAK, PHAK, gait2392), per method
//! (quaternion chain, homogeneous matrices), per precision, single frame and batch.
//!
//! `cargo bench -p qgait-kernel --bench fk` (criterion; medians in target/criterion).
//! Element throughput = frames: criterion prints frames per second per core.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use qgait_kernel::lanes::LaneScalar;
use qgait_kernel::reference::chain_by_matrices;
use qgait_kernel::{
    Anthropometry, BilateralPose, Gait2392, Gait2392Geometry, Gait2392Pose, Hak, HakAngles,
    LegPose, Limb, Phak, PhakAngles, Real, Vec3,
};
use std::hint::black_box;

const BATCH: usize = 4096;

/// Deterministic, gait-like angles (a few tenths of a radian), `n` frames of `N` coordinates.
fn angles<T: Real, const N: usize>(n: usize) -> Vec<[T; N]> {
    (0..n)
        .map(|i| {
            core::array::from_fn(|c| T::from_f64(0.6 * ((i * 7 + c * 13) as f64 * 0.017).sin()))
        })
        .collect()
}

fn bench_precision<T: LaneScalar + nalgebra::RealField>(c: &mut Criterion, precision: &str) {
    let phak = Phak::<T>::new(&Anthropometry::gait2392()).unwrap();
    let hak = Hak::<T>::new(&Limb::gait2392()).unwrap();
    let g = Gait2392::<T>::new(&Gait2392Geometry::generic()).unwrap();
    let q8 = angles::<T, 8>(BATCH);
    let q3 = angles::<T, 3>(BATCH);
    let q17 = angles::<T, 17>(BATCH);

    let mut single = c.benchmark_group(format!("single_frame/{precision}"));
    single.throughput(Throughput::Elements(1));
    single.bench_function("hak/quat", |b| {
        b.iter(|| hak.fk(&HakAngles::from_array(black_box(q3[1]))))
    });
    single.bench_function("hak/matrix", |b| {
        b.iter(|| chain_by_matrices(hak.chain(), black_box(&q3[1])))
    });
    single.bench_function("phak/quat", |b| {
        b.iter(|| phak.fk(&PhakAngles::from_array(black_box(q8[1]))))
    });
    single.bench_function("phak/matrix", |b| {
        b.iter(|| chain_by_matrices(phak.chain(), black_box(&q8[1])))
    });
    single.bench_function("gait2392/quat", |b| b.iter(|| g.fk(black_box(&q17[1]))));
    single.bench_function("gait2392/matrix", |b| {
        b.iter(|| chain_by_matrices(g.chain(), black_box(&q17[1])))
    });
    single.finish();

    let mut batch = c.benchmark_group(format!("batch/{precision}"));
    batch.throughput(Throughput::Elements(BATCH as u64));
    let phak_in: Vec<PhakAngles<T>> = q8.iter().map(|q| PhakAngles::from_array(*q)).collect();
    let hak_in: Vec<HakAngles<T>> = q3.iter().map(|q| HakAngles::from_array(*q)).collect();
    let mut phak_out = vec![BilateralPose::default(); BATCH];
    let mut hak_out = vec![LegPose::default(); BATCH];
    let mut g_out = vec![
        Gait2392Pose {
            points: [Vec3::zero(); 12]
        };
        BATCH
    ];
    batch.bench_function(BenchmarkId::new("hak", BATCH), |b| {
        b.iter(|| hak.fk_batch(black_box(&hak_in), &mut hak_out))
    });
    batch.bench_function(BenchmarkId::new("phak", BATCH), |b| {
        b.iter(|| phak.fk_batch(black_box(&phak_in), &mut phak_out))
    });
    batch.bench_function(BenchmarkId::new("gait2392", BATCH), |b| {
        b.iter(|| g.fk_batch(black_box(&q17), &mut g_out))
    });
    // The same frames one at a time, for the batch's speed-up.
    batch.bench_function(BenchmarkId::new("phak_loop_of_single", BATCH), |b| {
        b.iter(|| {
            for (q, o) in black_box(&phak_in).iter().zip(phak_out.iter_mut()) {
                *o = phak.fk(q);
            }
        })
    });
    batch.finish();
}

fn benches(c: &mut Criterion) {
    bench_precision::<f64>(c, "f64");
    bench_precision::<f32>(c, "f32");
}

criterion_group!(fk, benches);
criterion_main!(fk);
