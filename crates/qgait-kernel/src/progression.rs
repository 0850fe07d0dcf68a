//! Directions in the transverse (horizontal) plane, for gait analysis in cartesian space: the
//! direction the pelvis faces, a heading angle, and the foot progression angle of the foot's
//! long axis against the direction of progression. Axes as everywhere in qgait: x forward,
//! y up, z right; angles about the vertical are positive turning x toward -z (a right-handed
//! rotation about +y, as gait2392's `pelvis_rotation`).

use crate::imu::math::atan2;
use crate::{Real, Side, Vec3};

/// The horizontal unit vector the pelvis faces, from its hip centres: perpendicular to the
/// hip-to-hip line (right minus left) in the horizontal plane, `up × (right - left)` (with the
/// right hip on +z this is +x). `None` when the hip line is vertical or the hips coincide.
pub fn pelvis_forward<T: Real>(hip_right: Vec3<T>, hip_left: Vec3<T>) -> Option<Vec3<T>> {
    let across = hip_right - hip_left;
    // up × across = (across.z, 0, -across.x) for up = +y.
    horizontal_unit(Vec3::new(across.z, T::ZERO, -across.x))
}

/// The horizontal projection of `v` scaled to unit length; `None` if `v` is (nearly) vertical.
pub fn horizontal_unit<T: Real>(v: Vec3<T>) -> Option<Vec3<T>> {
    let h = Vec3::new(v.x, T::ZERO, v.z);
    let n = h.norm();
    if !n.is_finite() || n <= T::from_f64(1e-9) {
        return None;
    }
    Some(Vec3::new(h.x / n, T::ZERO, h.z / n))
}

/// The heading of a direction: the angle (radians, `(-pi, pi]`) about the vertical from +x to
/// the horizontal projection of `v` (positive turning x toward -z, as `pelvis_rotation`).
pub fn heading<T: Real>(v: Vec3<T>) -> T {
    atan2(-v.z, v.x)
}

/// The signed angle (radians) about the vertical from the horizontal projection of `from` to
/// that of `to` (positive turning x toward -z).
pub fn angle_about_vertical<T: Real>(from: Vec3<T>, to: Vec3<T>) -> T {
    // (from × to) · up and from · to, both horizontal projections.
    let cross = from.z * to.x - from.x * to.z;
    let dot = from.x * to.x + from.z * to.z;
    atan2(cross, dot)
}

/// The foot progression angle (radians) of one side, in the Conventional Gait Model's sign:
/// the foot's long axis (`rearfoot` to `forefoot`, e.g. the ankle centre to the MTP joint)
/// projected on the horizontal plane, against the direction of progression `forward`;
/// positive when the toes point toward the midline (in-toeing, internal), negative when they
/// point outward (out-toeing, external), on both sides.
pub fn foot_progression<T: Real>(
    side: Side,
    rearfoot: Vec3<T>,
    forefoot: Vec3<T>,
    forward: Vec3<T>,
) -> T {
    // About +y, toes turned toward +z (outward for the right foot) is negative.
    angle_about_vertical(forward, forefoot - rearfoot) * side.sign::<T>()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn pelvis_faces_forward_and_turns_with_the_hips() {
        let f = pelvis_forward(Vec3::new(0.0, 0.1, 0.08), Vec3::new(0.0, 0.1, -0.08)).unwrap();
        assert!(close(f.x, 1.0) && close(f.z, 0.0), "{f:?}");
        // Turned 30 degrees about +y: the right hip goes forward (x toward -z is positive).
        let a: f64 = 30f64.to_radians();
        let r = Vec3::new(0.08 * a.sin(), 0.0, 0.08 * a.cos());
        let f = pelvis_forward(r, -r).unwrap();
        assert!(close(heading(f), a), "{}", heading(f).to_degrees());
        // A listed pelvis (right hip lower) still faces forward.
        let f = pelvis_forward(Vec3::new(0.0, -0.02, 0.08), Vec3::new(0.0, 0.02, -0.08)).unwrap();
        assert!(close(f.x, 1.0), "{f:?}");
        assert!(pelvis_forward(Vec3::new(0.0, 1.0, 0.0), Vec3::zero()).is_none());
    }

    #[test]
    fn foot_progression_is_negative_out_toeing_on_both_sides() {
        let fwd = Vec3::new(1.0, 0.0, 0.0);
        let a: f64 = 10f64.to_radians();
        // Right foot toes toward +z (outward), left foot toes toward -z (outward).
        let right = Vec3::new(a.cos(), -0.05, a.sin());
        let left = Vec3::new(a.cos(), 0.02, -a.sin());
        let fp_r = foot_progression(Side::Right, Vec3::zero(), right, fwd);
        let fp_l = foot_progression(Side::Left, Vec3::zero(), left, fwd);
        assert!(close(fp_r, -a) && close(fp_l, -a), "{fp_r} {fp_l}");
        // In-toeing is positive; the progression direction itself may be any heading.
        let turn: f64 = 2.0;
        let rot = |v: Vec3<f64>| {
            Vec3::new(
                v.x * turn.cos() + v.z * turn.sin(),
                v.y,
                -v.x * turn.sin() + v.z * turn.cos(),
            )
        };
        let fp = foot_progression(Side::Right, Vec3::zero(), rot(left), rot(fwd));
        assert!(close(fp, a), "{fp}");
        assert!(close(heading(rot(fwd)), turn));
    }
}
