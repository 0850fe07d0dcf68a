//! PHAK: the paper's 8-DoF bilateral pelvis-hip-knee-ankle chain (Figure 3, Eqs 16-17).

use super::{x, y, z};
use crate::lanes::LaneScalar;
use crate::{
    Anthropometry, BilateralPose, Chain, JointSpec, ModelError, PointSpec, Real, Side, Vec3,
};

/// PHAK's chain type: 8 coordinates, 7 joints (pelvis, then hip, knee, ankle per side), 8 points.
pub type PhakChain<T> = Chain<T, 8, 7, 8, 0>;

/// PHAK's inputs (radians), OpenSim coordinates. Pelvis rotation turns about the vertical +y,
/// pelvis list (the paper's "tilt") about the forward +x, in that body-fixed order
/// (`P = Q_rot(y) Q_list(x)`); the leg angles turn about +z with OpenSim's signs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhakAngles<T> {
    /// `pelvis_rotation`, about +y.
    pub pelvis_rotation: T,
    /// `pelvis_list`, about +x.
    pub pelvis_list: T,
    /// `hip_flexion_r`.
    pub hip_flexion_r: T,
    /// `knee_angle_r`.
    pub knee_angle_r: T,
    /// `ankle_angle_r`.
    pub ankle_angle_r: T,
    /// `hip_flexion_l`.
    pub hip_flexion_l: T,
    /// `knee_angle_l`.
    pub knee_angle_l: T,
    /// `ankle_angle_l`.
    pub ankle_angle_l: T,
}

impl<T: Real> PhakAngles<T> {
    /// OpenSim coordinate names, in input order.
    pub const NAMES: [&'static str; 8] = [
        "pelvis_rotation",
        "pelvis_list",
        "hip_flexion_r",
        "knee_angle_r",
        "ankle_angle_r",
        "hip_flexion_l",
        "knee_angle_l",
        "ankle_angle_l",
    ];
    /// The angles in input order.
    pub fn to_array(self) -> [T; 8] {
        [
            self.pelvis_rotation,
            self.pelvis_list,
            self.hip_flexion_r,
            self.knee_angle_r,
            self.ankle_angle_r,
            self.hip_flexion_l,
            self.knee_angle_l,
            self.ankle_angle_l,
        ]
    }
    /// From the angles in input order.
    pub fn from_array(a: [T; 8]) -> Self {
        Self {
            pelvis_rotation: a[0],
            pelvis_list: a[1],
            hip_flexion_r: a[2],
            knee_angle_r: a[3],
            ankle_angle_r: a[4],
            hip_flexion_l: a[5],
            knee_angle_l: a[6],
            ankle_angle_l: a[7],
        }
    }
}

/// PHAK for a subject. Origin at the pelvis origin (midway between the hip centres), ground
/// axes; pelvis translation is ignored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phak<T> {
    chain: PhakChain<T>,
}

impl<T: Real> Phak<T> {
    /// PHAK with these lengths.
    pub fn new(a: &Anthropometry<T>) -> Result<Self, ModelError> {
        a.right.validate()?;
        a.left.validate()?;
        let zero = T::ZERO;
        let down = |l: T| Vec3::new(zero, -l, zero);
        let hip = |s: Side| Vec3::new(zero, zero, s.sign::<T>() * a.limb(s).pelvis_half_width);
        let (r, l) = (&a.right, &a.left);
        let joints = [
            JointSpec::new("pelvis", None, Vec3::zero(), &[(y(), 0), (x(), 1)]),
            JointSpec::new("hip_r", Some(0), hip(Side::Right), &[(z(), 2)]),
            JointSpec::new("knee_r", Some(1), down(r.femur), &[(z(), 3)]),
            JointSpec::new("ankle_r", Some(2), down(r.tibia), &[(z(), 4)]),
            JointSpec::new("hip_l", Some(0), hip(Side::Left), &[(z(), 5)]),
            JointSpec::new("knee_l", Some(4), down(l.femur), &[(z(), 6)]),
            JointSpec::new("ankle_l", Some(5), down(l.tibia), &[(z(), 7)]),
        ];
        let centre = |name, body| PointSpec {
            name,
            body,
            offset: Vec3::zero(),
        };
        let points = [
            centre("hip_r", 1),
            centre("knee_r", 2),
            centre("ankle_r", 3),
            PointSpec {
                name: "toe_r",
                body: 3,
                offset: x::<T>() * r.foot,
            },
            centre("hip_l", 4),
            centre("knee_l", 5),
            centre("ankle_l", 6),
            PointSpec {
                name: "toe_l",
                body: 6,
                offset: x::<T>() * l.foot,
            },
        ];
        Ok(Self {
            chain: Chain::new(joints, points, [])?,
        })
    }

    /// The chain table (for the matrix reference method and benchmarks).
    pub fn chain(&self) -> &PhakChain<T> {
        &self.chain
    }

    /// Forward kinematics of both legs.
    #[inline]
    pub fn fk(&self, q: &PhakAngles<T>) -> BilateralPose<T> {
        BilateralPose::from_points(self.chain.forward(&q.to_array()))
    }

    /// Forward kinematics of many frames (the SIMD batch path, see
    /// [`Chain::forward_batch`]): `out[i] = fk(q[i])` for `i` below the shorter length, which
    /// is returned.
    pub fn fk_batch(&self, q: &[PhakAngles<T>], out: &mut [BilateralPose<T>]) -> usize
    where
        T: LaneScalar,
    {
        let n = q.len().min(out.len());
        self.chain.forward_batch(
            n,
            |i| q[i].to_array(),
            |i, p| out[i] = BilateralPose::from_points(p),
        );
        n
    }
}
