//! Any OpenSim lower-limb chain as data: bodies joined by `CustomJoint`s (and the `PinJoint`,
//! `UniversalJoint` and `WeldJoint` special cases), each joint with oriented parent and child
//! offset frames and up to three rotations and three translations, each a function of one
//! coordinate (constant, linear, `SimmSpline`, piecewise linear, polynomial), coordinates coupled to an
//! independent one by a `CoordinateCouplerConstraint`. What Rajagopal 2015/2016 and
//! gait10dof18musc need, beside gait2392's family (which keeps its own faster
//! [`Gait2392`](super::Gait2392) table).
//!
//! A joint places its child body `B` on its parent body `P` as OpenSim does:
//! `X_PB = X_PF · X_FM(q) · X_BM⁻¹`, where `F` and `M` are the parent and child offset frames
//! (translation, then orientation as body-fixed x-y-z angles) and `X_FM` is the joint's
//! transform: the rotations body-fixed in order (each about its axis in the frame left by the
//! earlier ones), then the translations along their axes in `F`.
//!
//! Sizes are fixed: `N` input coordinates, `B` bodies (joint `b` moves body `b`), `P` output
//! points, up to [`MAX_SPLINES`] splines of up to [`MAX_SPLINE_KNOTS`] knots, up to
//! [`MAX_POLYNOMIALS`] polynomials and [`MAX_COUPLERS`] coupled coordinates. [`LowerLimb`] is the size the host uses: the 17
//! gait2392 coordinates, pelvis and two legs of five bodies, the 12 gait2392 points.

use super::packed::{PackError, PackedChain};
pub use super::parts::{
    Argument, BodyFrame, BodyPoint, Coupler, CustomJoint, Driven, Function, Functions, Offset,
    MAX_COUPLERS, MAX_POLYNOMIALS, MAX_SPLINES, MAX_SPLINE_KNOTS,
};
use super::parts::{AxisKind, ChainParts, Step};
use crate::differential::{FrameMotion, PointMotion};
use crate::{ModelError, Polynomial, Quat, Real, Spline, Vec3};

/// The chain of the host's lower-limb models: the 17 gait2392 coordinates in
/// [`COORDINATES`](super::gait2392::COORDINATES) order, 11 bodies (pelvis, then femur, tibia,
/// talus, calcaneus, toes right and left), the 12 points of
/// [`POINTS`](super::gait2392::POINTS).
pub type LowerLimb<T> = CustomChain<T, 17, 11, 12>;

/// A validated chain. Joint `b` moves body `b`. `S` spline slots of `K` knots each and `Q`
/// polynomial slots ([`MAX_SPLINES`], [`MAX_SPLINE_KNOTS`] and [`MAX_POLYNOMIALS`] unless said),
/// evaluated by its [`PackedChain`] of up to `D` drives and `W` numbers (enough for any chain
/// of 11 bodies unless said).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CustomChain<
    T,
    const N: usize,
    const B: usize,
    const P: usize,
    const S: usize = MAX_SPLINES,
    const K: usize = MAX_SPLINE_KNOTS,
    const Q: usize = MAX_POLYNOMIALS,
    const D: usize = MAX_DRIVES,
    const W: usize = MAX_WORDS,
> {
    joints: [CustomJoint<T>; B],
    /// Per joint, what its evaluation needs (built by [`rebuild`](Self::rebuild) from the
    /// joint, and packed into `table`).
    steps: [Step<T>; B],
    points: [BodyPoint<T>; P],
    splines: [Spline<T, K>; S],
    polynomials: [Polynomial<T>; Q],
    couplers: [Coupler<T>; MAX_COUPLERS],
    /// How many of `splines`, `couplers` and `polynomials` are in use.
    used: (u8, u8, u8),
    /// The chain packed: what [`forward`](Self::forward) and [`frames`](Self::frames)
    /// evaluate (the one evaluation of a chain, a device's too).
    table: PackedChain<T, N, B, P, S, Q, D, W>,
}

/// Most drives (moving axes and coupled coordinates) a [`CustomChain`]'s table holds unless
/// said: six axes for each of 11 bodies, and [`MAX_COUPLERS`].
pub const MAX_DRIVES: usize = 6 * 11 + MAX_COUPLERS;

/// Most numbers a [`CustomChain`]'s table holds unless said: every part of 11 joints (28
/// each), 12 points (3 each), the linear drives' two each, [`MAX_SPLINES`] of
/// [`MAX_SPLINE_KNOTS`] (3 a knot) and [`MAX_POLYNOMIALS`] of their most coefficients.
pub const MAX_WORDS: usize = 11 * 28
    + 12 * 3
    + 2 * MAX_DRIVES
    + MAX_SPLINES * 3 * MAX_SPLINE_KNOTS
    + MAX_POLYNOMIALS * crate::polynomial::MAX_COEFFICIENTS;

impl<
        T: Real,
        const N: usize,
        const B: usize,
        const P: usize,
        const S: usize,
        const K: usize,
        const Q: usize,
        const D: usize,
        const W: usize,
    > CustomChain<T, N, B, P, S, K, Q, D, W>
{
    /// A table of zeros (every point at the origin): a slot that
    /// [`rebuild`](Self::rebuild) fills in place. All zero bits, so writing it is a memset.
    pub const EMPTY: Self = {
        let zero = Vec3::new(T::ZERO, T::ZERO, T::ZERO);
        let offset = Offset {
            translation: zero,
            rotation: Quat::new(T::ZERO, T::ZERO, T::ZERO, T::ZERO),
        };
        let still = Driven {
            axis: zero,
            function: Function::Constant(T::ZERO),
            argument: Argument::None,
        };
        Self {
            joints: [CustomJoint {
                parent: None,
                in_parent: offset,
                in_child: offset,
                rotations: [still; 3],
                translations: [still; 3],
            }; B],
            steps: [Step {
                axes: [zero; 3],
                end: offset,
                kinds: [AxisKind::General; 3],
                moving: (0, 0),
                shape: 0,
            }; B],
            points: [BodyPoint {
                body: 0,
                offset: zero,
            }; P],
            splines: [Spline::EMPTY; S],
            polynomials: [Polynomial::ZERO; Q],
            couplers: [Coupler {
                independent: 0,
                function: Function::Constant(T::ZERO),
            }; MAX_COUPLERS],
            used: (0, 0, 0),
            table: PackedChain::EMPTY,
        }
    };

    /// Validates and builds a chain: parents come first (body 0 hangs on ground, every other
    /// body on an earlier one), axes are non-zero and finite (normalised here), arguments,
    /// splines and polynomials exist, offsets are finite, couplers depend on inputs and are not
    /// chained. Axes whose function is the constant 0 are dropped (the others keep their order).
    pub fn new(
        joints: [CustomJoint<T>; B],
        points: [BodyPoint<T>; P],
        functions: Functions<'_, T, K>,
        couplers: &[Coupler<T>],
    ) -> Result<Self, ModelError> {
        let mut chain = Self::EMPTY;
        chain.rebuild(&joints, &points, functions, couplers)?;
        Ok(chain)
    }

    /// Whether [`new`](Self::new) accepts this table, without building anything.
    pub fn check(
        joints: &[CustomJoint<T>; B],
        points: &[BodyPoint<T>; P],
        functions: Functions<'_, T, K>,
        couplers: &[Coupler<T>],
    ) -> Result<(), ModelError> {
        let Functions {
            splines,
            polynomials,
        } = functions;
        if splines.len() > S
            || couplers.len() > MAX_COUPLERS
            || splines.iter().any(|s| s.is_empty())
        {
            return Err(ModelError::SplineKnots);
        }
        if polynomials.len() > Q || polynomials.iter().any(|p| p.coefficients().is_empty()) {
            return Err(ModelError::PolynomialCoefficients);
        }
        let finite = |v: Vec3<T>| v.x.is_finite() && v.y.is_finite() && v.z.is_finite();
        let function_ok = |f: &Function<T>| match f {
            Function::Constant(c) => c.is_finite(),
            Function::Linear { slope, intercept } => slope.is_finite() && intercept.is_finite(),
            Function::Spline(k) => *k < splines.len(),
            Function::Polynomial(k) => *k < polynomials.len(),
        };
        for c in couplers {
            if c.independent >= N || !function_ok(&c.function) {
                return Err(ModelError::CoordinateOutOfRange { joint: 0 });
            }
        }
        for (b, joint) in joints.iter().enumerate() {
            if joint.parent.map_or(b > 0, |p| p >= b) {
                return Err(ModelError::ParentOrder { joint: b });
            }
            for o in [&joint.in_parent, &joint.in_child] {
                let q = o.rotation;
                let n = q.norm();
                if !(finite(o.translation)
                    && n.is_finite()
                    && (n - T::ONE).abs() < T::from_f64(1e-6))
                {
                    return Err(ModelError::BadLength);
                }
            }
            for d in joint.rotations.iter().chain(&joint.translations) {
                let length = d.axis.norm();
                if !(finite(d.axis) && length > T::ZERO && function_ok(&d.function)) {
                    return Err(ModelError::BadAxis { joint: b });
                }
                let argument_ok = match d.argument {
                    Argument::None => true,
                    Argument::Coordinate(i) => i < N,
                    Argument::Coupled(k) => k < couplers.len(),
                };
                if !argument_ok {
                    return Err(ModelError::CoordinateOutOfRange { joint: b });
                }
            }
        }
        for p in points {
            if p.body >= B || !finite(p.offset) {
                return Err(ModelError::BodyOutOfRange { index: p.body });
            }
        }
        Ok(())
    }

    /// Makes this chain the table [`new`](Self::new) builds, written in place (no chain on the
    /// stack). Unchanged if [`check`](Self::check) refuses the table.
    pub fn rebuild(
        &mut self,
        joints: &[CustomJoint<T>; B],
        points: &[BodyPoint<T>; P],
        functions: Functions<'_, T, K>,
        couplers: &[Coupler<T>],
    ) -> Result<(), ModelError> {
        Self::check(joints, points, functions, couplers)?;
        let Functions {
            splines,
            polynomials,
        } = functions;
        let still = |d: &Driven<T>| d.function == Function::Constant(T::ZERO);
        for (b, joint) in joints.iter().enumerate() {
            let mut joint = *joint;
            let mut m = (0u8, 0u8);
            for (axes, n) in [
                (&mut joint.rotations, &mut m.0),
                (&mut joint.translations, &mut m.1),
            ] {
                let mut kept = [Driven::NONE; 3];
                for d in axes.iter().filter(|d| !still(d)) {
                    kept[*n as usize] = Driven {
                        axis: d.axis * (T::ONE / d.axis.norm()),
                        ..*d
                    };
                    *n += 1;
                }
                *axes = kept;
            }
            self.joints[b] = joint;
            self.steps[b] = Step::of(&joint, m);
        }
        self.points = *points;
        for (slot, k) in self.splines.iter_mut().zip(0..) {
            *slot = splines.get(k).copied().unwrap_or(Spline::EMPTY);
        }
        for (slot, k) in self.polynomials.iter_mut().zip(0..) {
            *slot = polynomials.get(k).copied().unwrap_or(Polynomial::ZERO);
        }
        for (slot, k) in self.couplers.iter_mut().zip(0..) {
            *slot = couplers.get(k).copied().unwrap_or(Coupler {
                independent: 0,
                function: Function::Constant(T::ZERO),
            });
        }
        self.used = (
            splines.len() as u8,
            couplers.len() as u8,
            polynomials.len() as u8,
        );
        match self.packed() {
            Ok(table) => {
                self.table = table;
                Ok(())
            }
            Err(_) => {
                *self = Self::EMPTY;
                Err(ModelError::TableSize)
            }
        }
    }

    /// The joints, by body (zero-constant axes dropped, the moving ones first).
    pub fn joints(&self) -> &[CustomJoint<T>; B] {
        &self.joints
    }

    /// The output points.
    pub fn points(&self) -> &[BodyPoint<T>; P] {
        &self.points
    }

    /// The chain packed into a table of other sizes or another precision (a device's: `f32`,
    /// its sizes), its numbers rounded to `U`; [`table`](Self::table) is its own.
    pub fn packed<U: Real, const S2: usize, const Q2: usize, const D2: usize, const W2: usize>(
        &self,
    ) -> Result<PackedChain<U, N, B, P, S2, Q2, D2, W2>, PackError> {
        PackedChain::pack(&self.parts())
    }

    /// The chain's description, as its table is packed from it.
    pub(super) fn parts(&self) -> ChainParts<'_, T, K> {
        ChainParts {
            joints: &self.joints,
            steps: &self.steps,
            points: &self.points,
            splines: self.splines(),
            polynomials: self.polynomials(),
            couplers: self.couplers(),
        }
    }

    /// The splines the table's functions refer to ([`Function::Spline`] indices).
    pub fn splines(&self) -> &[Spline<T, K>] {
        &self.splines[..usize::from(self.used.0).min(S)]
    }

    /// The polynomials the table's functions refer to ([`Function::Polynomial`] indices).
    pub fn polynomials(&self) -> &[Polynomial<T>] {
        &self.polynomials[..usize::from(self.used.2).min(Q)]
    }

    /// The coupled coordinates ([`Argument::Coupled`] indices).
    pub fn couplers(&self) -> &[Coupler<T>] {
        &self.couplers[..usize::from(self.used.1).min(MAX_COUPLERS)]
    }

    /// Whether the table reads input coordinate `i`: an axis takes it, or a coupled
    /// coordinate follows it. A coordinate it does not read moves nothing (a locked one, held
    /// at its default when the table was built).
    pub fn reads(&self, i: usize) -> bool {
        let mut axes = self
            .joints
            .iter()
            .flat_map(|j| j.rotations.iter().chain(&j.translations));
        axes.any(|d| d.argument == Argument::Coordinate(i))
            || self.couplers().iter().any(|c| c.independent == i)
    }

    /// Every body's frame in ground for input coordinates `q`.
    pub fn frames(&self, q: &[T; N]) -> [BodyFrame<T>; B] {
        self.table.frames(q)
    }

    /// The output points in ground for input coordinates `q`: forward kinematics.
    #[inline]
    pub fn forward(&self, q: &[T; N]) -> [Vec3<T>; P] {
        self.table.forward(q)
    }

    /// Every body's motion in ground for coordinates `q`, speeds `qd` and accelerations `qdd`
    /// ([`PackedChain::motions`]).
    pub fn motions(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [FrameMotion<T>; B] {
        self.table.motions(q, qd, qdd)
    }

    /// The output points' positions, velocities and accelerations in ground
    /// ([`PackedChain::forward_motion`]).
    pub fn forward_motion(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [PointMotion<T>; P] {
        self.table.forward_motion(q, qd, qdd)
    }

    /// The packed table the chain evaluates (a device's is one of these, in `f32`).
    pub fn table(&self) -> &PackedChain<T, N, B, P, S, Q, D, W> {
        &self.table
    }

    /// The whole table in another precision (e.g. an `f64` model for an `f32` device).
    pub fn cast<U: Real>(&self) -> CustomChain<U, N, B, P, S, K, Q, D, W> {
        let v = |v: Vec3<T>| v.cast::<U>();
        let s = |x: T| U::from_f64(x.to_f64());
        let f = |f: Function<T>| match f {
            Function::Constant(c) => Function::Constant(s(c)),
            Function::Linear { slope, intercept } => Function::Linear {
                slope: s(slope),
                intercept: s(intercept),
            },
            Function::Spline(k) => Function::Spline(k),
            Function::Polynomial(k) => Function::Polynomial(k),
        };
        let d = |d: Driven<T>| Driven {
            axis: v(d.axis),
            function: f(d.function),
            argument: d.argument,
        };
        let q = |q: Quat<T>| Quat::new(s(q.w), s(q.x), s(q.y), s(q.z));
        let o = |o: Offset<T>| Offset {
            translation: v(o.translation),
            rotation: q(o.rotation),
        };
        CustomChain {
            joints: self.joints.map(|j| CustomJoint {
                parent: j.parent,
                in_parent: o(j.in_parent),
                in_child: o(j.in_child),
                rotations: j.rotations.map(d),
                translations: j.translations.map(d),
            }),
            steps: self.steps.map(|st| Step {
                axes: st.axes.map(v),
                end: o(st.end),
                kinds: st.kinds,
                moving: st.moving,
                shape: st.shape,
            }),
            points: self.points.map(|p| BodyPoint {
                body: p.body,
                offset: v(p.offset),
            }),
            splines: self.splines.map(|sp| sp.cast()),
            polynomials: self.polynomials.map(|p| p.cast()),
            couplers: self.couplers.map(|c| Coupler {
                independent: c.independent,
                function: f(c.function),
            }),
            used: self.used,
            // The same sizes as this chain's table, which packed: never refused.
            table: self.packed().unwrap_or(PackedChain::EMPTY),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_the_coordinates_its_axes_take_and_its_couplers_follow() {
        use crate::models::gait2392::COORDINATES;
        let chain = crate::models::fixtures::walker_chain();
        // Every coordinate but the MTPs, which the chain couples to the ankles.
        for (i, name) in COORDINATES.iter().enumerate() {
            assert_eq!(chain.reads(i), !name.starts_with("mtp_angle"), "{name}");
        }
    }
    use crate::models::gait2392::{Gait2392, Gait2392Geometry, COORDINATES};

    /// gait2392's generic chain said in this table's terms: the same points as the
    /// [`Gait2392`] table on any pose (the offsets and axes as data, the knee as splines).
    fn gait2392_as_custom() -> LowerLimb<f64> {
        let g = Gait2392Geometry::generic();
        let v = |a: [f64; 3]| Vec3::from_f64(a);
        let rot = |axis: [f64; 3], i: usize| Driven {
            axis: v(axis),
            function: Function::Linear {
                slope: 1.0,
                intercept: 0.0,
            },
            argument: Argument::Coordinate(i),
        };
        let at = |t: [f64; 3]| Offset {
            translation: v(t),
            rotation: Quat::identity(),
        };
        let mut joints = [CustomJoint::WELD; 11];
        joints[0].rotations = [
            rot([0., 0., 1.], 0),
            rot([1., 0., 0.], 1),
            rot([0., 1., 0.], 2),
        ];
        let mut splines = [Spline::EMPTY; 4];
        let mut points = [BodyPoint {
            body: 0,
            offset: Vec3::zero(),
        }; 12];
        for (side, leg) in [g.right, g.left].iter().enumerate() {
            let (b, c) = (1 + 5 * side, 3 + 7 * side);
            joints[b].parent = Some(0);
            joints[b].in_parent = at(leg.hip_in_pelvis);
            joints[b].rotations = [
                rot(leg.hip_axes[0], c),
                rot(leg.hip_axes[1], c + 1),
                rot(leg.hip_axes[2], c + 2),
            ];
            joints[b + 1].parent = Some(b);
            joints[b + 1].rotations[0] = rot([0., 0., 1.], c + 3);
            for (k, (knots, axis)) in [(leg.knee_tx, [1., 0., 0.]), (leg.knee_ty, [0., 1., 0.])]
                .iter()
                .enumerate()
            {
                splines[2 * side + k] =
                    Spline::new(&knots.x[..knots.n], &knots.y[..knots.n]).unwrap();
                joints[b + 1].translations[k] = Driven {
                    axis: v(*axis),
                    function: Function::Spline(2 * side + k),
                    argument: Argument::Coordinate(c + 3),
                };
            }
            for (k, (loc, axis)) in [
                (leg.ankle_in_tibia, leg.ankle_axis),
                (leg.subtalar_in_talus, leg.subtalar_axis),
                (leg.mtp_in_calcn, leg.mtp_axis),
            ]
            .iter()
            .enumerate()
            {
                joints[b + 2 + k].parent = Some(b + 1 + k);
                joints[b + 2 + k].in_parent = at(*loc);
                joints[b + 2 + k].rotations[0] = rot(*axis, c + 4 + k);
            }
            for k in 0..5 {
                points[6 * side + k].body = b + k;
            }
            points[6 * side + 5] = BodyPoint {
                body: b + 4,
                offset: v(leg.toetip_in_toes),
            };
        }
        LowerLimb::new(joints, points, Functions::splines(&splines), &[]).unwrap()
    }

    #[test]
    fn gait2392_in_this_table_is_the_gait2392_table() {
        assert_eq!(COORDINATES.len(), 17);
        let custom = gait2392_as_custom();
        // The table gives back its splines' knots, as built (cubic, not straight).
        let g = Gait2392Geometry::generic();
        assert_eq!(custom.splines().len(), 4);
        assert_eq!(
            custom.splines()[3].knots().1,
            &g.left.knee_ty.y[..g.left.knee_ty.n]
        );
        assert!(!custom.splines()[0].is_piecewise_linear());
        assert!(
            Spline::<f64, 4>::piecewise_linear(&[0.0, 1.0, 3.0], &[0.0, 2.0, 1.0])
                .unwrap()
                .is_piecewise_linear()
        );
        let fast = Gait2392::<f64>::new(&Gait2392Geometry::generic()).unwrap();
        for k in 0..50 {
            let q: [f64; 17] = core::array::from_fn(|i| {
                0.9 * libm_sin(0.37 * (k * 17 + i) as f64 + 0.1 * k as f64)
            });
            let a = custom.forward(&q);
            let b = fast.chain().forward(&q);
            for (p, r) in a.iter().zip(&b) {
                assert!(p.max_abs_diff(*r) < 1e-14, "{k}: {p:?} {r:?}");
            }
        }
    }

    /// A sine for test poses (no std in the kernel).
    fn libm_sin(x: f64) -> f64 {
        Real::sin_cos(x).0
    }

    #[test]
    fn oriented_frames_pins_and_couplers() {
        // Body 0 at the origin; body 1 on a parent frame turned 90° about z, its child frame
        // 0.1 along its own x, rotating about the frames' z by a coupler of coordinate 0
        // (twice it), and translating 0.5 along F's x.
        let half_pi = core::f64::consts::FRAC_PI_2;
        let mut joints = [CustomJoint::WELD; 2];
        joints[1].parent = Some(0);
        joints[1].in_parent = Offset::from_xyz(Vec3::new(1.0, 0.0, 0.0), [0.0, 0.0, half_pi]);
        joints[1].in_child = Offset::from_xyz(Vec3::new(0.1, 0.0, 0.0), [0.0; 3]);
        joints[1].rotations[0] = Driven {
            axis: Vec3::unit_z(),
            function: Function::Linear {
                slope: 1.0,
                intercept: 0.0,
            },
            argument: Argument::Coupled(0),
        };
        joints[1].translations[0] = Driven {
            axis: Vec3::unit_x(),
            function: Function::Constant(0.5),
            argument: Argument::None,
        };
        let points = [BodyPoint {
            body: 1,
            offset: Vec3::zero(),
        }];
        let couplers = [Coupler {
            independent: 0,
            function: Function::Linear {
                slope: 2.0,
                intercept: 0.0,
            },
        }];
        let chain =
            CustomChain::<f64, 1, 2, 1>::new(joints, points, Functions::splines(&[]), &couplers)
                .unwrap();
        assert_eq!(chain.couplers(), &couplers);
        assert!(chain.splines().is_empty());
        // q = π/4: F at (1, 0, 0) facing +y; M 0.5 along F's x: (1, 0.5, 0), turned a further
        // 90° (coupled): M's x is ground -x; the body origin is 0.1 back along M's x.
        let p = chain.forward(&[half_pi / 2.0])[0];
        assert!(p.max_abs_diff(Vec3::new(1.1, 0.5, 0.0)) < 1e-15, "{p:?}");
        // A zero constant between two rotations is dropped and changes nothing.
        let mut padded = joints;
        padded[1].rotations[2] = padded[1].rotations[0];
        padded[1].rotations[0].axis = Vec3::unit_x();
        padded[1].rotations[1] = Driven {
            axis: Vec3::unit_y(),
            function: Function::Constant(0.0),
            argument: Argument::Coordinate(0),
        };
        let mut turned = joints;
        turned[1].rotations[1] = turned[1].rotations[0];
        turned[1].rotations[0].axis = Vec3::unit_x();
        let a =
            CustomChain::<f64, 1, 2, 1>::new(padded, points, Functions::splines(&[]), &couplers)
                .unwrap();
        let b =
            CustomChain::<f64, 1, 2, 1>::new(turned, points, Functions::splines(&[]), &couplers)
                .unwrap();
        assert_eq!(a.joints()[1].rotations[1], b.joints()[1].rotations[1]);
        for t in [-0.7, 0.2, 1.3] {
            assert_eq!(a.forward(&[t]), b.forward(&[t]));
        }
        let bad = [Coupler {
            independent: 1,
            function: Function::Constant(0.0),
        }];
        assert!(
            CustomChain::<f64, 1, 2, 1>::new(joints, points, Functions::splines(&[]), &bad)
                .is_err()
        );
        let mut cyclic = joints;
        cyclic[1].parent = Some(1);
        assert!(CustomChain::<f64, 1, 2, 1>::new(
            cyclic,
            points,
            Functions::splines(&[]),
            &couplers
        )
        .is_err());
        // Rebuilt in place it is the chain `new` builds; a refused table changes nothing.
        let mut slot = CustomChain::<f64, 1, 2, 1>::EMPTY;
        slot.rebuild(&joints, &points, Functions::splines(&[]), &couplers)
            .unwrap();
        assert_eq!(slot, chain);
        assert!(slot
            .rebuild(&cyclic, &points, Functions::splines(&[]), &couplers)
            .is_err());
        assert_eq!(slot, chain);
    }

    #[test]
    fn polynomial_axes_are_their_polynomials_values() {
        // A knee-like joint on an oriented frame: a rotation and a translation, each a
        // polynomial of coordinate 0 (as Rajagopal-Lai-Uhlrich 2023's walker knee), against the
        // same joint driven linearly by inputs that hold the polynomials' values, summed power
        // by power here.
        let rotation = [0.0123, -0.045, 0.21, -0.3, 0.02];
        let translation = [-0.0031, 0.0102, -0.0035, 0.0005];
        let direct = |c: &[f64], x: f64| {
            let n = c.len() - 1;
            c.iter()
                .enumerate()
                .map(|(k, a)| a * x.powi((n - k) as i32))
                .sum::<f64>()
        };
        let polynomials = [
            Polynomial::new(&rotation).unwrap(),
            Polynomial::new(&translation).unwrap(),
        ];
        let joints = |rotate: (Function<f64>, Argument), slide: (Function<f64>, Argument)| {
            let mut joints = [CustomJoint::WELD; 2];
            joints[1].parent = Some(0);
            joints[1].in_parent =
                Offset::from_xyz(Vec3::new(-0.0045, -0.4096, 0.00175), [0.1, -0.2, 0.3]);
            joints[1].in_child = Offset::from_xyz(Vec3::new(0.0, 0.01, 0.0), [0.1, -0.2, 0.3]);
            joints[1].rotations[0] = Driven {
                axis: Vec3::new(0.0, 0.0, 1.0),
                function: rotate.0,
                argument: rotate.1,
            };
            joints[1].translations[0] = Driven {
                axis: Vec3::new(0.0, 1.0, 0.0),
                function: slide.0,
                argument: slide.1,
            };
            joints
        };
        let points = [BodyPoint {
            body: 1,
            offset: Vec3::new(0.01, -0.4, 0.002),
        }];
        let functions = Functions {
            splines: &[],
            polynomials: &polynomials,
        };
        let of_knee = CustomChain::<f64, 3, 2, 1>::new(
            joints(
                (Function::Polynomial(0), Argument::Coordinate(0)),
                (Function::Polynomial(1), Argument::Coordinate(0)),
            ),
            points,
            functions,
            &[],
        )
        .unwrap();
        let line = Function::Linear {
            slope: 1.0,
            intercept: 0.0,
        };
        let by_value = CustomChain::<f64, 3, 2, 1>::new(
            joints(
                (line, Argument::Coordinate(1)),
                (line, Argument::Coordinate(2)),
            ),
            points,
            Functions::splines(&[]),
            &[],
        )
        .unwrap();
        assert_eq!(of_knee.polynomials(), &polynomials);
        // Beyond any range: OpenSim evaluates a polynomial everywhere.
        for x in [-0.5, 0.0, 0.7, 1.4, 2.44, 3.0] {
            let a = of_knee.forward(&[x, 0.0, 0.0])[0];
            let b = by_value.forward(&[0.0, direct(&rotation, x), direct(&translation, x)])[0];
            assert!((a - b).norm() < 1e-15, "{x}: {a:?} against {b:?}");
        }
        // The f32 table evaluates the same polynomials.
        let device = of_knee.cast::<f32>();
        let p = device.forward(&[1.2, 0.0, 0.0])[0];
        assert!((p.cast::<f64>() - of_knee.forward(&[1.2, 0.0, 0.0])[0]).norm() < 1e-6);
        // Refused: a polynomial the table does not have, more than `Q`.
        let missing = joints(
            (Function::Polynomial(2), Argument::Coordinate(0)),
            (line, Argument::Coordinate(0)),
        );
        assert_eq!(
            CustomChain::<f64, 3, 2, 1>::new(missing, points, functions, &[]),
            Err(ModelError::BadAxis { joint: 1 })
        );
        let none = CustomChain::<f64, 3, 2, 1, 0, 2, 1>::new(
            joints(
                (Function::Polynomial(0), Argument::Coordinate(0)),
                (line, Argument::Coordinate(0)),
            ),
            points,
            Functions {
                splines: &[],
                polynomials: &polynomials,
            },
            &[],
        );
        assert_eq!(none, Err(ModelError::PolynomialCoefficients));
        // A table without polynomial slots (`Q = 0`, a device's) refuses them both ways.
        let polynomial_knee = joints(
            (Function::Polynomial(0), Argument::Coordinate(0)),
            (line, Argument::Coordinate(0)),
        );
        type NoPolynomials = CustomChain<f64, 3, 2, 1, 12, 16, 0>;
        assert_eq!(
            NoPolynomials::new(polynomial_knee, points, functions, &[]),
            Err(ModelError::PolynomialCoefficients)
        );
        assert_eq!(
            NoPolynomials::new(polynomial_knee, points, Functions::splines(&[]), &[]),
            Err(ModelError::BadAxis { joint: 1 })
        );
    }

    /// Every body's frame as OpenSim composes it, `X_PF · X_FM(q) · X_BM⁻¹` offset by offset
    /// (what `frames` computed before its joints were precomputed into steps).
    fn composed<const N: usize, const B: usize, const P: usize>(
        chain: &CustomChain<f64, N, B, P>,
        q: &[f64; N],
    ) -> [BodyFrame<f64>; B] {
        let ground = BodyFrame {
            rotation: Quat::identity(),
            origin: Vec3::zero(),
        };
        let mut frames = [ground; B];
        let function = |f: &Function<f64>, x: f64| match *f {
            Function::Constant(c) => c,
            Function::Linear { slope, intercept } => slope * x + intercept,
            Function::Spline(k) => chain.splines()[k].eval(x),
            Function::Polynomial(k) => chain.polynomials()[k].eval(x),
        };
        let then = |a: &BodyFrame<f64>, o: &Offset<f64>| BodyFrame {
            origin: a.origin + a.rotation.rotate(o.translation),
            rotation: a.rotation * o.rotation,
        };
        let coupled: [f64; MAX_COUPLERS] = core::array::from_fn(|k| {
            chain
                .couplers()
                .get(k)
                .map_or(0.0, |c| function(&c.function, q[c.independent]))
        });
        let value = |d: &Driven<f64>| {
            let x = match d.argument {
                Argument::None => 0.0,
                Argument::Coordinate(i) => q[i],
                Argument::Coupled(k) => coupled[k],
            };
            function(&d.function, x)
        };
        for (b, joint) in chain.joints().iter().enumerate() {
            let parent = joint.parent.map_or(ground, |p| frames[p]);
            let f = then(&parent, &joint.in_parent);
            let mut translation = Vec3::zero();
            for d in &joint.translations {
                translation += d.axis * value(d);
            }
            let mut rotation = f.rotation;
            for d in &joint.rotations {
                rotation = rotation * Quat::from_axis_angle(d.axis, value(d));
            }
            let m = BodyFrame {
                origin: f.origin + f.rotation.rotate(translation),
                rotation,
            };
            frames[b] = then(&m, &joint.in_child.inverse());
        }
        frames
    }

    #[test]
    fn steps_are_the_composed_offsets() {
        // Oriented frames of both kinds (the same orientation on both sides, and not), a
        // walker-knee-like joint with two splines through the same knots (one shared knot
        // search) and a third through others, a coupled pin, a weld, a translation-only joint.
        let x = [-1.0, -0.3, 0.2, 0.9, 1.6];
        let other = [-1.0, -0.2, 0.2, 0.9, 1.6];
        let splines = [
            Spline::from_knots(&x, &[0.0, 0.05, 0.02, -0.04, 0.01]).unwrap(),
            Spline::piecewise_linear(&x, &[0.01, 0.0, -0.01, 0.02, 0.03]).unwrap(),
            Spline::from_knots(&other, &[0.0, 0.1, 0.03, 0.0, 0.2]).unwrap(),
        ];
        let coordinate = |i| {
            (
                Function::Linear {
                    slope: 1.0,
                    intercept: 0.0,
                },
                Argument::Coordinate(i),
            )
        };
        let axis = |v: [f64; 3], (function, argument)| Driven {
            axis: Vec3::from_f64(v),
            function,
            argument,
        };
        let spline = |k, i| (Function::Spline(k), Argument::Coordinate(i));
        let mut joints = [CustomJoint::WELD; 6];
        joints[0].rotations = [
            axis([0., 0., 1.], coordinate(0)),
            axis([1., 0., 0.], coordinate(1)),
            axis([0., 1., 0.], coordinate(2)),
        ];
        joints[0].translations[1] = axis([0., 1., 0.], (Function::Constant(0.9), Argument::None));
        let turned = [-1.64, 1.45, 1.57];
        joints[1].parent = Some(0);
        joints[1].in_parent = Offset::from_xyz(Vec3::new(-0.008, -0.405, -0.0027), turned);
        joints[1].in_child = Offset::from_xyz(Vec3::new(-0.008, -0.004, -0.0015), turned);
        joints[1].rotations = [
            axis([-1., 0., 0.], coordinate(3)),
            axis([0., 0., 1.], spline(0, 3)),
            axis([0., 1., 0.], spline(2, 3)),
        ];
        joints[1].translations = [
            axis([0., 1., 0.], spline(1, 3)),
            axis([0., 0., 1.], spline(0, 3)),
            Driven::NONE,
        ];
        joints[2].parent = Some(1);
        joints[2].in_parent = Offset::from_xyz(Vec3::new(-0.01, -0.43, 0.0), [0.17, -0.1, 0.02]);
        joints[2].in_child = Offset::from_xyz(Vec3::zero(), [0.17, -0.1, 0.02]);
        joints[2].rotations[0] = axis(
            [0., 0., 1.],
            (
                Function::Linear {
                    slope: 0.5,
                    intercept: 0.1,
                },
                Argument::Coupled(0),
            ),
        );
        joints[3].parent = Some(2);
        joints[3].in_parent = Offset::from_xyz(Vec3::new(0.1, 0.0, 0.02), [0.3, 0.0, -0.2]);
        joints[3].in_child = Offset::from_xyz(Vec3::new(0.0, 0.01, 0.0), [-0.1, 0.4, 0.0]);
        joints[3].rotations[0] = axis([0.6, 0.8, 0.], coordinate(4));
        joints[4].parent = Some(3);
        joints[4].in_parent = Offset::from_xyz(Vec3::new(0.05, 0.0, 0.0), [0.0, 0.2, 0.0]);
        joints[4].in_child = Offset::from_xyz(Vec3::new(0.0, 0.0, 0.01), [0.1, 0.0, 0.0]);
        joints[5].parent = Some(0);
        joints[5].in_parent = Offset::from_xyz(Vec3::new(0.0, 0.1, 0.0), [0.0, 0.0, 0.3]);
        joints[5].translations[0] = axis([1., 0., 0.], coordinate(4));
        let points = [
            BodyPoint {
                body: 1,
                offset: joints[1].in_child.translation,
            },
            BodyPoint {
                body: 2,
                offset: Vec3::zero(),
            },
            BodyPoint {
                body: 4,
                offset: Vec3::new(0.05, 0.01, 0.0),
            },
            BodyPoint {
                body: 5,
                offset: Vec3::zero(),
            },
        ];
        let couplers = [Coupler {
            independent: 3,
            function: Function::Spline(2),
        }];
        let chain = CustomChain::<f64, 5, 6, 4>::new(
            joints,
            points,
            Functions::splines(&splines),
            &couplers,
        )
        .unwrap();
        // In the table's order (translations before rotations), one spline-driven axis takes
        // the weights of the one evaluated before it.
        let shares = chain
            .table()
            .drives()
            .filter(|d| d.function() & super::super::packed::Drive::SHARES != 0)
            .count();
        assert_eq!(shares, 1);
        for k in 0..200 {
            let q: [f64; 5] =
                core::array::from_fn(|i| 1.4 * libm_sin(0.61 * (k * 5 + i) as f64 + 0.3));
            let want = composed(&chain, &q);
            for (a, b) in chain.frames(&q).iter().zip(&want) {
                assert!(a.origin.max_abs_diff(b.origin) < 1e-15, "{k}: {a:?} {b:?}");
                let r = a.rotation.conj() * b.rotation;
                assert!(
                    r.x.abs().max(r.y.abs()).max(r.z.abs()) < 1e-15,
                    "{k}: {a:?} {b:?}"
                );
            }
            for (p, point) in chain.forward(&q).iter().zip(&points) {
                let f = &want[point.body];
                let w = f.origin + f.rotation.rotate(point.offset);
                assert!(p.max_abs_diff(w) < 1e-15, "{k}: {p:?} {w:?}");
            }
        }
    }
}
