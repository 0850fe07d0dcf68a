//! [`Chain`]'s differential kinematics (see [`crate::differential`]): every joint frame's and
//! output point's velocity and acceleration from `q`, `q̇`, `q̈`, in one pass beside
//! [`Chain::frames`]' own.

use super::{AxisKind, Chain};
use crate::differential::{Carried, FrameMotion, PointMotion, Twist};
use crate::{Quat, Real, Vec3};

impl<T: Real, const N: usize, const J: usize, const P: usize, const S: usize> Chain<T, N, J, P, S> {
    /// Every joint frame's motion in ground ([`FrameMotion`]: orientation, origin, the
    /// origin's velocity and acceleration, angular velocity and acceleration, all in ground
    /// axes) for coordinates `q` (radians), speeds `qd` (rad/s) and accelerations `qdd`
    /// (rad/s²). The orientations and origins are [`frames`](Self::frames)'.
    #[inline]
    pub fn motions(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [FrameMotion<T>; J] {
        self.carried(q, qd, qdd)
    }

    /// The output points' positions, velocities and accelerations in ground (ground axes,
    /// origin at the root joint's: the time derivatives of [`forward`](Self::forward)'s points)
    /// for coordinates `q`, speeds `qd` and accelerations `qdd`.
    #[inline]
    pub fn forward_motion(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [PointMotion<T>; P] {
        let frames: [FrameMotion<T>; J] = self.carried(q, qd, qdd);
        let mut out = [PointMotion::default(); P];
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.point_motion(&frames, i);
        }
        out
    }

    /// The output points' positions and velocities in ground (as
    /// [`forward_motion`](Self::forward_motion), the accelerations neither computed nor
    /// carried): `(positions, velocities)`.
    #[inline]
    pub fn forward_velocities(&self, q: &[T; N], qd: &[T; N]) -> ([Vec3<T>; P], [Vec3<T>; P]) {
        let frames: [Twist<T>; J] = self.carried(q, qd, qd);
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
    fn point_motion<K: Carried<T>>(&self, frames: &[K; J], i: usize) -> PointMotion<T> {
        let p = &self.points[i];
        let f = &frames[p.body];
        if self.at_origin[i] {
            f.origin_motion()
        } else {
            f.point_at(self.point_kinds[i].rotate(f.twist().rotation, p.offset))
        }
    }

    /// The frames' motions, with their accelerations if `K` carries them (`qdd` unread
    /// otherwise).
    #[inline(always)]
    fn carried<K: Carried<T>>(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [K; J] {
        if J == 0 {
            return [K::GROUND; J];
        }
        // The spline translations' values and first and second derivatives by their
        // coordinate, first (as `frames`: no calls in the joint loop).
        let mut slide = [(T::ZERO, T::ZERO, T::ZERO); S];
        for (value, s) in slide.iter_mut().zip(&self.splines) {
            *value = s.spline.eval_derivatives(q[s.coordinate]);
        }
        let mut frames = [self.joint_motion(0, &K::GROUND, q, qd, qdd, &slide); J];
        for j in 1..J {
            // (A copy of the parent's frame: fewer instructions than a reference into the
            // array being written, PHAK's velocities 2,182 against 2,519.)
            let parent = frames[self.joints[j].parent.unwrap_or(0)];
            frames[j] = self.joint_motion(j, &parent, q, qd, qdd, &slide);
        }
        frames
    }

    /// Joint `j`'s motion given its parent's.
    #[inline(always)]
    fn joint_motion<K: Carried<T>>(
        &self,
        j: usize,
        parent: &K,
        q: &[T; N],
        qd: &[T; N],
        qdd: &[T; N],
        slide: &[(T, T, T); S],
    ) -> K {
        let joint = &self.joints[j];
        let zero = Vec3::zero();
        let Twist {
            rotation: parent_rotation,
            origin: parent_origin,
            velocity: parent_velocity,
            angular_velocity: w,
        } = parent.twist();
        let (parent_acceleration, parent_alpha) = parent.accelerations();
        // The offset in the parent's frame and its rates (the splines'), then in ground.
        let mut offset = joint.offset;
        let (mut rate, mut accel) = (zero, zero);
        if S > 0 {
            let (start, end) = self.spline_ranges[j];
            #[allow(clippy::needless_range_loop)] // (28 instructions fewer than zipped slices)
            for k in start as usize..end as usize {
                let s = &self.splines[k];
                let (x, dx, ddx) = slide[k];
                let (u, du) = (qd[s.coordinate], qdd[s.coordinate]);
                offset += s.direction * x;
                rate += s.direction * (dx * u);
                if K::ACC {
                    accel += s.direction * (ddx * u * u + dx * du);
                }
            }
        }
        let r = self.offset_kinds[j].rotate(parent_rotation, offset);
        let mut velocity = parent_velocity + w.cross(r);
        let mut acceleration = zero;
        if K::ACC {
            acceleration = parent_acceleration + parent_alpha.cross(r) + w.cross(w.cross(r));
        }
        if S > 0 && self.spline_ranges[j].0 != self.spline_ranges[j].1 {
            let rate = parent_rotation.rotate(rate);
            velocity += rate;
            if K::ACC {
                acceleration += w.cross(rate) * T::TWO + parent_rotation.rotate(accel);
            }
        }
        let mut rotation = parent_rotation;
        let mut omega = w;
        let mut alpha = parent_alpha;
        let one = T::ONE;
        for (axis, kind) in joint.axes[..joint.n_axes].iter().zip(&self.axis_kinds[j]) {
            let c = axis.coordinate;
            let (s, co) = q[c].half_angle_sin_cos();
            // The axis in ground (unmoved by its own rotation).
            let g = match kind {
                AxisKind::X => {
                    rotation = rotation.then_about_x(s, co);
                    rotation.rotate_x(one)
                }
                AxisKind::Y => {
                    rotation = rotation.then_about_y(s, co);
                    rotation.rotate_y(one)
                }
                AxisKind::Z => {
                    rotation = rotation.then_about_z(s, co);
                    rotation.rotate_z(one)
                }
                AxisKind::General => {
                    rotation = rotation * Quat::from_axis_half_sin_cos(axis.direction, s, co);
                    rotation.rotate(axis.direction)
                }
            };
            if K::ACC {
                alpha += g * qdd[c] + omega.cross(g) * qd[c];
            }
            omega += g * qd[c];
        }
        let twist = Twist {
            rotation,
            origin: parent_origin + r,
            velocity,
            angular_velocity: omega,
        };
        K::of(twist, (acceleration, alpha))
    }
}
