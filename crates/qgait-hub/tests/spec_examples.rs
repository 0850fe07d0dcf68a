//! The hub's behaviour as `docs/protocol.md` states it: its transcripts (the blocks
//! ```` ```text example=NAME ````) are produced here by a real [`Hub`] and compared line for line
//! with the document, so the spec's examples are the hub's behaviour; and the configuration
//! rules of the spec (section 4.4, section 8) are checked one by one.
//!
//! To print every transcript as it must read:
//! `QGAIT_PRINT_EXAMPLES=1 cargo test --manifest-path crates/qgait-hub/Cargo.toml --test spec_examples -- --nocapture`.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

use qgait_hub::{Hub, ManualClock, MemorySerial};
use qgait_proto::{
    encode_frame, encode_raw_frame, Config, FrameDecoder, JointAngle, JointId, Message,
    MissingPolicy, ModelId, PoseFrame, RawImuSample, SampleHeader, SegmentId, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};

type Serial = MemorySerial<4096, 65536>;
type TestHub<'c> = Hub<Serial, &'c ManualClock>;

fn protocol_md() -> String {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/protocol.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `example=NAME` block of the document: NAME -> its text.
fn example_blocks(doc: &str) -> BTreeMap<String, String> {
    let mut blocks = BTreeMap::new();
    let mut lines = doc.lines();
    while let Some(line) = lines.next() {
        let Some(info) = line.trim().strip_prefix("```") else {
            continue;
        };
        let Some(name) = info
            .split_whitespace()
            .find_map(|w| w.strip_prefix("example="))
        else {
            continue;
        };
        let body: Vec<&str> = lines
            .by_ref()
            .take_while(|l| !l.trim().starts_with("```"))
            .collect();
        assert!(
            blocks.insert(name.to_owned(), body.join("\n")).is_none(),
            "example block {name} twice"
        );
    }
    blocks
}

/// One step of a transcript.
enum Step {
    /// A message sent as one frame, shown in hex with a description.
    Frame(Message, &'static str),
    /// Bytes sent as they are (damaged frames), in hex with a description.
    Raw(Vec<u8>, &'static str),
    /// Message bytes (possibly invalid) sent in a frame with a good CRC, in hex with a
    /// description.
    Body(Vec<u8>, &'static str),
    /// One `JointAngle` per (joint, angle), all of sample `seq`, in that order; node = the joint
    /// id, `timestamp_us` = 10 000 × seq, quality 0.
    Sample(u32, Vec<(JointId, f32)>),
    /// The clock moves on by this many milliseconds, then the hub polls once.
    Wait(u32),
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn frame_bytes(message: &Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    encode_frame(message, &mut buf).expect("encodes").to_vec()
}

fn packet(seq: u32, joint: JointId, angle: f32) -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: joint.index(),
        joint,
        seq,
        timestamp_us: seq.wrapping_mul(10_000),
        angle,
        quality: 0,
    }
}

const POINT_NAMES: [&str; 8] = [
    "hip_r", "knee_r", "ankle_r", "toe_r", "hip_l", "knee_l", "ankle_l", "toe_l",
];

fn describe_output(message: &Message, points: bool, out: &mut String) {
    match message {
        Message::PoseFrame(p) => {
            let angles: Vec<String> = p.angles.iter().map(|a| a.to_string()).collect();
            writeln!(
                out,
                "<- PoseFrame seq {}, {}, flags 0x{:02x}, angles {}",
                p.seq,
                p.model,
                p.flags,
                angles.join(" ")
            )
            .unwrap();
            if points {
                for (name, [x, y, z]) in POINT_NAMES.iter().zip(p.points) {
                    writeln!(out, "     {name:<8} {x:>12} {y:>12} {z:>12}").unwrap();
                }
                let [knee, ankle, toe] = p.distances;
                writeln!(
                    out,
                    "     distances knee-knee {knee}, ankle-ankle {ankle}, toe-toe {toe}"
                )
                .unwrap();
            }
        }
        Message::Status(s) => {
            let nonzero: Vec<String> = s
                .named_counters()
                .iter()
                .filter(|(_, v)| *v != 0)
                .map(|(n, v)| format!("{n} {v}"))
                .collect();
            writeln!(out, "<- Status {}", nonzero.join(", ")).unwrap();
        }
        other => writeln!(out, "<- {other:?}").unwrap(),
    }
}

/// Runs `steps` on a new hub (clock at 0, a status every 1000 ms) and writes the transcript:
/// each step, then the frames the hub sent in answer (`<-`), then the counters that changed
/// (`   +name n`; uptime and `frames_sent` left out: the frames are listed).
/// With `points`, each pose frame's points (x, y, z, metres) and distances follow it.
fn transcript(steps: &[Step], points: bool) -> String {
    let clock = ManualClock::new(0);
    let mut hub: TestHub<'_> = Hub::new(Serial::new(), &clock, 1000).expect("default model");
    let mut out = String::new();
    let mut decoder = FrameDecoder::new();
    let mut sent = 0;
    for step in steps {
        let before = hub.status();
        match step {
            Step::Frame(message, what) => {
                let bytes = frame_bytes(message);
                writeln!(out, "-> {}  {what}", hex(&bytes)).unwrap();
                push(&mut hub, &bytes);
            }
            Step::Body(body, what) => {
                let mut buf = [0u8; MAX_FRAME_LEN];
                let bytes = encode_raw_frame(body, &mut buf).expect("fits").to_vec();
                writeln!(out, "-> {}  {what}", hex(&bytes)).unwrap();
                push(&mut hub, &bytes);
            }
            Step::Raw(bytes, what) => {
                writeln!(out, "-> {}  {what}", hex(bytes)).unwrap();
                push(&mut hub, bytes);
            }
            Step::Sample(seq, packets) => {
                // Wrapped at 100 columns, continued under the first packet.
                let mut line = format!("-> seq {seq}:");
                for (i, (j, a)) in packets.iter().enumerate() {
                    let item = format!(" {j} {a}{}", if i + 1 < packets.len() { "," } else { "" });
                    if line.len() + item.len() > 100 {
                        writeln!(out, "{line}").unwrap();
                        line = " ".repeat(format!("-> seq {seq}:").len());
                    }
                    line += &item;
                }
                writeln!(out, "{line}").unwrap();
                for &(joint, angle) in packets {
                    push(
                        &mut hub,
                        &frame_bytes(&Message::JointAngle(packet(*seq, joint, angle))),
                    );
                }
            }
            Step::Wait(ms) => {
                writeln!(out, ".. {ms} ms").unwrap();
                clock.advance(*ms);
                hub.poll();
            }
        }
        let transmitted = hub.serial_mut().transmitted().to_vec();
        for &b in &transmitted[sent..] {
            match decoder.push(b) {
                Some(Ok(m)) => describe_output(&m, points, &mut out),
                Some(Err(e)) => panic!("the hub sent a bad frame: {e:?}"),
                None => {}
            }
        }
        sent = transmitted.len();
        let after = hub.status();
        let changed: Vec<String> = before
            .named_counters()
            .iter()
            .zip(after.named_counters())
            .filter(|((n, a), (_, b))| a != b && *n != "uptime_ms" && *n != "frames_sent")
            .map(|((n, a), (_, b))| format!("+{n} {}", b.wrapping_sub(*a)))
            .collect();
        if !changed.is_empty() {
            writeln!(out, "   {}", changed.join(", ")).unwrap();
        }
    }
    out.trim_end().to_owned()
}

fn push(hub: &mut TestHub<'_>, bytes: &[u8]) {
    assert_eq!(
        hub.serial_mut().receive(bytes),
        bytes.len(),
        "receive queue full"
    );
    while hub.serial_mut().pending() > 0 {
        hub.poll();
    }
}

fn config(
    model: ModelId,
    missing_policy: MissingPolicy,
    reorder_window: u8,
    request_status: bool,
) -> Message {
    Message::Config(Config {
        model,
        anthropometry: None,
        missing_policy,
        reorder_window,
        request_status,
    })
}

/// The example angle of `joint` in sample `seq`: a value per joint plus (seq mod 10) / 100,
/// so that each angle says which sample it came from.
fn angle(joint: JointId, seq: u32) -> f32 {
    let base: i32 = match joint {
        JointId::HipFlexionR => 50,
        JointId::KneeAngleR => -50,
        JointId::AnkleAngleR => 10,
        JointId::HipFlexionL => -20,
        JointId::KneeAngleL => -100,
        JointId::AnkleAngleL => -10,
        _ => 0,
    };
    (base + (seq % 10) as i32) as f32 / 100.0
}

/// The gait2392 example's angle of `joint`.
fn gait2392_angle(joint: JointId) -> f32 {
    use JointId::*;
    match joint {
        PelvisTilt => -0.125,
        PelvisList => 0.0625,
        PelvisRotation => 0.25,
        HipFlexionR | HipFlexionL => 0.5,
        HipAdductionR => -0.125,
        HipRotationL => 0.125,
        KneeAngleR => -1.0,
        KneeAngleL => -0.25,
        AnkleAngleR => 0.25,
        AnkleAngleL => -0.25,
        SubtalarAngleR => 0.125,
        MtpAngleL => 0.25,
        _ => 0.0,
    }
}

const HAK: [JointId; 6] = [
    JointId::HipFlexionR,
    JointId::KneeAngleR,
    JointId::AnkleAngleR,
    JointId::HipFlexionL,
    JointId::KneeAngleL,
    JointId::AnkleAngleL,
];

/// Sample `seq` with every HAK joint but `without`.
fn hak_sample(seq: u32, without: &[JointId]) -> Step {
    Step::Sample(
        seq,
        HAK.iter()
            .filter(|j| !without.contains(j))
            .map(|&j| (j, angle(j, seq)))
            .collect(),
    )
}

fn one(seq: u32, joint: JointId, angle: f32) -> Step {
    Step::Sample(seq, vec![(joint, angle)])
}

/// Every transcript of the document, by name.
fn examples() -> Vec<(&'static str, Vec<Step>)> {
    use JointId::*;
    vec![
        (
            "assembly",
            vec![
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 2, false),
                    "Config: HAK, drop, window 2",
                ),
                hak_sample(1, &[KneeAngleL]),
                hak_sample(2, &[]),
                one(3, HipFlexionR, angle(HipFlexionR, 3)),
                one(1, KneeAngleL, angle(KneeAngleL, 1)),
                one(3, HipFlexionR, angle(HipFlexionR, 3)),
                one(2, KneeAngleR, angle(KneeAngleR, 2)),
                one(3, PelvisList, 0.05),
                hak_sample(3, &[HipFlexionR]),
                one(5, HipFlexionR, angle(HipFlexionR, 5)),
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 2, true),
                    "Config: the same, status requested",
                ),
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 3, true),
                    "Config: window 3, status requested",
                ),
            ],
        ),
        (
            "hold-last",
            vec![
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::HoldLast, 1, false),
                    "Config: HAK, hold last, window 1",
                ),
                hak_sample(1, &[AnkleAngleL]),
                hak_sample(2, &[]),
                hak_sample(3, &[KneeAngleR]),
                one(4, KneeAngleR, f32::NAN),
                hak_sample(4, &[KneeAngleR]),
                one(5, KneeAngleR, 0.5),
                hak_sample(5, &[KneeAngleR]),
                hak_sample(6, &[KneeAngleR]),
                one(7, HipFlexionR, angle(HipFlexionR, 7)),
            ],
        ),
        (
            "resync",
            vec![
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 4, false),
                    "Config: HAK, drop, window 4",
                ),
                hak_sample(100, &[]),
                one(101, HipFlexionR, angle(HipFlexionR, 101)),
                one(97, HipFlexionR, angle(HipFlexionR, 97)),
                one(98, HipFlexionR, angle(HipFlexionR, 98)),
                one(2000, HipFlexionR, angle(HipFlexionR, 2000)),
                one(0, HipFlexionR, angle(HipFlexionR, 0)),
                hak_sample(0, &[HipFlexionR]),
                hak_sample(300, &[]),
                hak_sample(1, &[]),
                hak_sample(297, &[]),
            ],
        ),
        (
            "config",
            vec![
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 4, false),
                    "Config: HAK, drop, window 4",
                ),
                hak_sample(1, &[]),
                hak_sample(2, &[AnkleAngleL]),
                Step::Frame(
                    config(ModelId::Phak, MissingPolicy::Drop, 4, false),
                    "Config: PHAK, drop, window 4",
                ),
                hak_sample(3, &[]),
                Step::Sample(3, vec![(PelvisRotation, 0.1), (PelvisList, -0.05)]),
                Step::Frame(
                    config(ModelId::Phak, MissingPolicy::Drop, 0, true),
                    "Config: window 0, status requested",
                ),
                Step::Frame(
                    config(ModelId::Phak, MissingPolicy::Drop, 9, false),
                    "Config: window 9",
                ),
            ],
        ),
        (
            "kinematics",
            vec![
                Step::Sample(
                    1,
                    vec![
                        (PelvisRotation, 0.25),
                        (PelvisList, -0.125),
                        (HipFlexionR, 0.5),
                        (KneeAngleR, -1.0),
                        (AnkleAngleR, 0.25),
                        (HipFlexionL, -0.25),
                        (KneeAngleL, -0.5),
                        (AnkleAngleL, -0.125),
                    ],
                ),
                Step::Frame(
                    config(ModelId::Hak, MissingPolicy::Drop, 1, false),
                    "Config: HAK, drop, window 1",
                ),
                hak_sample(2, &[]),
                Step::Frame(
                    config(ModelId::Gait2392, MissingPolicy::Drop, 1, false),
                    "Config: gait2392, drop, window 1",
                ),
                Step::Sample(
                    3,
                    JointId::ALL
                        .iter()
                        .map(|&j| (j, gait2392_angle(j)))
                        .collect(),
                ),
            ],
        ),
        (
            "status",
            vec![
                Step::Wait(999),
                Step::Wait(1),
                Step::Raw(
                    vec![0x02, 0x00],
                    "a frame whose code byte points past its end",
                ),
                Step::Raw(vec![0x02, 0x05, 0x00], "a frame of 1 byte"),
                Step::Raw(
                    vec![
                        0x01, 0x09, 0x03, 0x02, 0x06, 0xac, 0x02, 0x87, 0xad, 0x4b, 0x01, 0x01,
                        0x07, 0xbf, 0x08, 0xab, 0xb1, 0x60, 0xdc, 0x00,
                    ],
                    "the JointAngle of 7.1 with a bad CRC",
                ),
                Step::Body(
                    vec![0x03, 0x05, 0x00, 0x09, 0x04, 0x00],
                    "a Config of model 5 (and missing policy 9)",
                ),
                Step::Body(
                    [0x02].into_iter().chain([0x00; 20]).collect(),
                    "a Status sent to the hub",
                ),
                Step::Frame(
                    Message::RawImuSample(RawImuSample {
                        header: SampleHeader::new(4, SegmentId::TibiaR, 300, 1_234_567),
                        gyro: [-188, 47, 3289],
                        accel: [251, 2005, -84],
                        mag: Some([133, -233, 80]),
                    }),
                    "the RawImuSample of 7.9: no hub takes raw input",
                ),
                Step::Body(
                    vec![
                        0x00, 0x01, 0x02, 0x06, 0xac, 0x02, 0x87, 0xad, 0x4b, 0x00, 0x00, 0x00,
                        0xbf, 0x08,
                    ],
                    "the JointAngle of 7.1 with version 1",
                ),
                Step::Body(
                    vec![
                        0x00, 0x03, 0x02, 0x11, 0xac, 0x02, 0x87, 0xad, 0x4b, 0x00, 0x00, 0x00,
                        0xbf, 0x08,
                    ],
                    "the JointAngle of 7.1 with joint 17",
                ),
                Step::Body(vec![0x14], "a message of tag 20"),
                Step::Wait(500),
                Step::Frame(
                    config(ModelId::Phak, MissingPolicy::Drop, 4, true),
                    "Config: the one in force, status requested",
                ),
                Step::Wait(999),
                Step::Wait(1),
            ],
        ),
    ]
}

#[test]
// The transcripts are of the hub without raw input (a raw sample to one with it is not
// `malformed`): `tests/raw_input.rs` covers that.
#[cfg_attr(
    feature = "raw",
    ignore = "the transcripts are of the hub without raw input"
)]
fn spec_examples_are_the_hubs_transcripts() {
    let doc = example_blocks(&protocol_md());
    let print = std::env::var_os("QGAIT_PRINT_EXAMPLES").is_some();
    let mut failures = Vec::new();
    let mut names = Vec::new();
    for (name, steps) in examples() {
        names.push(name.to_owned());
        let want = transcript(&steps, name == "kinematics");
        if print {
            println!("```text example={name}\n{want}\n```\n");
        }
        if doc.get(name).map(|s| s.trim_end()) != Some(want.as_str()) {
            failures.push(format!("example={name} should read:\n{want}\n"));
        }
    }
    assert!(
        failures.is_empty(),
        "docs/protocol.md disagrees with the hub:\n{}",
        failures.join("\n")
    );
    names.sort();
    assert_eq!(
        doc.into_keys().collect::<Vec<_>>(),
        names,
        "example blocks of docs/protocol.md"
    );
}

fn send(hub: &mut TestHub<'_>, message: &Message) {
    push(hub, &frame_bytes(message));
}

/// The poses the hub sent since `from` (a byte offset of its output).
fn poses_since(hub: &mut TestHub<'_>, from: usize) -> Vec<PoseFrame> {
    let mut decoder = FrameDecoder::new();
    let mut poses = Vec::new();
    for &b in &hub.serial_mut().transmitted()[from..] {
        if let Some(Ok(Message::PoseFrame(p))) = decoder.push(b) {
            poses.push(p);
        }
    }
    poses
}

/// Sends every joint of `model` for sample `seq` and returns the pose it gave.
fn pose_of(hub: &mut TestHub<'_>, model: ModelId, seq: u32) -> PoseFrame {
    let from = hub.serial_mut().transmitted().len();
    for &joint in model.required_joints() {
        send(
            hub,
            &Message::JointAngle(packet(seq, joint, angle(joint, seq))),
        );
    }
    let poses = poses_since(hub, from);
    assert_eq!(poses.len(), 1, "sample {seq}: {poses:?}");
    assert_eq!(poses[0].model, model);
    poses[0].clone()
}

fn distance(a: [f32; 3], b: [f32; 3]) -> f32 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f32>().sqrt()
}

/// Section 4.4: `anthropometry` none keeps the HAK and PHAK lengths in force, through other
/// models too; only a `Config` with lengths changes them.
#[test]
fn a_config_without_lengths_keeps_the_lengths_in_force() {
    let clock = ManualClock::new(0);
    let mut hub: TestHub<'_> = Hub::new(Serial::new(), &clock, 0).expect("default model");
    let right = [0.1, 0.45, 0.47, 0.22];
    let left = [0.11, 0.44, 0.46, 0.21];
    let lengths = Config {
        model: ModelId::Phak,
        anthropometry: Some([right, left]),
        missing_policy: MissingPolicy::Drop,
        reorder_window: 1,
        request_status: false,
    };
    send(&mut hub, &Message::Config(lengths));
    let check = |p: &PoseFrame, what: &str| {
        // PHAK's pelvis turns the hips off the z axis: their distance stays the two half-widths.
        assert!(
            (distance(p.points[0], p.points[4]) - (right[0] + left[0])).abs() < 1e-6,
            "{what}: {p:?}"
        );
        assert!(
            (distance(p.points[0], p.points[1]) - right[1]).abs() < 1e-6,
            "{what}: {p:?}"
        );
        assert!(
            (distance(p.points[5], p.points[6]) - left[2]).abs() < 1e-6,
            "{what}: {p:?}"
        );
    };
    check(&pose_of(&mut hub, ModelId::Phak, 1), "with the lengths");
    // Other settings, no lengths: the lengths stay.
    send(
        &mut hub,
        &Message::Config(Config {
            anthropometry: None,
            reorder_window: 2,
            ..lengths
        }),
    );
    check(
        &pose_of(&mut hub, ModelId::Phak, 10),
        "PHAK without lengths",
    );
    send(
        &mut hub,
        &Message::Config(Config {
            model: ModelId::Hak,
            anthropometry: None,
            ..lengths
        }),
    );
    let hak = pose_of(&mut hub, ModelId::Hak, 20);
    check(&hak, "HAK without lengths");
    // HAK: the hips on the z axis at +/- their half-widths.
    assert_eq!(
        (hak.points[0], hak.points[4]),
        ([0.0, 0.0, right[0]], [0.0, 0.0, -left[0]])
    );
    // Through gait2392 (whose lengths are its model's) and back.
    send(
        &mut hub,
        &Message::Config(Config {
            model: ModelId::Gait2392,
            anthropometry: None,
            ..lengths
        }),
    );
    pose_of(&mut hub, ModelId::Gait2392, 30);
    send(
        &mut hub,
        &Message::Config(Config {
            anthropometry: None,
            ..lengths
        }),
    );
    check(&pose_of(&mut hub, ModelId::Phak, 40), "PHAK after gait2392");
    assert_eq!(hub.status().config_rejected, 0);
    assert_eq!(hub.config().anthropometry, Some([right, left]));
}

/// Section 4.4: a reorder window outside 1..=8 is a configuration the hub cannot use:
/// rejected, counted in `config_rejected`, the configuration in force kept.
#[test]
fn reorder_windows_outside_one_to_eight_are_rejected_and_counted() {
    let clock = ManualClock::new(0);
    let mut hub: TestHub<'_> = Hub::new(Serial::new(), &clock, 0).expect("default model");
    let mut rejected = 0;
    for window in 0..=255u8 {
        let before = hub.config();
        send(
            &mut hub,
            &config(ModelId::Hak, MissingPolicy::HoldLast, window, false),
        );
        if (1..=qgait_proto::MAX_REORDER_WINDOW).contains(&window) {
            assert_eq!(
                (hub.config().model, hub.config().reorder_window),
                (ModelId::Hak, window)
            );
        } else {
            rejected += 1;
            assert_eq!(hub.config(), before, "window {window}");
        }
        assert_eq!(hub.status().config_rejected, rejected, "window {window}");
    }
    // The same for a SubjectConfig of a complete, valid subject model.
    let (legs, knees) =
        qgait_hub::parts_of(&qgait_kernel::Gait2392Geometry::generic(), 1).expect("parts");
    legs.iter()
        .for_each(|l| send(&mut hub, &Message::SubjectLeg(*l)));
    knees
        .iter()
        .for_each(|k| send(&mut hub, &Message::SubjectKnee(k.clone())));
    let subject = |reorder_window| {
        Message::SubjectConfig(qgait_proto::SubjectConfig {
            upload: 1,
            missing_policy: MissingPolicy::Drop,
            reorder_window,
            request_status: false,
        })
    };
    send(&mut hub, &subject(0));
    assert_eq!(
        (hub.status().config_rejected, hub.subject()),
        (rejected + 1, None)
    );
    send(&mut hub, &subject(8));
    assert_eq!(
        (hub.status().config_rejected, hub.subject()),
        (rejected + 1, Some(1))
    );
}

/// Section 8.6: lengths are compared by value. A `Config` that states gait2392's generic
/// lengths, with everything else as in force (which the hub starts with as "no lengths"), is
/// the configuration in force: the sample open across it stays open and gives its pose.
#[test]
fn a_config_stating_the_lengths_in_force_changes_nothing() {
    let clock = ManualClock::new(0);
    let mut hub: TestHub<'_> = Hub::new(Serial::new(), &clock, 0).expect("default model");
    let generic = qgait_kernel::Limb::<f32>::gait2392().to_array();
    let start = hub.config();
    let stated = Config {
        anthropometry: Some([generic, generic]),
        request_status: false,
        ..start
    };
    let from = hub.serial_mut().transmitted().len();
    let joints = ModelId::Phak.required_joints();
    let (last, first) = joints.split_last().expect("joints");
    for &joint in first {
        send(
            &mut hub,
            &Message::JointAngle(packet(1, joint, angle(joint, 1))),
        );
    }
    send(&mut hub, &Message::Config(stated));
    send(
        &mut hub,
        &Message::JointAngle(packet(1, *last, angle(*last, 1))),
    );
    let poses = poses_since(&mut hub, from);
    assert_eq!(poses.len(), 1, "{poses:?}");
    assert_eq!(
        (
            hub.status().samples_incomplete,
            hub.status().config_rejected
        ),
        (0, 0)
    );
    // Stated lengths that differ do take effect (and close the open sample).
    let mut longer = generic;
    longer[1] += 0.01;
    for &joint in first {
        send(
            &mut hub,
            &Message::JointAngle(packet(2, joint, angle(joint, 2))),
        );
    }
    send(
        &mut hub,
        &Message::Config(Config {
            anthropometry: Some([longer, generic]),
            ..stated
        }),
    );
    assert_eq!(hub.status().samples_incomplete, 1);
}
