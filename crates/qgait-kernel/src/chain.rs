//! Models as data: a fixed-size tree of joints evaluated with quaternions.
//!
//! A [`Chain`] is a constant description: joints in topological order, each with its offset from
//! its parent (in the parent's frame), a body-fixed sequence of up to three rotation axes each
//! driven by one input coordinate, and optionally translations that depend on a coordinate
//! through a [`Spline`] (gait2392's knee). Output points are fixed offsets in a joint's frame.
//! HAK, PHAK and gait2392 are three tables of this type; one evaluator serves them all.

use crate::{ModelError, Quat, Real, Spline, Vec3};

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
    /// Name, for messages and CLIs (e.g. `"hip_r"`).
    pub name: &'static str,
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
    pub fn new(
        name: &'static str,
        parent: Option<usize>,
        offset: Vec3<T>,
        axes: &[(Vec3<T>, usize)],
    ) -> Self {
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
            name,
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

/// A named output point fixed in a joint's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointSpec<T> {
    /// Name (e.g. `"toe_r"`).
    pub name: &'static str,
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

impl<T: Real, const N: usize, const J: usize, const P: usize, const S: usize> Chain<T, N, J, P, S> {
    /// Validates and builds a chain. Axes are normalised here, once.
    pub fn new(
        mut joints: [JointSpec<T>; J],
        points: [PointSpec<T>; P],
        mut splines: [SplineTranslation<T>; S],
    ) -> Result<Self, ModelError> {
        for (j, joint) in joints.iter_mut().enumerate() {
            // Joint 0 is the one root; every other joint hangs from an earlier one.
            if joint.parent.map_or(j > 0, |p| p >= j) {
                return Err(ModelError::ParentOrder { joint: j });
            }
            if joint.n_axes > MAX_AXES {
                return Err(ModelError::BadAxis { joint: j });
            }
            if !(joint.offset.x.is_finite()
                && joint.offset.y.is_finite()
                && joint.offset.z.is_finite())
            {
                return Err(ModelError::BadLength);
            }
            for axis in &mut joint.axes[..joint.n_axes] {
                if axis.coordinate >= N {
                    return Err(ModelError::CoordinateOutOfRange { joint: j });
                }
                let len = axis.direction.norm();
                if !(len.is_finite() && len > T::ZERO) {
                    return Err(ModelError::BadAxis { joint: j });
                }
                axis.direction = axis.direction * (T::ONE / len);
            }
        }
        let mut at_origin = [false; P];
        let mut point_kinds = [OffsetKind::General; P];
        for (i, p) in points.iter().enumerate() {
            if p.body >= J {
                return Err(ModelError::BodyOutOfRange { index: i });
            }
            at_origin[i] = p.offset == Vec3::zero();
            point_kinds[i] = OffsetKind::of(p.offset);
        }
        for (i, s) in splines.iter().enumerate() {
            if s.joint >= J {
                return Err(ModelError::BodyOutOfRange { index: i });
            }
            if s.coordinate >= N {
                return Err(ModelError::CoordinateOutOfRange { joint: s.joint });
            }
        }
        if J > u8::MAX as usize || S > u8::MAX as usize {
            return Err(ModelError::BodyOutOfRange { index: J.max(S) });
        }
        // By joint, in order of the description among a joint's splines: an insertion sort
        // (models have a handful of splines).
        for i in 1..S {
            let mut k = i;
            while k > 0 && splines[k - 1].joint > splines[k].joint {
                splines.swap(k - 1, k);
                k -= 1;
            }
        }
        let mut spline_ranges = [(0u8, 0u8); J];
        for (j, range) in spline_ranges.iter_mut().enumerate() {
            let start = splines.iter().take_while(|s| s.joint < j).count();
            let end = start + splines[start..].iter().take_while(|s| s.joint == j).count();
            *range = (start as u8, end as u8);
        }
        let axis_kinds = joints.map(|j| j.axes.map(|a| AxisKind::of(a.direction)));
        let mut offset_kinds = joints.map(|j| OffsetKind::of(j.offset));
        for (kind, range) in offset_kinds.iter_mut().zip(&spline_ranges) {
            if range.0 != range.1 {
                *kind = OffsetKind::General;
            }
        }
        Ok(Self {
            joints,
            points,
            at_origin,
            point_kinds,
            offset_kinds,
            spline_ranges,
            axis_kinds,
            splines,
        })
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
                name: j.name,
                parent: j.parent,
                offset: v(j.offset),
                axes: j.axes.map(|a| Axis {
                    direction: v(a.direction),
                    coordinate: a.coordinate,
                }),
                n_axes: j.n_axes,
            }),
            points: self.points.map(|p| PointSpec {
                name: p.name,
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
