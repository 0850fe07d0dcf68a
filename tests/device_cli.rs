//! `qgait packets`, `decode` and `verify` through the binary (no QEMU needed: the hub log is
//! made here from the f64 kernel rounded to f32, as a hub would send it).

use qgait_system_tests as common;

use common::{qgait, stderr, stdout};
use qgait_device::packets::push_frame;
use qgait_proto::device_model::{pose_distances, pose_points};
use qgait_proto::{Message, ModelId, PoseFrame, PoseModels, Status};

fn hub_log(seqs: impl IntoIterator<Item = u32>) -> Vec<u8> {
    let model = PoseModels::<f64>::defaults();
    let mut out = vec![0u8];
    for seq in seqs {
        let angles =
            heapless::Vec::from_slice(&[0.05, -0.02, 0.3, -0.6, 0.1, -0.1, -0.2, 0.05]).unwrap();
        let mut f = PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: ModelId::Phak,
            angles,
            points: [[0.0; 3]; 8],
            distances: [0.0; 3],
            flags: 0,
        };
        let pose = model.frame_pose(&f).expect("a hub's own model");
        f.points = pose_points(&pose);
        f.distances = pose_distances(&pose);
        push_frame(&mut out, &Message::PoseFrame(f));
    }
    push_frame(
        &mut out,
        &Message::Status(Status {
            packets_accepted: 8,
            ..Status::default()
        }),
    );
    out
}

#[test]
fn packets_then_decode_gives_one_packet_per_joint_per_row() {
    let dir = tempfile::tempdir().unwrap();
    let stream = dir.path().join("s.bin");
    let o = qgait(&[
        "packets",
        "builtin:normal,rows=5",
        "--rate",
        "50",
        "--model",
        "hak",
        "-o",
        stream.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("wrote 30 packets (5 samples × 6 joints)"),
        "{}",
        stderr(&o)
    );
    let o = qgait(&["decode", stream.to_str().unwrap(), "--format", "jsonl"]);
    assert!(o.status.success());
    assert_eq!(
        stdout(&o)
            .lines()
            .filter(|l| l.starts_with(r#"{"type":"joint_angle","version":3,"#))
            .count(),
        30
    );
    assert!(
        stderr(&o).contains(
            "0 pose frames, 0 status frames, 30 other messages, 0 damaged frames; \
             other messages: joint_angle 30"
        ),
        "{}",
        stderr(&o)
    );
}

#[test]
fn decode_skips_damage_and_verify_passes_a_good_log_and_fails_a_gap() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.bin");
    std::fs::write(&good, hub_log(0..10)).unwrap();
    let o = qgait(&["verify", good.to_str().unwrap()]);
    assert!(o.status.success(), "{}{}", stdout(&o), stderr(&o));
    assert!(
        stdout(&o).contains("10 frames (10 phak)") && stdout(&o).contains("verify: ok"),
        "{}",
        stdout(&o)
    );

    // A log cut off inside its last frame: both say that frame is lost.
    let mut cut = hub_log(0..10);
    cut.truncate(cut.len() - 20);
    let cut_path = dir.path().join("cut.bin");
    std::fs::write(&cut_path, &cut).unwrap();
    for command in ["decode", "verify"] {
        let o = qgait(&[command, cut_path.to_str().unwrap()]);
        assert!(
            stderr(&o).contains(&format!(
                "warning: {}: the log ends inside a frame",
                cut_path.display()
            )),
            "{command}: {}",
            stderr(&o)
        );
    }

    // A frame damaged in the middle: decode reports it and decodes the others; verify fails
    // because its sample is missing.
    let mut bytes = hub_log(0..10);
    let mid = bytes.len() / 2;
    bytes[mid] = 0x00;
    let bad = dir.path().join("bad.bin");
    std::fs::write(&bad, &bytes).unwrap();
    let o = qgait(&["decode", bad.to_str().unwrap()]);
    assert!(o.status.success());
    let rows = stdout(&o).lines().count() - 1;
    assert!(rows == 9, "{rows} rows\n{}", stdout(&o));
    assert!(
        stderr(&o).contains(&format!("{}: damaged frame ending at byte", bad.display())),
        "{}",
        stderr(&o)
    );
    let o = qgait(&["verify", bad.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        stdout(&o).contains("missing samples: 1")
            && stderr(&o).contains("error: verification failed"),
        "{}{}",
        stdout(&o),
        stderr(&o)
    );
    for tol in ["nan", "inf", "-1", "x"] {
        let o = qgait(&["verify", bad.to_str().unwrap(), &format!("--tol-um={tol}")]);
        assert!(!o.status.success());
        assert!(
            stderr(&o).contains("is not a tolerance in micrometres"),
            "{tol}: {}",
            stderr(&o)
        );
    }
}

/// `decode` of garbage or of a `.mot` finds no frame: it says so and fails.
#[test]
fn decode_of_what_is_not_a_log_says_nothing_was_found() {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in [
        ("garbage.bin", vec![0x5a_u8; 4096]),
        (
            "walk.mot",
            b"m\nversion=1\ninDegrees=yes\nendheader\ntime\tknee_angle_r\n0\t1\n".to_vec(),
        ),
    ] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        let o = qgait(&["decode", path.to_str().unwrap()]);
        assert!(!o.status.success(), "{name}");
        assert!(stderr(&o).contains("nothing was found"), "{}", stderr(&o));
    }
}

/// `decode` writes each frame's time, the sample's sensor time it carries; `--rate HZ` writes
/// `seq / HZ` instead. A frames CSV without times (an older qgait's) is refused by `gait`,
/// which says how to get them. A rate that is not above 0 is refused.
#[test]
fn decode_writes_each_frames_time() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hub.bin");
    std::fs::write(&log, hub_log([100, 101, 103])).unwrap();
    let log = log.to_str().unwrap();
    let times = |o: &std::process::Output| -> Vec<String> {
        stdout(o)
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(1).unwrap().to_string())
            .collect()
    };
    let o = qgait(&["decode", log]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(times(&o), ["1", "1.01", "1.03"]);
    let o = qgait(&["decode", log, "--rate", "50"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(times(&o), ["2", "2.02", "2.06"]);

    let o = qgait(&["decode", log]);
    let no_times: String = stdout(&o)
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let mut cells: Vec<&str> = l.split(',').collect();
            if i > 0 {
                cells[1] = "";
            }
            cells.join(",") + "\n"
        })
        .collect();
    let csv = dir.path().join("frames.csv");
    std::fs::write(&csv, no_times).unwrap();
    let o = qgait(&[
        "gait",
        csv.to_str().unwrap(),
        "-o",
        dir.path().join("g").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("`qgait decode` writes the times a hub's frames carry"),
        "{}",
        stderr(&o)
    );

    for bad in ["0", "-100", "nan"] {
        let o = qgait(&["decode", log, &format!("--rate={bad}")]);
        assert!(
            !o.status.success() && stderr(&o).contains("not a sampling rate"),
            "{bad}"
        );
    }
}
