//! The IMU orientation messages: what Q14 costs in accuracy (the figure of the spec), the
//! decoder's errors, and the device model's mapping to the kernel.
mod common;

use qgait_kernel::imu::{ImuError, UNIT_TOLERANCE};
use qgait_kernel::Quat;
use qgait_proto::device_model::{kernel_settings, packet_quat, q14_quat};
use qgait_proto::{
    decode_hub_message, decode_message, encode_message, DecodeError, HeadingAxisId, HubMessage,
    ImuConfig, ImuHeading, InputMode, Message, SampleHeader, SegmentId, SegmentOrientation, Status,
    WireByte, MAX_MESSAGE_LEN, Q14_MAX_ANGLE_ERROR_RAD,
};

fn packet(q14: [i16; 4]) -> SegmentOrientation {
    SegmentOrientation {
        header: SampleHeader::new(1, SegmentId::FemurL, 7, 70_000),
        q14,
        quality: 0,
    }
}

/// The rotation angle between two unit quaternions (radians).
fn angle_between(a: Quat<f64>, b: Quat<f64>) -> f64 {
    let dot = (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z)
        .abs()
        .min(1.0);
    2.0 * dot.acos()
}

/// Uniform random rotations (Shoemake), seeded.
fn random_rotation(rng: &mut common::Rng) -> Quat<f64> {
    let u = |rng: &mut common::Rng| f64::from(rng.next_u32()) / f64::from(u32::MAX);
    let (u1, u2, u3) = (u(rng), u(rng), u(rng));
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    Quat::new(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
}

/// The spec's accuracy figure: a million random rotations through Q14 and back (normalised, as
/// the hub does) move by at most `Q14_MAX_ANGLE_ERROR_RAD`; the measured largest is printed
/// for the spec.
#[test]
fn q14_costs_at_most_its_documented_angle() {
    let mut rng = common::Rng::new(0x5eed_fa11);
    let mut worst = 0.0f64;
    let mut sum = 0.0f64;
    let n = 1_000_000;
    for _ in 0..n {
        let q = random_rotation(&mut rng);
        let wire = SegmentOrientation::q14_of([q.w, q.x, q.y, q.z]);
        let back = packet_quat::<f64>(&packet(wire)).expect("a unit quaternion stays unit");
        let e = angle_between(q, back);
        worst = worst.max(e);
        sum += e;
    }
    println!(
        "Q14: largest rotation error {:.6} deg, mean {:.6} deg over {n} rotations",
        worst.to_degrees(),
        (sum / f64::from(n)).to_degrees()
    );
    assert!(worst <= Q14_MAX_ANGLE_ERROR_RAD, "{worst}");
    // The bound is not loose by an order of magnitude.
    assert!(worst > Q14_MAX_ANGLE_ERROR_RAD / 4.0, "{worst}");
}

#[test]
fn q14_of_rounds_to_nearest_and_saturates() {
    assert_eq!(
        SegmentOrientation::q14_of([1.0, -1.0, 0.5, -0.25]),
        [16384, -16384, 8192, -4096]
    );
    assert_eq!(
        SegmentOrientation::q14_of([0.5 / 16384.0, -0.5 / 16384.0, 0.49 / 16384.0, 0.0]),
        [1, -1, 0, 0]
    );
    assert_eq!(
        SegmentOrientation::q14_of([3.0, -3.0, f64::NAN, 0.0]),
        [i16::MAX, i16::MIN, 0, 0]
    );
    assert_eq!(
        packet(SegmentOrientation::q14_of([1.0, 0.0, 0.0, 0.0])).quaternion(),
        [1.0, 0.0, 0.0, 0.0]
    );
}

/// Nothing is clamped to ±1: a component over 1 is sent as it is, up to 32767 / 16384; q and
/// -q encode to each other's negation (protocol.md 4.7).
#[test]
fn q14_does_not_clamp_and_keeps_the_sign() {
    assert_eq!(
        SegmentOrientation::q14_of([1.00003, -1.00003, 1.5, -1.99]),
        [16384, -16384, 24576, -32604]
    );
    assert_eq!(
        SegmentOrientation::q14_of([1.99998, 0.0, 0.0, 0.0])[0],
        i16::MAX
    );
    assert_eq!(packet([24576, 0, 0, 0]).quaternion(), [1.5, 0.0, 0.0, 0.0]);
    let q = [0.5, -0.5, 0.5, -0.5];
    let minus = q.map(|c: f64| -c);
    assert_eq!(
        SegmentOrientation::q14_of(minus),
        SegmentOrientation::q14_of(q).map(|c| -c)
    );
}

/// A quaternion farther than the kernel's tolerance from unit length is refused (the hub
/// counts it in `orientation_not_unit`); nearer, it is normalised.
#[test]
fn far_from_unit_length_is_refused_near_is_normalised() {
    let zero = packet([0; 4]);
    assert_eq!(
        packet_quat::<f32>(&zero),
        Err(ImuError::NotUnit {
            segment: SegmentId::FemurL
        })
    );
    let long = (16384.0 * (1.0 + UNIT_TOLERANCE) * 1.01) as i16;
    assert!(packet_quat::<f32>(&packet([long, 0, 0, 0])).is_err());
    let near = (16384.0 * (1.0 + UNIT_TOLERANCE) * 0.99) as i16;
    let q = packet_quat::<f64>(&packet([near, 0, 0, 0])).expect("within tolerance");
    assert!((q.norm() - 1.0).abs() < 1e-15);
    assert_eq!(
        q14_quat::<f64>([near, 0, 0, 0]).w,
        f64::from(near) / 16384.0
    );
}

fn encoded(msg: Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_MESSAGE_LEN];
    encode_message(&msg, &mut buf).expect("encodes").to_vec()
}

#[test]
fn orientation_decode_errors_in_wire_order() {
    let good = encoded(packet([16384, 0, 0, 0]).into());
    assert_eq!(good[0], 7, "tag 7");
    // The version first: another version's layout may differ.
    let mut v1 = good.clone();
    v1[1] = 1;
    assert_eq!(decode_message(&v1), Err(DecodeError::UnknownVersion(1)));
    let mut unknown = good.clone();
    unknown[3] = 8;
    assert_eq!(
        decode_message(&unknown),
        Err(DecodeError::UnknownSegment(8))
    );
    // A hub decodes it as `decode_message` does; one without the orientation input does not
    // decode it.
    let hub_unknown = if cfg!(feature = "orientation") {
        Err(DecodeError::UnknownSegment(8))
    } else {
        Ok(HubMessage::NotTaken(7))
    };
    assert_eq!(decode_hub_message(&unknown), hub_unknown);
    let mut status = Status::default();
    status.count_decode_error(&DecodeError::UnknownSegment(8));
    assert_eq!(status.unknown_joint, 1);
    // Truncated and over-long bodies are malformed.
    assert_eq!(
        decode_message(&good[..good.len() - 1]),
        Err(DecodeError::Malformed)
    );
    let mut long = good.clone();
    long.push(0);
    assert_eq!(decode_message(&long), Err(DecodeError::Malformed));
    #[cfg(feature = "orientation")]
    assert_eq!(
        decode_hub_message(&good),
        Ok(HubMessage::SegmentOrientation(packet([16384, 0, 0, 0])))
    );
    #[cfg(not(feature = "orientation"))]
    assert_eq!(decode_hub_message(&good), Ok(HubMessage::NotTaken(7)));
}

#[test]
fn imu_config_decodes_and_refuses_unknown_values() {
    let config = ImuConfig {
        mode: InputMode::OrientationsClosedForm,
        segments: 0x7f,
        calibrate: false,
        sensor_to_opensim: [0.0, 0.5, -0.25],
        heading: Some(ImuHeading {
            base: SegmentId::Pelvis,
            axis: HeadingAxisId::NegX,
        }),
        request_status: true,
    };
    let good = encoded(config.into());
    assert_eq!(good[0], 8, "tag 8");
    assert_eq!(decode_hub_message(&good), Ok(HubMessage::ImuConfig(config)));
    let mut mode = good.clone();
    mode[1] = 3;
    assert_eq!(decode_message(&mode), Err(DecodeError::Malformed));
    // tag, mode, segments, calibrate, 12 bytes of angles, option tag, base, axis, request.
    let mut base = good.clone();
    base[17] = 9;
    assert_eq!(decode_message(&base), Err(DecodeError::UnknownSegment(9)));
    let mut axis = good.clone();
    axis[18] = 6;
    assert_eq!(decode_message(&axis), Err(DecodeError::Malformed));
}

/// The protocol's stable numbering (protocol.md 4.7 and 4.8), whatever the kernel's order: each
/// one's wire byte is its place here.
const SEGMENTS_BY_BYTE: [SegmentId; 8] = {
    use SegmentId::*;
    [
        Pelvis, FemurR, TibiaR, CalcnR, FemurL, TibiaL, CalcnL, Torso,
    ]
};
const AXES_BY_BYTE: [HeadingAxisId; 6] = {
    use HeadingAxisId::*;
    [X, NegX, Y, NegY, Z, NegZ]
};

/// `message` encoded by the crate and by postcard itself (the reference): the same bytes, which
/// decode back to it both ways.
fn encoded_both_ways(message: &Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_MESSAGE_LEN];
    let ours = encode_message(message, &mut buf).unwrap().to_vec();
    let mut reference = [0u8; MAX_MESSAGE_LEN];
    assert_eq!(
        postcard::to_slice(message, &mut reference).unwrap(),
        &ours[..]
    );
    assert_eq!(decode_message(&ours).as_ref(), Ok(message));
    assert_eq!(postcard::from_bytes::<Message>(&ours).as_ref(), Ok(message));
    ours
}

#[test]
fn segments_and_heading_axes_have_stable_wire_bytes() {
    assert_eq!(SegmentId::ALL.len(), SEGMENTS_BY_BYTE.len());
    assert_eq!(HeadingAxisId::ALL.len(), AXES_BY_BYTE.len());
    for (byte, segment) in (0u8..).zip(SEGMENTS_BY_BYTE) {
        assert_eq!(segment.wire_byte(), byte);
        assert_eq!(SegmentId::from_wire_byte(byte), Some(segment));
        // tag, version, node, segment: by hand and through postcard's serialiser.
        let mut orientation = packet([16384, 0, 0, 0]);
        orientation.header.segment = segment;
        assert_eq!(
            encoded_both_ways(&Message::SegmentOrientation(orientation))[3],
            byte
        );
        let raw = qgait_proto::RawImuSample {
            header: SampleHeader::new(0, segment, 0, 0),
            gyro: [0; 3],
            accel: [0; 3],
            mag: None,
        };
        assert_eq!(encoded_both_ways(&Message::RawImuSample(raw))[3], byte);
        for (axis_byte, axis) in (0u8..).zip(AXES_BY_BYTE) {
            assert_eq!(axis.wire_byte(), axis_byte);
            assert_eq!(HeadingAxisId::from_wire_byte(axis_byte), Some(axis));
            let config = ImuConfig {
                mode: InputMode::OrientationsClosedForm,
                segments: ImuConfig::ALL_SEGMENTS,
                calibrate: false,
                sensor_to_opensim: [0.0; 3],
                heading: Some(ImuHeading {
                    base: segment,
                    axis,
                }),
                request_status: false,
            };
            // tag, mode, segments, calibrate, 12 bytes of angles, option tag, base, axis.
            assert_eq!(
                encoded_both_ways(&Message::ImuConfig(config))[17..19],
                [byte, axis_byte]
            );
        }
    }
    for byte in 8..=255 {
        assert_eq!(SegmentId::from_wire_byte(byte), None);
    }
    for byte in 6..=255 {
        assert_eq!(HeadingAxisId::from_wire_byte(byte), None);
    }
    // An unknown byte is refused by postcard's deserialiser too.
    let mut bytes = encoded_both_ways(&Message::SegmentOrientation(packet([16384, 0, 0, 0])));
    bytes[3] = 8;
    assert!(postcard::from_bytes::<Message>(&bytes).is_err());
}

#[test]
fn the_wire_settings_are_the_kernels() {
    let config = ImuConfig {
        mode: InputMode::OrientationsLeastSquares,
        segments: ImuConfig::ALL_SEGMENTS,
        calibrate: true,
        sensor_to_opensim: [-std::f32::consts::FRAC_PI_2, 0.0, 0.0],
        heading: Some(ImuHeading {
            base: SegmentId::Torso,
            axis: HeadingAxisId::Z,
        }),
        request_status: false,
    };
    let settings = kernel_settings::<f64>(&config);
    let tutorial = qgait_kernel::imu::Settings::<f64>::opensense_tutorial();
    assert_eq!(settings.heading, tutorial.heading);
    assert!((settings.sensor_to_opensim[0] - tutorial.sensor_to_opensim[0]).abs() < 1e-7);
}
