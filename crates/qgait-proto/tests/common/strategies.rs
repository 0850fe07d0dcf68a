//! proptest strategies producing arbitrary valid messages (any bit pattern for floats, NaN
//! included, any u32).

use proptest::prelude::*;
use qgait_proto::{
    ChainTable, ChainTableConfig, Config, FusionMode, HeadingAxisId, ImuConfig, ImuHeading,
    InputMode, JointAngle, JointId, KneeDirection, Leg, Message, MissingPolicy, ModelId, PoseFrame,
    PoseVelocities, RawImuConfig, RawImuSample, RawImuStatus, SampleHeader, SegmentId,
    SegmentOrientation, Status, SubjectConfig, SubjectKnee, SubjectLeg, VelocityConfig,
    MAX_CHAIN_TABLE_BYTES, MAX_KNEE_KNOTS, MAX_POSE_ANGLES,
};

/// Any f32 bit pattern: NaNs, infinities, subnormals, signed zeros.
pub fn any_f32_bits() -> impl Strategy<Value = f32> {
    any::<u32>().prop_map(f32::from_bits)
}

/// u32 values spread over every varint length (1 to 5 bytes).
pub fn any_varint_u32() -> impl Strategy<Value = u32> {
    prop_oneof![
        0u32..128,
        128u32..16_384,
        16_384u32..2_097_152,
        2_097_152u32..268_435_456,
        any::<u32>()
    ]
}

pub fn joint_id() -> impl Strategy<Value = JointId> {
    (0..JointId::COUNT as u8).prop_map(|i| JointId::from_index(i).expect("in range"))
}

pub fn model_id() -> impl Strategy<Value = ModelId> {
    (0..ModelId::COUNT as u8).prop_map(|i| ModelId::from_index(i).expect("in range"))
}

pub fn joint_angle() -> impl Strategy<Value = JointAngle> {
    (
        any::<u8>(),
        joint_id(),
        any_varint_u32(),
        any_varint_u32(),
        any_f32_bits(),
        any::<u8>(),
    )
        .prop_map(
            |(node, joint, seq, timestamp_us, angle, quality)| JointAngle {
                version: qgait_proto::PROTOCOL_VERSION,
                node,
                joint,
                seq,
                timestamp_us,
                angle,
                quality,
            },
        )
}

pub fn pose_frame() -> impl Strategy<Value = PoseFrame> {
    (
        any_varint_u32(),
        any_varint_u32(),
        model_id(),
        proptest::collection::vec(any_f32_bits(), MAX_POSE_ANGLES),
        proptest::collection::vec(any_f32_bits(), 24 + 3),
        any::<u8>(),
    )
        .prop_map(|(seq, timestamp_us, model, angles, coords, flags)| {
            let n = model.required_joints().len();
            let angles = heapless::Vec::from_slice(&angles[..n]).expect("n <= 17");
            let mut points = [[0.0f32; 3]; 8];
            for (i, p) in points.iter_mut().enumerate() {
                p.copy_from_slice(&coords[3 * i..3 * i + 3]);
            }
            PoseFrame {
                seq,
                timestamp_us,
                model,
                angles,
                points,
                distances: [coords[24], coords[25], coords[26]],
                flags,
            }
        })
}

pub fn status() -> impl Strategy<Value = Status> {
    proptest::collection::vec(any_varint_u32(), 20).prop_map(|c| Status {
        packets_accepted: c[0],
        crc_errors: c[1],
        framing_errors: c[2],
        oversize_frames: c[3],
        unknown_version: c[4],
        unknown_joint: c[5],
        out_of_range: c[6],
        samples_completed: c[7],
        samples_incomplete: c[8],
        frames_sent: c[9],
        uart_overruns: c[10],
        uptime_ms: c[11],
        late_packets: c[12],
        duplicate_packets: c[13],
        malformed: c[14],
        config_rejected: c[15],
        orientation_not_unit: c[16],
        uncalibrated_samples: c[17],
        calibrations: c[18],
        calibration_rejected: c[19],
    })
}

pub fn config() -> impl Strategy<Value = Config> {
    (
        model_id(),
        proptest::option::of(proptest::collection::vec(any_f32_bits(), 8)),
        any::<bool>(),
        any::<u8>(),
        any::<bool>(),
    )
        .prop_map(
            |(model, lengths, hold, reorder_window, request_status)| Config {
                model,
                anthropometry: lengths
                    .map(|l| [[l[0], l[1], l[2], l[3]], [l[4], l[5], l[6], l[7]]]),
                missing_policy: if hold {
                    MissingPolicy::HoldLast
                } else {
                    MissingPolicy::Drop
                },
                reorder_window,
                request_status,
            },
        )
}

pub fn message() -> impl Strategy<Value = Message> {
    prop_oneof![
        joint_angle().prop_map(Message::JointAngle),
        pose_frame().prop_map(Message::PoseFrame),
        status().prop_map(Message::Status),
        config().prop_map(Message::Config),
        subject_leg().prop_map(Message::SubjectLeg),
        subject_knee().prop_map(Message::SubjectKnee),
        subject_config().prop_map(Message::SubjectConfig),
        segment_orientation().prop_map(Message::SegmentOrientation),
        imu_config().prop_map(Message::ImuConfig),
        chain_table().prop_map(Message::ChainTable),
        chain_table_config().prop_map(Message::ChainTableConfig),
        raw_imu_sample().prop_map(Message::RawImuSample),
        raw_imu_config().prop_map(Message::RawImuConfig),
        raw_imu_status().prop_map(Message::RawImuStatus),
        velocity_config().prop_map(Message::VelocityConfig),
        pose_velocities().prop_map(Message::PoseVelocities),
    ]
}

pub fn velocity_config() -> impl Strategy<Value = VelocityConfig> {
    (any::<bool>(), any_varint_u32(), any::<bool>()).prop_map(
        |(enabled, period_us, request_status)| VelocityConfig {
            enabled,
            period_us,
            request_status,
        },
    )
}

pub fn pose_velocities() -> impl Strategy<Value = PoseVelocities> {
    (
        any_varint_u32(),
        any_varint_u32(),
        proptest::array::uniform24(any_f32_bits()),
    )
        .prop_map(|(seq, dt_us, v)| PoseVelocities {
            seq,
            dt_us,
            velocities: core::array::from_fn(|p| core::array::from_fn(|k| v[3 * p + k])),
        })
}

pub fn chain_table() -> impl Strategy<Value = ChainTable> {
    (
        any::<u8>(),
        any::<u16>(),
        proptest::collection::vec(any::<u8>(), 0..=MAX_CHAIN_TABLE_BYTES),
    )
        .prop_map(|(upload, at, bytes)| ChainTable {
            upload,
            at,
            bytes: heapless::Vec::from_slice(&bytes).expect("at most MAX_CHAIN_TABLE_BYTES"),
        })
}

pub fn chain_table_config() -> impl Strategy<Value = ChainTableConfig> {
    (
        any::<u8>(),
        any::<u16>(),
        any::<u32>(),
        any::<bool>(),
        any::<bool>(),
        any::<u8>(),
        any::<bool>(),
    )
        .prop_map(
            |(upload, len, crc, knee_flexes_positive, hold, reorder_window, request_status)| {
                ChainTableConfig {
                    upload,
                    len,
                    crc,
                    knee_flexes_positive,
                    missing_policy: missing_policy(hold),
                    reorder_window,
                    request_status,
                }
            },
        )
}

pub fn segment_id() -> impl Strategy<Value = SegmentId> {
    proptest::sample::select(SegmentId::ALL.to_vec())
}

pub fn segment_orientation() -> impl Strategy<Value = SegmentOrientation> {
    (
        any::<u8>(),
        segment_id(),
        any_varint_u32(),
        any_varint_u32(),
        any::<[i16; 4]>(),
        any::<u8>(),
    )
        .prop_map(
            |(node, segment, seq, timestamp_us, q14, quality)| SegmentOrientation {
                header: SampleHeader::new(node, segment, seq, timestamp_us),
                q14,
                quality,
            },
        )
}

pub fn imu_config() -> impl Strategy<Value = ImuConfig> {
    (
        0u8..3,
        any::<u8>(),
        any::<bool>(),
        [any_f32_bits(), any_f32_bits(), any_f32_bits()],
        proptest::option::of((segment_id(), 0u8..6)),
        any::<bool>(),
    )
        .prop_map(
            |(mode, segments, calibrate, sensor_to_opensim, heading, request_status)| ImuConfig {
                mode: InputMode::from_repr(mode).expect("in range"),
                segments,
                calibrate,
                sensor_to_opensim,
                heading: heading.map(|(base, axis)| ImuHeading {
                    base,
                    axis: HeadingAxisId::ALL[usize::from(axis)],
                }),
                request_status,
            },
        )
}

fn missing_policy(hold: bool) -> MissingPolicy {
    if hold {
        MissingPolicy::HoldLast
    } else {
        MissingPolicy::Drop
    }
}

fn leg(right: bool) -> Leg {
    if right {
        Leg::Right
    } else {
        Leg::Left
    }
}

pub fn subject_leg() -> impl Strategy<Value = SubjectLeg> {
    (
        any::<u8>(),
        any::<bool>(),
        proptest::collection::vec(any_f32_bits(), 33),
    )
        .prop_map(|(upload, right, v)| {
            let at = |i: usize| [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
            SubjectLeg {
                upload,
                leg: leg(right),
                hip_in_pelvis: at(0),
                hip_axes: [at(1), at(2), at(3)],
                ankle_in_tibia: at(4),
                ankle_axis: at(5),
                subtalar_in_talus: at(6),
                subtalar_axis: at(7),
                mtp_in_calcn: at(8),
                mtp_axis: at(9),
                toetip_in_toes: at(10),
            }
        })
}

pub fn subject_knee() -> impl Strategy<Value = SubjectKnee> {
    (
        any::<u8>(),
        any::<bool>(),
        any::<bool>(),
        proptest::collection::vec([any_f32_bits(), any_f32_bits()], 0..=MAX_KNEE_KNOTS),
    )
        .prop_map(|(upload, right, tx, knots)| SubjectKnee {
            upload,
            leg: leg(right),
            direction: if tx {
                KneeDirection::Tx
            } else {
                KneeDirection::Ty
            },
            knots: heapless::Vec::from_slice(&knots).expect("at most MAX_KNEE_KNOTS"),
        })
}

pub fn subject_config() -> impl Strategy<Value = SubjectConfig> {
    (any::<u8>(), any::<bool>(), any::<u8>(), any::<bool>()).prop_map(
        |(upload, hold, reorder_window, request_status)| SubjectConfig {
            upload,
            missing_policy: missing_policy(hold),
            reorder_window,
            request_status,
        },
    )
}

/// Counts spread over every zigzag varint length (1 to 3 bytes), the ends included.
pub fn any_count() -> impl Strategy<Value = i16> {
    prop_oneof![
        -64i16..64,
        -8192i16..8192,
        Just(i16::MIN),
        Just(i16::MAX),
        any::<i16>(),
    ]
}

pub fn raw_imu_sample() -> impl Strategy<Value = RawImuSample> {
    (
        any::<u8>(),
        segment_id(),
        any_varint_u32(),
        any_varint_u32(),
        [any_count(), any_count(), any_count()],
        [any_count(), any_count(), any_count()],
        proptest::option::of([any_count(), any_count(), any_count()]),
    )
        .prop_map(
            |(node, segment, seq, timestamp_us, gyro, accel, mag)| RawImuSample {
                header: SampleHeader::new(node, segment, seq, timestamp_us),
                gyro,
                accel,
                mag,
            },
        )
}

pub fn raw_imu_config() -> impl Strategy<Value = RawImuConfig> {
    (
        any::<u8>(),
        any::<bool>(),
        prop_oneof![1u16..128, any::<u16>()],
        any::<u8>(),
        [any_f32_bits(), any_f32_bits(), any_f32_bits()],
        any::<bool>(),
    )
        .prop_map(
            |(segments, nine, rate_hz, output_every, [g, a, m], request_status)| RawImuConfig {
                segments,
                fusion: if nine {
                    FusionMode::NineD
                } else {
                    FusionMode::SixD
                },
                rate_hz,
                output_every,
                gyro_per_count: g,
                accel_per_count: a,
                mag_per_count: m,
                request_status,
            },
        )
}

pub fn raw_imu_status() -> impl Strategy<Value = RawImuStatus> {
    proptest::array::uniform9(any_varint_u32()).prop_map(|c| RawImuStatus {
        samples_accepted: c[0],
        saturated: c[1],
        rate_gaps: c[2],
        samples_lost: c[3],
        timing_errors: c[4],
        stale_samples: c[5],
        resyncs: c[6],
        missing_magnetometer: c[7],
        not_configured: c[8],
    })
}
