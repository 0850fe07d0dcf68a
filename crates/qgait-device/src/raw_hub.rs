//! A hub with raw input (the firmware's features `imu` and `raw`, protocol.md 4.10 and 8.9)
//! from the host's side: the stream that configures it and its raw nodes' samples
//! (`qgait packets --raw --hub`), and the host's `f64` path of the same stream that its pose
//! frames are checked against (`qgait verify --raw`, `qgait emulate --verify`).
//!
//! The stream is a `Config` selecting gait2392, an `ImuConfig` (the orientation input, the raw
//! segments, the calibration and heading settings, "the next complete sample is the
//! calibration pose"), then the [`RawStream`]: its `RawImuConfig` and every sample. The hub
//! fuses each sample into the `SegmentOrientation` a smart node would send (Q14), so its
//! first sample with every segment fused is the calibration pose and each later one a pose
//! frame. The host does the same in `f64`: the raw input's rules ([`host_orientations`]),
//! the orientations in Q14, then the kernel's calibration and solver
//! ([`solve_samples`]). The two differ by the hub's
//! `f32` fusion, so their angles are compared in degrees (the fusion's error carries into
//! every coordinate), not their points in micrometres.

use std::collections::{BTreeMap, BTreeSet};

use qgait_emulate::session::InputCounts;
use qgait_kernel::imu::{Mode, Settings};
use qgait_proto::{
    segment_bit, FrameDecoder, ImuConfig, Message, MissingPolicy, RawImuSample, SegmentId,
    SegmentOrientation,
};

use crate::orientations::{solve_samples, OrientationStream, OrientationStreamError, Q14Sample};
use crate::raw::{host_orientations, segment_name, RawStream};

/// A raw stream for a hub with raw input.
#[derive(Debug, Clone)]
pub struct RawHubStream {
    /// The raw nodes' stream.
    pub raw: RawStream,
    /// The IMU configuration: the raw stream's segments, `calibrate` set.
    pub imu: ImuConfig,
    /// The `seq` of the first sample after the IMU configuration: the calibration pose is the
    /// first sample from it on with every segment fused.
    pub calibrate_at: u32,
}

impl RawHubStream {
    /// The hub's stream of `raw`, solved with `settings` in `mode`, the IMU configuration
    /// sent before sample `calibrate_at`. Before it the hub fuses the samples and, in the
    /// joint-angle input, uses none of their orientations: the fusion settles while the
    /// subject stands still.
    ///
    /// The hub solves nothing without the pelvis's sensor (every coordinate is relative to
    /// it) and calibrates nothing without the heading's base sensor: both must be in `raw`.
    pub fn new(
        raw: RawStream,
        settings: &Settings<f64>,
        mode: Mode,
        calibrate_at: u32,
    ) -> Result<Self, RawHubError> {
        let mut imu = OrientationStream::imu_config(settings, mode);
        imu.segments = raw.config.segments;
        if imu.segments & segment_bit(SegmentId::Pelvis) == 0 {
            return Err(RawHubError::NoPelvis);
        }
        if let Some(h) = imu
            .heading
            .filter(|h| imu.segments & segment_bit(h.base) == 0)
        {
            return Err(RawHubError::NoBase(segment_name(h.base)));
        }
        Ok(RawHubStream {
            raw,
            imu,
            calibrate_at,
        })
    }

    /// The bytes (a 0x00 first): gait2392 (drop policy, reorder window `window`), the raw
    /// input's configuration, the samples before `calibrate_at`, the IMU configuration, the
    /// other samples.
    pub fn bytes(&self, window: u8) -> Vec<u8> {
        let mut out = vec![0u8];
        let [config, imu] =
            OrientationStream::config_messages_of(self.imu, MissingPolicy::Drop, window);
        qgait_emulate::push_frame(&mut out, &config);
        qgait_emulate::push_frame(&mut out, &Message::RawImuConfig(self.raw.config));
        let (before, after): (Vec<&RawImuSample>, Vec<_>) = self
            .raw
            .samples
            .iter()
            .partition(|s| s.header.seq < self.calibrate_at);
        for s in before {
            qgait_emulate::push_frame(&mut out, &Message::RawImuSample(*s));
        }
        qgait_emulate::push_frame(&mut out, &imu);
        for s in after {
            qgait_emulate::push_frame(&mut out, &Message::RawImuSample(*s));
        }
        out
    }
}

/// Why the host cannot compute a raw hub stream.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RawHubError {
    /// No recording of the pelvis's sensor.
    #[error("no recording of the pelvis's sensor: a hub solves every coordinate relative to it")]
    NoPelvis,
    /// No recording of the heading's base sensor.
    #[error(
        "no recording of {0}, the heading's base sensor (--base-imu): the hub could not calibrate"
    )]
    NoBase(&'static str),
    /// The stream configures no orientation input.
    #[error("no ImuConfig with an orientation mode: not a stream for a hub with raw input (`qgait packets --raw --hub`)")]
    NoImuConfig,
    /// No sample after the IMU configuration has every segment fused: no calibration pose.
    #[error(
        "no sample after the ImuConfig has an orientation of every segment: no calibration pose"
    )]
    NoCalibration,
    /// The kernel refused the calibration pose or a sample.
    #[error(transparent)]
    Solve(#[from] OrientationStreamError),
}

/// What the host's `f64` path makes of a raw hub stream.
#[derive(Debug, Clone)]
pub struct RawHubHost {
    /// The IMU configuration in force (the stream's last).
    pub imu: ImuConfig,
    /// The calibration pose's `seq`: the first sample with every segment fused.
    pub calibration: u32,
    /// Every sample from the calibration pose on with every segment fused, by `seq`: the
    /// orientations in Q14, as the hub's raw input passes them on.
    pub samples: BTreeMap<u32, Q14Sample>,
    /// The orientations the raw input passes on, complete samples or not.
    pub fused: usize,
}

impl RawHubHost {
    /// The host's fusion of `stream` (any bytes: damaged frames are skipped, as the hub skips
    /// them), its complete samples and calibration pose.
    pub fn of(stream: &[u8]) -> Result<RawHubHost, RawHubError> {
        // The last IMU configuration with an orientation mode, and the first raw sample after
        // it: the calibration pose is the first complete sample from there on.
        let (mut imu, mut from) = (None, None);
        for m in FrameDecoder::new().feed(stream).flatten() {
            match m {
                Message::ImuConfig(c) if c.mode.orientations() => (imu, from) = (Some(c), None),
                Message::RawImuSample(s) if from.is_none() && imu.is_some() => {
                    from = Some(s.header.seq)
                }
                _ => {}
            }
        }
        let imu = imu.ok_or(RawHubError::NoImuConfig)?;
        let mut samples: BTreeMap<u32, Q14Sample> = BTreeMap::new();
        let orientations = host_orientations(stream);
        let fused = orientations.len();
        for ((segment, seq), q) in orientations {
            samples.entry(seq).or_default()[segment as usize] = Some(SegmentOrientation::q14_of(q));
        }
        let complete =
            |s: &Q14Sample| (0..s.len()).all(|i| imu.segments & (1 << i) == 0 || s[i].is_some());
        let from = from.ok_or(RawHubError::NoCalibration)?;
        samples.retain(|seq, s| *seq >= from && complete(s));
        let calibration = *samples.keys().next().ok_or(RawHubError::NoCalibration)?;
        Ok(RawHubHost {
            imu,
            calibration,
            samples,
            fused,
        })
    }

    /// What the hub counts of `input`, all it is sent (this stream, closing frames
    /// included): [`InputCounts::of`] the input, but no raw sample as an accepted packet, each
    /// orientation its raw input passes on instead (protocol.md 4.10: the hub counts the raw
    /// samples in its `RawImuStatus`).
    pub fn input_counts(&self, input: &[u8]) -> InputCounts {
        let mut counts = InputCounts::of(input);
        let samples = FrameDecoder::new()
            .feed(input)
            .flatten()
            .filter(|m| matches!(m, Message::RawImuSample(_)))
            .count();
        counts.accepted = counts.accepted - samples as u32 + self.fused as u32;
        counts
    }

    /// The samples the hub owes a pose frame for: every complete one after the calibration
    /// pose.
    pub fn frames_due(&self) -> BTreeSet<u32> {
        self.samples
            .keys()
            .copied()
            .filter(|&seq| seq > self.calibration)
            .collect()
    }

    /// The host's angles of the samples whose `seq` `solved` holds (the ones the hub sent a
    /// frame for, so that the least squares' warm start is the same on both sides), indexed
    /// by `seq - 1` as [`OrientationCheck::run`](crate::orientations::OrientationCheck::run)
    /// takes them.
    pub fn angles_of(
        &self,
        solved: impl Fn(u32) -> bool,
    ) -> Result<Vec<Option<[f64; 17]>>, RawHubError> {
        let calibration = &self.samples[&self.calibration];
        let rows = self.samples.range(self.calibration + 1..);
        let solved = solve_samples(
            &self.imu,
            calibration,
            rows.map(|(seq, s)| (*seq, s)),
            solved,
        )?;
        let last = self.samples.keys().last().copied().unwrap_or(0) as usize;
        let mut out = vec![None; last];
        for (seq, angles) in solved {
            out[seq as usize - 1] = angles;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raw::Sensitivities;
    use qgait_fusion::RawRecording;
    use qgait_kernel::imu::{Heading, HeadingAxis, Segment};
    use qgait_proto::FusionMode;

    /// `n` samples at 100 Hz of a sensor at rest, z up.
    fn still(n: usize) -> RawRecording {
        RawRecording {
            source: "still.csv".into(),
            period: 0.01,
            times: (0..n).map(|k| k as f64 * 0.01).collect(),
            lines: (2..n + 2).collect(),
            gyr: vec![[0.0; 3]; n],
            acc: vec![[0.0, 0.0, 9.81]; n],
            mag: Some(vec![[20.0, 0.0, -40.0]; n]),
            truth: None,
            movement: None,
        }
    }

    fn raw(segments: &[SegmentId], n: usize) -> RawStream {
        let r = still(n);
        let sensors: Vec<_> = segments.iter().map(|s| (*s, &r)).collect();
        RawStream::new(&sensors, FusionMode::NineD, 1, Sensitivities::default()).unwrap()
    }

    #[test]
    fn the_calibration_pose_is_the_first_sample_after_the_imu_configuration() {
        let settings = Settings::<f64>::default();
        let stream = raw(&[SegmentId::Pelvis, SegmentId::FemurR], 50);
        let hub = RawHubStream::new(stream, &settings, Mode::LeastSquares, 20).unwrap();
        let bytes = hub.bytes(4);
        let messages: Vec<Message> = FrameDecoder::new().feed(&bytes).flatten().collect();
        // gait2392, the raw input's configuration, 20 samples of 2 sensors, the IMU
        // configuration, the other 30.
        assert!(matches!(messages[0], Message::Config(_)));
        assert!(matches!(messages[1], Message::RawImuConfig(_)));
        assert!(matches!(messages[42], Message::ImuConfig(c) if c.calibrate && c.segments == 0b11));
        assert_eq!(messages.len(), 2 + 100 + 1);
        let host = RawHubHost::of(&bytes).unwrap();
        assert_eq!(host.calibration, 20);
        assert_eq!(host.frames_due(), (21..50).collect());
        // At rest in the calibration pose: every coordinate near zero.
        let angles = host.angles_of(|_| true).unwrap();
        assert_eq!(angles.len(), 49);
        assert!(angles[..20].iter().all(Option::is_none));
        for a in angles[20..].iter().flatten() {
            assert!(a.iter().all(|x| x.abs() < 1e-3), "{a:?}");
        }
    }

    #[test]
    fn the_pelvis_and_the_base_sensor_are_needed() {
        let settings = Settings::<f64>::default();
        let femur = raw(&[SegmentId::FemurR], 5);
        assert!(matches!(
            RawHubStream::new(femur, &settings, Mode::LeastSquares, 0),
            Err(RawHubError::NoPelvis)
        ));
        let torso = Settings {
            heading: Some(Heading {
                base: Segment::Torso,
                axis: HeadingAxis::Z,
            }),
            ..settings
        };
        let pelvis = raw(&[SegmentId::Pelvis], 5);
        assert!(matches!(
            RawHubStream::new(pelvis, &torso, Mode::LeastSquares, 0),
            Err(RawHubError::NoBase("torso"))
        ));
        assert!(matches!(RawHubHost::of(&[]), Err(RawHubError::NoImuConfig)));
    }
}
