//! IMU orientations in, gait2392 coordinates out (or PHAK's, or an imported chain's: [`fit`]), as
//! OpenSim's OpenSense does it.
//!
//! An IMU node reports its own orientation as a unit quaternion in its world frame (the sensor
//! fusion's). Three steps turn the eight orientations of OpenSense's lower-body set (torso,
//! pelvis, femurs, tibias, calcanei: [`Segment`]) into the model's coordinates:
//!
//! 1. **Calibration** from one static pose ([`Calibration::new`]), as OpenSense's `IMUPlacer`
//!    (`IMUPlacer::run` and `OpenSenseUtilities::computeHeadingCorrection` in opensim-core):
//!    every reading is rotated into OpenSim's axes by the sensor-to-OpenSim rotation (a
//!    space-fixed X-Y-Z sequence, (-pi/2, 0, 0) by default: `OpenSenseUtilities::rotateOrientationTable`
//!    applies it on the left); then, if a base IMU and its heading axis are given, all of them
//!    are turned about the vertical by the angle between that axis and the model's forward
//!    direction (the x axis of the pelvis in the default pose), so the subject may face any
//!    direction; then each sensor's rotation relative to its segment is its segment's default
//!    orientation (all coordinates zero) inverted times its corrected reading (`R_FB = ~R_GB *
//!    R_GF`). Like OpenSense, the heading angle is `acos` of the dot product of the (3-D) heading
//!    axis with forward, signed by the cross product's vertical component, and it is applied at
//!    calibration only: a frame's segment orientation is the reading rotated into OpenSim's axes
//!    times the inverse of the sensor's rotation in its segment ([`Calibration::segments`]), so
//!    the pelvis is reported in the sensors' world frame (its heading is the walking
//!    direction), as OpenSense's inverse kinematics reports it.
//! 2. **Closed form** ([`Mode::ClosedForm`], the cheap mode): each joint's relative rotation
//!    (parent segment to child segment) decomposed into the joint's own axes: the pelvis
//!    (tilt, list, rotation about z, x, y, body-fixed, relative to ground), the hips (z, x, y;
//!    the left hip's x and y reversed) and the lumbar joint (z, x, y, the torso relative to the
//!    pelvis) by their three orthogonal axes ([`math::three_axes`]); the knee (its one axis, z:
//!    the spline translations do not change orientations) by the twist about its axis; the
//!    ankle and subtalar, whose oblique axes are not orthogonal and have the talus (no sensor)
//!    between them, from the calcaneus relative to the tibia by a two-axis decomposition
//!    ([`math::two_axes`]). Exact when the data fit the model; with real data the legs'
//!    misfit stays on the distal joints.
//! 3. **Least squares** ([`Mode::LeastSquares`]): per leg, Gauss-Newton over hip flexion,
//!    adduction, rotation, knee, ankle and subtalar minimising the sum of the squared angles of
//!    the rotations between each sensor's segment orientation (femur, tibia, calcaneus) and
//!    the model's prediction of it (the angle OpenSim's `OrientationSensors` goal squares),
//!    the pelvis fixed by its own sensor. The residual of each sensor is the rotation vector of
//!    the error rotation in ground, its Jacobian the joint axes in ground (from the chain's
//!    own frames, [`Chain::frames`](crate::Chain::frames)); because the rotation vector's log
//!    Jacobian leaves the residual unchanged (`J(r) r = r`), the fixed point is the exact
//!    minimiser, not an approximation of it. Warm start: the previous frame's solution (the
//!    closed form on the first frame and after [`Solver::reset`]); [`ITERATIONS`] iterations,
//!    none clamped: gait2392 clamps no coordinate, so OpenSense's inverse kinematics bounds
//!    none.
//!
//! **What the eight-IMU set determines.** The pelvis (tilt, list, rotation: pelvis sensor), the
//! hips (3 each: pelvis and femur), the knees (femur and tibia), the ankles and subtalars
//! (tibia and calcaneus), and the lumbar joint (3: pelvis and torso; gait2392's chain has no
//! torso, so [`ImuAngles::lumbar`] carries it beside the 17 chain coordinates). Not the MTP
//! joints (no toe sensor): they stay at zero. Pelvis translations are not estimated.
//!
//! The calibration depends on the model only through its bodies' orientations in the default
//! pose, which are all the ground's for gait2392 and every scaled subject of it: one
//! calibration serves any of them (a device may keep it across model switches).
//!
//! **Missing sensors.** A segment without a reading (no sensor, or none this frame, or none in
//! the calibration pose) constrains nothing: in the closed form, a joint whose parent or child
//! segment has no orientation keeps its previous value (zero before the first frame); in the
//! least squares, a coordinate that no present sensor depends on keeps its previous value,
//! and the others fit the sensors that remain (a tibia sensor alone still moves hip and knee).
//! [`ImuAngles::held`] says which were kept.
//!
//! **Turning.** `pelvis_rotation` is unbounded: each frame's value is unwrapped to within half a
//! turn of the previous frame's, so it never wraps or jumps by 360 degrees (no coordinate is
//! clamped: gait2392 clamps none, its pelvis's +-90 degree range included). [`heading_free_pelvis`]
//! re-expresses the pelvis relative to a direction of progression, for analyses of turning
//! walks (in the world frame, gait2392's tilt and list change with the walking direction).
//!
//! **Other models.** [`fit`] solves the same problem for PHAK on its own axes and for any
//! imported OpenSim chain ([`FitSolver`], [`FitModel`]; numeric Jacobian from the model's own
//! body orientations, bounded coordinates by an active set), calibrated from the model's
//! default pose ([`Calibration::for_model`]).
//!
//! Everything is fixed size, allocation-free and generic over [`Real`]: the
//! device runs it in `f32`, the host in `f64`.

mod calibration;
pub mod fit;
pub mod math;
mod solve;

pub use calibration::{Calibration, Heading, HeadingAxis, Settings};
pub use fit::{FitAngles, FitModel, FitSolver};
pub use solve::{
    closed_form, heading_free_pelvis, lumbar, ImuAngles, Mode, Solver, ITERATIONS, LUMBAR,
};

use core::fmt;

use crate::{Quat, Real};

/// How many sensors the set has.
pub const SENSORS: usize = 8;

/// A body segment that carries an IMU, in OpenSense's lower-body set. The discriminant is the
/// segment's index in [`Orientations`].
///
/// The protocol crate carries it as it is (`qgait_proto::SegmentId`), with its own stable wire
/// byte for each segment; features `serde` (by variant name, or index in a binary format) and
/// `defmt` derive those traits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Segment {
    /// The pelvis (gait2392's root body).
    Pelvis = 0,
    /// Right thigh.
    FemurR = 1,
    /// Right shank.
    TibiaR = 2,
    /// Right foot (heel bone).
    CalcnR = 3,
    /// Left thigh.
    FemurL = 4,
    /// Left shank.
    TibiaL = 5,
    /// Left foot.
    CalcnL = 6,
    /// The trunk (gait2392's `torso`, on the lumbar joint).
    Torso = 7,
}

impl Segment {
    /// All of them, in index order.
    pub const ALL: [Segment; SENSORS] = [
        Segment::Pelvis,
        Segment::FemurR,
        Segment::TibiaR,
        Segment::CalcnR,
        Segment::FemurL,
        Segment::TibiaL,
        Segment::CalcnL,
        Segment::Torso,
    ];

    /// OpenSim's body name: `"pelvis"`, `"femur_r"`, ..., `"torso"`.
    pub fn body(self) -> &'static str {
        match self {
            Segment::Pelvis => "pelvis",
            Segment::FemurR => "femur_r",
            Segment::TibiaR => "tibia_r",
            Segment::CalcnR => "calcn_r",
            Segment::FemurL => "femur_l",
            Segment::TibiaL => "tibia_l",
            Segment::CalcnL => "calcn_l",
            Segment::Torso => "torso",
        }
    }

    /// OpenSense's column label: the body name and `_imu` (`"pelvis_imu"`, ...).
    pub fn imu_label(self) -> &'static str {
        match self {
            Segment::Pelvis => "pelvis_imu",
            Segment::FemurR => "femur_r_imu",
            Segment::TibiaR => "tibia_r_imu",
            Segment::CalcnR => "calcn_r_imu",
            Segment::FemurL => "femur_l_imu",
            Segment::TibiaL => "tibia_l_imu",
            Segment::CalcnL => "calcn_l_imu",
            Segment::Torso => "torso_imu",
        }
    }

    /// The segment of a body name or an IMU label (`"femur_r"` or `"femur_r_imu"`).
    pub fn from_name(name: &str) -> Option<Segment> {
        let body = name.strip_suffix("_imu").unwrap_or(name);
        Segment::ALL.into_iter().find(|s| s.body() == body)
    }

    /// The segment with this index.
    pub fn from_index(i: usize) -> Option<Segment> {
        Segment::ALL.get(i).copied()
    }

    /// The gait2392 chain joint whose frame is this segment's body (`None` for the torso, which
    /// the chain does not carry).
    pub(crate) fn chain_joint(self) -> Option<usize> {
        match self {
            Segment::Pelvis => Some(0),
            Segment::FemurR => Some(1),
            Segment::TibiaR => Some(2),
            Segment::CalcnR => Some(4),
            Segment::FemurL => Some(6),
            Segment::TibiaL => Some(7),
            Segment::CalcnL => Some(9),
            Segment::Torso => None,
        }
    }
}

impl fmt::Display for Segment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.imu_label())
    }
}

/// One orientation (unit quaternion, sensor or segment frame to world) per [`Segment`], or none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orientations<T> {
    /// By [`Segment`] index.
    pub q: [Option<Quat<T>>; SENSORS],
}

impl<T: Real> Orientations<T> {
    /// No orientation at all.
    pub const EMPTY: Self = Self { q: [None; SENSORS] };

    /// The orientation of `segment`, if any.
    pub fn get(&self, segment: Segment) -> Option<Quat<T>> {
        self.q[segment as usize]
    }

    /// Sets (or with `None` clears) the orientation of `segment`.
    pub fn set(&mut self, segment: Segment, q: Option<Quat<T>>) {
        self.q[segment as usize] = q;
    }
}

impl<T: Real> Default for Orientations<T> {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// Largest accepted distance of a reading's norm from 1 ([`unit()`]): farther, the quaternion is
/// not a rotation (a corrupted or mis-scaled value); nearer, it is normalised.
pub const UNIT_TOLERANCE: f64 = 0.1;

/// `q` normalised, if its norm is finite and within [`UNIT_TOLERANCE`] of 1.
pub fn unit<T: Real>(q: Quat<T>, segment: Segment) -> Result<Quat<T>, ImuError> {
    let n = q.norm();
    if n.is_finite() && (n - T::ONE).abs() <= T::from_f64(UNIT_TOLERANCE) {
        let k = T::ONE / n;
        Ok(Quat::new(q.w * k, q.x * k, q.y * k, q.z * k))
    } else {
        Err(ImuError::NotUnit { segment })
    }
}

/// Why a calibration or a reading was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ImuError {
    /// A quaternion is not finite or its norm is farther than [`UNIT_TOLERANCE`] from 1.
    NotUnit {
        /// Whose reading.
        segment: Segment,
    },
    /// The heading correction's base IMU has no reading in the calibration pose.
    BaseMissing {
        /// The base IMU.
        segment: Segment,
    },
    /// The base IMU's heading axis is (nearly) vertical in the calibration pose, so it gives no
    /// heading (less than 0.1 of it horizontal, about 6 degrees from vertical).
    HeadingVertical {
        /// The base IMU.
        segment: Segment,
    },
}

impl fmt::Display for ImuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotUnit { segment } => write!(
                f,
                "{segment}: the quaternion is not finite or its norm is not within {UNIT_TOLERANCE} of 1"
            ),
            Self::BaseMissing { segment } => write!(
                f,
                "{segment}: the heading's base IMU has no orientation in the calibration pose"
            ),
            Self::HeadingVertical { segment } => write!(
                f,
                "{segment}: the heading axis of the base IMU is vertical in the calibration pose"
            ),
        }
    }
}

impl core::error::Error for ImuError {}
