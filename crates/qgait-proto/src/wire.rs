//! Message bytes (postcard, no framing): [`encode_message`] and [`decode_message`].
//!
//! Encoding serialises the public types with postcard. Decoding reads the message tag and the
//! protocol version by hand, then the body into mirror structs whose joint and model fields are
//! raw bytes, so that an unknown tag, version, joint or model is reported as its own
//! [`DecodeError`] instead of a generic postcard error.

use serde::de::DeserializeOwned;
use serde::Deserialize;

use crate::{
    Config, DecodeError, EncodeError, JointAngle, JointId, KneeDirection, Leg, Message,
    MissingPolicy, ModelId, PoseFrame, Status, SubjectConfig, SubjectKnee, SubjectLeg,
    MAX_KNEE_KNOTS, MAX_MESSAGE_LEN, MAX_POSE_ANGLES, PROTOCOL_VERSION,
};

/// Encodes `msg` as postcard bytes (no CRC, no framing) into `out`, returning the used part.
///
/// At most [`MAX_MESSAGE_LEN`] bytes are written. Fails if `out` is too small, or if a
/// [`PoseFrame`] does not have exactly `model.required_joints().len()` angles.
pub fn encode_message<'a>(msg: &Message, out: &'a mut [u8]) -> Result<&'a mut [u8], EncodeError> {
    if let Message::PoseFrame(frame) = msg {
        check_angle_count(frame.model, frame.angles.len())
            .map_err(|(expected, got)| EncodeError::AngleCount { expected, got })?;
    }
    postcard::to_slice(msg, out).map_err(|_| EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    })
}

/// Decodes one message from its postcard bytes (no CRC, no framing). Every byte must be used.
pub fn decode_message(bytes: &[u8]) -> Result<Message, DecodeError> {
    let (tag, body) =
        postcard::take_from_bytes::<u32>(bytes).map_err(|_| DecodeError::Malformed)?;
    match tag {
        0 => decode_joint_angle(body).map(Message::JointAngle),
        1 => decode_pose_frame(body).map(Message::PoseFrame),
        2 => take_all::<Status>(body).map(Message::Status),
        3 => decode_config(body).map(Message::Config),
        4 => decode_subject_leg(body).map(Message::SubjectLeg),
        5 => decode_subject_knee(body).map(Message::SubjectKnee),
        6 => decode_subject_config(body).map(Message::SubjectConfig),
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

fn decode_joint_angle(body: &[u8]) -> Result<JointAngle, DecodeError> {
    // The version is the first byte of the body: check it before anything else, so a packet of
    // another version (whose layout may differ) is reported as such.
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

fn decode_config(body: &[u8]) -> Result<Config, DecodeError> {
    let w: ConfigWire = take_all(body)?;
    let missing_policy = missing_policy(w.missing_policy)?;
    Ok(Config {
        model: ModelId::from_index(w.model).ok_or(DecodeError::UnknownModel(w.model))?,
        anthropometry: w.anthropometry,
        missing_policy,
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

fn decode_subject_leg(body: &[u8]) -> Result<SubjectLeg, DecodeError> {
    let w: SubjectLegWire = take_all(body)?;
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

fn decode_subject_knee(body: &[u8]) -> Result<SubjectKnee, DecodeError> {
    let w: SubjectKneeWire = take_all(body)?;
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

fn decode_subject_config(body: &[u8]) -> Result<SubjectConfig, DecodeError> {
    let w: SubjectConfigWire = take_all(body)?;
    Ok(SubjectConfig {
        upload: w.upload,
        missing_policy: missing_policy(w.missing_policy)?,
        reorder_window: w.reorder_window,
        request_status: w.request_status,
    })
}
