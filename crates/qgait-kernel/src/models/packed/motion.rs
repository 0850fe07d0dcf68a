//! [`PackedChain`]'s differential kinematics (see [`crate::differential`]): every body's and
//! output point's velocity and acceleration from `q`, `q̇`, `q̈`, the drives' rates by the
//! chain rule through their functions' analytic derivatives.

use super::{Drive, JointCode, PackedChain, SplineCode};
use crate::differential::{polynomial, Carried, FrameMotion, Jet, PointMotion, Twist};
use crate::models::custom::Shape;
use crate::{Quat, Real, Vec3};

impl<
        T: Real,
        const N: usize,
        const B: usize,
        const P: usize,
        const S: usize,
        const Q: usize,
        const D: usize,
        const W: usize,
    > PackedChain<T, N, B, P, S, Q, D, W>
{
    /// Every body's motion in ground ([`FrameMotion`]: orientation, origin, the origin's
    /// velocity and acceleration, angular velocity and acceleration, ground axes) for input
    /// coordinates `q`, speeds `qd` and accelerations `qdd`. The orientations and origins are
    /// [`frames`](Self::frames)'.
    pub fn motions(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [FrameMotion<T>; B] {
        self.carried(q, qd, qdd)
    }

    /// The output points' positions, velocities and accelerations in ground (the time
    /// derivatives of [`forward`](Self::forward)'s points).
    #[inline]
    pub fn forward_motion(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [PointMotion<T>; P] {
        let frames: [FrameMotion<T>; B] = self.carried(q, qd, qdd);
        self.points_of(&frames)
    }

    /// The output points' positions and velocities (as [`forward_motion`](Self::forward_motion),
    /// the accelerations neither computed nor carried): `(positions, velocities)`.
    #[inline]
    pub fn forward_velocities(&self, q: &[T; N], qd: &[T; N]) -> ([Vec3<T>; P], [Vec3<T>; P]) {
        let frames: [Twist<T>; B] = self.carried(q, qd, qd);
        let points = self.points_of(&frames);
        let mut positions = [Vec3::zero(); P];
        let mut velocities = [Vec3::zero(); P];
        for (i, p) in points.iter().enumerate() {
            positions[i] = p.position;
            velocities[i] = p.velocity;
        }
        (positions, velocities)
    }

    /// The points on their bodies' motions (as `forward` reads them).
    #[inline(always)]
    fn points_of<K: Carried<T>>(&self, frames: &[K; B]) -> [PointMotion<T>; P] {
        let mut cursor = usize::from(u16::from_le_bytes([
            self.codes.counts[2],
            self.codes.counts[3],
        ]));
        core::array::from_fn(|k| {
            let [body, at_origin] = self.codes.points[k];
            let Some(f) = frames.get(usize::from(body).min(B.saturating_sub(1))) else {
                return PointMotion::default();
            };
            if at_origin != 0 {
                f.origin_motion()
            } else {
                f.point_at(f.twist().0.rotate(self.vec(&mut cursor)))
            }
        })
    }

    /// The bodies' motions, with their accelerations if `K` carries them (`qdd` unread
    /// otherwise).
    #[inline(always)]
    fn carried<K: Carried<T>>(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [K; B] {
        let mut values = [Jet::ZERO; D];
        self.jets(q, qd, qdd, &mut values);
        let mut frames = [K::GROUND; B];
        let mut rest = values
            .get(usize::from(self.codes.counts[1])..)
            .unwrap_or(&[]);
        for (b, &code) in self.codes.joints.iter().enumerate() {
            let code = JointCode(code);
            let (nr, nt) = code.moving();
            let (v, after) = rest.split_at((nr + nt).min(rest.len()));
            rest = after;
            let (done, todo) = frames.split_at_mut(b);
            let parent = match done.get(code.parent()) {
                Some(p) if b > 0 => p,
                _ => &K::GROUND,
            };
            if let Some(f) = todo.first_mut() {
                *f = self.body_motion(code, parent, v, nr, nt);
            }
        }
        frames
    }

    /// Every drive's value and rates (see `values`), by the chain rule.
    #[inline(always)]
    fn jets(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N], values: &mut [Jet<T>; D]) {
        let mut cursor = 0;
        let mut weights = SplineWeights::default();
        let count = usize::from(self.codes.counts[0]).min(D);
        for i in 0..count {
            let [function, argument] = self.codes.drives[i];
            let index = usize::from(argument & Drive::INDEX);
            let x = match argument & Drive::KIND {
                Drive::COORDINATE if index < N => Jet {
                    value: q[index],
                    rate: qd[index],
                    accel: qdd[index],
                },
                Drive::COUPLED if index < i => values[index],
                _ => Jet::ZERO,
            };
            values[i] = self.function_jet(function, x, &mut cursor, &mut weights);
        }
    }

    /// Function code `function` through `x` (as `function`, with its derivatives).
    #[inline(always)]
    fn function_jet(
        &self,
        function: u8,
        x: Jet<T>,
        cursor: &mut usize,
        weights: &mut SplineWeights<T>,
    ) -> Jet<T> {
        let index = usize::from(function & Drive::FUNCTION_INDEX);
        let shared = function & Drive::SHARES != 0;
        let zero = T::ZERO;
        match function & Drive::KIND {
            Drive::LINEAR => {
                let [slope, intercept] = self.take::<2>(cursor);
                x.through(slope * x.value + intercept, slope, zero)
            }
            Drive::SPLINE => {
                let Some(&s) = self.codes.splines.get(index) else {
                    return Jet::ZERO;
                };
                let s = SplineCode(s);
                if !shared {
                    *weights = self.spline_weights(s, x.value);
                }
                let at = s.values() + weights.k;
                let n = s.knots();
                let [y0, y1] = self.take::<2>(&mut at.clone());
                let [m0, m1] = self.take::<2>(&mut (at + n));
                let [w, a, b] = weights.w;
                let [dw, da, db] = weights.d;
                let [ddw, dda, ddb] = weights.dd;
                let dy = y1 - y0;
                x.through(
                    y0 + dy * w + m0 * a + m1 * b,
                    dy * dw + m0 * da + m1 * db,
                    dy * ddw + m0 * dda + m1 * ddb,
                )
            }
            Drive::POLYNOMIAL => {
                let Some(&[s0, s1, len]) = self.codes.polynomials.get(index) else {
                    return Jet::ZERO;
                };
                let start = usize::from(u16::from_le_bytes([s0, s1]));
                let c = self.words.get(start..start + usize::from(len));
                let (p, dp, ddp) = polynomial(c.unwrap_or(&[]), x.value);
                x.through(p, dp, ddp)
            }
            _ => x,
        }
    }

    /// The Hermite weights of spline `s` at `t` (as `weights`) and their first and second
    /// derivatives by `t`.
    #[inline(always)]
    fn spline_weights(&self, s: SplineCode, t: T) -> SplineWeights<T> {
        let n = s.knots();
        let start = s.x();
        let (zero, one) = (T::ZERO, T::ONE);
        let Some(x) = self.words.get(start..start + n).filter(|x| x.len() >= 2) else {
            return SplineWeights::default();
        };
        let last = n - 1;
        if t < x[0] {
            // The first knot's line: y0 + m0 (t - x0).
            return SplineWeights {
                k: 0,
                w: [zero, t - x[0], zero],
                d: [zero, one, zero],
                dd: [zero; 3],
            };
        }
        if x[last] < t {
            return SplineWeights {
                k: last - 1,
                w: [one, zero, t - x[last]],
                d: [zero, zero, one],
                dd: [zero; 3],
            };
        }
        // As `weights`: the last knot at or below t, below the last knot.
        let (mut k, mut end) = (0, last);
        while end - k > 1 {
            let mid = (k + end) / 2;
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if x.get(mid).is_some_and(|&xm| !(t < xm)) {
                k = mid;
            } else {
                end = mid;
            }
        }
        let Some(&[xk, xk1]) = x.get(k..k + 2) else {
            return SplineWeights {
                k,
                ..SplineWeights::default()
            };
        };
        let h = xk1 - xk;
        let dx = t - xk;
        let s_ = dx / h;
        if s.linear() {
            return SplineWeights {
                k,
                w: [s_, zero, zero],
                d: [one / h, zero, zero],
                dd: [zero; 3],
            };
        }
        // w = s²(3 - 2s), a = h s (1 - s)², b = -h s² (1 - s), s = (t - xₖ) / h.
        let r = one - s_;
        let (two, three) = (T::TWO, T::TWO + one);
        let six = three * two;
        SplineWeights {
            k,
            w: [s_ * s_ * (three - two * s_), dx * r * r, -(dx * s_ * r)],
            d: [
                six * s_ * r / h,
                r * (one - three * s_),
                s_ * (three * s_ - two),
            ],
            dd: [
                six * (one - two * s_) / (h * h),
                (six * s_ - two - two) / h,
                (six * s_ - two) / h,
            ],
        }
    }

    /// A body's motion on its parent's, as `frame` places it: `v` its `nt` translations'
    /// drives, then its `nr` rotations'.
    #[inline(always)]
    fn body_motion<K: Carried<T>>(
        &self,
        code: JointCode,
        parent: &K,
        v: &[Jet<T>],
        nr: usize,
        nt: usize,
    ) -> K {
        let mut cursor = code.words();
        let shape = code.shape();
        let zero = Vec3::zero();
        let (parent_rotation, mut origin, mut velocity, w) = parent.twist();
        let (mut acceleration, parent_alpha) = parent.accelerations();
        if shape & Shape::START != 0 {
            let start = self.vec(&mut cursor);
            let (mut slide, mut rate, mut accel) = (zero, zero, zero);
            for x in v.iter().take(nt) {
                let axis = self.vec(&mut cursor);
                slide += axis * x.value;
                rate += axis * x.rate;
                if K::ACC {
                    accel += axis * x.accel;
                }
            }
            let r = parent_rotation.rotate(start + slide);
            let rate = parent_rotation.rotate(rate);
            origin += r;
            velocity += w.cross(r) + rate;
            if K::ACC {
                acceleration += parent_alpha.cross(r)
                    + w.cross(w.cross(r) + rate * T::TWO)
                    + parent_rotation.rotate(accel);
            }
        }
        let mut rotation = parent_rotation;
        let mut omega = w;
        let mut alpha = parent_alpha;
        let one = T::ONE;
        for (r, x) in v.iter().skip(nt).take(nr).enumerate() {
            let (s, c) = x.value.half_angle_sin_cos();
            let g = match code.kinds() >> (2 * r) & 3 {
                1 => {
                    rotation = rotation.then_about_x(s, c);
                    rotation.rotate_x(one)
                }
                2 => {
                    rotation = rotation.then_about_y(s, c);
                    rotation.rotate_y(one)
                }
                3 => {
                    rotation = rotation.then_about_z(s, c);
                    rotation.rotate_z(one)
                }
                _ => {
                    let axis = self.vec(&mut cursor);
                    rotation = rotation * Quat::from_axis_half_sin_cos(axis, s, c);
                    rotation.rotate(axis)
                }
            };
            if K::ACC {
                alpha += g * x.accel + omega.cross(g) * x.rate;
            }
            omega += g * x.rate;
        }
        if shape & Shape::TURNS != 0 {
            rotation = rotation * self.quat(&mut cursor);
        }
        let mut body = K::of((rotation, origin, velocity, omega), (acceleration, alpha));
        if shape & Shape::ENDS_AWAY != 0 {
            let end = body.point_at(rotation.rotate(self.vec(&mut cursor)));
            body = K::of(
                (rotation, end.position, end.velocity, omega),
                (end.acceleration, alpha),
            );
        }
        body
    }
}

/// A spline's cubic `k` and the weights of its knots' `[value difference, slope k, slope
/// k+1]` at the argument (`w`), with their first (`d`) and second (`dd`) derivatives by it.
#[derive(Clone, Copy, Default)]
struct SplineWeights<T> {
    k: usize,
    w: [T; 3],
    d: [T; 3],
    dd: [T; 3],
}
