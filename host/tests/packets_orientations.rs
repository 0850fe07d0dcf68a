//! `qgait packets --orientations`: the segment nodes' stream of an IMU recording (what the hub
//! is sent, in order), and its refusals.
mod common;

use common::{imu_dir, qgait, stderr};
use qgait_proto::{FrameDecoder, HeadingAxisId, InputMode, Message, ModelId, SegmentId};

#[test]
fn the_stream_is_the_configuration_the_calibration_pose_then_the_rows() {
    let Some(dir) = imu_dir() else { return };
    let out = tempfile::tempdir().expect("temp dir");
    let stream = out.path().join("imu.bin");
    let o = qgait(&[
        "packets",
        "--orientations",
        dir.join("walking_orientations.sto").to_str().unwrap(),
        "--calibration",
        dir.join("placement_orientations.sto").to_str().unwrap(),
        "--base-imu",
        "torso_imu",
        "--mode",
        "closed-form",
        "--rows",
        "25",
        "-o",
        stream.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&stream).expect("written");
    let messages: Vec<Message> = FrameDecoder::new()
        .feed(&bytes)
        .map(|r| r.expect("every frame decodes"))
        .collect();
    let (config, rest) = messages.split_first().expect("messages");
    assert!(matches!(config, Message::Config(c) if c.model == ModelId::Gait2392));
    let Some((Message::ImuConfig(imu), packets)) = rest.split_first() else {
        panic!("an ImuConfig second: {rest:?}");
    };
    assert_eq!(imu.mode, InputMode::OrientationsClosedForm);
    assert!(imu.calibrate);
    assert_eq!(imu.segments, 0xff);
    assert_eq!(
        imu.heading.map(|h| (h.base, h.axis)),
        Some((SegmentId::Torso, HeadingAxisId::Z))
    );
    assert_eq!(
        imu.sensor_to_opensim,
        [-std::f32::consts::FRAC_PI_2, 0.0, 0.0]
    );
    // 8 segments for the calibration pose (seq 0) and each of the 25 rows (seq 1 to 25).
    assert_eq!(packets.len(), 8 * 26);
    for (i, m) in packets.iter().enumerate() {
        let Message::SegmentOrientation(p) = m else {
            panic!("packet {i}: {m:?}");
        };
        assert_eq!(
            (p.header.seq, p.header.segment),
            ((i / 8) as u32, SegmentId::ALL[i % 8])
        );
        let n: f64 = p
            .q14
            .iter()
            .map(|&c| (f64::from(c) / 16384.0).powi(2))
            .sum();
        assert!((n.sqrt() - 1.0).abs() < 1e-3, "packet {i}: {p:?}");
    }
}

#[test]
fn orientations_need_their_calibration_and_no_motion() {
    let o = qgait(&["packets", "--orientations", "walk.sto", "-o", "x.bin"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--calibration"), "{}", stderr(&o));
    let o = qgait(&[
        "packets",
        "builtin:normal",
        "--orientations",
        "walk.sto",
        "--calibration",
        "static.sto",
        "-o",
        "x.bin",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    let o = qgait(&[
        "packets",
        "--orientations",
        "no/such/walk.sto",
        "--calibration",
        "no/such/static.sto",
        "-o",
        "x.bin",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("no/such/static.sto"), "{}", stderr(&o));
    // A recording has its own times: --rate is MOTION's.
    let o = qgait(&[
        "packets",
        "--orientations",
        "walk.sto",
        "--calibration",
        "static.sto",
        "--rate",
        "7",
        "-o",
        "x.bin",
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("'--rate <HZ>'") && stderr(&o).contains("cannot be used with"),
        "{}",
        stderr(&o)
    );
}
