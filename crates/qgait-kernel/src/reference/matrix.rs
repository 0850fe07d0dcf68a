use nalgebra::{Matrix4, RealField};

use crate::{Anthropometry, BilateralPose, Chain, LegPose, PhakAngles, Real, Side, Vec3};

/// Homogeneous rotation by `angle` about the unit `axis` (Rodrigues).
fn rotation<T: Real + RealField>(axis: Vec3<T>, angle: T) -> Matrix4<T> {
    let (s, c) = Real::sin_cos(angle);
    let t = T::ONE - c;
    let (x, y, z) = (axis.x, axis.y, axis.z);
    let (o, i) = (T::ZERO, T::ONE);
    #[rustfmt::skip]
    let m = Matrix4::new(
        c + x * x * t,     x * y * t - z * s, x * z * t + y * s, o,
        y * x * t + z * s, c + y * y * t,     y * z * t - x * s, o,
        z * x * t - y * s, z * y * t + x * s, c + z * z * t,     o,
        o,                 o,                 o,                 i,
    );
    m
}

/// Homogeneous translation by `v`.
fn translation<T: Real + RealField>(v: Vec3<T>) -> Matrix4<T> {
    let mut m = Matrix4::identity();
    m[(0, 3)] = v.x;
    m[(1, 3)] = v.y;
    m[(2, 3)] = v.z;
    m
}

fn apply<T: Real + RealField>(m: &Matrix4<T>, p: Vec3<T>) -> Vec3<T> {
    Vec3::new(
        m[(0, 0)] * p.x + m[(0, 1)] * p.y + m[(0, 2)] * p.z + m[(0, 3)],
        m[(1, 0)] * p.x + m[(1, 1)] * p.y + m[(1, 2)] * p.z + m[(1, 3)],
        m[(2, 0)] * p.x + m[(2, 1)] * p.y + m[(2, 2)] * p.z + m[(2, 3)],
    )
}

/// PHAK by homogeneous transforms, written out independently of the chain tables:
/// `T_pelvis = R_y(rotation) R_x(list)`, then per side `Trans(0, 0, s w) R_z(hip)`,
/// `Trans(0, -femur, 0) R_z(knee)`, `Trans(0, -tibia, 0) R_z(ankle)`, toe at `(foot, 0, 0)`.
pub fn phak_homogeneous<T: Real + RealField>(
    a: &Anthropometry<T>,
    q: &PhakAngles<T>,
) -> BilateralPose<T> {
    let (x, y, z) = (Vec3::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    let o = T::ZERO;
    let pelvis = rotation(y, q.pelvis_rotation) * rotation(x, q.pelvis_list);
    let leg = |side: Side, hip: T, knee: T, ankle: T| {
        let l = a.limb(side);
        let t_hip = pelvis
            * translation(Vec3::new(o, o, side.sign::<T>() * l.pelvis_half_width))
            * rotation(z, hip);
        let t_knee = t_hip * translation(Vec3::new(o, -l.femur, o)) * rotation(z, knee);
        let t_ankle = t_knee * translation(Vec3::new(o, -l.tibia, o)) * rotation(z, ankle);
        LegPose {
            hip: apply(&t_hip, Vec3::zero()),
            knee: apply(&t_knee, Vec3::zero()),
            ankle: apply(&t_ankle, Vec3::zero()),
            toe: apply(&t_ankle, Vec3::new(l.foot, o, o)),
        }
    };
    BilateralPose {
        right: leg(
            Side::Right,
            q.hip_flexion_r,
            q.knee_angle_r,
            q.ankle_angle_r,
        ),
        left: leg(Side::Left, q.hip_flexion_l, q.knee_angle_l, q.ankle_angle_l),
    }
}

/// Any chain evaluated with 4x4 homogeneous matrices: per joint
/// `T_j = T_parent Trans(offset + splines) R(axis_1, q) R(axis_2, q) ...`. Same table, other
/// algebra: the matrix method of the paper's cost comparison.
pub fn chain_by_matrices<
    T: Real + RealField,
    const N: usize,
    const J: usize,
    const P: usize,
    const S: usize,
>(
    chain: &Chain<T, N, J, P, S>,
    q: &[T; N],
) -> [Vec3<T>; P] {
    let mut frames = [Matrix4::<T>::identity(); J];
    for (j, joint) in chain.joints().iter().enumerate() {
        let parent = match joint.parent {
            Some(p) => frames[p],
            None => Matrix4::identity(),
        };
        let mut m = parent * translation(chain.offset(j, q));
        for axis in &joint.axes[..joint.n_axes] {
            m *= rotation(axis.direction, q[axis.coordinate]);
        }
        frames[j] = m;
    }
    chain.points().map(|p| apply(&frames[p.body], p.offset))
}
