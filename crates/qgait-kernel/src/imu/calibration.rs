//! Calibration from a static pose, as OpenSense's `IMUPlacer`.

use core::str::FromStr;

use super::fit::FitModel;
use super::math::{acos, space_fixed_xyz};
use super::{unit, ImuError, Orientations, Segment, SENSORS};
use crate::{Gait2392, Quat, Real, Vec3};

/// An axis of a sensor's own frame, with its sign (OpenSense's `base_heading_axis`). The
/// protocol crate carries it as it is (`qgait_proto::HeadingAxisId`), with its own stable wire
/// byte for each axis; features `serde` and `defmt` derive those traits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HeadingAxis {
    /// +x
    X,
    /// -x
    NegX,
    /// +y
    Y,
    /// -y
    NegY,
    /// +z
    Z,
    /// -z
    NegZ,
}

impl HeadingAxis {
    /// All of them, in declaration order.
    pub const ALL: [HeadingAxis; 6] = [
        HeadingAxis::X,
        HeadingAxis::NegX,
        HeadingAxis::Y,
        HeadingAxis::NegY,
        HeadingAxis::Z,
        HeadingAxis::NegZ,
    ];

    /// The unit vector.
    pub fn vector<T: Real>(self) -> Vec3<T> {
        match self {
            HeadingAxis::X => Vec3::unit_x(),
            HeadingAxis::NegX => -Vec3::unit_x(),
            HeadingAxis::Y => Vec3::unit_y(),
            HeadingAxis::NegY => -Vec3::unit_y(),
            HeadingAxis::Z => Vec3::unit_z(),
            HeadingAxis::NegZ => -Vec3::unit_z(),
        }
    }
}

impl FromStr for HeadingAxis {
    type Err = ();
    /// `x`, `-x`, `y`, `-y`, `z`, `-z` (either case), as OpenSense's setup files write it.
    fn from_str(s: &str) -> Result<Self, ()> {
        Ok(match s {
            "x" | "X" | "+x" | "+X" => HeadingAxis::X,
            "-x" | "-X" => HeadingAxis::NegX,
            "y" | "Y" | "+y" | "+Y" => HeadingAxis::Y,
            "-y" | "-Y" => HeadingAxis::NegY,
            "z" | "Z" | "+z" | "+Z" => HeadingAxis::Z,
            "-z" | "-Z" => HeadingAxis::NegZ,
            _ => return Err(()),
        })
    }
}

/// The heading correction: which IMU's which axis points forward in the calibration pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Heading {
    /// OpenSense's `base_imu_label`.
    pub base: Segment,
    /// OpenSense's `base_heading_axis`.
    pub axis: HeadingAxis,
}

/// OpenSense's placer settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings<T> {
    /// The rotation from the sensors' world frame to OpenSim's (y up), as a space-fixed X-Y-Z
    /// sequence in radians (`sensor_to_opensim_rotations`). Default `(-pi/2, 0, 0)`: a z-up
    /// sensor world (Xsens, APDM) to OpenSim's y up.
    pub sensor_to_opensim: [T; 3],
    /// The heading correction, or `None` for none (the subject then faces the world's x at
    /// calibration).
    pub heading: Option<Heading>,
}

impl<T: Real> Default for Settings<T> {
    fn default() -> Self {
        Self {
            sensor_to_opensim: [T::from_f64(-core::f64::consts::FRAC_PI_2), T::ZERO, T::ZERO],
            heading: None,
        }
    }
}

impl<T: Real> Settings<T> {
    /// The settings of OpenSense's tutorial recording: the default rotation, heading from the
    /// torso IMU's z axis.
    pub fn opensense_tutorial() -> Self {
        Self {
            heading: Some(Heading {
                base: Segment::Torso,
                axis: HeadingAxis::Z,
            }),
            ..Self::default()
        }
    }
}

/// Each sensor's place on its segment, from one static pose in the model's default pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration<T> {
    /// The sensor-to-OpenSim rotation.
    sensor_to_opensim: Quat<T>,
    /// The heading correction applied at calibration (radians about OpenSim's y).
    heading: T,
    /// Each sensor's frame in its segment's frame (OpenSense's `R_FB`), if it was calibrated.
    sensor_in_segment: [Option<Quat<T>>; SENSORS],
}

impl<T: Real> Calibration<T> {
    /// The calibration for the static `pose` (the raw readings, in the sensors' world frame,
    /// the subject standing in the model's default pose): see the [module](super) docs for
    /// the steps. A sensor without a reading here stays uncalibrated, and its later readings
    /// are ignored.
    pub fn new(
        model: &Gait2392<T>,
        pose: &Orientations<T>,
        settings: &Settings<T>,
    ) -> Result<Self, ImuError> {
        let default = super::solve::frames(model, &[T::ZERO; 17]);
        // The torso hangs from the pelvis without an orientation offset (gait2392's back
        // joint): in the default pose it is parallel to the pelvis.
        let orientations = Segment::ALL.map(|s| default[s.chain_joint().unwrap_or(0)].rotation);
        Self::with_default_pose(orientations, pose, settings)
    }

    /// The calibration for a [`FitModel`] (PHAK, an imported chain): its bodies' orientations
    /// at all coordinates zero; a segment the model lacks (the torso) is taken parallel to the
    /// pelvis, as in gait2392's and Rajagopal's default pose.
    pub fn for_model<M: FitModel<T, N>, const N: usize>(
        model: &M,
        pose: &Orientations<T>,
        settings: &Settings<T>,
    ) -> Result<Self, ImuError> {
        let default = model.orientations(&[T::ZERO; N]);
        let pelvis = default[Segment::Pelvis as usize].unwrap_or(Quat::identity());
        Self::with_default_pose(default.map(|o| o.unwrap_or(pelvis)), pose, settings)
    }

    /// The calibration for the static `pose` given each segment's orientation in the model's
    /// default pose (by [`Segment`] index; the pelvis's x is the model's forward direction).
    // Not inlined: one copy on the device whichever caller (flash; BENCHMARKS.md).
    #[inline(never)]
    pub fn with_default_pose(
        default: [Quat<T>; SENSORS],
        pose: &Orientations<T>,
        settings: &Settings<T>,
    ) -> Result<Self, ImuError> {
        let s = space_fixed_xyz(settings.sensor_to_opensim);
        let mut rotated = [None; SENSORS];
        for (segment, slot) in Segment::ALL.into_iter().zip(&mut rotated) {
            if let Some(q) = pose.get(segment) {
                *slot = Some(s * unit(q, segment)?);
            }
        }
        let default_of = |segment: Segment| default[segment as usize];
        let heading = match settings.heading {
            None => T::ZERO,
            Some(h) => {
                let base =
                    rotated[h.base as usize].ok_or(ImuError::BaseMissing { segment: h.base })?;
                let axis = base.rotate(h.axis.vector());
                if axis.x * axis.x + axis.z * axis.z < T::from_f64(0.01) {
                    return Err(ImuError::HeadingVertical { segment: h.base });
                }
                // computeHeadingCorrection: the angle between the axis and the base body's
                // (the chain root's) x in ground, negative when x cross axis points up.
                let forward = default_of(Segment::Pelvis).rotate(Vec3::unit_x());
                let angle = acos(axis.dot(forward));
                if forward.cross(axis).y > T::ZERO {
                    -angle
                } else {
                    angle
                }
            }
        };
        let h = Quat::from_axis_angle(Vec3::unit_y(), heading);
        let mut sensor_in_segment = [None; SENSORS];
        for segment in Segment::ALL {
            if let Some(r) = rotated[segment as usize] {
                sensor_in_segment[segment as usize] = Some(default_of(segment).conj() * (h * r));
            }
        }
        Ok(Self {
            sensor_to_opensim: s,
            heading,
            sensor_in_segment,
        })
    }

    /// The heading correction applied at calibration (radians about OpenSim's vertical y; zero
    /// without one): the subject faced `-heading` about y in the sensors' world frame.
    pub fn heading(&self) -> T {
        self.heading
    }

    /// The sensor-to-OpenSim rotation.
    pub fn sensor_to_opensim(&self) -> Quat<T> {
        self.sensor_to_opensim
    }

    /// A sensor's frame in its segment's frame, if it was calibrated.
    pub fn sensor_in_segment(&self, segment: Segment) -> Option<Quat<T>> {
        self.sensor_in_segment[segment as usize]
    }

    /// The orientation of `segment` (segment frame to OpenSim's ground, in the sensors' world
    /// heading) for its sensor's raw `reading`; `None` if the sensor was not calibrated.
    pub fn segment(&self, segment: Segment, reading: Quat<T>) -> Result<Option<Quat<T>>, ImuError> {
        let Some(offset) = self.sensor_in_segment[segment as usize] else {
            return Ok(None);
        };
        Ok(Some(
            self.sensor_to_opensim * unit(reading, segment)? * offset.conj(),
        ))
    }

    /// Every segment's orientation for one frame of raw readings ([`segment`](Self::segment)
    /// of each; the first bad reading is the error).
    // Not inlined: one copy on the device whichever caller (flash; BENCHMARKS.md).
    #[inline(never)]
    pub fn segments(&self, readings: &Orientations<T>) -> Result<Orientations<T>, ImuError> {
        let mut out = Orientations::EMPTY;
        for segment in Segment::ALL {
            if let Some(q) = readings.get(segment) {
                out.set(segment, self.segment(segment, q)?);
            }
        }
        Ok(out)
    }
}
