//! Host throughput of `qgait fuse`'s three steps on one shared BROAD trial (03, 58,412 samples
//! at 285.7 Hz, 8.4 MB): reading the CSV (`read_csv`), VQF over it (`fuse`, 9D and 6D) and
//! writing the orientation `.sto` (`write_orientations`, into memory). Element throughput =
//! samples. Prints why and does nothing when the shared data are absent.
//!
//! `cargo bench -p qgait-fusion --bench fuse` (criterion; medians in target/criterion).

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait_fusion::{fuse, read_csv, write_orientations, Mode};

fn bench_fuse(c: &mut Criterion) {
    let path = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"))
        .join("data/broad/03_undisturbed_slow_rotation_C.csv");
    if !path.is_file() {
        eprintln!("SKIPPED: {} not found (set QGAIT_SHARED)", path.display());
        return;
    }
    let rec = read_csv(&path).unwrap();
    let q = fuse(&rec, Mode::NineD, |_| {}).unwrap();
    let mut group = c.benchmark_group("fuse_trial03");
    group.sample_size(10);
    group.throughput(Throughput::Elements(rec.len() as u64));
    group.bench_function("read_csv", |b| b.iter(|| read_csv(&path).unwrap()));
    group.bench_function("fuse_9d", |b| {
        b.iter(|| fuse(&rec, Mode::NineD, |_| {}).unwrap())
    });
    group.bench_function("fuse_6d", |b| {
        b.iter(|| fuse(&rec, Mode::SixD, |_| {}).unwrap())
    });
    let mut buffer = Vec::with_capacity(4 << 20);
    group.bench_function("write_sto", |b| {
        b.iter(|| {
            buffer.clear();
            write_orientations(
                &mut buffer,
                1.0 / rec.period,
                &rec.times,
                &["pelvis_imu"],
                &[&q],
            )
            .unwrap();
            std::hint::black_box(buffer.len())
        })
    });
    group.finish();
}

criterion_group!(benches, bench_fuse);
criterion_main!(benches);
