//! Random messages and random streams for the stream fuzz, from the seeded [`Rng`].

use super::Rng;
use qgait_proto::{
    encode_frame, encode_message, encode_raw_frame, ChainTable, ChainTableConfig, Config,
    FusionMode, HeadingAxisId, ImuConfig, ImuHeading, InputMode, JointAngle, JointId,
    KneeDirection, Leg, Message, MissingPolicy, ModelId, PoseFrame, RawImuConfig, RawImuSample,
    RawImuStatus, SampleHeader, SegmentId, SegmentOrientation, Status, SubjectConfig, SubjectKnee,
    SubjectLeg, MAX_CHAIN_TABLE_BYTES, MAX_FRAME_LEN, MAX_KNEE_KNOTS, MAX_MESSAGE_LEN,
    PROTOCOL_VERSION,
};

/// A float that is usually ordinary and sometimes any bit pattern (NaN, inf, subnormal).
fn float(rng: &mut Rng) -> f32 {
    if rng.chance(10) {
        rng.f32_bits()
    } else {
        (rng.next_u32() as f32 / u32::MAX as f32 - 0.5) * 4.0
    }
}

/// A u32 of a random varint length.
fn varint_u32(rng: &mut Rng) -> u32 {
    let bits = [7u32, 14, 21, 28, 32][rng.below(5)];
    rng.next_u32() >> (32 - bits)
}

/// A sensor count: small (one varint byte), middling (two) or any (up to three).
fn count(rng: &mut Rng) -> i16 {
    match rng.below(3) {
        0 => rng.below(128) as i16 - 64,
        1 => rng.below(16384) as i16 - 8192,
        _ => rng.next_u32() as i16,
    }
}

/// Any valid message.
pub fn message(rng: &mut Rng) -> Message {
    match rng.below(16) {
        0 => Message::JointAngle(JointAngle {
            version: PROTOCOL_VERSION,
            node: rng.byte(),
            joint: JointId::ALL[rng.below(JointId::COUNT)],
            seq: varint_u32(rng),
            timestamp_us: varint_u32(rng),
            angle: float(rng),
            quality: rng.byte(),
        }),
        1 => {
            let model = ModelId::ALL[rng.below(ModelId::COUNT)];
            let mut angles = heapless::Vec::new();
            for _ in model.required_joints() {
                angles.push(float(rng)).expect("at most 17");
            }
            let mut points = [[0.0f32; 3]; 8];
            for p in points.iter_mut().flatten() {
                *p = float(rng);
            }
            Message::PoseFrame(PoseFrame {
                seq: varint_u32(rng),
                timestamp_us: varint_u32(rng),
                model,
                angles,
                points,
                distances: [float(rng), float(rng), float(rng)],
                flags: rng.byte(),
            })
        }
        2 => Message::Status(Status {
            packets_accepted: varint_u32(rng),
            crc_errors: varint_u32(rng),
            framing_errors: varint_u32(rng),
            oversize_frames: varint_u32(rng),
            unknown_version: varint_u32(rng),
            unknown_joint: varint_u32(rng),
            out_of_range: varint_u32(rng),
            samples_completed: varint_u32(rng),
            samples_incomplete: varint_u32(rng),
            frames_sent: varint_u32(rng),
            uart_overruns: varint_u32(rng),
            uptime_ms: varint_u32(rng),
            late_packets: varint_u32(rng),
            duplicate_packets: varint_u32(rng),
            malformed: varint_u32(rng),
            config_rejected: varint_u32(rng),
            orientation_not_unit: varint_u32(rng),
            uncalibrated_samples: varint_u32(rng),
            calibrations: varint_u32(rng),
            calibration_rejected: varint_u32(rng),
        }),
        7 => Message::SegmentOrientation(SegmentOrientation {
            header: SampleHeader::new(
                rng.byte(),
                SegmentId::ALL[rng.below(SegmentId::ALL.len())],
                varint_u32(rng),
                varint_u32(rng),
            ),
            q14: [0; 4].map(|_: i16| rng.next_u32() as i16),
            quality: rng.byte(),
        }),
        8 => Message::ImuConfig(ImuConfig {
            mode: InputMode::from_repr(rng.below(3) as u8).expect("in range"),
            segments: rng.byte(),
            calibrate: rng.chance(50),
            sensor_to_opensim: [float(rng), float(rng), float(rng)],
            heading: rng.chance(50).then(|| ImuHeading {
                base: SegmentId::ALL[rng.below(SegmentId::ALL.len())],
                axis: HeadingAxisId::ALL[rng.below(6)],
            }),
            request_status: rng.chance(50),
        }),
        9 => {
            let mut bytes = heapless::Vec::new();
            for _ in 0..rng.below(MAX_CHAIN_TABLE_BYTES + 1) {
                bytes
                    .push(rng.byte())
                    .expect("at most MAX_CHAIN_TABLE_BYTES");
            }
            Message::ChainTable(ChainTable {
                upload: rng.byte(),
                at: varint_u32(rng) as u16,
                bytes,
            })
        }
        10 => Message::ChainTableConfig(ChainTableConfig {
            upload: rng.byte(),
            len: varint_u32(rng) as u16,
            crc: varint_u32(rng),
            knee_flexes_positive: rng.chance(50),
            missing_policy: if rng.chance(50) {
                MissingPolicy::Drop
            } else {
                MissingPolicy::HoldLast
            },
            reorder_window: rng.byte(),
            request_status: rng.chance(50),
        }),
        11 => Message::RawImuSample(RawImuSample {
            header: SampleHeader::new(
                rng.byte(),
                SegmentId::ALL[rng.below(SegmentId::ALL.len())],
                varint_u32(rng),
                varint_u32(rng),
            ),
            gyro: [0; 3].map(|_: i16| count(rng)),
            accel: [0; 3].map(|_: i16| count(rng)),
            mag: rng.chance(50).then(|| [0; 3].map(|_: i16| count(rng))),
        }),
        12 => Message::RawImuConfig(RawImuConfig {
            segments: rng.byte(),
            fusion: if rng.chance(50) {
                FusionMode::SixD
            } else {
                FusionMode::NineD
            },
            rate_hz: varint_u32(rng) as u16,
            output_every: rng.byte(),
            gyro_per_count: float(rng),
            accel_per_count: float(rng),
            mag_per_count: float(rng),
            request_status: rng.chance(50),
        }),
        13 => Message::RawImuStatus(RawImuStatus {
            samples_accepted: varint_u32(rng),
            saturated: varint_u32(rng),
            rate_gaps: varint_u32(rng),
            samples_lost: varint_u32(rng),
            timing_errors: varint_u32(rng),
            stale_samples: varint_u32(rng),
            resyncs: varint_u32(rng),
            missing_magnetometer: varint_u32(rng),
            not_configured: varint_u32(rng),
        }),
        14 => Message::VelocityConfig(qgait_proto::VelocityConfig {
            enabled: rng.chance(50),
            period_us: varint_u32(rng),
            request_status: rng.chance(50),
        }),
        15 => Message::PoseVelocities(qgait_proto::PoseVelocities {
            seq: varint_u32(rng),
            dt_us: varint_u32(rng),
            velocities: [[0.0f32; 3]; 8].map(|p| p.map(|_| float(rng))),
        }),
        4 => Message::SubjectLeg(SubjectLeg {
            upload: rng.byte(),
            leg: Leg::ALL[rng.below(2)],
            hip_in_pelvis: [float(rng), float(rng), float(rng)],
            hip_axes: [
                [float(rng), float(rng), float(rng)],
                [float(rng), float(rng), float(rng)],
                [float(rng), float(rng), float(rng)],
            ],
            ankle_in_tibia: [float(rng), float(rng), float(rng)],
            ankle_axis: [float(rng), float(rng), float(rng)],
            subtalar_in_talus: [float(rng), float(rng), float(rng)],
            subtalar_axis: [float(rng), float(rng), float(rng)],
            mtp_in_calcn: [float(rng), float(rng), float(rng)],
            mtp_axis: [float(rng), float(rng), float(rng)],
            toetip_in_toes: [float(rng), float(rng), float(rng)],
        }),
        5 => {
            let mut knots = heapless::Vec::new();
            for _ in 0..rng.below(MAX_KNEE_KNOTS + 1) {
                knots
                    .push([float(rng), float(rng)])
                    .expect("at most MAX_KNEE_KNOTS");
            }
            Message::SubjectKnee(SubjectKnee {
                upload: rng.byte(),
                leg: Leg::ALL[rng.below(2)],
                direction: KneeDirection::ALL[rng.below(2)],
                knots,
            })
        }
        6 => Message::SubjectConfig(SubjectConfig {
            upload: rng.byte(),
            missing_policy: if rng.chance(50) {
                MissingPolicy::Drop
            } else {
                MissingPolicy::HoldLast
            },
            reorder_window: rng.byte(),
            request_status: rng.chance(50),
        }),
        _ => Message::Config(Config {
            model: ModelId::ALL[rng.below(ModelId::COUNT)],
            anthropometry: if rng.chance(50) {
                Some([
                    [float(rng), float(rng), float(rng), float(rng)],
                    [float(rng), float(rng), float(rng), float(rng)],
                ])
            } else {
                None
            },
            missing_policy: if rng.chance(50) {
                MissingPolicy::Drop
            } else {
                MissingPolicy::HoldLast
            },
            reorder_window: rng.byte(),
            request_status: rng.chance(50),
        }),
    }
}

/// Bytes of the postcard varint of `v`.
fn varint_len(v: u32) -> usize {
    (1..5).find(|&n| v < 1 << (7 * n)).unwrap_or(5)
}

/// The frame of a message.
pub fn frame_of(msg: &Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    encode_frame(msg, &mut buf)
        .expect("valid messages encode")
        .to_vec()
}

/// Applies 1 to 4 random byte-level mutations to `bytes`.
pub fn mutate(rng: &mut Rng, bytes: &mut Vec<u8>) {
    for _ in 0..1 + rng.below(4) {
        if bytes.is_empty() {
            bytes.push(rng.byte());
            continue;
        }
        let at = rng.below(bytes.len());
        match rng.below(7) {
            0 => bytes[at] ^= 1 << rng.below(8),
            1 => bytes[at] = rng.byte(),
            2 => {
                bytes.remove(at);
            }
            3 => bytes.insert(at, rng.byte()),
            4 => bytes.truncate(at),
            5 => bytes[at] = 0,
            _ => {
                let end = (at + 1 + rng.below(16)).min(bytes.len());
                let copy = bytes[at..end].to_vec();
                let to = rng.below(bytes.len() + 1);
                bytes.splice(to..to, copy);
            }
        }
    }
}

/// Builds a random stream of 1 to 12 pieces; returns its bytes and the good messages that were
/// sent after a resynchronising 0x00 (they must all decode, in order).
pub fn stream(rng: &mut Rng) -> (Vec<u8>, Vec<Message>) {
    let mut bytes = Vec::new();
    let mut goods = Vec::new();
    for _ in 0..1 + rng.below(12) {
        match rng.below(16) {
            0 | 1 => {
                let msg = message(rng);
                bytes.push(0);
                bytes.extend(frame_of(&msg));
                goods.push(msg);
            }
            2 => {
                // A valid frame without a leading 0x00: may merge with the noise before it.
                bytes.extend(frame_of(&message(rng)));
            }
            3 | 4 => {
                // A frame mutated on the wire (bit flips, truncation, lost or extra delimiters...).
                let mut f = frame_of(&message(rng));
                mutate(rng, &mut f);
                bytes.extend(f);
            }
            5 => {
                // Message bytes mutated before framing: a good CRC over bad contents.
                let msg = message(rng);
                let mut buf = [0u8; MAX_MESSAGE_LEN];
                let mut payload = encode_message(&msg, &mut buf).expect("encodes").to_vec();
                match &msg {
                    Message::PoseFrame(p) if rng.chance(30) => {
                        // Another model's id over these angles: an angle count mismatch.
                        let at = 1 + varint_len(p.seq) + varint_len(p.timestamp_us);
                        payload[at] = (payload[at] + 1 + rng.below(2) as u8) % 3;
                    }
                    _ => mutate(rng, &mut payload),
                }
                let mut out = vec![0u8; 2 * payload.len() + 16];
                bytes.extend_from_slice(encode_raw_frame(&payload, &mut out).expect("fits"));
            }
            6 => {
                // Random garbage with a random density of zeros.
                let zeros = [0u32, 1, 5, 30][rng.below(4)];
                for _ in 0..rng.below(300) {
                    bytes.push(if rng.chance(zeros) { 0 } else { rng.byte() });
                }
            }
            7 => {
                // A long run without a delimiter: oversize.
                for _ in 0..MAX_FRAME_LEN - 5 + rng.below(600) {
                    bytes.push(rng.byte() | 1);
                }
            }
            _ => {
                let zeros = rng.below(4);
                bytes.extend(std::iter::repeat_n(0u8, zeros));
            }
        }
    }
    (bytes, goods)
}
