//! What the hub does with the messages it does not take (the raw IMU messages, tags 11 to 13)
//! and with a quaternion sent as -q instead of q (protocol.md 4.7 and 4.10).

use qgait_hub::{Hub, ManualClock};
use qgait_hub_checks::imu::{
    calibration_readings, imu_config, model_f64, readings, send_orientations, truth,
};
use qgait_hub_checks::{drain, each_output, send, CheckSerial, STATUS_PERIOD_MS};
use qgait_proto::{
    encode_raw_frame, Config, FusionMode, ImuConfig, InputMode, Message, MissingPolicy, ModelId,
    PoseFrame, RawImuConfig, RawImuSample, RawImuStatus, SampleHeader, SegmentId, Status,
    MAX_FRAME_LEN,
};

fn new_hub(clock: &ManualClock) -> Hub<CheckSerial, &ManualClock> {
    Hub::new(CheckSerial::new(), clock, STATUS_PERIOD_MS).expect("the default model")
}

fn raw_sample(seq: u32) -> RawImuSample {
    RawImuSample {
        header: SampleHeader::new(3, SegmentId::TibiaR, seq, seq * 10_000),
        gyro: [-188, 47, 3289],
        accel: [251, 2005, -84],
        mag: None,
    }
}

fn raw_config() -> RawImuConfig {
    RawImuConfig {
        segments: 0xff,
        fusion: FusionMode::SixD,
        rate_hz: 100,
        output_every: 1,
        gyro_per_count: RawImuConfig::gyro_per_count_of(16.4),
        accel_per_count: RawImuConfig::accel_per_count_of(2048.0),
        mag_per_count: 0.15,
        request_status: true,
    }
}

/// A hub takes no raw input yet: each raw sample and raw configuration is a message it does
/// not take, and a raw status one only a receiver sends, each counted in `malformed` and
/// nothing else; a damaged one is counted where its damage is (its body undecoded); tag 14 is
/// an unknown message. Joint-angle samples around them are computed as ever.
#[test]
#[cfg_attr(
    feature = "raw",
    ignore = "a hub with raw input takes them: tests/raw_input.rs"
)]
fn raw_messages_are_counted_as_not_taken() {
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock);
    let serial = hub.serial_mut();
    assert!(qgait_hub_checks::send_sample(serial, ModelId::Phak, 1));
    assert!(send(serial, &raw_sample(1).into()));
    assert!(send(serial, &raw_config().into()));
    assert!(send(serial, &RawImuStatus::default().into()));
    // A raw sample of an unknown segment and of another version: not decoded, so `malformed`.
    let mut body = [0u8; MAX_FRAME_LEN];
    let mut out = [0u8; MAX_FRAME_LEN];
    let mut len = {
        let bytes = qgait_proto::encode_message(&raw_sample(2).into(), &mut body).expect("fits");
        bytes[3] = 8;
        bytes[1] = 1;
        bytes.len()
    };
    for payload in [&body[..len], &[13u8, 0xff][..], &[12u8][..]] {
        let frame = encode_raw_frame(payload, &mut out).expect("fits");
        assert_eq!(serial.receive(frame), frame.len());
    }
    // Tag 16: unknown.
    len = 2;
    body[..len].copy_from_slice(&[16, 0]);
    let frame = encode_raw_frame(&body[..len], &mut out).expect("fits");
    assert_eq!(serial.receive(frame), frame.len());
    assert!(qgait_hub_checks::send_sample(serial, ModelId::Phak, 2));
    assert!(send(
        serial,
        &Message::Config(Config {
            model: ModelId::Phak,
            anthropometry: None,
            missing_policy: MissingPolicy::Drop,
            reorder_window: 4,
            request_status: true,
        })
    ));
    drain(&mut hub);
    assert_eq!(
        hub.status(),
        Status {
            packets_accepted: 16,
            samples_completed: 2,
            malformed: 6,
            unknown_version: 1,
            frames_sent: 3,
            ..Status::default()
        }
    );
    let mut frames = 0;
    assert_eq!(each_output(&mut hub, |_| frames += 1), 0);
    assert_eq!(frames, 3);
}

/// A node may send q or -q (the same rotation): the hub's frames are the same either way.
#[test]
fn minus_q_gives_the_frames_of_q() {
    let model = model_f64().expect("the generic gait2392");
    for mode in [
        InputMode::OrientationsLeastSquares,
        InputMode::OrientationsClosedForm,
    ] {
        let run = |flip: u8| {
            let clock = ManualClock::new(0);
            let mut hub = new_hub(&clock);
            let serial = hub.serial_mut();
            let negate = |mut r: [[i16; 4]; 8]| {
                for (s, q) in r.iter_mut().enumerate() {
                    if flip & (1 << s) != 0 {
                        *q = q.map(|c| -c);
                    }
                }
                r
            };
            assert!(send(
                serial,
                &Message::Config(Config {
                    model: ModelId::Gait2392,
                    anthropometry: None,
                    missing_policy: MissingPolicy::Drop,
                    reorder_window: 4,
                    request_status: false,
                })
            ));
            assert!(send(serial, &Message::ImuConfig(imu_config(mode, true, 0))));
            let all = ImuConfig::ALL_SEGMENTS;
            assert!(send_orientations(
                serial,
                1,
                &negate(calibration_readings(&model)),
                all
            ));
            for k in 2..12 {
                assert!(send_orientations(
                    serial,
                    k,
                    &negate(readings(&model, &truth(k))),
                    all
                ));
            }
            drain(&mut hub);
            let mut frames: Vec<PoseFrame> = Vec::new();
            each_output(&mut hub, |m| {
                if let Message::PoseFrame(p) = m {
                    frames.push(p.clone());
                }
            });
            frames
        };
        let plain = run(0);
        assert_eq!(plain.len(), 10);
        for flip in [0xff, 0x55, 0x0f, 0x81] {
            assert_eq!(run(flip), plain, "{mode:?}, segments {flip:#04x} negated");
        }
    }
}

/// Mode 0 (protocol.md 4.8): any `segments`, the pelvis included or not, is accepted; the
/// settings and a calibration request are kept for a later orientation mode; non-finite
/// sensor-to-OpenSim angles are rejected (a hub built with the orientation input).
#[test]
fn mode_0_keeps_the_settings_and_a_calibration_request() {
    let model = model_f64().expect("the generic gait2392");
    let clock = ManualClock::new(0);
    let mut hub = new_hub(&clock);
    let serial = hub.serial_mut();
    assert!(send(
        serial,
        &Message::Config(Config {
            model: ModelId::Gait2392,
            anthropometry: None,
            missing_policy: MissingPolicy::Drop,
            reorder_window: 4,
            request_status: false,
        })
    ));
    let joints = ImuConfig {
        segments: 0,
        ..imu_config(InputMode::JointAngles, true, 0)
    };
    assert!(send(serial, &Message::ImuConfig(joints)));
    let nan = ImuConfig {
        sensor_to_opensim: [f32::NAN, 0.0, 0.0],
        calibrate: false,
        ..joints
    };
    assert!(send(serial, &Message::ImuConfig(nan)));
    // The orientation mode without `calibrate`: the request of the mode-0 message stands.
    let orientations = imu_config(InputMode::OrientationsClosedForm, false, 0);
    assert!(send(serial, &Message::ImuConfig(orientations)));
    assert!(send_orientations(
        serial,
        1,
        &calibration_readings(&model),
        ImuConfig::ALL_SEGMENTS
    ));
    assert!(send_orientations(
        serial,
        2,
        &readings(&model, &truth(2)),
        ImuConfig::ALL_SEGMENTS
    ));
    drain(&mut hub);
    let status = hub.status();
    assert_eq!(status.config_rejected, 1, "{status:?}");
    assert_eq!(status.calibrations, 1, "{status:?}");
    assert_eq!(status.uncalibrated_samples, 0, "{status:?}");
    assert_eq!(
        hub.imu_config().sensor_to_opensim,
        orientations.sensor_to_opensim
    );
}
