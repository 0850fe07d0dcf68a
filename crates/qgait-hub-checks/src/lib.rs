#![doc = include_str!("../README.md")]
#![no_std]
#![warn(missing_docs)]
#![forbid(unsafe_code)]

use qgait_kernel::models::fixtures::walker_chain;
use qgait_kernel::models::ranges::KneeFlexion;
use qgait_kernel::Gait2392Geometry;
use qgait_proto::device_model::{pose_points, CHAIN_IMAGE_LEN};
use qgait_proto::PoseModels;
use qgait_proto::{
    backward_difference, encode_frame, encode_raw_frame, Config, FrameDecoder, FrameFlags,
    JointAngle, JointId, Message, MissingPolicy, ModelId, PoseFrame, Status, SubjectConfig,
    VelocityConfig, MAX_FRAME_LEN, PROTOCOL_VERSION,
};

use qgait_hub::{
    parts_of, ChainUpload, Hub, Kinematics, ManualClock, MemorySerial, MAX_BYTES_PER_POLL,
    READ_CHUNK,
};

/// A failed check: what did not hold, and where.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CheckFailure {
    /// The condition that did not hold, as written in the source.
    pub what: &'static str,
    /// Line in this crate's `src/lib.rs`.
    pub line: u32,
}

/// Result of one check.
pub type CheckResult = Result<(), CheckFailure>;

/// The failure of `what` at `line` (`line!()` where it is found).
pub(crate) fn fail(what: &'static str, line: u32) -> CheckFailure {
    CheckFailure { what, line }
}

macro_rules! ensure {
    ($cond:expr) => {
        if !$cond {
            return Err(fail(stringify!($cond), line!()));
        }
    };
}

pub mod imu;

/// A xorshift32 generator: the pseudo-random streams of the hub's host tests.
pub struct XorShift(pub u32);

impl XorShift {
    /// The next number (never 0 from a seed that is not 0).
    pub fn next_u32(&mut self) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 17;
        self.0 ^= self.0 << 5;
        self.0
    }
}

/// A check: its name and the function that runs it.
pub type NamedCheck = (&'static str, fn() -> CheckResult);

/// Every check with its name.
pub const ALL: &[NamedCheck] = &[
    (
        "clean_stream_gives_one_pose_per_sample",
        clean_stream_gives_one_pose_per_sample,
    ),
    ("pose_matches_the_kernel", pose_matches_the_kernel),
    (
        "packets_reordered_within_the_window_still_complete",
        packets_reordered_within_the_window_still_complete,
    ),
    (
        "late_and_duplicate_packets_are_counted_and_dropped",
        late_and_duplicate_packets_are_counted_and_dropped,
    ),
    (
        "incomplete_sample_is_dropped_and_counted",
        incomplete_sample_is_dropped_and_counted,
    ),
    (
        "hold_last_policy_sends_flagged_frames",
        hold_last_policy_sends_flagged_frames,
    ),
    (
        "held_angle_out_of_range_is_flagged",
        held_angle_out_of_range_is_flagged,
    ),
    (
        "corrupt_frames_are_counted_and_the_next_packet_is_processed",
        corrupt_frames_are_counted_and_the_next_packet_is_processed,
    ),
    (
        "unknown_joint_and_version_are_counted",
        unknown_joint_and_version_are_counted,
    ),
    (
        "angles_out_of_range_are_flagged_and_unusable_ones_dropped",
        angles_out_of_range_are_flagged_and_unusable_ones_dropped,
    ),
    ("uart_overrun_is_counted", uart_overrun_is_counted),
    (
        "config_switches_model_and_answers_status_request",
        config_switches_model_and_answers_status_request,
    ),
    (
        "unusable_config_is_refused_and_counted",
        unusable_config_is_refused_and_counted,
    ),
    (
        "status_request_keeps_open_samples",
        status_request_keeps_open_samples,
    ),
    ("status_is_sent_periodically", status_is_sent_periodically),
    (
        "gait2392_config_gives_frames_of_the_generic_model",
        gait2392_config_gives_frames_of_the_generic_model,
    ),
    (
        "subject_model_switches_only_when_complete",
        subject_model_switches_only_when_complete,
    ),
    (
        "invalid_subject_model_is_rejected_and_counted",
        invalid_subject_model_is_rejected_and_counted,
    ),
    (
        "parts_of_another_upload_discard_the_held_ones",
        parts_of_another_upload_discard_the_held_ones,
    ),
    (
        "chain_model_switches_only_when_complete",
        chain_model_switches_only_when_complete,
    ),
    (
        "a_chains_knee_flexing_with_positive_angles_is_checked_in_its_range",
        a_chains_knee_flexing_with_positive_angles_is_checked_in_its_range,
    ),
    (
        "random_bytes_never_stop_the_pipeline",
        random_bytes_never_stop_the_pipeline,
    ),
    (
        "each_poll_reads_at_most_max_bytes_per_poll",
        each_poll_reads_at_most_max_bytes_per_poll,
    ),
    (
        "frames_split_across_reads_and_polls_still_decode",
        frames_split_across_reads_and_polls_still_decode,
    ),
    (
        "orientation_input_calibrates_then_sends_kernel_poses",
        imu::orientation_input_calibrates_then_sends_kernel_poses,
    ),
    (
        "orientation_failures_are_counted",
        imu::orientation_failures_are_counted,
    ),
    (
        "calibration_is_kept_across_model_and_input_switches",
        imu::calibration_is_kept_across_model_and_input_switches,
    ),
    (
        "incomplete_orientation_samples_follow_the_missing_policy",
        imu::incomplete_orientation_samples_follow_the_missing_policy,
    ),
    (
        "random_orientation_messages_never_stop_the_pipeline",
        imu::random_orientation_messages_never_stop_the_pipeline,
    ),
    (
        "velocities_follow_consecutive_poses",
        velocities_follow_consecutive_poses,
    ),
];

/// Serial port of the checks: room for a few hundred packets each way.
pub type CheckSerial = MemorySerial<4096, 8192>;

/// The hub under test.
pub type CheckHub<'c> = Hub<CheckSerial, &'c ManualClock>;

/// Status period of the hubs the checks build (milliseconds).
pub const STATUS_PERIOD_MS: u32 = 1000;

/// A PHAK-like gait angle of `joint` at sample `seq` (radians, inside the joint's range).
pub fn gait_angle(joint: JointId, seq: u32) -> f32 {
    let phase = (seq % 100) as f32 / 100.0;
    // A triangle wave in [-1, 1]: cheap, deterministic, no trigonometry needed.
    let tri = if phase < 0.5 {
        4.0 * phase - 1.0
    } else {
        3.0 - 4.0 * phase
    };
    let (mid, amp) = match joint {
        JointId::PelvisRotation => (0.0, 0.1),
        JointId::PelvisList => (0.0, 0.05),
        JointId::HipFlexionR => (0.2, 0.4),
        JointId::HipFlexionL => (0.2, -0.4),
        JointId::KneeAngleR => (-0.6, 0.5),
        JointId::KneeAngleL => (-0.6, -0.5),
        JointId::AnkleAngleR => (0.0, 0.2),
        JointId::AnkleAngleL => (0.0, -0.2),
        _ => (0.0, 0.1),
    };
    mid + amp * tri
}

/// The sensor time of sample `seq` in the checks' packets: 100 Hz from 0 (µs, wrapping).
pub fn sample_time(seq: u32) -> u32 {
    seq.wrapping_mul(10_000)
}

/// The `JointAngle` packet of `joint` in sample `seq`.
pub fn packet(seq: u32, joint: JointId) -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: joint.index(),
        joint,
        seq,
        timestamp_us: sample_time(seq),
        angle: gait_angle(joint, seq),
        quality: 0,
    }
}

/// Queues the encoded frame of `message` on `serial`; false if it did not fit.
pub fn send(serial: &mut CheckSerial, message: &Message) -> bool {
    let mut buf = [0u8; MAX_FRAME_LEN];
    match encode_frame(message, &mut buf) {
        Ok(frame) => serial.receive(frame) == frame.len(),
        Err(_) => false,
    }
}

/// Queues every packet of sample `seq` for `model`, in the model's joint order.
pub fn send_sample(serial: &mut CheckSerial, model: ModelId, seq: u32) -> bool {
    send_sample_edited(serial, model, seq, |_| true)
}

/// Queues the packets of sample `seq` for `model`, in the model's joint order, each as `edit`
/// leaves it: `edit` may change the packet, or return false to leave it out.
pub fn send_sample_edited(
    serial: &mut CheckSerial,
    model: ModelId,
    seq: u32,
    mut edit: impl FnMut(&mut JointAngle) -> bool,
) -> bool {
    model.required_joints().iter().all(|&j| {
        let mut p = packet(seq, j);
        !edit(&mut p) || send(serial, &Message::JointAngle(p))
    })
}

/// An edit for [`send_sample_edited`]: `joint`'s angle set to `angle`.
fn set_angle(joint: JointId, angle: f32) -> impl FnMut(&mut JointAngle) -> bool {
    move |p| {
        if p.joint == joint {
            p.angle = angle;
        }
        true
    }
}

/// Queues PHAK samples 0 to 9, sample 3 without its left ankle.
fn send_samples_3_without_left_ankle(serial: &mut CheckSerial) -> bool {
    (0..10).all(|seq| {
        send_sample_edited(serial, ModelId::Phak, seq, |p| {
            !(seq == 3 && p.joint == JointId::AnkleAngleL)
        })
    })
}

/// Polls until the serial port has nothing left to read.
pub fn drain(hub: &mut CheckHub<'_>) {
    while hub.serial_mut().pending() > 0 {
        hub.poll();
    }
}

/// Decodes what the hub wrote, calling `on` for each message; returns the number of frames
/// that did not decode.
pub fn each_output(hub: &mut CheckHub<'_>, mut on: impl FnMut(&Message)) -> u32 {
    let mut decoder = FrameDecoder::new();
    let mut bad = 0;
    for &b in hub.serial_mut().transmitted() {
        match decoder.push(b) {
            Some(Ok(m)) => on(&m),
            Some(Err(_)) => bad += 1,
            None => {}
        }
    }
    bad
}

/// The pose frames the hub wrote, as (count, sequence numbers in order via `on`).
fn poses(hub: &mut CheckHub<'_>, mut on: impl FnMut(&PoseFrame)) -> Result<u32, CheckFailure> {
    let mut n = 0;
    let bad = each_output(hub, |m| {
        if let Message::PoseFrame(p) = m {
            n += 1;
            on(p);
        }
    });
    ensure!(bad == 0);
    Ok(n)
}

/// The last status frame the hub wrote.
fn last_status(hub: &mut CheckHub<'_>) -> Option<Status> {
    let mut last = None;
    each_output(hub, |m| {
        if let Message::Status(s) = m {
            last = Some(*s);
        }
    });
    last
}

fn new_hub(clock: &ManualClock) -> Result<CheckHub<'_>, CheckFailure> {
    Hub::new(CheckSerial::new(), clock, STATUS_PERIOD_MS)
        .map_err(|_| fail("Hub::new refused the default model", line!()))
}

fn config(model: ModelId, policy: MissingPolicy, window: u8, request_status: bool) -> Message {
    Message::Config(Config {
        model,
        anthropometry: None,
        missing_policy: policy,
        reorder_window: window,
        request_status,
    })
}

/// 20 PHAK samples sent in order give 20 pose frames with the right sequence numbers.
pub fn clean_stream_gives_one_pose_per_sample() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    for seq in 0..20 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    drain(&mut hub);
    let mut expected_seq = 0;
    let mut in_order = true;
    let n = poses(&mut hub, |p| {
        in_order &= p.seq == expected_seq
            && p.model == ModelId::Phak
            && p.flags == 0
            && p.angles.len() == 8;
        expected_seq += 1;
    })?;
    ensure!(n == 20);
    ensure!(in_order);
    let s = hub.status();
    ensure!(s.packets_accepted == 160);
    ensure!(s.samples_completed == 20);
    ensure!(s.frames_sent == 20);
    ensure!(s.samples_incomplete == 0 && s.late_packets == 0 && s.crc_errors == 0);
    Ok(())
}

/// The points and distances of a frame are the kernel's f32 FK of the sample's angles, and
/// the angles are echoed in the model's joint order.
pub fn pose_matches_the_kernel() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 37));
    drain(&mut hub);
    let mut frame = None;
    poses(&mut hub, |p| frame = Some(p.clone()))?;
    let frame = frame.ok_or(fail("no pose frame", line!()))?;
    let mut angles = [0.0; JointId::COUNT];
    for j in JointId::ALL {
        angles[j.index() as usize] = gait_angle(j, 37);
    }
    let kinematics =
        Kinematics::new(ModelId::Phak, None).map_err(|_| fail("Kinematics::new", line!()))?;
    let expected = kinematics.pose_frame(37, sample_time(37), &angles, 0);
    ensure!(frame == expected);
    for (a, j) in frame.angles.iter().zip(ModelId::Phak.required_joints()) {
        ensure!(*a == gait_angle(*j, 37));
    }
    // Legs of a standing-ish pose: hips at pelvis height, toes below the knees.
    ensure!(frame.points[0][1].abs() < 0.1 && frame.points[3][1] < frame.points[1][1]);
    ensure!(frame.distances.iter().all(|d| d.is_finite() && *d > 0.0));
    Ok(())
}

/// The angles of sample `seq` as the checks send them (indexed by [`JointId::index`]).
fn sample_angles(seq: u32) -> [f32; JointId::COUNT] {
    core::array::from_fn(|i| JointId::ALL.get(i).map_or(0.0, |&j| gait_angle(j, seq)))
}

/// With velocities on (10 ms), a `PoseVelocities` follows each pose frame whose sample follows
/// the last one posed: the kernel's PHAK velocities at the sample's angles with their backward
/// difference. None for the first sample, after a gap (sample 5 never sent), or after a
/// configuration that takes effect; a period of 0 is refused and counted.
pub fn velocities_follow_consecutive_poses() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let on = |period_us| {
        Message::VelocityConfig(VelocityConfig {
            enabled: true,
            period_us,
            request_status: false,
        })
    };
    ensure!(send(hub.serial_mut(), &on(10_000)));
    for seq in (0..5).chain(6..9) {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    drain(&mut hub);
    // A window change takes effect: 9 starts the differences again.
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Phak, MissingPolicy::Drop, 3, false)
    ));
    for seq in 9..11 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    ensure!(send(hub.serial_mut(), &on(0)));
    drain(&mut hub);
    let phak = qgait_kernel::Phak::<f32>::new(&qgait_kernel::Anthropometry::gait2392())
        .map_err(|_| fail("Phak::new", line!()))?;
    let (mut poses, mut with, mut last_pose, mut right) = (0u32, 0u32, None, true);
    let bad = each_output(&mut hub, |m| match m {
        Message::PoseFrame(p) => {
            poses += 1;
            last_pose = Some(p.seq);
        }
        Message::PoseVelocities(v) => {
            with += 1;
            let (now, before) = (sample_angles(v.seq), sample_angles(v.seq.wrapping_sub(1)));
            let rates = backward_difference(&before, &now, 10_000.0 * 1e-6);
            let expected =
                qgait_proto::device_model::stick_velocities(&phak, ModelId::Phak, &now, &rates);
            right &= last_pose == Some(v.seq)
                && [1, 2, 3, 4, 7, 8, 10].contains(&v.seq)
                && v.dt_us == 10_000
                && expected
                    .iter()
                    .zip(&v.velocities)
                    .all(|(e, g)| e.to_array() == *g);
        }
        _ => {}
    });
    ensure!(bad == 0);
    ensure!(poses == 10 && with == 7);
    ensure!(right);
    let s = hub.status();
    ensure!(s.config_rejected == 1 && s.frames_sent == 17);
    ensure!(hub.velocity_config().period_us == 10_000);
    Ok(())
}

/// Packets of samples 0..3 interleaved and shuffled (window 4) all complete.
pub fn packets_reordered_within_the_window_still_complete() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let joints = ModelId::Phak.required_joints();
    // Round-robin over samples, joints in reverse order.
    for j in joints.iter().rev() {
        for seq in [2u32, 0, 3, 1] {
            ensure!(send(
                hub.serial_mut(),
                &Message::JointAngle(packet(seq, *j))
            ));
        }
    }
    drain(&mut hub);
    let mut seen = 0u32;
    let n = poses(&mut hub, |p| seen |= 1 << p.seq)?;
    ensure!(n == 4 && seen == 0b1111);
    let s = hub.status();
    ensure!(s.samples_completed == 4 && s.samples_incomplete == 0 && s.late_packets == 0);
    Ok(())
}

/// A packet older than the window and a repeated packet are counted and change nothing.
pub fn late_and_duplicate_packets_are_counted_and_dropped() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &Message::JointAngle(packet(0, JointId::HipFlexionR))
    ));
    ensure!(send(
        hub.serial_mut(),
        &Message::JointAngle(packet(0, JointId::HipFlexionR))
    ));
    for seq in 1..=5 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    // Sample 0 left the window (4) when sample 4 arrived.
    ensure!(send(
        hub.serial_mut(),
        &Message::JointAngle(packet(0, JointId::KneeAngleR))
    ));
    // Sample 5 is complete: another packet of it is a duplicate.
    ensure!(send(
        hub.serial_mut(),
        &Message::JointAngle(packet(5, JointId::KneeAngleR))
    ));
    drain(&mut hub);
    let s = hub.status();
    ensure!(s.duplicate_packets == 2);
    ensure!(s.late_packets == 1);
    ensure!(s.samples_completed == 5);
    ensure!(s.samples_incomplete == 1);
    ensure!(poses(&mut hub, |_| {})? == 5);
    Ok(())
}

/// With the default drop policy a sample missing a joint gives no frame and is counted.
pub fn incomplete_sample_is_dropped_and_counted() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send_samples_3_without_left_ankle(hub.serial_mut()));
    drain(&mut hub);
    let mut has_3 = false;
    let n = poses(&mut hub, |p| has_3 |= p.seq == 3)?;
    ensure!(n == 9 && !has_3);
    let s = hub.status();
    ensure!(s.samples_incomplete == 1 && s.samples_completed == 9);
    Ok(())
}

/// With hold-last the same stream gives 10 frames, sample 3 flagged and holding sample 2's angle.
pub fn hold_last_policy_sends_flagged_frames() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Phak, MissingPolicy::HoldLast, 2, false)
    ));
    ensure!(send_samples_3_without_left_ankle(hub.serial_mut()));
    drain(&mut hub);
    let mut held = None;
    let mut others_clean = true;
    let n = poses(&mut hub, |p| {
        if p.seq == 3 {
            held = Some(p.clone());
        } else {
            others_clean &= p.flags == 0;
        }
    })?;
    ensure!(n == 10 && others_clean);
    let held = held.ok_or(fail("no frame for sample 3", line!()))?;
    ensure!(held.flags == FrameFlags::MISSING | FrameFlags::HELD);
    // ankle_angle_l is the last PHAK joint.
    ensure!(held.angles[7] == gait_angle(JointId::AnkleAngleL, 2));
    ensure!(hub.status().samples_incomplete == 0);
    Ok(())
}

/// Under hold-last, a sample holding an out-of-range angle from an earlier sample is flagged
/// out of range though its own packets were all in range; one holding an in-range angle is not.
pub fn held_angle_out_of_range_is_flagged() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Phak, MissingPolicy::HoldLast, 2, false)
    ));
    // Sample 3's right knee hyperextended; samples 4 and 6 lack the right knee (4 holds
    // sample 3's, 6 holds sample 5's, in range).
    for seq in 0..10 {
        ensure!(send_sample_edited(
            hub.serial_mut(),
            ModelId::Phak,
            seq,
            |p| {
                if p.joint == JointId::KneeAngleR {
                    match seq {
                        3 => p.angle = 1.5,
                        4 | 6 => return false,
                        _ => {}
                    }
                }
                true
            }
        ));
    }
    drain(&mut hub);
    let mut flags = [0xFFu8; 10];
    let mut knee_4 = 0.0;
    let n = poses(&mut hub, |p| {
        if let Some(f) = flags.get_mut(p.seq as usize) {
            *f = p.flags;
        }
        if p.seq == 4 {
            // knee_angle_r is PHAK's fourth joint.
            knee_4 = p.angles[3];
        }
    })?;
    ensure!(n == 10);
    ensure!(flags[3] == FrameFlags::OUT_OF_RANGE);
    ensure!(flags[4] == FrameFlags::MISSING | FrameFlags::HELD | FrameFlags::OUT_OF_RANGE);
    ensure!(knee_4 == 1.5);
    ensure!(flags[6] == FrameFlags::MISSING | FrameFlags::HELD);
    ensure!(flags
        .iter()
        .enumerate()
        .all(|(seq, &f)| matches!(seq, 3 | 4 | 6) || f == 0));
    let s = hub.status();
    ensure!(s.out_of_range == 1 && s.samples_incomplete == 0 && s.samples_completed == 10);
    Ok(())
}

/// Garbage, a frame with a bad CRC, a truncated frame and an oversize run are counted, and
/// the sample after them is processed.
pub fn corrupt_frames_are_counted_and_the_next_packet_is_processed() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let mut buf = [0u8; MAX_FRAME_LEN];
    let frame = encode_frame(
        &Message::JointAngle(packet(0, JointId::HipFlexionR)),
        &mut buf,
    )
    .map_err(|_| fail("encode", line!()))?;
    let len = frame.len();
    // Bad CRC: flip a bit of the body (keeping it non-zero).
    let mut bad_crc = [0u8; MAX_FRAME_LEN];
    bad_crc[..len].copy_from_slice(&buf[..len]);
    bad_crc[3] ^= if bad_crc[3] == 0x01 { 0x02 } else { 0x01 };
    ensure!(hub.serial_mut().receive(&bad_crc[..len]) == len);
    // Truncated: the first half of a frame, then a delimiter.
    ensure!(hub.serial_mut().receive(&buf[..len / 2]) == len / 2);
    ensure!(hub.serial_mut().receive(&[0]) == 1);
    // Oversize: more than MAX_FRAME_LEN non-zero bytes, then a delimiter.
    for _ in 0..MAX_FRAME_LEN + 10 {
        ensure!(hub.serial_mut().receive(&[0x55]) == 1);
    }
    ensure!(hub.serial_mut().receive(&[0]) == 1);
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 1));
    drain(&mut hub);
    let s = hub.status();
    ensure!(s.crc_errors == 1);
    ensure!(s.framing_errors + s.crc_errors + s.malformed >= 2);
    ensure!(s.oversize_frames == 1);
    ensure!(s.samples_completed == 1);
    ensure!(poses(&mut hub, |_| {})? == 1);
    Ok(())
}

/// Raw payloads with an unknown joint byte and an unknown version are counted per kind.
pub fn unknown_joint_and_version_are_counted() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let mut buf = [0u8; MAX_FRAME_LEN];
    // postcard JointAngle: tag 0, version, node, joint, seq (varint), timestamp (varint), f32 LE, quality.
    let unknown_joint = [0u8, PROTOCOL_VERSION, 1, 99, 5, 0, 0, 0, 0, 0, 0];
    let unknown_version = [0u8, PROTOCOL_VERSION + 7, 1, 3, 5, 0, 0, 0, 0, 0, 0];
    for payload in [&unknown_joint[..], &unknown_version[..]] {
        let frame =
            encode_raw_frame(payload, &mut buf).map_err(|_| fail("encode_raw_frame", line!()))?;
        let n = frame.len();
        ensure!(hub.serial_mut().receive(&buf[..n]) == n);
    }
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 6));
    drain(&mut hub);
    let s = hub.status();
    ensure!(s.unknown_joint == 1);
    ensure!(s.unknown_version == 1);
    ensure!(s.samples_completed == 1);
    Ok(())
}

/// An implausible but finite angle is used and flagged; a NaN angle, or one beyond
/// [`JointAngle::MAX_ANGLE`](qgait_proto::JointAngle::MAX_ANGLE), is dropped (the sample then
/// lacks that joint).
pub fn angles_out_of_range_are_flagged_and_unusable_ones_dropped() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let serial = hub.serial_mut();
    // The knee hyperextended by 86 degrees.
    ensure!(send_sample_edited(
        serial,
        ModelId::Phak,
        0,
        set_angle(JointId::KneeAngleR, 1.5)
    ));
    ensure!(send_sample_edited(
        serial,
        ModelId::Phak,
        1,
        set_angle(JointId::HipFlexionL, f32::NAN)
    ));
    // A finite angle too large to mean anything (10⁶ rad) is not used either.
    ensure!(send_sample_edited(
        serial,
        ModelId::Phak,
        2,
        set_angle(JointId::AnkleAngleR, 1.0e6)
    ));
    for seq in 3..7 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    drain(&mut hub);
    let mut flagged = 0;
    let mut first_flag = 0;
    let n = poses(&mut hub, |p| {
        if p.flags & FrameFlags::OUT_OF_RANGE != 0 {
            flagged += 1;
            first_flag = p.seq;
        }
    })?;
    ensure!(n == 5 && flagged == 1 && first_flag == 0);
    let s = hub.status();
    ensure!(s.out_of_range == 3);
    ensure!(s.samples_incomplete == 2);
    Ok(())
}

/// The chain's knee flexes with positive angles (Rajagopal's walker knee): with it in force, a
/// sample with both knees flexed 60° is in range and one with a knee hyperextended 30° is
/// flagged; after a `Config` back to PHAK the knees flexed 60° (positive) are flagged.
pub fn a_chains_knee_flexing_with_positive_angles_is_checked_in_its_range() -> CheckResult {
    const DEG: f32 = core::f32::consts::PI / 180.0;
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let chain = walker_chain();
    ensure!(KneeFlexion::of(|q| chain.forward(q)) == KneeFlexion::Positive);
    let upload =
        ChainUpload::of_chain(&chain, 6).map_err(|_| fail("ChainUpload::of_chain", line!()))?;
    ensure!(send_chain(hub.serial_mut(), &upload, 0));
    ensure!(send(
        hub.serial_mut(),
        &Message::ChainTableConfig(upload.config(MissingPolicy::Drop, 4, false))
    ));
    // `knees[seq]`: the knee angles of sample `seq` (the other angles as `packet` has them,
    // all in range).
    let knees = [60.0 * DEG, -30.0 * DEG, 60.0 * DEG];
    let sample = |hub: &mut CheckHub<'_>, model: ModelId, seq: u32| {
        send_sample_edited(hub.serial_mut(), model, seq, |p| {
            if matches!(p.joint, JointId::KneeAngleR | JointId::KneeAngleL) {
                p.angle = knees[seq as usize];
            }
            true
        })
    };
    ensure!(sample(&mut hub, ModelId::Chain, 0) && sample(&mut hub, ModelId::Chain, 1));
    drain(&mut hub);
    ensure!(hub.config().model == ModelId::Chain && hub.status().out_of_range == 2);
    ensure!(send(
        hub.serial_mut(),
        &self::config(ModelId::Phak, MissingPolicy::Drop, 4, false)
    ));
    ensure!(sample(&mut hub, ModelId::Phak, 2));
    drain(&mut hub);
    let mut flagged = [None; 3];
    poses(&mut hub, |p| {
        if let Some(f) = flagged.get_mut(p.seq as usize) {
            *f = Some(p.flags & FrameFlags::OUT_OF_RANGE != 0);
        }
    })?;
    ensure!(flagged == [Some(false), Some(true), Some(true)]);
    ensure!(hub.status().out_of_range == 4);
    Ok(())
}

/// A receive overrun reported by the port is counted; the bytes around it still decode.
pub fn uart_overrun_is_counted() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 0));
    ensure!(hub.serial_mut().receive_overrun());
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 1));
    drain(&mut hub);
    let s = hub.status();
    ensure!(s.uart_overruns == 1);
    ensure!(s.samples_completed == 2);
    Ok(())
}

/// A Config switches to HAK (6 joints, 6 angles per frame) and its status request is answered.
pub fn config_switches_model_and_answers_status_request() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Hak, MissingPolicy::Drop, 3, true)
    ));
    ensure!(send_sample(hub.serial_mut(), ModelId::Hak, 0));
    drain(&mut hub);
    ensure!(hub.config().model == ModelId::Hak && hub.config().reorder_window == 3);
    let mut hak_frames = 0;
    let n = poses(&mut hub, |p| {
        hak_frames += u32::from(p.model == ModelId::Hak && p.angles.len() == 6)
    })?;
    ensure!(n == 1 && hak_frames == 1);
    let status = last_status(&mut hub).ok_or(fail("no status", line!()))?;
    ensure!(status.frames_sent == 1 && status.packets_accepted == 0);
    // HAK legs hang from a level pelvis: the hips are on the z axis.
    let mut hips_on_axis = false;
    poses(&mut hub, |p| {
        hips_on_axis = p.points[0][0] == 0.0 && p.points[0][1] == 0.0 && p.points[0][2] > 0.0
    })?;
    ensure!(hips_on_axis);
    Ok(())
}

/// gait2392 with segment lengths and a negative femur are refused and counted; the hub keeps
/// computing PHAK.
pub fn unusable_config_is_refused_and_counted() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let with_lengths = Config {
        model: ModelId::Gait2392,
        anthropometry: Some([[0.0835, 0.4, 0.43, 0.21]; 2]),
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: false,
    };
    ensure!(send(hub.serial_mut(), &Message::Config(with_lengths)));
    let mut legs = [[0.0835, 0.4, 0.43, 0.21]; 2];
    legs[1][1] = -0.4;
    let bad = Config {
        model: ModelId::Phak,
        anthropometry: Some(legs),
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: false,
    };
    ensure!(send(hub.serial_mut(), &Message::Config(bad)));
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 0));
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 2 && hub.status().malformed == 0);
    ensure!(hub.config().model == ModelId::Phak);
    ensure!(poses(&mut hub, |_| {})? == 1);
    Ok(())
}

/// A status request repeating the configuration in force leaves the open samples alone.
pub fn status_request_keeps_open_samples() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let joints = ModelId::Phak.required_joints();
    for &j in &joints[..4] {
        ensure!(send(hub.serial_mut(), &Message::JointAngle(packet(0, j))));
    }
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Phak, MissingPolicy::Drop, 4, true)
    ));
    for &j in &joints[4..] {
        ensure!(send(hub.serial_mut(), &Message::JointAngle(packet(0, j))));
    }
    drain(&mut hub);
    ensure!(last_status(&mut hub).is_some());
    ensure!(poses(&mut hub, |_| {})? == 1);
    ensure!(hub.status().samples_incomplete == 0 && hub.status().malformed == 0);
    Ok(())
}

/// A status frame goes out once per period, with the uptime.
pub fn status_is_sent_periodically() -> CheckResult {
    let clock = ManualClock::new(5_000);
    let mut hub = new_hub(&clock)?;
    hub.poll();
    ensure!(last_status(&mut hub).is_none());
    clock.advance(STATUS_PERIOD_MS);
    hub.poll();
    hub.poll();
    clock.advance(STATUS_PERIOD_MS / 2);
    hub.poll();
    let mut count = 0;
    each_output(&mut hub, |m| {
        count += u32::from(matches!(m, Message::Status(_)))
    });
    ensure!(count == 1);
    ensure!(last_status(&mut hub).map(|s| s.uptime_ms) == Some(STATUS_PERIOD_MS));
    clock.advance(STATUS_PERIOD_MS / 2);
    hub.poll();
    ensure!(last_status(&mut hub).map(|s| s.frames_sent) == Some(2));
    Ok(())
}

/// Pseudo-random bytes (including zeros) between good samples: each good sample still
/// produces its pose, and the hub keeps answering.
pub fn random_bytes_never_stop_the_pipeline() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let mut state = 0x2545_F491_u32;
    for seq in 0..12 {
        for _ in 0..150 {
            // xorshift32
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            ensure!(hub.serial_mut().receive(&[state as u8]) == 1);
        }
        // End any half-frame the noise left open, then a good sample.
        ensure!(hub.serial_mut().receive(&[0]) == 1);
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
        drain(&mut hub);
    }
    let s = hub.status();
    ensure!(s.samples_completed == 12);
    let errors = s.crc_errors
        + s.framing_errors
        + s.oversize_frames
        + s.malformed
        + s.unknown_version
        + s.unknown_joint;
    ensure!(errors > 0);
    ensure!(poses(&mut hub, |_| {})? == 12);
    Ok(())
}

/// Each poll reads what is pending up to MAX_BYTES_PER_POLL bytes (a line error read is not a
/// byte), and stopping there mid-frame, mid-run or inside an oversize frame loses nothing.
pub fn each_poll_reads_at_most_max_bytes_per_poll() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    for seq in 0..3 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    ensure!(hub.serial_mut().receive_overrun());
    // An oversize frame: reported once, its bytes discarded up to the delimiter.
    for _ in 0..MAX_FRAME_LEN + 100 {
        ensure!(hub.serial_mut().receive(&[0x55]) == 1);
    }
    ensure!(hub.serial_mut().receive(&[0]) == 1);
    for seq in 3..6 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Phak, seq));
    }
    // Everything pending but the overrun is a byte.
    let total = hub.serial_mut().pending() - 1;
    ensure!(total > 3 * MAX_BYTES_PER_POLL);
    let mut read = 0;
    let mut polls = 0;
    loop {
        let summary = hub.poll();
        polls += 1;
        ensure!(summary.bytes as usize == (total - read).min(MAX_BYTES_PER_POLL));
        read += summary.bytes as usize;
        if summary.bytes == 0 {
            break;
        }
    }
    ensure!(read == total && hub.serial_mut().pending() == 0);
    ensure!(polls == total.div_ceil(MAX_BYTES_PER_POLL) + 1);
    let s = hub.status();
    ensure!(s.uart_overruns == 1 && s.oversize_frames == 1);
    ensure!(s.samples_completed == 6 && s.samples_incomplete == 0);
    ensure!(s.crc_errors + s.framing_errors + s.malformed == 0);
    ensure!(poses(&mut hub, |_| {})? == 6);
    Ok(())
}

/// The hub reads in blocks of READ_CHUNK bytes and a frame may end anywhere in one, or in the
/// next poll's: samples whose bytes arrive in pieces of every length from 1 to
/// 2 * READ_CHUNK + 1, a poll after each piece, all give their pose. An overrun queued after a piece that ends
/// mid-frame is reported after that piece's bytes (the poll reads them all and counts it), and
/// the frame it falls in still decodes (the port lost no byte).
pub fn frames_split_across_reads_and_polls_still_decode() -> CheckResult {
    const SAMPLES: u32 = 12;
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let mut stream: heapless::Vec<u8, 2048> = heapless::Vec::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    for seq in 0..SAMPLES {
        for &joint in ModelId::Phak.required_joints() {
            let frame = encode_frame(&Message::JointAngle(packet(seq, joint)), &mut buf);
            ensure!(frame.is_ok_and(|f| stream.extend_from_slice(f).is_ok()));
        }
    }
    let (mut at, mut len, mut overrun_at) = (0, 1, None);
    while at < stream.len() {
        let end = (at + len).min(stream.len());
        ensure!(hub.serial_mut().receive(&stream[at..end]) == end - at);
        // Once, after a piece that ends inside a frame's data.
        let mid_frame = end < stream.len() && stream[end - 1] != 0 && stream[end] != 0;
        if overrun_at.is_none() && mid_frame && end > stream.len() / 2 {
            ensure!(hub.serial_mut().receive_overrun());
            overrun_at = Some(end);
        }
        let summary = hub.poll();
        ensure!(summary.bytes as usize == end - at);
        ensure!(hub.serial_mut().pending() == 0);
        ensure!(hub.status().uart_overruns == overrun_at.is_some() as u32);
        at = end;
        len = len % (2 * READ_CHUNK + 1) + 1;
    }
    ensure!(overrun_at.is_some());
    let s = hub.status();
    ensure!(s.samples_completed == SAMPLES && s.samples_incomplete == 0);
    ensure!(s.crc_errors + s.framing_errors + s.malformed + s.oversize_frames == 0);
    let mut seq = 0;
    let mut in_order = true;
    ensure!(
        poses(&mut hub, |p| {
            in_order &= p.seq == seq;
            seq += 1;
        })? == SAMPLES
    );
    ensure!(in_order);
    Ok(())
}

/// A subject gait2392 model: the generic one scaled by 1.1 (right leg) and 0.95 (left leg),
/// positions and knee translations alike, as OpenSim's scaling does.
pub fn scaled_subject() -> Gait2392Geometry {
    let mut g = Gait2392Geometry::generic();
    for (leg, s) in [(&mut g.right, 1.1), (&mut g.left, 0.95)] {
        for p in [
            &mut leg.hip_in_pelvis,
            &mut leg.ankle_in_tibia,
            &mut leg.subtalar_in_talus,
            &mut leg.mtp_in_calcn,
            &mut leg.toetip_in_toes,
        ] {
            *p = p.map(|c| c * s);
        }
        for k in [&mut leg.knee_tx, &mut leg.knee_ty] {
            for y in k.y.iter_mut() {
                *y *= s;
            }
        }
    }
    g
}

/// Queues the 6 parts of `geometry` as upload `upload` (with `skip` parts left out at the end).
pub fn send_subject(
    serial: &mut CheckSerial,
    geometry: &Gait2392Geometry,
    upload: u8,
    skip: usize,
) -> bool {
    let Ok((legs, knees)) = parts_of(geometry, upload) else {
        return false;
    };
    let mut messages: heapless::Vec<Message, 6> = heapless::Vec::new();
    for leg in legs {
        let _ = messages.push(Message::SubjectLeg(leg));
    }
    for knee in knees {
        let _ = messages.push(Message::SubjectKnee(knee));
    }
    let n = messages.len().saturating_sub(skip);
    messages[..n].iter().all(|m| send(serial, m))
}

/// The message switching to the subject model of `upload`, drop policy, window 4.
pub fn subject_config(upload: u8, request_status: bool) -> Message {
    Message::SubjectConfig(SubjectConfig {
        upload,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status,
    })
}

/// The frame a hub computing `kinematics` sends for sample `seq` of [`gait_angle`]s.
fn expected_frame(kinematics: &Kinematics, seq: u32) -> PoseFrame {
    expected_frame_of(kinematics, seq, gait_angle)
}

/// The frame `kinematics` gives sample `seq` with the angles `angle(joint, seq)`.
fn expected_frame_of(
    kinematics: &Kinematics,
    seq: u32,
    angle: fn(JointId, u32) -> f32,
) -> PoseFrame {
    let mut angles = [0.0; JointId::COUNT];
    for j in JointId::ALL {
        angles[j.index() as usize] = angle(j, seq);
    }
    kinematics.pose_frame(seq, sample_time(seq), &angles, 0)
}

/// [`gait_angle`] in the signs of a chain whose knee flexes with positive angles (Rajagopal's):
/// the knees negated.
pub fn walker_angle(joint: JointId, seq: u32) -> f32 {
    match joint {
        JointId::KneeAngleR | JointId::KneeAngleL => -gait_angle(joint, seq),
        _ => gait_angle(joint, seq),
    }
}

/// A Config for gait2392 gives frames with all 17 angles, equal to the generic model's.
pub fn gait2392_config_gives_frames_of_the_generic_model() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Gait2392, MissingPolicy::Drop, 4, false)
    ));
    for seq in 0..3 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Gait2392, seq));
    }
    drain(&mut hub);
    let generic = Kinematics::gait2392(Kinematics::generic_gait2392())
        .map_err(|_| fail("Kinematics::gait2392(generic)", line!()))?;
    let mut all_equal = true;
    let mut seq = 0;
    let n = poses(&mut hub, |p| {
        all_equal &= p.angles.len() == 17 && *p == expected_frame(&generic, seq);
        seq += 1;
    })?;
    ensure!(n == 3 && all_equal);
    ensure!(hub.status().samples_completed == 3 && hub.status().config_rejected == 0);
    Ok(())
}

/// Five parts and a SubjectConfig: refused, PHAK stays. The sixth part and the SubjectConfig
/// again: the hub computes the subject's model, which is not the generic one.
pub fn subject_model_switches_only_when_complete() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let subject = scaled_subject();
    ensure!(send_subject(hub.serial_mut(), &subject, 9, 1));
    ensure!(send(hub.serial_mut(), &subject_config(9, true)));
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 0));
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 1);
    ensure!(hub.config().model == ModelId::Phak && hub.subject().is_none());
    ensure!(last_status(&mut hub).map(|s| s.config_rejected) == Some(1));
    ensure!(send_subject(hub.serial_mut(), &subject, 9, 0));
    ensure!(send(hub.serial_mut(), &subject_config(9, false)));
    for seq in 1..4 {
        ensure!(send_sample(hub.serial_mut(), ModelId::Gait2392, seq));
    }
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 1);
    ensure!(hub.config().model == ModelId::Gait2392 && hub.subject() == Some(9));
    // What the hub holds is the subject rounded to f32 on the wire.
    let held = hub
        .subject_parts()
        .geometry(9)
        .map_err(|_| fail("the hub's parts make no model", line!()))?;
    let (Ok(mine), Ok(generic)) = (
        Kinematics::gait2392(held),
        Kinematics::gait2392(Kinematics::generic_gait2392()),
    ) else {
        return Err(fail("Kinematics::gait2392", line!()));
    };
    let (mut subject_frames, mut far_from_generic) = (0, true);
    poses(&mut hub, |p| {
        if p.model == ModelId::Gait2392 {
            subject_frames += u32::from(*p == expected_frame(&mine, p.seq));
            let g = expected_frame(&generic, p.seq);
            // The 1.1-scaled right leg: its toe is centimetres away from the generic toe.
            far_from_generic &= (p.points[3][1] - g.points[3][1]).abs() > 0.02;
        }
    })?;
    ensure!(subject_frames == 3 && far_from_generic);
    // A Config switches back to a built-in model; the subject's SubjectConfig again to it.
    ensure!(send(
        hub.serial_mut(),
        &config(ModelId::Gait2392, MissingPolicy::Drop, 4, false)
    ));
    drain(&mut hub);
    ensure!(hub.subject().is_none());
    ensure!(send(hub.serial_mut(), &subject_config(9, false)));
    drain(&mut hub);
    ensure!(hub.subject() == Some(9) && hub.status().config_rejected == 1);
    // A part resent under the same upload with other numbers takes effect with the next
    // SubjectConfig, even one repeating the settings in force.
    let mut longer = subject;
    longer.right.ankle_in_tibia[1] -= 0.05;
    ensure!(send_subject(hub.serial_mut(), &longer, 9, 0));
    ensure!(send(hub.serial_mut(), &subject_config(9, false)));
    ensure!(send_sample(hub.serial_mut(), ModelId::Gait2392, 4));
    drain(&mut hub);
    let held = hub
        .subject_parts()
        .geometry(9)
        .map_err(|_| fail("the hub's parts make no model", line!()))?;
    let longer_kinematics =
        Kinematics::gait2392(held).map_err(|_| fail("Kinematics::gait2392", line!()))?;
    let mut sample_4 = None;
    poses(&mut hub, |p| {
        if p.seq == 4 {
            sample_4 = Some(p.clone());
        }
    })?;
    let sample_4 = sample_4.ok_or(fail("no frame for sample 4", line!()))?;
    ensure!(sample_4 == expected_frame(&longer_kinematics, 4));
    ensure!(sample_4 != expected_frame(&mine, 4));
    Ok(())
}

/// A subject model with a zero ankle axis (refused by the kernel), one with a hip 5 m from the
/// pelvis, and one with knots out of order are each counted; the model in force stays.
pub fn invalid_subject_model_is_rejected_and_counted() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let mut zero_axis = scaled_subject();
    zero_axis.left.ankle_axis = [0.0; 3];
    let mut far_hip = scaled_subject();
    far_hip.right.hip_in_pelvis[2] = 5.0;
    let mut unordered = scaled_subject();
    unordered.right.knee_ty.x.swap(1, 2);
    for (upload, geometry) in [(1, zero_axis), (2, far_hip), (3, unordered)] {
        ensure!(send_subject(hub.serial_mut(), &geometry, upload, 0));
        ensure!(send(hub.serial_mut(), &subject_config(upload, false)));
        drain(&mut hub);
    }
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 0));
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 3 && hub.status().malformed == 0);
    ensure!(hub.config().model == ModelId::Phak && hub.subject().is_none());
    ensure!(poses(&mut hub, |_| {})? == 1);
    Ok(())
}

/// A part of another upload discards the parts held: the first upload is then incomplete.
pub fn parts_of_another_upload_discard_the_held_ones() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let subject = scaled_subject();
    ensure!(send_subject(hub.serial_mut(), &subject, 1, 0));
    drain(&mut hub);
    ensure!(hub.subject_parts().upload() == Some(1) && hub.subject_parts().count() == 6);
    ensure!(send_subject(hub.serial_mut(), &subject, 2, 5));
    ensure!(send(hub.serial_mut(), &subject_config(1, false)));
    drain(&mut hub);
    ensure!(hub.subject_parts().upload() == Some(2) && hub.subject_parts().count() == 1);
    ensure!(hub.status().config_rejected == 1 && hub.subject().is_none());
    Ok(())
}

/// Queues the [`ChainTable`](qgait_proto::ChainTable) parts of `upload`, the last `skip` left
/// out.
pub fn send_chain(serial: &mut CheckSerial, upload: &ChainUpload, skip: usize) -> bool {
    let n = upload.parts().count().saturating_sub(skip);
    upload
        .parts()
        .take(n)
        .all(|part| send(serial, &Message::ChainTable(part)))
}

/// A chain's table without its last part and its `ChainTableConfig`: refused, and PHAK, stopped
/// by the first part, computes nothing (a complete sample closes without a pose). The last part
/// and the `ChainTableConfig` again: frames of model `chain` with all 17 angles, each the frame
/// of the kernel's table written from the same parts, within 10 µm of the chain in `f64`. A
/// `Config` naming the chain model is refused, a part reaching past the image counted as
/// malformed and not stopping the model.
pub fn chain_model_switches_only_when_complete() -> CheckResult {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock)?;
    let chain = walker_chain();
    let upload =
        ChainUpload::of_chain(&chain, 5).map_err(|_| fail("ChainUpload::of_chain", line!()))?;
    let config = upload.config(MissingPolicy::Drop, 4, true);
    ensure!(send_chain(hub.serial_mut(), &upload, 1));
    ensure!(send(
        hub.serial_mut(),
        &Message::ChainTableConfig(config.clone())
    ));
    ensure!(send_sample(hub.serial_mut(), ModelId::Phak, 0));
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 1 && hub.config().model == ModelId::Phak);
    ensure!(hub.status().samples_incomplete == 1 && hub.status().samples_completed == 0);
    ensure!(send_chain(hub.serial_mut(), &upload, 0));
    ensure!(send(
        hub.serial_mut(),
        &Message::ChainTableConfig(config.clone())
    ));
    // The gait's knees in the chain's signs (it flexes with positive angles): in range.
    for seq in 1..4 {
        ensure!(send_sample_edited(
            hub.serial_mut(),
            ModelId::Chain,
            seq,
            |p| {
                p.angle = walker_angle(p.joint, seq);
                true
            }
        ));
    }
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 1 && hub.config().model == ModelId::Chain);
    ensure!(hub.status().out_of_range == 0);
    let mut mine = Kinematics::EMPTY;
    for part in upload.parts() {
        ensure!(mine.write_chain(&part));
    }
    ensure!(mine.set_chain(&config).is_ok());
    let host = PoseModels::<f64>::defaults().with_chain(chain);
    let (mut frames, mut worst) = (0, 0.0f32);
    poses(&mut hub, |p| {
        if p.model == ModelId::Chain && *p == expected_frame_of(&mine, p.seq, walker_angle) {
            frames += 1;
            if let Some(pose) = host.frame_pose(p) {
                for (a, b) in p
                    .points
                    .iter()
                    .flatten()
                    .zip(pose_points(&pose).iter().flatten())
                {
                    worst = worst.max((a - b).abs());
                }
            }
        }
    })?;
    ensure!(frames == 3 && worst < 1e-5);
    // A Config cannot name the chain model; a part out of range is malformed.
    ensure!(send(
        hub.serial_mut(),
        &self::config(ModelId::Chain, MissingPolicy::Drop, 4, false)
    ));
    let mut far = upload
        .parts()
        .next()
        .ok_or(fail("ChainUpload::parts", line!()))?;
    far.at = (CHAIN_IMAGE_LEN + 1 - far.bytes.len()) as u16;
    ensure!(send(hub.serial_mut(), &Message::ChainTable(far)));
    ensure!(send_sample(hub.serial_mut(), ModelId::Chain, 4));
    drain(&mut hub);
    ensure!(hub.status().config_rejected == 2 && hub.status().malformed == 1);
    ensure!(hub.config().model == ModelId::Chain && hub.status().samples_completed == 4);
    Ok(())
}
