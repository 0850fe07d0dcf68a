//! The IMU input's wire values as the kernel's: settings, modes and quaternions
//! ([`SegmentOrientation`] and [`ImuConfig`] to `qgait_kernel::imu`; segments and heading axes
//! are the kernel's own types).

use qgait_kernel::imu::{self, ImuError, Mode, Settings};
use qgait_kernel::{Quat, Real};

use crate::{ImuConfig, ImuHeading, InputMode, SegmentOrientation, Q14_ONE};

/// The kernel's solver mode of an input mode (`None` for joint angles).
pub const fn kernel_mode(mode: InputMode) -> Option<Mode> {
    match mode {
        InputMode::JointAngles => None,
        InputMode::OrientationsClosedForm => Some(Mode::ClosedForm),
        InputMode::OrientationsLeastSquares => Some(Mode::LeastSquares),
    }
}

/// The input mode of a kernel solver mode.
pub const fn input_mode(mode: Mode) -> InputMode {
    match mode {
        Mode::ClosedForm => InputMode::OrientationsClosedForm,
        Mode::LeastSquares => InputMode::OrientationsLeastSquares,
    }
}

/// The kernel's calibration settings of an [`ImuConfig`], in precision `T` (the `f32` numbers
/// on the wire, widened).
pub fn kernel_settings<T: Real>(config: &ImuConfig) -> Settings<T> {
    Settings {
        sensor_to_opensim: config.sensor_to_opensim.map(|r| T::from_f64(f64::from(r))),
        heading: config.heading.map(|h| imu::Heading {
            base: h.base,
            axis: h.axis,
        }),
    }
}

/// The wire settings of kernel settings: the sensor-to-OpenSim angles rounded to `f32`, the
/// precision the wire carries (a host computing beside a hub uses
/// [`kernel_settings`] of the result, so both use the same numbers).
pub fn wire_settings<T: Real>(settings: &Settings<T>) -> ([f32; 3], Option<ImuHeading>) {
    (
        settings.sensor_to_opensim.map(|r| r.to_f64() as f32),
        settings.heading.map(|h| ImuHeading {
            base: h.base,
            axis: h.axis,
        }),
    )
}

/// The quaternion of Q14 components `w, x, y, z`, as decoded (not normalised).
pub fn q14_quat<T: Real>(q14: [i16; 4]) -> Quat<T> {
    let [w, x, y, z] = q14.map(|c| T::from_f32(f32::from(c) / Q14_ONE));
    Quat::new(w, x, y, z)
}

/// A packet's orientation for the kernel: its Q14 quaternion decoded and normalised if its
/// norm is within the kernel's [`UNIT_TOLERANCE`](imu::UNIT_TOLERANCE) of 1, the error of
/// [`imu::unit`] otherwise.
pub fn packet_quat<T: Real>(packet: &SegmentOrientation) -> Result<Quat<T>, ImuError> {
    imu::unit(q14_quat(packet.q14), packet.header.segment)
}
