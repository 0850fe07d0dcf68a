//! The end-to-end UART session with the application firmware under QEMU. The built-in normal
//! gait (200 PHAK samples, from `qgait packets`) goes in through UART0 with the packets of
//! consecutive samples interleaved and faults injected (a sample missing a joint, line noise, a
//! corrupted frame, a duplicate and a late packet), then every kind of model switch (`qgait
//! config`: the generic gait2392, HAK with a subject's lengths, a subject's gait2392 uploaded
//! in parts), so that the stack peak the firmware logs covers them.
//!
//! `qgait emulate --stream ... --verify` runs it (the flow-controlled session of
//! `qgait-emulate`, which ends with a status request): it checks every pose frame against the
//! `f64` kernel and that the hub's counters account for every frame of the input. This module
//! checks, from the hub's UART output and status, that each injected fault was counted exactly
//! once and that every frame echoes the angles sent, and reads the stack peak from the
//! firmware's log.

use anyhow::anyhow;
use std::path::{Path, PathBuf};
use std::process::Command;

use qgait_emulate::faults::samples_of_stream;
use qgait_emulate::push_frame;
use qgait_proto::{FrameDecoder, JointAngle, JointId, Message, ModelId};

use crate::cargo::qgait_binary;
use crate::{repo_root, TempDir};

/// Samples sent.
const SAMPLES: u32 = 200;
/// Sample sent without its ankle_angle_l packet (dropped by the default policy).
const INCOMPLETE_SEQ: u32 = 50;
/// Sample whose hip_flexion_r packet is sent twice.
const DUPLICATE_SEQ: u32 = 120;
/// Sample whose knee_angle_r packet is sent again long after its window closed.
const LATE_SEQ: u32 = 10;
/// Largest accepted distance between a firmware point (f32) and the host's f64 value (µm).
const TOLERANCE_UM: &str = "5";
/// The model switches, as `qgait config --model` arguments (relative to the repository root).
const SWITCHES: [&[&str]; 3] = [
    &["gait2392"],
    &["hak", "--anthropometry", "xtask/data/hak.toml"],
    &["xtask/data/subject.toml"],
];

/// The outcome of a session.
pub struct Report {
    /// Everything that did not match.
    pub failures: Vec<String>,
    /// Deepest stack use the firmware logged (bytes).
    pub stack_peak: Option<u32>,
}

impl Report {
    /// Whether every check held.
    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }
}

/// The bytes to send and what the hub must count for them.
struct Plan {
    bytes: Vec<u8>,
    packets_accepted: u32,
    decode_errors: u32,
}

/// The packet of `joint` in `sample`.
fn packet(sample: &[JointAngle], joint: JointId) -> Message {
    let p = sample.iter().find(|p| p.joint == joint);
    Message::JointAngle(*p.expect("every PHAK sample has every PHAK joint"))
}

/// The session's input: `samples` (PHAK, one `Vec` per sample) with the faults, then
/// `switches` (configuration frames).
fn plan(samples: &[Vec<JointAngle>], switches: &[u8]) -> Plan {
    let mut bytes = vec![0u8];
    let mut packets = 0;
    // Samples go in pairs, their packets interleaved, so every sample is reordered.
    for pair in (0..SAMPLES).step_by(2) {
        for &joint in ModelId::Phak.required_joints() {
            for seq in [pair + 1, pair] {
                if !(seq == INCOMPLETE_SEQ && joint == JointId::AnkleAngleL) {
                    push_frame(&mut bytes, &packet(&samples[seq as usize], joint));
                    packets += 1;
                }
            }
        }
        match pair {
            80 => {
                // Line noise: non-zero garbage closed by a delimiter is one bad frame.
                bytes.extend((1..=40u8).map(|i| i.wrapping_mul(37) | 1));
                bytes.push(0);
            }
            100 => {
                // A frame with one corrupted byte (kept non-zero): one CRC or framing error.
                let mut frame = Vec::new();
                push_frame(
                    &mut frame,
                    &packet(&samples[pair as usize], JointId::HipFlexionR),
                );
                let i = frame.len() / 2;
                frame[i] ^= if frame[i] == 0x01 { 0x02 } else { 0x01 };
                bytes.extend_from_slice(&frame);
            }
            p if p == DUPLICATE_SEQ => {
                let sample = &samples[DUPLICATE_SEQ as usize];
                push_frame(&mut bytes, &packet(sample, JointId::HipFlexionR));
                packets += 1;
            }
            150 => {
                let sample = &samples[LATE_SEQ as usize];
                push_frame(&mut bytes, &packet(sample, JointId::KneeAngleR));
                packets += 1;
            }
            _ => {}
        }
    }
    bytes.extend_from_slice(switches);
    Plan {
        bytes,
        packets_accepted: packets,
        decode_errors: 2,
    }
}

/// Runs `qgait ARGS` in the repository root; its stdout and stderr.
fn qgait(exe: &Path, args: &[&str]) -> anyhow::Result<(String, String)> {
    let out = Command::new(exe)
        .args(args)
        .current_dir(repo_root())
        .output()
        .map_err(|e| anyhow!("starting {}: {e}", exe.display()))?;
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    // `emulate` fails when a check fails: that is reported with the session's own checks.
    if !out.status.success() && args[0] != "emulate" {
        return Err(anyhow!("qgait {} failed: {stderr}", args.join(" ")));
    }
    Ok((stdout, stderr))
}

/// The value of counter `name` in the `device status:` lines of `qgait emulate`.
fn counter(out: &str, name: &str) -> Option<u32> {
    out.lines()
        .find_map(|l| l.trim().strip_prefix(name)?.trim().parse().ok())
}

/// What came back from the firmware, decoded from its UART output.
#[derive(Default)]
struct Received {
    poses: u32,
    wrong_angles: u32,
    undecodable: u32,
    seen: Vec<u32>,
}

/// Decodes `uart`; each frame's angles are compared with those of `samples`.
fn receive(uart: &[u8], samples: &[Vec<JointAngle>]) -> Received {
    let mut r = Received::default();
    for result in FrameDecoder::new().feed(uart) {
        match result {
            Ok(Message::PoseFrame(frame)) => {
                r.poses += 1;
                r.seen.push(frame.seq);
                let sent: Option<Vec<f32>> = samples.get(frame.seq as usize).map(|s| {
                    ModelId::Phak
                        .required_joints()
                        .iter()
                        .filter_map(|&j| s.iter().find(|p| p.joint == j))
                        .map(|p| p.angle)
                        .collect()
                });
                r.wrong_angles += u32::from(sent.as_deref() != Some(frame.angles.as_slice()));
            }
            Ok(_) => {}
            Err(_) => r.undecodable += 1,
        }
    }
    r
}

/// Everything in the run that does not match the plan: `stdout` is `qgait emulate`'s.
fn evaluate(r: &Received, stdout: &str, plan: &Plan) -> Vec<String> {
    let mut failures = Vec::new();
    let mut check = |ok: bool, what: String| {
        if !ok {
            failures.push(what);
        }
    };
    let expected_poses = SAMPLES - 1;
    check(
        r.poses == expected_poses,
        format!("{} pose frames, expected {expected_poses}", r.poses),
    );
    check(
        !r.seen.contains(&INCOMPLETE_SEQ),
        format!("sample {INCOMPLETE_SEQ} lacked a joint but got a pose"),
    );
    check(
        stdout.contains("verify: ok"),
        format!("the frames do not verify against the f64 kernel within {TOLERANCE_UM} µm"),
    );
    check(
        r.wrong_angles == 0,
        format!(
            "{} frames echo other angles than those sent",
            r.wrong_angles
        ),
    );
    check(
        r.undecodable == 0,
        format!("{} frames from the firmware did not decode", r.undecodable),
    );
    if counter(stdout, "packets_accepted").is_none() {
        check(false, "no Status frame answered the request".into());
        return failures;
    }
    let decode_errors = [
        "crc_errors",
        "framing_errors",
        "oversize_frames",
        "malformed",
        "unknown_version",
        "unknown_joint",
    ]
    .iter()
    .filter_map(|n| counter(stdout, n))
    .sum::<u32>();
    let counters = [
        ("packets_accepted", plan.packets_accepted),
        ("samples_completed", expected_poses),
        ("samples_incomplete", 1),
        ("duplicate_packets", 1),
        ("late_packets", 1),
        ("uart_overruns", 0),
        // All the model switches were accepted.
        ("config_rejected", 0),
    ];
    for (name, want) in counters {
        match counter(stdout, name) {
            Some(got) => check(got == want, format!("{name} {got} != {want}")),
            None => check(false, format!("no {name} in the status")),
        }
    }
    check(
        decode_errors == plan.decode_errors,
        format!("decode errors {decode_errors} != {}", plan.decode_errors),
    );
    failures
}

/// The packets of `qgait packets builtin:normal,rows=200` and the frames of the model
/// switches, written in `dir`.
fn inputs(exe: &Path, dir: &Path) -> anyhow::Result<(Vec<Vec<JointAngle>>, Vec<u8>)> {
    let path = |name: &str| dir.join(name).to_string_lossy().into_owned();
    let clean = path("packets.bin");
    let motion = format!("builtin:normal,rows={SAMPLES}");
    qgait(exe, &["-q", "packets", &motion, "-o", &clean])?;
    let bytes = std::fs::read(&clean).map_err(|e| anyhow!("{clean}: {e}"))?;
    let samples = samples_of_stream(&bytes).map_err(|e| anyhow!("{clean}: {e}"))?;
    let mut switches = Vec::new();
    for (i, model) in SWITCHES.iter().enumerate() {
        let out = path(&format!("switch{i}.bin"));
        let mut args = vec!["-q", "config", "--model"];
        args.extend_from_slice(model);
        args.extend(["--window", "4", "--policy", "drop", "--no-status-request"]);
        args.extend(["-o", &out]);
        qgait(exe, &args)?;
        switches.extend(std::fs::read(&out).map_err(|e| anyhow!("{out}: {e}"))?);
    }
    Ok((samples, switches))
}

/// Runs the session against `elf` and prints its report.
pub fn run(elf: &Path) -> anyhow::Result<Report> {
    let exe = qgait_binary()?;
    let dir = TempDir::new("qgait-uart-session")?;
    let (samples, switches) = inputs(&exe, &dir.0)?;
    let plan = plan(&samples, &switches);
    let at = |name: &str| -> PathBuf { dir.0.join(name) };
    let (input, uart) = (at("session.bin"), at("uart.bin"));
    std::fs::write(&input, &plan.bytes).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    let elf = elf
        .canonicalize()
        .map_err(|e| anyhow!("{}: {e}", elf.display()))?;
    let s = |p: &Path| p.to_string_lossy().into_owned();
    let (stdout, stderr) = qgait(
        &exe,
        &[
            "emulate",
            "--stream",
            &s(&input),
            "--elf",
            &s(&elf),
            "--verify",
            "--tol-um",
            TOLERANCE_UM,
            "--log",
            &s(&uart),
        ],
    )?;
    eprint!("{stderr}");
    print!("{stdout}");
    let received = match std::fs::read(&uart) {
        Ok(bytes) => receive(&bytes, &samples),
        Err(e) => return Err(anyhow!("qgait emulate wrote no UART log ({e}): {stderr}")),
    };
    let stack_peak = stack_peak(&stderr);
    let largest_um = stdout.lines().find_map(|l| {
        l.strip_prefix("largest error ")?
            .split(' ')
            .next()?
            .parse::<f64>()
            .ok()
    });
    let failures = evaluate(&received, &stdout, &plan);
    println!(
        "uart session: {SAMPLES} samples ({} bytes) in, {} poses out, largest |f32 - f64| {} m, stack peak {} bytes",
        plan.bytes.len(),
        received.poses,
        largest_um.map_or("?".to_string(), |e| format!("{:.2e}", e * 1e-6)),
        stack_peak.map_or("?".to_string(), |p: u32| p.to_string())
    );
    for f in &failures {
        println!("uart session FAILED: {f}");
    }
    println!(
        "uart session: {}",
        if failures.is_empty() {
            "passed"
        } else {
            "failed"
        }
    );
    Ok(Report {
        failures,
        stack_peak,
    })
}

/// The largest "stack peak N" the firmware logged in `log`.
pub fn stack_peak(log: &str) -> Option<u32> {
    log.lines()
        .filter_map(|l| {
            l.split("stack peak ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()
        })
        .max()
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_emulate::packet;
    use qgait_proto::PoseFrame;

    fn samples() -> Vec<Vec<JointAngle>> {
        (0..SAMPLES)
            .map(|seq| {
                let angle = |j: JointId| 0.01 * seq as f32 + 0.001 * f32::from(j.index());
                ModelId::Phak
                    .required_joints()
                    .iter()
                    .map(|&j| packet(seq, seq * 5000, j, angle(j)))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_plan_holds_each_fault_once_and_counts_what_the_hub_must() {
        let s = samples();
        let plan = plan(&s, &[]);
        let mut accepted = 0;
        let mut errors = 0;
        let mut per_sample = vec![0u32; SAMPLES as usize];
        for r in FrameDecoder::new().feed(&plan.bytes) {
            match r {
                Ok(Message::JointAngle(p)) => {
                    accepted += 1;
                    per_sample[p.seq as usize] += 1;
                }
                Ok(m) => panic!("{m:?}"),
                Err(_) => errors += 1,
            }
        }
        assert_eq!(
            (accepted, errors),
            (plan.packets_accepted, plan.decode_errors)
        );
        // 8 packets a sample, one fewer for the incomplete one, one more for the duplicate
        // and the late one.
        for (seq, n) in per_sample.iter().enumerate() {
            let want = match seq as u32 {
                INCOMPLETE_SEQ => 7,
                DUPLICATE_SEQ | LATE_SEQ => 9,
                _ => 8,
            };
            assert_eq!(*n, want, "seq {seq}");
        }
    }

    #[test]
    fn echoed_angles_are_compared_with_those_sent() {
        let s = samples();
        let frame = |seq: u32, angles: Vec<f32>| PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: ModelId::Phak,
            angles: heapless::Vec::from_slice(&angles).unwrap(),
            points: [[0.0; 3]; qgait_proto::point::COUNT],
            distances: [0.0; 3],
            flags: 0,
        };
        let sent: Vec<f32> = s[3].iter().map(|p| p.angle).collect();
        let mut wrong = sent.clone();
        wrong[7] += 1e-3;
        let mut uart = Vec::new();
        push_frame(&mut uart, &Message::PoseFrame(frame(3, sent)));
        push_frame(&mut uart, &Message::PoseFrame(frame(3, wrong)));
        uart.extend([7, 7, 0]);
        let r = receive(&uart, &s);
        assert_eq!((r.poses, r.wrong_angles, r.undecodable), (2, 1, 1));
    }

    #[test]
    fn counters_are_read_from_the_status_lines() {
        let out = "device status:\n  packets_accepted     1601\n  late_packets         1\n";
        assert_eq!(counter(out, "packets_accepted"), Some(1601));
        assert_eq!(counter(out, "late_packets"), Some(1));
        assert_eq!(counter(out, "crc_errors"), None);
    }
}
