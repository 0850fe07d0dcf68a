//! The raw IMU messages: what the sensor's counts cost in accuracy (the figures of protocol.md
//! 4.10, printed with `--nocapture`), the decoder's errors in wire order, the `i16` varint's
//! limits, and the hub's decoding of the tags it does not take.
mod common;

use common::Rng;
use qgait_kernel::{Quat, Vec3};
use qgait_proto::{
    decode_hub_message, decode_message, encode_message, DecodeError, FusionMode, HubMessage,
    Message, RawImuConfig, RawImuSample, RawImuStatus, MAX_MESSAGE_LEN, PROTOCOL_VERSION,
    RAW_IMU_CONFIG_TAG, RAW_IMU_SAMPLE_TAG, RAW_IMU_STATUS_TAG,
};

/// The sensitivities the spec's figures are for: an ICM-20948 (gyroscope at ±2000 °/s,
/// 16.4 counts per °/s; accelerometer at ±16 g, 2048 counts per g; its AK09916 magnetometer,
/// 0.15 µT per count).
fn icm20948() -> RawImuConfig {
    common::raw_imu_config()
}

fn uniform(rng: &mut Rng, half_range: f64) -> f64 {
    (f64::from(rng.next_u32()) / f64::from(u32::MAX) * 2.0 - 1.0) * half_range
}

fn encoded(msg: Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_MESSAGE_LEN];
    encode_message(&msg, &mut buf).expect("encodes").to_vec()
}

/// Each sensor's rounding is at most half a count (in its unit), reached to within 0.1 %.
#[test]
fn a_count_costs_at_most_half_its_sensitivity() {
    let config = icm20948();
    let mut rng = Rng::new(11);
    for (name, per_count) in [
        ("gyroscope rad/s", config.gyro_per_count),
        ("accelerometer m/s^2", config.accel_per_count),
        ("magnetometer uT", config.mag_per_count),
    ] {
        let per_count = f64::from(per_count);
        let mut worst: f64 = 0.0;
        for _ in 0..1_000_000 {
            let value = uniform(&mut rng, 32_000.0 * per_count);
            let count = RawImuSample::count_of(value, per_count);
            worst = worst.max((f64::from(count) * per_count - value).abs());
        }
        println!("{name}: per count {per_count:.6e}, largest rounding {worst:.6e}");
        assert!(worst <= per_count / 2.0 * (1.0 + 1e-9), "{name}: {worst}");
        assert!(worst > per_count / 2.0 * 0.999, "{name}: {worst}");
    }
}

/// `q` rotated on by the body rate `w` (rad/s) for `dt`: `q ⊗ exp(w dt / 2)`, exact for a
/// constant rate.
fn integrate(q: Quat<f64>, w: [f64; 3], dt: f64) -> Quat<f64> {
    let w = Vec3::new(w[0], w[1], w[2]);
    let angle = w.norm() * dt;
    if angle == 0.0 {
        return q;
    }
    let axis = w * (1.0 / w.norm());
    let (s, c) = (angle / 2.0).sin_cos();
    q * Quat::new(c, axis.x * s, axis.y * s, axis.z * s)
}

fn angle_between(a: Quat<f64>, b: Quat<f64>) -> f64 {
    let dot = (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z)
        .abs()
        .min(1.0);
    2.0 * dot.acos()
}

/// One second at 100 Hz integrated from the true rates and from their counts: the angle
/// between the two orientations. `rate(t)` is the true body rate at time `t`.
fn drift_over_a_second(rate: impl Fn(f64) -> [f64; 3], per_count: f64) -> f64 {
    let dt = 0.01;
    let (mut truth, mut wire) = (Quat::identity(), Quat::identity());
    for k in 0..100 {
        let w = rate(f64::from(k) * dt);
        let counts = w.map(|v| RawImuSample::count_of(v, per_count));
        truth = integrate(truth, w, dt);
        wire = integrate(wire, counts.map(|c| f64::from(c) * per_count), dt);
    }
    angle_between(truth, wire)
}

/// The angle the gyroscope's counts cost over a second of integration: at most
/// `√3 / 2` counts' worth of rate for the whole second (a constant rate rounded the same way
/// every sample), much less for a rate that changes (the roundings then cancel).
#[test]
fn a_second_of_integration_costs_at_most_the_documented_angle() {
    let per_count = f64::from(icm20948().gyro_per_count);
    let bound = 3f64.sqrt() / 2.0 * per_count;
    let mut rng = Rng::new(12);
    let (mut worst_constant, mut worst_gait, mut sum_gait) = (0.0f64, 0.0f64, 0.0);
    let trials = 20_000;
    for _ in 0..trials {
        let w = [0; 3].map(|_| uniform(&mut rng, 10.0));
        worst_constant = worst_constant.max(drift_over_a_second(|_| w, per_count));
        // Gait-like: each axis a 1 Hz swing of up to 6 rad/s with a random phase and offset.
        let [a, p, o] = [0; 3].map(|_| [0; 3].map(|_| uniform(&mut rng, 1.0)));
        let gait = |t: f64| {
            [0, 1, 2].map(|i| 6.0 * a[i] * (std::f64::consts::TAU * t + 3.0 * p[i]).sin() + o[i])
        };
        let d = drift_over_a_second(gait, per_count);
        worst_gait = worst_gait.max(d);
        sum_gait += d;
    }
    let deg = 180.0 / std::f64::consts::PI;
    println!(
        "constant rates: largest {:.4} deg (bound {:.4}); gait-like: largest {:.4} deg, mean {:.5} deg",
        worst_constant * deg,
        bound * deg,
        worst_gait * deg,
        sum_gait / f64::from(trials) * deg
    );
    assert!(worst_constant <= bound * (1.0 + 1e-6), "{worst_constant}");
    assert!(worst_constant > bound * 0.8, "{worst_constant}");
    assert!(worst_gait < bound / 4.0, "{worst_gait}");
}

#[test]
fn sensitivities_from_datasheet_units() {
    let c = icm20948();
    assert!((f64::from(c.gyro_per_count) - 1.064_225e-3).abs() < 1e-9);
    assert!((f64::from(c.accel_per_count) - 4.788_403e-3).abs() < 1e-9);
    assert_eq!(
        c.gyro([16, 0, -16]),
        [16.0 * c.gyro_per_count, 0.0, -16.0 * c.gyro_per_count]
    );
    assert_eq!(c.accel([2048, 0, 0])[0], 2048.0 * c.accel_per_count);
    assert_eq!(c.mag([0, 0, 100])[2], 100.0 * c.mag_per_count);
    assert!(c.usable());
    assert!(!RawImuConfig { rate_hz: 0, ..c }.usable());
    assert!(!RawImuConfig {
        output_every: 0,
        ..c
    }
    .usable());
    assert!(!RawImuConfig {
        gyro_per_count: f32::NAN,
        ..c
    }
    .usable());
    assert!(!RawImuConfig {
        accel_per_count: -1.0,
        ..c
    }
    .usable());
    assert!(!RawImuConfig {
        mag_per_count: 0.0,
        ..c
    }
    .usable());
    let six = RawImuConfig {
        fusion: FusionMode::SixD,
        mag_per_count: 0.0,
        ..c
    };
    assert!(
        six.usable(),
        "6D does not read the magnetometer's sensitivity"
    );
}

#[test]
fn counts_round_to_nearest_ties_away_and_saturate() {
    assert_eq!(RawImuSample::count_of(2.5, 1.0), 3);
    assert_eq!(RawImuSample::count_of(-2.5, 1.0), -3);
    assert_eq!(RawImuSample::count_of(2.49, 1.0), 2);
    assert_eq!(RawImuSample::count_of(1e9, 1.0), i16::MAX);
    assert_eq!(RawImuSample::count_of(-1e9, 1.0), i16::MIN);
    assert_eq!(RawImuSample::count_of(f64::NAN, 1.0), 0);
    let mut s = common::raw_imu_sample();
    assert!(!s.saturated());
    s.gyro[1] = i16::MIN;
    assert!(s.saturated());
    s.gyro[1] = 0;
    s.mag = Some([0, i16::MAX, 0]);
    assert!(s.saturated());
}

/// The version first, then the layout, then the segment; the fusion byte is malformed.
#[test]
fn raw_decode_errors_in_wire_order() {
    let good = encoded(common::raw_imu_sample().into());
    assert_eq!(u32::from(good[0]), RAW_IMU_SAMPLE_TAG);
    assert_eq!(
        decode_message(&good),
        Ok(Message::RawImuSample(common::raw_imu_sample()))
    );
    let mut v1 = good.clone();
    v1[1] = 1;
    v1[3] = 9;
    assert_eq!(decode_message(&v1), Err(DecodeError::UnknownVersion(1)));
    let mut segment = good.clone();
    segment[3] = 8;
    assert_eq!(
        decode_message(&segment),
        Err(DecodeError::UnknownSegment(8))
    );
    // A bad segment and a truncated body: the layout comes first.
    assert_eq!(
        decode_message(&segment[..segment.len() - 1]),
        Err(DecodeError::Malformed)
    );
    // The magnetometer's option byte (after 20 bytes) not 0 or 1.
    let mut option = good.clone();
    assert_eq!(option[20], 1);
    option[20] = 2;
    assert_eq!(decode_message(&option), Err(DecodeError::Malformed));
    let mut config = encoded(common::raw_imu_config().into());
    assert_eq!(u32::from(config[0]), RAW_IMU_CONFIG_TAG);
    config[2] = 2;
    assert_eq!(decode_message(&config), Err(DecodeError::Malformed));
    let status = encoded(RawImuStatus::default().into());
    assert_eq!(
        status,
        [RAW_IMU_STATUS_TAG as u8, 0, 0, 0, 0, 0, 0, 0, 0, 0]
    );
    assert_eq!(decode_message(&status[..9]), Err(DecodeError::Malformed));
}

/// An `i16` is the varint of its zigzag value, 1 to 3 bytes, the third at most 0x03.
#[test]
fn i16_varints_and_their_limits() {
    let sample = |gyro0: &[u8]| {
        let mut b = vec![RAW_IMU_SAMPLE_TAG as u8, PROTOCOL_VERSION, 1, 0, 0, 0];
        b.extend_from_slice(gyro0);
        b.extend_from_slice(&[0, 0, 0, 0, 0, 0]);
        decode_message(&b)
    };
    let gyro0 = |r: Result<Message, DecodeError>| match r {
        Ok(Message::RawImuSample(s)) => Ok(s.gyro[0]),
        Ok(other) => panic!("{other:?}"),
        Err(e) => Err(e),
    };
    assert_eq!(gyro0(sample(&[0x00])), Ok(0));
    assert_eq!(gyro0(sample(&[0x01])), Ok(-1));
    assert_eq!(gyro0(sample(&[0x02])), Ok(1));
    assert_eq!(gyro0(sample(&[0x7f])), Ok(-64));
    assert_eq!(gyro0(sample(&[0x80, 0x01])), Ok(64));
    assert_eq!(gyro0(sample(&[0xfe, 0xff, 0x03])), Ok(i16::MAX));
    assert_eq!(gyro0(sample(&[0xff, 0xff, 0x03])), Ok(i16::MIN));
    // A third byte over 0x03 (more than 16 bits), a third byte with bit 7 set: malformed.
    assert_eq!(
        gyro0(sample(&[0xff, 0xff, 0x04])),
        Err(DecodeError::Malformed)
    );
    assert_eq!(
        gyro0(sample(&[0x80, 0x80, 0x80, 0x00])),
        Err(DecodeError::Malformed)
    );
    // A non-shortest form is read (as postcard does).
    assert_eq!(gyro0(sample(&[0x82, 0x00])), Ok(1));
    for v in [
        i16::MIN,
        -8193,
        -8192,
        -65,
        -64,
        0,
        63,
        64,
        8191,
        8192,
        i16::MAX,
    ] {
        let mut s = common::raw_imu_sample();
        s.gyro[0] = v;
        let len = encoded(s.into()).len();
        let base = {
            s.gyro[0] = 0;
            encoded(s.into()).len()
        };
        let zigzag = ((v as i32) << 1 ^ (v as i32) >> 15) as u16;
        let bytes = if zigzag < 1 << 7 {
            1
        } else if zigzag < 1 << 14 {
            2
        } else {
            3
        };
        assert_eq!(len - base + 1, bytes, "{v}");
    }
}

/// A hub takes no raw input: a raw sample or configuration is a message it does not take, a
/// raw status one only a receiver sends; none of their bodies is decoded.
#[test]
fn a_hub_does_not_decode_raw_messages() {
    for (msg, expected) in [
        (
            Message::from(common::raw_imu_sample()),
            HubMessage::NotTaken(RAW_IMU_SAMPLE_TAG),
        ),
        (
            common::raw_imu_config().into(),
            HubMessage::NotTaken(RAW_IMU_CONFIG_TAG),
        ),
        (
            RawImuStatus::default().into(),
            HubMessage::FromHub(RAW_IMU_STATUS_TAG),
        ),
    ] {
        let mut bytes = encoded(msg);
        assert_eq!(decode_hub_message(&bytes), Ok(expected.clone()));
        bytes.truncate(1);
        assert_eq!(decode_hub_message(&bytes), Ok(expected));
    }
    assert_eq!(
        decode_hub_message(&[16]),
        Err(DecodeError::UnknownMessage(16))
    );
    assert_eq!(decode_message(&[16]), Err(DecodeError::UnknownMessage(16)));
}
