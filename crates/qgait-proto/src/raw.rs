//! Raw IMU input: [`RawImuSample`] (a node's raw gyroscope, accelerometer and magnetometer
//! sample, node to the receiver that fuses it), [`RawImuConfig`] (the fusion's settings and the
//! sensors' scales, host to that receiver) and [`RawImuStatus`] (its counters, receiver to
//! host).
//!
//! A raw node forwards its IMU's FIFO as it reads it: signed 16-bit counts per axis, the
//! sensor's own integers, so the wire adds no rounding of its own. Their physical values are
//! the counts times the sensitivities of the [`RawImuConfig`] (rad/s, m/s², µT per count).
//! The counts travel as postcard's zigzag varints (1 to 3 bytes each, see `docs/protocol.md`
//! section 4.10, which also gives what the sensor's quantisation costs).

use serde::{Deserialize, Serialize};
use strum::FromRepr;

use crate::SampleHeader;

/// Wire tag of [`RawImuSample`].
pub const RAW_IMU_SAMPLE_TAG: u32 = 11;
/// Wire tag of [`RawImuConfig`].
pub const RAW_IMU_CONFIG_TAG: u32 = 12;
/// Wire tag of [`RawImuStatus`].
pub const RAW_IMU_STATUS_TAG: u32 = 13;

/// One raw sample of one node's IMU: the sensor's counts, axes of the sensor's own frame
/// (right-handed, as its datasheet draws them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawImuSample {
    /// Sender, segment, sample number and time.
    pub header: SampleHeader,
    /// Angular rate, x, y, z, counts ([`RawImuConfig::gyro_per_count`] rad/s each).
    pub gyro: [i16; 3],
    /// Specific force (reads +g along the axis pointing up at rest), x, y, z, counts
    /// ([`RawImuConfig::accel_per_count`] m/s² each).
    pub accel: [i16; 3],
    /// Magnetic field, x, y, z, counts ([`RawImuConfig::mag_per_count`] µT each), if the node
    /// has a magnetometer sample for this one.
    pub mag: Option<[i16; 3]>,
}

impl RawImuSample {
    /// The count of the physical value `value` for a sensitivity of `per_count` (units per
    /// count), rounded to the nearest integer, ties away from zero; saturating at the `i16`
    /// range (the sensor's full scale) and 0 for NaN, as a sensor's ADC (the encoding a
    /// simulated node uses).
    pub fn count_of(value: f64, per_count: f64) -> i16 {
        let v = value / per_count;
        // `as` saturates and maps NaN to 0; the rounding is half away from zero.
        (if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i16
    }

    /// Whether any count of the sample is at an end of the `i16` range (-32768 or 32767): the
    /// sensor's full scale reached, the true value may be beyond.
    pub fn saturated(&self) -> bool {
        let at_end = |c: &i16| *c == i16::MIN || *c == i16::MAX;
        self.gyro.iter().any(at_end)
            || self.accel.iter().any(at_end)
            || self.mag.is_some_and(|m| m.iter().any(at_end))
    }
}

/// Which sensors the fusion uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, FromRepr)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum FusionMode {
    /// Gyroscope and accelerometer: inclination from gravity, heading by integration only
    /// (it drifts; the calibration's heading correction takes it out at calibration).
    SixD = 0,
    /// Gyroscope, accelerometer and magnetometer: heading from the magnetic field too.
    NineD = 1,
}

/// The raw input's settings, sent by the host to whoever fuses raw samples (a hub with raw
/// input, or a node fusing its own sensor): which segments, the fusion, the rate and each
/// sensor's sensitivity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawImuConfig {
    /// The segments these settings are for, one bit per [`SegmentId`](crate::SegmentId) ([`segment_bit`](crate::segment_bit)):
    /// a hub fuses their orientations from [`RawImuSample`]s (the others still come as
    /// [`SegmentOrientation`](crate::SegmentOrientation)s); 0: no raw input (the default).
    pub segments: u8,
    /// 6D or 9D.
    pub fusion: FusionMode,
    /// The nominal sample rate, Hz (at least 1).
    pub rate_hz: u16,
    /// One orientation per this many samples (at least 1): those whose `seq` is a multiple of
    /// it.
    pub output_every: u8,
    /// Gyroscope sensitivity, rad/s per count (finite, positive).
    pub gyro_per_count: f32,
    /// Accelerometer sensitivity, m/s² per count (finite, positive).
    pub accel_per_count: f32,
    /// Magnetometer sensitivity, µT per count (finite, positive; not read in 6D).
    pub mag_per_count: f32,
    /// `true` asks for a [`Status`](crate::Status) and a [`RawImuStatus`] in answer.
    pub request_status: bool,
}

impl RawImuConfig {
    /// Standard gravity, m/s² per g (what accelerometer datasheets' g is).
    pub const G: f32 = 9.806_65;

    /// A gyroscope's sensitivity in rad/s per count from its datasheet's, counts per °/s
    /// (e.g. 16.4 at ±2000 °/s).
    pub fn gyro_per_count_of(counts_per_dps: f32) -> f32 {
        (core::f64::consts::PI / 180.0 / f64::from(counts_per_dps)) as f32
    }

    /// An accelerometer's sensitivity in m/s² per count from its datasheet's, counts per g
    /// (e.g. 2048 at ±16 g).
    pub fn accel_per_count_of(counts_per_g: f32) -> f32 {
        (f64::from(Self::G) / f64::from(counts_per_g)) as f32
    }

    /// Whether a receiver can use these settings: a rate and an output divider of at least 1,
    /// the gyroscope's and accelerometer's sensitivities (and in 9D the magnetometer's) finite
    /// and positive.
    pub fn usable(&self) -> bool {
        let scale = |s: f32| s.is_finite() && s > 0.0;
        self.rate_hz > 0
            && self.output_every > 0
            && scale(self.gyro_per_count)
            && scale(self.accel_per_count)
            && (self.fusion == FusionMode::SixD || scale(self.mag_per_count))
    }

    /// The angular rate of `counts`, rad/s.
    pub fn gyro(&self, counts: [i16; 3]) -> [f32; 3] {
        counts.map(|c| f32::from(c) * self.gyro_per_count)
    }

    /// The specific force of `counts`, m/s².
    pub fn accel(&self, counts: [i16; 3]) -> [f32; 3] {
        counts.map(|c| f32::from(c) * self.accel_per_count)
    }

    /// The magnetic field of `counts`, µT.
    pub fn mag(&self, counts: [i16; 3]) -> [f32; 3] {
        counts.map(|c| f32::from(c) * self.mag_per_count)
    }
}

/// The counters of a raw input (a hub with raw input, or a node fusing its own sensor), sent
/// right after each [`Status`](crate::Status) while raw input is configured. Every counter
/// wraps at `u32::MAX`; all are zero at start.
///
/// A message of its own, not more counters in [`Status`](crate::Status): a decoder of this version
/// reads exactly 20 counters and rejects a longer `Status` (protocol.md section 6).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RawImuStatus {
    /// Raw samples of a configured segment, used by the fusion.
    pub samples_accepted: u32,
    /// Samples with a count at an end of the `i16` range ([`RawImuSample::saturated`]): used
    /// as they are.
    pub saturated: u32,
    /// Gaps in a segment's stream: a sample 2 to 1024 ahead of the previous one of its
    /// segment.
    pub rate_gaps: u32,
    /// Samples missing in those gaps (`seq` difference − 1, summed).
    pub samples_lost: u32,
    /// Samples whose timestamp disagrees with their `seq` (the time since the previous sample
    /// of the segment not within half a period of `seq` difference × period): integrated over
    /// the nominal period instead.
    pub timing_errors: u32,
    /// Samples not ahead of the previous one of their segment (repeated or out of order, at
    /// most 1024 behind): dropped.
    pub stale_samples: u32,
    /// Jumps of more than 1024 samples either way: the segment's fusion starts again.
    pub resyncs: u32,
    /// 9D samples without a magnetometer reading: fused as 6D.
    pub missing_magnetometer: u32,
    /// Samples of a segment the raw input is not configured for: dropped.
    pub not_configured: u32,
}

/// Number of `u32` counters in a [`RawImuStatus`].
pub const RAW_IMU_STATUS_COUNTERS: usize = 9;

impl RawImuStatus {
    /// Every counter with its field name, in wire order.
    pub fn named_counters(&self) -> [(&'static str, u32); RAW_IMU_STATUS_COUNTERS] {
        [
            ("samples_accepted", self.samples_accepted),
            ("saturated", self.saturated),
            ("rate_gaps", self.rate_gaps),
            ("samples_lost", self.samples_lost),
            ("timing_errors", self.timing_errors),
            ("stale_samples", self.stale_samples),
            ("resyncs", self.resyncs),
            ("missing_magnetometer", self.missing_magnetometer),
            ("not_configured", self.not_configured),
        ]
    }
}
