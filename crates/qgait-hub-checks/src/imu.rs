//! Scenario checks of the hub's IMU orientation input (`qgait_hub::orientation`).
//!
//! **Generator** (the kernel's IMU tests' one, `crates/qgait-kernel/tests/imu_common`, cut down
//! to what runs without `std`): known gait2392 coordinates (the kernel's synthetic walk,
//! [`truth`]) go through the kernel's
//! `f64` forward kinematics; each sensor's segment orientation is its chain body's frame (the
//! torso's: the pelvis frame, lumbar angles zero); each sensor sits on its segment at a fixed
//! mounting of 20 to 30 degrees ([`MOUNTINGS`]; the torso's with its z axis forward, as the
//! heading correction from the torso's z assumes) and reports `S^-1 B M` in its world frame,
//! `S` OpenSense's default sensor-to-OpenSim rotation; the calibration pose is the default
//! pose facing [`HEADING0`]. The readings travel as Q14, as a node sends them.

use qgait_kernel::imu::{math, Calibration, Mode, Orientations, Segment, Solver};
use qgait_kernel::models::fixtures::{imu_walk, IMU_WALK_HEADING0};
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat, Vec3};
use qgait_proto::device_model::{kernel_settings, q14_quat};
use qgait_proto::{
    segment_bit, Config, FrameFlags, HeadingAxisId, ImuConfig, ImuHeading, InputMode, JointId,
    Message, MissingPolicy, ModelId, SampleHeader, SegmentId, SegmentOrientation, WireByte,
};

use qgait_hub::{Kinematics, ManualClock};

use crate::{
    config, drain, fail, new_hub, poses, send, send_sample, send_subject, subject_config,
    CheckFailure, CheckResult, CheckSerial,
};

/// The names of the checks of this module in [`ALL`](crate::ALL) (their failures' lines are
/// in this file).
pub const CHECKS: [&str; 5] = [
    "random_orientation_messages_never_stop_the_pipeline",
    "orientation_input_calibrates_then_sends_kernel_poses",
    "orientation_failures_are_counted",
    "calibration_is_kept_across_model_and_input_switches",
    "incomplete_orientation_samples_follow_the_missing_policy",
];

/// The subject's heading at calibration (radians about the vertical).
pub const HEADING0: f64 = IMU_WALK_HEADING0;

const DEG: f64 = core::f64::consts::PI / 180.0;

/// Sensor mountings (sensor frame in segment frame) as (axis, degrees), by segment index; the
/// torso's is its z axis turned forward (90 degrees about y) then rolled.
pub const MOUNTINGS: [([f64; 3], f64); 8] = [
    ([0.0, 0.0, 1.0], 25.0),
    ([1.0, 0.0, 0.0], -30.0),
    ([0.0, 1.0, 0.0], 20.0),
    ([0.6, 0.0, 0.8], 28.0),
    ([0.0, 0.8, 0.6], -22.0),
    ([1.0, 0.0, 0.0], 27.0),
    ([0.0, 0.6, -0.8], -25.0),
    ([0.0, 1.0, 0.0], 90.0),
];

/// The true coordinates of sample `k` (17 chain coordinates, 20 samples a second): the
/// kernel's synthetic walk ([`imu_walk`]).
pub fn truth(k: u32) -> [f64; 17] {
    imu_walk(f64::from(k) * 0.05).0
}

/// The sensors' Q14 readings for coordinates `q` (see the module docs).
pub fn readings(model: &Gait2392<f64>, q: &[f64; 17]) -> [[i16; 4]; 8] {
    let frames = model.chain().frames(q);
    let body = [0, 1, 2, 4, 6, 7, 9, 0];
    let s_inv = math::space_fixed_xyz([-90.0 * DEG, 0.0, 0.0]).conj();
    core::array::from_fn(|i| {
        let (axis, deg) = MOUNTINGS[i];
        let [x, y, z] = axis;
        let mut m = Quat::from_axis_angle(Vec3::new(x, y, z), deg * DEG);
        if i == Segment::Torso as usize {
            m = Quat::from_axis_angle(Vec3::unit_x(), 12.0 * DEG) * m;
        }
        let r = s_inv * frames[body[i]].rotation * m;
        SegmentOrientation::q14_of([r.w, r.x, r.y, r.z])
    })
}

/// The calibration pose's readings: the default pose facing [`HEADING0`].
pub fn calibration_readings(model: &Gait2392<f64>) -> [[i16; 4]; 8] {
    let mut q = [0.0; 17];
    q[2] = HEADING0;
    readings(model, &q)
}

/// The generator's model.
pub fn model_f64() -> Option<Gait2392<f64>> {
    Gait2392::new(&Gait2392Geometry::generic()).ok()
}

/// OpenSense's tutorial settings in `mode` (heading from the torso's z), for all eight
/// segments but those cleared in `without`.
pub fn imu_config(mode: InputMode, calibrate: bool, without: u8) -> ImuConfig {
    ImuConfig {
        segments: ImuConfig::ALL_SEGMENTS & !without,
        ..ImuConfig::opensense_tutorial(mode, calibrate)
    }
}

fn orientation(seq: u32, segment: SegmentId, q14: [i16; 4]) -> SegmentOrientation {
    SegmentOrientation {
        header: SampleHeader::new(segment.wire_byte(), segment, seq, crate::sample_time(seq)),
        q14,
        quality: 0,
    }
}

/// Queues the orientations of sample `seq` (the segments of `segments`, a bit each).
pub fn send_orientations(
    serial: &mut CheckSerial,
    seq: u32,
    q14: &[[i16; 4]; 8],
    segments: u8,
) -> bool {
    SegmentId::ALL
        .into_iter()
        .filter(|&s| segments & segment_bit(s) != 0)
        .all(|s| {
            send(
                serial,
                &Message::SegmentOrientation(orientation(seq, s, q14[s as usize])),
            )
        })
}

/// The `Config` of the generic gait2392 with `policy` and a window of 4.
pub fn gait2392_config(policy: MissingPolicy) -> Message {
    config(ModelId::Gait2392, policy, 4, false)
}

/// The kernel's own `f32` path on the same Q14 readings: calibration, solver, then the pose
/// frame `kinematics` makes of its angles. The hub must send exactly these.
struct Expected {
    calibration: Calibration<f32>,
    solver: Solver<f32>,
    model: Gait2392<f32>,
}

impl Expected {
    fn new(calibration: &[[i16; 4]; 8], config: &ImuConfig) -> Result<Self, CheckFailure> {
        let model = Gait2392::from_geometry(Kinematics::generic_gait2392())
            .map_err(|_| fail("the generic gait2392 in f32", line!()))?;
        let calibration = Calibration::new(
            &model,
            &kernel_readings(calibration),
            &kernel_settings::<f32>(config),
        )
        .map_err(|_| fail("Calibration::new on the calibration pose", line!()))?;
        Ok(Self {
            calibration,
            solver: Solver::new(),
            model,
        })
    }

    fn angles(&mut self, q14: &[[i16; 4]; 8], mode: Mode) -> Result<[f32; 17], CheckFailure> {
        let segments = self
            .calibration
            .segments(&kernel_readings(q14))
            .map_err(|_| fail("Calibration::segments", line!()))?;
        Ok(self.solver.solve(&self.model, &segments, mode).coordinates)
    }
}

fn kernel_readings(q14: &[[i16; 4]; 8]) -> Orientations<f32> {
    let mut o = Orientations::EMPTY;
    for s in Segment::ALL {
        o.set(s, Some(q14_quat(q14[s as usize])));
    }
    o
}

/// Samples before the calibration are dropped and counted; the flagged sample calibrates
/// (no frame); every later sample gives the frame of the kernel's own `f32` path on the same
/// readings (bit for bit), with angles within 0.05 degrees of the truth, in both modes.
pub fn orientation_input_calibrates_then_sends_kernel_poses() -> CheckResult {
    let Some(truth_model) = model_f64() else {
        return Err(fail("the generic gait2392 in f64", line!()));
    };
    let Ok(generic) = Kinematics::gait2392(Kinematics::generic_gait2392()) else {
        return Err(fail("Kinematics::gait2392(generic)", line!()));
    };
    for mode in [
        InputMode::OrientationsLeastSquares,
        InputMode::OrientationsClosedForm,
    ] {
        let clock = ManualClock::new(0);
        let mut hub = new_hub(&clock)?;
        let serial = hub.serial_mut();
        let all = ImuConfig::ALL_SEGMENTS;
        ensure!(send(serial, &gait2392_config(MissingPolicy::Drop)));
        ensure!(send(
            serial,
            &Message::ImuConfig(imu_config(mode, false, 0))
        ));
        ensure!(send_orientations(
            serial,
            0,
            &readings(&truth_model, &truth(0)),
            all
        ));
        ensure!(send(serial, &Message::ImuConfig(imu_config(mode, true, 0))));
        let pose = calibration_readings(&truth_model);
        ensure!(send_orientations(serial, 1, &pose, all));
        for k in 2..8 {
            ensure!(send_orientations(
                serial,
                k,
                &readings(&truth_model, &truth(k)),
                all
            ));
        }
        drain(&mut hub);
        let status = hub.status();
        ensure!(status.uncalibrated_samples == 1 && status.calibrations == 1);
        ensure!(status.samples_completed == 6 && status.config_rejected == 0);
        ensure!(hub.imu().calibration().is_some() && !hub.imu().calibration_pending());
        let mut expected = Expected::new(&pose, &imu_config(mode, true, 0))?;
        let Some(kernel_mode) = qgait_proto::device_model::kernel_mode(mode) else {
            return Err(fail("kernel_mode", line!()));
        };
        let (mut seq, mut same, mut close) = (2, true, true);
        let n = poses(&mut hub, |p| {
            let Ok(angles) = expected.angles(&readings(&truth_model, &truth(seq)), kernel_mode)
            else {
                same = false;
                return;
            };
            same &= *p == generic.pose_frame(seq, crate::sample_time(seq), &angles, 0);
            let want = truth(seq);
            for (i, (got, want)) in p.angles.iter().zip(want).enumerate() {
                let mtp = i == JointId::MtpAngleR.index() as usize
                    || i == JointId::MtpAngleL.index() as usize;
                close &= mtp || libm::fabs(f64::from(*got) - want) < 0.05 * DEG;
            }
            seq += 1;
        })?;
        ensure!(n == 6 && same && close);
    }
    Ok(())
}

/// Each new failure is counted: a quaternion far from unit length, an orientation mode with
/// PHAK in force or without the pelvis, a switch to PHAK in an orientation mode, a
/// calibration pose without the heading's base IMU; late and duplicate orientation packets as
/// joint packets are; joint-angle packets in an orientation mode give nothing.
pub fn orientation_failures_are_counted() -> CheckResult {
    let Some(truth_model) = model_f64() else {
        return Err(fail("the generic gait2392 in f64", line!()));
    };
    let ls = InputMode::OrientationsLeastSquares;
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let serial = hub.serial_mut();
    // PHAK in force: refused.
    ensure!(send(serial, &Message::ImuConfig(imu_config(ls, true, 0))));
    ensure!(send(serial, &gait2392_config(MissingPolicy::Drop)));
    // No pelvis: refused.
    let no_pelvis = segment_bit(SegmentId::Pelvis);
    ensure!(send(
        serial,
        &Message::ImuConfig(imu_config(ls, true, no_pelvis))
    ));
    // No torso, heading from the torso: the calibration pose is refused.
    let no_torso = segment_bit(SegmentId::Torso);
    ensure!(send(
        serial,
        &Message::ImuConfig(imu_config(ls, true, no_torso))
    ));
    let pose = calibration_readings(&truth_model);
    ensure!(send_orientations(serial, 1, &pose, !no_torso));
    // Far from unit length, and zero.
    ensure!(send(
        serial,
        &Message::SegmentOrientation(orientation(2, SegmentId::Pelvis, [20_000, 0, 0, 0]))
    ));
    ensure!(send(
        serial,
        &Message::SegmentOrientation(orientation(2, SegmentId::FemurR, [0; 4]))
    ));
    // A switch to PHAK: refused while the orientation input is in force.
    ensure!(send(
        serial,
        &Message::Config(Config {
            model: ModelId::Phak,
            anthropometry: None,
            missing_policy: MissingPolicy::Drop,
            reorder_window: 4,
            request_status: false,
        })
    ));
    // Joint angles: accepted, not used.
    ensure!(send_sample(serial, ModelId::Gait2392, 3));
    drain(&mut hub);
    let status = hub.status();
    ensure!(status.config_rejected == 3);
    ensure!(status.calibration_rejected == 1 && status.calibrations == 0);
    ensure!(status.orientation_not_unit == 2);
    ensure!(status.packets_accepted == 7 + 17);
    ensure!(hub.config().model == ModelId::Gait2392);
    ensure!(hub.imu().calibration_pending());
    // Now with the torso: it calibrates; late and duplicate packets are counted.
    let serial = hub.serial_mut();
    ensure!(send(serial, &Message::ImuConfig(imu_config(ls, true, 0))));
    ensure!(send_orientations(
        serial,
        10,
        &pose,
        ImuConfig::ALL_SEGMENTS
    ));
    ensure!(send(
        serial,
        &Message::SegmentOrientation(orientation(10, SegmentId::Pelvis, pose[0]))
    ));
    for k in 11..16 {
        let q = readings(&truth_model, &truth(k));
        ensure!(send_orientations(serial, k, &q, ImuConfig::ALL_SEGMENTS));
    }
    ensure!(send(
        serial,
        &Message::SegmentOrientation(orientation(5, SegmentId::Pelvis, pose[0]))
    ));
    drain(&mut hub);
    let status = hub.status();
    ensure!(status.calibrations == 1 && status.samples_completed == 5);
    ensure!(status.duplicate_packets == 1 && status.late_packets == 1);
    ensure!(poses(&mut hub, |_| {})? == 5);
    Ok(())
}

/// The calibration is kept through a switch to a subject's gait2392 (frames then of the
/// subject's model) and through the joint-angle input and back; a restart of the calibration
/// is only ever asked for.
pub fn calibration_is_kept_across_model_and_input_switches() -> CheckResult {
    let Some(truth_model) = model_f64() else {
        return Err(fail("the generic gait2392 in f64", line!()));
    };
    let ls = InputMode::OrientationsLeastSquares;
    let all = ImuConfig::ALL_SEGMENTS;
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let serial = hub.serial_mut();
    ensure!(send(serial, &gait2392_config(MissingPolicy::Drop)));
    ensure!(send(serial, &Message::ImuConfig(imu_config(ls, true, 0))));
    let pose = calibration_readings(&truth_model);
    ensure!(send_orientations(serial, 1, &pose, all));
    ensure!(send_orientations(
        serial,
        2,
        &readings(&truth_model, &truth(2)),
        all
    ));
    drain(&mut hub);
    let subject = crate::scaled_subject();
    let serial = hub.serial_mut();
    ensure!(send_subject(serial, &subject, 4, 0));
    ensure!(send(serial, &subject_config(4, false)));
    ensure!(send_orientations(
        serial,
        3,
        &readings(&truth_model, &truth(3)),
        all
    ));
    drain(&mut hub);
    // Joint angles and back, with the same settings: no calibration asked for.
    let serial = hub.serial_mut();
    ensure!(send(
        serial,
        &Message::ImuConfig(imu_config(InputMode::JointAngles, false, 0))
    ));
    ensure!(send_sample(serial, ModelId::Gait2392, 4));
    ensure!(send(serial, &Message::ImuConfig(imu_config(ls, false, 0))));
    ensure!(send_orientations(
        serial,
        5,
        &readings(&truth_model, &truth(5)),
        all
    ));
    drain(&mut hub);
    let status = hub.status();
    ensure!(status.calibrations == 1 && status.uncalibrated_samples == 0);
    ensure!(status.samples_completed == 4 && status.config_rejected == 0);
    let Ok(subject_kinematics) = Kinematics::gait2392(&subject.cast()) else {
        return Err(fail("Kinematics::gait2392(subject)", line!()));
    };
    let mut seqs = [0u32; 4];
    let mut i = 0;
    let mut subject_frames = true;
    let n = poses(&mut hub, |p| {
        if let Some(s) = seqs.get_mut(i) {
            *s = p.seq;
        }
        if p.seq >= 3 {
            let angles = p.joint_angles::<f32>();
            subject_frames &= *p
                == subject_kinematics.pose_frame(
                    p.seq,
                    crate::sample_time(p.seq),
                    &angles,
                    p.flags,
                );
        }
        i += 1;
    })?;
    ensure!(n == 4 && seqs == [2, 3, 4, 5] && subject_frames);
    Ok(())
}

/// Random orientation packets (any quaternion, segment and nearby sequence number) and random
/// IMU configurations (non-finite settings, any mode, segments and heading) between clean
/// samples never stop the hub: afterwards a calibration and samples still give their frames.
pub fn random_orientation_messages_never_stop_the_pipeline() -> CheckResult {
    let Some(truth_model) = model_f64() else {
        return Err(fail("the generic gait2392 in f64", line!()));
    };
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &gait2392_config(MissingPolicy::HoldLast)
    ));
    let mut state = 0x9E37_79B9_u32;
    let mut next = || {
        // xorshift32
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let mut rejected_nan = false;
    for round in 0..40u32 {
        for _ in 0..12 {
            let r = next();
            let segment = SegmentId::ALL[(r % 8) as usize];
            let q14 = [next() as i16, next() as i16, next() as i16, next() as i16];
            let seq = round * 3 + (r >> 8) % 5;
            let p = orientation(seq, segment, q14);
            ensure!(send(hub.serial_mut(), &Message::SegmentOrientation(p)));
        }
        let r = next();
        let nan = r % 4 == 0;
        let config = ImuConfig {
            mode: [
                InputMode::JointAngles,
                InputMode::OrientationsClosedForm,
                InputMode::OrientationsLeastSquares,
            ][(r % 3) as usize],
            segments: (next() as u8) | 1,
            calibrate: r & 16 != 0,
            sensor_to_opensim: if nan {
                [f32::NAN, f32::INFINITY, 0.0]
            } else {
                [f32::from_bits(next() & 0x407f_ffff), 0.0, 1.0]
            },
            heading: (r & 32 != 0).then(|| ImuHeading {
                base: SegmentId::ALL[((r >> 6) % 8) as usize],
                axis: HeadingAxisId::ALL[((r >> 9) % 6) as usize],
            }),
            request_status: false,
        };
        let before = hub.status().config_rejected;
        ensure!(send(hub.serial_mut(), &Message::ImuConfig(config)));
        drain(&mut hub);
        rejected_nan |= nan && hub.status().config_rejected == before + 1;
    }
    ensure!(rejected_nan);
    let ls = InputMode::OrientationsLeastSquares;
    let all = ImuConfig::ALL_SEGMENTS;
    let serial = hub.serial_mut();
    ensure!(send(serial, &Message::ImuConfig(imu_config(ls, true, 0))));
    let pose = calibration_readings(&truth_model);
    ensure!(send_orientations(serial, 5000, &pose, all));
    for k in 5001..5004 {
        ensure!(send_orientations(
            serial,
            k,
            &readings(&truth_model, &truth(k)),
            all
        ));
    }
    drain(&mut hub);
    let mut last = [0u32; 3];
    let mut i = 0;
    poses(&mut hub, |p| {
        last.rotate_left(1);
        last[2] = p.seq;
        i += 1;
    })?;
    ensure!(last == [5001, 5002, 5003]);
    Ok(())
}

/// An incomplete orientation sample is dropped (policy drop) or completed with the segment's
/// last quaternion and flagged missing and held (policy hold last), as joint samples are.
pub fn incomplete_orientation_samples_follow_the_missing_policy() -> CheckResult {
    let Some(truth_model) = model_f64() else {
        return Err(fail("the generic gait2392 in f64", line!()));
    };
    let cf = InputMode::OrientationsClosedForm;
    let all = ImuConfig::ALL_SEGMENTS;
    let no_calcn_l = !segment_bit(SegmentId::CalcnL);
    for (policy, frames, flagged) in [(MissingPolicy::Drop, 2, 0), (MissingPolicy::HoldLast, 3, 1)]
    {
        let clock = ManualClock::new(0);
        let mut hub = new_hub(&clock)?;
        let serial = hub.serial_mut();
        ensure!(send(serial, &gait2392_config(policy)));
        ensure!(send(serial, &Message::ImuConfig(imu_config(cf, true, 0))));
        ensure!(send_orientations(
            serial,
            1,
            &calibration_readings(&truth_model),
            all
        ));
        ensure!(send_orientations(
            serial,
            2,
            &readings(&truth_model, &truth(2)),
            all
        ));
        ensure!(send_orientations(
            serial,
            3,
            &readings(&truth_model, &truth(3)),
            no_calcn_l
        ));
        for k in 4..9 {
            let q = readings(&truth_model, &truth(k));
            ensure!(send_orientations(
                serial,
                k,
                &q,
                if k == 4 { all } else { 1 }
            ));
        }
        drain(&mut hub);
        let mut held = 0;
        let n = poses(&mut hub, |p| {
            if p.flags == FrameFlags::MISSING | FrameFlags::HELD {
                held += 1;
            }
        })?;
        ensure!(n == frames && held == flagged);
    }
    Ok(())
}
