//! Raw streams (`qgait packets --raw`) and the host's f64 fusion of them (`verify --raw`).

use qgait_device::raw::{host_orientations, RawCheck, RawStream, RawStreamError, Sensitivities};
use qgait_fusion::RawRecording;
use qgait_proto::{FrameDecoder, FusionMode, Message, SampleHeader, SegmentId, SegmentOrientation};

/// `n` samples at 285.714 Hz (BROAD's) of a sensor turning about z at 1 rad/s, level.
fn recording(name: &str, n: usize, mag: bool) -> RawRecording {
    let period = 0.0035;
    let times: Vec<f64> = (0..n).map(|i| 10.0 + i as f64 * period).collect();
    RawRecording {
        source: name.into(),
        period,
        lines: (2..n + 2).collect(),
        gyr: vec![[0.01, -0.02, 1.0]; n],
        acc: vec![[0.05, 0.02, 9.81]; n],
        mag: mag.then(|| {
            times
                .iter()
                .map(|t| {
                    let yaw = t - 10.0;
                    [20.0 * yaw.sin(), 20.0 * yaw.cos(), -40.0]
                })
                .collect()
        }),
        times,
        truth: None,
        movement: None,
    }
}

#[test]
fn a_stream_carries_the_configuration_then_every_sample_in_seq_order() {
    let (a, b) = (recording("a", 50, true), recording("b", 50, true));
    let s = RawStream::new(
        &[(SegmentId::FemurL, &a), (SegmentId::Pelvis, &b)],
        FusionMode::NineD,
        5,
        Sensitivities::default(),
    )
    .expect("a stream");
    assert_eq!(s.config.rate_hz, 286);
    assert_eq!(s.config.segments, 0b1_0001);
    assert_eq!(s.config.output_every, 5);
    let messages: Vec<Message> = FrameDecoder::new()
        .feed(&s.bytes())
        .map(|m| m.expect("decodes"))
        .collect();
    assert_eq!(messages.len(), 101);
    assert_eq!(messages[0], Message::RawImuConfig(s.config));
    let Message::RawImuSample(third) = messages[3] else {
        panic!("{:?}", messages[3]);
    };
    // Row 1 of the first sensor: timestamps from the first sample, the counts rounded.
    assert_eq!(
        (third.header.seq, third.header.segment, third.header.node),
        (1, SegmentId::FemurL, 4)
    );
    assert_eq!(third.header.timestamp_us, 3500);
    assert_eq!(third.gyro[2], 940); // 1 rad/s at 1.0642e-3 rad/s per count
    assert_eq!(third.accel[2], 2049); // 9.81 m/s² at 4.7884e-3
                                      // The host's fusion: every fifth sample of each segment.
    let host = host_orientations(&s.bytes());
    assert_eq!(host.len(), 20);
    assert!(host.contains_key(&(SegmentId::Pelvis, 45)));
}

#[test]
fn the_check_finds_differences_missing_and_unexpected_orientations() {
    let r = recording("a", 200, true);
    let s = RawStream::new(
        &[(SegmentId::TibiaR, &r)],
        FusionMode::NineD,
        1,
        Sensitivities::default(),
    )
    .expect("a stream");
    let host = host_orientations(&s.bytes());
    let packet = |seq: u32, q: [f64; 4]| SegmentOrientation {
        header: SampleHeader::new(2, SegmentId::TibiaR, seq, 0),
        q14: SegmentOrientation::q14_of(q),
        quality: 0,
    };
    let device: Vec<_> = host.iter().map(|((_, seq), q)| packet(*seq, *q)).collect();
    let c = RawCheck::run(&device, &host);
    assert_eq!((c.compared, c.missing, c.unexpected), (200, 0, 0));
    assert!(c.max_deg < 0.01 && c.passed(0.1), "{}", c.report(0.1));
    // One lost, one not owed, one turned by 90° about x.
    let mut bad = device[1..].to_vec();
    bad.push(packet(500, [1.0, 0.0, 0.0, 0.0]));
    let q = host[&(SegmentId::TibiaR, 7)];
    let h = std::f64::consts::FRAC_1_SQRT_2;
    // q ⊗ (cos 45°, sin 45°, 0, 0).
    let turned = [
        h * (q[0] - q[1]),
        h * (q[1] + q[0]),
        h * (q[2] + q[3]),
        h * (q[3] - q[2]),
    ];
    bad[6] = packet(7, turned);
    let c = RawCheck::run(&bad, &host);
    assert_eq!((c.missing, c.unexpected), (1, 1));
    assert!((c.max_deg - 90.0).abs() < 0.02, "{}", c.max_deg);
    assert_eq!(c.worst, Some((SegmentId::TibiaR, 7)));
    assert!(!c.passed(0.1));
    assert!(c.report(0.1).ends_with("FAIL"));
}

#[test]
fn recordings_that_cannot_make_a_stream_are_refused() {
    let (a, short, six) = (
        recording("a", 50, true),
        recording("short", 40, true),
        recording("six", 50, false),
    );
    let new = |sensors: &[(SegmentId, &RawRecording)], fusion| {
        RawStream::new(sensors, fusion, 1, Sensitivities::default())
    };
    assert!(matches!(
        new(&[], FusionMode::NineD),
        Err(RawStreamError::Empty)
    ));
    assert!(matches!(
        new(
            &[(SegmentId::Pelvis, &a), (SegmentId::Pelvis, &a)],
            FusionMode::NineD
        ),
        Err(RawStreamError::DuplicateSegment("pelvis"))
    ));
    assert!(matches!(
        new(
            &[(SegmentId::Pelvis, &a), (SegmentId::Torso, &short)],
            FusionMode::NineD
        ),
        Err(RawStreamError::NotInStep { .. })
    ));
    assert!(matches!(
        new(&[(SegmentId::Pelvis, &six)], FusionMode::NineD),
        Err(RawStreamError::NoMagnetometer(_))
    ));
    let s = new(&[(SegmentId::Pelvis, &six)], FusionMode::SixD).expect("6D needs no magnetometer");
    assert!(s.samples.iter().all(|x| x.mag.is_none()));
}
