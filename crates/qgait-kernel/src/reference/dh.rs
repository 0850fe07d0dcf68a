use nalgebra::{Matrix4, RealField};

use crate::{HakAngles, LegPose, Limb, Real, Vec3};

/// The Denavit-Hartenberg transform of one link (Eq 4):
/// `Rot_z(theta) Trans_z(d) Trans_x(a) Rot_x(alpha)`.
pub fn dh_transform<T: Real + RealField>(theta: T, d: T, a: T, alpha: T) -> Matrix4<T> {
    let (st, ct) = Real::sin_cos(theta);
    let (sa, ca) = Real::sin_cos(alpha);
    let (o, i) = (T::ZERO, T::ONE);
    #[rustfmt::skip]
    let m = Matrix4::new(
        ct, -st * ca,  st * sa, a * ct,
        st,  ct * ca, -ct * sa, a * st,
        o,   sa,       ca,      d,
        o,   o,        o,       i,
    );
    m
}

/// HAK by the DH table (Table 2): link i has `d = 0`, `a = l_i`, `alpha = 0` and
/// `theta_1 = q1 - pi/2`, `theta_2 = q2`, `theta_3 = q3 + pi/2`. The knee, ankle and toe are
/// the origins of `H1`, `H1 H2` and `H1 H2 H3`.
pub fn hak_denavit_hartenberg<T: Real + RealField>(limb: &Limb<T>, q: &HakAngles<T>) -> LegPose<T> {
    let half_pi = <T as Real>::from_f64(core::f64::consts::FRAC_PI_2);
    let o = T::ZERO;
    let h1 = dh_transform(q.hip_flexion - half_pi, o, limb.femur, o);
    let h12 = h1 * dh_transform(q.knee_angle, o, limb.tibia, o);
    let h123 = h12 * dh_transform(q.ankle_angle + half_pi, o, limb.foot, o);
    let origin = |m: &Matrix4<T>| Vec3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]);
    LegPose {
        hip: Vec3::zero(),
        knee: origin(&h1),
        ankle: origin(&h12),
        toe: origin(&h123),
    }
}
