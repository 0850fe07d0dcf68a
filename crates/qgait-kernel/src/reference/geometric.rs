use crate::{HakAngles, LegPose, Limb, Real, Vec3};

/// HAK in closed form (Eqs 1-3): with `q12 = q1 + q2`, `q123 = q12 + q3`,
/// `knee = (l1 sin q1, -l1 cos q1)`, `ankle = knee + (l2 sin q12, -l2 cos q12)`,
/// `toe = ankle + (l3 cos q123, l3 sin q123)`, all with z = 0.
pub fn hak_geometric<T: Real>(limb: &Limb<T>, q: &HakAngles<T>) -> LegPose<T> {
    let (s1, c1) = q.hip_flexion.sin_cos();
    let q12 = q.hip_flexion + q.knee_angle;
    let (s12, c12) = q12.sin_cos();
    let (s123, c123) = (q12 + q.ankle_angle).sin_cos();
    let zero = T::ZERO;
    let knee = Vec3::new(limb.femur * s1, -limb.femur * c1, zero);
    let ankle = knee + Vec3::new(limb.tibia * s12, -limb.tibia * c12, zero);
    let toe = ankle + Vec3::new(limb.foot * c123, limb.foot * s123, zero);
    LegPose {
        hip: Vec3::zero(),
        knee,
        ankle,
        toe,
    }
}
