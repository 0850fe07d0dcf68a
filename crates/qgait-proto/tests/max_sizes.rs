//! The MAX_* constants are true maxima: reached exactly by worst-case messages, and the
//! decoder accepts a frame of exactly MAX_FRAME_LEN bytes but not one byte more.
mod common;

use qgait_proto::{
    cobs_max_encoded_len, encode_frame, encode_message, Config, DecodeError, FrameDecoder,
    FusionMode, HeadingAxisId, ImuConfig, ImuHeading, InputMode, JointAngle, JointId,
    KneeDirection, Leg, Message, MissingPolicy, ModelId, PoseFrame, RawImuConfig, RawImuSample,
    RawImuStatus, SampleHeader, SegmentId, SegmentOrientation, Status, SubjectConfig, SubjectKnee,
    SubjectLeg, CONFIG_MAX_LEN, CRC_LEN, IMU_CONFIG_MAX_LEN, JOINT_ANGLE_MAX_FRAME_LEN,
    JOINT_ANGLE_MAX_LEN, MAX_FRAME_LEN, MAX_KNEE_KNOTS, MAX_MESSAGE_LEN, POSE_FRAME_MAX_LEN,
    RAW_IMU_CONFIG_MAX_LEN, RAW_IMU_SAMPLE_MAX_LEN, RAW_IMU_STATUS_MAX_LEN,
    SEGMENT_ORIENTATION_MAX_LEN, STATUS_MAX_LEN, SUBJECT_CONFIG_MAX_LEN, SUBJECT_KNEE_MAX_LEN,
    SUBJECT_LEG_MAX_LEN,
};

/// Any float: an f32 is always 4 bytes.
const ANGLE: f32 = 1.234_567_9;

fn message_len(msg: &Message) -> usize {
    let mut buf = [0u8; 512];
    encode_message(msg, &mut buf).expect("encodes").len()
}

fn worst_joint_angle(seq: u32) -> JointAngle {
    JointAngle {
        version: 1,
        node: 0xFF,
        joint: JointId::MtpAngleL,
        seq,
        timestamp_us: u32::MAX,
        angle: ANGLE,
        quality: 0xFF,
    }
}

fn worst_pose_frame(seq: u32) -> PoseFrame {
    PoseFrame {
        seq,
        timestamp_us: u32::MAX,
        model: ModelId::Gait2392,
        angles: heapless::Vec::from_slice(&[ANGLE; JointId::COUNT]).expect("17 fit"),
        points: [[ANGLE; 3]; 8],
        distances: [ANGLE; 3],
        flags: 0xFF,
    }
}

#[test]
fn per_message_maxima_are_reached_exactly() {
    let all_max = Status {
        packets_accepted: u32::MAX,
        crc_errors: u32::MAX,
        framing_errors: u32::MAX,
        oversize_frames: u32::MAX,
        unknown_version: u32::MAX,
        unknown_joint: u32::MAX,
        out_of_range: u32::MAX,
        samples_completed: u32::MAX,
        samples_incomplete: u32::MAX,
        frames_sent: u32::MAX,
        uart_overruns: u32::MAX,
        uptime_ms: u32::MAX,
        late_packets: u32::MAX,
        duplicate_packets: u32::MAX,
        malformed: u32::MAX,
        config_rejected: u32::MAX,
        orientation_not_unit: u32::MAX,
        uncalibrated_samples: u32::MAX,
        calibrations: u32::MAX,
        calibration_rejected: u32::MAX,
    };
    let leg = SubjectLeg {
        upload: 0xFF,
        leg: Leg::Left,
        hip_in_pelvis: [ANGLE; 3],
        hip_axes: [[ANGLE; 3]; 3],
        ankle_in_tibia: [ANGLE; 3],
        ankle_axis: [ANGLE; 3],
        subtalar_in_talus: [ANGLE; 3],
        subtalar_axis: [ANGLE; 3],
        mtp_in_calcn: [ANGLE; 3],
        mtp_axis: [ANGLE; 3],
        toetip_in_toes: [ANGLE; 3],
    };
    let knee = SubjectKnee {
        upload: 0xFF,
        leg: Leg::Left,
        direction: KneeDirection::Ty,
        knots: heapless::Vec::from_slice(&[[ANGLE; 2]; MAX_KNEE_KNOTS]).expect("12 fit"),
    };
    let subject_config = SubjectConfig {
        upload: 0xFF,
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 0xFF,
        request_status: true,
    };
    let config = Config {
        model: ModelId::Gait2392,
        anthropometry: Some([[ANGLE; 4]; 2]),
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 0xFF,
        request_status: true,
    };
    assert_eq!(
        message_len(&worst_joint_angle(u32::MAX).into()),
        JOINT_ANGLE_MAX_LEN
    );
    assert_eq!(
        message_len(&worst_pose_frame(u32::MAX).into()),
        POSE_FRAME_MAX_LEN
    );
    assert_eq!(message_len(&all_max.into()), STATUS_MAX_LEN);
    assert_eq!(message_len(&config.into()), CONFIG_MAX_LEN);
    assert_eq!(message_len(&leg.into()), SUBJECT_LEG_MAX_LEN);
    assert_eq!(message_len(&knee.into()), SUBJECT_KNEE_MAX_LEN);
    assert_eq!(message_len(&subject_config.into()), SUBJECT_CONFIG_MAX_LEN);
    // A node sample's longest header.
    let header = SampleHeader {
        version: 0xFF,
        node: 0xFF,
        segment: SegmentId::Torso,
        seq: u32::MAX,
        timestamp_us: u32::MAX,
    };
    let orientation = SegmentOrientation {
        header,
        // Zigzag: -16384 and 16383 take 3 bytes as much as i16::MIN does.
        q14: [i16::MIN, -16384, 16383, i16::MAX],
        quality: 0xFF,
    };
    assert_eq!(
        message_len(&orientation.into()),
        SEGMENT_ORIENTATION_MAX_LEN
    );
    let imu_config = ImuConfig {
        mode: InputMode::OrientationsLeastSquares,
        segments: 0xFF,
        calibrate: true,
        sensor_to_opensim: [ANGLE; 3],
        heading: Some(ImuHeading {
            base: SegmentId::Torso,
            axis: HeadingAxisId::NegZ,
        }),
        request_status: true,
    };
    assert_eq!(message_len(&imu_config.into()), IMU_CONFIG_MAX_LEN);
    let raw_sample = RawImuSample {
        header,
        // Zigzag: every count of magnitude 8192 or more takes 3 bytes.
        gyro: [i16::MIN, i16::MAX, -8193],
        accel: [8192, -32767, 20000],
        mag: Some([i16::MIN, 8192, -8193]),
    };
    assert_eq!(message_len(&raw_sample.into()), RAW_IMU_SAMPLE_MAX_LEN);
    let raw_6d = RawImuSample {
        mag: None,
        ..raw_sample
    };
    assert_eq!(message_len(&raw_6d.into()), RAW_IMU_SAMPLE_MAX_LEN - 9);
    let raw_config = RawImuConfig {
        segments: 0xFF,
        fusion: FusionMode::NineD,
        rate_hz: u16::MAX,
        output_every: 0xFF,
        gyro_per_count: ANGLE,
        accel_per_count: ANGLE,
        mag_per_count: ANGLE,
        request_status: true,
    };
    assert_eq!(message_len(&raw_config.into()), RAW_IMU_CONFIG_MAX_LEN);
    let raw_status = RawImuStatus {
        samples_accepted: u32::MAX,
        saturated: u32::MAX,
        rate_gaps: u32::MAX,
        samples_lost: u32::MAX,
        timing_errors: u32::MAX,
        stale_samples: u32::MAX,
        resyncs: u32::MAX,
        missing_magnetometer: u32::MAX,
        not_configured: u32::MAX,
    };
    assert_eq!(message_len(&raw_status.into()), RAW_IMU_STATUS_MAX_LEN);
    // The smallest: 6D, every number under 64 in magnitude, 7-bit seq and timestamp.
    let raw_small = RawImuSample {
        header: SampleHeader {
            seq: 1,
            timestamp_us: 100,
            ..raw_6d.header
        },
        gyro: [0, -1, 63],
        accel: [-64, 0, 1],
        ..raw_6d
    };
    assert_eq!(message_len(&raw_small.into()), 13);
    assert_eq!(
        MAX_MESSAGE_LEN,
        [
            JOINT_ANGLE_MAX_LEN,
            POSE_FRAME_MAX_LEN,
            STATUS_MAX_LEN,
            CONFIG_MAX_LEN,
            SUBJECT_LEG_MAX_LEN,
            SUBJECT_KNEE_MAX_LEN,
            SUBJECT_CONFIG_MAX_LEN,
            SEGMENT_ORIENTATION_MAX_LEN,
            IMU_CONFIG_MAX_LEN,
            qgait_proto::CHAIN_TABLE_MAX_LEN,
            qgait_proto::CHAIN_TABLE_CONFIG_MAX_LEN,
            RAW_IMU_SAMPLE_MAX_LEN,
            RAW_IMU_CONFIG_MAX_LEN,
            RAW_IMU_STATUS_MAX_LEN,
        ]
        .into_iter()
        .max()
        .unwrap()
    );
    // Smaller values take fewer bytes: the maximum is not a constant size.
    assert!(message_len(&worst_joint_angle(0).into()) < JOINT_ANGLE_MAX_LEN);
}

#[test]
fn max_frame_len_is_reached_and_decoded() {
    // Below 254 bytes COBS always adds exactly one code byte, zeros or not, so the largest
    // message gives the largest frame.
    const { assert!(MAX_MESSAGE_LEN + CRC_LEN < 254) };
    let frame = common::frame(&worst_pose_frame(u32::MAX).into());
    assert_eq!(frame.len(), MAX_FRAME_LEN);
    assert_eq!(
        MAX_FRAME_LEN,
        cobs_max_encoded_len(MAX_MESSAGE_LEN + CRC_LEN) + 1
    );
    let mut decoder = FrameDecoder::new();
    let got = common::decode_all(&mut decoder, &frame);
    assert_eq!(got.len(), 1);
    assert!(got[0].is_ok(), "{:?}", got[0]);

    let ja = common::frame(&worst_joint_angle(u32::MAX).into());
    assert_eq!(ja.len(), JOINT_ANGLE_MAX_FRAME_LEN);
}

#[test]
fn one_byte_more_than_max_frame_len_is_oversize() {
    let mut decoder = FrameDecoder::new();
    // MAX_FRAME_LEN - 1 non-zero bytes fill the buffer without an error...
    for _ in 0..MAX_FRAME_LEN - 1 {
        assert_eq!(decoder.push(0x42), None);
    }
    // ...and one more is reported once as Oversize.
    assert_eq!(decoder.push(0x42), Some(Err(DecodeError::Oversize)));
    for _ in 0..1000 {
        assert_eq!(decoder.push(0x42), None);
    }
    assert_eq!(
        decoder.push(0),
        None,
        "the delimiter ends the discarded frame silently"
    );
    let msg: Message = common::status().into();
    assert_eq!(
        common::decode_all(&mut decoder, &common::frame(&msg)),
        vec![Ok(msg)]
    );
}

#[test]
fn encode_frame_fits_a_max_frame_len_buffer() {
    let msg: Message = worst_pose_frame(u32::MAX).into();
    let mut exact = [0u8; MAX_FRAME_LEN];
    assert!(encode_frame(&msg, &mut exact).is_ok());
}

/// `ChainTable` is 4 to 135 bytes and `ChainTableConfig` 8 to 14 (protocol.md 4.9): the
/// smallest fields, then the largest.
#[test]
fn chain_table_messages_are_their_documented_sizes() {
    use qgait_proto::{
        ChainTable, ChainTableConfig, CHAIN_TABLE_CONFIG_MAX_LEN, CHAIN_TABLE_MAX_LEN,
        MAX_CHAIN_TABLE_BYTES,
    };
    let mut part = ChainTable {
        upload: 0,
        at: 0,
        bytes: heapless::Vec::new(),
    };
    assert_eq!(message_len(&Message::ChainTable(part.clone())), 4);
    part.upload = 0xFF;
    part.at = u16::MAX;
    part.bytes.resize(MAX_CHAIN_TABLE_BYTES, 0xFF).unwrap();
    assert_eq!(message_len(&Message::ChainTable(part)), 135);
    assert_eq!(CHAIN_TABLE_MAX_LEN, 135);
    let mut config = ChainTableConfig {
        upload: 0,
        len: 0,
        crc: 0,
        knee_flexes_positive: false,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 1,
        request_status: false,
    };
    assert_eq!(message_len(&Message::ChainTableConfig(config.clone())), 8);
    config.len = u16::MAX;
    config.crc = u32::MAX;
    assert_eq!(message_len(&Message::ChainTableConfig(config)), 14);
    assert_eq!(CHAIN_TABLE_CONFIG_MAX_LEN, 14);
}
