//! Differential kinematics: velocities and accelerations of frames and points, and the signals
//! of an ideal IMU fixed to a body.
//!
//! The evaluators are beside the positions' ones, on each chain type:
//! [`Chain::motions`](crate::Chain::motions), [`Chain::forward_motion`](crate::Chain::forward_motion)
//! and [`Chain::forward_velocities`](crate::Chain::forward_velocities) (HAK, PHAK, gait2392), and
//! the same three on [`PackedChain`](crate::models::packed::PackedChain) (imported chains, with
//! spline-driven and coupled coordinates). They take the coordinates `q` (radians, metres),
//! their speeds `q̇` (per second) and accelerations `q̈` (per second squared) and propagate
//! quaternion differential kinematics down the chain, not differences of positions:
//! - a body's angular velocity is its parent's plus each rotation axis, turned into ground by
//!   the rotation up to it, times its speed: `ω = ω_P + Σ gₖ ẋₖ`;
//! - its angular acceleration `α = α_P + Σ (gₖ ẍₖ + (ωₖ₋₁ × gₖ) ẋₖ)`, `ωₖ₋₁` the angular
//!   velocity of the frame that carries axis `k` (the parent's and the earlier axes');
//! - a point `r` away from a frame's origin (in ground) moves with `v = v_O + ω × r + ṙ` and
//!   `a = a_O + α × r + ω × (ω × r) + 2 ω × ṙ + r̈`, where `ṙ`, `r̈` are the coordinate-driven
//!   translations' own rates (gait2392's knee, a walker knee), turned into ground;
//! - a function-driven axis (a spline, a polynomial, a linear function, of a coordinate or of a
//!   coupled coordinate) moves at `ẋ = f'(u) u̇`, `ẍ = f''(u) u̇² + f'(u) ü` (the chain rule;
//!   `u` the coordinate, or the coupler's function of it, the same way), with the functions'
//!   derivatives analytic: a `SimmSpline`'s cubic, a piecewise-linear function's slopes (its
//!   second derivative zero between knots), a polynomial by Horner's rule.
//!
//! **Frames.** Every quantity the evaluators return is in ground, expressed in ground axes:
//! positions with the origin at the chain's root (the pelvis origin: the models have no pelvis
//! translation), linear velocities and accelerations of the points relative to that root
//! (the time derivatives of exactly the positions `forward` returns), angular velocities and
//! accelerations of each body (joint frame) relative to ground. A motion with a pelvis
//! translation adds the translation's velocity and acceleration
//! ([`FrameMotion::moved_by`], [`PointMotion::moved_by`]); rotations are unchanged by it.
//!
//! **IMU.** [`imu_signals`] gives what an ideal IMU fixed to a body measures, as OpenSim's
//! `IMU` component computes it: the gyroscope is the IMU frame's angular velocity relative to
//! ground, expressed in the IMU frame (rad/s); the accelerometer is the IMU origin's
//! acceleration in ground minus gravity ([`GRAVITY`], OpenSim's default `(0, -9.80665, 0)`),
//! expressed in the IMU frame (m/s²; at rest it reads `+9.80665` along the IMU's upward axis).
//! (opensim-core #3366/#3367 report users reading OpenSim's gyroscope in other frames: these are
//! the frames.)

use crate::models::parts::BodyFrame;
use crate::{Quat, Real, Vec3};

/// Gravity in ground (m/s²): OpenSim's default, `(0, -9.80665, 0)` (y up).
pub const GRAVITY: [f64; 3] = [0.0, -9.80665, 0.0];

/// A frame's (a body's) motion: position and orientation, and their first and second time
/// derivatives, all in ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameMotion<T> {
    /// Orientation (frame to ground), as [`Frame::rotation`](crate::Frame::rotation).
    pub rotation: Quat<T>,
    /// Origin in ground (m).
    pub origin: Vec3<T>,
    /// The origin's velocity in ground, ground axes (m/s).
    pub velocity: Vec3<T>,
    /// The origin's acceleration in ground, ground axes (m/s²).
    pub acceleration: Vec3<T>,
    /// Angular velocity of the frame relative to ground, expressed in ground (rad/s).
    pub angular_velocity: Vec3<T>,
    /// Angular acceleration of the frame relative to ground, expressed in ground (rad/s²):
    /// the time derivative of `angular_velocity`.
    pub angular_acceleration: Vec3<T>,
}

/// A point's position, velocity and acceleration in ground (m, m/s, m/s²; ground axes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PointMotion<T> {
    /// Position.
    pub position: Vec3<T>,
    /// Velocity: the time derivative of `position`.
    pub velocity: Vec3<T>,
    /// Acceleration: the time derivative of `velocity`.
    pub acceleration: Vec3<T>,
}

impl<T: Real> FrameMotion<T> {
    /// Ground: at the origin, not moving.
    pub const GROUND: Self = Self {
        rotation: Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO),
        origin: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        velocity: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        acceleration: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        angular_velocity: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        angular_acceleration: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
    };

    /// The motion of the point fixed at `offset` in this frame (its position in ground, from
    /// `r = R offset`: `v = v_O + ω × r`, `a = a_O + α × r + ω × (ω × r)`).
    #[inline(always)]
    pub fn point(&self, offset: Vec3<T>) -> PointMotion<T> {
        self.point_at(self.rotation.rotate(offset))
    }

    /// The motion of the point fixed in this frame at `r` from its origin, `r` in ground axes.
    #[inline(always)]
    pub(crate) fn point_at(&self, r: Vec3<T>) -> PointMotion<T> {
        let w = self.angular_velocity;
        PointMotion {
            position: self.origin + r,
            velocity: self.velocity + w.cross(r),
            acceleration: self.acceleration
                + self.angular_acceleration.cross(r)
                + w.cross(w.cross(r)),
        }
    }

    /// This frame carried by a translation of the whole chain (a pelvis translation, moving
    /// with `root`'s position, velocity and acceleration in ground): rotations unchanged.
    pub fn moved_by(&self, root: &PointMotion<T>) -> Self {
        Self {
            origin: self.origin + root.position,
            velocity: self.velocity + root.velocity,
            acceleration: self.acceleration + root.acceleration,
            ..*self
        }
    }
}

impl<T: Real> PointMotion<T> {
    /// This point carried by a translation of the whole chain (see [`FrameMotion::moved_by`]).
    pub fn moved_by(&self, root: &PointMotion<T>) -> Self {
        Self {
            position: self.position + root.position,
            velocity: self.velocity + root.velocity,
            acceleration: self.acceleration + root.acceleration,
        }
    }
}

/// Where an IMU sits on its body: an OpenSim `PhysicalOffsetFrame` carrying an `IMU`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuMount<T> {
    /// The IMU's origin in the body frame (m).
    pub translation: Vec3<T>,
    /// The IMU frame's orientation in the body frame (unit quaternion, IMU to body).
    pub rotation: Quat<T>,
}

impl<T: Real> ImuMount<T> {
    /// As an OpenSim `PhysicalOffsetFrame`'s `translation` and `orientation`: body-fixed X-Y-Z
    /// angles (radians), `R_body_imu = Rx(o₀) Ry(o₁) Rz(o₂)`.
    pub fn from_xyz(translation: Vec3<T>, orientation: [T; 3]) -> Self {
        let offset = crate::models::parts::Offset::from_xyz(translation, orientation);
        Self {
            translation,
            rotation: offset.rotation,
        }
    }
}

/// What an ideal IMU measures (see the module docs for the frames).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSignals<T> {
    /// The IMU frame's orientation in ground (IMU to ground), as OpenSense's orientation files.
    pub orientation: Quat<T>,
    /// Gyroscope: the IMU frame's angular velocity relative to ground, expressed in the IMU
    /// frame (rad/s).
    pub gyroscope: Vec3<T>,
    /// Accelerometer: the IMU origin's acceleration in ground minus [`GRAVITY`], expressed in
    /// the IMU frame (m/s²).
    pub accelerometer: Vec3<T>,
}

/// The signals of an ideal IMU mounted at `mount` on the body moving with `body` (a
/// [`FrameMotion`] from a chain's `motions`, carried by the pelvis translation with
/// [`FrameMotion::moved_by`] when the motion has one: the accelerometer needs the translation's
/// acceleration, the gyroscope does not).
#[inline]
pub fn imu_signals<T: Real>(body: &FrameMotion<T>, mount: &ImuMount<T>) -> ImuSignals<T> {
    let orientation = body.rotation * mount.rotation;
    let at = body.point(mount.translation);
    let g = Vec3::new(
        T::from_f64(GRAVITY[0]),
        T::from_f64(GRAVITY[1]),
        T::from_f64(GRAVITY[2]),
    );
    let to_imu = orientation.conj();
    ImuSignals {
        orientation,
        gyroscope: to_imu.rotate(body.angular_velocity),
        accelerometer: to_imu.rotate(at.acceleration - g),
    }
}

/// The first and second time derivatives of a uniformly sampled series (a coordinate of a
/// motion file without speeds), `dt` apart: five-point stencils, fourth order, no filter.
///
/// Inside, the central differences `q̇ᵢ = (qᵢ₋₂ − 8qᵢ₋₁ + 8qᵢ₊₁ − qᵢ₊₂) / 12Δt` and
/// `q̈ᵢ = (−qᵢ₋₂ + 16qᵢ₋₁ − 30qᵢ + 16qᵢ₊₁ − qᵢ₊₂) / 12Δt²`; the two samples at each end take the
/// one-sided five-point stencils. Non-causal (two samples ahead), so for recorded series, not
/// a live stream. Accuracy on a sinusoid of angular frequency `ω`: inside, relative errors of
/// `(ωΔt)⁴/30` (rate) and `(ωΔt)⁴/90` (acceleration), so a 6 Hz component (gait's highest of
/// note) comes out within 6.7e-4 and 2.2e-4 of itself at 100 Hz, 6.7e-8 and 2.2e-8 at 1 kHz;
/// at the first and last samples `(ωΔt)⁴/5` and `5(ωΔt)³/6` (the one-sided acceleration is
/// third order: 4.5 % at 6 Hz and 100 Hz, 4.5e-5 at 1 kHz; the second and last-but-one samples
/// a twelfth of that). Noise `ε` on the samples gives about `0.95 ε / Δt` on the rate and
/// `3 ε / Δt²` on the acceleration (no smoothing: low-pass filter a noisy recording first, as
/// OpenSim's tools offer a cut-off).
///
/// Writes `min(q, qd, qdd)` lengths; a series of fewer than five samples gives NaN.
pub fn differentiate<T: Real>(q: &[T], dt: T, qd: &mut [T], qdd: &mut [T]) {
    let n = q.len().min(qd.len()).min(qdd.len());
    let nan = T::from_f64(f64::NAN);
    if n < 5 {
        qd[..n].fill(nan);
        qdd[..n].fill(nan);
        return;
    }
    let c = |k: i32| T::from_f64(f64::from(k));
    let (d1, d2) = (T::ONE / (c(12) * dt), T::ONE / (c(12) * dt * dt));
    let at = |i: usize, w: [i32; 5]| {
        q[i..i + 5]
            .iter()
            .zip(w)
            .fold(T::ZERO, |s, (&v, k)| s + c(k) * v)
    };
    for i in 2..n - 2 {
        qd[i] = at(i - 2, [1, -8, 0, 8, -1]) * d1;
        qdd[i] = at(i - 2, [-1, 16, -30, 16, -1]) * d2;
    }
    let last = n - 5;
    qd[0] = at(0, [-25, 48, -36, 16, -3]) * d1;
    qd[1] = at(0, [-3, -10, 18, -6, 1]) * d1;
    qd[n - 2] = at(last, [-1, 6, -18, 10, 3]) * d1;
    qd[n - 1] = at(last, [3, -16, 36, -48, 25]) * d1;
    qdd[0] = at(0, [35, -104, 114, -56, 11]) * d2;
    qdd[1] = at(0, [11, -20, 6, 4, -1]) * d2;
    qdd[n - 2] = at(last, [-1, 4, 6, -20, 11]) * d2;
    qdd[n - 1] = at(last, [11, -56, 114, -104, 35]) * d2;
}

/// A frame's position and velocity only: what the velocity evaluators carry down the chain
/// (a [`FrameMotion`] without its accelerations, so they are neither computed nor copied).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Twist<T> {
    pub(crate) rotation: Quat<T>,
    pub(crate) origin: Vec3<T>,
    pub(crate) velocity: Vec3<T>,
    pub(crate) angular_velocity: Vec3<T>,
}

/// A frame's motion as an evaluator carries it: [`FrameMotion`] (with accelerations),
/// [`Twist`] (without: its accelerations read as zero and are dropped when set) or
/// [`BodyFrame`] (the position alone: its rates read as zero and are dropped when set).
pub(crate) trait Carried<T: Real>: Copy {
    /// Whether the accelerations are carried.
    const ACC: bool;
    /// Ground.
    const GROUND: Self;
    /// Orientation, origin, the origin's velocity, angular velocity.
    fn twist(&self) -> Twist<T>;
    /// The origin's acceleration and the angular acceleration (zero without them).
    fn accelerations(&self) -> (Vec3<T>, Vec3<T>);
    /// From its parts (what it does not carry ignored).
    fn of(twist: Twist<T>, accelerations: (Vec3<T>, Vec3<T>)) -> Self;

    /// The origin itself: position, velocity, acceleration (no arithmetic on a zero offset:
    /// `0 · x` does not fold in floating point).
    #[inline(always)]
    fn origin_motion(&self) -> PointMotion<T> {
        let Twist {
            origin, velocity, ..
        } = self.twist();
        PointMotion {
            position: origin,
            velocity,
            acceleration: if Self::ACC {
                self.accelerations().0
            } else {
                Vec3::zero()
            },
        }
    }

    /// The point `r` (ground axes) from the origin: position, velocity, acceleration.
    #[inline(always)]
    fn point_at(&self, r: Vec3<T>) -> PointMotion<T> {
        let Twist {
            origin,
            velocity,
            angular_velocity: w,
            ..
        } = self.twist();
        let mut acceleration = Vec3::zero();
        if Self::ACC {
            let (a, alpha) = self.accelerations();
            acceleration = a + alpha.cross(r) + w.cross(w.cross(r));
        }
        PointMotion {
            position: origin + r,
            velocity: velocity + w.cross(r),
            acceleration,
        }
    }
}

impl<T: Real> Carried<T> for FrameMotion<T> {
    const ACC: bool = true;
    const GROUND: Self = FrameMotion::GROUND;
    #[inline(always)]
    fn twist(&self) -> Twist<T> {
        Twist {
            rotation: self.rotation,
            origin: self.origin,
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
        }
    }
    #[inline(always)]
    fn accelerations(&self) -> (Vec3<T>, Vec3<T>) {
        (self.acceleration, self.angular_acceleration)
    }
    #[inline(always)]
    fn of(twist: Twist<T>, (acceleration, angular_acceleration): (Vec3<T>, Vec3<T>)) -> Self {
        let Twist {
            rotation,
            origin,
            velocity,
            angular_velocity,
        } = twist;
        Self {
            rotation,
            origin,
            velocity,
            acceleration,
            angular_velocity,
            angular_acceleration,
        }
    }
}

impl<T: Real> Carried<T> for Twist<T> {
    const ACC: bool = false;
    const GROUND: Self = Twist {
        rotation: Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO),
        origin: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        velocity: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        angular_velocity: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
    };
    #[inline(always)]
    fn twist(&self) -> Twist<T> {
        *self
    }
    #[inline(always)]
    fn accelerations(&self) -> (Vec3<T>, Vec3<T>) {
        (Vec3::zero(), Vec3::zero())
    }
    #[inline(always)]
    fn of(twist: Twist<T>, _: (Vec3<T>, Vec3<T>)) -> Self {
        twist
    }
}

impl<T: Real> Carried<T> for BodyFrame<T> {
    const ACC: bool = false;
    const GROUND: Self = BodyFrame::GROUND;
    #[inline(always)]
    fn twist(&self) -> Twist<T> {
        Twist {
            rotation: self.rotation,
            origin: self.origin,
            velocity: Vec3::zero(),
            angular_velocity: Vec3::zero(),
        }
    }
    #[inline(always)]
    fn accelerations(&self) -> (Vec3<T>, Vec3<T>) {
        (Vec3::zero(), Vec3::zero())
    }
    #[inline(always)]
    fn of(twist: Twist<T>, _: (Vec3<T>, Vec3<T>)) -> Self {
        BodyFrame {
            rotation: twist.rotation,
            origin: twist.origin,
        }
    }
}

/// A value and its first and second time derivatives: what a coordinate-driven function
/// passes down the chain rule.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Jet<T> {
    pub(crate) value: T,
    pub(crate) rate: T,
    pub(crate) accel: T,
}

/// What a coordinate-driven function passes on: the value alone (`T`, for positions) or a
/// [`Jet`] (with its rates, by the chain rule).
pub(crate) trait ChainRule<T: Real>: Copy {
    /// Zero, not moving.
    const ZERO: Self;
    /// The value.
    fn value(self) -> T;
    /// The first time derivative (zero for a value alone).
    fn rate(self) -> T;
    /// The second time derivative (zero for a value alone).
    fn accel(self) -> T;
    /// `f(self)` given `f`'s value, first and second derivatives at `self.value()` (the
    /// derivatives unread for a value alone).
    fn through(self, f: T, df: T, ddf: T) -> Self;
}

impl<T: Real> ChainRule<T> for T {
    const ZERO: Self = T::ZERO;
    #[inline(always)]
    fn value(self) -> T {
        self
    }
    #[inline(always)]
    fn rate(self) -> T {
        T::ZERO
    }
    #[inline(always)]
    fn accel(self) -> T {
        T::ZERO
    }
    #[inline(always)]
    fn through(self, f: T, _: T, _: T) -> Self {
        f
    }
}

impl<T: Real> ChainRule<T> for Jet<T> {
    const ZERO: Self = Self {
        value: T::ZERO,
        rate: T::ZERO,
        accel: T::ZERO,
    };
    #[inline(always)]
    fn value(self) -> T {
        self.value
    }
    #[inline(always)]
    fn rate(self) -> T {
        self.rate
    }
    #[inline(always)]
    fn accel(self) -> T {
        self.accel
    }
    #[inline(always)]
    fn through(self, f: T, df: T, ddf: T) -> Self {
        Self {
            value: f,
            rate: df * self.rate,
            accel: ddf * self.rate * self.rate + df * self.accel,
        }
    }
}
