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
    crate::assembly::JointSet,
    qgait_kernel::imu::{Calibration, Solver},
};

#[cfg(feature = "imu")]
/// The IMU settings and state of a hub: its [`ImuConfig`], the calibration and the solver.
#[derive(Debug, Clone)]
pub struct ImuInput {
    /// In force (`calibrate` and `request_status` are always `false` here).
    pub(crate) config: ImuConfig,
    /// Whether the next complete orientation sample is the calibration pose.
    pub(crate) calibrate: bool,
    pub(crate) calibration: Option<Calibration<f32>>,
    pub(crate) solver: Solver<f32>,
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
