//! OpenSim's gait2392 lower-limb chain, exactly: pelvis, hips, spline knees, oblique ankles,
//! subtalar and MTP joints, toe tips. Geometry: `gait2392-geometry.md` (the generic model);
//! subject-scaled models change only the numbers in [`Gait2392Geometry`].

use super::{x, y, z};
use crate::lanes::LaneScalar;
use crate::spline::MAX_KNOTS;
use crate::{
    BilateralPose, Chain, JointSpec, LegPose, ModelError, PointSpec, Real, Side, Spline,
    SplineTranslation, Vec3,
};

/// gait2392's chain type: 17 coordinates, 11 joints, 12 points, 4 spline translations.
pub type Gait2392Chain<T> = Chain<T, 17, 11, 12, 4>;

/// The 17 input coordinates, OpenSim names, in input order (pelvis, then right leg, then left).
pub const COORDINATES: [&str; 17] = [
    "pelvis_tilt",
    "pelvis_list",
    "pelvis_rotation",
    "hip_flexion_r",
    "hip_adduction_r",
    "hip_rotation_r",
    "knee_angle_r",
    "ankle_angle_r",
    "subtalar_angle_r",
    "mtp_angle_r",
    "hip_flexion_l",
    "hip_adduction_l",
    "hip_rotation_l",
    "knee_angle_l",
    "ankle_angle_l",
    "subtalar_angle_l",
    "mtp_angle_l",
];

/// The 12 output points, in output order: per side (right first) the hip, knee, ankle, subtalar
/// and MTP joint centres, then the toe tip.
pub const POINTS: [&str; 12] = [
    "hip_r",
    "knee_r",
    "ankle_r",
    "subtalar_r",
    "mtp_r",
    "toetip_r",
    "hip_l",
    "knee_l",
    "ankle_l",
    "subtalar_l",
    "mtp_l",
    "toetip_l",
];

/// Knots of one spline (`x` in radians, `y` in metres), up to [`MAX_KNOTS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knots {
    /// Number of knots used.
    pub n: usize,
    /// Abscissae (strictly increasing).
    pub x: [f64; MAX_KNOTS],
    /// Values.
    pub y: [f64; MAX_KNOTS],
}

impl Knots {
    /// From slices of equal length (at most [`MAX_KNOTS`]; extra knots make [`Gait2392::new`]
    /// fail).
    pub fn new(x: &[f64], y: &[f64]) -> Self {
        let mut k = Self {
            n: x.len().min(y.len()),
            x: [0.0; MAX_KNOTS],
            y: [0.0; MAX_KNOTS],
        };
        if x.len() != y.len() || x.len() > MAX_KNOTS {
            k.n = MAX_KNOTS + 1;
            return k;
        }
        k.x[..x.len()].copy_from_slice(x);
        k.y[..y.len()].copy_from_slice(y);
        k
    }
    fn spline<T: Real>(&self) -> Result<Spline<T>, ModelError> {
        if self.n > MAX_KNOTS {
            return Err(ModelError::SplineKnots);
        }
        Spline::new(&self.x[..self.n], &self.y[..self.n])
    }
}

/// The numbers of one leg (metres, unit axes; frames and names as in OpenSim).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegGeometry {
    /// Hip centre in the pelvis frame (`hip` joint `location_in_parent`).
    pub hip_in_pelvis: [f64; 3],
    /// Hip flexion, adduction and rotation axes (body-fixed sequence).
    pub hip_axes: [[f64; 3]; 3],
    /// Knee centre translation along the femur's x as a function of `knee_angle`.
    pub knee_tx: Knots,
    /// Knee centre translation along the femur's y as a function of `knee_angle`.
    pub knee_ty: Knots,
    /// Ankle centre in the tibia frame.
    pub ankle_in_tibia: [f64; 3],
    /// Ankle axis.
    pub ankle_axis: [f64; 3],
    /// Subtalar centre in the talus frame.
    pub subtalar_in_talus: [f64; 3],
    /// Subtalar axis.
    pub subtalar_axis: [f64; 3],
    /// MTP centre in the calcaneus frame.
    pub mtp_in_calcn: [f64; 3],
    /// MTP axis.
    pub mtp_axis: [f64; 3],
    /// Toe tip (the gait2392 marker set's `Toe.Tip`) in the toes frame.
    pub toetip_in_toes: [f64; 3],
}

/// The numbers of the whole chain: one leg each side (a scaled subject may differ per side).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gait2392Geometry {
    /// Right leg.
    pub right: LegGeometry,
    /// Left leg.
    pub left: LegGeometry,
}

/// The generic model's knee spline knots (identical for both knees), as written in the model file
/// (rounded degrees in radians: they are data, not approximations of pi).
#[allow(clippy::approx_constant)]
const KNEE_TX_X: [f64; 12] = [
    -2.0944, -1.74533, -1.39626, -1.0472, -0.698132, -0.349066, -0.174533, 0.197344, 0.337395,
    0.490178, 1.52146, 2.0944,
];
const KNEE_TX_Y: [f64; 12] = [
    -0.0032, 0.00179, 0.00411, 0.0041, 0.00212, -0.001, -0.0031, -0.005227, -0.005435, -0.005574,
    -0.005435, -0.00525,
];
#[allow(clippy::approx_constant)]
const KNEE_TY_X: [f64; 7] = [
    -2.0944, -1.22173, -0.523599, -0.349066, -0.174533, 0.159149, 2.0944,
];
const KNEE_TY_Y: [f64; 7] = [
    -0.4226, -0.4082, -0.399, -0.3976, -0.3966, -0.395264, -0.396,
];

impl LegGeometry {
    /// The generic gait2392 right leg, with every number as written in `gait2392_simbody.osim`
    /// (the axes to 8 digits; `gait2392-geometry.md` rounds them to 6).
    pub fn generic_right() -> Self {
        Self {
            hip_in_pelvis: [-0.0707, -0.0661, 0.0835],
            hip_axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            knee_tx: Knots::new(&KNEE_TX_X, &KNEE_TX_Y),
            knee_ty: Knots::new(&KNEE_TY_X, &KNEE_TY_Y),
            ankle_in_tibia: [0.0, -0.43, 0.0],
            ankle_axis: [-0.10501355, -0.17402245, 0.97912632],
            subtalar_in_talus: [-0.04877, -0.04195, 0.00792],
            subtalar_axis: [0.78717961, 0.60474746, -0.12094949],
            mtp_in_calcn: [0.1788, -0.002, 0.00108],
            mtp_axis: [-0.5809544, 0.0, 0.81393611],
            toetip_in_toes: [0.0812, 0.007, -0.00108],
        }
    }

    /// This leg reflected through the sagittal plane: positions `(x, y, -z)`, rotation axes as
    /// axial vectors `(-x, -y, z)`. `generic_right().mirrored()` is gait2392's left leg.
    pub fn mirrored(&self) -> Self {
        let p = |v: [f64; 3]| [v[0], v[1], -v[2]];
        let a = |v: [f64; 3]| [-v[0], -v[1], v[2]];
        Self {
            hip_in_pelvis: p(self.hip_in_pelvis),
            hip_axes: self.hip_axes.map(a),
            knee_tx: self.knee_tx,
            knee_ty: self.knee_ty,
            ankle_in_tibia: p(self.ankle_in_tibia),
            ankle_axis: a(self.ankle_axis),
            subtalar_in_talus: p(self.subtalar_in_talus),
            subtalar_axis: a(self.subtalar_axis),
            mtp_in_calcn: p(self.mtp_in_calcn),
            mtp_axis: a(self.mtp_axis),
            toetip_in_toes: p(self.toetip_in_toes),
        }
    }
}

impl Gait2392Geometry {
    /// The generic, unscaled gait2392 (1.8 m, 75 kg).
    pub fn generic() -> Self {
        let right = LegGeometry::generic_right();
        Self {
            right,
            left: right.mirrored(),
        }
    }
    /// One leg.
    pub fn leg(&self, side: Side) -> &LegGeometry {
        match side {
            Side::Right => &self.right,
            Side::Left => &self.left,
        }
    }
}

impl Default for Gait2392Geometry {
    fn default() -> Self {
        Self::generic()
    }
}

/// The 12 points of a gait2392 pose, in [`POINTS`] order (metres; origin at the pelvis origin,
/// ground axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gait2392Pose<T> {
    /// Points in [`POINTS`] order.
    pub points: [Vec3<T>; 12],
}

impl<T: Real> Gait2392Pose<T> {
    /// Hip, knee, ankle and toe tip of both legs: the columns every model reports.
    pub fn bilateral(&self) -> BilateralPose<T> {
        let p = &self.points;
        BilateralPose {
            right: LegPose {
                hip: p[0],
                knee: p[1],
                ankle: p[2],
                toe: p[5],
            },
            left: LegPose {
                hip: p[6],
                knee: p[7],
                ankle: p[8],
                toe: p[11],
            },
        }
    }
    /// Subtalar joint centre of one side.
    pub fn subtalar(&self, side: Side) -> Vec3<T> {
        self.points[side_base(side) + 3]
    }
    /// MTP joint centre of one side.
    pub fn mtp(&self, side: Side) -> Vec3<T> {
        self.points[side_base(side) + 4]
    }
}

fn side_base(side: Side) -> usize {
    match side {
        Side::Right => 0,
        Side::Left => 6,
    }
}

/// gait2392's leg chain. Inputs: the 17 [`COORDINATES`] (radians); pelvis translation is not an
/// input (origin at the pelvis origin, ground axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gait2392<T> {
    chain: Gait2392Chain<T>,
}

impl<T: Real> Gait2392<T> {
    /// The chain for these numbers.
    pub fn new(g: &Gait2392Geometry) -> Result<Self, ModelError> {
        let v = Vec3::<T>::from_f64;
        let leg_joints = |s: Side, first: usize, coord: usize| {
            let l = g.leg(s);
            let [a1, a2, a3] = l.hip_axes.map(v);
            [
                JointSpec::new(
                    ["hip_r", "hip_l"][s as usize],
                    Some(0),
                    v(l.hip_in_pelvis),
                    &[(a1, coord), (a2, coord + 1), (a3, coord + 2)],
                ),
                JointSpec::new(
                    ["knee_r", "knee_l"][s as usize],
                    Some(first),
                    Vec3::zero(),
                    &[(z(), coord + 3)],
                ),
                JointSpec::new(
                    ["ankle_r", "ankle_l"][s as usize],
                    Some(first + 1),
                    v(l.ankle_in_tibia),
                    &[(v(l.ankle_axis), coord + 4)],
                ),
                JointSpec::new(
                    ["subtalar_r", "subtalar_l"][s as usize],
                    Some(first + 2),
                    v(l.subtalar_in_talus),
                    &[(v(l.subtalar_axis), coord + 5)],
                ),
                JointSpec::new(
                    ["mtp_r", "mtp_l"][s as usize],
                    Some(first + 3),
                    v(l.mtp_in_calcn),
                    &[(v(l.mtp_axis), coord + 6)],
                ),
            ]
        };
        let [r0, r1, r2, r3, r4] = leg_joints(Side::Right, 1, 3);
        let [l0, l1, l2, l3, l4] = leg_joints(Side::Left, 6, 10);
        let pelvis = JointSpec::new(
            "pelvis",
            None,
            Vec3::zero(),
            &[(z(), 0), (x(), 1), (y(), 2)],
        );
        let joints = [pelvis, r0, r1, r2, r3, r4, l0, l1, l2, l3, l4];
        let leg_points = |s: Side, first: usize| {
            let at = |k: usize| PointSpec {
                name: POINTS[side_base(s) + k],
                body: first + k,
                offset: Vec3::zero(),
            };
            [
                at(0),
                at(1),
                at(2),
                at(3),
                at(4),
                PointSpec {
                    name: POINTS[side_base(s) + 5],
                    body: first + 4,
                    offset: v(g.leg(s).toetip_in_toes),
                },
            ]
        };
        let [p0, p1, p2, p3, p4, p5] = leg_points(Side::Right, 1);
        let [p6, p7, p8, p9, p10, p11] = leg_points(Side::Left, 6);
        let knee = |s: Side,
                    joint: usize,
                    coordinate: usize|
         -> Result<[SplineTranslation<T>; 2], ModelError> {
            let l = g.leg(s);
            Ok([
                SplineTranslation {
                    joint,
                    direction: x(),
                    coordinate,
                    spline: l.knee_tx.spline()?,
                },
                SplineTranslation {
                    joint,
                    direction: y(),
                    coordinate,
                    spline: l.knee_ty.spline()?,
                },
            ])
        };
        let [s0, s1] = knee(Side::Right, 2, 6)?;
        let [s2, s3] = knee(Side::Left, 7, 13)?;
        let chain = Chain::new(
            joints,
            [p0, p1, p2, p3, p4, p5, p6, p7, p8, p9, p10, p11],
            [s0, s1, s2, s3],
        )?;
        Ok(Self { chain })
    }

    /// The chain table.
    pub fn chain(&self) -> &Gait2392Chain<T> {
        &self.chain
    }

    /// Forward kinematics: the 12 points for the 17 [`COORDINATES`] (radians).
    #[inline]
    pub fn fk(&self, q: &[T; 17]) -> Gait2392Pose<T> {
        Gait2392Pose {
            points: self.chain.forward(q),
        }
    }

    /// Forward kinematics of many frames (the SIMD batch path): `out[i] = fk(q[i])` for `i`
    /// below the shorter length, which is returned.
    pub fn fk_batch(&self, q: &[[T; 17]], out: &mut [Gait2392Pose<T>]) -> usize
    where
        T: LaneScalar,
    {
        let n = q.len().min(out.len());
        self.chain
            .forward_batch(n, |i| q[i], |i, points| out[i] = Gait2392Pose { points });
        n
    }
}
