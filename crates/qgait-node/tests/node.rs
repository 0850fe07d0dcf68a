//! The node on the host: raw samples in through its serial port, orientations and counters out,
//! by protocol.md 4.10's rules; the same rules in f64 (`RawInput<f64, _>`) as the reference.

use qgait_hub::{ManualClock, MemorySerial};
use qgait_node::{orientation_packet, Node, RawInput, RawOutcome};
use qgait_proto::{
    encode_frame, segment_bit, FrameDecoder, FusionMode, JointAngle, Message, RawImuConfig,
    RawImuSample, RawImuStatus, SampleHeader, SegmentId, SegmentOrientation, Status, MAX_FRAME_LEN,
    PROTOCOL_VERSION,
};

type TestNode<'a> = Node<MemorySerial<512, 65536>, &'a ManualClock>;

fn icm20948(segments: u8, fusion: FusionMode, output_every: u8) -> RawImuConfig {
    RawImuConfig {
        segments,
        fusion,
        rate_hz: 100,
        output_every,
        gyro_per_count: RawImuConfig::gyro_per_count_of(16.4),
        accel_per_count: RawImuConfig::accel_per_count_of(2048.0),
        mag_per_count: 0.15,
        request_status: false,
    }
}

/// A sample of segment `segment` at `seq` (timestamp `seq` × 10 ms) turning about z at `wz`
/// rad/s, level (gravity along z), the field pointing north and down.
fn sample(segment: SegmentId, seq: u32, wz: f64, c: &RawImuConfig) -> RawImuSample {
    let count = |v: f64, per: f32| RawImuSample::count_of(v, f64::from(per));
    // The field in the sensor frame of a sensor turned by wz·t about the vertical.
    let yaw = wz * f64::from(seq) * 0.01;
    let (n, down) = (20.0, -40.0);
    let mag = [n * yaw.sin(), n * yaw.cos(), down];
    RawImuSample {
        header: SampleHeader::new(3, segment, seq, seq.wrapping_mul(10_000)),
        gyro: [0.0, 0.0, wz].map(|w| count(w, c.gyro_per_count)),
        accel: [0.0, 0.0, 9.81].map(|a| count(a, c.accel_per_count)),
        mag: Some(mag.map(|m| count(m, c.mag_per_count))),
    }
}

fn frame(m: Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    encode_frame(&m, &mut buf).expect("encodes").to_vec()
}

/// Feeds `bytes` to the node, polling as its receive queue fills and until it is empty.
fn feed(node: &mut TestNode, bytes: &[u8]) {
    let mut rest = bytes;
    while !rest.is_empty() {
        let n = node.serial_mut().receive(rest);
        rest = &rest[n..];
        node.poll();
    }
    while node.serial_mut().pending() > 0 {
        node.poll();
    }
}

/// Everything the node sent, decoded.
fn sent(node: &mut TestNode) -> Vec<Message> {
    let out = node.serial_mut().transmitted().to_vec();
    FrameDecoder::new()
        .feed(&out)
        .map(|m| m.expect("the node's frames decode"))
        .collect()
}

fn orientations(messages: &[Message]) -> Vec<SegmentOrientation> {
    messages
        .iter()
        .filter_map(|m| match m {
            Message::SegmentOrientation(o) => Some(*o),
            _ => None,
        })
        .collect()
}

/// The angle between two quaternions, degrees.
fn angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let na = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let nb = b.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() / (na * nb);
    2.0 * dot.abs().min(1.0).acos().to_degrees()
}

#[test]
fn orientations_every_output_every_th_sample_as_the_f64_rules_give_them() {
    let clock = ManualClock::new(0);
    let mut node: TestNode = Node::new(MemorySerial::new(), &clock, 0);
    let c = icm20948(segment_bit(SegmentId::TibiaR), FusionMode::NineD, 4);
    let mut bytes = frame(Message::RawImuConfig(c));
    let mut reference = RawInput::<f64, 1>::new();
    assert!(reference.configure(&c));
    let mut expected = Vec::new();
    for seq in 0..400 {
        let s = sample(SegmentId::TibiaR, seq, 1.5, &c);
        bytes.extend(frame(Message::RawImuSample(s)));
        if let RawOutcome::Fused(Some(q)) = reference.push(&s) {
            expected.push((s, q));
        }
    }
    bytes.extend(frame(Message::RawImuConfig(RawImuConfig {
        request_status: true,
        ..c
    })));
    feed(&mut node, &bytes);
    let messages = sent(&mut node);
    let got = orientations(&messages);
    assert_eq!(got.len(), 100);
    assert_eq!(expected.len(), 100);
    let mut worst: f64 = 0.0;
    for (o, (s, q)) in got.iter().zip(&expected) {
        assert_eq!(o.header.seq % 4, 0);
        assert_eq!(
            (o.header.seq, o.header.node, o.header.segment),
            (s.header.seq, 3, SegmentId::TibiaR)
        );
        assert_eq!(o.header.timestamp_us, s.header.timestamp_us);
        let device = o.quaternion().map(f64::from);
        worst = worst.max(angle_deg(device, *q));
    }
    // f32 against f64, plus Q14's 0.007° at most.
    assert!(worst < 0.02, "largest difference {worst}°");
    // The answer to the request: a Status and the raw counters, last.
    let n = messages.len();
    let Message::Status(status) = messages[n - 2] else {
        panic!("no status: {:?}", &messages[n - 2..]);
    };
    let Message::RawImuStatus(raw) = messages[n - 1] else {
        panic!("no raw status");
    };
    assert_eq!(status.packets_accepted, 400);
    assert_eq!(status.samples_completed, 100);
    assert_eq!(status.frames_sent, 101);
    assert_eq!(raw.samples_accepted, 400);
    assert_eq!(
        raw,
        RawImuStatus {
            samples_accepted: 400,
            ..Default::default()
        }
    );
}

#[test]
fn the_rules_count_gaps_stale_samples_resyncs_timing_and_missing_magnetometers() {
    let c = icm20948(segment_bit(SegmentId::Pelvis), FusionMode::NineD, 1);
    let mut input = RawInput::<f32, 1>::new();
    let s = |seq| sample(SegmentId::Pelvis, seq, 0.5, &c);
    // Before any configuration: not configured.
    assert_eq!(input.push(&s(0)), RawOutcome::NotConfigured);
    assert!(input.configure(&c));
    assert!(matches!(input.push(&s(10)), RawOutcome::Fused(Some(_))));
    assert!(matches!(input.push(&s(11)), RawOutcome::Fused(_)));
    // A gap of 3 samples lost.
    assert!(matches!(input.push(&s(15)), RawOutcome::Fused(_)));
    // Repeated and behind: stale.
    assert_eq!(input.push(&s(15)), RawOutcome::Stale);
    assert_eq!(input.push(&s(12)), RawOutcome::Stale);
    // A timestamp off by more than half a period: the nominal step.
    let mut late = s(16);
    late.header.timestamp_us += 6_000;
    assert!(matches!(input.push(&late), RawOutcome::Fused(_)));
    // Within half a period: its own step.
    let mut near = s(17);
    near.header.timestamp_us += 4_000;
    input.push(&near);
    // No magnetometer in 9D; a saturated axis.
    let mut no_mag = s(18);
    no_mag.mag = None;
    no_mag.gyro[0] = i16::MAX;
    input.push(&no_mag);
    // More than 1024 ahead: the fusion starts afresh; then another segment.
    input.push(&s(18 + 1025));
    assert_eq!(
        input.push(&sample(SegmentId::FemurR, 2000, 0.0, &c)),
        RawOutcome::NotConfigured
    );
    // 1025 behind the last is a resync too, wrapping below 0 included.
    input.push(&s(0u32.wrapping_sub(5)));
    assert_eq!(
        input.status(),
        RawImuStatus {
            samples_accepted: 8,
            saturated: 1,
            rate_gaps: 1,
            samples_lost: 3,
            timing_errors: 1,
            stale_samples: 2,
            resyncs: 2,
            missing_magnetometer: 1,
            not_configured: 2,
        }
    );
}

#[test]
fn a_gap_is_integrated_over_its_length() {
    // 6D, turning at 1 rad/s about the vertical: after a gap the heading is where it would be
    // without one.
    let c = icm20948(segment_bit(SegmentId::Pelvis), FusionMode::SixD, 1);
    let run = |skip: &dyn Fn(u32) -> bool| {
        let mut input = RawInput::<f64, 1>::new();
        assert!(input.configure(&c));
        let mut last = None;
        for seq in (0..200).filter(|s| !skip(*s)) {
            if let RawOutcome::Fused(Some(q)) = input.push(&sample(SegmentId::Pelvis, seq, 1.0, &c))
            {
                last = Some(q);
            }
        }
        (last.unwrap(), input.status())
    };
    let (full, _) = run(&|_| false);
    let (gapped, status) = run(&|s| (100..110).contains(&s));
    assert_eq!((status.rate_gaps, status.samples_lost), (1, 10));
    let d = angle_deg(full, gapped);
    assert!(d < 0.05, "{d}°");
    // Without the dt / T scaling the heading would lag by 10 samples × 0.01 s × 1 rad/s.
    assert!(0.1f64.to_degrees() > 50.0 * d);
}

#[test]
fn configurations_the_node_cannot_use_are_rejected() {
    let clock = ManualClock::new(0);
    let mut node: TestNode = Node::new(MemorySerial::new(), &clock, 0);
    let good = icm20948(segment_bit(SegmentId::CalcnL), FusionMode::NineD, 1);
    let bad = [
        RawImuConfig { rate_hz: 0, ..good },
        RawImuConfig {
            output_every: 0,
            ..good
        },
        RawImuConfig {
            gyro_per_count: f32::NAN,
            ..good
        },
        RawImuConfig {
            mag_per_count: -1.0,
            ..good
        },
        // Two segments: a node fuses its own IMU only.
        RawImuConfig {
            segments: 0b11,
            ..good
        },
    ];
    let mut bytes = frame(Message::RawImuConfig(good));
    for b in bad {
        bytes.extend(frame(Message::RawImuConfig(b)));
    }
    // 6D needs no magnetometer sensitivity.
    bytes.extend(frame(Message::RawImuConfig(RawImuConfig {
        fusion: FusionMode::SixD,
        mag_per_count: f32::NAN,
        ..good
    })));
    feed(&mut node, &bytes);
    assert_eq!(node.status().config_rejected, 5);
    assert_eq!(node.input().config().fusion, FusionMode::SixD);
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

#[test]
fn any_byte_stream_is_counted_and_never_stops_the_node() {
    let clock = ManualClock::new(0);
    let mut node: TestNode = Node::new(MemorySerial::new(), &clock, 0);
    let c = icm20948(segment_bit(SegmentId::Pelvis), FusionMode::NineD, 1);
    let mut rng = Rng(0x6e6f_6465);
    let mut bytes = frame(Message::RawImuConfig(c));
    let mut good_samples = 0u32;
    for seq in 0..3000u32 {
        let mut s = sample(SegmentId::Pelvis, seq, 2.0, &c);
        // Wild values too: extreme counts, random seq and timestamps.
        if rng.next().is_multiple_of(7) {
            s.gyro = [0; 3].map(|_| rng.next() as i16);
            s.accel = [0; 3].map(|_| rng.next() as i16);
            s.header.seq = rng.next() as u32;
            s.header.timestamp_us = rng.next() as u32;
        }
        let mut f = frame(Message::RawImuSample(s));
        match rng.next() % 10 {
            // A flipped byte (not the delimiter).
            0 => {
                let i = (rng.next() as usize) % (f.len() - 1);
                f[i] ^= 1 + (rng.next() % 255) as u8;
                if f[i] == 0 {
                    f[i] = 1;
                }
            }
            // A message the node does not take.
            1 => {
                f = frame(Message::JointAngle(JointAngle {
                    version: PROTOCOL_VERSION,
                    node: 1,
                    joint: qgait_proto::JointId::ALL[3],
                    seq,
                    timestamp_us: 0,
                    angle: 0.1,
                    quality: 0,
                }))
            }
            // Noise.
            2 => f = (0..(rng.next() % 40)).map(|_| rng.next() as u8).collect(),
            _ => good_samples += 1,
        }
        bytes.extend(f);
        // A stray delimiter between frames: an empty frame, counted nowhere.
        bytes.push(0);
    }
    bytes.extend(frame(Message::RawImuConfig(RawImuConfig {
        request_status: true,
        ..c
    })));
    feed(&mut node, &bytes);
    let messages = sent(&mut node);
    let status: Status = node.status();
    assert!(status.packets_accepted >= good_samples);
    let raw = node.input().status();
    assert_eq!(
        raw.samples_accepted + raw.stale_samples + raw.not_configured,
        status.packets_accepted
    );
    // Every orientation sent is a unit quaternion (never NaN), whatever the input.
    for o in orientations(&messages) {
        let n: f32 = o.quaternion().iter().map(|x| x * x).sum::<f32>().sqrt();
        assert!((n - 1.0).abs() < 1e-3, "{o:?}");
    }
    assert!(matches!(messages.last(), Some(Message::RawImuStatus(_))));
}

#[test]
fn the_orientation_packet_carries_the_sample_s_identity() {
    let c = icm20948(segment_bit(SegmentId::Torso), FusionMode::NineD, 1);
    let s = sample(SegmentId::Torso, 77, 0.0, &c);
    let p = orientation_packet(&s, [0.5f32, -0.5, 0.5, -0.5]);
    assert_eq!(
        (
            p.header.node,
            p.header.segment,
            p.header.seq,
            p.header.timestamp_us
        ),
        (3, SegmentId::Torso, 77, 770_000)
    );
    assert_eq!(p.q14, [8192, -8192, 8192, -8192]);
}
