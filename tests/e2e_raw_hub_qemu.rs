//! End to end: eight raw sensors through the hub with raw input under QEMU (mps2-an386, the
//! firmware built with its features `imu` and `raw`).
//!
//! The sensors are synthesized from the real IMU walk's joint angles (OpenSense's solution of
//! the OpenSense tutorial's first 12 s, `../shared/data/imu/`) by `qgait imu-signals`, with an
//! ICM-20948's white noise (gyroscope 0.015 °/s/√Hz, accelerometer 230 µg/√Hz), a gyroscope
//! bias of about 0.5 °/s per axis that walks, and a magnetometer (0.5 µT noise) in a homogeneous
//! field of 48 µT whose horizontal part points along OpenSim's −z, so that the fusion's world
//! (east, north, up) turned by the default sensor-to-OpenSim rotation is OpenSim's ground and
//! the hub's pelvis heading is the truth's. The eight: pelvis, both femurs, tibias and calcanei,
//! mounted at angles to their bodies, and the torso's, which rides the pelvis (`imu-signals`
//! moves no lumbar joint). `qgait packets --raw --hub` makes the raw nodes' stream (the
//! calibration pose 2 s in, while the subject still stands), then:
//!
//! - `qgait emulate --verify` (and `qgait verify --raw` of its log): every frame's points
//!   within 10 µm of the `f64` kernel's for its angles, a frame for every sample due, and the
//!   angles within 0.1° RMS of the host's `f64` fusion and IMU path of the same stream;
//! - the hub's joint angles within 2° RMS of the angles the signals were made from (the 14
//!   coordinates sensors determine; the pelvis rotation compared modulo a turn);
//! - through a radio link (flipped bits, lost and swapped packets, the fault tests' ledger): a
//!   frame for exactly the samples whose every raw sample arrived after the calibration pose,
//!   and those frames as the host computes the damaged stream.
//!
//! Skipped, with the reason printed, without `../shared`, QEMU or the firmware build.

use qgait_system_tests as common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use qgait_device::log::HubLog;
use qgait_device::orientations::OrientationCheck;
use qgait_device::raw_hub::RawHubHost;
use qgait_emulate::faults::{damage, FaultPlan};
use qgait_emulate::push_frame;
use qgait_emulate::qemu::Echo;
use qgait_emulate::session::{self, closing_frames, InputCounts, Limits};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_proto::{FrameDecoder, Message, RawImuSample};

/// The recording the signals are made from.
const TRUTH: &str = "walking_gait2392_opensense_0-12s.sto";

/// The IMUs, in the segments' order (pelvis, femur_r, tibia_r, calcn_r, femur_l, tibia_l,
/// calcn_l, torso): the pelvis sensor's z axis points forward (the heading's base axis).
const PLACEMENT: &str = r#"
[[imu]]
name = "pelvis_imu"
body = "pelvis"
translation = [-0.17, 0.05, 0.0]
orientation = [0.0, 1.5707963267948966, 0.0]

[[imu]]
name = "femur_r_imu"
body = "femur_r"
translation = [0.02, -0.20, 0.06]
orientation = [0.10, 0.30, -0.20]

[[imu]]
name = "tibia_r_imu"
body = "tibia_r"
translation = [0.03, -0.15, 0.05]
orientation = [-0.30, 0.20, 0.60]

[[imu]]
name = "calcn_r_imu"
body = "calcn_r"
translation = [0.10, 0.05, 0.0]
orientation = [1.20, -0.40, 0.30]

[[imu]]
name = "femur_l_imu"
body = "femur_l"
translation = [0.02, -0.20, -0.06]
orientation = [-0.20, 0.40, 0.10]

[[imu]]
name = "tibia_l_imu"
body = "tibia_l"
translation = [0.03, -0.15, -0.05]
orientation = [0.30, -0.10, -0.50]

[[imu]]
name = "calcn_l_imu"
body = "calcn_l"
translation = [0.10, 0.05, 0.0]
orientation = [-1.00, 0.30, 0.20]

[[imu]]
name = "torso_imu"
body = "pelvis"
translation = [-0.15, 0.35, 0.0]
orientation = [0.0, 1.5707963267948966, 0.1]
"#;

/// The firmware with raw input; `None` (the reason printed) without QEMU or a build.
fn raw_hub_elf() -> Option<PathBuf> {
    static ELF: OnceLock<Option<PathBuf>> = OnceLock::new();
    ELF.get_or_init(|| common::feature_firmware_elf("imu,raw", "QGAIT_RAW_FIRMWARE_ELF"))
        .clone()
}

/// The synthesized signals and the hub's stream, made once: (the truth file, the stream).
fn stream() -> Option<(PathBuf, PathBuf)> {
    static STREAM: OnceLock<Option<(PathBuf, PathBuf)>> = OnceLock::new();
    STREAM.get_or_init(make_stream).clone()
}

fn make_stream() -> Option<(PathBuf, PathBuf)> {
    let truth = common::imu_dir()?.join(TRUTH);
    let dir = common::scratch("e2e-raw-hub", "signals");
    let placement = dir.join("placement.toml");
    std::fs::write(&placement, PLACEMENT).expect("the placement writes");
    let p = |p: &Path| p.to_str().expect("utf-8 path").to_string();
    let signals = dir.join("signals");
    let out = common::qgait(&[
        "imu-signals",
        &p(&truth),
        "--imus",
        &p(&placement),
        "-o",
        &p(&signals),
        "--gyro-noise-density",
        "2.6e-4",
        "--accel-noise-density",
        "2.3e-3",
        "--gyro-bias",
        "0.01,-0.008,0.006",
        "--gyro-bias-walk",
        "1e-4",
        "--magnetic-field",
        "0,-44,-20",
        "--mag-noise-std",
        "0.5",
        "--seed",
        "1",
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let stream = dir.join("hub.bin");
    let mut args: Vec<String> = ["packets", "--raw"].map(String::from).to_vec();
    for name in [
        "pelvis", "femur_r", "tibia_r", "calcn_r", "femur_l", "tibia_l", "calcn_l", "torso",
    ] {
        args.push(p(&signals.join(format!("raw/{name}_imu.csv"))));
    }
    args.extend(
        [
            "--hub",
            "--base-imu",
            "pelvis_imu",
            "--base-heading-axis",
            "z",
            "-o",
            &p(&stream),
        ]
        .map(String::from),
    );
    let out = common::qgait(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(out.status.success(), "{}", common::stderr(&out));
    Some((truth, stream))
}

/// The truth's 17 coordinates (radians) per row, from OpenSense's `.sto` (degrees).
fn truth_angles(path: &Path) -> Vec<[f64; 17]> {
    let text = std::fs::read_to_string(path).expect("the truth reads");
    let mut lines = text.lines().skip_while(|l| *l != "endheader").skip(1);
    let header: Vec<&str> = lines.next().expect("a header").split('\t').collect();
    let at = COORDINATES.map(|n| header.iter().position(|h| *h == n).expect(n));
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let cells: Vec<f64> = l
                .split('\t')
                .map(|c| c.parse().expect("a number"))
                .collect();
            at.map(|i| cells[i].to_radians())
        })
        .collect()
}

#[test]
fn eight_raw_sensors_through_the_hub_give_the_walk_s_angles() {
    let Some(elf) = raw_hub_elf() else { return };
    let Some((truth, stream)) = stream() else {
        return;
    };
    let dir = common::scratch("e2e-raw-hub", "clean");
    let log = dir.join("hub.log");
    let p = |p: &Path| p.to_str().expect("utf-8 path").to_string();
    let out = common::qgait(&[
        "emulate",
        "--stream",
        &p(&stream),
        "--elf",
        &p(&elf),
        "--verify",
        "--log",
        &p(&log),
    ]);
    let stdout = common::stdout(&out);
    eprintln!("{stdout}");
    assert!(out.status.success(), "{stdout}\n{}", common::stderr(&out));
    assert!(stdout.contains("missing samples: 0"), "{stdout}");
    assert!(stdout.contains("PASS"), "{stdout}");
    // The same check of the log on its own.
    let out = common::qgait(&["verify", &p(&log), "--raw", &p(&stream)]);
    let stdout = common::stdout(&out);
    assert!(out.status.success(), "{stdout}\n{}", common::stderr(&out));
    assert!(stdout.contains("raw input: 1000 frames"), "{stdout}");

    let poses = HubLog::decode(&std::fs::read(&log).expect("the log reads")).poses;
    let truth = truth_angles(&truth);
    // Frames from 2 s (the calibration pose) to the end of the 12 s.
    assert!(poses.len() >= 990, "{} frames", poses.len());
    let (mut sum, mut count) = (0.0, 0usize);
    let mut worst = (0.0f64, "");
    for (i, name) in COORDINATES.iter().enumerate() {
        if name.starts_with("mtp") {
            continue;
        }
        let mut squares = 0.0;
        for f in &poses {
            let want = truth[f.seq as usize][i];
            let d = f64::from(f.angles[i]) - want;
            // The pelvis rotation, unwrapped on the hub, modulo a turn.
            let d =
                (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
            squares += d * d;
        }
        let rms = (squares / poses.len() as f64).sqrt().to_degrees();
        if rms > worst.0 {
            worst = (rms, name);
        }
        sum += squares;
        count += poses.len();
    }
    let rms = (sum / count as f64).sqrt().to_degrees();
    eprintln!(
        "hub against the walk's angles: {rms:.3}° RMS over {} frames, worst coordinate {} {:.3}°",
        poses.len(),
        worst.1,
        worst.0
    );
    assert!(
        rms <= 2.0,
        "{rms}° RMS from the angles the signals were made from"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn raw_streams_through_a_radio_link() {
    let Some(elf) = raw_hub_elf() else { return };
    let Some((_, stream)) = stream() else {
        return;
    };
    let bytes = std::fs::read(&stream).expect("the stream reads");
    // The configuration and the samples before the calibration pose's are sent clean; the
    // link damages the rest, sample by sample.
    let messages: Vec<Message> = FrameDecoder::new().feed(&bytes).flatten().collect();
    let imu_at = messages
        .iter()
        .position(|m| matches!(m, Message::ImuConfig(_)))
        .expect("an ImuConfig");
    let mut input = vec![0u8];
    for m in &messages[..=imu_at] {
        push_frame(&mut input, m);
    }
    let mut rows: Vec<Vec<RawImuSample>> = Vec::new();
    for m in &messages[imu_at + 1..] {
        if let Message::RawImuSample(s) = m {
            match rows.last_mut() {
                Some(row) if row[0].header.seq == s.header.seq => row.push(*s),
                _ => rows.push(vec![*s]),
            }
        }
    }
    // The calibration pose clean, the rest through the link.
    let (calibration, rows) = rows.split_first().expect("samples");
    for s in calibration {
        push_frame(&mut input, &Message::RawImuSample(*s));
    }
    let d = damage(rows, &FaultPlan::radio_link(7, 4));
    input.extend_from_slice(&d.stream);
    let host = RawHubHost::of(&input).expect("the host computes the damaged stream");
    let due = host.frames_due();
    assert!(due.len() < rows.len(), "the link damaged nothing");
    // The ledger's view: the samples whose every raw sample was delivered are the ones due.
    assert_eq!(
        due,
        d.intact_samples(),
        "the host's rules against the link's ledger"
    );

    let config = messages
        .iter()
        .find(|m| matches!(m, Message::Config(_)))
        .expect("a Config");
    let mut sent = input.clone();
    sent.extend(closing_frames(config).expect("closing frames"));
    let expected = host.input_counts(&sent);
    let limits = Limits::for_stream(sent.len());
    let out = session::run(&elf, sent, expected, Echo::Quiet, limits).expect("QEMU runs");
    let status = out
        .status
        .unwrap_or_else(|| panic!("{}", out.problem.unwrap_or_default()));
    assert_eq!(InputCounts::counted_by(&status), expected, "{status:?}");
    let poses = HubLog::decode(&out.uart).poses;
    let got: BTreeSet<u32> = poses.iter().map(|p| p.seq).collect();
    assert_eq!(
        got, due,
        "one frame for each sample whose raw samples all arrived"
    );
    let c = OrientationCheck::run(
        &poses,
        &host
            .angles_of(|seq| got.contains(&seq))
            .expect("the host solves the stream"),
    );
    eprintln!(
        "radio link: {} of {} samples due a frame; {}",
        due.len(),
        rows.len(),
        c.angles_report(0.1)
    );
    assert!(c.angles_passed(0.1), "{}", c.angles_report(0.1));
}
