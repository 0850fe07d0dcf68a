//! Host cost of the IMU path per frame, in `f64`: eight calibrated segment orientations to
//! gait2392's coordinates (the per-leg least squares, or the closed form) and gait2392's FK,
//! PHAK's (its own axes) and PHAK's FK, and OpenSense's Rajagopal model's (an imported chain)
//! and its FK,
//! on the real recording of `../shared/data/imu/` (OpenSense tutorial, first 12 s) with
//! OpenSense's settings (base IMU `torso_imu`, heading axis `z`, sensor-to-OpenSim (-pi/2, 0,
//! 0)). Each iteration solves the next frame of the recording, warm-started from the previous
//! one as `qgait imu` does. BENCHMARKS.md sets the median beside OpenSense's own IK
//! (`scripts/opensense_ik_timing.py`).
//!
//! `cargo bench -p qgait-model --bench imu` (criterion; medians in target/criterion). Without
//! `../shared` it prints why and measures nothing.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::imu::{
    Calibration, FitSolver, Heading, HeadingAxis, Mode, Orientations, Segment, Settings, Solver,
};
use qgait_kernel::models::{Phak, PhakAngles};
use qgait_kernel::{Gait2392, Gait2392Geometry};
use qgait_opensim::imu_sto::OrientationReader;

/// The recording's frames used (the 12 s OpenSense's reference solution covers).
const FRAMES: usize = 1201;

fn imu_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/imu");
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
    // The generic least squares: PHAK on its own axes, and OpenSense's own Rajagopal model
    // (an imported chain: numeric Jacobian through the chain's frames, lumbar locked as in
    // that model), each with its FK.
    let phak = Phak::<f64>::new(&Anthropometry::gait2392()).expect("PHAK");
    let phak_calibration =
        Calibration::for_model(&phak, &pose.readings, &settings).expect("calibrates");
    let phak_frames = segments(&phak_calibration, &dir);
    let mut solver = FitSolver::<f64, 8>::new();
    let mut next = 0;
    group.bench_function("phak_least_squares_and_fk", |b| {
        b.iter(|| {
            let solved = solver.solve(&phak, &phak_frames[next]);
            next = (next + 1) % phak_frames.len();
            black_box(phak.fk(&PhakAngles::from_array(solved.coordinates)))
        })
    });
    let osim = dir.join("../opensim/Rajagopal2015_opensense.osim");
    if let Ok(text) = std::fs::read_to_string(&osim) {
        let imported = qgait_model::leg_chain::import(&text, "Rajagopal2015_opensense", None)
            .expect("imports");
        let chain = imported.model.chain("bench").expect("a chain");
        let (min, max) = imported.model.bounds("bench").expect("ranges");
        let chain_calibration =
            Calibration::for_model(&chain, &pose.readings, &settings).expect("calibrates");
        let chain_frames = segments(&chain_calibration, &dir);
        let mut solver = FitSolver::<f64, 17>::new();
        (solver.min, solver.max) = (min, max);
        solver.torso_on_pelvis = true;
        let mut next = 0;
        group.bench_function("rajagopal_chain_least_squares_and_fk", |b| {
            b.iter(|| {
                let solved = solver.solve(&chain, &chain_frames[next]);
                next = (next + 1) % chain_frames.len();
                black_box(chain.forward(&solved.coordinates))
            })
        });
    }
    group.finish();
}

/// The recording's first [`FRAMES`] frames as segment orientations for `calibration`.
fn segments(calibration: &Calibration<f64>, dir: &Path) -> Vec<Orientations<f64>> {
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
    frames
}

criterion_group!(benches, bench);
criterion_main!(benches);
