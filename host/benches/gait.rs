//! `qgait gait` on the 24 s IMU walking recording (2,432 rows at 100 Hz, through `qgait imu`):
//! the analysis (load, gait2392 FK of every row, events, cycles, angles, spatiotemporal
//! parameters, GPS against the normative data) and the whole report with its figures.
//!
//! `cargo bench -p qgait --bench gait` (criterion; medians in target/criterion). Needs the
//! shared data (`../shared/data/imu`, `../shared/data/normative`); skips with a message
//! without it.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use qgait_gait::output::{self, ReferenceArg, Subject};
use qgait_gait::{analyse, trial, CycleMode};
use qgait_model::choice::Model;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let shared = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    let imu = shared.join("imu");
    if !imu.join("walking_orientations.sto").is_file() {
        eprintln!("skipped: no shared data at {}", shared.display());
        return;
    }
    let dir = tempfile::tempdir().expect("temporary directory");
    let mot = dir.path().join("walk.mot");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_qgait"))
        .args(["-q", "imu"])
        .arg(imu.join("walking_orientations.sto"))
        .arg("--calibration")
        .arg(imu.join("placement_orientations.sto"))
        .args(["--base-imu", "torso_imu", "-o"])
        .arg(&mot)
        .status()
        .expect("qgait imu runs");
    assert!(status.success());
    let mot = mot.to_str().expect("utf-8 path").to_string();
    let (model, _) = Model::load("gait2392", None).expect("gait2392");
    let normative = qgait_gait::normative::Source::Dir(shared.join("normative"));
    let analysis = || {
        let (t, _) = trial::load(&mot, &model).expect("loads");
        let walk = analyse(t, CycleMode::Auto).expect("analyses");
        output::build(
            vec![walk],
            "gait2392".into(),
            CycleMode::Auto,
            &ReferenceArg::Normative(None),
            None,
            &normative,
            Subject::default(),
        )
        .expect("builds")
    };
    let mut g = c.benchmark_group("gait");
    g.sample_size(10);
    g.bench_function("imu_walk_24s_analysis", |b| {
        b.iter(|| black_box(analysis()))
    });
    let out = dir.path().join("out");
    g.bench_function("imu_walk_24s_report", |b| {
        b.iter(|| black_box(qgait_gait::files::write(&analysis(), &out).expect("writes")))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
