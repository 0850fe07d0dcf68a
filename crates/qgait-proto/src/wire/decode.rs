//! The decoders: one per message body with values to check and one ([`plain`]) for the others,
//! each reading the fields one at a time (the joint-angle packet by hand, the others through
//! postcard's deserialiser per field; the parts several messages share, once), raw bytes for the
//! joint and model fields so that an unknown joint or model is reported as its own
//! [`DecodeError`]. [`decode_packet`] is the hub's per-packet fast path; [`decode_hub_message`]
//! decodes the messages sent to a hub and only the tag of the others, so that a hub links no
//! decoder of a message it does not take.

use super::check_angle_count;
use super::varint::{end, take, take_varint_u32};
use crate::WireByte;
use crate::{
    point, segment, Config, DecodeError, HeadingAxisId, ImuConfig, ImuHeading, InputMode,
    JointAngle, JointId, KneeDirection, Leg, MissingPolicy, ModelId, PoseFrame, SampleHeader,
    SegmentId, SegmentOrientation, SubjectConfig, SubjectKnee, SubjectLeg, CHAIN_TABLE_CONFIG_TAG,
    CHAIN_TABLE_TAG, MAX_KNEE_KNOTS, MAX_POSE_ANGLES, PROTOCOL_VERSION,
};
use crate::{ChainTable, ChainTableConfig};
use crate::{
    FusionMode, RawImuConfig, RawImuSample, RAW_IMU_CONFIG_TAG, RAW_IMU_SAMPLE_TAG,
    RAW_IMU_STATUS_TAG,
};
use crate::{VelocityConfig, POSE_VELOCITIES_TAG, VELOCITY_CONFIG_TAG};

/// A message as a hub takes it ([`decode_hub_message`]): the messages sent to a hub, decoded,
/// and the ones only a hub sends, not decoded.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HubMessage {
    /// Tag 0.
    JointAngle(JointAngle),
    /// Tag 3.
    Config(Config),
    /// Tag 4.
    SubjectLeg(SubjectLeg),
    /// Tag 5.
    SubjectKnee(SubjectKnee),
    /// Tag 6.
    SubjectConfig(SubjectConfig),
    /// Tag 7 (with the `orientation` feature).
    #[cfg(feature = "orientation")]
    SegmentOrientation(SegmentOrientation),
    /// Tag 8.
    ImuConfig(ImuConfig),
    /// Tag 9 (with the `chain` feature).
    #[cfg(feature = "chain")]
    ChainTable(ChainTable),
    /// Tag 10 (with the `chain` feature).
    #[cfg(feature = "chain")]
    ChainTableConfig(ChainTableConfig),
    /// Tag 14.
    VelocityConfig(VelocityConfig),
    /// A message this hub does not take, with its tag: a segment orientation (tag 7) to a hub
    /// built without the `orientation` feature, a chain message (tag 9 or 10) to a hub built
    /// without the `chain` feature, or a raw IMU sample or configuration (tag 11 or 12:
    /// no hub of this crate takes raw input yet). Its body is not decoded (so such a hub links
    /// none of their decoders).
    NotTaken(u32),
    /// A message only a hub (or a raw input) sends ([`PoseFrame`], tag 1,
    /// [`Status`](crate::Status), tag 2, [`RawImuStatus`](crate::RawImuStatus), tag 13, or
    /// [`PoseVelocities`](crate::PoseVelocities), tag 15), with this tag. Its body is not decoded:
    /// it may or may not be well-formed.
    FromHub(u32),
}

/// The hub's fast path: if `bytes` (one message, as [`decode_message`](crate::decode_message)
/// takes it) is a [`JointAngle`] whose tag is the canonical single byte 0x00, its
/// `decode_message` result without building a [`Message`](crate::Message); `None` for any other
/// message (decode those with `decode_message` or [`decode_hub_message`]).
#[inline(always)]
pub fn decode_packet(bytes: &[u8]) -> Option<Result<JointAngle, DecodeError>> {
    match bytes.split_first() {
        Some((0, body)) => Some(joint_angle(body)),
        _ => None,
    }
}

/// [`decode_message`](crate::decode_message) for a hub: the messages sent to a hub are decoded
/// exactly as `decode_message` decodes them (the same values, the same errors); a
/// [`PoseFrame`] or a [`Status`](crate::Status) is reported as [`HubMessage::FromHub`] without
/// decoding its body, so their decoders are not linked into a hub that does not call
/// `decode_message`.
pub fn decode_hub_message(bytes: &[u8]) -> Result<HubMessage, DecodeError> {
    if let Some(packet) = decode_packet(bytes) {
        return packet.map(HubMessage::JointAngle);
    }
    let (tag, body) = take::<u32>(bytes)?;
    match tag {
        0 => joint_angle(body).map(HubMessage::JointAngle),
        1 | 2 => Ok(HubMessage::FromHub(tag)),
        3 => config(body).map(HubMessage::Config),
        4 => subject_leg(body).map(HubMessage::SubjectLeg),
        5 => subject_knee(body).map(HubMessage::SubjectKnee),
        6 => subject_config(body).map(HubMessage::SubjectConfig),
        #[cfg(feature = "orientation")]
        7 => segment_orientation(body).map(HubMessage::SegmentOrientation),
        #[cfg(not(feature = "orientation"))]
        7 => Ok(HubMessage::NotTaken(tag)),
        8 => imu_config(body).map(HubMessage::ImuConfig),
        #[cfg(feature = "chain")]
        CHAIN_TABLE_TAG => chain_table(body).map(HubMessage::ChainTable),
        #[cfg(feature = "chain")]
        CHAIN_TABLE_CONFIG_TAG => chain_table_config(body).map(HubMessage::ChainTableConfig),
        #[cfg(not(feature = "chain"))]
        CHAIN_TABLE_TAG..=CHAIN_TABLE_CONFIG_TAG => Ok(HubMessage::NotTaken(tag)),
        RAW_IMU_SAMPLE_TAG | RAW_IMU_CONFIG_TAG => Ok(HubMessage::NotTaken(tag)),
        RAW_IMU_STATUS_TAG | POSE_VELOCITIES_TAG => Ok(HubMessage::FromHub(tag)),
        VELOCITY_CONFIG_TAG => plain(body).map(HubMessage::VelocityConfig),
        unknown => Err(DecodeError::UnknownMessage(unknown)),
    }
}

/// A message as a node fusing its own sensor takes it ([`decode_node_message`]): its raw
/// samples and their configuration, decoded; any other known message only by its tag.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NodeMessage {
    /// Tag 11.
    RawImuSample(RawImuSample),
    /// Tag 12.
    RawImuConfig(RawImuConfig),
    /// A known message a node does not take (tags 0 to 10 and 13 to 15), with its tag. Its body is
    /// not decoded (so a node links none of their decoders).
    NotTaken(u32),
}

/// [`decode_message`](crate::decode_message) for a node fusing its own sensor (protocol.md
/// 4.10): a [`RawImuSample`] or a [`RawImuConfig`] is decoded exactly as `decode_message`
/// decodes it (the same values, the same errors); any other known tag is
/// [`NodeMessage::NotTaken`], an unknown one [`DecodeError::UnknownMessage`].
pub fn decode_node_message(bytes: &[u8]) -> Result<NodeMessage, DecodeError> {
    let (tag, body) = take::<u32>(bytes)?;
    match tag {
        RAW_IMU_SAMPLE_TAG => raw_imu_sample(body).map(NodeMessage::RawImuSample),
        RAW_IMU_CONFIG_TAG => raw_imu_config(body).map(NodeMessage::RawImuConfig),
        0..=POSE_VELOCITIES_TAG => Ok(NodeMessage::NotTaken(tag)),
        unknown => Err(DecodeError::UnknownMessage(unknown)),
    }
}

/// A [`JointAngle`]'s body (after the tag), by hand: version, node, joint, seq (varint),
/// timestamp (varint), angle (`f32` LE), quality, and nothing after. The errors are postcard's
/// for the layout: the version first, then the layout (`Malformed`), then the joint.
#[inline(always)]
pub(super) fn joint_angle(body: &[u8]) -> Result<JointAngle, DecodeError> {
    let (version, rest) = versioned(body)?;
    let [node, joint, rest @ ..] = rest else {
        return Err(DecodeError::Malformed);
    };
    let (seq, rest) = take_varint_u32(rest)?;
    let (timestamp_us, rest) = take_varint_u32(rest)?;
    let &[a0, a1, a2, a3, quality] = rest else {
        return Err(DecodeError::Malformed);
    };
    Ok(JointAngle {
        version,
        node: *node,
        joint: JointId::from_index(*joint).ok_or(DecodeError::UnknownJoint(*joint))?,
        seq,
        timestamp_us,
        angle: f32::from_le_bytes([a0, a1, a2, a3]),
        quality,
    })
}

/// A [`PoseFrame`]'s body: the layout first (`Malformed`), then the model, then the angle count.
pub(super) fn pose_frame(body: &[u8]) -> Result<PoseFrame, DecodeError> {
    let (seq, rest) = take(body)?;
    let (timestamp_us, rest) = take(rest)?;
    let (model, rest) = take::<u8>(rest)?;
    let (angles, rest) = take::<heapless::Vec<f32, MAX_POSE_ANGLES>>(rest)?;
    let (points, rest) = take::<[[f32; 3]; point::COUNT]>(rest)?;
    let (distances, rest) = take(rest)?;
    let (flags, rest) = take(rest)?;
    end(rest)?;
    let model = ModelId::from_index(model).ok_or(DecodeError::UnknownModel(model))?;
    check_angle_count(model, angles.len())
        .map_err(|(expected, got)| DecodeError::AngleCount { expected, got })?;
    Ok(PoseFrame {
        seq,
        timestamp_us,
        model,
        angles,
        points,
        distances,
        flags,
    })
}

/// The body of a message whose fields carry no value of their own to check
/// ([`Status`](crate::Status), its 20 varints; [`RawImuStatus`](crate::RawImuStatus), its 9;
/// [`VelocityConfig`]; [`PoseVelocities`](crate::PoseVelocities)): postcard's decoding of the
/// whole, and nothing after.
pub(super) fn plain<T: serde::de::DeserializeOwned>(body: &[u8]) -> Result<T, DecodeError> {
    let (value, rest) = take(body)?;
    end(rest)?;
    Ok(value)
}

/// A [`Config`]'s body. The fields' values are checked in wire order (section 5 of the spec),
/// after the layout: an unknown model before a bad missing policy.
pub(super) fn config(body: &[u8]) -> Result<Config, DecodeError> {
    let (model, rest) = take::<u8>(body)?;
    let (anthropometry, rest) = take::<Option<[[f32; segment::COUNT]; 2]>>(rest)?;
    let (policy, reorder_window, request_status) = sample_settings(rest)?;
    Ok(Config {
        model: ModelId::from_index(model).ok_or(DecodeError::UnknownModel(model))?,
        anthropometry,
        missing_policy: missing_policy(policy)?,
        reorder_window,
        request_status,
    })
}

/// A [`SubjectLeg`]'s body: the 11 vectors in one loop.
pub(super) fn subject_leg(body: &[u8]) -> Result<SubjectLeg, DecodeError> {
    let (upload, rest) = take(body)?;
    let (side, mut rest) = take::<u8>(rest)?;
    let mut v = [[0.0f32; 3]; 11];
    for slot in &mut v {
        (*slot, rest) = take(rest)?;
    }
    end(rest)?;
    let [hip_in_pelvis, h0, h1, h2, ankle_in_tibia, ankle_axis, subtalar_in_talus, subtalar_axis, mtp_in_calcn, mtp_axis, toetip_in_toes] =
        v;
    Ok(SubjectLeg {
        upload,
        leg: leg(side)?,
        hip_in_pelvis,
        hip_axes: [h0, h1, h2],
        ankle_in_tibia,
        ankle_axis,
        subtalar_in_talus,
        subtalar_axis,
        mtp_in_calcn,
        mtp_axis,
        toetip_in_toes,
    })
}

/// A [`SubjectKnee`]'s body.
pub(super) fn subject_knee(body: &[u8]) -> Result<SubjectKnee, DecodeError> {
    let (upload, rest) = take(body)?;
    let (side, rest) = take::<u8>(rest)?;
    let (direction, rest) = take::<u8>(rest)?;
    // More than MAX_KNEE_KNOTS fails to deserialise: Malformed.
    let (knots, rest) = take::<heapless::Vec<[f32; 2], MAX_KNEE_KNOTS>>(rest)?;
    end(rest)?;
    Ok(SubjectKnee {
        upload,
        leg: leg(side)?,
        direction: KneeDirection::from_index(direction).ok_or(DecodeError::Malformed)?,
        knots,
    })
}

/// A [`SubjectConfig`]'s body.
pub(super) fn subject_config(body: &[u8]) -> Result<SubjectConfig, DecodeError> {
    let (upload, rest) = take(body)?;
    let (policy, reorder_window, request_status) = sample_settings(rest)?;
    Ok(SubjectConfig {
        upload,
        missing_policy: missing_policy(policy)?,
        reorder_window,
        request_status,
    })
}

/// A [`SegmentOrientation`]'s body: the version first (as a [`JointAngle`]'s), then the
/// layout (`Malformed`), then the segment.
pub(super) fn segment_orientation(body: &[u8]) -> Result<SegmentOrientation, DecodeError> {
    let (head, rest) = sample_head(body)?;
    let (q14, rest) = take(rest)?;
    let (quality, rest) = take(rest)?;
    end(rest)?;
    Ok(SegmentOrientation {
        header: head.checked()?,
        q14,
        quality,
    })
}

/// An [`ImuConfig`]'s body: the layout first (`Malformed`), then the values in wire order:
/// the mode, then the heading's base segment, then its axis.
pub(super) fn imu_config(body: &[u8]) -> Result<ImuConfig, DecodeError> {
    let (mode, rest) = take::<u8>(body)?;
    let (segments, rest) = take(rest)?;
    let (calibrate, rest) = take(rest)?;
    let (sensor_to_opensim, rest) = take(rest)?;
    let (heading, rest) = take::<Option<(u8, u8)>>(rest)?;
    let (request_status, rest) = take(rest)?;
    end(rest)?;
    let mode = InputMode::from_repr(mode).ok_or(DecodeError::Malformed)?;
    let heading = match heading {
        None => None,
        Some((base, axis)) => Some(ImuHeading {
            base: SegmentId::from_wire_byte(base).ok_or(DecodeError::UnknownSegment(base))?,
            axis: HeadingAxisId::from_wire_byte(axis).ok_or(DecodeError::Malformed)?,
        }),
    };
    Ok(ImuConfig {
        mode,
        segments,
        calibrate,
        sensor_to_opensim,
        heading,
        request_status,
    })
}

/// A [`ChainTable`]'s body: upload, `at` (a `u16` varint), the byte count, the bytes.
pub(super) fn chain_table(body: &[u8]) -> Result<ChainTable, DecodeError> {
    let (upload, rest) = take(body)?;
    let (at, rest) = take::<u16>(rest)?;
    let (count, rest) = take_varint_u32(rest)?;
    let (bytes, rest) = usize::try_from(count)
        .ok()
        .and_then(|n| rest.split_at_checked(n))
        .ok_or(DecodeError::Malformed)?;
    end(rest)?;
    Ok(ChainTable {
        upload,
        at,
        bytes: heapless::Vec::from_slice(bytes).map_err(|_| DecodeError::Malformed)?,
    })
}

/// A [`ChainTableConfig`]'s body.
pub(super) fn chain_table_config(body: &[u8]) -> Result<ChainTableConfig, DecodeError> {
    let (upload, rest) = take(body)?;
    let (len, rest) = take::<u16>(rest)?;
    let (crc, rest) = take_varint_u32(rest)?;
    let (knee_flexes_positive, rest) = take(rest)?;
    let (policy, reorder_window, request_status) = sample_settings(rest)?;
    Ok(ChainTableConfig {
        upload,
        len,
        crc,
        knee_flexes_positive,
        missing_policy: missing_policy(policy)?,
        reorder_window,
        request_status,
    })
}

/// A [`RawImuSample`]'s body: the version first (as a [`JointAngle`]'s), then the layout
/// (`Malformed`), then the segment.
pub(super) fn raw_imu_sample(body: &[u8]) -> Result<RawImuSample, DecodeError> {
    let (head, rest) = sample_head(body)?;
    let (gyro, rest) = take(rest)?;
    let (accel, rest) = take(rest)?;
    let (mag, rest) = take(rest)?;
    end(rest)?;
    Ok(RawImuSample {
        header: head.checked()?,
        gyro,
        accel,
        mag,
    })
}

/// A [`RawImuConfig`]'s body: the layout, then the fusion mode.
pub(super) fn raw_imu_config(body: &[u8]) -> Result<RawImuConfig, DecodeError> {
    let (segments, rest) = take(body)?;
    let (fusion, rest) = take::<u8>(rest)?;
    let (rate_hz, rest) = take(rest)?;
    let (output_every, rest) = take(rest)?;
    let (gyro_per_count, rest) = take(rest)?;
    let (accel_per_count, rest) = take(rest)?;
    let (mag_per_count, rest) = take(rest)?;
    let (request_status, rest) = take(rest)?;
    end(rest)?;
    Ok(RawImuConfig {
        segments,
        fusion: FusionMode::from_repr(fusion).ok_or(DecodeError::Malformed)?,
        rate_hz,
        output_every,
        gyro_per_count,
        accel_per_count,
        mag_per_count,
        request_status,
    })
}

/// The version byte a [`JointAngle`], a [`SegmentOrientation`] and a [`RawImuSample`] start
/// with, checked before anything else (a message of another version, whose layout may differ,
/// is reported as such); returns it and the bytes after it.
#[inline(always)]
fn versioned(body: &[u8]) -> Result<(u8, &[u8]), DecodeError> {
    let (&version, rest) = body.split_first().ok_or(DecodeError::Malformed)?;
    if version != PROTOCOL_VERSION {
        return Err(DecodeError::UnknownVersion(version));
    }
    Ok((version, rest))
}

/// A [`SampleHeader`] as read, its segment's wire byte not yet checked: a sample's errors
/// are the layout's (`Malformed`) before the segment's.
struct SampleHead {
    version: u8,
    node: u8,
    segment: u8,
    seq: u32,
    timestamp_us: u32,
}

impl SampleHead {
    /// The header, or [`DecodeError::UnknownSegment`].
    fn checked(self) -> Result<SampleHeader, DecodeError> {
        Ok(SampleHeader {
            version: self.version,
            node: self.node,
            segment: SegmentId::from_wire_byte(self.segment)
                .ok_or(DecodeError::UnknownSegment(self.segment))?,
            seq: self.seq,
            timestamp_us: self.timestamp_us,
        })
    }
}

/// A sample's [`SampleHead`]: the version first ([`versioned`]), then node, segment, seq and
/// timestamp (varints); returns it and the bytes after it.
#[inline(always)]
fn sample_head(body: &[u8]) -> Result<(SampleHead, &[u8]), DecodeError> {
    let (version, rest) = versioned(body)?;
    let (node, rest) = take(rest)?;
    let (segment, rest) = take::<u8>(rest)?;
    let (seq, rest) = take_varint_u32(rest)?;
    let (timestamp_us, rest) = take_varint_u32(rest)?;
    let head = SampleHead {
        version,
        node,
        segment,
        seq,
        timestamp_us,
    };
    Ok((head, rest))
}

/// The settings a [`Config`], a [`SubjectConfig`] and a [`ChainTableConfig`] end with: the
/// missing policy (its byte: checked with [`missing_policy`] in wire order, after the layout),
/// the reorder window and the status request, and nothing after.
#[inline(always)]
fn sample_settings(rest: &[u8]) -> Result<(u8, u8, bool), DecodeError> {
    let (policy, rest) = take::<u8>(rest)?;
    let (reorder_window, rest) = take(rest)?;
    let (request_status, rest) = take(rest)?;
    end(rest)?;
    Ok((policy, reorder_window, request_status))
}

fn missing_policy(byte: u8) -> Result<MissingPolicy, DecodeError> {
    match byte {
        0 => Ok(MissingPolicy::Drop),
        1 => Ok(MissingPolicy::HoldLast),
        _ => Err(DecodeError::Malformed),
    }
}

fn leg(byte: u8) -> Result<Leg, DecodeError> {
    Leg::from_index(byte).ok_or(DecodeError::Malformed)
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use crate::wire::varint::{varint_u32, VARINT_U32_MAX};
    use crate::{decode_message, Message, MAX_MESSAGE_LEN};
    use proptest::prelude::*;
    use serde::Deserialize;
    use std::vec;
    use std::vec::Vec;

    /// The postcard decoding of a [`JointAngle`] body that [`joint_angle`] replaces,
    /// kept as the reference it is tested against.
    fn decode_joint_angle_postcard(body: &[u8]) -> Result<JointAngle, DecodeError> {
        #[derive(Deserialize)]
        struct JointAngleWire {
            version: u8,
            node: u8,
            joint: u8,
            seq: u32,
            timestamp_us: u32,
            angle: f32,
            quality: u8,
        }
        let version = *body.first().ok_or(DecodeError::Malformed)?;
        if version != PROTOCOL_VERSION {
            return Err(DecodeError::UnknownVersion(version));
        }
        let w: JointAngleWire = match postcard::take_from_bytes(body) {
            Ok((w, [])) => w,
            _ => return Err(DecodeError::Malformed),
        };
        Ok(JointAngle {
            version: w.version,
            node: w.node,
            joint: JointId::from_index(w.joint).ok_or(DecodeError::UnknownJoint(w.joint))?,
            seq: w.seq,
            timestamp_us: w.timestamp_us,
            angle: w.angle,
            quality: w.quality,
        })
    }

    /// The whole-message postcard decoding with the reference for tag 0.
    fn decode_message_postcard(bytes: &[u8]) -> Result<Message, DecodeError> {
        let (tag, body) =
            postcard::take_from_bytes::<u32>(bytes).map_err(|_| DecodeError::Malformed)?;
        if tag == 0 {
            decode_joint_angle_postcard(body).map(Message::JointAngle)
        } else {
            decode_message(bytes)
        }
    }

    /// Results compared with floats as bits (NaN payloads included).
    fn same(a: &Result<Message, DecodeError>, b: &Result<Message, DecodeError>) -> bool {
        match (a, b) {
            (Ok(Message::JointAngle(x)), Ok(Message::JointAngle(y))) => {
                x.angle.to_bits() == y.angle.to_bits()
                    && JointAngle { angle: 0.0, ..*x } == JointAngle { angle: 0.0, ..*y }
            }
            (Ok(_), Ok(_)) => {
                let mut x = [0u8; MAX_MESSAGE_LEN];
                let mut y = [0u8; MAX_MESSAGE_LEN];
                let (Ok(x), Ok(y)) = (
                    postcard::to_slice(a.as_ref().unwrap(), &mut x),
                    postcard::to_slice(b.as_ref().unwrap(), &mut y),
                ) else {
                    return false;
                };
                x == y
            }
            (Err(x), Err(y)) => x == y,
            _ => false,
        }
    }

    /// Bytes that look like a joint-angle packet, then mutated: every length around the real
    /// ones, every varint length (canonical or not, over-long, unterminated), every version
    /// and joint byte.
    fn packet_like() -> impl Strategy<Value = Vec<u8>> {
        let varint = prop_oneof![
            any::<u32>().prop_map(|v| {
                let mut b = [0u8; VARINT_U32_MAX];
                varint_u32(v, &mut b).to_vec()
            }),
            proptest::collection::vec(any::<u8>(), 0..7),
            proptest::collection::vec(
                prop_oneof![Just(0x80u8), Just(0xFF), Just(0x0F), Just(0x10), Just(0)],
                1..7
            ),
        ];
        (
            prop_oneof![
                Just(vec![0u8]),
                Just(vec![0x80, 0x00]),
                proptest::collection::vec(any::<u8>(), 0..3)
            ],
            prop_oneof![4 => Just(PROTOCOL_VERSION), 1 => any::<u8>()],
            any::<u8>(),
            prop_oneof![0u8..20, any::<u8>()],
            varint.clone(),
            varint,
            proptest::collection::vec(any::<u8>(), 0..8),
        )
            .prop_map(|(tag, version, node, joint, seq, ts, tail)| {
                let mut v = tag;
                v.extend([version, node, joint]);
                v.extend(seq);
                v.extend(ts);
                v.extend(tail);
                v
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 20_000, ..ProptestConfig::default() })]

        /// The fast joint-angle decoding accepts exactly the bytes postcard accepts, with the
        /// same values, and rejects the rest with the same errors.
        #[test]
        fn joint_angle_fast_path_is_postcard(bytes in packet_like()) {
            let fast = decode_message(&bytes);
            let reference = decode_message_postcard(&bytes);
            prop_assert!(same(&fast, &reference), "{bytes:02x?}: {fast:?} vs {reference:?}");
            match decode_packet(&bytes) {
                Some(packet) => prop_assert!(same(&packet.map(Message::JointAngle), &reference)),
                None => prop_assert_ne!(bytes.first(), Some(&0)),
            }
        }
    }
}
