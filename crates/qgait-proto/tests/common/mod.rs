//! Shared helpers of the integration tests: sample messages and stream helpers.
#![allow(dead_code)]

use qgait_proto::{
    encode_frame, Config, DecodeError, FrameDecoder, JointAngle, JointId, KneeDirection, Leg,
    Message, MissingPolicy, ModelId, PoseFrame, SampleHeader, Status, SubjectConfig, SubjectKnee,
    SubjectLeg, MAX_FRAME_LEN, PROTOCOL_VERSION,
};

/// A typical joint-angle packet.
pub fn joint_angle(seq: u32, joint: JointId, angle: f32) -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: 3,
        joint,
        seq,
        timestamp_us: seq.wrapping_mul(10_000),
        angle,
        quality: 0,
    }
}

/// A pose frame of `model` at 100 Hz (`seq` × 10 ms) with angles `0.1, 0.2, ...` and made-up points.
pub fn pose_frame(seq: u32, model: ModelId) -> PoseFrame {
    let mut angles = heapless::Vec::new();
    for i in 0..model.required_joints().len() {
        angles
            .push(0.1 * (i as f32 + 1.0))
            .expect("at most 17 angles");
    }
    let mut points = [[0.0f32; 3]; 8];
    for (i, p) in points.iter_mut().enumerate() {
        *p = [
            0.01 * i as f32,
            -0.1 * i as f32,
            if i < 4 { 0.08 } else { -0.08 },
        ];
    }
    PoseFrame {
        seq,
        timestamp_us: seq.wrapping_mul(10_000),
        model,
        angles,
        points,
        distances: [0.16, 0.17, 0.18],
        flags: 0,
    }
}

/// A status with distinct counters.
pub fn status() -> Status {
    Status {
        packets_accepted: 1_000_000,
        crc_errors: 1,
        framing_errors: 2,
        oversize_frames: 3,
        unknown_version: 4,
        unknown_joint: 5,
        out_of_range: 6,
        samples_completed: 70_000,
        samples_incomplete: 8,
        frames_sent: 69_990,
        uart_overruns: 9,
        uptime_ms: 3_600_000,
        late_packets: 10,
        duplicate_packets: 11,
        malformed: 12,
        config_rejected: 13,
        orientation_not_unit: 14,
        uncalibrated_samples: 15,
        calibrations: 16,
        calibration_rejected: 17,
    }
}

/// A config with anthropometry.
pub fn config() -> Config {
    Config {
        model: ModelId::Phak,
        anthropometry: Some([[0.0835, 0.396, 0.43, 0.2]; 2]),
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 4,
        request_status: true,
    }
}

/// One message of every kind.
pub fn every_message() -> Vec<Message> {
    vec![
        joint_angle(7, JointId::KneeAngleR, -0.5).into(),
        pose_frame(7, ModelId::Phak).into(),
        status().into(),
        config().into(),
        subject_leg().into(),
        subject_knee().into(),
        subject_config().into(),
        qgait_proto::SegmentOrientation {
            header: SampleHeader::new(4, qgait_proto::SegmentId::CalcnR, 7, 70_000),
            q14: [16384, 0, -8, 3],
            quality: 0,
        }
        .into(),
        qgait_proto::ImuConfig {
            mode: qgait_proto::InputMode::OrientationsClosedForm,
            segments: qgait_proto::ImuConfig::ALL_SEGMENTS,
            calibrate: true,
            sensor_to_opensim: [-1.5707964, 0.0, 0.0],
            heading: None,
            request_status: false,
        }
        .into(),
        raw_imu_sample().into(),
        raw_imu_config().into(),
        raw_imu_status().into(),
    ]
}

/// The golden raw sample of protocol.md 7.9: node 4 on the right shank, an ICM-20948's counts
/// (gyroscope at ±2000 °/s, accelerometer at ±16 g, AK09916 magnetometer).
pub fn raw_imu_sample() -> qgait_proto::RawImuSample {
    qgait_proto::RawImuSample {
        header: SampleHeader::new(4, qgait_proto::SegmentId::TibiaR, 300, 1_234_567),
        gyro: [-188, 47, 3289],
        accel: [251, 2005, -84],
        mag: Some([133, -233, 80]),
    }
}

/// The golden raw configuration of protocol.md 7.9: every segment, 9D, 100 Hz, an
/// orientation per sample, the ICM-20948's sensitivities, status requested.
pub fn raw_imu_config() -> qgait_proto::RawImuConfig {
    qgait_proto::RawImuConfig {
        segments: 0xff,
        fusion: qgait_proto::FusionMode::NineD,
        rate_hz: 100,
        output_every: 1,
        gyro_per_count: qgait_proto::RawImuConfig::gyro_per_count_of(16.4),
        accel_per_count: qgait_proto::RawImuConfig::accel_per_count_of(2048.0),
        mag_per_count: 0.15,
        request_status: true,
    }
}

/// The golden raw status of protocol.md 7.9.
pub fn raw_imu_status() -> qgait_proto::RawImuStatus {
    qgait_proto::RawImuStatus {
        samples_accepted: 48_000,
        saturated: 3,
        rate_gaps: 2,
        samples_lost: 5,
        timing_errors: 1,
        stale_samples: 1,
        resyncs: 0,
        missing_magnetometer: 0,
        not_configured: 4,
    }
}

/// The generic gait2392 right leg as a subject-model part.
pub fn subject_leg() -> SubjectLeg {
    SubjectLeg {
        upload: 7,
        leg: Leg::Right,
        hip_in_pelvis: [-0.0707, -0.0661, 0.0835],
        hip_axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        ankle_in_tibia: [0.0, -0.43, 0.0],
        ankle_axis: [-0.105_013_55, -0.174_022_45, 0.979_126_33],
        subtalar_in_talus: [-0.04877, -0.04195, 0.00792],
        subtalar_axis: [0.787_179_6, 0.604_747_5, -0.120_949_49],
        mtp_in_calcn: [0.1788, -0.002, 0.00108],
        mtp_axis: [-0.580_954_4, 0.0, 0.813_936_1],
        toetip_in_toes: [0.0812, 0.007, -0.00108],
    }
}

/// The generic gait2392 left knee_ty spline as a subject-model part (knots as the model file
/// writes them: rounded degrees in radians, data rather than approximations of pi).
#[allow(clippy::approx_constant)]
pub fn subject_knee() -> SubjectKnee {
    let knots = [
        [-2.0944, -0.4226],
        [-1.22173, -0.4082],
        [-0.523599, -0.399],
        [-0.349066, -0.3976],
        [-0.174533, -0.3966],
        [0.159149, -0.395264],
        [2.0944, -0.396],
    ];
    SubjectKnee {
        upload: 7,
        leg: Leg::Left,
        direction: KneeDirection::Ty,
        knots: heapless::Vec::from_slice(&knots).expect("7 knots fit"),
    }
}

/// Bytes 1,200 to 1,207 of the table image of upload 3: two numbers of its pool, 1 and -0.5
/// (`f32` little-endian).
pub fn chain_table() -> qgait_proto::ChainTable {
    qgait_proto::ChainTable {
        upload: 3,
        at: 1200,
        bytes: heapless::Vec::from_slice(&[0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xbf])
            .expect("8 fit"),
    }
}

/// Switch to the table of upload 3, whose image's first 1,532 bytes have the CRC-32C
/// 0x1234_5678, hold last, window 4, status requested.
pub fn chain_table_config() -> qgait_proto::ChainTableConfig {
    qgait_proto::ChainTableConfig {
        upload: 3,
        len: 1532,
        crc: 0x1234_5678,
        knee_flexes_positive: true,
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 4,
        request_status: true,
    }
}

/// Switch to upload 7, hold last, window 4, status requested.
pub fn subject_config() -> SubjectConfig {
    SubjectConfig {
        upload: 7,
        missing_policy: MissingPolicy::HoldLast,
        reorder_window: 4,
        request_status: true,
    }
}

/// The frame of `msg`, as a Vec.
pub fn frame(msg: &Message) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    encode_frame(msg, &mut buf).expect("encodes").to_vec()
}

/// Pushes `bytes` one at a time and collects every result.
pub fn decode_all(decoder: &mut FrameDecoder, bytes: &[u8]) -> Vec<Result<Message, DecodeError>> {
    bytes.iter().filter_map(|&b| decoder.push(b)).collect()
}

/// Bitwise equality (NaN-safe) of two messages: equal encodings.
pub fn same(a: &Message, b: &Message) -> bool {
    frame(a) == frame(b)
}

pub mod random;
pub mod strategies;

/// Small deterministic PRNG (xorshift64*), so every stream test is reproducible from its seed.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }
    pub fn byte(&mut self) -> u8 {
        (self.next_u64() >> 56) as u8
    }
    /// Uniform in `0..n` (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() >> 32) as usize) % n
    }
    pub fn chance(&mut self, percent: u32) -> bool {
        self.next_u32() % 100 < percent
    }
    pub fn f32_bits(&mut self) -> f32 {
        f32::from_bits(self.next_u32())
    }
}

/// The COBS code-byte positions of a frame body (delimiter excluded), walking the codes.
pub fn code_positions(body: &[u8]) -> Vec<usize> {
    let mut positions = Vec::new();
    let mut i = 0;
    while i < body.len() {
        positions.push(i);
        i += body[i] as usize;
    }
    positions
}

/// The chain table of protocol.md 9.5, byte by byte as section 9.4 lays it out: one coupled
/// coordinate (a linear function of `knee_angle_r`) sliding body 1 along an axis, body 1
/// turning about z by a linear function of `hip_flexion_r`, three points. The first
/// `192 + 4 × used` bytes of its image (what a host sends).
pub fn chain_coupled_image() -> Vec<u8> {
    const DRIVES: usize = 66;
    const POINTS: usize = 114;
    const COUNTS: usize = 186;
    const NUMBERS: usize = 192;
    let numbers: [f32; 16] = [
        // linear drives' slopes and values at 0, in drive order: drive 0, then drive 2
        0.5, 0.1, -1.0, 0.25, //
        // body 1 (from index 4): t_F, the translation's axis, e (ENDS_AWAY)
        0.0, -0.1, 0.08, 0.6, 0.8, 0.0, 0.0, -0.4, 0.0, //
        // points_at 13: point 2's offset in body 1
        0.05, -0.2, 0.0,
    ];
    let mut image = vec![0u8; NUMBERS + 4 * numbers.len()];
    // Joint 1: parent 0, one rotation and one translation, START | ENDS_AWAY, rotation 0
    // about z, its numbers from index 4.
    image[6..12].copy_from_slice(&[0, 0x05, 0x09, 0x03, 4, 0]);
    // Drive 0 (the coupled coordinate): linear of angle 6 (knee_angle_r). Drive 1 (body 1's
    // translation): the argument itself, coupled coordinate 0. Drive 2 (body 1's rotation):
    // linear of angle 3 (hip_flexion_r).
    image[DRIVES..DRIVES + 6].copy_from_slice(&[0x00, 0x46, 0xc0, 0x80, 0x00, 0x43]);
    // Points: 0 at body 0's origin, 1 at body 1's origin, 2 at an offset in body 1, the others
    // at body 0's origin.
    for k in 0..12 {
        image[POINTS + 2 * k..POINTS + 2 * k + 2].copy_from_slice(&[0, 1]);
    }
    image[POINTS + 2..POINTS + 6].copy_from_slice(&[1, 1, 1, 0]);
    // 3 drives, 1 coupled coordinate, points_at 13, 16 numbers in use.
    image[COUNTS..COUNTS + 6].copy_from_slice(&[3, 1, 13, 0, 16, 0]);
    for (k, n) in numbers.iter().enumerate() {
        image[NUMBERS + 4 * k..NUMBERS + 4 * k + 4].copy_from_slice(&n.to_le_bytes());
    }
    image
}
