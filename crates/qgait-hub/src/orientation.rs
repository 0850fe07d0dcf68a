//! The IMU orientation input (cargo feature `imu`): segment orientations in, calibrated joint
//! angles and their pose out, by the kernel's `imu` path in `f32`.
//!
//! In the orientation modes of [`ImuConfig`] the hub's reorder window
//! assembles [`SegmentOrientation`](qgait_proto::SegmentOrientation) packets instead of joint
//! angles ([`SegmentAssembler`](crate::assembly::SegmentAssembler), the same window, late,
//! duplicate and missing policies, in the same memory: the input is one or the other). A sample
//! that leaves the window complete (or held) is, in this order:
//!
//! 1. **the calibration pose**, if one was asked for ([`ImuConfig::calibrate`](qgait_proto::ImuConfig::calibrate))
//!    and the sample is complete: the kernel's `Calibration::new` with the settings in force
//!    (sensor-to-OpenSim rotation, heading from a base IMU), counted in `calibrations` (or,
//!    refused, in `calibration_rejected`, and the next complete sample is tried); no pose
//!    frame;
//! 2. **dropped before the first calibration**, counted in `uncalibrated_samples` (a pose from
//!    uncalibrated sensors would be a pose of nothing);
//! 3. otherwise each reading becomes its segment's orientation (the calibration), the kernel's
//!    solver gives gait2392's 17 coordinates (closed form, or the per-leg least squares warm
//!    started from the previous sample) and the model in force its pose: a `PoseFrame` with the
//!    17 angles, which the host recomputes as it does any frame.
//!
//! The calibration depends on the model only through its bodies' orientations in the default
//! pose, the same for gait2392 and every subject of it, so it is kept when the model changes
//! between them, and when the input goes back to joint angles and returns: only a new
//! calibration pose replaces it (a restart forgets it). Settings sent later take effect at the
//! next calibration pose.

use qgait_proto::{ImuConfig, InputMode};
#[cfg(feature = "imu")]
use {
    crate::assembly::{JointSet, SampleEvent, SegmentSample},
    crate::counters::bump,
    crate::hub::Output,
    qgait_kernel::imu::{Calibration, Orientations, Solver, SENSORS},
    qgait_proto::device_model::{kernel_mode, kernel_settings, q14_quat},
    qgait_proto::{FrameFlags, SegmentId, WireByte},
};

#[cfg(feature = "imu")]
/// The IMU settings and state of a hub: its [`ImuConfig`], the calibration and the solver.
#[derive(Debug, Clone)]
pub struct ImuInput {
    /// In force (`calibrate` and `request_status` are always `false` here).
    config: ImuConfig,
    /// Whether the next complete orientation sample is the calibration pose.
    calibrate: bool,
    calibration: Option<Calibration<f32>>,
    solver: Solver<f32>,
}

/// The IMU configuration a hub starts with: joint-angle input, all eight segments, no
/// calibration asked for, OpenSense's default sensor-to-OpenSim rotation (-pi/2, 0, 0), no
/// heading correction.
pub const DEFAULT_IMU_CONFIG: ImuConfig = ImuConfig {
    heading: None,
    ..ImuConfig::opensense_tutorial(InputMode::JointAngles, false)
};

#[cfg(feature = "imu")]
impl ImuInput {
    /// [`DEFAULT_IMU_CONFIG`], uncalibrated.
    pub fn new() -> Self {
        Self {
            config: DEFAULT_IMU_CONFIG,
            calibrate: false,
            calibration: None,
            solver: Solver::new(),
        }
    }

    /// The configuration in force.
    pub fn config(&self) -> ImuConfig {
        self.config
    }

    /// Whether a calibration pose is awaited.
    pub fn calibration_pending(&self) -> bool {
        self.calibrate
    }

    /// The calibration in force, if any.
    pub fn calibration(&self) -> Option<&Calibration<f32>> {
        self.calibration.as_ref()
    }

    /// The segments a sample needs, as the assembler's keys.
    pub fn required(&self) -> JointSet {
        JointSet::from_bits(u32::from(self.config.segments))
    }

    /// Makes `config` the one in force (its `calibrate` asks for a calibration pose; a change
    /// of solver mode restarts the solver's warm start).
    pub fn set(&mut self, config: &ImuConfig) {
        if config.mode != self.config.mode {
            self.solver.reset();
        }
        self.config = ImuConfig {
            calibrate: false,
            request_status: false,
            ..*config
        };
        self.calibrate |= config.calibrate;
    }
}

#[cfg(feature = "imu")]
impl Default for ImuInput {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(feature = "imu")]
impl<S: embedded_io::Write> Output<'_, S> {
    /// One orientation sample leaving the window (see the [module](self) docs).
    // Never inlined: the solver's frame (its chain frames and normal equations) exists only
    // while a sample is solved.
    #[inline(never)]
    pub(crate) fn on_segment_sample(&mut self, event: SampleEvent<'_, [i16; 4], { SENSORS }>) {
        let (sample, flags) = match event {
            SampleEvent::Complete(sample) => (sample, 0),
            SampleEvent::Held { sample, .. } => (sample, FrameFlags::MISSING | FrameFlags::HELD),
            SampleEvent::Dropped { .. } => {
                bump(&mut self.status.samples_incomplete);
                return;
            }
        };
        // The orientation input is only ever in force with gait2392 (the hub refuses the
        // configurations that would make it otherwise); without it, nothing can be computed.
        let (Some(model), Some(mode)) = (
            self.kinematics.gait2392_model(),
            kernel_mode(self.imu.config.mode),
        ) else {
            bump(&mut self.status.uncalibrated_samples);
            return;
        };
        let readings = readings(sample, self.imu.required());
        if self.imu.calibrate && flags == 0 {
            let settings = kernel_settings(&self.imu.config);
            match Calibration::new(model, &readings, &settings) {
                Ok(calibration) => {
                    self.imu.calibration = Some(calibration);
                    self.imu.calibrate = false;
                    self.imu.solver.reset();
                    bump(&mut self.status.calibrations);
                }
                Err(_) => bump(&mut self.status.calibration_rejected),
            }
            return;
        }
        let Some(calibration) = &self.imu.calibration else {
            bump(&mut self.status.uncalibrated_samples);
            return;
        };
        // Every reading passed the unit-length check when its packet arrived.
        let Ok(segments) = calibration.segments(&readings) else {
            bump(&mut self.status.orientation_not_unit);
            return;
        };
        let angles = self.imu.solver.solve(model, &segments, mode);
        bump(&mut self.status.samples_completed);
        if let Ok(frame) = self.kinematics.encode_pose_frame(
            sample.seq,
            sample.timestamp_us,
            &angles.coordinates,
            flags,
            self.tx,
        ) {
            crate::line::write_frame(self.serial, self.status, frame);
        }
    }
}

#[cfg(feature = "imu")]
/// The kernel's readings of a sample: the quaternion of each required segment.
fn readings(sample: &SegmentSample, required: JointSet) -> Orientations<f32> {
    let mut out = Orientations::EMPTY;
    for segment in SegmentId::ALL {
        let byte = segment.wire_byte();
        if required.contains_index(byte) {
            let q14 = sample.angles[usize::from(byte)];
            out.set(segment, Some(q14_quat(q14)));
        }
    }
    out
}
