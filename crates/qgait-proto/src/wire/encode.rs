//! The hand-written encoders: a [`PoseFrame`] (the hub sends one per sample, and 46 `f32`s
//! through postcard's serialiser cost several times more on the hub) and a [`Status`] (so that
//! a hub links no message serialiser at all). Their bytes are postcard's, documented in
//! `docs/protocol.md`; the tests below hold them to postcard itself, byte for byte, on random
//! messages in buffers of every size.

use super::check_angle_count;
use crate::WireByte;
use crate::{
    point, EncodeError, ModelId, PoseFrame, PoseVelocities, RawImuStatus, SegmentOrientation,
    Status, MAX_MESSAGE_LEN,
};

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
            timestamp_us: self.timestamp_us,
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
    /// [`PoseFrame::timestamp_us`].
    pub timestamp_us: u32,
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
    // tag, seq, timestamp, model, angle count (< 128: one varint byte), angles, points,
    // distances, flags; the varints' lengths first, so that each is written in place.
    let (seq_len, time_len) = (varint_len(parts.seq), varint_len(parts.timestamp_us));
    let head_len = 1 + seq_len + time_len + 2;
    let len = head_len + 4 * (count + 3 * point::COUNT + 3) + 1;
    let Some(out) = out.get_mut(..len) else {
        return Err(EncodeError::BufferTooSmall {
            needed: MAX_MESSAGE_LEN,
        });
    };
    let (head, rest) = out.split_at_mut(head_len);
    if let [tag, varints @ .., model, angle_count] = head {
        *tag = 1; // Message::PoseFrame's tag
        let (seq, time) = varints.split_at_mut(seq_len);
        put_varint(seq, parts.seq);
        put_varint(time, parts.timestamp_us);
        *model = parts.model.index();
        *angle_count = count as u8;
    }
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

/// The length of `value`'s varint: 1 to 5 bytes, 7 bits each.
///
/// `(bits + 6) / 7` and not `bits.div_ceil(7)`, whose remainder test costs the hub's whole
/// sample 19 instructions more (5,993 against 5,974; `cargo xtask bench`).
#[inline(always)]
#[allow(clippy::manual_div_ceil)]
fn varint_len(value: u32) -> usize {
    ((32 - (value | 1).leading_zeros() + 6) / 7) as usize
}

/// Writes `value`'s varint into `slots`, which [`varint_len`] sized.
#[inline(always)]
fn put_varint(slots: &mut [u8], mut value: u32) {
    for slot in slots.iter_mut() {
        *slot = (value as u8) | 0x80;
        value >>= 7;
    }
    if let Some(last) = slots.last_mut() {
        *last &= 0x7F;
    }
}

/// [`encode_message`] of `Message::Status(status)`, without building the [`Message`]: the same
/// bytes as postcard's (the tag, then the 20 counters as varints in declaration order), written
/// by hand so that a hub, which encodes no other message with [`encode_message`], links no
/// other message's serialiser.
pub(crate) fn encode_status_message<'a>(
    status: &Status,
    out: &'a mut [u8],
) -> Result<&'a mut [u8], EncodeError> {
    let counters = status.counters();
    let too_small = EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    };
    *out.first_mut().ok_or(too_small)? = 2; // Message::Status's tag
    let mut len = 1;
    // The varints written straight into `out`, their length found as they are written.
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

/// A message written a field at a time as postcard writes it: `u8`s as bytes, `u32`s as
/// varints, `i16`s as zigzag varints.
struct Fields<'a> {
    out: &'a mut [u8],
    len: usize,
}

impl Fields<'_> {
    const TOO_SMALL: EncodeError = EncodeError::BufferTooSmall {
        needed: MAX_MESSAGE_LEN,
    };

    fn byte(&mut self, b: u8) -> Result<(), EncodeError> {
        *self.out.get_mut(self.len).ok_or(Self::TOO_SMALL)? = b;
        self.len += 1;
        Ok(())
    }

    fn varint(&mut self, mut value: u32) -> Result<(), EncodeError> {
        while value >= 0x80 {
            self.byte((value as u8) | 0x80)?;
            value >>= 7;
        }
        self.byte(value as u8)
    }

    fn zigzag(&mut self, v: i16) -> Result<(), EncodeError> {
        self.varint(u32::from(((v << 1) ^ (v >> 15)) as u16))
    }
}

/// [`encode_message`] of `Message::SegmentOrientation(packet)`, by hand (a node links no
/// message serialiser): the tag 7, version, node, segment, seq, timestamp, the Q14
/// components, quality.
pub(crate) fn encode_segment_orientation_message(
    p: &SegmentOrientation,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let mut f = Fields { out, len: 0 };
    f.byte(7)?;
    f.byte(p.header.version)?;
    f.byte(p.header.node)?;
    f.byte(p.header.segment.wire_byte())?;
    f.varint(p.header.seq)?;
    f.varint(p.header.timestamp_us)?;
    for c in p.q14 {
        f.zigzag(c)?;
    }
    f.byte(p.quality)?;
    Ok(f.len)
}

/// [`encode_message`] of `Message::RawImuStatus(status)`, by hand: the tag 13, then its
/// counters as varints in wire order.
pub(crate) fn encode_raw_imu_status_message(
    s: &RawImuStatus,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let mut f = Fields { out, len: 0 };
    f.varint(crate::RAW_IMU_STATUS_TAG)?;
    for (_, value) in s.named_counters() {
        f.varint(value)?;
    }
    Ok(f.len)
}

/// [`encode_message`] of `Message::PoseVelocities(v)`, by hand (a hub links no message
/// serialiser): the tag 15, seq, dt_us, the 24 `f32`s.
pub(crate) fn encode_pose_velocities_message(
    v: &PoseVelocities,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let mut f = Fields { out, len: 0 };
    f.varint(crate::POSE_VELOCITIES_TAG)?;
    f.varint(v.seq)?;
    f.varint(v.dt_us)?;
    let at = f.len;
    let bytes = f
        .out
        .get_mut(at..at + 4 * 3 * point::COUNT)
        .ok_or(Fields::TOO_SMALL)?;
    put_f32s(bytes, v.velocities.as_flattened());
    Ok(at + 4 * 3 * point::COUNT)
}

/// Writes `values` as postcard writes `f32`s (4 bytes, little-endian) into `out`.
#[inline(always)]
fn put_f32s(out: &mut [u8], values: &[f32]) {
    for (slot, value) in out.chunks_exact_mut(4).zip(values) {
        slot.copy_from_slice(&value.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use crate::sizes::STATUS_COUNTERS;
    use crate::{encode_message, Message};
    use proptest::prelude::*;

    fn any_pose_frame() -> impl Strategy<Value = PoseFrame> {
        (
            prop_oneof![
                0u32..128,
                128u32..16_384,
                16_384u32..2_097_152,
                2_097_152u32..268_435_456,
                any::<u32>()
            ],
            prop_oneof![0u32..128, 2_097_152u32..268_435_456, any::<u32>()],
            0u8..ModelId::COUNT as u8,
            proptest::collection::vec(any::<u32>(), 46),
            any::<u8>(),
        )
            .prop_map(|(seq, timestamp_us, model, bits, flags)| {
                let model = ModelId::from_index(model).unwrap();
                let f = |i: usize| f32::from_bits(bits[i]);
                let mut angles = heapless::Vec::new();
                for i in 0..model.required_joints().len() {
                    angles.push(f(i)).unwrap();
                }
                PoseFrame {
                    seq,
                    timestamp_us,
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
                orientation_not_unit: c(16),
                uncalibrated_samples: c(17),
                calibrations: c(18),
                calibration_rejected: c(19),
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
            timestamp_us: 10_000,
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
}
