//! HAK: the paper's 3-DoF sagittal hip-knee-ankle-toe chain (Figure 2, Eqs 12-15).

use super::{x, z};
use crate::lanes::LaneScalar;
use crate::{Chain, JointSpec, LegPose, Limb, ModelError, PointSpec, Real, Vec3};

/// HAK's chain type: 3 coordinates, 3 joints, 4 points, no splines.
pub type HakChain<T> = Chain<T, 3, 3, 4, 0>;

/// HAK's inputs (radians, OpenSim signs: hip flexion > 0 forward, knee angle < 0 flexion,
/// ankle angle > 0 dorsiflexion). All three rotate about +z.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HakAngles<T> {
    /// `q1`.
    pub hip_flexion: T,
    /// `q2`.
    pub knee_angle: T,
    /// `q3`.
    pub ankle_angle: T,
}

impl<T: Real> HakAngles<T> {
    /// Coordinate names, in input order.
    pub const NAMES: [&'static str; 3] = ["hip_flexion", "knee_angle", "ankle_angle"];
    /// The angles in input order.
    pub fn to_array(self) -> [T; 3] {
        [self.hip_flexion, self.knee_angle, self.ankle_angle]
    }
    /// From the angles in input order.
    pub fn from_array(a: [T; 3]) -> Self {
        Self {
            hip_flexion: a[0],
            knee_angle: a[1],
            ankle_angle: a[2],
        }
    }
}

/// HAK for one leg (either side: the sagittal chain is the same). The hip is the origin; at
/// q = 0 femur and tibia point down (-y) and the foot forward (+x).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hak<T> {
    chain: HakChain<T>,
}

impl<T: Real> Hak<T> {
    /// HAK with this leg's femur, tibia and foot (`pelvis_half_width` is not used).
    pub fn new(limb: &Limb<T>) -> Result<Self, ModelError> {
        limb.validate()?;
        let zero = T::ZERO;
        let joints = [
            JointSpec::new(None, Vec3::zero(), &[(z(), 0)]),
            JointSpec::new(Some(0), Vec3::new(zero, -limb.femur, zero), &[(z(), 1)]),
            JointSpec::new(Some(1), Vec3::new(zero, -limb.tibia, zero), &[(z(), 2)]),
        ];
        let points = [
            PointSpec {
                body: 0,
                offset: Vec3::zero(),
            },
            PointSpec {
                body: 1,
                offset: Vec3::zero(),
            },
            PointSpec {
                body: 2,
                offset: Vec3::zero(),
            },
            PointSpec {
                body: 2,
                offset: x::<T>() * limb.foot,
            },
        ];
        Ok(Self {
            chain: Chain::new(joints, points, [])?,
        })
    }

    /// The chain table (for the matrix reference method and benchmarks).
    pub fn chain(&self) -> &HakChain<T> {
        &self.chain
    }

    /// Forward kinematics: `toe = Q1 (-l1 j) Q1* + Q1Q2 (-l2 j) (Q1Q2)* + Q1Q2Q3 (l3 i) (Q1Q2Q3)*`.
    #[inline]
    pub fn fk(&self, q: &HakAngles<T>) -> LegPose<T> {
        LegPose::from_points(self.chain.forward(&q.to_array()))
    }

    /// Forward kinematics of many frames (the SIMD batch path): `out[i] = fk(q[i])` for `i`
    /// below the shorter length, which is returned.
    pub fn fk_batch(&self, q: &[HakAngles<T>], out: &mut [LegPose<T>]) -> usize
    where
        T: LaneScalar,
    {
        let n = q.len().min(out.len());
        self.chain.forward_batch(
            n,
            |i| q[i].to_array(),
            |i, p| out[i] = LegPose::from_points(p),
        );
        n
    }
}
