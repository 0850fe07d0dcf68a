//! The parts of the hub that turn a sample into frames on the serial port ([`Output`]),
//! borrowed apart from the input whose assembler reports the samples: a joint-angle sample
//! straight to its pose frame (and its points' velocities), an orientation sample first through
//! the IMU input's calibration and solver, in the order the
//! [`orientation`](crate::orientation) module describes.

use embedded_io::Write;
use qgait_proto::{FrameFlags, Status, MAX_FRAME_LEN};

use crate::assembly::SampleEvent;
use crate::counters::bump;
use crate::line::write_frame;
use crate::velocity::Differentiator;
use crate::Kinematics;
#[cfg(feature = "imu")]
use {
    crate::assembly::{JointSet, SegmentSample},
    crate::orientation::ImuInput,
    qgait_kernel::imu::{Calibration, Orientations, SENSORS},
    qgait_proto::device_model::{kernel_mode, kernel_settings, q14_quat},
    qgait_proto::{SegmentId, WireByte},
};

/// The parts of the hub that turn samples (joint angles, or segment orientations in
/// [`orientation`](crate::orientation)) into pose frames on the serial port: borrowed apart
/// from the assembler, which reports the samples.
pub(crate) struct Output<'a, S> {
    pub(crate) kinematics: &'a Kinematics,
    pub(crate) status: &'a mut Status,
    pub(crate) serial: &'a mut S,
    pub(crate) tx: &'a mut [u8; MAX_FRAME_LEN],
    pub(crate) velocity: &'a mut Differentiator,
    /// The orientation input's settings, calibration and solver.
    #[cfg(feature = "imu")]
    pub(crate) imu: &'a mut ImuInput,
}

impl<S: Write> Output<'_, S> {
    pub(crate) fn on_sample(&mut self, event: SampleEvent<'_>) {
        // The sample stays in the assembler's slot: lent, not copied.
        let (sample, mut flags) = match event {
            SampleEvent::Complete(sample) => (sample, 0),
            SampleEvent::Held { sample, .. } => (sample, FrameFlags::MISSING | FrameFlags::HELD),
            SampleEvent::Dropped { .. } => {
                bump(&mut self.status.samples_incomplete);
                return;
            }
        };
        // No model while a chain's table is being written.
        if !self.kinematics.computes() {
            bump(&mut self.status.samples_incomplete);
            return;
        }
        bump(&mut self.status.samples_completed);
        // The joints judged out of range as their packets arrived (a held angle as its packet
        // was): the angles are not checked again here.
        if !sample.out_of_range.is_empty() {
            flags |= FrameFlags::OUT_OF_RANGE;
        }
        // Encoded straight from the sample and the pose: no `PoseFrame` built and copied.
        let Ok(frame) = self.kinematics.encode_pose_frame(
            sample.seq,
            sample.timestamp_us,
            &sample.angles,
            flags,
            self.tx,
        ) else {
            return;
        };
        write_frame(self.serial, self.status, frame);
        // Then its points' velocities, if on and the sample follows the last one posed.
        if let Some((rates, dt_us)) = self.velocity.next(sample.seq, &sample.angles) {
            if let Ok(frame) = self.kinematics.encode_pose_velocities(
                sample.seq,
                dt_us,
                &sample.angles,
                &rates,
                self.tx,
            ) {
                write_frame(self.serial, self.status, frame);
            }
        }
    }
}

#[cfg(feature = "imu")]
impl<S: Write> Output<'_, S> {
    /// One orientation sample leaving the window (see the [`orientation`](crate::orientation)
    /// module docs).
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
            write_frame(self.serial, self.status, frame);
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
