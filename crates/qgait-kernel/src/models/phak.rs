//! PHAK: the paper's 8-DoF bilateral pelvis-hip-knee-ankle chain (Figure 3, Eqs 16-17).

use super::{x, y, z};
use crate::chain::Description;
use crate::lanes::LaneScalar;
use crate::{
    Anthropometry, BilateralPose, Chain, JointSpec, ModelError, PointSpec, Real, Side,
    SplineTranslation, Vec3,
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
    /// These angles with a level, forward-facing pelvis (`pelvis_rotation` and `pelvis_list`
    /// 0): HAK's input to PHAK ([`Phak::fk_hak`]).
    pub fn level_pelvis(self) -> Self {
        Self {
            pelvis_rotation: T::ZERO,
            pelvis_list: T::ZERO,
            ..self
        }
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

/// PHAK's chain for a subject's lengths, joint by joint: the pelvis (rotation about +y, then
/// list about +x), then per side (right first) hip, knee and ankle flexion about +z; points: hip,
/// knee, ankle and toe of each side.
struct PhakDescription<'a, T> {
    a: &'a Anthropometry<T>,
}

impl<T: Real> Description<T> for PhakDescription<'_, T> {
    fn joint(&self, j: usize) -> JointSpec<T> {
        let zero = T::ZERO;
        if j == 0 {
            return JointSpec::new(None, Vec3::zero(), &[(y(), 0), (x(), 1)]);
        }
        // Joints 1-3 the right hip, knee and ankle, 4-6 the left ones.
        let (side, k) = if j <= 3 {
            (Side::Right, j - 1)
        } else {
            (Side::Left, j - 4)
        };
        let limb = self.a.limb(side);
        let first = 1 + 3 * side as usize;
        let offset = match k {
            0 => Vec3::new(zero, zero, side.sign::<T>() * limb.pelvis_half_width),
            1 => Vec3::new(zero, -limb.femur, zero),
            _ => Vec3::new(zero, -limb.tibia, zero),
        };
        let parent = if k == 0 { 0 } else { j - 1 };
        JointSpec::new(Some(parent), offset, &[(z(), first + 1 + k)])
    }

    fn point(&self, i: usize) -> PointSpec<T> {
        // Points 0-3 the right hip, knee, ankle and toe, 4-7 the left ones.
        let (side, k) = if i < 4 {
            (Side::Right, i)
        } else {
            (Side::Left, i - 4)
        };
        let first = 1 + 3 * side as usize;
        PointSpec {
            body: first + k.min(2),
            offset: if k == 3 {
                x::<T>() * self.a.limb(side).foot
            } else {
                Vec3::zero()
            },
        }
    }

    fn spline(&self, s: usize) -> Result<SplineTranslation<T>, ModelError> {
        // PHAK has no spline translations (`S` = 0): never asked.
        Err(ModelError::BodyOutOfRange { index: s })
    }
}

impl<T: Real> Phak<T> {
    /// PHAK with nothing set ([`Chain::EMPTY`]): a slot to [`rebuild`](Self::rebuild).
    pub const EMPTY: Self = Self {
        chain: Chain::EMPTY,
    };

    /// PHAK with these lengths.
    pub fn new(a: &Anthropometry<T>) -> Result<Self, ModelError> {
        let mut phak = Self::EMPTY;
        phak.rebuild(a)?;
        Ok(phak)
    }

    /// Whether [`new`](Self::new) or [`rebuild`](Self::rebuild) accept these lengths, without
    /// building anything.
    pub fn check(a: &Anthropometry<T>) -> Result<(), ModelError> {
        a.right.validate()?;
        a.left.validate()?;
        PhakChain::check(&PhakDescription { a })
    }

    /// This PHAK rebuilt in place with these lengths (little stack: see [`Chain::rebuild`]);
    /// unchanged on an error.
    pub fn rebuild(&mut self, a: &Anthropometry<T>) -> Result<(), ModelError> {
        a.right.validate()?;
        a.left.validate()?;
        self.chain.rebuild(&PhakDescription { a })
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

    /// HAK's pose of both legs: PHAK with a level, forward-facing pelvis (`q`'s pelvis angles
    /// are ignored, as 0). This is what "HAK" means for both legs everywhere (host, hub, wire):
    /// the hips at ±`pelvis_half_width` on the z axis, the origin midway between them, so HAK
    /// and PHAK poses are in the same frame; each leg is [`Hak`](super::Hak)'s chain moved to
    /// its hip.
    #[inline]
    pub fn fk_hak(&self, q: &PhakAngles<T>) -> BilateralPose<T> {
        self.fk(&q.level_pelvis())
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
