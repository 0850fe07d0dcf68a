//! The end-to-end UART session with the application firmware under QEMU: a stream of PHAK
//! joint-angle packets (interleaved across samples, with injected faults) goes in through
//! UART0, the pose frames that come back are checked against the kernel in f64 on the host,
//! and a requested `Status` must count every injected fault exactly. The session ends with
//! model switches (gait2392, HAK, a subject's gait2392 uploaded in parts, back to PHAK), so
//! that the stack peak the firmware logs covers them.

use std::io::{Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::Path;
use std::thread;
use std::time::{Duration, Instant};

use qgait::device::config::{self, HubModel, HubSettings};
use qgait_kernel::metrics::distances;
use qgait_kernel::{Anthropometry, Gait2392Geometry, Limb, Phak, PhakAngles};
use qgait_proto::{
    encode_frame, Config, FrameDecoder, JointAngle, JointId, Message, MissingPolicy, ModelId,
    PoseFrame, Status, MAX_FRAME_LEN, PROTOCOL_VERSION,
};

use crate::gait;
use crate::qemu::Qemu;

/// Samples sent.
const SAMPLES: u32 = 200;
/// Sample sent without its ankle_angle_l packet (dropped by the default policy).
const INCOMPLETE_SEQ: u32 = 50;
/// Sample whose hip_flexion_r packet is sent twice.
const DUPLICATE_SEQ: u32 = 120;
/// Sample whose knee_angle_r packet is sent again long after its window closed.
const LATE_SEQ: u32 = 10;
/// Largest accepted distance between a firmware point (f32) and the host's f64 value (m).
const TOLERANCE_M: f64 = 5e-6;
/// Longest the whole session may take.
const DEADLINE: Duration = Duration::from_secs(60);

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

/// The bytes to send and the counters they must produce.
struct Plan {
    bytes: Vec<u8>,
    packets_accepted: u32,
    decode_errors: u32,
}

fn push_frame(bytes: &mut Vec<u8>, message: &Message) {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let frame = encode_frame(message, &mut buf).expect("every message fits MAX_FRAME_LEN");
    bytes.extend_from_slice(frame);
}

fn packet(seq: u32, joint: JointId) -> Message {
    Message::JointAngle(JointAngle {
        version: PROTOCOL_VERSION,
        node: joint.index(),
        joint,
        seq,
        timestamp_us: seq * 10_000,
        angle: gait::angle(joint, seq),
        quality: 0,
    })
}

fn plan() -> Plan {
    let joints = ModelId::Phak.required_joints();
    let mut bytes = Vec::new();
    let mut packets = 0;
    // Samples go in pairs, their packets interleaved, so every sample is reordered.
    for pair in (0..SAMPLES).step_by(2) {
        for &joint in joints {
            for seq in [pair + 1, pair] {
                if !(seq == INCOMPLETE_SEQ && joint == JointId::AnkleAngleL) {
                    push_frame(&mut bytes, &packet(seq, joint));
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
                push_frame(&mut frame, &packet(pair, JointId::HipFlexionR));
                let i = frame.len() / 2;
                frame[i] ^= if frame[i] == 0x01 { 0x02 } else { 0x01 };
                bytes.extend_from_slice(&frame);
            }
            p if p == DUPLICATE_SEQ => {
                push_frame(&mut bytes, &packet(DUPLICATE_SEQ, JointId::HipFlexionR));
                packets += 1;
            }
            150 => {
                push_frame(&mut bytes, &packet(LATE_SEQ, JointId::KneeAngleR));
                packets += 1;
            }
            _ => {}
        }
    }
    // Every kind of model switch, so that the stack peak the firmware logs covers them: the
    // generic gait2392, HAK with a subject's lengths, a subject gait2392 uploaded in parts,
    // then back to the default PHAK with the status request.
    let settings = HubSettings {
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: false,
    };
    let mut scaled = Gait2392Geometry::generic();
    scaled.right.ankle_in_tibia[1] *= 1.1;
    let hak = Limb {
        pelvis_half_width: 0.09,
        femur: 0.43,
        tibia: 0.41,
        foot: 0.17,
    };
    let switches = [
        HubModel::Gait2392,
        HubModel::Stick {
            model: ModelId::Hak,
            anthropometry: Some(Anthropometry::symmetric(hak)),
        },
        HubModel::Subject {
            geometry: Box::new(scaled),
            upload: None,
        },
    ];
    for model in &switches {
        let messages = config::messages(model, settings).expect("the session's models are valid");
        for message in &messages {
            push_frame(&mut bytes, message);
        }
    }
    let request = Config {
        model: ModelId::Phak,
        anthropometry: None,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 4,
        request_status: true,
    };
    push_frame(&mut bytes, &Message::Config(request));
    Plan {
        bytes,
        packets_accepted: packets,
        decode_errors: 2,
    }
}

/// Largest |f32 - f64| over the points and distances of `frame`, and whether its angles are
/// exactly the ones sent.
fn compare(phak: &Phak<f64>, frame: &PoseFrame) -> (f64, bool) {
    let sent: Vec<f32> = ModelId::Phak
        .required_joints()
        .iter()
        .map(|&j| gait::angle(j, frame.seq))
        .collect();
    let angles = PhakAngles {
        pelvis_rotation: f64::from(sent[0]),
        pelvis_list: f64::from(sent[1]),
        hip_flexion_r: f64::from(sent[2]),
        knee_angle_r: f64::from(sent[3]),
        ankle_angle_r: f64::from(sent[4]),
        hip_flexion_l: f64::from(sent[5]),
        knee_angle_l: f64::from(sent[6]),
        ankle_angle_l: f64::from(sent[7]),
    };
    let pose = phak.fk(&angles);
    let mut worst = 0.0f64;
    for (got, want) in frame.points.iter().zip(pose.points()) {
        for (g, w) in got.iter().zip(want.to_array()) {
            worst = worst.max((f64::from(*g) - w).abs());
        }
    }
    for (g, w) in frame.distances.iter().zip(distances(&pose).to_array()) {
        worst = worst.max((f64::from(*g) - w).abs());
    }
    (worst, frame.angles.as_slice() == sent.as_slice())
}

fn accept(listener: &UnixListener, deadline: Instant) -> Result<UnixStream, String> {
    listener.set_nonblocking(true).map_err(|e| e.to_string())?;
    loop {
        match listener.accept() {
            Ok((stream, _)) => {
                stream.set_nonblocking(false).map_err(|e| e.to_string())?;
                return Ok(stream);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock && Instant::now() < deadline => {
                thread::sleep(Duration::from_millis(5))
            }
            Err(e) => return Err(format!("QEMU did not connect to the UART socket: {e}")),
        }
    }
}

/// Binds the UART socket, starts QEMU on it and accepts its connection.
fn connect(elf: &Path, deadline: Instant) -> Result<(Qemu, UnixStream), String> {
    let socket = std::env::temp_dir().join(format!("qgait-uart-{}.sock", std::process::id()));
    let _ = std::fs::remove_file(&socket);
    let listener =
        UnixListener::bind(&socket).map_err(|e| format!("binding {}: {e}", socket.display()))?;
    let started = Qemu::start(elf, Some(&socket));
    let accepted = match &started {
        Ok(_) => accept(&listener, deadline),
        Err(_) => Err(String::new()),
    };
    let _ = std::fs::remove_file(&socket);
    match (started, accepted) {
        (Ok(qemu), Ok(stream)) => Ok((qemu, stream)),
        (Ok(qemu), Err(e)) => {
            qemu.stop();
            Err(e)
        }
        (Err(e), _) => Err(e),
    }
}

/// What came back from the firmware.
#[derive(Default)]
struct Received {
    poses: u32,
    worst_error_m: f64,
    wrong_angles: u32,
    undecodable: u32,
    seen: Vec<u32>,
    status: Option<Status>,
    read_error: Option<String>,
}

/// Reads frames until the `Status` answering the request arrives (or the deadline).
fn receive(stream: &mut UnixStream, phak: &Phak<f64>, plan: &Plan, deadline: Instant) -> Received {
    let mut r = Received::default();
    let mut decoder = FrameDecoder::new();
    let mut buf = [0u8; 1024];
    while r.status.is_none() && Instant::now() < deadline {
        let n = match stream.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                continue
            }
            Err(e) => {
                r.read_error = Some(format!("reading the UART socket: {e}"));
                break;
            }
        };
        for &byte in &buf[..n] {
            match decoder.push(byte) {
                Some(Ok(Message::PoseFrame(frame))) => {
                    r.poses += 1;
                    r.seen.push(frame.seq);
                    let (err, angles_ok) = compare(phak, &frame);
                    r.worst_error_m = r.worst_error_m.max(err);
                    r.wrong_angles += u32::from(!angles_ok);
                }
                Some(Ok(Message::Status(s))) if s.packets_accepted >= plan.packets_accepted => {
                    r.status = Some(s)
                }
                Some(Ok(_)) => {}
                Some(Err(_)) => r.undecodable += 1,
                None => {}
            }
        }
    }
    r
}

/// Everything in `r` that does not match the plan.
fn evaluate(r: &Received, plan: &Plan) -> Vec<String> {
    let mut failures = Vec::new();
    let mut check = |ok: bool, what: String| {
        if !ok {
            failures.push(what);
        }
    };
    if let Some(e) = &r.read_error {
        check(false, e.clone());
    }
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
        r.worst_error_m <= TOLERANCE_M,
        format!(
            "largest |f32 - f64| {:.3e} m > {TOLERANCE_M:.0e} m",
            r.worst_error_m
        ),
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
    let Some(s) = &r.status else {
        check(false, "no Status frame answered the request".into());
        return failures;
    };
    let decode_errors = s.crc_errors
        + s.framing_errors
        + s.oversize_frames
        + s.malformed
        + s.unknown_version
        + s.unknown_joint;
    let counters = [
        (
            "packets_accepted",
            s.packets_accepted,
            plan.packets_accepted,
        ),
        ("samples_completed", s.samples_completed, expected_poses),
        ("samples_incomplete", s.samples_incomplete, 1),
        ("duplicate_packets", s.duplicate_packets, 1),
        ("late_packets", s.late_packets, 1),
        ("decode errors", decode_errors, plan.decode_errors),
        ("uart_overruns", s.uart_overruns, 0),
        // All the model switches were accepted.
        ("config_rejected", s.config_rejected, 0),
    ];
    for (name, got, want) in counters {
        check(got == want, format!("{name} {got} != {want}"));
    }
    failures
}

/// Runs the session against `elf` and prints its report.
pub fn run(elf: &Path) -> Result<Report, String> {
    let phak = Phak::new(&Anthropometry::<f64>::gait2392()).map_err(|e| format!("kernel: {e}"))?;
    let plan = plan();
    let deadline = Instant::now() + DEADLINE;
    let (qemu, mut stream) = connect(elf, deadline)?;
    let mut writer = match (
        stream.try_clone(),
        stream.set_read_timeout(Some(Duration::from_millis(50))),
    ) {
        (Ok(w), Ok(())) => w,
        (Err(e), _) | (_, Err(e)) => {
            qemu.stop();
            return Err(format!("setting up the UART socket: {e}"));
        }
    };
    let bytes = plan.bytes.clone();
    let sender = thread::spawn(move || writer.write_all(&bytes));
    let received = receive(&mut stream, &phak, &plan, deadline);
    // The firmware logs its stack peak right after sending the status: let that line through.
    thread::sleep(Duration::from_millis(200));
    let finished = qemu.stop();
    let _ = sender.join();

    let stack_peak = finished
        .log
        .iter()
        .filter_map(|l| {
            l.split("stack peak ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()
        })
        .max();
    let failures = evaluate(&received, &plan);
    println!(
        "uart session: {SAMPLES} samples ({} bytes) in, {} poses out, largest |f32 - f64| {:.2e} m, stack peak {} bytes",
        plan.bytes.len(),
        received.poses,
        received.worst_error_m,
        stack_peak.map_or("?".to_string(), |p: u32| p.to_string())
    );
    if let Some(s) = &received.status {
        println!("uart session: status {s:?}");
    }
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
