//! The IMU path on synthetic recordings made by the kernel's own forward kinematics from known
//! coordinates (the generator: `imu_common`): exact data come back exactly in both modes and
//! both precisions; noise, calibration noise and heading drift stay within 2.5 degrees rms; a
//! sensor that moved after calibration, or a base IMU that does not point forward, is seen.

mod imu_common;

use imu_common::*;
use qgait_kernel::imu::{Calibration, ImuAngles, Mode, Orientations, Settings, Solver};
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat, Real};

/// Per determined coordinate: (name, rms error, max error) in degrees.
type Errors = Vec<(&'static str, f64, f64)>;

fn cast<T: Real>(o: &Orientations<f64>) -> Orientations<T> {
    Orientations {
        q: o.q.map(|q| {
            q.map(|q| {
                Quat::new(
                    T::from_f64(q.w),
                    T::from_f64(q.x),
                    T::from_f64(q.y),
                    T::from_f64(q.z),
                )
            })
        }),
    }
}

/// Calibrates on the recording's static pose with the tutorial's settings (heading from the
/// torso's z), solves every frame in `mode` in precision `T`, and compares with the truth.
fn errors<T: Real>(rec: &Recording, mode: Mode) -> Errors {
    let model = Gait2392::<T>::new(&Gait2392Geometry::generic()).unwrap();
    let cal = Calibration::new(
        &model,
        &cast(&rec.calibration),
        &Settings::opensense_tutorial(),
    )
    .unwrap();
    let mut solver = Solver::<T>::new();
    let det = determined();
    let mut sum = vec![0.0; det.len()];
    let mut max = vec![0.0f64; det.len()];
    for (readings, q, lumbar) in &rec.frames {
        let seg = cal.segments(&cast(readings)).unwrap();
        let out: ImuAngles<T> = solver.solve(&model, &seg, mode);
        for (k, (i, _)) in det.iter().enumerate() {
            let (got, want) = if *i < 17 {
                (out.coordinates[*i].to_f64(), q[*i])
            } else {
                (out.lumbar[i - 17].to_f64(), lumbar[i - 17])
            };
            let e = (got - want) / DEG;
            sum[k] += e * e;
            max[k] = max[k].max(e.abs());
        }
    }
    det.iter()
        .enumerate()
        .map(|(k, (_, name))| (*name, (sum[k] / rec.frames.len() as f64).sqrt(), max[k]))
        .collect()
}

fn print(title: &str, e: &Errors) {
    eprintln!("{title}: coordinate, rms, max error (degrees)");
    for (name, rms, max) in e {
        eprintln!("  {name:18} {rms:10.6} {max:10.6}");
    }
}

fn worst_max(e: &Errors) -> f64 {
    e.iter().map(|x| x.2).fold(0.0, f64::max)
}

fn worst_rms(e: &Errors) -> f64 {
    e.iter().map(|x| x.1).fold(0.0, f64::max)
}

fn exact() -> Recording {
    let m = mountings(7);
    recording(10.0, &m, &m, Disturbance::default())
}

#[test]
fn exact_data_come_back_within_a_hundredth_of_a_degree_in_f64() {
    let rec = exact();
    for mode in [Mode::ClosedForm, Mode::LeastSquares] {
        let e = errors::<f64>(&rec, mode);
        print(&format!("f64 {mode:?}"), &e);
        assert!(worst_max(&e) < 0.01, "{mode:?}: {}", worst_max(&e));
    }
}

/// gait2392 clamps no coordinate, so OpenSense's inverse kinematics bounds none: a knee
/// hyperextended past the model's +10° range, or a hip flexed past its 120°, comes back as it is.
#[test]
fn coordinates_beyond_the_models_ranges_are_not_bounded() {
    let model = model();
    let mount = mountings(3);
    let rec = recording(0.1, &mount, &mount, Disturbance::default());
    let cal = Calibration::new(&model, &rec.calibration, &Settings::opensense_tutorial()).unwrap();
    let s_inv = sensor_to_opensim().conj();
    let (_, q0, lumbar) = &rec.frames[0];
    let mut q = *q0;
    q[6] = 15.0 * DEG; // knee_angle_r (range -120..10)
    q[10] = 125.0 * DEG; // hip_flexion_l (range -120..120)
    let bodies = segments(&model, &q, lumbar);
    let mut readings = Orientations::EMPTY;
    for (i, seg) in qgait_kernel::imu::Segment::ALL.into_iter().enumerate() {
        readings.set(seg, Some(s_inv * bodies[i] * mount[i]));
    }
    let seg = cal.segments(&readings).unwrap();
    for mode in [Mode::ClosedForm, Mode::LeastSquares] {
        let mut solver = Solver::<f64>::new();
        let mut out: ImuAngles<f64> = solver.solve(&model, &seg, mode);
        for _ in 0..5 {
            out = solver.solve(&model, &seg, mode);
        }
        for i in [6, 10] {
            let e = (out.coordinates[i] - q[i]).abs() / DEG;
            assert!(e < 0.01, "{mode:?} coordinate {i}: {e} off");
        }
    }
}

#[test]
fn exact_data_in_f32_are_close() {
    let rec = exact();
    for mode in [Mode::ClosedForm, Mode::LeastSquares] {
        let e = errors::<f32>(&rec, mode);
        print(&format!("f32 {mode:?}"), &e);
        // Measured: 0.0001 degrees.
        assert!(worst_max(&e) < 0.001, "{mode:?}: {}", worst_max(&e));
    }
}

#[test]
fn other_mountings_and_seeds_also_exact() {
    for seed in [1, 2, 3] {
        let m = mountings(100 + seed);
        let rec = recording(3.0, &m, &m, Disturbance::default());
        let e = errors::<f64>(&rec, Mode::LeastSquares);
        assert!(worst_max(&e) < 0.01, "seed {seed}: {}", worst_max(&e));
    }
}

/// Pools the squared errors of several recordings (rms over time and over the random draws of
/// noise, calibration noise and drift rates): per coordinate (name, rms, worst single-recording
/// rms) in degrees.
fn pooled<T: Real>(recs: &[Recording], mode: Mode) -> Errors {
    let per: Vec<Errors> = recs.iter().map(|r| errors::<T>(r, mode)).collect();
    (0..per[0].len())
        .map(|k| {
            let mean_square = per.iter().map(|e| e[k].1 * e[k].1).sum::<f64>() / per.len() as f64;
            let worst = per.iter().map(|e| e[k].1).fold(0.0, f64::max);
            (per[0][k].0, mean_square.sqrt(), worst)
        })
        .collect()
}

#[test]
fn noise_calibration_noise_and_heading_drift_stay_within_two_and_a_half_degrees_rms() {
    // 1 degree rms rotation noise on every reading and on the calibration pose; each sensor's
    // heading drifting at a constant rate of up to 3 degrees a minute (1 degree after the
    // 20 s). Eight seeded draws of noise, drift rates and mountings; the rms pools them (one
    // draw's calibration noise is a constant bias, so a single recording's rms is one sample).
    let recs: Vec<Recording> = (1..=8)
        .map(|seed| {
            let m = mountings(10 + seed);
            let d = Disturbance {
                noise: 1.0 * DEG,
                drift: 3.0 * DEG / 60.0,
                seed,
            };
            recording(20.0, &m, &m, d)
        })
        .collect();
    for mode in [Mode::LeastSquares, Mode::ClosedForm] {
        let e = pooled::<f64>(&recs, mode);
        print(
            &format!("noise 1 deg rms, drift, f64 {mode:?} (rms, worst recording's rms)"),
            &e,
        );
        assert!(worst_rms(&e) < 2.5, "{mode:?}: {}", worst_rms(&e));
    }
    let e = pooled::<f32>(&recs[..2], Mode::LeastSquares);
    print(
        "noise 1 deg rms, drift, f32 LeastSquares (2 recordings)",
        &e,
    );
    assert!(worst_rms(&e) < 2.5, "f32: {}", worst_rms(&e));
    // Without the disturbances the same recordings are exact: the bound measures them.
    let m = mountings(11);
    let clean = recording(20.0, &m, &m, Disturbance::default());
    assert!(worst_max(&errors::<f64>(&clean, Mode::LeastSquares)) < 0.01);
}

#[test]
fn a_sensor_that_moved_after_calibration_is_seen() {
    // The right femur's sensor turned 10 degrees about its long axis between the calibration
    // and the walk: the hip's rotation is off by about that much.
    let m = mountings(7);
    let mut moved = m;
    moved[1] = moved[1] * Quat::from_axis_angle(qgait_kernel::Vec3::unit_y(), 10.0 * DEG);
    let rec = recording(3.0, &moved, &m, Disturbance::default());
    let e = errors::<f64>(&rec, Mode::LeastSquares);
    print("right femur sensor moved", &e);
    let hip_rotation = e.iter().find(|x| x.0 == "hip_rotation_r").unwrap();
    assert!(hip_rotation.1 > 2.0, "{hip_rotation:?}");
    // The left leg does not notice.
    assert!(e.iter().filter(|x| x.0.ends_with("_l")).all(|x| x.2 < 0.01));
}

#[test]
fn a_base_imu_not_pointing_forward_turns_the_joint_axes() {
    // The torso sensor's z axis 20 degrees off the forward direction (about the vertical): the
    // heading correction is 20 degrees wrong, so every segment is seen turned about the
    // vertical and the joint angles mix (flexion into adduction).
    let mut m = mountings(7);
    m[7] = Quat::from_axis_angle(qgait_kernel::Vec3::unit_y(), 20.0 * DEG) * m[7];
    let rec = recording(3.0, &m, &m, Disturbance::default());
    let e = errors::<f64>(&rec, Mode::LeastSquares);
    print("base IMU 20 degrees off forward", &e);
    assert!(worst_max(&e) > 1.0, "{}", worst_max(&e));
    let pelvis_rotation = e.iter().find(|x| x.0 == "pelvis_rotation").unwrap();
    assert!(
        (pelvis_rotation.1 - 20.0).abs() < 0.5,
        "{pelvis_rotation:?}"
    );
}
