//! Models as data: a fixed-size tree of joints evaluated with quaternions.
//!
//! A [`Chain`] is a constant description: joints in topological order, each with its offset from
//! its parent (in the parent's frame), a body-fixed sequence of up to three rotation axes each
//! driven by one input coordinate, and optionally translations that depend on a coordinate
//! through a [`Spline`] (gait2392's knee). Output points are fixed offsets in a joint's frame.
//! HAK, PHAK and gait2392 are three tables of this type, all evaluated by [`Chain::forward`];
//! an imported OpenSim chain is evaluated by its
//! [`PackedChain`](crate::models::packed::PackedChain) instead.

use crate::{ModelError, Quat, Real, Spline, Vec3};

mod motion;

/// Most rotation axes one joint has (OpenSim's CustomJoint: three).
pub const MAX_AXES: usize = 3;

/// One rotation axis of a joint, driven by an input coordinate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis<T> {
    /// Unit direction in the joint's frame after the earlier axes of the same joint
    /// (body-fixed sequence). Normalised by [`Chain::new`].
    pub direction: Vec3<T>,
    /// Index of the coordinate (radians) in the chain's input array.
    pub coordinate: usize,
}

/// One joint: where its frame sits on its parent and how it rotates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointSpec<T> {
    /// Index of the parent joint (an earlier one), or `None` for the root (the ground frame is
    /// its parent). The root is joint 0, and there is one.
    pub parent: Option<usize>,
    /// Location of this joint's centre in the parent's frame (metres).
    pub offset: Vec3<T>,
    /// Body-fixed rotation sequence; only the first `n_axes` are used.
    pub axes: [Axis<T>; MAX_AXES],
    /// How many of `axes` this joint has (0 to [`MAX_AXES`]).
    pub n_axes: usize,
}

impl<T: Real> JointSpec<T> {
    /// A joint with the given axes `(direction, coordinate)`, in order.
    pub fn new(parent: Option<usize>, offset: Vec3<T>, axes: &[(Vec3<T>, usize)]) -> Self {
        let mut a = [Axis {
            direction: Vec3::zero(),
            coordinate: 0,
        }; MAX_AXES];
        let n_axes = axes.len().min(MAX_AXES);
        for (slot, (direction, coordinate)) in a.iter_mut().zip(axes) {
            *slot = Axis {
                direction: *direction,
                coordinate: *coordinate,
            };
        }
        // More than MAX_AXES is reported by Chain::new through n_axes mismatch.
        Self {
            parent,
            offset,
            axes: a,
            n_axes: if axes.len() > MAX_AXES {
                MAX_AXES + 1
            } else {
                n_axes
            },
        }
    }
}

/// A translation of a joint centre, along a fixed direction of the parent frame, by a spline of
/// one coordinate (OpenSim: a CustomJoint translation driven by a function).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplineTranslation<T> {
    /// The joint whose centre moves.
    pub joint: usize,
    /// Direction in the parent frame (not rotated by the joint's own rotation).
    pub direction: Vec3<T>,
    /// The driving coordinate.
    pub coordinate: usize,
    /// Displacement (metres) as a function of the coordinate (radians).
    pub spline: Spline<T>,
}

/// An output point fixed in a joint's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSpec<T> {
    /// The joint whose frame carries the point.
    pub body: usize,
    /// Position in that frame (metres); zero for the joint centre itself.
    pub offset: Vec3<T>,
}

/// How an axis composes onto a rotation: the coordinate axes take a cheaper product.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum AxisKind {
    X,
    Y,
    Z,
    General,
}

impl AxisKind {
    fn of<T: Real>(d: Vec3<T>) -> Self {
        let (o, i) = (T::ZERO, T::ONE);
        match (d.x == i, d.y == i, d.z == i) {
            (true, _, _) if d.y == o && d.z == o => AxisKind::X,
            (_, true, _) if d.x == o && d.z == o => AxisKind::Y,
            (_, _, true) if d.x == o && d.y == o => AxisKind::Z,
            _ => AxisKind::General,
        }
    }
}

/// How an offset is rotated: along a coordinate axis it is one column of the rotation matrix,
/// and a zero offset (a root at the origin, a point at its joint's centre) stays zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OffsetKind {
    Zero,
    X,
    Y,
    Z,
    General,
}

impl OffsetKind {
    fn of<T: Real>(v: Vec3<T>) -> Self {
        let o = T::ZERO;
        match (v.x != o, v.y != o, v.z != o) {
            (false, false, false) => OffsetKind::Zero,
            (true, false, false) => OffsetKind::X,
            (false, true, false) => OffsetKind::Y,
            (false, false, true) => OffsetKind::Z,
            _ => OffsetKind::General,
        }
    }

    /// `R(rotation) v` for a `v` of this kind.
    #[inline(always)]
    fn rotate<T: Real>(self, rotation: Quat<T>, v: Vec3<T>) -> Vec3<T> {
        match self {
            OffsetKind::Zero => Vec3::zero(),
            OffsetKind::X => rotation.rotate_x(v.x),
            OffsetKind::Y => rotation.rotate_y(v.y),
            OffsetKind::Z => rotation.rotate_z(v.z),
            OffsetKind::General => rotation.rotate(v),
        }
    }
}

/// Position and orientation of a joint frame in the ground frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame<T> {
    /// Orientation (unit quaternion, frame to ground).
    pub rotation: Quat<T>,
    /// Origin (the joint centre) in ground.
    pub origin: Vec3<T>,
}

impl<T: Real> Frame<T> {
    /// All zeros (not a rotation): what a frame array holds before it is filled.
    const UNSET: Self = Self {
        rotation: Quat::new(T::ZERO, T::ZERO, T::ZERO, T::ZERO),
        origin: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
    };
    /// The ground frame.
    pub fn ground() -> Self {
        Self {
            rotation: Quat::identity(),
            origin: Vec3::zero(),
        }
    }
    /// Maps a point given in this frame to ground.
    #[inline(always)]
    pub fn transform(&self, p: Vec3<T>) -> Vec3<T> {
        self.origin + self.rotation.rotate(p)
    }
}

/// A validated model: `N` input coordinates, `J` joints, `P` output points and `S` spline
/// translations, all in fixed-size arrays (no allocation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chain<T, const N: usize, const J: usize, const P: usize, const S: usize> {
    joints: [JointSpec<T>; J],
    points: [PointSpec<T>; P],
    /// Whether each point is its joint's centre (nothing to rotate).
    at_origin: [bool; P],
    /// How each point's offset is rotated.
    point_kinds: [OffsetKind; P],
    /// How each joint's offset is rotated (`General` when splines move it).
    offset_kinds: [OffsetKind; J],
    /// For each joint, the range of `splines` (sorted by joint) that move it.
    spline_ranges: [(u8, u8); J],
    /// For each joint axis, whether it is +x, +y, +z or another direction.
    axis_kinds: [[AxisKind; MAX_AXES]; J],
    splines: [SplineTranslation<T>; S],
}

/// A model description given piece by piece: what [`Chain::rebuild`] and [`Chain::check`]
/// read. A model implements it over its numbers (segment lengths, a gait2392 geometry), so a
/// chain can be rebuilt where it lives without the whole description ever being a temporary
/// (a device swapping models in a fixed slot). The pieces must be the same every time they
/// are asked for.
pub trait Description<T> {
    /// Joint `j`, for `j` below the chain's `J`.
    fn joint(&self, j: usize) -> JointSpec<T>;
    /// Output point `i`, for `i` below the chain's `P`.
    fn point(&self, i: usize) -> PointSpec<T>;
    /// Spline translation `s`, for `s` below the chain's `S` (building its spline can fail).
    fn spline(&self, s: usize) -> Result<SplineTranslation<T>, ModelError>;
}

/// A description held in three arrays (what [`Chain::new`] takes).
struct Tables<T, const J: usize, const P: usize, const S: usize> {
    joints: [JointSpec<T>; J],
    points: [PointSpec<T>; P],
    splines: [SplineTranslation<T>; S],
}

impl<T: Real, const J: usize, const P: usize, const S: usize> Description<T>
    for Tables<T, J, P, S>
{
    fn joint(&self, j: usize) -> JointSpec<T> {
        self.joints[j]
    }
    fn point(&self, i: usize) -> PointSpec<T> {
        self.points[i]
    }
    fn spline(&self, s: usize) -> Result<SplineTranslation<T>, ModelError> {
        Ok(self.splines[s])
    }
}

impl<T: Real> JointSpec<T> {
    /// No parent, no offset, no axes (all zero bits).
    const EMPTY: Self = Self {
        parent: None,
        offset: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        axes: [Axis {
            direction: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            coordinate: 0,
        }; MAX_AXES],
        n_axes: 0,
    };

    /// Checks joint `j` of a chain of `n` coordinates; returns its axes' lengths.
    fn check(&self, j: usize, n: usize) -> Result<[T; MAX_AXES], ModelError> {
        // Joint 0 is the one root; every other joint hangs from an earlier one.
        if self.parent.map_or(j > 0, |p| p >= j) {
            return Err(ModelError::ParentOrder { joint: j });
        }
        if self.n_axes > MAX_AXES {
            return Err(ModelError::BadAxis { joint: j });
        }
        if !(self.offset.x.is_finite() && self.offset.y.is_finite() && self.offset.z.is_finite()) {
            return Err(ModelError::BadLength);
        }
        let mut lengths = [T::ONE; MAX_AXES];
        for (axis, length) in self.axes[..self.n_axes].iter().zip(&mut lengths) {
            if axis.coordinate >= n {
                return Err(ModelError::CoordinateOutOfRange { joint: j });
            }
            *length = axis.direction.norm();
            if !(length.is_finite() && *length > T::ZERO) {
                return Err(ModelError::BadAxis { joint: j });
            }
        }
        Ok(lengths)
    }
}

impl<T: Real, const N: usize, const J: usize, const P: usize, const S: usize> Chain<T, N, J, P, S> {
    /// The chain with nothing set (all zero bits): every joint a root at the origin without
    /// axes, every point at the origin, every spline without knots; it maps any input to the
    /// origin. A slot for [`rebuild`](Self::rebuild), e.g. where a device keeps its model.
    pub const EMPTY: Self = Self {
        joints: [JointSpec::EMPTY; J],
        points: [PointSpec {
            body: 0,
            offset: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
        }; P],
        at_origin: [false; P],
        point_kinds: [OffsetKind::Zero; P],
        offset_kinds: [OffsetKind::Zero; J],
        spline_ranges: [(0, 0); J],
        axis_kinds: [[AxisKind::X; MAX_AXES]; J],
        splines: [SplineTranslation {
            joint: 0,
            direction: Vec3::new(T::ZERO, T::ZERO, T::ZERO),
            coordinate: 0,
            spline: Spline::EMPTY,
        }; S],
    };

    /// Validates and builds a chain. Axes are normalised here, once.
    pub fn new(
        joints: [JointSpec<T>; J],
        points: [PointSpec<T>; P],
        splines: [SplineTranslation<T>; S],
    ) -> Result<Self, ModelError> {
        let mut chain = Self::EMPTY;
        chain.rebuild(&Tables {
            joints,
            points,
            splines,
        })?;
        Ok(chain)
    }

    /// Checks a description as [`rebuild`](Self::rebuild) would, storing nothing: `Ok` means
    /// that `rebuild` with it succeeds.
    pub fn check(description: &impl Description<T>) -> Result<(), ModelError> {
        if J > u8::MAX as usize || S > u8::MAX as usize {
            return Err(ModelError::BodyOutOfRange { index: J.max(S) });
        }
        for j in 0..J {
            description.joint(j).check(j, N)?;
        }
        for i in 0..P {
            if description.point(i).body >= J {
                return Err(ModelError::BodyOutOfRange { index: i });
            }
        }
        for i in 0..S {
            let s = description.spline(i)?;
            if s.joint >= J {
                return Err(ModelError::BodyOutOfRange { index: i });
            }
            if s.coordinate >= N {
                return Err(ModelError::CoordinateOutOfRange { joint: s.joint });
            }
        }
        Ok(())
    }

    /// Rebuilds this chain in place from `description`, validated first
    /// ([`check`](Self::check)): on an error the chain is unchanged. Only one piece of the
    /// description at a time is a temporary, so a model can be swapped where it lives with
    /// little stack. Axes are normalised here, once.
    ///
    /// (A description whose pieces change between the check and the writes leaves a mix of
    /// old and new pieces, each valid on its own, so evaluating the chain still cannot fail.)
    pub fn rebuild(&mut self, description: &impl Description<T>) -> Result<(), ModelError> {
        Self::check(description)?;
        for j in 0..J {
            let mut joint = description.joint(j);
            let lengths = joint.check(j, N)?;
            let n_axes = joint.n_axes;
            for (axis, length) in joint.axes[..n_axes].iter_mut().zip(lengths) {
                axis.direction = axis.direction * (T::ONE / length);
            }
            self.joints[j] = joint;
            self.axis_kinds[j] = joint.axes.map(|a| AxisKind::of(a.direction));
        }
        for i in 0..P {
            let point = description.point(i);
            self.points[i] = point;
            self.at_origin[i] = point.offset == Vec3::zero();
            self.point_kinds[i] = OffsetKind::of(point.offset);
        }
        for i in 0..S {
            self.splines[i] = description.spline(i)?;
        }
        // By joint, in order of the description among a joint's splines: an insertion sort
        // (models have a handful of splines).
        for i in 1..S {
            let mut k = i;
            while k > 0 && self.splines[k - 1].joint > self.splines[k].joint {
                self.splines.swap(k - 1, k);
                k -= 1;
            }
        }
        for j in 0..J {
            let start = self.splines.iter().take_while(|s| s.joint < j).count();
            let end = start
                + self.splines[start..]
                    .iter()
                    .take_while(|s| s.joint == j)
                    .count();
            self.spline_ranges[j] = (start as u8, end as u8);
            // Splines move the joint centre along their directions: a general offset.
            self.offset_kinds[j] = if start != end {
                OffsetKind::General
            } else {
                OffsetKind::of(self.joints[j].offset)
            };
        }
        Ok(())
    }

    /// The joints, in evaluation order.
    pub fn joints(&self) -> &[JointSpec<T>; J] {
        &self.joints
    }

    /// The output points, in output order.
    pub fn points(&self) -> &[PointSpec<T>; P] {
        &self.points
    }

    /// The coordinate-driven translations.
    pub fn splines(&self) -> &[SplineTranslation<T>; S] {
        &self.splines
    }

    /// Offset of joint `j` from its parent for coordinates `q`: the constant offset plus the
    /// joint's spline translations.
    #[inline(always)]
    pub fn offset(&self, j: usize, q: &[T; N]) -> Vec3<T> {
        let mut offset = self.joints[j].offset;
        if S > 0 {
            // (A compile-time test: models without splines carry no spline code.)
            let (start, end) = self.spline_ranges[j];
            for s in &self.splines[start as usize..end as usize] {
                offset += s.direction * s.spline.eval(q[s.coordinate]);
            }
        }
        offset
    }

    /// Every joint frame in ground for coordinates `q` (radians). One half-angle sine/cosine
    /// pair per axis, one quaternion product per axis (half of one for the coordinate axes), one
    /// vector rotation per non-root joint.
    #[inline(always)]
    pub fn frames(&self, q: &[T; N]) -> [Frame<T>; J] {
        if J == 0 {
            return [Frame::UNSET; J];
        }
        // The spline translations first, so that the joint loop makes no calls.
        let mut slide = [T::ZERO; S];
        for (value, s) in slide.iter_mut().zip(&self.splines) {
            *value = s.spline.eval(q[s.coordinate]);
        }
        // Joint 0 is a root (parents come first), so its frame can fill the array that the
        // other joints then overwrite in order: no separate initialisation pass.
        let mut frames = [self.joint_frame(0, Frame::ground(), q, &slide); J];
        for j in 1..J {
            // (Chain::new: every joint after the first has an earlier parent.)
            let parent = frames[self.joints[j].parent.unwrap_or(0)];
            frames[j] = self.joint_frame(j, parent, q, &slide);
        }
        frames
    }

    /// The frame of joint `j` given its parent's frame (ground for a root) and the values of
    /// the spline translations.
    #[inline(always)]
    fn joint_frame(&self, j: usize, parent: Frame<T>, q: &[T; N], slide: &[T; S]) -> Frame<T> {
        let joint = &self.joints[j];
        let mut offset = joint.offset;
        if S > 0 {
            let (start, end) = self.spline_ranges[j];
            #[allow(clippy::needless_range_loop)] // (55 instructions fewer than zipped slices)
            for k in start as usize..end as usize {
                offset += self.splines[k].direction * slide[k];
            }
        }
        let mut rotation = parent.rotation;
        let origin = parent.origin + self.offset_kinds[j].rotate(rotation, offset);
        for (axis, kind) in joint.axes[..joint.n_axes].iter().zip(&self.axis_kinds[j]) {
            let (s, c) = q[axis.coordinate].half_angle_sin_cos();
            rotation = match kind {
                AxisKind::X => rotation.then_about_x(s, c),
                AxisKind::Y => rotation.then_about_y(s, c),
                AxisKind::Z => rotation.then_about_z(s, c),
                AxisKind::General => rotation * Quat::from_axis_half_sin_cos(axis.direction, s, c),
            };
        }
        Frame { rotation, origin }
    }

    /// The output points in ground for coordinates `q` (radians): forward kinematics.
    #[inline(always)]
    pub fn forward(&self, q: &[T; N]) -> [Vec3<T>; P] {
        let frames = self.frames(q);
        let mut out = [Vec3::zero(); P];
        for (i, p) in self.points.iter().enumerate() {
            let f = &frames[p.body];
            out[i] = if self.at_origin[i] {
                f.origin
            } else {
                f.origin + self.point_kinds[i].rotate(f.rotation, p.offset)
            };
        }
        out
    }

    /// Converts the whole description to another precision (e.g. an `f64` model for the
    /// firmware's `f32`).
    pub fn cast<U: Real>(&self) -> Chain<U, N, J, P, S> {
        let v = |v: Vec3<T>| v.cast::<U>();
        Chain {
            joints: self.joints.map(|j| JointSpec {
                parent: j.parent,
                offset: v(j.offset),
                axes: j.axes.map(|a| Axis {
                    direction: v(a.direction),
                    coordinate: a.coordinate,
                }),
                n_axes: j.n_axes,
            }),
            points: self.points.map(|p| PointSpec {
                body: p.body,
                offset: v(p.offset),
            }),
            at_origin: self.at_origin,
            point_kinds: self.point_kinds,
            offset_kinds: self.offset_kinds,
            spline_ranges: self.spline_ranges,
            axis_kinds: self.axis_kinds,
            splines: self.splines.map(|s| SplineTranslation {
                joint: s.joint,
                direction: v(s.direction),
                coordinate: s.coordinate,
                spline: s.spline.cast(),
            }),
        }
    }
}
