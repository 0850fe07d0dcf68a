//! The hub's own entry points against the general ones: [`decode_hub_message`] decodes what a
//! hub takes as [`decode_message`] does (and reports a pose frame or a status by its tag only),
//! [`encode_status_frame`] writes [`encode_frame`]'s bytes.
mod common;

use common::{random, strategies, Rng};
use proptest::prelude::*;
use qgait_proto::{
    decode_hub_message, decode_message, encode_frame, encode_message, encode_status_frame,
    DecodeError, EncodeError, HubMessage, Message, MAX_FRAME_LEN, MAX_MESSAGE_LEN,
};

/// The message tag at the start of `bytes` as postcard reads it (a varint), if any.
fn tag(bytes: &[u8]) -> Option<u32> {
    postcard::take_from_bytes::<u32>(bytes)
        .ok()
        .map(|(tag, _)| tag)
}

/// The message encoded (floats as bits, so NaN payloads count).
fn encoded(msg: &Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_MESSAGE_LEN];
    encode_message(msg, &mut buf).expect("encodes").to_vec()
}

/// `msg` as postcard serialises it (whatever its angle count).
fn postcard_bytes(msg: &Message) -> Vec<u8> {
    let mut buf = [0u8; 4 * MAX_MESSAGE_LEN];
    postcard::to_slice(msg, &mut buf).expect("fits").to_vec()
}

/// Round `round` of a mutation test: random bytes every fourth round, else the mutated
/// encoding of a random message.
fn mutated_or_random(rng: &mut Rng, round: u32) -> Vec<u8> {
    let mut bytes = if round.is_multiple_of(4) {
        (0..rng.below(40)).map(|_| rng.byte()).collect()
    } else {
        encoded(&random::message(rng))
    };
    random::mutate(rng, &mut bytes);
    bytes
}

/// Checks [`decode_hub_message`] of `bytes` against [`decode_message`] of the same bytes.
fn check_hub_decoding(bytes: &[u8]) -> Result<(), String> {
    let general = decode_message(bytes);
    let hub = decode_hub_message(bytes);
    let ok = match (&general, &hub) {
        (Ok(Message::JointAngle(a)), Ok(HubMessage::JointAngle(b))) => {
            encoded(&Message::JointAngle(*a)) == encoded(&Message::JointAngle(*b))
        }
        (Ok(Message::Config(a)), Ok(HubMessage::Config(b))) => {
            encoded(&Message::Config(*a)) == encoded(&Message::Config(*b))
        }
        (Ok(Message::SubjectLeg(a)), Ok(HubMessage::SubjectLeg(b))) => {
            encoded(&Message::SubjectLeg(*a)) == encoded(&Message::SubjectLeg(*b))
        }
        (Ok(Message::SubjectKnee(a)), Ok(HubMessage::SubjectKnee(b))) => {
            encoded(&Message::SubjectKnee(a.clone())) == encoded(&Message::SubjectKnee(b.clone()))
        }
        (Ok(Message::SubjectConfig(a)), Ok(HubMessage::SubjectConfig(b))) => a == b,
        #[cfg(feature = "orientation")]
        (Ok(Message::SegmentOrientation(a)), Ok(HubMessage::SegmentOrientation(b))) => a == b,
        (Ok(Message::VelocityConfig(a)), Ok(HubMessage::VelocityConfig(b))) => a == b,
        (Ok(Message::ImuConfig(a)), Ok(HubMessage::ImuConfig(b))) => {
            encoded(&Message::ImuConfig(*a)) == encoded(&Message::ImuConfig(*b))
        }
        // A hub without the `orientation` feature reports a segment orientation by its tag,
        // undecoded, one without `chain` a chain message, and every hub a raw sample or
        // configuration.
        (_, Ok(HubMessage::NotTaken(t))) => {
            (cfg!(not(feature = "orientation")) && *t == 7
                || cfg!(not(feature = "chain")) && (9..=10).contains(t)
                || (11..=12).contains(t))
                && tag(bytes) == Some(*t)
        }
        #[cfg(feature = "chain")]
        (Ok(Message::ChainTable(a)), Ok(HubMessage::ChainTable(b))) => a == b,
        #[cfg(feature = "chain")]
        (Ok(Message::ChainTableConfig(a)), Ok(HubMessage::ChainTableConfig(b))) => a == b,
        // A pose frame or a status, well-formed or not, is reported by its tag.
        (Ok(Message::PoseFrame(_)), Ok(HubMessage::FromHub(1)))
        | (Ok(Message::Status(_)), Ok(HubMessage::FromHub(2)))
        | (Ok(Message::RawImuStatus(_)), Ok(HubMessage::FromHub(13)))
        | (Ok(Message::PoseVelocities(_)), Ok(HubMessage::FromHub(15))) => true,
        (Err(_), Ok(HubMessage::FromHub(t))) => {
            matches!(*t, 1 | 2 | 13 | 15) && tag(bytes) == Some(*t)
        }
        // Without the `orientation` or `chain` feature their tags never reach an error
        // (`NotTaken`).
        (Err(a), Err(b)) => {
            a == b
                && !matches!(tag(bytes), Some(1 | 2 | 11..=13 | 15))
                && (cfg!(feature = "orientation") || tag(bytes) != Some(7))
                && (cfg!(feature = "chain") || !matches!(tag(bytes), Some(9..=10)))
        }
        _ => false,
    };
    if ok {
        Ok(())
    } else {
        Err(format!("{bytes:02x?}: {general:?} vs {hub:?}"))
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 5000, ..ProptestConfig::default() })]

    #[test]
    fn hub_decoding_of_valid_messages_is_decode_message(msg in strategies::message()) {
        let bytes = encoded(&msg);
        check_hub_decoding(&bytes).map_err(TestCaseError::fail)?;
        let from_hub = matches!(
            msg,
            Message::PoseFrame(_)
                | Message::Status(_)
                | Message::RawImuStatus(_)
                | Message::PoseVelocities(_)
        );
        prop_assert_eq!(
            from_hub,
            matches!(decode_hub_message(&bytes), Ok(HubMessage::FromHub(_)))
        );
    }

    /// The status frame is `encode_frame`'s, byte for byte, in buffers of every size (too small
    /// ones refused alike).
    #[test]
    fn status_frame_is_encode_frames(status in strategies::status(), size in 0usize..MAX_FRAME_LEN + 4) {
        let mut a = vec![0u8; size];
        let mut b = vec![0u8; size];
        let fast = encode_status_frame(&status, &mut a).map(|f| f.to_vec());
        let reference = encode_frame(&Message::Status(status), &mut b).map(|f| f.to_vec());
        prop_assert_eq!(&fast, &reference);
        if size >= MAX_FRAME_LEN {
            prop_assert!(fast.is_ok());
        } else if let Err(e) = fast {
            let too_small = matches!(e, EncodeError::BufferTooSmall { .. });
            prop_assert!(too_small);
        }
    }
}

/// Mutated encodings of every message and plain random bytes: the same results as
/// `decode_message` for what a hub takes, the tag alone for pose frames and statuses.
#[test]
fn hub_decoding_of_mutated_and_random_bytes_is_decode_message() {
    let mut rng = Rng::new(0x4855_4221);
    let mut from_hub_errors = 0;
    for round in 0..200_000 {
        let bytes = mutated_or_random(&mut rng, round);
        check_hub_decoding(&bytes).unwrap();
        if decode_message(&bytes).is_err()
            && matches!(decode_hub_message(&bytes), Ok(HubMessage::FromHub(_)))
        {
            from_hub_errors += 1;
        }
    }
    // The mutations do reach ill-formed pose frames and statuses.
    assert!(from_hub_errors > 100, "{from_hub_errors}");
}

#[test]
fn hub_decoding_errors_are_decode_messages() {
    for (bytes, error) in [
        (&[][..], DecodeError::Malformed),
        (&[0x14][..], DecodeError::UnknownMessage(20)),
        (&[0x80, 0x00, 0x04][..], DecodeError::UnknownVersion(4)),
        (&[0x03, 0x09][..], DecodeError::Malformed),
    ] {
        assert_eq!(decode_hub_message(bytes), Err(error), "{bytes:02x?}");
        assert_eq!(
            decode_message(bytes).map(|_| ()),
            Err(error),
            "{bytes:02x?}"
        );
    }
    // A status and a pose frame whose bodies are cut short: only their tags are read.
    assert_eq!(
        decode_hub_message(&[0x02, 0x05]),
        Ok(HubMessage::FromHub(2))
    );
    assert_eq!(
        decode_hub_message(&[0x81, 0x00]),
        Ok(HubMessage::FromHub(1))
    );
}

/// The decoders read every body field by field; postcard's own deserialiser of the public
/// types (their serde derives, whole) is the reference: on mutated encodings of every message
/// and random bytes, a message one decodes the other decodes to the same bytes, and what
/// postcard refuses is refused. The only messages postcard takes and the protocol refuses
/// are a joint-angle, segment-orientation or raw sample packet of another version and a pose frame
/// with another angle count.
#[test]
fn field_by_field_decoding_is_postcards() {
    let mut rng = Rng::new(0x5053_4344);
    let mut decoded = 0;
    for round in 0..200_000 {
        let bytes = mutated_or_random(&mut rng, round);
        let ours = decode_message(&bytes);
        // Every byte used, as the protocol requires.
        let reference = match postcard::take_from_bytes::<Message>(&bytes) {
            Ok((m, [])) => Ok(m),
            Ok(_) => Err(postcard::Error::DeserializeBadEncoding),
            Err(e) => Err(e),
        };
        match (&ours, &reference) {
            (Ok(a), Ok(b)) => {
                assert_eq!(encoded(a), postcard_bytes(b), "{bytes:02x?}");
                decoded += 1;
            }
            (Ok(a), Err(_)) => panic!("{bytes:02x?}: {a:?} refused by postcard"),
            // postcard reads the enum fields (joint, model, leg, ...) as varints where the wire
            // has one raw byte: it is the reference for the bytes it would write itself.
            (Err(e), Ok(b)) if postcard_bytes(b) == bytes => assert!(
                matches!(
                    (e, b),
                    (DecodeError::UnknownVersion(_), Message::JointAngle(_))
                        | (
                            DecodeError::UnknownVersion(_),
                            Message::SegmentOrientation(_)
                        )
                        | (DecodeError::UnknownVersion(_), Message::RawImuSample(_))
                        | (DecodeError::AngleCount { .. }, Message::PoseFrame(_))
                ),
                "{bytes:02x?}: {e:?} vs {b:?}"
            ),
            _ => {}
        }
    }
    // The mutations leave many messages intact or still well-formed.
    assert!(decoded > 10_000, "{decoded}");
}
