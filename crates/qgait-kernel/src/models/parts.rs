//! The parts an OpenSim lower-limb chain is described with ([`CustomJoint`]s of [`Driven`]
//! axes, [`Function`]s of an [`Argument`], [`Coupler`]s, [`BodyPoint`]s) and what its
//! evaluation precomputes from each joint ([`Step`]): the vocabulary of
//! [`CustomChain`](super::CustomChain), which describes a chain, and of
//! [`PackedChain`](super::packed::PackedChain), which packs and evaluates it. Re-exported by
//! [`custom`](super::custom).

use crate::{Polynomial, Quat, Real, Spline, Vec3};

/// Most knots of one spline (Rajagopal's knee: 13).
pub const MAX_SPLINE_KNOTS: usize = 16;
/// Most splines one chain holds (Rajagopal: four per knee).
pub const MAX_SPLINES: usize = 12;
/// Most polynomials one chain holds (Rajagopal-Lai-Uhlrich 2023: five per knee).
pub const MAX_POLYNOMIALS: usize = 12;
/// Most coupled coordinates one chain holds.
pub const MAX_COUPLERS: usize = 4;

/// What a transform axis's value (radians or metres) is a function of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Argument {
    /// Nothing: the function is evaluated at 0 (a constant, or a coordinate absent from the
    /// inputs held at its default, baked in by whoever builds the table).
    None,
    /// Input coordinate `i`.
    Coordinate(usize),
    /// Coupled coordinate `k` (see [`Coupler`]).
    Coupled(usize),
}

/// A function of one argument.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Function<T> {
    /// OpenSim `Constant`.
    Constant(T),
    /// OpenSim `LinearFunction`: `slope · x + intercept`.
    Linear {
        /// Slope.
        slope: T,
        /// Value at 0.
        intercept: T,
    },
    /// Spline `k` of the chain's spline table (a `SimmSpline` or a `PiecewiseLinearFunction`).
    Spline(usize),
    /// Polynomial `k` of the chain's polynomial table (a `PolynomialFunction`).
    Polynomial(usize),
}

/// One transform axis: a direction and how far along or about it, as a function of an argument.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driven<T> {
    /// Direction (normalised by the chain); rotation axes in the frame left by the joint's
    /// earlier rotations, translation axes in the parent offset frame.
    pub axis: Vec3<T>,
    /// The value as a function of `argument`.
    pub function: Function<T>,
    /// What the function is evaluated at.
    pub argument: Argument,
}

impl<T: Real> Driven<T> {
    /// Nothing (a zero constant about x).
    pub const NONE: Self = Self {
        axis: Vec3::new(T::ONE, T::ZERO, T::ZERO),
        function: Function::Constant(T::ZERO),
        argument: Argument::None,
    };
}

/// A fixed transform: a translation and an orientation (unit quaternion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset<T> {
    /// Origin of the frame in its body (metres).
    pub translation: Vec3<T>,
    /// Orientation of the frame in its body.
    pub rotation: Quat<T>,
}

impl<T: Real> Offset<T> {
    /// No offset.
    pub const IDENTITY: Self = Self {
        translation: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        rotation: Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO),
    };

    /// An OpenSim `PhysicalOffsetFrame`: `translation`, and `orientation` as body-fixed x-y-z
    /// angles (radians).
    pub fn from_xyz(translation: Vec3<T>, orientation: [T; 3]) -> Self {
        let mut rotation = Quat::identity();
        for (k, a) in orientation.iter().enumerate() {
            let (s, c) = a.half_angle_sin_cos();
            rotation = match k {
                0 => rotation.then_about_x(s, c),
                1 => rotation.then_about_y(s, c),
                _ => rotation.then_about_z(s, c),
            };
        }
        Self {
            translation,
            rotation,
        }
    }

    /// This offset followed by `o` (`o` given in this frame).
    pub(super) fn then(&self, o: &Self) -> Self {
        Self {
            translation: self.translation + self.rotation.rotate(o.translation),
            rotation: self.rotation * o.rotation,
        }
    }

    /// The inverse transform.
    pub(super) fn inverse(&self) -> Self {
        let rotation = self.rotation.conj();
        Self {
            translation: -rotation.rotate(self.translation),
            rotation,
        }
    }
}

/// The joint that moves one body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CustomJoint<T> {
    /// The parent body (an earlier one), or `None` for ground (body 0 only).
    pub parent: Option<usize>,
    /// The parent offset frame `F` in the parent body.
    pub in_parent: Offset<T>,
    /// The child offset frame `M` in the moved body.
    pub in_child: Offset<T>,
    /// Rotations, body-fixed, in order (unused ones [`Driven::NONE`]).
    pub rotations: [Driven<T>; 3],
    /// Translations along axes of `F`, after the rotations.
    pub translations: [Driven<T>; 3],
}

impl<T: Real> CustomJoint<T> {
    /// A weld at the origins (what an unset table holds).
    pub const WELD: Self = Self {
        parent: None,
        in_parent: Offset::IDENTITY,
        in_child: Offset::IDENTITY,
        rotations: [Driven::NONE; 3],
        translations: [Driven::NONE; 3],
    };
}

/// A coupled coordinate: a function of an input coordinate (OpenSim's
/// `CoordinateCouplerConstraint`, dependent = f(independent)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coupler<T> {
    /// The independent input coordinate.
    pub independent: usize,
    /// The coupling function (a spline refers to the chain's spline table).
    pub function: Function<T>,
}

/// The function tables a chain's [`Function`]s index.
#[derive(Clone, Copy, Debug)]
pub struct Functions<'a, T, const K: usize> {
    /// [`Function::Spline`]`(k)` is `splines[k]`.
    pub splines: &'a [Spline<T, K>],
    /// [`Function::Polynomial`]`(k)` is `polynomials[k]`.
    pub polynomials: &'a [Polynomial<T>],
}

impl<'a, T, const K: usize> Functions<'a, T, K> {
    /// Splines only.
    pub fn splines(splines: &'a [Spline<T, K>]) -> Self {
        Functions {
            splines,
            polynomials: &[],
        }
    }
}

/// An output point fixed in a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyPoint<T> {
    /// The body.
    pub body: usize,
    /// Position in the body's frame (metres).
    pub offset: Vec3<T>,
}

/// A joint as [`CustomChain::frames`](super::CustomChain::frames) evaluates it, precomputed
/// from the [`CustomJoint`] by `CustomChain::rebuild`. With `R_F`, `t_F` and `R_M`, `t_M` the parent and child offset
/// frames, the body's frame on its parent's is
/// `R = R_P · (R_F Q₁ R_F⁻¹)(R_F Q₂ R_F⁻¹)(R_F Q₃ R_F⁻¹) · R_F R_M⁻¹` and
/// `o = o_P + R_P (t_F + R_F Σ xᵢ dᵢ) − R t_M`: the rotation axes turned into the parent
/// body's frame once, so an oriented pin whose frames share their orientation (Rajagopal's
/// ankles) is one product about its axis, and the identity rotations and zero translations
/// left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Step<T> {
    /// The moving rotation axes in the parent body's frame (`R_F aᵢ`).
    pub(super) axes: [Vec3<T>; 3],
    /// After the rotations: `R_F R_M⁻¹` and `−t_M`. For a joint that does not move, the whole
    /// joint, `F · M⁻¹`, applied to the parent's frame.
    pub(super) end: Offset<T>,
    /// Whether each of `axes` is a coordinate axis.
    pub(super) kinds: [AxisKind; 3],
    /// How many rotations and translations move (the others, zero constants, are dropped by
    /// [`CustomChain::new`](super::CustomChain::new): no work for a locked coordinate or an unused axis).
    pub(super) moving: (u8, u8),
    /// [`Shape`] bits: which parts of the joint are not the identity.
    pub(super) shape: u8,
}

/// Bits of [`Step::shape`].
pub(super) struct Shape;

impl Shape {
    /// `t_F` is not zero or translations move: `R_P (t_F + …)` is computed.
    pub(super) const START: u8 = 1;
    /// `R_F` is not the identity: translations are turned by it.
    pub(super) const ORIENTED: u8 = 2;
    /// `R_F R_M⁻¹` is not the identity.
    pub(super) const TURNS: u8 = 4;
    /// `t_M` is not zero.
    pub(super) const ENDS_AWAY: u8 = 8;
}

/// How a rotation axis is turned about: a coordinate axis (the cheaper product) or any.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum AxisKind {
    /// Any axis (all zero bits: what an empty table holds).
    General = 0,
    /// +x.
    X,
    /// +y.
    Y,
    /// +z.
    Z,
}

/// A body's frame in ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyFrame<T> {
    /// Orientation (body to ground).
    pub rotation: Quat<T>,
    /// Origin in ground.
    pub origin: Vec3<T>,
}

impl<T: Real> Step<T> {
    /// The step of `joint` (its zero constants dropped, `moving` the counts left).
    pub(super) fn of(joint: &CustomJoint<T>, moving: (u8, u8)) -> Self {
        let (f, m) = (&joint.in_parent, &joint.in_child);
        let identity = Quat::identity();
        let mut step = Step {
            axes: [Vec3::zero(); 3],
            end: Offset::IDENTITY,
            kinds: [AxisKind::General; 3],
            moving,
            shape: 0,
        };
        if moving == (0, 0) {
            // A joint that does not move (a weld, a locked pin) is one fixed offset: `F · M⁻¹`
            // folded here, so `frames` applies one offset instead of two.
            step.end = f.then(&m.inverse());
            return step;
        }
        let oriented = f.rotation != identity;
        for ((axis, kind), d) in step
            .axes
            .iter_mut()
            .zip(&mut step.kinds)
            .zip(&joint.rotations)
        {
            // (Exactly the axis when `F` is not turned: coordinate axes stay coordinate axes.)
            *axis = if oriented {
                let a = f.rotation.rotate(d.axis);
                a * (T::ONE / a.norm())
            } else {
                d.axis
            };
            let (one, zero) = (T::ONE, T::ZERO);
            *kind = if *axis == Vec3::new(one, zero, zero) {
                AxisKind::X
            } else if *axis == Vec3::new(zero, one, zero) {
                AxisKind::Y
            } else if *axis == Vec3::new(zero, zero, one) {
                AxisKind::Z
            } else {
                AxisKind::General
            };
        }
        // The same orientation on both sides (a pin's frames, a walker knee's) leaves no
        // rotation after the joint's own.
        let turn = if f.rotation == m.rotation {
            identity
        } else {
            f.rotation * m.rotation.conj()
        };
        step.end = Offset {
            translation: -m.translation,
            rotation: turn,
        };
        let zero = Vec3::zero();
        for (flag, on) in [
            (Shape::START, f.translation != zero || moving.1 > 0),
            (Shape::ORIENTED, oriented),
            (Shape::TURNS, turn != identity),
            (Shape::ENDS_AWAY, m.translation != zero),
        ] {
            if on {
                step.shape |= flag;
            }
        }
        step
    }
}

impl<T: Real> BodyFrame<T> {
    /// The ground frame.
    pub(crate) const GROUND: Self = Self {
        rotation: Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO),
        origin: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
    };
}

/// A chain's description as [`PackedChain::pack`](super::packed::PackedChain::pack) reads it:
/// [`CustomChain::parts`](super::CustomChain::parts).
#[derive(Clone, Copy, Debug)]
pub(super) struct ChainParts<'a, T, const K: usize> {
    /// The joints, by body.
    pub(super) joints: &'a [CustomJoint<T>],
    /// What each joint's evaluation needs.
    pub(super) steps: &'a [Step<T>],
    /// The output points.
    pub(super) points: &'a [BodyPoint<T>],
    /// The splines in use.
    pub(super) splines: &'a [Spline<T, K>],
    /// The polynomials in use.
    pub(super) polynomials: &'a [Polynomial<T>],
    /// The coupled coordinates in use.
    pub(super) couplers: &'a [Coupler<T>],
}
