//! The node's entry point against the general one: [`decode_node_message`] decodes a raw sample
//! and a raw configuration as [`decode_message`] does, and reports any other known message by
//! its tag only.
mod common;

use common::{random, strategies, Rng};
use proptest::prelude::*;
use qgait_proto::{
    decode_message, decode_node_message, encode_frame, encode_message, encode_raw_imu_status_frame,
    encode_segment_orientation_frame, Message, NodeMessage, MAX_FRAME_LEN,
};

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
            tag(bytes) == Some(*t) && *t <= 15 && !matches!(*t, 11 | 12)
        }
        (Err(a), Err(b)) => a == b && matches!(tag(bytes), Some(11 | 12) | None | Some(16..)),
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

proptest! {
    /// A node's frames are `encode_frame`'s, byte for byte, in buffers of every size (too small
    /// ones refused alike).
    #[test]
    fn node_frames_are_encode_frames(msg in strategies::message(), size in 0usize..MAX_FRAME_LEN + 4) {
        let mut a = vec![0u8; size];
        let mut b = vec![0u8; size];
        let fast = match &msg {
            Message::SegmentOrientation(p) => encode_segment_orientation_frame(p, &mut a),
            Message::RawImuStatus(s) => encode_raw_imu_status_frame(s, &mut a),
            Message::PoseVelocities(v) => qgait_proto::encode_pose_velocities_frame(v, &mut a),
            _ => return Ok(()),
        }
        .map(|f| f.to_vec());
        let reference = encode_frame(&msg, &mut b).map(|f| f.to_vec());
        prop_assert_eq!(fast.is_ok(), reference.is_ok());
        if let (Ok(f), Ok(r)) = (fast, reference) {
            prop_assert_eq!(f, r);
        }
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
