//! `qgait decode --format jsonl` prints every kind of message with its fields: a node stream
//! (`qgait packets`), the host's configuration frames (`qgait config`) and the raw IMU
//! messages of the protocol's golden examples.
mod common;

use std::path::Path;

use common::{imu_dir, qgait, stderr, stdout};
use qgait_proto::{FrameDecoder, Message};
use serde_json::Value;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The messages in `file` (decoded here, with the protocol crate) and `qgait decode
/// --format jsonl`'s lines for it, one each.
fn decode(file: &Path) -> (Vec<Message>, Vec<Value>) {
    let bytes = std::fs::read(file).unwrap();
    let messages: Vec<Message> = FrameDecoder::new()
        .feed(&bytes)
        .map(|r| r.expect("every frame decodes"))
        .collect();
    let o = qgait(&["decode", s(file), "--format", "jsonl"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let lines: Vec<Value> = stdout(&o)
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON object"))
        .collect();
    assert_eq!(lines.len(), messages.len(), "{}", stdout(&o));
    for line in &lines {
        assert_ne!(line["type"], "other", "{line}");
    }
    (messages, lines)
}

/// `v` as an array of numbers.
fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn a_node_stream_is_its_joint_angles() {
    let dir = tempfile::tempdir().unwrap();
    let stream = dir.path().join("p.bin");
    let o = qgait(&[
        "packets",
        "builtin:normal,rows=3",
        "--model",
        "hak",
        "-o",
        s(&stream),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (messages, lines) = decode(&stream);
    assert_eq!(messages.len(), 18);
    for (m, line) in messages.iter().zip(&lines) {
        let Message::JointAngle(a) = m else {
            panic!("{m:?}")
        };
        assert_eq!(line["type"], "joint_angle");
        assert_eq!(line["version"], a.version);
        assert_eq!(line["node"], a.node);
        assert_eq!(line["joint"], a.joint.name());
        assert_eq!(line["seq"], a.seq);
        assert_eq!(line["timestamp_us"], a.timestamp_us);
        assert_eq!(line["angle"].as_f64(), Some(f64::from(a.angle)));
        assert_eq!(line["quality"], a.quality);
        assert_eq!(line.as_object().unwrap().len(), 8, "{line}");
    }
    assert_eq!(lines[17]["seq"], 2);
}

#[test]
fn configuration_frames_are_their_settings() {
    let dir = tempfile::tempdir().unwrap();
    let lengths = dir.path().join("a.toml");
    std::fs::write(
        &lengths,
        "pelvis_half_width = 0.09\nfemur = 0.41\ntibia_r = 0.44\ntibia_l = 0.43\nfoot = 0.21\n",
    )
    .unwrap();
    let out = dir.path().join("c.bin");
    let o = qgait(&[
        "config",
        "--model",
        "phak",
        "--anthropometry",
        s(&lengths),
        "--policy",
        "hold",
        "--window",
        "3",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (messages, lines) = decode(&out);
    let [Message::Config(c)] = messages.as_slice() else {
        panic!("{messages:?}")
    };
    let line = &lines[0];
    assert_eq!(line["type"], "config");
    assert_eq!(line["model"], "phak");
    let lengths = c.anthropometry.expect("lengths sent");
    for leg in 0..2 {
        assert_eq!(
            floats(&line["anthropometry"][leg]),
            lengths[leg].map(f64::from)
        );
    }
    assert_eq!(
        line["anthropometry"][1][2].as_f64(),
        Some(f64::from(0.43f32))
    );
    assert_eq!(line["missing_policy"], "HoldLast");
    assert_eq!(line["reorder_window"], 3);
    assert_eq!(line["request_status"], true);
    assert_eq!(
        line.as_object().unwrap().keys().collect::<Vec<_>>(),
        [
            "type",
            "model",
            "anthropometry",
            "missing_policy",
            "reorder_window",
            "request_status"
        ]
    );

    let o = qgait(&["config", "--model", "hak", "-o", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, lines) = decode(&out);
    assert!(lines[0]["anthropometry"].is_null(), "{}", lines[0]);
}

#[test]
fn an_orientation_stream_is_its_imu_configuration_and_quaternions() {
    let Some(imu) = imu_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let stream = dir.path().join("imu.bin");
    let o = qgait(&[
        "packets",
        "--orientations",
        s(&imu.join("walking_orientations.sto")),
        "--calibration",
        s(&imu.join("placement_orientations.sto")),
        "--base-imu",
        "torso_imu",
        "--base-heading-axis",
        "-z",
        "--rows",
        "2",
        "-o",
        s(&stream),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (messages, lines) = decode(&stream);
    let mut orientations = 0;
    for (m, line) in messages.iter().zip(&lines) {
        match m {
            Message::Config(_) => assert_eq!(line["type"], "config"),
            Message::ImuConfig(c) => {
                assert_eq!(line["type"], "imu_config");
                assert_eq!(line["segments"], c.segments);
                assert_eq!(line["calibrate"], c.calibrate);
                assert_eq!(line["heading"]["base"], "Torso");
                assert_eq!(line["heading"]["axis"], "NegZ");
                assert_eq!(
                    floats(&line["sensor_to_opensim"]),
                    c.sensor_to_opensim.map(f64::from)
                );
            }
            Message::SegmentOrientation(q) => {
                orientations += 1;
                assert_eq!(line["type"], "segment_orientation");
                assert_eq!(line["seq"], q.header.seq);
                assert_eq!(line["node"], q.header.node);
                assert_eq!(line["timestamp_us"], q.header.timestamp_us);
                let q14: Vec<i64> = line["q14"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|c| c.as_i64().unwrap())
                    .collect();
                assert_eq!(q14, q.q14.map(i64::from));
                let decoded = floats(&line["quaternion"]);
                assert_eq!(decoded, q.quaternion().map(f64::from));
                let norm = decoded.iter().map(|c| c * c).sum::<f64>().sqrt();
                assert!((norm - 1.0).abs() < 1e-3, "{line}");
                let keys: Vec<&String> = line.as_object().unwrap().keys().collect();
                assert_eq!(keys[keys.len() - 2..], ["quaternion", "quality"]);
            }
            other => panic!("{other:?}"),
        }
    }
    assert!(orientations >= 3 * 8, "{orientations}");
}

/// The hex blocks `hex golden=NAME` of `docs/protocol.md`, as bytes.
fn golden(name: &str) -> Vec<u8> {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/protocol.md"))
        .unwrap();
    let start = doc
        .find(&format!("```hex golden={name}\n"))
        .unwrap_or_else(|| panic!("no block {name}"));
    let body = &doc[start..]
        .lines()
        .skip(1)
        .take_while(|l| !l.starts_with("```"));
    body.clone()
        .flat_map(|l| l.split_whitespace())
        .map(|b| u8::from_str_radix(b, 16).unwrap())
        .collect()
}

#[test]
fn the_raw_imu_golden_frames_are_their_fields() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("raw.bin");
    let mut bytes = vec![0u8];
    for name in ["raw-imu-sample", "raw-imu-config", "raw-imu-status"] {
        bytes.extend(golden(&format!("{name}.frame")));
    }
    std::fs::write(&file, &bytes).unwrap();
    let (_, lines) = decode(&file);
    let [sample, config, status] = lines.as_slice() else {
        panic!("{lines:?}")
    };
    // The values the protocol spells out field by field (section 4.10's examples).
    assert_eq!(sample["type"], "raw_imu_sample");
    assert_eq!(sample["version"], 3);
    assert_eq!(sample["node"], 4);
    assert_eq!(sample["segment"], "TibiaR");
    assert_eq!(sample["seq"], 300);
    assert_eq!(floats(&sample["gyro"]), [-188.0, 47.0, 3289.0]);
    assert_eq!(floats(&sample["accel"]), [251.0, 2005.0, -84.0]);
    assert_eq!(floats(&sample["mag"]), [133.0, -233.0, 80.0]);

    assert_eq!(config["type"], "raw_imu_config");
    assert_eq!(config["segments"], 255);
    assert_eq!(config["fusion"], "NineD");
    assert_eq!(config["rate_hz"], 100);
    assert_eq!(config["output_every"], 1);
    assert_eq!(
        config["gyro_per_count"].as_f64(),
        Some(f64::from(1.0642252e-3f32))
    );
    assert_eq!(
        config["accel_per_count"].as_f64(),
        Some(f64::from(4.7884034e-3f32))
    );
    assert_eq!(config["mag_per_count"].as_f64(), Some(f64::from(0.15f32)));
    assert_eq!(config["request_status"], true);

    let expected = [
        ("type", Value::from("raw_imu_status")),
        ("samples_accepted", 48_000.into()),
        ("saturated", 3.into()),
        ("rate_gaps", 2.into()),
        ("samples_lost", 5.into()),
        ("timing_errors", 1.into()),
        ("stale_samples", 1.into()),
        ("resyncs", 0.into()),
        ("missing_magnetometer", 0.into()),
        ("not_configured", 4.into()),
    ];
    let got: Vec<(&str, Value)> = status
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, v)| (k.as_str(), v.clone()))
        .collect();
    assert_eq!(got, expected);
}
