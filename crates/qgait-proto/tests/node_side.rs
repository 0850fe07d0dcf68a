//! The node's entry point against the general one: [`decode_node_message`] decodes a raw sample
//! and a raw configuration as [`decode_message`] does, and reports any other known message by
//! its tag only.
mod common;

use common::{random, strategies, Rng};
use proptest::prelude::*;
use qgait_proto::{decode_message, decode_node_message, encode_message, Message, NodeMessage};

/// The message tag at the start of `bytes` as postcard reads it (a varint), if any.
fn tag(bytes: &[u8]) -> Option<u32> {
    postcard::take_from_bytes::<u32>(bytes)
        .ok()
        .map(|(tag, _)| tag)
}

fn encoded(msg: &Message) -> Vec<u8> {
    let mut buf = [0u8; qgait_proto::MAX_MESSAGE_LEN];
    encode_message(msg, &mut buf).expect("encodes").to_vec()
}

/// Checks [`decode_node_message`] of `bytes` against [`decode_message`] of the same bytes.
fn check_node_decoding(bytes: &[u8]) -> Result<(), String> {
    let general = decode_message(bytes);
    let node = decode_node_message(bytes);
    let ok = match (&general, &node) {
        (Ok(Message::RawImuSample(a)), Ok(NodeMessage::RawImuSample(b))) => a == b,
        (Ok(Message::RawImuConfig(a)), Ok(NodeMessage::RawImuConfig(b))) => {
            encoded(&Message::RawImuConfig(*a)) == encoded(&Message::RawImuConfig(*b))
        }
        // Any other known tag, well-formed or not, by its tag alone.
        (_, Ok(NodeMessage::NotTaken(t))) => {
            tag(bytes) == Some(*t) && *t <= 13 && !matches!(*t, 11 | 12)
        }
        (Err(a), Err(b)) => a == b && matches!(tag(bytes), Some(11 | 12) | None | Some(14..)),
        _ => false,
    };
    if ok {
        Ok(())
    } else {
        Err(format!("{bytes:02x?}: {general:?} vs {node:?}"))
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn node_decoding_of_valid_messages_is_decode_message(msg in strategies::message()) {
        let bytes = encoded(&msg);
        check_node_decoding(&bytes).map_err(TestCaseError::fail)?;
        let taken = matches!(msg, Message::RawImuSample(_) | Message::RawImuConfig(_));
        prop_assert_eq!(
            taken,
            !matches!(decode_node_message(&bytes), Ok(NodeMessage::NotTaken(_)))
        );
    }
}

/// Mutated encodings of every message and plain random bytes.
#[test]
fn node_decoding_of_mutated_and_random_bytes_is_decode_message() {
    let mut rng = Rng::new(0x4e4f_4445);
    for round in 0..100_000u32 {
        let mut bytes = if round.is_multiple_of(4) {
            (0..rng.below(40)).map(|_| rng.byte()).collect()
        } else {
            encoded(&random::message(&mut rng))
        };
        random::mutate(&mut rng, &mut bytes);
        check_node_decoding(&bytes).unwrap();
    }
}
