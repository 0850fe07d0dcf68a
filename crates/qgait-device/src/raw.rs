//! Raw IMU streams (protocol.md 4.10): what raw nodes send for recordings of raw sensor data
//! (`qgait packets --raw`, from `qgait fuse`'s input files), and the host's `f64` fusion of
//! the same stream by the same rules (`qgait verify --raw`, `emulate --node --verify`), which a
//! device's orientations are checked against.

use std::collections::BTreeMap;

use qgait_fusion::RawRecording;
use qgait_node::{RawInput, RawOutcome};
use qgait_proto::{
    segment_bit, FrameDecoder, FusionMode, Message, RawImuConfig, RawImuSample, SampleHeader,
    SegmentId, SegmentOrientation, WireByte,
};

/// OpenSim's body name of a segment (`pelvis`, `femur_r`, ..., `torso`).
pub fn segment_name(segment: SegmentId) -> &'static str {
    segment.body()
}

/// The segment of an OpenSim body name, if it is one of the eight.
pub fn segment_of_name(name: &str) -> Option<SegmentId> {
    SegmentId::ALL
        .into_iter()
        .find(|s| segment_name(*s) == name)
}

/// The sensors' sensitivities the counts are made with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensitivities {
    /// rad/s per count.
    pub gyro: f32,
    /// m/s² per count.
    pub accel: f32,
    /// µT per count.
    pub mag: f32,
}

impl Default for Sensitivities {
    /// An ICM-20948 at ±2000 °/s (16.4 counts per °/s) and ±16 g (2048 counts per g) with its
    /// AK09916 magnetometer (0.15 µT per count): protocol.md 4.10's example.
    fn default() -> Self {
        Sensitivities {
            gyro: RawImuConfig::gyro_per_count_of(16.4),
            accel: RawImuConfig::accel_per_count_of(2048.0),
            mag: 0.15,
        }
    }
}

/// Why recordings cannot make a raw stream.
#[derive(Debug, thiserror::Error)]
pub enum RawStreamError {
    /// No recording given.
    #[error("no raw recording")]
    Empty,
    /// A segment given twice.
    #[error("segment {0} is given twice")]
    DuplicateSegment(&'static str),
    /// The recordings do not sample in step.
    #[error("{other}: {other_len} samples every {other_period} s, but {first} has {first_len} every {first_period} s: the sensors of one stream must sample in step")]
    NotInStep {
        /// The first recording.
        first: String,
        /// Its length.
        first_len: usize,
        /// Its period, s.
        first_period: f64,
        /// The one that differs.
        other: String,
        /// Its length.
        other_len: usize,
        /// Its period, s.
        other_period: f64,
    },
    /// A rate the message cannot carry.
    #[error("{path}: a sampling rate of {rate_hz:.3} Hz is not within 1 to 65535 Hz")]
    Rate {
        /// The recording.
        path: String,
        /// Its rate.
        rate_hz: f64,
    },
    /// 9D without a magnetometer.
    #[error("{0}: 9D fusion needs magnetometer columns (use 6D)")]
    NoMagnetometer(String),
}

/// A raw stream: the configuration, then every sample of every sensor in `seq` order.
#[derive(Debug, Clone)]
pub struct RawStream {
    /// What the receiver is configured with (`request_status` false).
    pub config: RawImuConfig,
    /// The samples, sensor after sensor within each `seq`.
    pub samples: Vec<RawImuSample>,
    /// The samples per sensor.
    pub rows: usize,
}

impl RawStream {
    /// The stream of `sensors` (each a segment and its recording, all sampling in step): the
    /// nominal rate rounded to whole hertz (the timestamps carry the true times, µs from the
    /// first sample), the counts rounded with `scales` (saturating at the sensor's full scale),
    /// the node id the segment's. 9D needs every recording's magnetometer.
    pub fn new(
        sensors: &[(SegmentId, &RawRecording)],
        fusion: FusionMode,
        output_every: u8,
        scales: Sensitivities,
    ) -> Result<RawStream, RawStreamError> {
        let (_, first) = sensors.first().ok_or(RawStreamError::Empty)?;
        let mut segments = 0u8;
        for &(segment, r) in sensors {
            if segments & segment_bit(segment) != 0 {
                return Err(RawStreamError::DuplicateSegment(segment_name(segment)));
            }
            segments |= segment_bit(segment);
            if r.len() != first.len() || (r.period - first.period).abs() > 1e-9 * first.period {
                return Err(RawStreamError::NotInStep {
                    first: first.source.clone(),
                    first_len: first.len(),
                    first_period: first.period,
                    other: r.source.clone(),
                    other_len: r.len(),
                    other_period: r.period,
                });
            }
            if fusion == FusionMode::NineD && r.mag.is_none() {
                return Err(RawStreamError::NoMagnetometer(r.source.clone()));
            }
        }
        let rate_hz = 1.0 / first.period;
        if !(0.5..65535.5).contains(&rate_hz) {
            return Err(RawStreamError::Rate {
                path: first.source.clone(),
                rate_hz,
            });
        }
        let config = RawImuConfig {
            segments,
            fusion,
            rate_hz: rate_hz.round() as u16,
            output_every: output_every.max(1),
            gyro_per_count: scales.gyro,
            accel_per_count: scales.accel,
            mag_per_count: scales.mag,
            request_status: false,
        };
        let counts = |v: [f64; 3], per: f32| v.map(|x| RawImuSample::count_of(x, f64::from(per)));
        let t0 = first.times.first().copied().unwrap_or(0.0);
        let mut samples = Vec::with_capacity(first.len() * sensors.len());
        for row in 0..first.len() {
            for (segment, r) in sensors {
                let micros = ((r.times[row] - t0) * 1e6).round();
                // Wraps after 2^32 µs, as a sensor's clock.
                let timestamp_us = (micros as u64) as u32;
                samples.push(RawImuSample {
                    header: SampleHeader::new(
                        segment.wire_byte(),
                        *segment,
                        row as u32,
                        timestamp_us,
                    ),
                    gyro: counts(r.gyr[row], scales.gyro),
                    accel: counts(r.acc[row], scales.accel),
                    mag: r.mag.as_ref().map(|m| counts(m[row], scales.mag)),
                });
            }
        }
        Ok(RawStream {
            config,
            samples,
            rows: first.len(),
        })
    }

    /// The bytes: the configuration frame, then one frame per sample.
    pub fn bytes(&self) -> Vec<u8> {
        let mut out = Vec::new();
        qgait_emulate::push_frame(&mut out, &Message::RawImuConfig(self.config));
        for s in &self.samples {
            qgait_emulate::push_frame(&mut out, &Message::RawImuSample(*s));
        }
        out
    }
}

/// The orientations a receiver owes for a stream, by segment and `seq`: what the host's `f64`
/// fusion gives by protocol.md 4.10's rules (the same code as the device's, in `f64`).
pub type HostOrientations = BTreeMap<(SegmentId, u32), [f64; 4]>;

/// Runs `stream` (any bytes: damaged frames are skipped, as a receiver skips them) through the
/// rules in `f64`, for up to eight segments.
pub fn host_orientations(stream: &[u8]) -> HostOrientations {
    let mut input = RawInput::<f64, 8>::new();
    let mut out = BTreeMap::new();
    for message in FrameDecoder::new().feed(stream).flatten() {
        match message {
            Message::RawImuConfig(c) => {
                input.configure(&c);
            }
            Message::RawImuSample(s) => {
                if let RawOutcome::Fused(Some(q)) = input.push(&s) {
                    out.insert((s.header.segment, s.header.seq), q);
                }
            }
            _ => {}
        }
    }
    out
}

/// The angle between two rotations given as quaternions of any norm, degrees.
pub fn angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let norm = |q: &[f64; 4]| q.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot = a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() / (norm(&a) * norm(&b));
    2.0 * dot.abs().min(1.0).acos().to_degrees()
}

/// A device's orientations against the host's.
#[derive(Debug, Clone, Default)]
pub struct RawCheck {
    /// Orientations compared.
    pub compared: usize,
    /// Host orientations the device did not send.
    pub missing: usize,
    /// Device orientations the host has none for.
    pub unexpected: usize,
    /// RMS of the angle between device and host, degrees.
    pub rms_deg: f64,
    /// The largest, degrees, and where.
    pub max_deg: f64,
    /// Segment and `seq` of the largest.
    pub worst: Option<(SegmentId, u32)>,
}

impl RawCheck {
    /// Compares `device` (as sent: Q14, normalised here) with `host`.
    pub fn run(device: &[SegmentOrientation], host: &HostOrientations) -> RawCheck {
        let mut c = RawCheck::default();
        let mut sum = 0.0;
        let mut seen = std::collections::BTreeSet::new();
        for o in device {
            let key = (o.header.segment, o.header.seq);
            let Some(q) = host.get(&key) else {
                c.unexpected += 1;
                continue;
            };
            seen.insert(key);
            let d = angle_deg(o.quaternion().map(f64::from), *q);
            c.compared += 1;
            sum += d * d;
            if d > c.max_deg || c.worst.is_none() {
                c.max_deg = d;
                c.worst = Some(key);
            }
        }
        c.missing = host.keys().filter(|k| !seen.contains(k)).count();
        if c.compared > 0 {
            c.rms_deg = (sum / c.compared as f64).sqrt();
        }
        c
    }

    /// Whether every owed orientation came, none more, and the RMS is within `tol_deg`.
    pub fn passed(&self, tol_deg: f64) -> bool {
        self.compared > 0 && self.missing == 0 && self.unexpected == 0 && self.rms_deg <= tol_deg
    }

    /// One line per finding.
    pub fn report(&self, tol_deg: f64) -> String {
        let worst = self
            .worst
            .map(|(s, seq)| format!(" ({} seq {seq})", segment_name(s)))
            .unwrap_or_default();
        format!(
            "raw input: {} orientations against the host's f64 fusion of the same stream: RMS {:.5}°, largest {:.5}°{worst} (tolerance {tol_deg}° RMS); {} owed and not sent, {} not owed: {}",
            self.compared,
            self.rms_deg,
            self.max_deg,
            self.missing,
            self.unexpected,
            if self.passed(tol_deg) { "PASS" } else { "FAIL" }
        )
    }
}
