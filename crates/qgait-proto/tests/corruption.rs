//! Every corruption class is reported with the right error kind, and the next good frame still
//! decodes.
mod common;

use common::{code_positions, decode_all, frame, Rng};
use qgait_proto::{
    encode_frame, encode_raw_frame, DecodeError, ErrorKind, FrameDecoder, JointAngle, JointId,
    Message, ModelId, MAX_FRAME_LEN, PROTOCOL_VERSION,
};

fn good_a() -> Message {
    common::joint_angle(41, JointId::HipFlexionL, 0.25).into()
}

fn good_b() -> Message {
    common::pose_frame(42, ModelId::Hak).into()
}

fn good_c() -> Message {
    common::status().into()
}

/// Decodes `bad` followed by the frame of `next` on a fresh decoder; returns the errors and
/// checks that `next` is the one and last message decoded.
fn errors_then_next(bad: &[u8], next: &Message) -> Vec<DecodeError> {
    let mut stream = bad.to_vec();
    stream.extend(frame(next));
    let results = decode_all(&mut FrameDecoder::new(), &stream);
    let (last, errors) = results.split_last().expect("at least the good frame");
    assert_eq!(last, &Ok(next.clone()), "next good frame after {bad:02x?}");
    errors
        .iter()
        .map(|r| r.clone().expect_err("only errors before the good frame"))
        .collect()
}

fn raw_frame(payload: &[u8]) -> Vec<u8> {
    let mut buf = [0u8; 512];
    encode_raw_frame(payload, &mut buf).expect("fits").to_vec()
}

#[test]
fn bit_flip_in_a_data_byte_is_a_crc_error() {
    for msg in common::every_message() {
        let good = frame(&msg);
        let body_len = good.len() - 1;
        let codes = code_positions(&good[..body_len]);
        for pos in (0..body_len).filter(|p| !codes.contains(p)) {
            for bit in 0..8 {
                let mut bad = good.clone();
                bad[pos] ^= 1 << bit;
                if bad[pos] == 0 {
                    continue; // a new delimiter: see bit_flip_to_zero_splits_the_frame
                }
                assert_eq!(
                    errors_then_next(&bad, &good_b()),
                    vec![DecodeError::Crc],
                    "pos {pos} bit {bit}"
                );
            }
        }
    }
}

#[test]
fn two_bit_flips_in_data_bytes_are_crc_errors() {
    let good = frame(&good_a());
    let body_len = good.len() - 1;
    let codes = code_positions(&good[..body_len]);
    let bits: Vec<(usize, u8)> = (0..body_len)
        .filter(|p| !codes.contains(p))
        .flat_map(|p| (0..8).map(move |b| (p, b)))
        .collect();
    for (i, &(p1, b1)) in bits.iter().enumerate() {
        for &(p2, b2) in &bits[i + 1..] {
            let mut bad = good.clone();
            bad[p1] ^= 1 << b1;
            bad[p2] ^= 1 << b2;
            if bad[p1] == 0 || bad[p2] == 0 {
                continue;
            }
            assert_eq!(errors_then_next(&bad, &good_c()), vec![DecodeError::Crc]);
        }
    }
}

#[test]
fn bit_flip_in_a_code_byte_is_a_framing_or_crc_error() {
    for msg in common::every_message() {
        let good = frame(&msg);
        let body_len = good.len() - 1;
        let mut kinds = Vec::new();
        for pos in code_positions(&good[..body_len]) {
            for bit in 0..8 {
                let mut bad = good.clone();
                bad[pos] ^= 1 << bit;
                if bad[pos] == 0 {
                    continue;
                }
                let errors = errors_then_next(&bad, &good_a());
                assert_eq!(errors.len(), 1, "pos {pos} bit {bit}: {errors:?}");
                assert!(
                    matches!(errors[0], DecodeError::Cobs | DecodeError::Crc),
                    "{errors:?}"
                );
                kinds.push(errors[0]);
            }
        }
        assert!(
            kinds.contains(&DecodeError::Cobs),
            "a code byte pointing past the end is Cobs"
        );
    }
}

#[test]
fn bit_flip_to_zero_splits_the_frame_into_reported_fragments() {
    let good = frame(&good_b());
    let mut bad = good.clone();
    let pos = good.len() / 2;
    bad[pos] = 0;
    let errors = errors_then_next(&bad, &good_a());
    assert!(!errors.is_empty() && errors.len() <= 2, "{errors:?}");
    for e in errors {
        assert!(
            matches!(
                e,
                DecodeError::Cobs | DecodeError::Crc | DecodeError::TooShort
            ),
            "{e:?}"
        );
    }
}

/// Truncation keeping the delimiter: cut inside a COBS block it is a framing error; cut at a
/// block boundary the COBS is valid, so it is TooShort (under 5 bytes) or a CRC error.
#[test]
fn truncation_is_reported_and_the_next_frame_decodes() {
    for msg in common::every_message() {
        let good = frame(&msg);
        let body = &good[..good.len() - 1];
        let codes = code_positions(body);
        for keep in 1..body.len() {
            let mut bad = body[..keep].to_vec();
            bad.push(0);
            let block_end = codes.contains(&keep);
            let expected = if !block_end {
                DecodeError::Cobs
            } else if keep - 1 < qgait_proto::MIN_PAYLOAD_LEN {
                DecodeError::TooShort
            } else {
                DecodeError::Crc
            };
            assert_eq!(
                errors_then_next(&bad, &good_c()),
                vec![expected],
                "keep {keep} of {}",
                body.len()
            );
        }
    }
}

/// A frame that lost its delimiter runs into the next frame: the merged frame is one CRC error
/// (both frames are lost) and the frame after decodes.
#[test]
fn missing_delimiter_costs_the_merged_frames_only() {
    let a = frame(&good_a());
    let mut stream = a[..a.len() - 1].to_vec();
    stream.extend(frame(&good_b()));
    assert_eq!(errors_then_next(&stream, &good_c()), vec![DecodeError::Crc]);
}

/// With an extra 0x00 before each frame (allowed: empty frames are skipped) a lost delimiter
/// costs nothing.
#[test]
fn leading_delimiter_makes_a_lost_delimiter_harmless() {
    let a = frame(&good_a());
    let mut stream = vec![0];
    stream.extend_from_slice(&a[..a.len() - 1]);
    stream.push(0);
    stream.extend(frame(&good_b()));
    let results = decode_all(&mut FrameDecoder::new(), &stream);
    assert_eq!(results, vec![Ok(good_a()), Ok(good_b())]);
}

#[test]
fn oversize_is_reported_once_then_resynchronises() {
    let mut rng = Rng::new(7);
    for extra in [1usize, 2, 50, 1000, 10_000] {
        let garbage: Vec<u8> = (0..MAX_FRAME_LEN - 1 + extra)
            .map(|_| rng.byte() | 1)
            .collect();
        let mut bad = garbage.clone();
        bad.push(0);
        assert_eq!(
            errors_then_next(&bad, &good_b()),
            vec![DecodeError::Oversize],
            "extra {extra}"
        );
        // A real frame too long to be one (e.g. from a future version): the same.
        let mut buf = vec![0u8; 2 * garbage.len() + 16];
        let long = encode_raw_frame(&garbage, &mut buf).expect("fits").to_vec();
        assert_eq!(
            errors_then_next(&long, &good_a()),
            vec![DecodeError::Oversize]
        );
    }
}

#[test]
fn wrong_version_is_unknown_version() {
    for version in [
        0u8,
        PROTOCOL_VERSION - 1,
        PROTOCOL_VERSION + 1,
        0x7F,
        0x80,
        0xFF,
    ] {
        let msg = Message::JointAngle(JointAngle {
            version,
            ..common::joint_angle(9, JointId::KneeAngleL, -1.0)
        });
        let errors = errors_then_next(&frame(&msg), &good_a());
        assert_eq!(errors, vec![DecodeError::UnknownVersion(version)]);
        assert_eq!(errors[0].kind(), ErrorKind::UnknownVersion);
    }
}

#[test]
fn unknown_version_is_reported_even_if_the_rest_differs() {
    // A packet of the next version may have another layout: only its first body byte is
    // looked at.
    let next = PROTOCOL_VERSION + 1;
    let errors = errors_then_next(
        &raw_frame(&[0x00, next, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF]),
        &good_a(),
    );
    assert_eq!(errors, vec![DecodeError::UnknownVersion(next)]);
}

#[test]
fn unknown_joint_is_unknown_joint() {
    for joint in [17u8, 18, 0x7F, 0x80, 0xFF] {
        // tag 0, version, node 3, joint, seq 5, timestamp 300 (0xAC 0x02), angle 1.0, quality 0
        let payload = [
            0x00,
            PROTOCOL_VERSION,
            0x03,
            joint,
            0x05,
            0xAC,
            0x02,
            0x00,
            0x00,
            0x80,
            0x3F,
            0x00,
        ];
        let errors = errors_then_next(&raw_frame(&payload), &good_c());
        assert_eq!(errors, vec![DecodeError::UnknownJoint(joint)]);
        assert_eq!(errors[0].kind(), ErrorKind::UnknownJoint);
        // The same payload with a known joint decodes: the error is about the joint alone.
        let mut ok = payload;
        ok[3] = JointId::KneeAngleR.index();
        let results = decode_all(&mut FrameDecoder::new(), &raw_frame(&ok));
        assert!(
            matches!(&results[..], [Ok(Message::JointAngle(j))] if j.joint == JointId::KneeAngleR && j.timestamp_us == 300)
        );
    }
}

#[test]
fn garbage_between_frames_is_reported_and_costs_at_most_the_frame_it_runs_into() {
    let mut rng = Rng::new(2026);
    for round in 0..500 {
        let len = 1 + rng.below(if round % 10 == 0 { 600 } else { 40 });
        let zero_percent = [0u32, 2, 10, 50][round % 4];
        let garbage: Vec<u8> = (0..len)
            .map(|_| {
                if rng.chance(zero_percent) {
                    0
                } else {
                    rng.byte()
                }
            })
            .collect();
        for resync in [false, true] {
            let mut stream = frame(&good_a());
            stream.extend_from_slice(&garbage);
            if resync {
                stream.push(0);
            }
            stream.extend(frame(&good_b()));
            stream.extend(frame(&good_c()));
            let results = decode_all(&mut FrameDecoder::new(), &stream);
            let oks: Vec<&Message> = results.iter().filter_map(|r| r.as_ref().ok()).collect();
            let errors: Vec<&DecodeError> =
                results.iter().filter_map(|r| r.as_ref().err()).collect();
            let b_survives = resync || garbage.last() == Some(&0);
            let expected: Vec<Message> = if b_survives {
                vec![good_a(), good_b(), good_c()]
            } else {
                vec![good_a(), good_c()]
            };
            assert_eq!(
                oks.into_iter().cloned().collect::<Vec<_>>(),
                expected,
                "round {round} {garbage:02x?}"
            );
            assert_eq!(results.first(), Some(&Ok(good_a())));
            assert_eq!(results.last(), Some(&Ok(good_c())));
            if garbage.iter().any(|&b| b != 0) {
                assert!(
                    !errors.is_empty(),
                    "garbage must be reported: {garbage:02x?}"
                );
            }
            for e in errors {
                assert!(
                    matches!(
                        e,
                        DecodeError::Cobs
                            | DecodeError::Crc
                            | DecodeError::TooShort
                            | DecodeError::Oversize
                    ),
                    "random garbage fails framing or CRC, got {e:?}"
                );
            }
        }
    }
}

#[test]
fn bad_contents_with_a_good_crc_are_reported_by_kind() {
    use DecodeError::*;
    let cases: Vec<(&str, Vec<u8>, DecodeError)> = vec![
        ("unknown tag 20", vec![0x14], UnknownMessage(20)),
        ("empty segment orientation body", vec![0x07], Malformed),
        (
            "unknown tag 200 (two-byte varint)",
            vec![0xC8, 0x01, 0x00],
            UnknownMessage(200),
        ),
        (
            "tag varint too long",
            vec![0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x01],
            Malformed,
        ),
        (
            "joint angle body cut short",
            vec![0x00, PROTOCOL_VERSION, 0x03, 0x06],
            Malformed,
        ),
        (
            "joint angle with a trailing byte",
            vec![
                0x00,
                PROTOCOL_VERSION,
                0x03,
                0x06,
                0x05,
                0x05,
                0,
                0,
                0,
                0,
                0,
                0xEE,
            ],
            Malformed,
        ),
        ("empty status body", vec![0x02], Malformed),
        (
            "pose frame of unknown model 4",
            pose_payload(4, 6),
            UnknownModel(4),
        ),
        (
            "HAK pose frame with 5 angles",
            pose_payload(0, 5),
            AngleCount {
                expected: 6,
                got: 5,
            },
        ),
        (
            "pose frame with 18 angles (over capacity)",
            pose_payload(2, 18),
            Malformed,
        ),
        (
            "config of unknown model 9",
            vec![0x03, 9, 0, 0, 4, 1],
            UnknownModel(9),
        ),
        (
            "config with option tag 2",
            vec![0x03, 1, 2, 0, 4, 1],
            Malformed,
        ),
        (
            "config with missing policy 2",
            vec![0x03, 1, 0, 2, 4, 1],
            Malformed,
        ),
        ("config with bool 2", vec![0x03, 1, 0, 0, 4, 2], Malformed),
        ("subject leg of leg 2", subject_leg_payload(2), Malformed),
        (
            "subject leg one float short",
            subject_leg_payload(0)[..130].to_vec(),
            Malformed,
        ),
        (
            "subject knee of direction 2",
            subject_knee_payload(0, 2, 3),
            Malformed,
        ),
        (
            "subject knee with 13 knots (over capacity)",
            subject_knee_payload(1, 0, 13),
            Malformed,
        ),
        (
            "subject config with missing policy 2",
            vec![0x06, 7, 2, 4, 0],
            Malformed,
        ),
        (
            "subject config with a trailing byte",
            vec![0x06, 7, 0, 4, 0, 0],
            Malformed,
        ),
    ];
    for (what, payload, expected) in cases {
        assert_eq!(
            errors_then_next(&raw_frame(&payload), &good_a()),
            vec![expected],
            "{what}"
        );
    }
    // A valid config, for contrast with the cases above.
    let results = decode_all(&mut FrameDecoder::new(), &raw_frame(&[0x03, 1, 0, 0, 4, 1]));
    assert!(
        matches!(&results[..], [Ok(Message::Config(c))] if c.model == ModelId::Phak && c.request_status)
    );
}

/// Message bytes of a pose frame with `count` angles, all values 0.
fn pose_payload(model: u8, count: u8) -> Vec<u8> {
    // tag, seq 5, timestamp 50 000 µs (`d0 86 03`), model, angle count
    let mut p = vec![0x01, 0x05, 0xd0, 0x86, 0x03, model, count];
    p.extend(std::iter::repeat_n(
        0u8,
        4 * count as usize + 4 * 24 + 4 * 3,
    ));
    p.push(0);
    p
}

#[test]
fn frames_shorter_than_tag_and_crc_are_too_short() {
    for payload_len in 0..4usize {
        // COBS of 1 to 4 non-zero bytes (no CRC at all).
        let mut bad = vec![payload_len as u8 + 1];
        bad.extend(std::iter::repeat_n(0x11, payload_len));
        bad.push(0);
        assert_eq!(
            errors_then_next(&bad, &good_b()),
            vec![DecodeError::TooShort]
        );
    }
    // Tag plus CRC but the payload is only the CRC of nothing: 4 bytes, too short.
    assert_eq!(
        errors_then_next(&raw_frame(&[]), &good_b()),
        vec![DecodeError::TooShort]
    );
}

#[test]
fn encode_frame_rejects_a_short_buffer_and_a_wrong_angle_count() {
    use qgait_proto::EncodeError;
    let msg = good_b();
    let full = frame(&msg);
    for size in 0..full.len() {
        let mut buf = vec![0u8; size];
        assert!(
            matches!(
                encode_frame(&msg, &mut buf),
                Err(EncodeError::BufferTooSmall { .. })
            ),
            "size {size}"
        );
    }
    let mut pose = common::pose_frame(1, ModelId::Phak);
    pose.angles.pop();
    let mut buf = [0u8; MAX_FRAME_LEN];
    assert_eq!(
        encode_frame(&pose.into(), &mut buf),
        Err(EncodeError::AngleCount {
            expected: 8,
            got: 7
        })
    );
}

/// Message bytes of a subject leg part for `leg`, every number 0.
fn subject_leg_payload(leg: u8) -> Vec<u8> {
    let mut p = vec![0x04, 7, leg];
    p.extend(std::iter::repeat_n(0u8, 33 * 4));
    p
}

/// Message bytes of a subject knee part with `count` knots, every number 0.
fn subject_knee_payload(leg: u8, direction: u8, count: u8) -> Vec<u8> {
    let mut p = vec![0x05, 7, leg, direction, count];
    p.extend(std::iter::repeat_n(0u8, 8 * count as usize));
    p
}
