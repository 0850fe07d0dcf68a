//! The hub's IMU orientation input from the host's side: the byte stream the segment nodes of
//! a recording would send (`qgait packets --orientations`), and the host's `f64` computation
//! of the same stream that a hub's frames are checked against (`qgait verify --orientations`).
//!
//! The stream is a `Config` selecting gait2392, an `ImuConfig` (the input mode, the segments
//! sent, the calibration and heading settings, "the next complete sample is the calibration
//! pose"), the calibration pose as sample 0, then the recording's rows as samples 1, 2, ...:
//! per row one `SegmentOrientation` per segment with a reading, its quaternion in Q14 as a
//! node sends it. The host's computation ([`OrientationStream::host_angles`]) starts from the
//! same Q14 values decoded (so the two differ by the hub's `f32` only, not by the encoding),
//! through the kernel's calibration and solver in `f64` with the settings as they travel on
//! the wire, then the kernel's gait2392 forward kinematics.

use std::path::Path;

use qgait_kernel::imu::{
    Calibration, ImuError, Mode, Orientations, Segment, Settings, Solver, SENSORS,
};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat};
use qgait_proto::device_model::{
    input_mode, kernel_mode, kernel_settings, q14_quat, wire_settings,
};
use qgait_proto::{
    segment_bit, Config, FrameFlags, ImuConfig, Message, MissingPolicy, ModelId, PoseFrame,
    PoseModels, SampleHeader, SegmentId, SegmentOrientation, WireByte,
};

use qgait_opensim::diagnostics::Warning;
use qgait_opensim::imu_sto::OrientationReader;
use qgait_opensim::mot::MotError;

/// gait2392's 17 coordinates, radians.
pub type Angles = [f64; 17];

/// One sample: the Q14 quaternion of each segment with a reading (by segment index).
pub type Q14Sample = [Option<[i16; 4]>; SENSORS];

/// A recording as its segment nodes send it.
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationStream {
    /// The IMU configuration sent first (its `calibrate` set).
    pub imu: ImuConfig,
    /// The calibration pose (sample 0).
    pub calibration: Q14Sample,
    /// The recording's rows (samples 1, 2, ...): sensor time (µs, wrapping) and readings.
    pub rows: Vec<(u32, Q14Sample)>,
}

/// Why a stream could not be made or computed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum OrientationStreamError {
    /// Reading an orientation file.
    #[error(transparent)]
    Read(#[from] MotError),
    /// The calibration pose has no pelvis reading (every coordinate is relative to it).
    #[error("{path}: the calibration pose has no pelvis_imu reading")]
    NoPelvis {
        /// The calibration file.
        path: String,
    },
    /// The kernel refused the calibration pose or a reading.
    #[error("{0}")]
    Imu(#[from] ImuError),
    /// The kernel refused the generic gait2392 (its tests rule it out).
    #[error("gait2392: {0}")]
    Model(#[from] qgait_kernel::ModelError),
}

/// A reading in Q14 (the kernel's quaternion, already normalised by the reader).
fn q14(q: Quat<f64>) -> [i16; 4] {
    SegmentOrientation::q14_of([q.w, q.x, q.y, q.z])
}

fn sample_of(readings: &Orientations<f64>) -> Q14Sample {
    core::array::from_fn(|i| readings.q[i].map(q14))
}

/// Microseconds as the wire's wrapping `u32`.
fn wire_us(seconds: f64) -> u32 {
    (seconds * 1e6).round().rem_euclid(4_294_967_296.0) as u32
}

impl OrientationStream {
    /// The stream of `calibration` (readings of the static pose) and `rows` (time in seconds
    /// and readings), sending the segments the calibration pose has a reading of.
    pub fn new(
        calibration: &Orientations<f64>,
        rows: impl IntoIterator<Item = (f64, Orientations<f64>)>,
        settings: &Settings<f64>,
        mode: Mode,
    ) -> OrientationStream {
        let segments = Segment::ALL
            .into_iter()
            .filter(|&s| calibration.get(s).is_some())
            .fold(0u8, |bits, s| bits | segment_bit(s));
        let mut t0 = None;
        let rows = rows
            .into_iter()
            .map(|(t, r)| (wire_us(t - *t0.get_or_insert(t)), sample_of(&r)))
            .collect();
        OrientationStream {
            imu: ImuConfig {
                segments,
                ..Self::imu_config(settings, mode)
            },
            calibration: sample_of(calibration),
            rows,
        }
    }

    /// The IMU configuration of `settings` and `mode`, asking for a calibration pose, with no
    /// segment.
    pub fn imu_config(settings: &Settings<f64>, mode: Mode) -> ImuConfig {
        let (sensor_to_opensim, heading) = wire_settings(settings);
        ImuConfig {
            mode: input_mode(mode),
            segments: 0,
            calibrate: true,
            sensor_to_opensim,
            heading,
            request_status: false,
        }
    }

    /// Reads the recording `orientations` (at most `max_rows` rows) and the static pose
    /// `calibration` (its first row), OpenSim orientation `.sto` files.
    pub fn read(
        orientations: &Path,
        calibration: &Path,
        settings: &Settings<f64>,
        mode: Mode,
        max_rows: Option<usize>,
    ) -> Result<(OrientationStream, Vec<Warning>), OrientationStreamError> {
        let mut warnings = Vec::new();
        let mut cal = OrientationReader::open(calibration)?;
        let pose = cal.next_row()?.map(|r| r.readings).unwrap_or_default();
        warnings.extend(cal.take_warnings());
        if pose.get(Segment::Pelvis).is_none() {
            return Err(OrientationStreamError::NoPelvis {
                path: cal.source().to_string(),
            });
        }
        let mut rec = OrientationReader::open(orientations)?;
        let mut rows = Vec::new();
        while max_rows.is_none_or(|n| rows.len() < n) {
            let Some(row) = rec.next_row()? else { break };
            rows.push((row.time, row.readings));
        }
        warnings.extend(rec.take_warnings());
        Ok((
            OrientationStream::new(&pose, rows, settings, mode),
            warnings,
        ))
    }

    /// The configuration messages: gait2392 (with `policy` and `window`), then the IMU one.
    pub fn config_messages(&self, policy: MissingPolicy, window: u8) -> [Message; 2] {
        Self::config_messages_of(self.imu, policy, window)
    }

    /// gait2392 (with `policy` and `window`), then `imu`.
    pub fn config_messages_of(imu: ImuConfig, policy: MissingPolicy, window: u8) -> [Message; 2] {
        [
            Message::Config(Config {
                model: ModelId::Gait2392,
                anthropometry: None,
                missing_policy: policy,
                reorder_window: window,
                request_status: false,
            }),
            Message::ImuConfig(imu),
        ]
    }

    /// The packets of sample `seq` (0: the calibration pose; `k`: row `k - 1`), in segment
    /// order.
    pub fn packets(&self, seq: u32) -> Vec<SegmentOrientation> {
        let (timestamp_us, sample) = match seq {
            0 => (0, &self.calibration),
            k => match self.rows.get(k as usize - 1) {
                Some((t, s)) => (*t, s),
                None => return Vec::new(),
            },
        };
        SegmentId::ALL
            .into_iter()
            .filter(|&s| self.imu.segments & segment_bit(s) != 0)
            .filter_map(|s| {
                sample[s as usize].map(|q14| SegmentOrientation {
                    header: SampleHeader::new(s.wire_byte(), s, seq, timestamp_us),
                    q14,
                    quality: 0,
                })
            })
            .collect()
    }

    /// Every sample's packets, the calibration pose first.
    pub fn samples(&self) -> Vec<Vec<SegmentOrientation>> {
        (0..=self.rows.len() as u32)
            .map(|k| self.packets(k))
            .collect()
    }

    /// The bytes the nodes send (a 0x00 first): the configuration messages (drop policy,
    /// window `window`), then every sample.
    pub fn bytes(&self, window: u8) -> Vec<u8> {
        let mut out = vec![0u8];
        for m in self.config_messages(MissingPolicy::Drop, window) {
            qgait_emulate::push_frame(&mut out, &m);
        }
        for sample in self.samples() {
            for p in sample {
                qgait_emulate::push_frame(&mut out, &Message::SegmentOrientation(p));
            }
        }
        out
    }

    /// The host's `f64` computation of every row (index `k` is sample `k + 1`): the Q14
    /// readings decoded, the kernel's calibration on the calibration pose with the settings as
    /// sent, its solver on each row in order.
    pub fn host_angles(&self) -> Result<Vec<Option<[f64; 17]>>, OrientationStreamError> {
        self.host_angles_of(|_| true)
    }

    /// [`host_angles`](Self::host_angles) of the rows whose sequence number `solved` holds,
    /// the others skipped (`None`): the rows a hub solved (the ones it sent a frame for), so
    /// that the least squares' warm start, the previous solved row, is the same on both sides
    /// when the link lost samples (the hub drops an incomplete sample without solving it).
    pub fn host_angles_of(
        &self,
        solved: impl Fn(u32) -> bool,
    ) -> Result<Vec<Option<[f64; 17]>>, OrientationStreamError> {
        let rows = (1u32..).zip(self.rows.iter().map(|(_, s)| s));
        Ok(solve_samples(&self.imu, &self.calibration, rows, solved)?
            .into_iter()
            .map(|(_, angles)| angles)
            .collect())
    }
}

/// The host's `f64` IMU path of samples as a hub gets them: the Q14 readings of the segments
/// `imu` selects decoded, the kernel's calibration on `calibration` with `imu`'s settings as
/// sent, then its solver (in `imu`'s mode) on each of `rows` (`seq` and readings) in order whose
/// `seq` `solved` holds, the others skipped (`None`).
pub fn solve_samples<'a>(
    imu: &ImuConfig,
    calibration: &Q14Sample,
    rows: impl IntoIterator<Item = (u32, &'a Q14Sample)>,
    solved: impl Fn(u32) -> bool,
) -> Result<Vec<(u32, Option<Angles>)>, OrientationStreamError> {
    let model = Gait2392::<f64>::new(&Gait2392Geometry::generic())?;
    let decode = |s: &Q14Sample| Orientations {
        q: core::array::from_fn(|i| {
            s[i].filter(|_| imu.segments & (1 << i) != 0)
                .map(q14_quat::<f64>)
        }),
    };
    let calibration = Calibration::new(&model, &decode(calibration), &kernel_settings::<f64>(imu))?;
    let mode = kernel_mode(imu.mode).unwrap_or(Mode::LeastSquares);
    let mut solver = Solver::<f64>::new();
    rows.into_iter()
        .map(|(seq, s)| {
            if !solved(seq) {
                return Ok((seq, None));
            }
            let segments = calibration.segments(&decode(s))?;
            Ok((seq, Some(solver.solve(&model, &segments, mode).coordinates)))
        })
        .collect()
}

/// A hub's frames of an orientation stream against the host's `f64` computation of it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct OrientationCheck {
    /// Frames compared.
    pub frames: u64,
    /// Frames whose sequence number is no row of the stream (or a row the host did not solve).
    pub unknown: u64,
    /// Frames the hub computed from a held sample ([`FrameFlags::HELD`](qgait_proto::FrameFlags::HELD):
    /// some sensors missing, their coordinates kept): not compared, the host solves every row
    /// from all its readings.
    pub held: u64,
    /// Largest distance of a hub point from the host's (metres).
    pub max_point_m: f64,
    /// Largest difference of a hub angle from the host's (radians; MTP joints included).
    pub max_angle_rad: f64,
    /// Root mean square of the differences of the hub's angles from the host's over every
    /// frame compared and its 14 coordinates that sensors determine (not the MTP joints,
    /// which are 0 on both sides), radians.
    pub rms_angle_rad: f64,
    /// The frame with the largest point error: (seq, metres).
    pub worst: Option<(u32, f64)>,
}

impl OrientationCheck {
    /// Compares `frames` with `host` ([`OrientationStream::host_angles`]): each frame's angles
    /// and points with the host's angles and their `f64` gait2392 pose.
    pub fn run(frames: &[PoseFrame], host: &[Option<[f64; 17]>]) -> OrientationCheck {
        let models = PoseModels::<f64>::defaults();
        let mut c = OrientationCheck::default();
        let (mut squares, mut count) = (0.0, 0usize);
        for f in frames {
            if f.flags & FrameFlags::HELD != 0 {
                c.held += 1;
                continue;
            }
            let want = (f.seq as usize).checked_sub(1).and_then(|k| host.get(k));
            let Some(Some(want)) = want else {
                c.unknown += 1;
                continue;
            };
            c.frames += 1;
            for (i, (got, want)) in f.angles.iter().zip(want).enumerate() {
                let e = (f64::from(*got) - want).abs();
                let e = if e.is_finite() { e } else { f64::INFINITY };
                c.max_angle_rad = c.max_angle_rad.max(e);
                // The MTP joints: no sensor determines them.
                if !COORDINATES[i].starts_with("mtp") {
                    squares += e * e;
                    count += 1;
                }
            }
            // gait2392 is always one of the models (only a chain can be missing).
            let Some(pose) = models.pose(ModelId::Gait2392, want) else {
                c.unknown += 1;
                continue;
            };
            for (got, want) in f.points.iter().zip(pose.points()) {
                let d = ((f64::from(got[0]) - want.x).powi(2)
                    + (f64::from(got[1]) - want.y).powi(2)
                    + (f64::from(got[2]) - want.z).powi(2))
                .sqrt();
                let d = if d.is_finite() { d } else { f64::INFINITY };
                if c.worst.is_none_or(|(_, w)| d > w) {
                    c.worst = Some((f.seq, d));
                }
                c.max_point_m = c.max_point_m.max(d);
            }
        }
        if count > 0 {
            c.rms_angle_rad = (squares / count as f64).sqrt();
        }
        c
    }

    /// Whether every frame is a row's and the angles' RMS difference is within `tol_deg`
    /// degrees (a hub fusing raw samples: its `f32` fusion's error is in every coordinate).
    pub fn angles_passed(&self, tol_deg: f64) -> bool {
        self.frames > 0 && self.unknown == 0 && self.rms_angle_rad.to_degrees() <= tol_deg
    }

    /// A short report of [`angles_passed`](Self::angles_passed).
    pub fn angles_report(&self, tol_deg: f64) -> String {
        format!(
            "raw input: {} frames against the host's f64 fusion and IMU path of the same stream: angles RMS {:.4}°, largest {:.4}° (tolerance {tol_deg}° RMS){}{}: {}",
            self.frames,
            self.rms_angle_rad.to_degrees(),
            self.max_angle_rad.to_degrees(),
            if self.unknown > 0 {
                format!(", {} frames of no sample", self.unknown)
            } else {
                String::new()
            },
            if self.held > 0 {
                format!(", {} held frames not compared", self.held)
            } else {
                String::new()
            },
            if self.angles_passed(tol_deg) { "PASS" } else { "FAIL" }
        )
    }

    /// Whether every frame is a row's and within `tol` metres of the host.
    pub fn passed(&self, tol: f64) -> bool {
        self.frames > 0 && self.unknown == 0 && self.max_point_m <= tol
    }

    /// A short report.
    pub fn report(&self, tol: f64) -> String {
        format!(
            "orientations: {} frames against the host's f64 IMU path: largest point error {:.3} µm{} (tolerance {:.1} µm), largest angle difference {:.5} deg{}",
            self.frames,
            self.max_point_m * 1e6,
            self.worst
                .map(|(s, _)| format!(" at seq {s}"))
                .unwrap_or_default(),
            tol * 1e6,
            self.max_angle_rad.to_degrees(),
            if self.unknown > 0 {
                format!(", {} frames of no row", self.unknown)
            } else {
                String::new()
            }
        ) + &if self.held > 0 {
            format!(", {} held frames not compared", self.held)
        } else {
            String::new()
        }
    }
}
