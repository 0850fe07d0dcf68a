//! The hub's raw input (protocol.md 4.10, feature `raw`): raw samples of eight sensors fused in
//! the hub give exactly the pose frames that the same samples give when each is fused by its
//! own node (the node's `RawInput`, one segment) and sent as `SegmentOrientation`s; and no
//! mix of raw messages and line noise stops the pipeline.
#![cfg(feature = "raw")]

use qgait_hub::raw::{icm20948_config, orientation_packet, RawInput, RawOutcome};
use qgait_hub::{Hub, ManualClock, MemorySerial};
use qgait_hub_checks::{imu, XorShift};
use qgait_proto::{
    encode_frame, segment_bit, FrameDecoder, FusionMode, ImuConfig, InputMode, Message,
    MissingPolicy, PoseFrame, RawImuConfig, RawImuSample, RawImuStatus, SampleHeader, SegmentId,
    Status, MAX_FRAME_LEN,
};

type Serial = MemorySerial<8192, 65_536>;

/// Runs `f` on a thread with room for two hubs and their ports on its stack.
fn with_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

fn send(hub: &mut Hub<Serial, &ManualClock>, message: &Message) {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let frame = encode_frame(message, &mut buf).unwrap();
    assert_eq!(hub.serial_mut().receive(frame), frame.len());
    while hub.serial_mut().pending() > 0 {
        hub.poll();
    }
}

fn outputs(hub: &mut Hub<Serial, &ManualClock>) -> Vec<Message> {
    assert!(!hub.serial_mut().tx_overflowed());
    let mut decoder = FrameDecoder::new();
    let mut out = Vec::new();
    for &b in hub.serial_mut().transmitted() {
        if let Some(m) = decoder.push(b) {
            out.push(m.unwrap());
        }
    }
    out
}

fn poses(hub: &mut Hub<Serial, &ManualClock>) -> Vec<PoseFrame> {
    outputs(hub)
        .into_iter()
        .filter_map(|m| match m {
            Message::PoseFrame(p) => Some(p),
            _ => None,
        })
        .collect()
}

fn imu_config(calibrate: bool) -> Message {
    Message::ImuConfig(imu::imu_config(
        InputMode::OrientationsLeastSquares,
        calibrate,
        0,
    ))
}

fn raw_config(segments: u8, fusion: FusionMode) -> RawImuConfig {
    icm20948_config(segments, fusion)
}

/// Sample `seq` of the sensor on `segment`: at rest but for a slow turn, tilted so that each
/// sensor sees gravity along its own direction (the torso's along its x: its z horizontal,
/// as the heading correction needs), in 9D a constant field.
fn sample(segment: SegmentId, seq: u32) -> RawImuSample {
    let i = segment as i16;
    let up: [i16; 3] = match segment {
        SegmentId::Torso => [2048, 0, 0],
        _ => [300 * (i - 3), 200 - 60 * i, 1900],
    };
    RawImuSample {
        header: SampleHeader::new(
            segment as u8,
            segment,
            seq,
            seq.wrapping_mul(10_000)
                .wrapping_add(u32::from(seq.is_multiple_of(3)) * 7),
        ),
        gyro: [3 - i, 2, (seq % 5) as i16 - 2],
        accel: up,
        mag: Some([150 + 10 * i, -40, 200]),
    }
}

fn hub_for_orientations(clock: &ManualClock) -> Hub<Serial, &ManualClock> {
    let mut hub = Hub::new(Serial::new(), clock, 0).unwrap();
    send(&mut hub, &imu::gait2392_config(MissingPolicy::Drop));
    send(&mut hub, &imu_config(false));
    hub
}

/// Eight raw sensors into the hub, and the same samples through eight node fusions as
/// orientations into another hub: the same pose frames, byte for byte, in 6D and 9D.
#[test]
fn raw_samples_give_the_frames_of_nodes_fusing_the_same_samples() {
    with_stack(raw_samples_give_the_frames_of_nodes_fusing_the_same_samples_body);
}

fn raw_samples_give_the_frames_of_nodes_fusing_the_same_samples_body() {
    for fusion in [FusionMode::SixD, FusionMode::NineD] {
        let clock = ManualClock::new(0);
        let mut raw_hub = hub_for_orientations(&clock);
        let mut smart_hub = hub_for_orientations(&clock);
        send(
            &mut raw_hub,
            &Message::RawImuConfig(raw_config(ImuConfig::ALL_SEGMENTS, fusion)),
        );
        let mut nodes: Vec<RawInput<f32, 1>> = SegmentId::ALL
            .iter()
            .map(|s| {
                let mut node = RawInput::new();
                assert!(node.configure(&raw_config(segment_bit(*s), fusion)));
                node
            })
            .collect();
        let samples = 60;
        for seq in 0..samples {
            if seq == 1 {
                send(&mut raw_hub, &imu_config(true));
                send(&mut smart_hub, &imu_config(true));
            }
            for (segment, node) in SegmentId::ALL.into_iter().zip(&mut nodes) {
                let s = sample(segment, seq);
                send(&mut raw_hub, &Message::RawImuSample(s));
                let RawOutcome::Fused(Some(q)) = node.push(&s) else {
                    panic!("node fusion gave no orientation at {seq}");
                };
                send(
                    &mut smart_hub,
                    &Message::SegmentOrientation(orientation_packet(&s, q)),
                );
            }
        }
        let (raw, smart) = (poses(&mut raw_hub), poses(&mut smart_hub));
        // Sample 0 before the calibration, 1 calibrates.
        assert_eq!(smart.len(), samples as usize - 2, "{fusion:?}");
        assert_eq!(raw, smart, "{fusion:?}");
        let status = raw_hub.raw().status();
        assert_eq!(
            status,
            RawImuStatus {
                samples_accepted: 8 * samples,
                timing_errors: 0,
                ..RawImuStatus::default()
            },
            "{fusion:?}"
        );
        let (a, b) = (raw_hub.status(), smart_hub.status());
        assert_eq!(a.packets_accepted, b.packets_accepted);
        assert_eq!(a.samples_completed, b.samples_completed);
        assert_eq!((a.malformed, a.config_rejected), (0, 0));
    }
}

/// A status request in a `RawImuConfig` is answered with a `Status` and a `RawImuStatus`; an
/// unusable configuration is counted and leaves the one in force.
#[test]
fn raw_config_is_checked_and_answers_status_requests() {
    with_stack(raw_config_is_checked_and_answers_status_requests_body);
}

fn raw_config_is_checked_and_answers_status_requests_body() {
    let clock = ManualClock::new(0);
    let mut hub = hub_for_orientations(&clock);
    let good = raw_config(0b11, FusionMode::SixD);
    send(&mut hub, &Message::RawImuConfig(good));
    let bad = RawImuConfig {
        rate_hz: 0,
        request_status: true,
        ..raw_config(0xff, FusionMode::NineD)
    };
    send(&mut hub, &Message::RawImuConfig(bad));
    assert_eq!(hub.raw().config(), good);
    assert_eq!(hub.status().config_rejected, 1);
    send(
        &mut hub,
        &Message::RawImuSample(sample(SegmentId::Torso, 5)),
    );
    let out = outputs(&mut hub);
    assert!(matches!(
        out[..],
        [
            Message::Status(Status {
                config_rejected: 1,
                ..
            }),
            Message::RawImuStatus(_)
        ]
    ));
    assert_eq!(hub.raw().status().not_configured, 1);
}

/// Raw samples with random segments, sequence numbers and timestamps, random (also unusable)
/// raw configurations, and line noise between frames: the hub never panics, and every raw
/// sample that arrives whole is counted once by the raw input (used, stale or not configured).
#[test]
fn random_raw_streams_never_stop_the_pipeline() {
    with_stack(random_raw_streams_never_stop_the_pipeline_body);
}

fn random_raw_streams_never_stop_the_pipeline_body() {
    for seed in 1..=100u32 {
        let clock = ManualClock::new(0);
        let mut hub = hub_for_orientations(&clock);
        let mut rng = XorShift(seed);
        let mut sent = 0;
        for _ in 0..200 {
            let r = rng.next_u32();
            if r.is_multiple_of(17) {
                let config = RawImuConfig {
                    segments: rng.next_u32() as u8,
                    rate_hz: (rng.next_u32() % 300) as u16,
                    output_every: (rng.next_u32() % 4) as u8,
                    fusion: if r.is_multiple_of(2) {
                        FusionMode::SixD
                    } else {
                        FusionMode::NineD
                    },
                    ..raw_config(0, FusionMode::SixD)
                };
                send(&mut hub, &Message::RawImuConfig(config));
            } else if r.is_multiple_of(13) {
                send(&mut hub, &imu_config(r.is_multiple_of(2)));
            } else if r.is_multiple_of(7) {
                let noise: Vec<u8> = (0..rng.next_u32() % 200)
                    .map(|_| (rng.next_u32() % 255 + 1) as u8)
                    .collect();
                hub.serial_mut().receive(&noise);
                hub.serial_mut().receive(&[0]);
                send(
                    &mut hub,
                    &Message::RawImuSample(sample(SegmentId::Pelvis, 0)),
                );
                sent += 1;
            } else {
                let segment = SegmentId::ALL[(rng.next_u32() % 8) as usize];
                let mut s = sample(segment, rng.next_u32() % 64);
                s.header.timestamp_us = rng.next_u32();
                s.gyro = [
                    rng.next_u32() as i16,
                    rng.next_u32() as i16,
                    rng.next_u32() as i16,
                ];
                s.accel = [
                    rng.next_u32() as i16,
                    rng.next_u32() as i16,
                    rng.next_u32() as i16,
                ];
                s.mag = (!r.is_multiple_of(3))
                    .then(|| [rng.next_u32() as i16, 0, rng.next_u32() as i16]);
                send(&mut hub, &Message::RawImuSample(s));
                sent += 1;
            }
        }
        let s = hub.raw().status();
        assert_eq!(
            s.samples_accepted + s.stale_samples + s.not_configured,
            sent,
            "seed {seed}"
        );
        let _ = outputs(&mut hub);
    }
}

/// A hub built in place (`Hub::init`, as the firmware builds it) starts with no raw segment
/// and takes a raw configuration and samples.
#[test]
fn hub_built_in_place_takes_raw_input() {
    with_stack(hub_built_in_place_takes_raw_input_body);
}

fn hub_built_in_place_takes_raw_input_body() {
    let clock = ManualClock::new(0);
    let mut slot = Box::new(core::mem::MaybeUninit::uninit());
    let hub = Hub::init(&mut slot, Serial::new(), &clock, 0).unwrap();
    assert_eq!(hub.raw().config().segments, 0);
    assert_eq!(hub.raw().status(), RawImuStatus::default());
    send(hub, &Message::RawImuSample(sample(SegmentId::Pelvis, 0)));
    send(
        hub,
        &Message::RawImuConfig(raw_config(0b1, FusionMode::SixD)),
    );
    send(hub, &Message::RawImuSample(sample(SegmentId::Pelvis, 1)));
    let status = hub.raw().status();
    assert_eq!((status.not_configured, status.samples_accepted), (1, 1));
}
