//! End to end: the IMU orientation input through the hub firmware under QEMU (mps2-an386, the
//! firmware built with its `imu` feature): the segment nodes' stream of a recording
//! (`OrientationStream`: gait2392 and the IMU configuration, the calibration pose, the rows),
//! every pose frame checked against the host's `f64` computation of the same stream (the
//! kernel's calibration, solver and forward kinematics), and the hub's counters against what
//! the stream must make it count.
//!
//! - a synthetic recording made by the kernel's IMU tests' generator
//!   (`crates/qgait-kernel/tests/imu_common`: known coordinates through the kernel's own gait2392
//!   forward kinematics, sensors mounted at random up to 30 degrees, the subject facing -115
//!   degrees at calibration), clean in both solver modes and with the radio link's damage
//!   (`FaultPlan::radio_link`);
//! - the real recording (`../shared/data/imu/`, OpenSense's tutorial, its first 5 s), clean in
//!   both solver modes and with the radio link's damage.
//!
//! Needs `qemu-system-arm`; the IMU firmware (`QGAIT_IMU_FIRMWARE_ELF`, else
//! `firmware::imu_elf`, built or brought up to date first). Each test is skipped, with the reason printed,
//! when QEMU or the build is missing.

use qgait_system_tests as common;
#[path = "../crates/qgait-kernel/tests/imu_common/mod.rs"]
mod imu_common;

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use qgait_device::log::HubLog;
use qgait_device::orientations::{OrientationCheck, OrientationStream};
use qgait_emulate::faults::{damage, FaultPlan};
use qgait_emulate::push_frame;
use qgait_emulate::qemu::Echo;
use qgait_emulate::session::{self, closing_frames, InputCounts, Limits};
use qgait_kernel::imu::{Mode, Settings};
use qgait_proto::{Message, MissingPolicy, PoseFrame, Status};

/// Largest accepted error of a point of the hub's `f32` frames from the host's `f64` (metres).
const TOLERANCE_M: f64 = 10e-6;
/// The reorder window of the stream.
const WINDOW: u8 = 4;
/// One QEMU at a time.
static QEMU_TURN: Mutex<()> = Mutex::new(());

/// The IMU firmware (found or built once for all the tests); `None` (the reason printed)
/// without QEMU or a build.
fn imu_elf() -> Option<PathBuf> {
    static ELF: std::sync::OnceLock<Option<PathBuf>> = std::sync::OnceLock::new();
    let elf = ELF.get_or_init(find_or_build_imu_elf).clone();
    if elf.is_none() {
        eprintln!("skipped: no IMU firmware (see above)");
    }
    elf
}

fn find_or_build_imu_elf() -> Option<PathBuf> {
    qgait_system_tests::feature_firmware_elf("imu", "QGAIT_IMU_FIRMWARE_ELF")
}

/// Runs `input` (a stream beginning with its configuration) through the hub, then the closing
/// request; the frames and the final status.
fn run(
    elf: &Path,
    stream: &OrientationStream,
    input: Vec<u8>,
    what: &str,
) -> (Vec<PoseFrame>, Status) {
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let [config, _] = stream.config_messages(MissingPolicy::Drop, WINDOW);
    let mut input = input;
    input.extend(closing_frames(&config).expect("closing frames"));
    let expected = InputCounts::of(&input);
    let limits = Limits::for_stream(input.len());
    let out = session::run(elf, input, expected, Echo::Quiet, limits).expect("QEMU runs");
    let status = out.status.unwrap_or_else(|| {
        panic!("{what}: {}", out.problem.unwrap_or_default());
    });
    let log = HubLog::decode(&out.uart);
    assert_eq!(log.counts.damaged_total(), 0, "{what}: {}", log.counts);
    eprintln!(
        "{what}: {} frames in {:.2} s",
        log.poses.len(),
        out.elapsed.as_secs_f64()
    );
    (log.poses, status)
}

/// The synthetic recording of `seconds` as its nodes send it, solved in `mode`.
fn synthetic(seconds: f64, mode: Mode) -> OrientationStream {
    let mount = imu_common::mountings(7);
    let rec = imu_common::recording(seconds, &mount, &mount, imu_common::Disturbance::default());
    OrientationStream::new(
        &rec.calibration,
        rec.frames
            .iter()
            .enumerate()
            .map(|(k, (o, _, _))| (k as f64 / imu_common::RATE, *o)),
        &Settings::opensense_tutorial(),
        mode,
    )
}

/// A clean stream: one frame per row, each within [`TOLERANCE_M`] of the host's `f64`; the
/// calibration counted, nothing else.
fn clean(elf: &Path, stream: &OrientationStream, what: &str) -> OrientationCheck {
    let host = stream.host_angles().expect("the host computes the stream");
    let (frames, status) = run(elf, stream, stream.bytes(WINDOW), what);
    let c = OrientationCheck::run(&frames, &host);
    eprintln!("{what}: {}", c.report(TOLERANCE_M));
    assert_eq!(frames.len(), stream.rows.len(), "{what}: {status:?}");
    assert_eq!(
        (
            status.calibrations,
            status.calibration_rejected,
            status.uncalibrated_samples
        ),
        (1, 0, 0),
        "{what}: {status:?}"
    );
    assert_eq!(
        (
            status.samples_completed as usize,
            status.samples_incomplete,
            status.config_rejected
        ),
        (stream.rows.len(), 0, 0),
        "{what}: {status:?}"
    );
    c
}

#[test]
fn synthetic_recording_clean_in_both_modes() {
    let Some(elf) = imu_elf() else { return };
    for mode in [Mode::LeastSquares, Mode::ClosedForm] {
        let stream = synthetic(3.0, mode);
        let what = format!("synthetic 300 samples, {mode:?}");
        let c = clean(&elf, &stream, &what);
        assert!(c.passed(TOLERANCE_M), "{what}: {}", c.report(TOLERANCE_M));
    }
}

/// `stream` through the radio link's damage (`FaultPlan::radio_link`, the fault tests' model)
/// after a clean calibration pose (a damaged one would only move the calibration to the next
/// complete sample): exactly the samples whose packets were all delivered have a frame, the
/// counters account for every packet, and each frame is within [`TOLERANCE_M`] of the host's
/// `f64` computation of the same rows (the host skipping the lost ones as the hub does, so the
/// least squares' warm start is the same).
fn through_a_radio_link(elf: &Path, stream: &OrientationStream, what: &str) {
    let samples = stream.samples();
    let (calibration, rows) = samples.split_first().expect("a calibration pose");
    let d = damage(rows, &FaultPlan::radio_link(11, u32::from(WINDOW)));
    let mut input = vec![0u8];
    for m in stream.config_messages(MissingPolicy::Drop, WINDOW) {
        push_frame(&mut input, &m);
    }
    for p in calibration {
        push_frame(&mut input, &Message::SegmentOrientation(*p));
    }
    input.extend_from_slice(&d.stream);
    let (frames, status) = run(elf, stream, input, what);
    // The samples whose packets were all delivered: exactly those have a frame.
    let intact: Vec<u32> = d.intact_samples().into_iter().collect();
    assert!(
        intact.len() < rows.len(),
        "{what}: the link damaged nothing"
    );
    let mut got: Vec<u32> = frames.iter().map(|p| p.seq).collect();
    got.sort_unstable();
    assert_eq!(got, intact, "{what}: one frame for each intact sample");
    let a = d.accounting();
    assert_eq!(
        (
            status.packets_accepted,
            status.samples_completed,
            status.samples_incomplete,
            status.calibrations,
        ),
        (
            a.delivered + calibration.len() as u32,
            a.complete,
            a.incomplete,
            1
        ),
        "{what}: {a:?}\n{status:?}"
    );
    assert_eq!(
        qgait_emulate::faults::Accounting::decode_errors(&status),
        a.bad_runs,
        "{what}: {status:?}"
    );
    let host = stream
        .host_angles_of(|seq| intact.binary_search(&seq).is_ok())
        .expect("the host computes the stream");
    let c = OrientationCheck::run(&frames, &host);
    eprintln!(
        "{what}: {} of {} samples intact; {}",
        intact.len(),
        rows.len(),
        c.report(TOLERANCE_M)
    );
    assert_eq!(
        c.frames as usize,
        intact.len(),
        "{what}: {}",
        c.report(TOLERANCE_M)
    );
    assert!(c.passed(TOLERANCE_M), "{what}: {}", c.report(TOLERANCE_M));
}

#[test]
fn synthetic_recording_through_a_radio_link() {
    let Some(elf) = imu_elf() else { return };
    let stream = synthetic(4.0, Mode::LeastSquares);
    through_a_radio_link(&elf, &stream, "synthetic 400 samples, radio link");
}

/// The real recording (`../shared/data/imu/`), its first `rows` rows, solved in `mode`; `None`
/// (the reason printed) without the data or the firmware.
fn real(rows: usize, mode: Mode) -> Option<(PathBuf, OrientationStream)> {
    let dir = common::imu_dir()?;
    let elf = imu_elf()?;
    let (stream, _) = OrientationStream::read(
        &dir.join("walking_orientations.sto"),
        &dir.join("placement_orientations.sto"),
        &Settings::opensense_tutorial(),
        mode,
        Some(rows),
    )
    .expect("the recording reads");
    Some((elf, stream))
}

#[test]
fn real_recording_through_a_radio_link() {
    let Some((elf, stream)) = real(500, Mode::LeastSquares) else {
        return;
    };
    through_a_radio_link(
        &elf,
        &stream,
        "OpenSense tutorial recording, first 500 rows, radio link",
    );
}

#[test]
fn real_recording_clean() {
    for mode in [Mode::LeastSquares, Mode::ClosedForm] {
        let Some((elf, stream)) = real(500, mode) else {
            return;
        };
        let what = format!("OpenSense tutorial recording, first 500 rows, {mode:?}");
        let c = clean(&elf, &stream, &what);
        assert_eq!(c.unknown, 0);
        assert!(c.passed(TOLERANCE_M), "{what}: {}", c.report(TOLERANCE_M));
    }
}

/// The command-line path of the README: `qgait packets --orientations` writes the nodes' stream
/// of the real recording, `qgait emulate --stream --verify` runs it through the IMU firmware
/// (a frame for every intact sample but the calibration pose, each within the tolerance of the
/// `f64` kernel on its echoed angles, the hub's counters accounting for every packet, the
/// stream's gait2392 configuration kept to the end), and `qgait verify --orientations` checks
/// the hub's log against the host's own `f64` IMU path.
#[test]
fn cli_packets_emulate_and_verify_an_orientation_stream() {
    let Some((elf, _)) = real(0, Mode::LeastSquares) else {
        return;
    };
    let Some(dir) = common::imu_dir() else { return };
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().unwrap();
    let (walk, pose) = (
        dir.join("walking_orientations.sto"),
        dir.join("placement_orientations.sto"),
    );
    let (stream, log) = (tmp.path().join("imu.bin"), tmp.path().join("hub.bin"));
    let recording = [
        "--orientations",
        walk.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "--base-imu",
        "torso_imu",
        "--rows",
        "300",
    ];
    let o = common::qgait(
        &[
            &["packets"],
            &recording[..],
            &["-o", stream.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = common::qgait(&[
        "emulate",
        "--stream",
        stream.to_str().unwrap(),
        "--elf",
        elf.to_str().unwrap(),
        "--log",
        log.to_str().unwrap(),
        "--verify",
    ]);
    let out = common::stdout(&o);
    assert!(o.status.success(), "{out}\n{}", common::stderr(&o));
    assert!(
        out.contains("stream: 301 samples with every packet intact"),
        "{out}"
    );
    assert!(out.contains("missing samples: 0"), "{out}");
    assert!(out.contains("config_rejected      0"), "{out}");
    assert!(out.contains("samples_completed    300"), "{out}");
    let o = common::qgait(&[&["verify", log.to_str().unwrap()], &recording[..]].concat());
    let out = common::stdout(&o);
    assert!(o.status.success(), "{out}\n{}", common::stderr(&o));
    assert!(
        out.contains("orientations: 300 frames against the host's f64 IMU path"),
        "{out}"
    );
}
