//! Host cost of the IMU path per frame, in `f64`: eight calibrated segment orientations to
//! gait2392's coordinates (the per-leg least squares, or the closed form) and gait2392's FK,
//! on the real recording of `../shared/data/imu/` (OpenSense tutorial, first 12 s) with
//! OpenSense's settings (base IMU `torso_imu`, heading axis `z`, sensor-to-OpenSim (-pi/2, 0,
//! 0)). Each iteration solves the next frame of the recording, warm-started from the previous
//! one as `qgait imu` does. BENCHMARKS.md sets the median beside OpenSense's own IK
//! (`scripts/opensense_ik_timing.py`).
//!
//! `cargo bench -p qgait --bench imu` (criterion; medians in target/criterion). Without
//! `../shared` it prints why and measures nothing.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait::opensim::imu_sto::OrientationReader;
use qgait_kernel::imu::{Calibration, Heading, HeadingAxis, Mode, Segment, Settings, Solver};
use qgait_kernel::{Gait2392, Gait2392Geometry};

/// The recording's frames used (the 12 s OpenSense's reference solution covers).
const FRAMES: usize = 1201;

fn imu_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/imu");
    dir.is_dir().then_some(dir)
}

fn bench(c: &mut Criterion) {
    let Some(dir) = imu_dir() else {
        eprintln!("imu bench skipped: ../shared/data/imu is absent");
        return;
    };
    let model = Gait2392::<f64>::new(&Gait2392Geometry::generic()).expect("generic gait2392");
    let settings = Settings {
        heading: Some(Heading {
            base: Segment::from_name("torso_imu").expect("a segment"),
            axis: HeadingAxis::Z,
        }),
        ..Settings::default()
    };
    let mut placement = OrientationReader::open(&dir.join("placement_orientations.sto"))
        .expect("the calibration pose");
    let pose = placement.next_row().expect("readable").expect("one row");
    let calibration = Calibration::new(&model, &pose.readings, &settings).expect("calibrates");
    let mut reader =
        OrientationReader::open(&dir.join("walking_orientations.sto")).expect("the recording");
    let mut frames = Vec::new();
    while let Some(row) = reader.next_row().expect("readable") {
        if frames.len() == FRAMES {
            break;
        }
        frames.push(
            calibration
                .segments(&row.readings)
                .expect("unit quaternions"),
        );
    }
    let mut group = c.benchmark_group("imu_per_frame");
    group.throughput(Throughput::Elements(1));
    for (name, mode) in [
        ("least_squares_and_fk", Mode::LeastSquares),
        ("closed_form_and_fk", Mode::ClosedForm),
    ] {
        let mut solver = Solver::new();
        let mut next = 0;
        group.bench_function(name, |b| {
            b.iter(|| {
                let solved = solver.solve(&model, &frames[next], mode);
                next = (next + 1) % frames.len();
                black_box(model.fk(&solved.coordinates))
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
