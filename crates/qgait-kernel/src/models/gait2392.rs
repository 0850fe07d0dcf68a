//! OpenSim's gait2392 lower-limb chain, exactly: pelvis, hips, spline knees, oblique ankles,
//! subtalar and MTP joints, toe tips. Geometry: `gait2392-geometry.md` (the generic model);
//! subject-scaled models change only the numbers in [`Gait2392Geometry`].

use super::{x, y, z};
use crate::chain::Description;
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

/// Knots of one spline (`x` in radians, `y` in metres), up to [`MAX_KNOTS`], in `f64` (the
/// default) or `f32` (a device's copy, see [`Gait2392::from_geometry`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knots<T = f64> {
    /// Number of knots used.
    pub n: usize,
    /// Abscissae (strictly increasing).
    pub x: [T; MAX_KNOTS],
    /// Values.
    pub y: [T; MAX_KNOTS],
}

impl<T: Real> Knots<T> {
    /// From slices of equal length (at most [`MAX_KNOTS`]; extra knots make [`Gait2392::new`]
    /// fail).
    pub fn new(x: &[T], y: &[T]) -> Self {
        let mut k = Self {
            n: x.len().min(y.len()),
            x: [T::ZERO; MAX_KNOTS],
            y: [T::ZERO; MAX_KNOTS],
        };
        if x.len() != y.len() || x.len() > MAX_KNOTS {
            k.n = MAX_KNOTS + 1;
            return k;
        }
        k.x[..x.len()].copy_from_slice(x);
        k.y[..y.len()].copy_from_slice(y);
        k
    }

    /// In another precision (rounding to nearest for `f32`).
    pub fn cast<U: Real>(&self) -> Knots<U> {
        Knots {
            n: self.n,
            x: self.x.map(|v| U::from_f64(v.to_f64())),
            y: self.y.map(|v| U::from_f64(v.to_f64())),
        }
    }

    /// The spline through these knots, its coefficients computed in `T`.
    fn spline(&self) -> Result<Spline<T>, ModelError> {
        match (self.x.get(..self.n), self.y.get(..self.n)) {
            (Some(x), Some(y)) => Spline::from_knots(x, y),
            _ => Err(ModelError::SplineKnots),
        }
    }
}

impl Knots<f64> {
    /// The knots of `x` and `y`, at compile time.
    const fn of<const N: usize>(x: &[f64; N], y: &[f64; N]) -> Self {
        let mut k = Knots {
            n: N,
            x: [0.0; MAX_KNOTS],
            y: [0.0; MAX_KNOTS],
        };
        let mut i = 0;
        while i < N {
            k.x[i] = x[i];
            k.y[i] = y[i];
            i += 1;
        }
        k
    }

    /// The spline through these knots, its coefficients computed in `f64` and rounded to `T`.
    fn spline_rounded<T: Real>(&self) -> Result<Spline<T>, ModelError> {
        match (self.x.get(..self.n), self.y.get(..self.n)) {
            (Some(x), Some(y)) => Spline::new(x, y),
            _ => Err(ModelError::SplineKnots),
        }
    }

    /// Rounded to `f32`, at compile time if wanted.
    pub const fn to_f32(&self) -> Knots<f32> {
        Knots {
            n: self.n,
            x: round(&self.x),
            y: round(&self.y),
        }
    }
}

/// `v` rounded to `f32`, element by element (a `const fn`).
const fn round<const N: usize>(v: &[f64; N]) -> [f32; N] {
    let mut out = [0.0; N];
    let mut i = 0;
    while i < N {
        out[i] = v[i] as f32;
        i += 1;
    }
    out
}

/// The numbers of one leg (metres, unit axes; frames and names as in OpenSim), in `f64` (the
/// default) or `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LegGeometry<T = f64> {
    /// Hip centre in the pelvis frame (`hip` joint `location_in_parent`).
    pub hip_in_pelvis: [T; 3],
    /// Hip flexion, adduction and rotation axes (body-fixed sequence).
    pub hip_axes: [[T; 3]; 3],
    /// Knee centre translation along the femur's x as a function of `knee_angle`.
    pub knee_tx: Knots<T>,
    /// Knee centre translation along the femur's y as a function of `knee_angle`.
    pub knee_ty: Knots<T>,
    /// Ankle centre in the tibia frame.
    pub ankle_in_tibia: [T; 3],
    /// Ankle axis.
    pub ankle_axis: [T; 3],
    /// Subtalar centre in the talus frame.
    pub subtalar_in_talus: [T; 3],
    /// Subtalar axis.
    pub subtalar_axis: [T; 3],
    /// MTP centre in the calcaneus frame.
    pub mtp_in_calcn: [T; 3],
    /// MTP axis.
    pub mtp_axis: [T; 3],
    /// Toe tip (the gait2392 marker set's `Toe.Tip`) in the toes frame.
    pub toetip_in_toes: [T; 3],
}

/// The numbers of the whole chain: one leg each side (a scaled subject may differ per side), in
/// `f64` (the default) or `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gait2392Geometry<T = f64> {
    /// Right leg.
    pub right: LegGeometry<T>,
    /// Left leg.
    pub left: LegGeometry<T>,
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

impl LegGeometry<f64> {
    /// The generic gait2392 right leg, with every number as written in `gait2392_simbody.osim`
    /// (the axes to 8 digits; `gait2392-geometry.md` rounds them to 6).
    pub const fn generic_right() -> Self {
        Self {
            hip_in_pelvis: [-0.0707, -0.0661, 0.0835],
            hip_axes: [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            knee_tx: Knots::of(&KNEE_TX_X, &KNEE_TX_Y),
            knee_ty: Knots::of(&KNEE_TY_X, &KNEE_TY_Y),
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
    /// axial vectors `(-x, -y, z)`, at compile time. `generic_right().mirrored()` is gait2392's
    /// left leg.
    pub const fn mirrored(&self) -> Self {
        const fn p(v: [f64; 3]) -> [f64; 3] {
            [v[0], v[1], -v[2]]
        }
        const fn a(v: [f64; 3]) -> [f64; 3] {
            [-v[0], -v[1], v[2]]
        }
        Self {
            hip_in_pelvis: p(self.hip_in_pelvis),
            hip_axes: [
                a(self.hip_axes[0]),
                a(self.hip_axes[1]),
                a(self.hip_axes[2]),
            ],
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

    /// Rounded to `f32`, at compile time if wanted.
    pub const fn to_f32(&self) -> LegGeometry<f32> {
        let h = &self.hip_axes;
        LegGeometry {
            hip_in_pelvis: round(&self.hip_in_pelvis),
            hip_axes: [round(&h[0]), round(&h[1]), round(&h[2])],
            knee_tx: self.knee_tx.to_f32(),
            knee_ty: self.knee_ty.to_f32(),
            ankle_in_tibia: round(&self.ankle_in_tibia),
            ankle_axis: round(&self.ankle_axis),
            subtalar_in_talus: round(&self.subtalar_in_talus),
            subtalar_axis: round(&self.subtalar_axis),
            mtp_in_calcn: round(&self.mtp_in_calcn),
            mtp_axis: round(&self.mtp_axis),
            toetip_in_toes: round(&self.toetip_in_toes),
        }
    }
}

impl<T: Real> LegGeometry<T> {
    /// In another precision (rounding to nearest for `f32`).
    pub fn cast<U: Real>(&self) -> LegGeometry<U> {
        let v = |a: [T; 3]| a.map(|c| U::from_f64(c.to_f64()));
        LegGeometry {
            hip_in_pelvis: v(self.hip_in_pelvis),
            hip_axes: self.hip_axes.map(v),
            knee_tx: self.knee_tx.cast(),
            knee_ty: self.knee_ty.cast(),
            ankle_in_tibia: v(self.ankle_in_tibia),
            ankle_axis: v(self.ankle_axis),
            subtalar_in_talus: v(self.subtalar_in_talus),
            subtalar_axis: v(self.subtalar_axis),
            mtp_in_calcn: v(self.mtp_in_calcn),
            mtp_axis: v(self.mtp_axis),
            toetip_in_toes: v(self.toetip_in_toes),
        }
    }
}

impl Gait2392Geometry<f64> {
    /// The generic, unscaled gait2392 (1.8 m, 75 kg).
    pub const fn generic() -> Self {
        let right = LegGeometry::generic_right();
        Self {
            right,
            left: right.mirrored(),
        }
    }

    /// Rounded to `f32`, at compile time if wanted: `Gait2392Geometry::generic().to_f32()` in a
    /// `const` is the generic model as data, with no `f64` arithmetic on a device.
    pub const fn to_f32(&self) -> Gait2392Geometry<f32> {
        Gait2392Geometry {
            right: self.right.to_f32(),
            left: self.left.to_f32(),
        }
    }
}

impl<T: Real> Gait2392Geometry<T> {
    /// One leg.
    pub fn leg(&self, side: Side) -> &LegGeometry<T> {
        match side {
            Side::Right => &self.right,
            Side::Left => &self.left,
        }
    }

    /// In another precision (rounding to nearest for `f32`).
    pub fn cast<U: Real>(&self) -> Gait2392Geometry<U> {
        Gait2392Geometry {
            right: self.right.cast(),
            left: self.left.cast(),
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

/// gait2392's chain for a geometry, piece by piece: the pelvis (tilt about +z, list about +x,
/// rotation about +y), then per side (right first) hip, knee, ankle, subtalar and MTP, each
/// hanging from the one before (the hips from the pelvis); points: per side the five joint
/// centres and the toe tip; the knee centre slides along the femur's x and y by splines of
/// `knee_angle`.
struct Gait2392Description<'a, T> {
    g: &'a Gait2392Geometry<T>,
    /// The numbers in `f64` when the knee splines are computed in `f64` and rounded to `T`
    /// ([`Gait2392::new`]); `None` computes them in `T`.
    knees_in_f64: Option<&'a Gait2392Geometry<f64>>,
}

/// Index of a side's first point (its hip centre) in the output.
fn side_base(side: Side) -> usize {
    match side {
        Side::Right => 0,
        Side::Left => 6,
    }
}

/// Index of a side's hip joint (its leg's first joint) and of its hip flexion coordinate.
fn leg_start(side: Side) -> (usize, usize) {
    match side {
        Side::Right => (1, 3),
        Side::Left => (6, 10),
    }
}

impl<T: Real> Description<T> for Gait2392Description<'_, T> {
    fn joint(&self, j: usize) -> JointSpec<T> {
        if j == 0 {
            return JointSpec::new(None, Vec3::zero(), &[(z(), 0), (x(), 1), (y(), 2)]);
        }
        let side = if j < leg_start(Side::Left).0 {
            Side::Right
        } else {
            Side::Left
        };
        let (first, coord) = leg_start(side);
        let l = self.g.leg(side);
        let v = |a: [T; 3]| Vec3::new(a[0], a[1], a[2]);
        match j - first {
            0 => {
                let [a1, a2, a3] = l.hip_axes.map(v);
                JointSpec::new(
                    Some(0),
                    v(l.hip_in_pelvis),
                    &[(a1, coord), (a2, coord + 1), (a3, coord + 2)],
                )
            }
            // The knee's centre moves by its splines only.
            1 => JointSpec::new(Some(j - 1), Vec3::zero(), &[(z(), coord + 3)]),
            2 => JointSpec::new(
                Some(j - 1),
                v(l.ankle_in_tibia),
                &[(v(l.ankle_axis), coord + 4)],
            ),
            3 => JointSpec::new(
                Some(j - 1),
                v(l.subtalar_in_talus),
                &[(v(l.subtalar_axis), coord + 5)],
            ),
            _ => JointSpec::new(
                Some(j - 1),
                v(l.mtp_in_calcn),
                &[(v(l.mtp_axis), coord + 6)],
            ),
        }
    }

    fn point(&self, i: usize) -> PointSpec<T> {
        let side = if i < side_base(Side::Left) {
            Side::Right
        } else {
            Side::Left
        };
        let k = i - side_base(side);
        let l = self.g.leg(side);
        PointSpec {
            // The five joint centres, then the toe tip on the MTP joint's frame (the toes).
            body: leg_start(side).0 + k.min(4),
            offset: if k == 5 {
                Vec3::new(
                    l.toetip_in_toes[0],
                    l.toetip_in_toes[1],
                    l.toetip_in_toes[2],
                )
            } else {
                Vec3::zero()
            },
        }
    }

    fn spline(&self, s: usize) -> Result<SplineTranslation<T>, ModelError> {
        // [right tx, right ty, left tx, left ty]: the knee (the joint after the hip) along the
        // femur's x, then y, driven by the knee angle.
        let side = if s < 2 { Side::Right } else { Side::Left };
        let (first, coord) = leg_start(side);
        let along_y = s % 2 == 1;
        let spline = match self.knees_in_f64 {
            Some(g) => {
                let l = g.leg(side);
                (if along_y { &l.knee_ty } else { &l.knee_tx }).spline_rounded()?
            }
            None => {
                let l = self.g.leg(side);
                (if along_y { &l.knee_ty } else { &l.knee_tx }).spline()?
            }
        };
        Ok(SplineTranslation {
            joint: first + 1,
            direction: if along_y { y() } else { x() },
            coordinate: coord + 3,
            spline,
        })
    }
}

/// gait2392's leg chain. Inputs: the 17 [`COORDINATES`] (radians); pelvis translation is not an
/// input (origin at the pelvis origin, ground axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gait2392<T> {
    chain: Gait2392Chain<T>,
}

impl<T: Real> Gait2392<T> {
    /// gait2392 with nothing set ([`Chain::EMPTY`]): a slot to [`rebuild`](Self::rebuild).
    pub const EMPTY: Self = Self {
        chain: Chain::EMPTY,
    };

    /// The chain for these numbers. The knee splines' coefficients are computed in `f64` and
    /// rounded to `T`.
    pub fn new(g: &Gait2392Geometry) -> Result<Self, ModelError> {
        let mut model = Self::EMPTY;
        let in_t = g.cast();
        model.chain.rebuild(&Gait2392Description {
            g: &in_t,
            knees_in_f64: Some(g),
        })?;
        Ok(model)
    }

    /// The chain for these numbers given in `T`, everything computed in `T`: for `f32`, no
    /// double-precision arithmetic at all (what a device with a single-precision FPU wants;
    /// its knee splines differ from [`new`](Self::new)'s by a few `f32` ulps).
    pub fn from_geometry(g: &Gait2392Geometry<T>) -> Result<Self, ModelError> {
        let mut model = Self::EMPTY;
        model.rebuild(g)?;
        Ok(model)
    }

    /// Whether [`from_geometry`](Self::from_geometry) or [`rebuild`](Self::rebuild) accept these
    /// numbers, without building anything.
    pub fn check(g: &Gait2392Geometry<T>) -> Result<(), ModelError> {
        Gait2392Chain::check(&Gait2392Description {
            g,
            knees_in_f64: None,
        })
    }

    /// This model rebuilt in place as [`from_geometry`](Self::from_geometry) builds it (little
    /// stack: see [`Chain::rebuild`]); unchanged on an error.
    pub fn rebuild(&mut self, g: &Gait2392Geometry<T>) -> Result<(), ModelError> {
        self.chain.rebuild(&Gait2392Description {
            g,
            knees_in_f64: None,
        })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gait2392s_knee_flexes_with_negative_angles() {
        use crate::models::ranges::KneeFlexion;
        let g = Gait2392::<f64>::new(&Gait2392Geometry::generic()).unwrap();
        assert_eq!(
            KneeFlexion::of(|q| g.chain().forward(q)),
            KneeFlexion::Negative
        );
        let g = Gait2392::<f32>::new(&Gait2392Geometry::generic()).unwrap();
        assert_eq!(
            KneeFlexion::of(|q| g.chain().forward(q)),
            KneeFlexion::Negative
        );
    }

    #[test]
    fn const_f32_geometry_is_the_generic_one_rounded() {
        const G32: Gait2392Geometry<f32> = Gait2392Geometry::generic().to_f32();
        let g = Gait2392Geometry::generic();
        assert_eq!(G32, g.cast::<f32>());
        assert_eq!(g.left, g.right.mirrored());
        assert_eq!(G32.left, g.right.mirrored().to_f32());
        assert_eq!(g.cast::<f32>().cast::<f64>().cast::<f32>(), G32);
    }

    #[test]
    fn from_geometry_is_new_in_f64_and_close_to_it_in_f32() {
        let g = Gait2392Geometry::generic();
        let exact = Gait2392::<f64>::new(&g).unwrap();
        assert_eq!(Gait2392::<f64>::from_geometry(&g).unwrap(), exact);
        let rounded = Gait2392::<f32>::new(&g).unwrap();
        let in_f32 = Gait2392::<f32>::from_geometry(&g.to_f32()).unwrap();
        let mut q = [0.0f32; 17];
        for step in 0..200 {
            for (i, a) in q.iter_mut().enumerate() {
                *a = (0.37 * (step * 17 + i) as f32).sin() * 1.9;
            }
            let want = exact.fk(&q.map(f64::from));
            for (k, (a, b)) in in_f32
                .fk(&q)
                .points
                .iter()
                .zip(rounded.fk(&q).points)
                .enumerate()
            {
                for (c, (x, y)) in a.to_array().iter().zip(b.to_array()).enumerate() {
                    let w = want.points[k].to_array()[c];
                    // Both f32 models are within a micrometre of f64, and of each other.
                    assert!((f64::from(*x) - w).abs() < 1e-6 && (f64::from(y) - w).abs() < 1e-6);
                }
            }
        }
        let mut bad = g.to_f32();
        bad.left.knee_ty.x.swap(1, 2);
        assert_eq!(
            Gait2392::<f32>::from_geometry(&bad).unwrap_err(),
            ModelError::SplineKnots
        );
        bad.left.knee_ty.n = MAX_KNOTS + 1;
        assert!(Gait2392::<f32>::from_geometry(&bad).is_err());
    }
}
