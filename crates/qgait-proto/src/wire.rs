//! Message bytes (postcard, no framing): [`encode_message`] and [`decode_message`].
//!
//! Encoding serialises the public types with postcard. Decoding reads the message tag and the
//! protocol version by hand, then the body into mirror structs whose joint and model fields are
//! raw bytes, so that an unknown tag, version, joint or model is reported as its own
//! [`DecodeError`] instead of a generic postcard error.
//!
//! Two messages take a hand-written fast path, because the hub handles one of them per packet
//! and one per sample: decoding a [`JointAngle`] ([`decode_packet`]) and encoding a
//! [`PoseFrame`]. Their layout is postcard's (documented in `docs/protocol.md`); the unit tests
//! below hold them to postcard itself, byte for byte, on random messages and on random bytes
//! (the same bytes accepted, the same values, the same errors).
//!
//! A hub decodes with [`decode_hub_message`]: only the messages sent to a hub, their bodies
//! deserialised field by field; `tests/hub_side.rs` holds it to [`decode_message`].

use serde::de::DeserializeOwned;
use serde::Deserialize;

use crate::sizes::STATUS_COUNTERS;
use crate::{
    point, Config, DecodeError, EncodeError, JointAngle, JointId, KneeDirection, Leg, Message,
    MissingPolicy, ModelId, PoseFrame, Status, SubjectConfig, SubjectKnee, SubjectLeg,
    MAX_KNEE_KNOTS, MAX_MESSAGE_LEN, MAX_POSE_ANGLES, PROTOCOL_VERSION,
};

/// Encodes `msg` as postcard bytes (no CRC, no framing) into `out`, returning the used part.
///
/// At most [`MAX_MESSAGE_LEN`] bytes are written. Fails if `out` is too small, or if a
/// [`PoseFrame`] does not have exactly `model.required_joints().len()` angles.
pub fn encode_message<'a>(msg: &Message, out: &'a mut [u8]) -> Result<&'a mut [u8], EncodeError> {
    if let Message::PoseFrame(frame) = msg {
        return encode_pose_frame_message(frame, out);
    }
    postcard::to_slice(msg, out).map_err(|_| EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    })
}

/// [`encode_message`] of `Message::PoseFrame(frame)`, without building the [`Message`]: the
/// same bytes as postcard's, written by hand (46 `f32`s through postcard's serializer cost
/// several times more on the hub). The layout is [`encode_pose_frame_parts_message`]'s, once.
pub(crate) fn encode_pose_frame_message<'a>(
    frame: &PoseFrame,
    out: &'a mut [u8],
) -> Result<&'a mut [u8], EncodeError> {
    check_angle_count(frame.model, frame.angles.len())
        .map_err(|(expected, got)| EncodeError::AngleCount { expected, got })?;
    encode_pose_frame_parts_message(&frame.parts(), out)
}

impl PoseFrame {
    /// This frame as [`PoseFrameParts`] (what [`encode_pose_frame_parts`](crate::encode_pose_frame_parts)
    /// takes). Encoded, they give this frame's bytes when its angle count is its model's.
    pub fn parts(
        &self,
    ) -> PoseFrameParts<impl Fn(usize) -> f32 + '_, impl Fn(usize) -> [f32; 3] + '_> {
        PoseFrameParts {
            seq: self.seq,
            model: self.model,
            angle: |i: usize| self.angles.get(i).copied().unwrap_or(0.0),
            point: |i: usize| self.points.get(i).copied().unwrap_or([0.0; 3]),
            distances: self.distances,
            flags: self.flags,
        }
    }
}

/// The fields of a [`PoseFrame`] where they already are, for
/// [`encode_pose_frame_parts`](crate::encode_pose_frame_parts): the angles and points are read
/// through `angle` and `point` as they are written, so no `PoseFrame` is built (and copied) on
/// the way to the bytes.
pub struct PoseFrameParts<A, P> {
    /// [`PoseFrame::seq`].
    pub seq: u32,
    /// [`PoseFrame::model`].
    pub model: ModelId,
    /// `angle(i)` is [`PoseFrame::angles`]`[i]`, for `i` in `0..model.required_joints().len()`
    /// (the angle of `model.required_joints()[i]`).
    pub angle: A,
    /// `point(i)` is [`PoseFrame::points`]`[i]`, for `i` in `0..point::COUNT`.
    pub point: P,
    /// [`PoseFrame::distances`].
    pub distances: [f32; 3],
    /// [`PoseFrame::flags`].
    pub flags: u8,
}

/// [`encode_pose_frame_message`] of the pose frame `parts` make: the same bytes (the same
/// layout, written from the parts; the tests below hold the two to each other and to
/// postcard). The angle count is the model's, always right.
pub(crate) fn encode_pose_frame_parts_message<'a, A, P>(
    parts: &PoseFrameParts<A, P>,
    out: &'a mut [u8],
) -> Result<&'a mut [u8], EncodeError>
where
    A: Fn(usize) -> f32,
    P: Fn(usize) -> [f32; 3],
{
    let count = parts.model.required_joints().len();
    let mut seq = [0u8; VARINT_U32_MAX];
    let seq = varint_u32(parts.seq, &mut seq);
    // tag, seq, model, angle count (< 128: one varint byte), angles, points, distances, flags
    let len = 1 + seq.len() + 2 + 4 * (count + 3 * point::COUNT + 3) + 1;
    let Some(out) = out.get_mut(..len) else {
        return Err(EncodeError::BufferTooSmall {
            needed: MAX_MESSAGE_LEN,
        });
    };
    let (head, rest) = out.split_at_mut(1 + seq.len() + 2);
    head[0] = 1; // Message::PoseFrame's tag
                 // A byte loop: one to five bytes, fewer instructions than a memcpy call.
    for (slot, &byte) in head[1..].iter_mut().zip(seq) {
        *slot = byte;
    }
    head[1 + seq.len()] = parts.model.index();
    head[2 + seq.len()] = count as u8;
    let (angle_bytes, rest) = rest.split_at_mut(4 * count);
    for (i, slot) in angle_bytes.chunks_exact_mut(4).enumerate() {
        slot.copy_from_slice(&(parts.angle)(i).to_le_bytes());
    }
    let (point_bytes, rest) = rest.split_at_mut(4 * 3 * point::COUNT);
    for (i, slot) in point_bytes.chunks_exact_mut(4 * 3).enumerate() {
        let [x, y, z] = (parts.point)(i);
        // A point's 12 bytes as an array: the three stores at fixed offsets, unchecked.
        if let Ok(slot) = <&mut [u8; 12]>::try_from(slot) {
            slot[..4].copy_from_slice(&x.to_le_bytes());
            slot[4..8].copy_from_slice(&y.to_le_bytes());
            slot[8..].copy_from_slice(&z.to_le_bytes());
        }
    }
    let (distance_bytes, flags) = rest.split_at_mut(4 * 3);
    put_f32s(distance_bytes, &parts.distances);
    flags[0] = parts.flags;
    Ok(out)
}

/// [`encode_message`] of `Message::Status(status)`, without building the [`Message`]: the same
/// bytes as postcard's (the tag, then the 16 counters as varints in declaration order), written
/// by hand so that a hub, which encodes no other message with [`encode_message`], links no
/// other message's serialiser.
pub(crate) fn encode_status_message<'a>(
    status: &Status,
    out: &'a mut [u8],
) -> Result<&'a mut [u8], EncodeError> {
    // Every field named (no `..`): a counter added to `Status` must be added here.
    let Status {
        packets_accepted,
        crc_errors,
        framing_errors,
        oversize_frames,
        unknown_version,
        unknown_joint,
        out_of_range,
        samples_completed,
        samples_incomplete,
        frames_sent,
        uart_overruns,
        uptime_ms,
        late_packets,
        duplicate_packets,
        malformed,
        config_rejected,
    } = *status;
    let counters: [u32; STATUS_COUNTERS] = [
        packets_accepted,
        crc_errors,
        framing_errors,
        oversize_frames,
        unknown_version,
        unknown_joint,
        out_of_range,
        samples_completed,
        samples_incomplete,
        frames_sent,
        uart_overruns,
        uptime_ms,
        late_packets,
        duplicate_packets,
        malformed,
        config_rejected,
    ];
    let too_small = EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    };
    *out.first_mut().ok_or(too_small)? = 2; // Message::Status's tag
    let mut len = 1;
    // The varints written straight into `out` (not with `varint_u32`, which the pose frame
    // encoding then no longer has to itself: it would be a call there).
    for mut value in counters {
        loop {
            let slot = out.get_mut(len).ok_or(too_small)?;
            len += 1;
            if value < 0x80 {
                *slot = value as u8;
                break;
            }
            *slot = (value as u8) | 0x80;
            value >>= 7;
        }
    }
    out.get_mut(..len).ok_or(too_small)
}

/// Writes `values` as postcard writes `f32`s (4 bytes, little-endian) into `out`.
#[inline(always)]
fn put_f32s(out: &mut [u8], values: &[f32]) {
    for (slot, value) in out.chunks_exact_mut(4).zip(values) {
        slot.copy_from_slice(&value.to_le_bytes());
    }
}

/// Most bytes of a `u32` varint.
const VARINT_U32_MAX: usize = 5;

/// postcard's varint of `value` (LEB128, 7 bits per byte, least significant first), in `buf`.
fn varint_u32(mut value: u32, buf: &mut [u8; VARINT_U32_MAX]) -> &[u8] {
    let mut len = 0;
    for slot in buf.iter_mut() {
        len += 1;
        if value < 0x80 {
            *slot = value as u8;
            break;
        }
        *slot = (value as u8) | 0x80;
        value >>= 7;
    }
    &buf[..len]
}

/// Reads postcard's varint `u32` at the start of `bytes`; returns it and the bytes after it.
///
/// As postcard: at most 5 bytes, the fifth at most 0x0F (the 4 bits left of a `u32`);
/// over-long encodings of small values (e.g. `80 00` for 0) are accepted.
#[inline(always)]
fn take_varint_u32(bytes: &[u8]) -> Result<(u32, &[u8]), DecodeError> {
    // Written out byte by byte (the compiler keeps a loop otherwise): most values end in the
    // first two or three bytes.
    let (&b0, rest) = bytes.split_first().ok_or(DecodeError::Malformed)?;
    let value = u32::from(b0 & 0x7F);
    if b0 < 0x80 {
        return Ok((value, rest));
    }
    let (&b1, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b1 & 0x7F) << 7;
    if b1 < 0x80 {
        return Ok((value, rest));
    }
    let (&b2, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b2 & 0x7F) << 14;
    if b2 < 0x80 {
        return Ok((value, rest));
    }
    let (&b3, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b3 & 0x7F) << 21;
    if b3 < 0x80 {
        return Ok((value, rest));
    }
    // The fifth byte holds the last 4 bits and ends the varint.
    let (&b4, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    if b4 > 0x0F {
        return Err(DecodeError::Malformed);
    }
    Ok((value | u32::from(b4) << 28, rest))
}

/// The hub's fast path: if `bytes` (one message, as [`decode_message`] takes it) is a
/// [`JointAngle`] whose tag is the canonical single byte 0x00, its [`decode_message`] result
/// without building a [`Message`]; `None` for any other message (decode those with
/// [`decode_message`]).
#[inline(always)]
pub fn decode_packet(bytes: &[u8]) -> Option<Result<JointAngle, DecodeError>> {
    match bytes.split_first() {
        Some((0, body)) => Some(decode_joint_angle(body)),
        _ => None,
    }
}

/// Decodes one message from its postcard bytes (no CRC, no framing). Every byte must be used.
// Never inlined: with a single caller (a device's benchmark) the compiler would inline all 7
// decoders there, and the joint-angle fast path at its head costs twice as much inlined.
#[inline(never)]
pub fn decode_message(bytes: &[u8]) -> Result<Message, DecodeError> {
    if let Some(packet) = decode_packet(bytes) {
        return packet.map(Message::JointAngle);
    }
    let (tag, body) =
        postcard::take_from_bytes::<u32>(bytes).map_err(|_| DecodeError::Malformed)?;
    match tag {
        0 => decode_joint_angle(body).map(Message::JointAngle),
        1 => decode_pose_frame(body).map(Message::PoseFrame),
        2 => take_all::<Status>(body).map(Message::Status),
        3 => decode_config(take_all(body)?).map(Message::Config),
        4 => decode_subject_leg(take_all(body)?).map(Message::SubjectLeg),
        5 => decode_subject_knee(take_all(body)?).map(Message::SubjectKnee),
        6 => decode_subject_config(take_all(body)?).map(Message::SubjectConfig),
        unknown => Err(DecodeError::UnknownMessage(unknown)),
    }
}

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
    /// A message only a hub sends ([`PoseFrame`], tag 1, or [`Status`], tag 2), with this tag.
    /// Its body is not decoded: it may or may not be well-formed.
    FromHub(u32),
}

/// [`decode_message`] for a hub: the messages sent to a hub are decoded exactly as
/// [`decode_message`] decodes them (the same values, the same errors); a [`PoseFrame`] or a
/// [`Status`] is reported as [`HubMessage::FromHub`] without decoding its body, so their
/// decoders are not linked into a hub that does not call [`decode_message`].
pub fn decode_hub_message(bytes: &[u8]) -> Result<HubMessage, DecodeError> {
    if let Some(packet) = decode_packet(bytes) {
        return packet.map(HubMessage::JointAngle);
    }
    let (tag, body) =
        postcard::take_from_bytes::<u32>(bytes).map_err(|_| DecodeError::Malformed)?;
    match tag {
        0 => decode_joint_angle(body).map(HubMessage::JointAngle),
        1 | 2 => Ok(HubMessage::FromHub(tag)),
        3 => decode_config(ConfigWire::take_fields(body)?).map(HubMessage::Config),
        4 => decode_subject_leg(SubjectLegWire::take_fields(body)?).map(HubMessage::SubjectLeg),
        5 => decode_subject_knee(SubjectKneeWire::take_fields(body)?).map(HubMessage::SubjectKnee),
        6 => decode_subject_config(SubjectConfigWire::take_fields(body)?)
            .map(HubMessage::SubjectConfig),
        unknown => Err(DecodeError::UnknownMessage(unknown)),
    }
}

/// Returns `Err((expected, got))` unless `count` is the number of joints `model` takes.
fn check_angle_count(model: ModelId, count: usize) -> Result<(), (u8, u8)> {
    let expected = model.required_joints().len();
    if count == expected {
        Ok(())
    } else {
        // Both are <= MAX_POSE_ANGLES (heapless capacity), so they fit a u8.
        Err((expected as u8, count.min(u8::MAX as usize) as u8))
    }
}

/// Deserialises a `T` that must use every byte of `body`.
fn take_all<T: DeserializeOwned>(body: &[u8]) -> Result<T, DecodeError> {
    match postcard::take_from_bytes::<T>(body) {
        Ok((value, [])) => Ok(value),
        _ => Err(DecodeError::Malformed),
    }
}

/// Deserialises a `T` at the start of `bytes`; returns it and the bytes after it.
///
/// The hub decodes its messages' bodies field by field with this (`take_fields`): a few
/// small instances of postcard's deserialiser instead of one per mirror struct (a kilobyte
/// each on a Cortex-M), for the same bytes accepted and the same values
/// (`tests/hub_side.rs` holds them to [`decode_message`], which deserialises the mirror
/// structs whole).
fn take<T: DeserializeOwned>(bytes: &[u8]) -> Result<(T, &[u8]), DecodeError> {
    postcard::take_from_bytes::<T>(bytes).map_err(|_| DecodeError::Malformed)
}

/// `Ok` if `rest` is empty: every byte of a body must be used.
fn end(rest: &[u8]) -> Result<(), DecodeError> {
    if rest.is_empty() {
        Ok(())
    } else {
        Err(DecodeError::Malformed)
    }
}

/// A [`JointAngle`]'s body (after the tag), by hand: version, node, joint, seq (varint),
/// timestamp (varint), angle (`f32` LE), quality, and nothing after. The errors are those of
/// the postcard decoding it replaces: the version first, then the layout (`Malformed`), then
/// the joint.
#[inline(always)]
fn decode_joint_angle(body: &[u8]) -> Result<JointAngle, DecodeError> {
    // The version is the first byte of the body: check it before anything else, so a packet of
    // another version (whose layout may differ) is reported as such.
    let (&version, rest) = body.split_first().ok_or(DecodeError::Malformed)?;
    if version != PROTOCOL_VERSION {
        return Err(DecodeError::UnknownVersion(version));
    }
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

#[derive(Deserialize)]
struct PoseFrameWire {
    seq: u32,
    model: u8,
    angles: heapless::Vec<f32, MAX_POSE_ANGLES>,
    points: [[f32; 3]; crate::point::COUNT],
    distances: [f32; 3],
    flags: u8,
}

fn decode_pose_frame(body: &[u8]) -> Result<PoseFrame, DecodeError> {
    let w: PoseFrameWire = take_all(body)?;
    let model = ModelId::from_index(w.model).ok_or(DecodeError::UnknownModel(w.model))?;
    check_angle_count(model, w.angles.len())
        .map_err(|(expected, got)| DecodeError::AngleCount { expected, got })?;
    Ok(PoseFrame {
        seq: w.seq,
        model,
        angles: w.angles,
        points: w.points,
        distances: w.distances,
        flags: w.flags,
    })
}

#[derive(Deserialize)]
struct ConfigWire {
    model: u8,
    anthropometry: Option<[[f32; crate::segment::COUNT]; 2]>,
    missing_policy: u8,
    reorder_window: u8,
    request_status: bool,
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

impl ConfigWire {
    /// The body field by field (see [`take`]).
    fn take_fields(body: &[u8]) -> Result<Self, DecodeError> {
        let (model, rest) = take(body)?;
        let (anthropometry, rest) = take(rest)?;
        let (missing_policy, rest) = take(rest)?;
        let (reorder_window, rest) = take(rest)?;
        let (request_status, rest) = take(rest)?;
        end(rest)?;
        Ok(Self {
            model,
            anthropometry,
            missing_policy,
            reorder_window,
            request_status,
        })
    }
}

/// The fields' values checked in wire order (section 5 of the spec): an unknown model before
/// a bad missing policy.
fn decode_config(w: ConfigWire) -> Result<Config, DecodeError> {
    let model = ModelId::from_index(w.model).ok_or(DecodeError::UnknownModel(w.model))?;
    Ok(Config {
        model,
        anthropometry: w.anthropometry,
        missing_policy: missing_policy(w.missing_policy)?,
        reorder_window: w.reorder_window,
        request_status: w.request_status,
    })
}

#[derive(Deserialize)]
struct SubjectLegWire {
    upload: u8,
    leg: u8,
    hip_in_pelvis: [f32; 3],
    hip_axes: [[f32; 3]; 3],
    ankle_in_tibia: [f32; 3],
    ankle_axis: [f32; 3],
    subtalar_in_talus: [f32; 3],
    subtalar_axis: [f32; 3],
    mtp_in_calcn: [f32; 3],
    mtp_axis: [f32; 3],
    toetip_in_toes: [f32; 3],
}

impl SubjectLegWire {
    /// The body field by field (see [`take`]): the 11 vectors in one loop.
    fn take_fields(body: &[u8]) -> Result<Self, DecodeError> {
        let (upload, rest) = take(body)?;
        let (leg, mut rest) = take(rest)?;
        let mut v = [[0.0f32; 3]; 11];
        for slot in &mut v {
            (*slot, rest) = take(rest)?;
        }
        end(rest)?;
        let [hip_in_pelvis, h0, h1, h2, ankle_in_tibia, ankle_axis, subtalar_in_talus, subtalar_axis, mtp_in_calcn, mtp_axis, toetip_in_toes] =
            v;
        Ok(Self {
            upload,
            leg,
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
}

fn decode_subject_leg(w: SubjectLegWire) -> Result<SubjectLeg, DecodeError> {
    Ok(SubjectLeg {
        upload: w.upload,
        leg: leg(w.leg)?,
        hip_in_pelvis: w.hip_in_pelvis,
        hip_axes: w.hip_axes,
        ankle_in_tibia: w.ankle_in_tibia,
        ankle_axis: w.ankle_axis,
        subtalar_in_talus: w.subtalar_in_talus,
        subtalar_axis: w.subtalar_axis,
        mtp_in_calcn: w.mtp_in_calcn,
        mtp_axis: w.mtp_axis,
        toetip_in_toes: w.toetip_in_toes,
    })
}

#[derive(Deserialize)]
struct SubjectKneeWire {
    upload: u8,
    leg: u8,
    direction: u8,
    // More than MAX_KNEE_KNOTS fails to deserialise: Malformed.
    knots: heapless::Vec<[f32; 2], MAX_KNEE_KNOTS>,
}

impl SubjectKneeWire {
    /// The body field by field (see [`take`]).
    fn take_fields(body: &[u8]) -> Result<Self, DecodeError> {
        let (upload, rest) = take(body)?;
        let (leg, rest) = take(rest)?;
        let (direction, rest) = take(rest)?;
        let (knots, rest) = take(rest)?;
        end(rest)?;
        Ok(Self {
            upload,
            leg,
            direction,
            knots,
        })
    }
}

fn decode_subject_knee(w: SubjectKneeWire) -> Result<SubjectKnee, DecodeError> {
    Ok(SubjectKnee {
        upload: w.upload,
        leg: leg(w.leg)?,
        direction: KneeDirection::from_index(w.direction).ok_or(DecodeError::Malformed)?,
        knots: w.knots,
    })
}

#[derive(Deserialize)]
struct SubjectConfigWire {
    upload: u8,
    missing_policy: u8,
    reorder_window: u8,
    request_status: bool,
}

impl SubjectConfigWire {
    /// The body field by field (see [`take`]).
    fn take_fields(body: &[u8]) -> Result<Self, DecodeError> {
        let (upload, rest) = take(body)?;
        let (missing_policy, rest) = take(rest)?;
        let (reorder_window, rest) = take(rest)?;
        let (request_status, rest) = take(rest)?;
        end(rest)?;
        Ok(Self {
            upload,
            missing_policy,
            reorder_window,
            request_status,
        })
    }
}

fn decode_subject_config(w: SubjectConfigWire) -> Result<SubjectConfig, DecodeError> {
    Ok(SubjectConfig {
        upload: w.upload,
        missing_policy: missing_policy(w.missing_policy)?,
        reorder_window: w.reorder_window,
        request_status: w.request_status,
    })
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use proptest::prelude::*;
    use std::vec;
    use std::vec::Vec;

    /// The postcard decoding of a [`JointAngle`] body that [`decode_joint_angle`] replaces,
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
        let w: JointAngleWire = take_all(body)?;
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

    fn any_pose_frame() -> impl Strategy<Value = PoseFrame> {
        (
            prop_oneof![
                0u32..128,
                128u32..16_384,
                16_384u32..2_097_152,
                2_097_152u32..268_435_456,
                any::<u32>()
            ],
            0u8..ModelId::COUNT as u8,
            proptest::collection::vec(any::<u32>(), 46),
            any::<u8>(),
        )
            .prop_map(|(seq, model, bits, flags)| {
                let model = ModelId::from_index(model).unwrap();
                let f = |i: usize| f32::from_bits(bits[i]);
                let mut angles = heapless::Vec::new();
                for i in 0..model.required_joints().len() {
                    angles.push(f(i)).unwrap();
                }
                PoseFrame {
                    seq,
                    model,
                    angles,
                    points: core::array::from_fn(|p| core::array::from_fn(|k| f(17 + 3 * p + k))),
                    distances: [f(41), f(42), f(43)],
                    flags,
                }
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

        /// The hand-written pose frame encoding is postcard's, byte for byte, in buffers of
        /// every size (too small ones refused as postcard refuses them).
        #[test]
        fn pose_frame_fast_path_is_postcard(frame in any_pose_frame(), size in 0usize..MAX_MESSAGE_LEN + 4) {
            let msg = Message::PoseFrame(frame.clone());
            let mut a = [0u8; MAX_MESSAGE_LEN + 4];
            let mut b = [0u8; MAX_MESSAGE_LEN + 4];
            let fast = encode_message(&msg, &mut a[..size]).map(|m| m.to_vec());
            let reference = postcard::to_slice(&msg, &mut b[..size]).map(|m| m.to_vec());
            match (&fast, &reference) {
                (Ok(x), Ok(y)) => prop_assert_eq!(x, y),
                (Err(e), Err(_)) => prop_assert_eq!(*e, EncodeError::BufferTooSmall { needed: MAX_MESSAGE_LEN }),
                _ => prop_assert!(false, "size {}: {:?} vs {:?}", size, fast, reference),
            }
            // The same frame from its parts (the hub's path): the same bytes, the same refusals.
            let parts = frame.parts();
            let mut c = [0u8; MAX_MESSAGE_LEN + 4];
            let from_parts = encode_pose_frame_parts_message(&parts, &mut c[..size]).map(|m| m.to_vec());
            prop_assert_eq!(from_parts, fast);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 20_000, ..ProptestConfig::default() })]

        /// The hand-written status encoding is postcard's, byte for byte, and
        /// `encode_message`'s, in buffers of every size (too small ones refused as postcard
        /// refuses them).
        #[test]
        fn status_encoding_is_postcard(
            counters in proptest::collection::vec(
                prop_oneof![0u32..128, 128u32..16_384, 16_384u32..2_097_152, 2_097_152u32..268_435_456, any::<u32>()],
                STATUS_COUNTERS,
            ),
            size in 0usize..MAX_MESSAGE_LEN + 4,
        ) {
            let c = |i: usize| counters[i];
            let status = Status {
                packets_accepted: c(0),
                crc_errors: c(1),
                framing_errors: c(2),
                oversize_frames: c(3),
                unknown_version: c(4),
                unknown_joint: c(5),
                out_of_range: c(6),
                samples_completed: c(7),
                samples_incomplete: c(8),
                frames_sent: c(9),
                uart_overruns: c(10),
                uptime_ms: c(11),
                late_packets: c(12),
                duplicate_packets: c(13),
                malformed: c(14),
                config_rejected: c(15),
            };
            let msg = Message::Status(status);
            let mut a = [0u8; MAX_MESSAGE_LEN + 4];
            let mut b = [0u8; MAX_MESSAGE_LEN + 4];
            let mut c = [0u8; MAX_MESSAGE_LEN + 4];
            let fast = encode_status_message(&status, &mut a[..size]).map(|m| m.to_vec());
            let reference = postcard::to_slice(&msg, &mut b[..size]).map(|m| m.to_vec());
            let general = encode_message(&msg, &mut c[..size]).map(|m| m.to_vec());
            prop_assert_eq!(&fast, &general);
            match (&fast, &reference) {
                (Ok(x), Ok(y)) => prop_assert_eq!(x, y),
                (Err(e), Err(_)) => prop_assert_eq!(*e, EncodeError::BufferTooSmall { needed: MAX_MESSAGE_LEN }),
                _ => prop_assert!(false, "size {}: {:?} vs {:?}", size, fast, reference),
            }
        }
    }

    #[test]
    fn pose_frame_with_the_wrong_angle_count_is_refused() {
        let mut frame = PoseFrame {
            seq: 1,
            model: ModelId::Phak,
            angles: heapless::Vec::from_slice(&[0.0; 7]).unwrap(),
            points: [[0.0; 3]; point::COUNT],
            distances: [0.0; 3],
            flags: 0,
        };
        let mut buf = [0u8; MAX_MESSAGE_LEN];
        let err = encode_message(&Message::PoseFrame(frame.clone()), &mut buf);
        assert_eq!(
            err.unwrap_err(),
            EncodeError::AngleCount {
                expected: 8,
                got: 7
            }
        );
        frame.angles.push(0.0).unwrap();
        assert!(encode_message(&Message::PoseFrame(frame), &mut buf).is_ok());
    }

    #[test]
    fn varints_are_postcards() {
        for v in [
            0,
            1,
            127,
            128,
            300,
            16_383,
            16_384,
            1 << 21,
            (1 << 28) - 1,
            1 << 28,
            u32::MAX,
        ] {
            let mut ours = [0u8; VARINT_U32_MAX];
            let mut theirs = [0u8; VARINT_U32_MAX];
            let theirs = postcard::to_slice(&v, &mut theirs).unwrap();
            assert_eq!(varint_u32(v, &mut ours), &theirs[..], "{v}");
            assert_eq!(take_varint_u32(theirs), Ok((v, &[][..])));
        }
    }
}
