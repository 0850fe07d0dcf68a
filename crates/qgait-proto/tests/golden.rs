//! Golden vectors: the hex blocks of docs/protocol.md are checked byte for byte against the
//! encoder, and decoded back. The document is parsed, so it cannot drift from the code.
//!
//! A block is a fenced code block whose info string is `hex golden=NAME` (bytes as hex pairs)
//! or `text golden=constants` (`NAME = value` lines). To print every block as it should read:
//! `QGAIT_PRINT_GOLDEN=1 cargo test -p qgait-proto --test golden document_holds -- --nocapture`.
mod common;

use std::collections::BTreeMap;
use std::path::PathBuf;

use qgait_proto::{
    crc32c, encode_message, encode_raw_frame, Config, DecodeError, FrameDecoder, FrameFlags,
    HeadingAxisId, ImuConfig, ImuHeading, InputMode, JointAngle, JointId, Message, MissingPolicy,
    ModelId, PoseFrame, QualityFlags, SampleHeader, SegmentId, SegmentOrientation, Status, CRC_LEN,
    FRAME_CRC_CHECK, MAX_FRAME_LEN, MAX_MESSAGE_LEN, PROTOCOL_VERSION,
};

fn protocol_md() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/protocol.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `golden=NAME` block of the document: NAME -> the block's lines.
fn golden_blocks(doc: &str) -> BTreeMap<String, Vec<String>> {
    let mut blocks = BTreeMap::new();
    let mut lines = doc.lines();
    while let Some(line) = lines.next() {
        let Some(info) = line.trim().strip_prefix("```") else {
            continue;
        };
        let Some(name) = info
            .split_whitespace()
            .find_map(|w| w.strip_prefix("golden="))
        else {
            continue;
        };
        let body: Vec<String> = lines
            .by_ref()
            .take_while(|l| !l.trim().starts_with("```"))
            .map(str::to_owned)
            .collect();
        assert!(
            blocks.insert(name.to_owned(), body).is_none(),
            "golden block {name} twice"
        );
    }
    blocks
}

fn parse_hex(lines: &[String]) -> Vec<u8> {
    lines
        .iter()
        .flat_map(|l| l.split_whitespace())
        .map(|pair| {
            u8::from_str_radix(pair, 16).unwrap_or_else(|e| panic!("bad hex {pair:?}: {e}"))
        })
        .collect()
}

fn to_hex_block(name: &str, bytes: &[u8]) -> String {
    let mut s = format!("```hex golden={name}\n");
    for row in bytes.chunks(16) {
        let row: Vec<String> = row.iter().map(|b| format!("{b:02x}")).collect();
        s += &row.join(" ");
        s += "\n";
    }
    s + "```"
}

fn joint_angle() -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: 2,
        joint: JointId::KneeAngleR,
        seq: 300,
        timestamp_us: 1_234_567,
        angle: -0.5,
        quality: QualityFlags::MAG_DISTURBED,
    }
}

/// The golden messages, by name.
fn golden_messages() -> Vec<(&'static str, Message)> {
    vec![
        ("joint-angle", joint_angle().into()),
        (
            "pose-frame",
            PoseFrame {
                seq: 300,
                timestamp_us: 1_234_567,
                model: ModelId::Hak,
                angles: heapless::Vec::from_slice(&[0.5, -0.25, 0.125, -0.5, 0.0, 0.25])
                    .expect("6 fit"),
                points: [
                    [0.0, 0.0, 0.0625],
                    [0.25, -0.375, 0.0625],
                    [0.0, -0.75, 0.0625],
                    [0.1875, -0.75, 0.0625],
                    [0.0, 0.0, -0.0625],
                    [-0.125, -0.375, -0.0625],
                    [-0.25, -0.75, -0.0625],
                    [-0.0625, -0.75, -0.0625],
                ],
                distances: [0.4375, 0.3125, 0.25],
                flags: FrameFlags::HELD,
            }
            .into(),
        ),
        (
            "status",
            Status {
                packets_accepted: 1_000_000,
                crc_errors: 3,
                framing_errors: 1,
                oversize_frames: 0,
                unknown_version: 0,
                unknown_joint: 2,
                out_of_range: 5,
                samples_completed: 62_500,
                samples_incomplete: 7,
                frames_sent: 62_500,
                uart_overruns: 0,
                uptime_ms: 600_000,
                late_packets: 4,
                duplicate_packets: 0,
                malformed: 0,
                config_rejected: 1,
                orientation_not_unit: 0,
                uncalibrated_samples: 12,
                calibrations: 1,
                calibration_rejected: 0,
            }
            .into(),
        ),
        (
            "config",
            Config {
                model: ModelId::Phak,
                anthropometry: Some([[0.0625, 0.375, 0.4375, 0.25], [0.0625, 0.375, 0.4375, 0.25]]),
                missing_policy: MissingPolicy::HoldLast,
                reorder_window: 4,
                request_status: false,
            }
            .into(),
        ),
        (
            "config-status-request",
            Config {
                model: ModelId::Gait2392,
                anthropometry: None,
                missing_policy: MissingPolicy::Drop,
                reorder_window: 1,
                request_status: true,
            }
            .into(),
        ),
        ("subject-leg", common::subject_leg().into()),
        ("subject-knee", common::subject_knee().into()),
        ("subject-config", common::subject_config().into()),
        ("segment-orientation", segment_orientation().into()),
        (
            "imu-config",
            ImuConfig {
                mode: InputMode::OrientationsLeastSquares,
                segments: ImuConfig::ALL_SEGMENTS,
                calibrate: true,
                sensor_to_opensim: [-core::f32::consts::FRAC_PI_2, 0.0, 0.0],
                heading: Some(ImuHeading {
                    base: SegmentId::Torso,
                    axis: HeadingAxisId::Z,
                }),
                request_status: false,
            }
            .into(),
        ),
        ("chain-table", common::chain_table().into()),
        ("chain-table-config", common::chain_table_config().into()),
        ("raw-imu-sample", common::raw_imu_sample().into()),
        ("raw-imu-config", common::raw_imu_config().into()),
        ("raw-imu-status", common::raw_imu_status().into()),
        (
            "velocity-config",
            qgait_proto::VelocityConfig {
                enabled: true,
                period_us: 10_000,
                request_status: false,
            }
            .into(),
        ),
        ("pose-velocities", pose_velocities().into()),
    ]
}

/// The velocities of the golden pose frame's points (sample 300, 10 ms after sample 299):
/// the right leg swinging forward, the left one back, numbers exact in binary.
fn pose_velocities() -> qgait_proto::PoseVelocities {
    qgait_proto::PoseVelocities {
        seq: 300,
        dt_us: 10_000,
        velocities: [
            [0.0, 0.0, 0.0],
            [0.5, 0.125, 0.0],
            [1.25, 0.25, 0.0],
            [1.5, 0.5, 0.0],
            [0.0, 0.0, 0.0],
            [-0.25, 0.0625, 0.0],
            [-0.75, 0.125, 0.0],
            [-1.0, -0.5, 0.0],
        ],
    }
}

/// The tibia node's orientation of sample 300: a rotation of 60 degrees about z, in Q14
/// (cos 30 = 0.8660 -> 14189, sin 30 = 0.5 -> 8192).
fn segment_orientation() -> SegmentOrientation {
    SegmentOrientation {
        header: SampleHeader::new(3, SegmentId::TibiaR, 300, 1_234_567),
        q14: SegmentOrientation::q14_of([0.75f64.sqrt(), 0.0, 0.0, 0.5]),
        quality: 0,
    }
}

/// Golden frames that must fail, by name: their message bytes and the expected error.
fn golden_errors() -> Vec<(&'static str, Vec<u8>, DecodeError)> {
    let mut good = [0u8; MAX_MESSAGE_LEN];
    let ja = encode_message(&joint_angle().into(), &mut good)
        .expect("encodes")
        .to_vec();
    let mut wrong_version = ja.clone();
    wrong_version[1] = 1;
    let mut unknown_joint = ja.clone();
    unknown_joint[3] = 17;
    // Section 5: the fields' values are checked in wire order, so a `Config` with an unknown
    // model and a bad missing policy is an unknown model.
    let unknown_model = vec![0x03, 0x05, 0x00, 0x09, 0x04, 0x00];
    let mut unknown_segment = encode_message(&segment_orientation().into(), &mut good)
        .expect("encodes")
        .to_vec();
    unknown_segment[3] = 8;
    // An `ImuConfig` of mode 3 (not 0-2) whose heading's base is 9 (no segment): the mode is
    // field 1, the heading field 5, so `Malformed`.
    let mode_first = vec![
        0x08, 0x03, 0x01, 0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x01, 0x09, 0x00, 0x00,
    ];
    vec![
        (
            "error-imu-config-mode-first",
            mode_first,
            DecodeError::Malformed,
        ),
        (
            "error-unknown-model",
            unknown_model,
            DecodeError::UnknownModel(5),
        ),
        (
            "error-unknown-version",
            wrong_version,
            DecodeError::UnknownVersion(1),
        ),
        (
            "error-unknown-joint",
            unknown_joint,
            DecodeError::UnknownJoint(17),
        ),
        (
            "error-unknown-segment",
            unknown_segment,
            DecodeError::UnknownSegment(8),
        ),
    ]
}

fn frame_of_payload(payload: &[u8]) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    encode_raw_frame(payload, &mut buf).expect("fits").to_vec()
}

/// Every block the document must hold, as it must read.
fn expected_blocks() -> BTreeMap<String, Vec<u8>> {
    let mut blocks = BTreeMap::new();
    for (name, msg) in golden_messages() {
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let bytes = encode_message(&msg, &mut buf).expect("encodes").to_vec();
        blocks.insert(format!("{name}.frame"), common::frame(&msg));
        blocks.insert(format!("{name}.message"), bytes);
    }
    for (name, payload, _) in golden_errors() {
        blocks.insert(format!("{name}.frame"), frame_of_payload(&payload));
    }
    let bad_crc = {
        let mut f = common::frame(&joint_angle().into());
        let last_crc_byte = f.len() - 2;
        f[last_crc_byte] ^= 0x01;
        f
    };
    blocks.insert("error-crc.frame".to_owned(), bad_crc);
    blocks.insert(
        "chain-coupled.image".to_owned(),
        common::chain_coupled_image(),
    );
    blocks
}

/// The points of protocol.md 9.5's table for its angles, as the document lists them: every
/// point the hub computes, `f32` as Rust prints it.
fn chain_coupled_points(image: &[u8]) -> Vec<String> {
    let mut table = qgait_proto::device_model::DeviceChain::EMPTY;
    table.write_image(0, image);
    let mut q = [0.0f32; 17];
    q[JointId::HipFlexionR.index() as usize] = 0.5;
    q[JointId::KneeAngleR.index() as usize] = -0.6;
    table
        .forward(&q)
        .iter()
        .enumerate()
        .map(|(k, p)| format!("point {k}: {} {} {}", p.x, p.y, p.z))
        .collect()
}

fn constants() -> Vec<String> {
    vec![
        format!("PROTOCOL_VERSION = {PROTOCOL_VERSION}"),
        format!("MAX_MESSAGE_LEN = {MAX_MESSAGE_LEN}"),
        format!("CRC_LEN = {CRC_LEN}"),
        format!("MAX_FRAME_LEN = {MAX_FRAME_LEN}"),
        format!("JOINT_ANGLE_MAX_LEN = {}", qgait_proto::JOINT_ANGLE_MAX_LEN),
        format!(
            "JOINT_ANGLE_MAX_FRAME_LEN = {}",
            qgait_proto::JOINT_ANGLE_MAX_FRAME_LEN
        ),
        format!("POSE_FRAME_MAX_LEN = {}", qgait_proto::POSE_FRAME_MAX_LEN),
        format!("STATUS_MAX_LEN = {}", qgait_proto::STATUS_MAX_LEN),
        format!("CONFIG_MAX_LEN = {}", qgait_proto::CONFIG_MAX_LEN),
        format!("SUBJECT_LEG_MAX_LEN = {}", qgait_proto::SUBJECT_LEG_MAX_LEN),
        format!(
            "SUBJECT_KNEE_MAX_LEN = {}",
            qgait_proto::SUBJECT_KNEE_MAX_LEN
        ),
        format!(
            "SUBJECT_CONFIG_MAX_LEN = {}",
            qgait_proto::SUBJECT_CONFIG_MAX_LEN
        ),
        format!(
            "SEGMENT_ORIENTATION_MAX_LEN = {}",
            qgait_proto::SEGMENT_ORIENTATION_MAX_LEN
        ),
        format!("IMU_CONFIG_MAX_LEN = {}", qgait_proto::IMU_CONFIG_MAX_LEN),
        format!("CHAIN_TABLE_MAX_LEN = {}", qgait_proto::CHAIN_TABLE_MAX_LEN),
        format!(
            "CHAIN_TABLE_CONFIG_MAX_LEN = {}",
            qgait_proto::CHAIN_TABLE_CONFIG_MAX_LEN
        ),
        format!("MAX_KNEE_KNOTS = {}", qgait_proto::MAX_KNEE_KNOTS),
        format!("MAX_CHAIN_SPLINES = {}", qgait_proto::MAX_CHAIN_SPLINES),
        format!("MAX_CHAIN_DRIVES = {}", qgait_proto::MAX_CHAIN_DRIVES),
        format!("MAX_CHAIN_WORDS = {}", qgait_proto::MAX_CHAIN_WORDS),
        format!(
            "MAX_CHAIN_TABLE_BYTES = {}",
            qgait_proto::MAX_CHAIN_TABLE_BYTES
        ),
        format!(
            "CHAIN_IMAGE_LEN = {}",
            qgait_proto::device_model::CHAIN_IMAGE_LEN
        ),
        format!("CHAIN_TABLE_TAG = {}", qgait_proto::CHAIN_TABLE_TAG),
        format!(
            "CHAIN_TABLE_CONFIG_TAG = {}",
            qgait_proto::CHAIN_TABLE_CONFIG_TAG
        ),
        format!(
            "RAW_IMU_SAMPLE_MAX_LEN = {}",
            qgait_proto::RAW_IMU_SAMPLE_MAX_LEN
        ),
        format!(
            "RAW_IMU_CONFIG_MAX_LEN = {}",
            qgait_proto::RAW_IMU_CONFIG_MAX_LEN
        ),
        format!(
            "RAW_IMU_STATUS_MAX_LEN = {}",
            qgait_proto::RAW_IMU_STATUS_MAX_LEN
        ),
        format!("RAW_IMU_SAMPLE_TAG = {}", qgait_proto::RAW_IMU_SAMPLE_TAG),
        format!("RAW_IMU_CONFIG_TAG = {}", qgait_proto::RAW_IMU_CONFIG_TAG),
        format!("RAW_IMU_STATUS_TAG = {}", qgait_proto::RAW_IMU_STATUS_TAG),
        format!(
            "VELOCITY_CONFIG_MAX_LEN = {}",
            qgait_proto::VELOCITY_CONFIG_MAX_LEN
        ),
        format!(
            "POSE_VELOCITIES_MAX_LEN = {}",
            qgait_proto::POSE_VELOCITIES_MAX_LEN
        ),
        format!("VELOCITY_CONFIG_TAG = {}", qgait_proto::VELOCITY_CONFIG_TAG),
        format!("POSE_VELOCITIES_TAG = {}", qgait_proto::POSE_VELOCITIES_TAG),
        format!(
            "MAX_VELOCITY_PERIOD_US = {}",
            qgait_proto::MAX_VELOCITY_PERIOD_US
        ),
        format!("MAX_REORDER_WINDOW = {}", qgait_proto::MAX_REORDER_WINDOW),
        format!("FRAME_CRC_CHECK = 0x{FRAME_CRC_CHECK:08X}"),
    ]
}

/// Prints every block as it must read (when `QGAIT_PRINT_GOLDEN` is set), to update the doc.
fn print_blocks_on_request() {
    if std::env::var_os("QGAIT_PRINT_GOLDEN").is_none() {
        return;
    }
    for (name, bytes) in expected_blocks() {
        println!("{}\n", to_hex_block(&name, &bytes));
    }
    println!("```text golden=constants\n{}\n```", constants().join("\n"));
    println!(
        "```text golden=chain-coupled.points\n{}\n```",
        chain_coupled_points(&common::chain_coupled_image()).join("\n")
    );
}

#[test]
fn document_holds_exactly_the_golden_blocks() {
    print_blocks_on_request();
    let doc = golden_blocks(&protocol_md());
    let mut want: Vec<String> = expected_blocks().into_keys().collect();
    want.push("constants".to_owned());
    want.push("chain-coupled.points".to_owned());
    want.sort();
    let have: Vec<String> = doc.into_keys().collect();
    assert_eq!(have, want);
}

#[test]
fn golden_hex_matches_the_encoder_byte_for_byte() {
    let doc = golden_blocks(&protocol_md());
    for (name, bytes) in expected_blocks() {
        let block = doc
            .get(&name)
            .unwrap_or_else(|| panic!("docs/protocol.md lacks {name}"));
        assert_eq!(
            parse_hex(block),
            bytes,
            "{name} should read:\n{}",
            to_hex_block(&name, &bytes)
        );
    }
}

#[test]
fn golden_frames_decode_to_the_golden_messages() {
    let doc = golden_blocks(&protocol_md());
    for (name, msg) in golden_messages() {
        let frame = parse_hex(&doc[&format!("{name}.frame")]);
        assert_eq!(
            common::decode_all(&mut FrameDecoder::new(), &frame),
            vec![Ok(msg.clone())],
            "{name}"
        );
        let message = parse_hex(&doc[&format!("{name}.message")]);
        assert_eq!(qgait_proto::decode_message(&message), Ok(msg), "{name}");
    }
}

#[test]
fn golden_error_frames_give_their_errors() {
    let doc = golden_blocks(&protocol_md());
    let mut cases: Vec<(String, DecodeError)> = golden_errors()
        .into_iter()
        .map(|(n, _, e)| (n.to_owned(), e))
        .collect();
    cases.push(("error-crc".to_owned(), DecodeError::Crc));
    for (name, expected) in cases {
        let frame = parse_hex(&doc[&format!("{name}.frame")]);
        assert_eq!(
            common::decode_all(&mut FrameDecoder::new(), &frame),
            vec![Err(expected)],
            "{name}"
        );
    }
}

#[test]
fn golden_constants_match_the_crate() {
    let doc = golden_blocks(&protocol_md());
    let block: Vec<String> = doc["constants"]
        .iter()
        .map(|l| l.trim().to_owned())
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(block, constants());
}

/// The CRC is the documented CRC-32C: a bitwise implementation written from the document's
/// parameters (reflected polynomial 0x82F63B78, init and xorout 0xFFFFFFFF) agrees with it.
#[test]
fn crc_is_crc32c_as_documented() {
    fn crc32c_bitwise(bytes: &[u8]) -> u32 {
        let mut crc = 0xFFFF_FFFFu32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0x82F6_3B78
                } else {
                    crc >> 1
                };
            }
        }
        crc ^ 0xFFFF_FFFF
    }
    assert_eq!(crc32c(b"123456789"), 0xE306_9283);
    assert_eq!(crc32c_bitwise(b"123456789"), FRAME_CRC_CHECK);
    let mut rng = common::Rng::new(5);
    for len in 0..300 {
        let data: Vec<u8> = (0..len).map(|_| rng.byte()).collect();
        assert_eq!(crc32c(&data), crc32c_bitwise(&data), "len {len}");
    }
}

/// 9.5's worked chain: its image, read from the document, evaluates to the points the document
/// lists (the hub's table code, `f32`).
#[test]
fn chain_example_points_are_the_documented_ones() {
    let doc = golden_blocks(&protocol_md());
    let image = parse_hex(&doc["chain-coupled.image"]);
    let listed: Vec<String> = doc["chain-coupled.points"]
        .iter()
        .map(|l| l.trim().to_owned())
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(listed, chain_coupled_points(&image));
}
