//! Round trips of every message: message bytes, whole frames, the streaming decoder with any
//! chunking. Floats are compared bit for bit (NaN payloads included).
mod common;

use common::strategies;
use proptest::prelude::*;
use qgait_proto::{
    decode_frame, decode_message, encode_frame, encode_message, encode_pose_frame,
    encode_pose_frame_parts, EncodeError, FrameDecoder, Message, CONFIG_MAX_LEN, CRC_LEN,
    JOINT_ANGLE_MAX_LEN, MAX_FRAME_LEN, MAX_MESSAGE_LEN, POSE_FRAME_MAX_LEN, STATUS_MAX_LEN,
    SUBJECT_CONFIG_MAX_LEN, SUBJECT_KNEE_MAX_LEN, SUBJECT_LEG_MAX_LEN,
};

/// Two messages are the same iff their encodings are (every field has a fixed-size or
/// self-delimiting encoding, floats as raw bits, so NaN payloads count). When no NaN is present
/// they are also compared with `==`, as an independent check.
fn assert_same(decoded: &Message, original: &Message) {
    let mut a = [0u8; MAX_MESSAGE_LEN];
    let mut b = [0u8; MAX_MESSAGE_LEN];
    let a = encode_message(decoded, &mut a).expect("encodes").to_vec();
    let b = encode_message(original, &mut b).expect("encodes").to_vec();
    assert_eq!(a, b);
    assert_eq!(
        core::mem::discriminant(decoded),
        core::mem::discriminant(original)
    );
    let has_nan = format!("{original:?}").contains("NaN");
    if !has_nan {
        assert_eq!(decoded, original);
    }
}

fn kind_max_len(msg: &Message) -> usize {
    match msg {
        Message::JointAngle(_) => JOINT_ANGLE_MAX_LEN,
        Message::PoseFrame(_) => POSE_FRAME_MAX_LEN,
        Message::Status(_) => STATUS_MAX_LEN,
        Message::Config(_) => CONFIG_MAX_LEN,
        Message::SubjectLeg(_) => SUBJECT_LEG_MAX_LEN,
        Message::SubjectKnee(_) => SUBJECT_KNEE_MAX_LEN,
        Message::SubjectConfig(_) => SUBJECT_CONFIG_MAX_LEN,
        Message::SegmentOrientation(_) => qgait_proto::SEGMENT_ORIENTATION_MAX_LEN,
        Message::ImuConfig(_) => qgait_proto::IMU_CONFIG_MAX_LEN,
        Message::ChainTable(_) => qgait_proto::CHAIN_TABLE_MAX_LEN,
        Message::ChainTableConfig(_) => qgait_proto::CHAIN_TABLE_CONFIG_MAX_LEN,
        Message::RawImuSample(_) => qgait_proto::RAW_IMU_SAMPLE_MAX_LEN,
        Message::RawImuConfig(_) => qgait_proto::RAW_IMU_CONFIG_MAX_LEN,
        Message::RawImuStatus(_) => qgait_proto::RAW_IMU_STATUS_MAX_LEN,
        Message::VelocityConfig(_) => qgait_proto::VELOCITY_CONFIG_MAX_LEN,
        Message::PoseVelocities(_) => qgait_proto::POSE_VELOCITIES_MAX_LEN,
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn message_bytes_round_trip(msg in strategies::message()) {
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let bytes = encode_message(&msg, &mut buf).expect("encodes");
        prop_assert!(bytes.len() <= kind_max_len(&msg));
        prop_assert_eq!(u32::from(bytes[0]), msg.tag());
        let decoded = decode_message(bytes).expect("decodes");
        assert_same(&decoded, &msg);
    }

    #[test]
    fn postcard_of_the_public_types_is_the_wire_encoding(msg in strategies::message()) {
        let mut a = [0u8; MAX_MESSAGE_LEN];
        let mut b = [0u8; MAX_MESSAGE_LEN];
        let ours = encode_message(&msg, &mut a).expect("encodes");
        let plain = postcard::to_slice(&msg, &mut b).expect("encodes");
        prop_assert_eq!(&ours[..], &plain[..]);
    }

    #[test]
    fn frame_round_trips(msg in strategies::message()) {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let frame = encode_frame(&msg, &mut buf).expect("encodes");
        prop_assert!(frame.len() <= MAX_FRAME_LEN);
        prop_assert_eq!(frame.last(), Some(&0));
        prop_assert!(!frame[..frame.len() - 1].contains(&0));
        let mut body = frame[..frame.len() - 1].to_vec();
        let decoded = decode_frame(&mut body).expect("decodes");
        assert_same(&decoded, &msg);
    }

    /// `encode_frame` into a buffer of any size: the frame iff it fits, else `BufferTooSmall`
    /// with the COBS bound; the pose frame paths (`encode_pose_frame`, `encode_pose_frame_parts`)
    /// give the same bytes.
    #[test]
    fn frames_in_buffers_of_every_size(msg in strategies::message(), size in 0usize..MAX_FRAME_LEN + 2) {
        let mut full = [0u8; MAX_FRAME_LEN];
        let frame = encode_frame(&msg, &mut full).expect("encodes").to_vec();
        let mut payload = [0u8; MAX_MESSAGE_LEN];
        let payload_len = encode_message(&msg, &mut payload).expect("encodes").len();
        let needed = qgait_proto::cobs_max_encoded_len(payload_len + CRC_LEN) + 1;
        let mut buf = [0xA5u8; MAX_FRAME_LEN + 2];
        let got = encode_frame(&msg, &mut buf[..size]).map(|f| f.to_vec());
        if size >= frame.len() {
            prop_assert_eq!(got, Ok(frame.clone()));
        } else {
            prop_assert_eq!(got, Err(EncodeError::BufferTooSmall { needed }));
        }
        if let Message::PoseFrame(pose) = &msg {
            let mut buf = [0xA5u8; MAX_FRAME_LEN + 2];
            let got = encode_pose_frame(pose, &mut buf[..size]).map(|f| f.to_vec());
            // The same frame from its parts, as the hub encodes it.
            let parts = pose.parts();
            let mut buf = [0xA5u8; MAX_FRAME_LEN + 2];
            let from_parts = encode_pose_frame_parts(&parts, &mut buf[..size]).map(|f| f.to_vec());
            prop_assert_eq!(&from_parts, &got);
            if size >= frame.len() {
                prop_assert_eq!(got, Ok(frame));
            } else {
                prop_assert_eq!(got, Err(EncodeError::BufferTooSmall { needed }));
            }
        }
    }

    /// `push_frame` + `decode_message` is `push`, byte for byte, on streams of good frames
    /// with random bytes (often zeros) thrown in.
    #[test]
    fn push_frame_then_decode_message_is_push(
        msgs in proptest::collection::vec(strategies::message(), 1..6),
        noise in proptest::collection::vec((0usize..2000, prop_oneof![Just(0u8), any::<u8>()]), 0..10),
    ) {
        let mut stream: Vec<u8> = msgs.iter().flat_map(common::frame).collect();
        for (at, byte) in noise {
            let at = at % (stream.len() + 1);
            stream.insert(at, byte);
        }
        let mut a = FrameDecoder::new();
        let mut b = FrameDecoder::new();
        for &byte in &stream {
            let pushed = a.push(byte);
            let framed = b.push_frame(byte).map(|f| f.and_then(decode_message));
            prop_assert_eq!(pushed.is_some(), framed.is_some());
            if let (Some(x), Some(y)) = (pushed, framed) {
                match (x, y) {
                    (Ok(x), Ok(y)) => assert_same(&x, &y),
                    (x, y) => prop_assert_eq!(x.err(), y.err()),
                }
            }
            prop_assert_eq!(a.pending_len(), b.pending_len());
        }
    }

    /// A stream of frames cut into arbitrary chunks decodes to the same messages, in order,
    /// whether fed by chunks or byte by byte.
    #[test]
    fn stream_round_trips_with_any_chunking(
        msgs in proptest::collection::vec(strategies::message(), 1..8),
        cuts in proptest::collection::vec(0usize..2000, 0..12),
    ) {
        let stream: Vec<u8> = msgs.iter().flat_map(common::frame).collect();
        let mut cuts: Vec<usize> = cuts.into_iter().map(|c| c % (stream.len() + 1)).collect();
        cuts.push(0);
        cuts.push(stream.len());
        cuts.sort_unstable();
        let mut decoder = FrameDecoder::new();
        let mut by_chunks = Vec::new();
        for pair in cuts.windows(2) {
            by_chunks.extend(decoder.feed(&stream[pair[0]..pair[1]]));
        }
        prop_assert_eq!(decoder.pending_len(), 0);
        let by_bytes = common::decode_all(&mut FrameDecoder::new(), &stream);
        prop_assert_eq!(by_chunks.len(), msgs.len());
        prop_assert_eq!(by_bytes.len(), msgs.len());
        for ((chunked, single), msg) in by_chunks.iter().zip(&by_bytes).zip(&msgs) {
            assert_same(chunked.as_ref().expect("decodes"), msg);
            assert_same(single.as_ref().expect("decodes"), msg);
        }
    }
}

#[test]
fn joint_ids_round_trip_through_index_and_name() {
    use qgait_proto::JointId;
    assert_eq!(JointId::ALL.len(), JointId::COUNT);
    for (i, joint) in JointId::ALL.iter().enumerate() {
        assert_eq!(usize::from(joint.index()), i);
        assert_eq!(JointId::from_index(joint.index()), Some(*joint));
        assert_eq!(JointId::from_name(joint.name()), Some(*joint));
    }
    assert_eq!(JointId::from_index(17), None);
    assert_eq!(JointId::from_index(255), None);
    assert_eq!(
        JointId::from_name("hip_flexion_r"),
        Some(JointId::HipFlexionR)
    );
    assert_eq!(JointId::from_name("pelvis_list"), Some(JointId::PelvisList));
    assert_eq!(JointId::from_name("lumbar_extension"), None);
    assert_eq!(JointId::MtpAngleL.to_string(), "mtp_angle_l");
}

#[test]
fn models_round_trip_and_list_their_joints() {
    use qgait_proto::{JointId, ModelId};
    for (i, model) in ModelId::ALL.iter().enumerate() {
        assert_eq!(usize::from(model.index()), i);
        assert_eq!(ModelId::from_index(model.index()), Some(*model));
        assert_eq!(ModelId::from_name(model.name()), Some(*model));
    }
    assert_eq!(ModelId::from_index(4), None);
    assert_eq!(ModelId::Chain.required_joints(), &JointId::ALL);
    use JointId::*;
    assert_eq!(
        ModelId::Phak.required_joints(),
        &[
            PelvisRotation,
            PelvisList,
            HipFlexionR,
            KneeAngleR,
            AnkleAngleR,
            HipFlexionL,
            KneeAngleL,
            AnkleAngleL
        ]
    );
    assert_eq!(
        ModelId::Hak.required_joints(),
        &[
            HipFlexionR,
            KneeAngleR,
            AnkleAngleR,
            HipFlexionL,
            KneeAngleL,
            AnkleAngleL
        ]
    );
    assert_eq!(ModelId::Gait2392.required_joints(), &JointId::ALL);
}
