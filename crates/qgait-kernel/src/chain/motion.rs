//! [`Chain`]'s differential kinematics (see [`crate::differential`]): every joint frame's and
//! output point's velocity and acceleration from `q`, `q̇`, `q̈`, in one pass beside
//! [`Chain::frames`]' own.

use super::{AxisKind, Chain};
use crate::differential::{FrameMotion, PointMotion};
use crate::{Quat, Real, Vec3};

impl<T: Real, const N: usize, const J: usize, const P: usize, const S: usize> Chain<T, N, J, P, S> {
    /// Every joint frame's motion in ground ([`FrameMotion`]: orientation, origin, the
    /// origin's velocity and acceleration, angular velocity and acceleration, all in ground
    /// axes) for coordinates `q` (radians), speeds `qd` (rad/s) and accelerations `qdd`
    /// (rad/s²). The orientations and origins are [`frames`](Self::frames)'.
    #[inline]
    pub fn motions(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [FrameMotion<T>; J] {
        self.motions_inline::<true>(q, qd, qdd)
    }

    /// The output points' positions, velocities and accelerations in ground (ground axes,
    /// origin at the root joint's: the time derivatives of [`forward`](Self::forward)'s points)
    /// for coordinates `q`, speeds `qd` and accelerations `qdd`.
    #[inline]
    pub fn forward_motion(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [PointMotion<T>; P] {
        let frames = self.motions_inline::<true>(q, qd, qdd);
        core::array::from_fn(|i| self.point_motion(&frames, i))
    }

    /// The output points' positions and velocities in ground (as
    /// [`forward_motion`](Self::forward_motion), without the accelerations' work): `(positions,
    /// velocities)`.
    #[inline]
    pub fn forward_velocities(&self, q: &[T; N], qd: &[T; N]) -> ([Vec3<T>; P], [Vec3<T>; P]) {
        let frames = self.motions_inline::<false>(q, qd, qd);
        let mut positions = [Vec3::zero(); P];
        let mut velocities = [Vec3::zero(); P];
        for i in 0..P {
            let m = self.point_motion(&frames, i);
            positions[i] = m.position;
            velocities[i] = m.velocity;
        }
        (positions, velocities)
    }

    /// Point `i`'s motion on its joint's frame.
    #[inline(always)]
    fn point_motion(&self, frames: &[FrameMotion<T>; J], i: usize) -> PointMotion<T> {
        let p = &self.points[i];
        let f = &frames[p.body];
        if self.at_origin[i] {
            PointMotion {
                position: f.origin,
                velocity: f.velocity,
                acceleration: f.acceleration,
            }
        } else {
            f.point_at(self.point_kinds[i].rotate(f.rotation, p.offset))
        }
    }

    /// The frames' motions; with `ACC` false, the accelerations are not computed (left zero,
    /// `qdd` unread).
    #[inline(always)]
    fn motions_inline<const ACC: bool>(
        &self,
        q: &[T; N],
        qd: &[T; N],
        qdd: &[T; N],
    ) -> [FrameMotion<T>; J] {
        if J == 0 {
            return [FrameMotion::GROUND; J];
        }
        // The spline translations' values and first and second derivatives by their
        // coordinate, first (as `frames`: no calls in the joint loop).
        let mut slide = [(T::ZERO, T::ZERO, T::ZERO); S];
        for (value, s) in slide.iter_mut().zip(&self.splines) {
            *value = s.spline.eval_derivatives(q[s.coordinate]);
        }
        let mut frames = [self.joint_motion::<ACC>(0, &FrameMotion::GROUND, q, qd, qdd, &slide); J];
        for j in 1..J {
            let parent = frames[self.joints[j].parent.unwrap_or(0)];
            frames[j] = self.joint_motion::<ACC>(j, &parent, q, qd, qdd, &slide);
        }
        frames
    }

    /// Joint `j`'s motion given its parent's.
    #[inline(always)]
    fn joint_motion<const ACC: bool>(
        &self,
        j: usize,
        parent: &FrameMotion<T>,
        q: &[T; N],
        qd: &[T; N],
        qdd: &[T; N],
        slide: &[(T, T, T); S],
    ) -> FrameMotion<T> {
        let joint = &self.joints[j];
        let zero = Vec3::zero();
        // The offset in the parent's frame and its rates (the splines'), then in ground.
        let mut offset = joint.offset;
        let (mut rate, mut accel) = (zero, zero);
        if S > 0 {
            let (start, end) = self.spline_ranges[j];
            for k in start as usize..end as usize {
                let s = &self.splines[k];
                let (x, dx, ddx) = slide[k];
                let (u, du) = (qd[s.coordinate], qdd[s.coordinate]);
                offset += s.direction * x;
                rate += s.direction * (dx * u);
                if ACC {
                    accel += s.direction * (ddx * u * u + dx * du);
                }
            }
        }
        let r = self.offset_kinds[j].rotate(parent.rotation, offset);
        let w = parent.angular_velocity;
        let mut velocity = parent.velocity + w.cross(r);
        let mut acceleration = zero;
        if ACC {
            acceleration =
                parent.acceleration + parent.angular_acceleration.cross(r) + w.cross(w.cross(r));
        }
        if S > 0 && self.spline_ranges[j].0 != self.spline_ranges[j].1 {
            let rate = parent.rotation.rotate(rate);
            velocity += rate;
            if ACC {
                acceleration += w.cross(rate) * T::TWO + parent.rotation.rotate(accel);
            }
        }
        let mut rotation = parent.rotation;
        let mut omega = w;
        let mut alpha = parent.angular_acceleration;
        let one = T::ONE;
        for (axis, kind) in joint.axes[..joint.n_axes].iter().zip(&self.axis_kinds[j]) {
            let c = axis.coordinate;
            let (s, co) = q[c].half_angle_sin_cos();
            rotation = match kind {
                AxisKind::X => rotation.then_about_x(s, co),
                AxisKind::Y => rotation.then_about_y(s, co),
                AxisKind::Z => rotation.then_about_z(s, co),
                AxisKind::General => rotation * Quat::from_axis_half_sin_cos(axis.direction, s, co),
            };
            // The axis in ground (unmoved by its own rotation).
            let g = match kind {
                AxisKind::X => rotation.rotate_x(one),
                AxisKind::Y => rotation.rotate_y(one),
                AxisKind::Z => rotation.rotate_z(one),
                AxisKind::General => rotation.rotate(axis.direction),
            };
            if ACC {
                alpha += g * qdd[c] + omega.cross(g) * qd[c];
            }
            omega += g * qd[c];
        }
        FrameMotion {
            rotation,
            origin: parent.origin + r,
            velocity,
            acceleration,
            angular_velocity: omega,
            angular_acceleration: alpha,
        }
    }
}
