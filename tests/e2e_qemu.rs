//! End to end: the hub firmware under QEMU (mps2-an386), joint-angle streams fed into its UART,
//! every pose frame it sends checked against the f64 kernel, and its `Status` counters checked
//! against what the stream must make it count. Clean streams (the shared normal, crouch1 and
//! crouch4 motions, the built-in gait, a 20,000-sample recording) and the same streams with
//! seeded bit flips, dropped packets, packets reordered inside the reorder window, and bursts
//! of line noise; the reference damage of a radio link (`FaultPlan::radio_link`) on 2,000 and
//! 5,000 samples, through the library and through `qgait emulate --stream`; a node down.
//!
//! Needs `qemu-system-arm` and the release firmware (`QGAIT_FIRMWARE_ELF`, else the default
//! build location); each test is skipped, with the reason printed, when either is missing.
//! `cargo xtask test` builds the firmware first, so there they run.

use qgait_system_tests as common;

use common::firmware_elf;

use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

use qgait_device::log::HubLog;
use qgait_device::log::{LogDecoder, Record};
use qgait_device::packets::{Samples, Timing};
use qgait_device::verify::{Expected, Verification, Verifier};
use qgait_emulate::faults::{damage, Arrivals, Damaged, Fate, FaultPlan, Noise};
use qgait_emulate::qemu::Echo;
use qgait_emulate::session::{self, closing_frames, InputCounts, Limits};
use qgait_model::coords::KneeFlexion;
use qgait_model::motion::source::load_motion;
use qgait_opensim::mot::MotionTable;
use qgait_proto::{
    Config, JointAngle, JointId, Message, MissingPolicy, ModelId, PoseModels, Status,
    VelocityConfig,
};

/// Largest accepted error of a point or distance (metres).
const TOLERANCE_M: f64 = 10e-6;
/// One QEMU at a time: they share 2 cores with everything else.
static QEMU_TURN: Mutex<()> = Mutex::new(());

/// The reorder window the tests configure.
const WINDOW: u8 = 4;

fn config() -> Config {
    Config {
        model: ModelId::Phak,
        anthropometry: None,
        missing_policy: MissingPolicy::Drop,
        reorder_window: WINDOW,
        request_status: false,
    }
}

/// What one run gave back.
struct Run {
    log: HubLog,
    status: Status,
    seconds: f64,
    /// The hub's bytes.
    uart: Vec<u8>,
}

/// Sends `stream` (framed packets) to the hub, after a PHAK configuration and before the
/// closing request.
fn run(elf: &Path, stream: &[u8], what: &str) -> Run {
    run_after(elf, &[], stream, what)
}

/// [`run`] with the messages `before` sent after the PHAK configuration, before the stream.
fn run_after(elf: &Path, before: &[Message], stream: &[u8], what: &str) -> Run {
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let mut input = vec![0u8];
    qgait_emulate::push_frame(&mut input, &Message::Config(config()));
    for m in before {
        qgait_emulate::push_frame(&mut input, m);
    }
    input.extend_from_slice(stream);
    input.extend(closing_frames(&Message::Config(config())).unwrap());
    let expected = InputCounts::of(&input);
    let started = Instant::now();
    let out = session::run(
        elf,
        input,
        expected,
        Echo::Quiet,
        Limits::for_stream(stream.len()),
    )
    .expect("QEMU runs");
    let seconds = started.elapsed().as_secs_f64();
    let status = out.status.unwrap_or_else(|| {
        panic!(
            "{what}: {}; log ends: {:?}",
            out.problem.unwrap_or_default(),
            &out.log[out.log.len().saturating_sub(4)..]
        )
    });
    let log = HubLog::decode(&out.uart);
    assert_eq!(
        log.counts.damaged_total(),
        0,
        "{what}: the hub's own output was damaged: {}",
        log.counts
    );
    eprintln!(
        "{what}: {} bytes in, {} frames out in {seconds:.2} s",
        stream.len(),
        log.poses.len()
    );
    Run {
        log,
        status,
        seconds,
        uart: out.uart,
    }
}

fn samples_of(table: &MotionTable) -> Samples {
    Samples::from_motion(
        table,
        ModelId::Phak,
        KneeFlexion::Negative,
        Timing::TimeColumn,
    )
    .expect("PHAK columns")
    .0
}

fn packets_by_sample(s: &Samples) -> Vec<Vec<JointAngle>> {
    (0..s.len()).map(|r| s.packets(r).collect()).collect()
}

/// A clean stream: every sample gives a frame equal to the f64 kernel's, none is missing, and
/// the status counts exactly the packets and samples sent.
fn clean(elf: &Path, samples: &Samples, what: &str) -> f64 {
    let stream = damage(
        &packets_by_sample(samples),
        &FaultPlan::none(u32::from(WINDOW)),
    )
    .stream;
    let r = run(elf, &stream, what);
    let v = Verification::run(
        &PoseModels::defaults(),
        &r.log.poses,
        Expected::Range {
            first: 0,
            count: samples.len() as u32,
        },
    );
    assert!(v.passed(TOLERANCE_M), "{what}:\n{}", v.report(TOLERANCE_M));
    assert_eq!(
        v.frames,
        samples.len() as u64,
        "{what}: one frame per sample"
    );
    let n = samples.len() as u32;
    let s = &r.status;
    assert_eq!(
        (
            s.packets_accepted,
            s.samples_completed,
            s.samples_incomplete
        ),
        (8 * n, n, 0),
        "{what}: {s:?}"
    );
    let errors = s.crc_errors
        + s.framing_errors
        + s.oversize_frames
        + s.unknown_version
        + s.unknown_joint
        + s.malformed;
    assert_eq!(
        (errors, s.late_packets, s.duplicate_packets, s.uart_overruns),
        (0, 0, 0, 0),
        "{what}: {s:?}"
    );
    eprintln!("{what}: largest error {:.3} µm", v.max_error() * 1e6);
    r.seconds
}

/// A damaged stream: every sample whose packets all arrived intact has a correct frame, no
/// other sample has one, and the status accounts for every packet the link dropped or
/// damaged ([`faults`](qgait_emulate::faults) says what that means): its decode
/// counters equal the protocol decoder's on the damaged stream, and its accepted packets,
/// decode errors and complete and incomplete samples equal what the link's ledger predicts.
fn damaged(elf: &Path, samples: &Samples, plan: FaultPlan, what: &str) {
    let d = damage(&packets_by_sample(samples), &plan);
    let stream = &d.stream;
    // As the hub reads it: the closing request starts with a 0x00.
    let arrivals = Arrivals::of(&[stream.as_slice(), &[0]].concat());
    let r = run(elf, stream, what);
    let intact: Vec<u32> = (0..samples.len() as u32)
        .filter(|&s| arrivals.intact(s, ModelId::Phak))
        .collect();
    let partial = arrivals.partial(ModelId::Phak);
    assert!(
        intact.len() < samples.len() && !partial.is_empty(),
        "{what}: the plan damaged nothing"
    );
    // Frames come in completion order (a reordered sample may complete after a later one).
    let mut got: Vec<u32> = r.log.poses.iter().map(|p| p.seq).collect();
    got.sort_unstable();
    assert_eq!(
        got, intact,
        "{what}: one frame for each intact sample, none for the others"
    );
    let v = Verification::run(&PoseModels::defaults(), &r.log.poses, Expected::FirstToLast);
    assert!(
        v.max_error() <= TOLERANCE_M,
        "{what}:\n{}",
        v.report(TOLERANCE_M)
    );
    // Every frame echoes the angles that were sent for its sample.
    for p in &r.log.poses {
        let sent: Vec<f32> = samples.packets(p.seq as usize).map(|a| a.angle).collect();
        assert_eq!(
            p.angles.as_slice(),
            sent.as_slice(),
            "{what}: seq {}",
            p.seq
        );
    }
    let (s, e) = (&r.status, &arrivals.status);
    let counters = |s: &Status| {
        [
            s.packets_accepted,
            s.crc_errors,
            s.framing_errors,
            s.oversize_frames,
            s.unknown_version,
            s.unknown_joint,
            s.malformed,
        ]
    };
    assert_eq!(counters(s), counters(e), "{what}: decode counters (accepted, crc, framing, oversize, version, joint, malformed)\n{s:?}");
    assert_eq!(s.samples_completed as usize, intact.len(), "{what}: {s:?}");
    assert_eq!(
        s.samples_incomplete as usize,
        partial.len(),
        "{what}: {s:?}"
    );
    assert_eq!((s.late_packets, s.uart_overruns), (0, 0), "{what}: {s:?}");
    let accounting = d.accounting();
    assert_eq!(
        accounting.mismatches(s),
        Vec::<String>::new(),
        "{what}: {accounting:?}\n{s:?}"
    );
    eprintln!(
        "{what}: {} samples, {} intact, {} incomplete counted, {} damaged frames counted, largest error {:.3} µm",
        samples.len(),
        intact.len(),
        s.samples_incomplete,
        e.crc_errors + e.framing_errors + e.oversize_frames + e.malformed + e.unknown_version + e.unknown_joint,
        v.max_error() * 1e6
    );
}

fn plan(seed: u64) -> FaultPlan {
    FaultPlan {
        seed,
        flip: 0.02,
        drop: 0.02,
        swap: 0.0,
        reorder: 0.5,
        window: u32::from(WINDOW),
        garbage: 0.01,
        noise: Noise::Any,
        silent: None,
    }
}

fn builtin(spec: &str) -> Samples {
    samples_of(&load_motion(spec).expect("builtin").0)
}

#[test]
fn builtin_gait_clean_and_damaged() {
    let Some(elf) = firmware_elf() else { return };
    let s = builtin("builtin:normal");
    clean(&elf, &s, "builtin:normal");
    damaged(
        &elf,
        &builtin("builtin:normal,rows=400"),
        plan(1),
        "builtin:normal,rows=400 damaged (seed 1)",
    );
}

/// Velocities on (10 ms, the built-in gait's 100 Hz), with the firmware built with them: every
/// pose frame but the first is
/// followed by its points' velocities, each within 1 mm/s of the host's f64 recomputation from
/// the echoed angles (the same backward difference, protocol.md 4.11), and every pose frame
/// still within 10 µm.
#[test]
fn builtin_gait_with_velocities() {
    // The firmware with the points' velocities (its feature `velocity`, not the default build).
    let Some(elf) = common::feature_firmware_elf("velocity", "QGAIT_VELOCITY_FIRMWARE_ELF") else {
        return;
    };
    let samples = builtin("builtin:normal");
    let stream = damage(
        &packets_by_sample(&samples),
        &FaultPlan::none(u32::from(WINDOW)),
    )
    .stream;
    let on = Message::VelocityConfig(VelocityConfig {
        enabled: true,
        period_us: 10_000,
        request_status: false,
    });
    let what = "builtin:normal with velocities";
    let r = run_after(&elf, std::slice::from_ref(&on), &stream, what);
    let models = PoseModels::defaults();
    let mut verifier = Verifier::new(&models, Expected::FirstToLast);
    LogDecoder::new().feed(&r.uart, |record| {
        if let Record::Message { message, .. } = record {
            verifier.add_message(&message);
        }
    });
    let v = verifier.finish();
    let report = v.report(TOLERANCE_M);
    let n = samples.len() as u64;
    assert!(v.passed(TOLERANCE_M), "{what}:\n{report}");
    assert_eq!((v.frames, v.missing), (n, 0), "{what}:\n{report}");
    assert_eq!(
        (v.velocity_frames, v.velocity_absent, v.velocity_unmatched),
        (n - 1, 0, 0),
        "{what}: velocities after every frame but the first\n{report}"
    );
    // The frames sent: the poses, their velocities, and the closing status.
    assert_eq!(r.status.frames_sent as u64, 2 * n - 1 + 1, "{:?}", r.status);
    eprintln!(
        "{what}: {} velocity frames, largest error {:.6} mm/s (tolerance 1 mm/s)",
        v.velocity_frames,
        v.velocity_max_error() * 1e3
    );
    // `qgait emulate --verify` checks them too: the same stream, the velocities turned on in it.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("velocities.bin");
    let mut with_on = Vec::new();
    qgait_emulate::push_frame(&mut with_on, &on);
    with_on.extend_from_slice(&stream);
    std::fs::write(&path, &with_on).unwrap();
    let emulate = |tol_mm_s: &str| {
        let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
        let (path, elf) = (path.to_str().unwrap(), elf.to_str().unwrap());
        let args = ["-q", "emulate", "--stream", path, "--verify", "--elf", elf];
        common::qgait(&[&args[..], &["--tol-mm-s", tol_mm_s]].concat())
    };
    let o = emulate("1");
    let (out, err) = (common::stdout(&o), common::stderr(&o));
    assert!(o.status.success(), "{out}{err}");
    assert!(
        out.contains(&format!("{} velocity frames checked", n - 1)) && out.contains("verify: ok"),
        "{out}"
    );
    // A tolerance no f32 velocity meets: the same run fails the check.
    let o = emulate("0");
    let out = common::stdout(&o);
    assert!(
        !o.status.success() && out.contains("tolerance 0 mm/s"),
        "{out}"
    );
}

#[test]
fn shared_motions_clean_and_damaged() {
    let Some(elf) = firmware_elf() else { return };
    let Some(shared) = common::shared_dir() else {
        return;
    };
    for (i, name) in ["normal", "crouch1", "crouch4"].into_iter().enumerate() {
        let path = shared.join(format!("data/opensim/{name}.mot"));
        let (table, _) = MotionTable::read(&path).expect("shared motion");
        let s = samples_of(&table);
        clean(&elf, &s, name);
        damaged(
            &elf,
            &s,
            plan(10 + i as u64),
            &format!("{name} damaged (seed {})", 10 + i),
        );
    }
}

/// A long recording: the built-in gait cycle repeated, 100 Hz timestamps (so sequence numbers
/// and timestamps need their longer varints).
fn recording(samples: usize) -> Samples {
    let cycle = builtin("builtin:normal");
    let rows = cycle.len() - 1; // the last row repeats the first
    Samples {
        model: ModelId::Phak,
        timestamps_us: (0..samples)
            .map(|i| (i as u32).wrapping_mul(10_000))
            .collect(),
        angles: (0..samples)
            .map(|i| cycle.angles[i % rows].clone())
            .collect(),
    }
}

/// The longest clean run of `cargo test`: 20,000 samples (200 s of a 100 Hz recording, 3.6 MB
/// through the UART, its receive ring wrapped many times), every frame correct, no counter off,
/// no overrun; under a minute on an idle 2-core machine.
#[test]
fn recording_of_20000_samples() {
    let Some(elf) = firmware_elf() else { return };
    let seconds = clean(&elf, &recording(20_000), "20,000-sample recording");
    eprintln!("20,000 samples: {seconds:.1} s");
}

/// The same over 100,000 samples (18 MB in, 15 MB out; several minutes under QEMU's one-byte
/// UART, so not in `cargo xtask test`): run it on purpose with
/// `cargo test -p qgait-system-tests --test e2e_qemu recording_of_100000 -- --ignored`.
#[test]
#[ignore = "several minutes under QEMU: cargo test -p qgait-system-tests --test e2e_qemu -- --ignored"]
fn recording_of_100000_samples() {
    let Some(elf) = firmware_elf() else { return };
    let seconds = clean(&elf, &recording(100_000), "100,000-sample recording");
    eprintln!("100,000 samples: {seconds:.1} s");
}

/// The reference damage of a radio link ([`FaultPlan::radio_link`]) on 2,000 samples of the
/// built-in gait and on a 5,000-sample recording: the hub consumes a damaged stream at its own
/// pace (a run that paced itself on the frames answered stalled on every damaged sample and
/// ran out of time), and accounts for every packet lost.
#[test]
fn radio_link_damage_on_2000_and_5000_samples() {
    let Some(elf) = firmware_elf() else { return };
    let window = u32::from(WINDOW);
    damaged(
        &elf,
        &builtin("builtin:normal,rows=2000"),
        FaultPlan::radio_link(21, window),
        "builtin:normal,rows=2000, radio link (seed 21)",
    );
    damaged(
        &elf,
        &recording(5000),
        FaultPlan::radio_link(22, window),
        "5,000-sample recording, radio link (seed 22)",
    );
}

/// One node down for 2,000 samples: the hub answers no sample with a frame, yet consumes the
/// stream at its own pace (a run that paced itself on the frames answered crawled through it
/// 480 bytes per quarter second and ran out of time) and counts every sample incomplete.
#[test]
fn a_node_down_for_2000_samples() {
    let Some(elf) = firmware_elf() else { return };
    damaged(
        &elf,
        &builtin("builtin:normal,rows=2000"),
        FaultPlan {
            silent: Some(JointId::AnkleAngleL),
            ..FaultPlan::none(u32::from(WINDOW))
        },
        "builtin:normal,rows=2000, ankle_angle_l node down",
    );
}

/// The value of `name` in the `device status:` lines of `qgait emulate`.
fn status_value(out: &str, name: &str) -> u32 {
    out.lines()
        .find_map(|l| l.trim().strip_prefix(name)?.trim().parse().ok())
        .unwrap_or_else(|| panic!("no {name} in\n{out}"))
}

/// `qgait emulate --stream` on 2,000 samples damaged as by a radio link, ending with a burst of
/// noise: it ends normally, writes a correct frame for exactly the samples whose packets all
/// arrived intact (`--verify`), and its status accounts for every damaged packet.
#[test]
fn emulate_command_on_a_radio_damaged_stream_of_2000_samples() {
    let Some(elf) = firmware_elf() else { return };
    let samples = builtin("builtin:normal,rows=2000");
    let mut d: Damaged = damage(
        &packets_by_sample(&samples),
        &FaultPlan::radio_link(5, u32::from(WINDOW)),
    );
    // Noise at the very end, with no delimiter after it.
    d.stream.extend((1..=40u8).map(|i| i.wrapping_mul(37) | 1));
    let accounting = d.accounting();
    let complete: Vec<u32> = (0..samples.len() as u32)
        .filter(|&seq| {
            d.packets
                .iter()
                .filter(|(p, _)| p.seq == seq)
                .all(|(_, f)| *f == Fate::Delivered)
        })
        .collect();
    assert_eq!(complete.len() as u32, accounting.complete);
    assert!(accounting.incomplete > 500, "{accounting:?}");

    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let (bad, csv) = (dir.path().join("bad.bin"), dir.path().join("f.csv"));
    std::fs::write(&bad, &d.stream).unwrap();
    let o = common::qgait(&[
        "-q",
        "emulate",
        "--stream",
        bad.to_str().unwrap(),
        "--frames-csv",
        csv.to_str().unwrap(),
        "--verify",
        "--elf",
        elf.to_str().unwrap(),
    ]);
    let (out, err) = (common::stdout(&o), common::stderr(&o));
    assert!(o.status.success(), "{out}{err}");
    assert!(out.contains("verify: ok"), "{out}");
    assert!(
        out.contains(&format!(
            "input accounted for: {} packets accepted, {} damaged frames counted",
            accounting.delivered, accounting.bad_runs
        )),
        "{out}"
    );
    let counted = [
        "crc_errors",
        "framing_errors",
        "oversize_frames",
        "unknown_version",
        "unknown_joint",
        "malformed",
    ]
    .map(|n| status_value(&out, n))
    .iter()
    .sum::<u32>();
    assert_eq!(
        [
            status_value(&out, "packets_accepted"),
            counted,
            status_value(&out, "samples_completed"),
            status_value(&out, "samples_incomplete"),
            status_value(&out, "late_packets"),
            status_value(&out, "duplicate_packets"),
            status_value(&out, "uart_overruns"),
        ],
        [
            accounting.delivered,
            accounting.bad_runs,
            accounting.complete,
            accounting.incomplete,
            0,
            0,
            0
        ],
        "{accounting:?}\n{out}"
    );
    let table =
        qgait_device::frames_csv::parse(&std::fs::read_to_string(&csv).unwrap(), "f.csv").unwrap();
    let mut seqs = table.seq.clone();
    seqs.sort_unstable();
    assert_eq!(seqs, complete, "a frame for exactly the intact samples");
}

#[test]
fn emulate_command_verifies_and_writes_the_frames_csv() {
    let Some(elf) = firmware_elf() else { return };
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("frames.csv");
    let o = common::qgait(&[
        "emulate",
        "builtin:crouch=0.5,rows=20",
        "--verify",
        "--elf",
        elf.to_str().unwrap(),
        "--frames-csv",
        csv.to_str().unwrap(),
    ]);
    let (out, err) = (common::stdout(&o), common::stderr(&o));
    assert!(o.status.success(), "{out}{err}");
    assert!(
        out.contains("samples_completed    20") && out.contains("verify: ok"),
        "{out}"
    );
    assert!(
        err.contains("device: INFO  qgait hub on mps2-an386"),
        "{err}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let table = qgait_device::frames_csv::parse(&text, "frames.csv").unwrap();
    assert_eq!(table.seq, (0..20).collect::<Vec<u32>>());
    assert_eq!(
        table.time[1],
        Some(0.052632),
        "20 rows over 1 s, in whole µs"
    );
}

/// A hub's log decoded is a recording `gait` reads: the firmware's frames carry their samples'
/// times (the nodes' `timestamp_us`), so `decode` writes each frame's time with no `--rate`,
/// the motion's own time, and `gait` finds the events of the cycle in it.
#[test]
fn a_decoded_hub_log_is_a_recording_gait_reads() {
    let Some(elf) = firmware_elf() else { return };
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hub.bin");
    let o = common::qgait(&[
        "-q",
        "emulate",
        "builtin:normal",
        "--model",
        "phak",
        "--elf",
        elf.to_str().unwrap(),
        "--log",
        log.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let o = common::qgait(&["-q", "decode", log.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let text = common::stdout(&o);
    let table = qgait_device::frames_csv::parse(&text, "frames.csv").unwrap();
    assert_eq!(table.seq, (0..101).collect::<Vec<u32>>());
    // 101 rows over 1 s: 10 ms apart (whole µs, printed as seconds).
    for (seq, time) in table.seq.iter().zip(&table.time) {
        let time = time.unwrap_or(f64::NAN);
        assert!(
            (time - f64::from(*seq) * 0.01).abs() < 1e-9,
            "seq {seq}: {time}"
        );
    }
    let csv = dir.path().join("frames.csv");
    std::fs::write(&csv, text).unwrap();
    let out = dir.path().join("gait");
    let o = common::qgait(&[
        "-q",
        "gait",
        csv.to_str().unwrap(),
        "--cycle",
        "whole",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let events = std::fs::read_to_string(out.join("events.csv")).unwrap();
    for event in [
        "right,heel_strike",
        "right,toe_off",
        "left,heel_strike",
        "left,toe_off",
    ] {
        assert!(events.contains(event), "{event} in {events}");
    }
}

/// A motion holding an angle the hub does not use (finite, but beyond `JointAngle::MAX_ANGLE`):
/// the hub drops that sample and `emulate --verify` expects no frame for it; every other frame
/// is a rigid pose within tolerance.
#[test]
fn emulate_command_expects_no_frame_for_an_angle_the_hub_does_not_use() {
    let Some(elf) = firmware_elf() else { return };
    let _turn = QEMU_TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let mot = dir.path().join("huge.mot");
    let mut text = String::from("huge\nversion=1\nnRows=6\nnColumns=7\ninDegrees=yes\nendheader\ntime\thip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l\n");
    for i in 0..6 {
        let hip = if i == 3 { "1e10" } else { "20" };
        text.push_str(&format!(
            "{}\t{hip}\t-30\t5\t-10\t-20\t0\n",
            f64::from(i) * 0.01
        ));
    }
    std::fs::write(&mot, text).unwrap();
    let o = common::qgait(&[
        "emulate",
        mot.to_str().unwrap(),
        "--model",
        "hak",
        "--verify",
        "--elf",
        elf.to_str().unwrap(),
    ]);
    let (out, err) = (common::stdout(&o), common::stderr(&o));
    assert!(o.status.success(), "{out}{err}");
    assert!(out.contains("out_of_range         1"), "{out}");
    assert!(out.contains("no frame due: 1 (3)"), "{out}");
    assert!(
        out.contains("5 frames (5 hak)") && out.contains("verify: ok"),
        "{out}"
    );
}
