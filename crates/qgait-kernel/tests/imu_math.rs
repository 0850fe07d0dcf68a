//! The IMU path's own pieces: its arctangent against libm in both precisions, the joint
//! decompositions against the rotations they decompose, the calibration's errors and
//! conventions, missing sensors and the unbounded pelvis rotation.

mod imu_common;

use imu_common::*;
use qgait_kernel::imu::{
    math, unit, Calibration, Heading, HeadingAxis, ImuError, Mode, Orientations, Segment, Settings,
    Solver,
};
use qgait_kernel::{Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

#[test]
fn atan2_matches_libm() {
    let mut rng = SmallRng::seed_from_u64(1);
    let (mut e64, mut e32) = (0.0f64, 0.0f64);
    for i in 0..200_000 {
        // Every quadrant and scale, the axes included.
        let (y, x): (f64, f64) = match i % 50 {
            0 => (0.0, rng.random_range(-2.0..2.0)),
            1 => (rng.random_range(-2.0..2.0), 0.0),
            _ => (rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0)),
        };
        e64 = e64.max((math::atan2(y, x) - libm::atan2(y, x)).abs());
        let (y32, x32) = (y as f32, x as f32);
        e32 = e32.max(
            (f64::from(math::atan2(y32, x32)) - libm::atan2(f64::from(y32), f64::from(x32))).abs(),
        );
    }
    eprintln!("atan2 max error: f64 {e64:e}, f32 {e32:e}");
    assert!(e64 < 2e-15, "{e64:e}");
    assert!(e32 < 1e-6, "{e32:e}");
    assert_eq!(math::atan2(0.0, 0.0), 0.0);
    assert_eq!(math::atan2(0.0, -1.0), core::f64::consts::PI);
    assert!(math::atan2(f64::NAN, 1.0).is_nan());
    assert!((math::acos(0.5f64) - core::f64::consts::FRAC_PI_3).abs() < 1e-15);
    assert_eq!(math::acos(1.5f64), 0.0);
}

#[test]
fn decompositions_invert_the_rotations_they_decompose() {
    let mut rng = SmallRng::seed_from_u64(2);
    let (x, y, z) = (Vec3::<f64>::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    let m = model();
    let joints = m.chain().joints();
    let [ankle, subtalar] = [joints[3].axes[0].direction, joints[4].axes[0].direction];
    let left_hip = [
        joints[6].axes[0].direction,
        joints[6].axes[1].direction,
        joints[6].axes[2].direction,
    ];
    let mut worst = 0.0f64;
    for _ in 0..20_000 {
        let a: [f64; 3] = [
            rng.random_range(-3.1..3.1),
            rng.random_range(-1.5..1.5),
            rng.random_range(-3.1..3.1),
        ];
        for axes in [[z, x, y], left_hip, [x, y, z], [y, -z, x]] {
            let q = Quat::from_axis_angle(axes[0], a[0])
                * Quat::from_axis_angle(axes[1], a[1])
                * Quat::from_axis_angle(axes[2], a[2]);
            let got = math::three_axes(q, axes);
            for k in 0..3 {
                worst = worst.max((got[k] - a[k]).abs());
            }
        }
        let q = Quat::from_axis_angle(ankle, a[0]) * Quat::from_axis_angle(subtalar, a[1]);
        let [g0, g1] = math::two_axes(q, ankle, subtalar);
        worst = worst.max((g0 - a[0]).abs()).max((g1 - a[1]).abs());
        let t = math::twist(Quat::from_axis_angle(ankle, a[0]), ankle);
        worst = worst.max((t - a[0]).abs());
        let r = math::rotation_vector(Quat::from_axis_angle(subtalar, a[0]));
        worst = worst.max((r - subtalar * a[0]).norm());
    }
    eprintln!("decompositions: max error {worst:e} rad");
    assert!(worst < 1e-12, "{worst:e}");
    // A wrong sequence does not decompose: the check can fail.
    let q = Quat::from_axis_angle(z, 0.3)
        * Quat::from_axis_angle(x, 0.2)
        * Quat::from_axis_angle(y, 0.1);
    let wrong = math::three_axes(q, [x, y, z]);
    assert!((wrong[0] - 0.3).abs() > 1e-3 || (wrong[1] - 0.2).abs() > 1e-3);
}

#[test]
fn space_fixed_xyz_is_opensims_convention() {
    // Space-fixed X then Y then Z: Rz Ry Rx. (-pi/2, 0, 0) takes a z-up world's z to y.
    let s = math::space_fixed_xyz([-90.0 * DEG, 0.0, 0.0]);
    assert!((s.rotate(Vec3::unit_z()) - Vec3::unit_y()).norm() < 1e-15);
    let r = math::space_fixed_xyz([0.1, 0.2, 0.3f64]);
    let want = Quat::from_axis_angle(Vec3::unit_z(), 0.3)
        * Quat::from_axis_angle(Vec3::unit_y(), 0.2)
        * Quat::from_axis_angle(Vec3::unit_x(), 0.1);
    assert!((r.w - want.w).abs() + (r.vector() - want.vector()).norm() < 1e-15);
}

fn static_pose(heading: f64, mount: &[Quat<f64>; 8]) -> Orientations<f64> {
    let mut q = [0.0; 17];
    q[2] = heading;
    let b = segments(&model(), &q, &[0.0; 3]);
    let s_inv = sensor_to_opensim().conj();
    let mut o = Orientations::EMPTY;
    for (i, seg) in Segment::ALL.into_iter().enumerate() {
        o.set(seg, Some(s_inv * b[i] * mount[i]));
    }
    o
}

#[test]
fn heading_is_opensenses_angle_and_sign() {
    // Facing 40 degrees left of the world's x (about +y): the correction is -40 degrees.
    let pose = static_pose(40.0 * DEG, &mountings(3));
    let cal = Calibration::new(&model(), &pose, &Settings::opensense_tutorial()).unwrap();
    assert!(
        (cal.heading() + 40.0 * DEG).abs() < 1e-12,
        "{}",
        cal.heading()
    );
    // The same axis reversed points backwards: 180 degrees more.
    let mut settings = Settings::opensense_tutorial();
    settings.heading = Some(Heading {
        base: Segment::Torso,
        axis: HeadingAxis::NegZ,
    });
    let cal = Calibration::new(&model(), &pose, &settings).unwrap();
    assert!(
        (cal.heading() - 140.0 * DEG).abs() < 1e-12,
        "{}",
        cal.heading()
    );
    // Without a heading correction, nothing is turned.
    let cal = Calibration::new(&model(), &pose, &Settings::default()).unwrap();
    assert_eq!(cal.heading(), 0.0);
    assert_eq!("-z".parse(), Ok(HeadingAxis::NegZ));
    assert!("w".parse::<HeadingAxis>().is_err());
}

#[test]
fn bad_calibrations_and_readings_are_refused() {
    let m = mountings(3);
    let mut pose = static_pose(0.0, &m);
    let settings = Settings::opensense_tutorial();
    let model = model();
    let good = pose.get(Segment::TibiaL).unwrap();
    pose.set(
        Segment::TibiaL,
        Some(Quat::new(
            good.w * 1.3,
            good.x * 1.3,
            good.y * 1.3,
            good.z * 1.3,
        )),
    );
    assert_eq!(
        Calibration::new(&model, &pose, &settings),
        Err(ImuError::NotUnit {
            segment: Segment::TibiaL
        })
    );
    // Slightly off unit length is normalised.
    pose.set(
        Segment::TibiaL,
        Some(Quat::new(
            good.w * 1.05,
            good.x * 1.05,
            good.y * 1.05,
            good.z * 1.05,
        )),
    );
    let cal = Calibration::new(&model, &pose, &settings).unwrap();
    let n = unit(Quat::new(1.05, 0.0, 0.0, 0.0), Segment::Pelvis).unwrap();
    assert_eq!(n, Quat::identity());
    assert!(unit(Quat::new(f64::NAN, 0.0, 0.0, 0.0), Segment::Pelvis).is_err());
    assert_eq!(
        cal.segment(Segment::Pelvis, Quat::new(0.0, 0.0, 0.0, 0.0)),
        Err(ImuError::NotUnit {
            segment: Segment::Pelvis
        })
    );
    pose.set(Segment::Torso, None);
    assert_eq!(
        Calibration::new(&model, &pose, &settings),
        Err(ImuError::BaseMissing {
            segment: Segment::Torso
        })
    );
    // The torso's y is vertical in the pose: no heading.
    let mut settings_y = settings;
    settings_y.heading = Some(Heading {
        base: Segment::Pelvis,
        axis: HeadingAxis::Y,
    });
    let mut upright = [Quat::identity(); 8];
    upright[0] = Quat::identity();
    assert_eq!(
        Calibration::new(&model, &static_pose(0.3, &upright), &settings_y),
        Err(ImuError::HeadingVertical {
            segment: Segment::Pelvis
        })
    );
    assert!(ImuError::HeadingVertical {
        segment: Segment::Pelvis
    }
    .to_string()
    .contains("pelvis_imu"));
    assert_eq!(Segment::from_name("calcn_l_imu"), Some(Segment::CalcnL));
    assert_eq!(Segment::from_name("tibia_r"), Some(Segment::TibiaR));
    assert_eq!(Segment::from_name("toes_r_imu"), None);
}

#[test]
fn missing_sensors_hold_their_coordinates() {
    let m = mountings(7);
    let rec = recording(1.0, &m, &m, Disturbance::default());
    let model = model();
    let cal = Calibration::new(&model, &rec.calibration, &Settings::opensense_tutorial()).unwrap();
    for mode in [Mode::ClosedForm, Mode::LeastSquares] {
        let mut solver = Solver::new();
        let mut last = None;
        for (k, (readings, q, _)) in rec.frames.iter().enumerate() {
            let mut readings = *readings;
            let dropped = k >= 50;
            if dropped {
                readings.set(Segment::CalcnR, None);
            }
            let out = solver.solve(&model, &cal.segments(&readings).unwrap(), mode);
            if dropped {
                // Ankle and subtalar of the right leg keep their last values; the rest follows.
                let held: [f64; 2] = last.unwrap();
                assert_eq!([out.coordinates[7], out.coordinates[8]], held);
                assert_eq!(out.held, 0b11 << 7, "{mode:?}");
                assert!((out.coordinates[6] - q[6]).abs() < 1e-6, "{mode:?}");
                assert!((out.coordinates[14] - q[14]).abs() < 1e-6, "{mode:?}");
            } else {
                assert_eq!(out.held, 0);
                last = Some([out.coordinates[7], out.coordinates[8]]);
            }
        }
    }
    // A sensor that was not in the calibration pose is ignored.
    let mut pose = rec.calibration;
    pose.set(Segment::FemurL, None);
    let cal = Calibration::new(&model, &pose, &Settings::opensense_tutorial()).unwrap();
    assert_eq!(cal.segment(Segment::FemurL, Quat::identity()), Ok(None));
    let seg = cal.segments(&rec.frames[10].0).unwrap();
    assert!(seg.get(Segment::FemurL).is_none() && seg.get(Segment::FemurR).is_some());
}

#[test]
fn pelvis_rotation_turns_without_wrapping() {
    // The synthetic walk turns 500 degrees in 10 s: pelvis_rotation follows continuously.
    let m = mountings(7);
    let rec = recording(10.0, &m, &m, Disturbance::default());
    let model = model();
    let cal = Calibration::new(&model, &rec.calibration, &Settings::opensense_tutorial()).unwrap();
    let mut solver = Solver::new();
    let mut prev: Option<f64> = None;
    let mut max = f64::MIN;
    for (readings, q, _) in &rec.frames {
        let out = solver.solve(&model, &cal.segments(readings).unwrap(), Mode::LeastSquares);
        let r = out.coordinates[2];
        assert!((r - q[2]).abs() < 1e-9);
        if let Some(p) = prev {
            assert!((r - p).abs() < 5.0 * DEG);
        }
        prev = Some(r);
        max = max.max(r);
    }
    assert!(max > 300.0 * DEG, "{}", max / DEG);
    // After a reset the solver starts afresh: the first frame's value is within half a turn.
    solver.reset();
    let out = solver.solve(
        &model,
        &cal.segments(&rec.frames.last().unwrap().0).unwrap(),
        Mode::ClosedForm,
    );
    assert!(out.coordinates[2].abs() <= core::f64::consts::PI);
}

#[test]
fn heading_free_pelvis_removes_the_walking_direction() {
    let model = model();
    let (tilt, list): (f64, f64) = (0.1, -0.05);
    for heading in [0.0, 1.0, 2.5, -2.0, 7.0] {
        // Walking towards `heading` (plus a 0.05 rad sway), in the world-frame sequence tilt and
        // list depend on the heading; relative to the heading they are the same every time.
        let world = Quat::from_axis_angle(Vec3::unit_y(), heading)
            * Quat::from_axis_angle(Vec3::unit_z(), tilt)
            * Quat::from_axis_angle(Vec3::unit_x(), list)
            * Quat::from_axis_angle(Vec3::unit_y(), 0.05);
        let [t, l, r] = math::three_axes(world, [Vec3::unit_z(), Vec3::unit_x(), Vec3::unit_y()]);
        let free = qgait_kernel::imu::heading_free_pelvis(&model, [t, l, r], heading);
        assert!(
            (free[0] - tilt).abs() < 1e-12 && (free[1] - list).abs() < 1e-12,
            "{free:?}"
        );
        assert!((free[2] - 0.05).abs() < 1e-12, "{free:?}");
        if heading == 2.5 {
            // (Facing nearly backwards, the world-frame tilt and list are far from the truth.)
            assert!((t - tilt).abs() > 0.1 && (l - list).abs() > 0.05, "{t} {l}");
        }
    }
}

#[test]
fn a_leg_back_from_a_sensor_gap_is_exact_at_once() {
    // The right leg's three sensors drop out for half a second (the leg moves on meanwhile,
    // its coordinates held); on the first frame back, the least squares is exact again at once
    // (three Gauss-Newton iterations from the values held since before the gap).
    let m = mountings(7);
    let rec = recording(1.0, &m, &m, Disturbance::default());
    let model = model();
    let cal = Calibration::new(&model, &rec.calibration, &Settings::opensense_tutorial()).unwrap();
    let mut solver = Solver::new();
    for (k, (readings, q, _)) in rec.frames.iter().enumerate().take(71) {
        let mut readings = *readings;
        if (20..70).contains(&k) {
            for s in [Segment::FemurR, Segment::TibiaR, Segment::CalcnR] {
                readings.set(s, None);
            }
        }
        let out = solver.solve(
            &model,
            &cal.segments(&readings).unwrap(),
            Mode::LeastSquares,
        );
        if k == 70 {
            assert_eq!(out.held, 0);
            for (c, (got, want)) in out.coordinates.iter().zip(q).enumerate().take(9).skip(3) {
                let e = (got - want).abs() / DEG;
                assert!(e < 0.01, "coordinate {c}: {e} deg");
            }
        }
    }
}

/// A rotation matrix back to its quaternion (up to sign), for every branch of Shepperd's
/// method (rotations near 0 and near half a turn about each axis included).
#[test]
fn rotation_matrix_round_trips_to_its_quaternion() {
    let mut rng = SmallRng::seed_from_u64(7);
    let mut worst = 0.0f64;
    for i in 0..20_000 {
        let axis = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let axis = match i % 4 {
            1 => Vec3::unit_x(),
            2 => Vec3::unit_y(),
            3 => Vec3::unit_z(),
            _ => axis * (1.0 / axis.norm()),
        };
        let angle = match i % 3 {
            0 => rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
            1 => std::f64::consts::PI - rng.random_range(0.0..1e-3),
            _ => rng.random_range(-1e-3..1e-3),
        };
        let q = math::positive(Quat::from_axis_angle(axis, angle));
        let back = math::from_rotation_matrix(q.to_rotation_matrix());
        let same = (back.w - q.w)
            .abs()
            .max((back.x - q.x).abs())
            .max((back.y - q.y).abs())
            .max((back.z - q.z).abs());
        let opposite = (back.w + q.w)
            .abs()
            .max((back.x + q.x).abs())
            .max((back.y + q.y).abs())
            .max((back.z + q.z).abs());
        worst = worst.max(same.min(opposite));
    }
    assert!(worst < 1e-14, "{worst}");
}
