//! A [`CustomChain`](super::CustomChain) packed for a device: the same forward kinematics from
//! a table that holds only what is not the identity.
//! [`CustomChain::packed`](super::CustomChain::packed) builds it (on the host, from the
//! validated chain); [`PackedChain::forward`] evaluates it; in `f32` its bytes
//! ([`PackedChain::IMAGE_LEN`], [`read_image`](PackedChain::read_image),
//! [`write_image`](PackedChain::write_image)) are what a host uploads into a hub's model slot.
//!
//! The table is byte codes and a pool of numbers:
//! - per joint a [`JointCode`]: its parent, how many rotations and translations move, which
//!   parts of the joint are not the identity (the chain's evaluation steps), each
//!   rotation's axis kind, and where its numbers start in the pool (in a fixed order, see
//!   [`JointCode`]);
//! - per coupled coordinate, then per moving axis, joint by joint, a [`Drive`]: its function
//!   and the argument it is evaluated at;
//! - splines in Hermite form: per knot its value and slope (the same cubic between two knots as
//!   the Forsythe-Malcolm-Moler coefficients, two numbers a knot instead of four), splines
//!   through the same abscissae (a knee's four) sharing them;
//! - polynomials' coefficients and the output points.
//!
//! [`motions`](PackedChain::motions), [`forward_motion`](PackedChain::forward_motion) and
//! [`forward_velocities`](PackedChain::forward_velocities) are its differential kinematics (see
//! [`crate::differential`]): the same evaluator carrying each body's rates beside its frame,
//! the drives' rates by the chain rule through their functions' analytic derivatives.
//!
//! Every read is bounded without panicking (a read past the pool reads its last numbers, an
//! index past a table reads nothing), so a table of any content evaluates without panicking.
//!
//! The image of a table (`f32`), in bytes: the joints' codes ([`JointCode::LEN`] each), the
//! drives' (2 each), the points' (2 each), the splines' ([`SplineCode::LEN`] each), the
//! polynomials' (3 each), the counts (the drives in use, how many of them are coupled
//! coordinates, where the points' offsets start and how many numbers are in use, the last two
//! `u16` little-endian), then the `W` numbers, each `f32` little-endian.

use super::parts::{
    Argument, AxisKind, BodyFrame, ChainParts, Driven, Function, Shape, MAX_COUPLERS,
};
use crate::differential::{Carried, ChainRule, FrameMotion, Jet, PointMotion, Twist};
use crate::polynomial::with_derivatives;
use crate::{Quat, Real, Vec3};

/// What drives one moving axis: its function byte and its argument byte.
///
/// Function, bits 6-7: [`Drive::LINEAR`] (two numbers in the pool: slope, value at 0),
/// [`Drive::SPLINE`], [`Drive::POLYNOMIAL`] (bits 0-4: which), or [`Drive::IDENTITY`] (the
/// argument itself); bit 5, [`Drive::SHARES`]: a spline that takes the weights of the
/// spline-driven axis evaluated before it (the same argument and abscissae). Argument, bits 6-7:
/// [`Drive::NONE`] (0), [`Drive::COORDINATE`] or [`Drive::COUPLED`] (coupled coordinate `k`:
/// the value of drive `k`, one of the first drives); bits 0-5: which.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Drive(pub [u8; 2]);

impl Drive {
    /// `slope · x + intercept`.
    pub const LINEAR: u8 = 0;
    /// Spline `k` of the table.
    pub const SPLINE: u8 = 1 << 6;
    /// Polynomial `k` of the table.
    pub const POLYNOMIAL: u8 = 2 << 6;
    /// `x`.
    pub const IDENTITY: u8 = 3 << 6;
    /// With [`Drive::SPLINE`]: the weights of the spline before it.
    pub const SHARES: u8 = 1 << 5;
    /// Evaluated at 0.
    pub const NONE: u8 = 0;
    /// Input coordinate `i`.
    pub const COORDINATE: u8 = 1 << 6;
    /// Coupled coordinate `k`.
    pub const COUPLED: u8 = 2 << 6;
    const KIND: u8 = 3 << 6;
    const INDEX: u8 = 0x3f;
    const FUNCTION_INDEX: u8 = 0x1f;

    /// The function byte.
    #[inline(always)]
    pub fn function(self) -> u8 {
        self.0[0]
    }

    /// The argument byte.
    #[inline(always)]
    pub fn argument(self) -> u8 {
        self.0[1]
    }
}

/// A code's `LEN` and its fields at their bytes, as the code's docs lay them out: `u8` and
/// `u16` (little-endian) fields are read as indices, `byte` fields as they are.
macro_rules! code_fields {
    ($code:ident, $len:literal, { $($field:ident: $kind:ident @ $at:literal),* $(,)? }) => {
        impl $code {
            /// Bytes of one code.
            pub const LEN: usize = $len;
            $(
                #[inline(always)]
                fn $field(self) -> code_fields!(@type $kind) {
                    code_fields!(@read $kind, self.0, $at)
                }
            )*
        }
    };
    (@type byte) => { u8 };
    (@type $kind:ident) => { usize };
    (@read byte, $code:expr, $at:literal) => { $code[$at] };
    (@read u8, $code:expr, $at:literal) => { usize::from($code[$at]) };
    (@read u16, $code:expr, $at:literal) => { le16(&$code, $at) };
}

/// One joint: `[parent, moving, shape, kinds, words (u16 little-endian)]`.
///
/// - `parent`: the parent body (ignored for body 0, which hangs on ground);
/// - `moving`: moving rotations (bits 0-1) and translations (bits 2-3); their drives are the
///   next ones of the table, translations first, then rotations, and their
///   [`Drive::LINEAR`] slopes and intercepts are at the pool's start (in the drives' order);
/// - `shape`: bits 1 `START`, 4 `TURNS`, 8 `ENDS_AWAY` (below; bit 2 is not used);
/// - `kinds`: each moving rotation's axis, two bits each from bit 0: 0 general, 1 +x, 2 +y,
///   3 +z;
/// - `words`: the joint's first number in the pool. From there, in order: with `START` the
///   parent frame's origin `t_F` (3) and each moving translation's axis in the parent body's
///   frame (3, `R_F dᵢ`); each moving rotation about a general axis, the axis in the parent
///   body's frame (3, `R_F aᵢ`); with `TURNS` the
///   rotation after the joint's own, `R_F R_M⁻¹` (4); with `ENDS_AWAY`, `−t_M` (3). A joint
///   that does not move (a weld) has its whole offset `F · M⁻¹` as its `t_F` and its turn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct JointCode(pub [u8; JointCode::LEN]);

code_fields!(JointCode, 6, { parent: u8 @ 0, shape: byte @ 2, kinds: byte @ 3, words: u16 @ 4 });

impl JointCode {
    /// Moving rotations and translations.
    #[inline(always)]
    fn moving(self) -> (usize, usize) {
        (usize::from(self.0[1] & 3), usize::from(self.0[1] >> 2 & 3))
    }
}

/// One spline in Hermite form: `[x, values (u16 little-endian each), knots, linear]`: `knots`
/// abscissae at `x` in the pool, then `knots` values and `knots` slopes at `values`; `linear`
/// 1: straight between the knots (a `PiecewiseLinearFunction`), the slopes each segment's.
/// Outside the knots, lines with the end slopes (as OpenSim's `SimmSpline` and
/// `PiecewiseLinearFunction`). Fewer than 2 knots: zero everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SplineCode(pub [u8; SplineCode::LEN]);

code_fields!(SplineCode, 6, { x: u16 @ 0, values: u16 @ 2, knots: u8 @ 4 });

impl SplineCode {
    #[inline(always)]
    fn linear(self) -> bool {
        self.0[5] != 0
    }
}

/// The index a code's little-endian `u16` at byte `at` holds.
#[inline(always)]
fn le16(code: &[u8], at: usize) -> usize {
    usize::from(u16::from_le_bytes([code[at], code[at + 1]]))
}

/// The table's codes, in image order, and its numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Codes<const B: usize, const P: usize, const S: usize, const Q: usize, const D: usize> {
    joints: [[u8; JointCode::LEN]; B],
    /// `[function, argument]` ([`Drive`]).
    drives: [[u8; 2]; D],
    /// `[body, at_origin]`: an output point fixed in `body`, its offset three numbers in the
    /// pool (none if `at_origin` is 1), points in order from `points_at`.
    points: [[u8; 2]; P],
    splines: [[u8; SplineCode::LEN]; S],
    /// `[start (u16 little-endian), len]`: `len` coefficients, highest power first.
    polynomials: [[u8; 3]; Q],
    /// `[drives in use, coupled coordinates (the first drives), points_at (u16), used (u16)]`.
    counts: [u8; 6],
}

/// What [`CustomChain::packed`](super::CustomChain::packed) cannot pack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PackError {
    /// The numbers need more than the pool's `W` (or 65,535).
    Words {
        /// How many it needs.
        needed: usize,
    },
    /// More splines or polynomials than the table's `S` or `Q`, or an index past 31.
    Functions,
    /// A coordinate or coupled coordinate past the table's `N` or [`MAX_COUPLERS`], or past 63.
    Arguments,
    /// More moving axes than the table's `D`.
    Drives,
}

/// A chain of `N` input coordinates, `B` bodies and `P` points, packed: up to `S` splines, `Q`
/// polynomials, [`MAX_COUPLERS`] couplers, `D` moving axes and a pool of `W` numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PackedChain<
    T,
    const N: usize,
    const B: usize,
    const P: usize,
    const S: usize,
    const Q: usize,
    const D: usize,
    const W: usize,
> {
    codes: Codes<B, P, S, Q, D>,
    words: [T; W],
}

/// A spline's cubic `k` and the weights of its knots' `[value difference, slope k, slope
/// k+1]` at the argument (`w`: the value `y[k] + (y[k+1] − y[k]) w₀ + m[k] w₁ + m[k+1] w₂`),
/// with their first (`d`) and second (`dd`) derivatives by it.
#[derive(Clone, Copy, Default)]
struct SplineWeights<T> {
    k: usize,
    w: [T; 3],
    d: [T; 3],
    dd: [T; 3],
}

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
    /// Everything zero: every point at the origin.
    pub const EMPTY: Self = Self {
        codes: Codes {
            joints: [[0; JointCode::LEN]; B],
            drives: [[0; 2]; D],
            points: [[0; 2]; P],
            splines: [[0; SplineCode::LEN]; S],
            polynomials: [[0; 3]; Q],
            counts: [0; 6],
        },
        words: [T::ZERO; W],
    };

    /// Bytes of the codes, the start of the image.
    pub const CODES_LEN: usize =
        JointCode::LEN * B + 2 * D + 2 * P + SplineCode::LEN * S + 3 * Q + 6;

    /// Packs `chain`, its numbers rounded to `T`.
    pub(super) fn pack<U: Real, const K: usize>(
        chain: &ChainParts<'_, U, K>,
    ) -> Result<Self, PackError> {
        let mut table = Self::EMPTY;
        let codes = &mut table.codes;
        let mut pool = Pool {
            words: &mut table.words,
            len: 0,
        };
        let index = |k: usize, limit: usize| {
            if k < limit && k <= usize::from(Drive::FUNCTION_INDEX) {
                Ok(k as u8)
            } else {
                Err(PackError::Functions)
            }
        };
        let argument_index = |k: usize, limit: usize| {
            if k < limit && k <= usize::from(Drive::INDEX) {
                Ok(k as u8)
            } else {
                Err(PackError::Arguments)
            }
        };
        // Every function's code; linear coefficients pushed to the pool as met.
        let drive_function = |f: &Function<U>,
                              argument: Argument,
                              pool: &mut Pool<'_, T, W>|
         -> Result<u8, PackError> {
            Ok(match *f {
                Function::Linear { slope, intercept }
                    if slope == U::ONE && intercept == U::ZERO && argument != Argument::None =>
                {
                    Drive::IDENTITY
                }
                Function::Linear { slope, intercept } => {
                    pool.push(&[slope, intercept]);
                    Drive::LINEAR
                }
                Function::Constant(c) => {
                    pool.push(&[U::ZERO, c]);
                    Drive::LINEAR
                }
                Function::Spline(k) => Drive::SPLINE | index(k, S)?,
                Function::Polynomial(k) => Drive::POLYNOMIAL | index(k, Q)?,
            })
        };
        let couplers = chain.couplers;
        codes.counts[1] = couplers.len() as u8;
        // Abscissae first seen (their pool position) for each spline, to share them.
        let splines = chain.splines;
        if splines.len() > S || chain.polynomials.len() > Q {
            return Err(PackError::Functions);
        }
        let mut previous: Option<(u8, u8)> = None;
        let mut spline_x = [u16::MAX; S];
        let mut count = 0;
        // The drives (their linear coefficients in the same order): the coupled coordinates,
        // then by joint, translations first, then rotations; then the geometry.
        let coupled = couplers.iter().map(|c| Driven {
            axis: Vec3::zero(),
            function: c.function,
            argument: Argument::Coordinate(c.independent),
        });
        let moving = chain
            .joints
            .iter()
            .zip(chain.steps)
            .flat_map(|(joint, step)| {
                let (nr, nt) = step.moving;
                joint.translations[..usize::from(nt)]
                    .iter()
                    .chain(&joint.rotations[..usize::from(nr)])
                    .copied()
            });
        for d in coupled.chain(moving) {
            {
                let mut function = drive_function(&d.function, d.argument, &mut pool)?;
                let argument = match d.argument {
                    Argument::None => Drive::NONE,
                    Argument::Coordinate(k) => Drive::COORDINATE | argument_index(k, N)?,
                    Argument::Coupled(k) => Drive::COUPLED | argument_index(k, MAX_COUPLERS)?,
                };
                if function & Drive::KIND == Drive::SPLINE {
                    let k = usize::from(function & Drive::FUNCTION_INDEX);
                    // The abscissae's first user, by the splines' own abscissae.
                    let first = (0..=k)
                        .find(|&j| splines[j].same_abscissae(&splines[k]))
                        .unwrap_or(k);
                    let linear = u8::from(splines[k].is_piecewise_linear());
                    let key = (first as u8 | linear << 7, argument);
                    if previous == Some(key) {
                        function |= Drive::SHARES;
                    }
                    previous = Some(key);
                }
                let slot = codes.drives.get_mut(count).ok_or(PackError::Drives)?;
                *slot = [function, argument];
                count += 1;
            }
        }
        codes.counts[0] = count as u8;
        for (b, (joint, step)) in chain.joints.iter().zip(chain.steps).enumerate() {
            let code = &mut codes.joints[b];
            code[0] = joint.parent.unwrap_or(0) as u8;
            [code[4], code[5]] = (pool.len as u16).to_le_bytes();
            let (nr, nt) = step.moving;
            if (nr, nt) == (0, 0) {
                // A weld, `F · M⁻¹` on the parent: the steps' start and turn, those that are
                // not the identity.
                let end = &step.end;
                if end.translation != Vec3::zero() {
                    code[2] |= Shape::START;
                    pool.vec(end.translation);
                }
                if end.rotation != Quat::identity() {
                    code[2] |= Shape::TURNS;
                    pool.quat(end.rotation);
                }
                continue;
            }
            code[1] = nr | nt << 2;
            // The translation axes are stored turned into the parent body's frame.
            let shape = step.shape & !Shape::ORIENTED;
            code[2] = shape;
            if shape & Shape::START != 0 {
                pool.vec(joint.in_parent.translation);
            }
            for d in &joint.translations[..usize::from(nt)] {
                pool.vec(joint.in_parent.rotation.rotate(d.axis));
            }
            for (r, kind) in step.kinds[..usize::from(nr)].iter().enumerate() {
                code[3] |= (*kind as u8) << (2 * r);
                if *kind == AxisKind::General {
                    pool.vec(step.axes[r]);
                }
            }
            if shape & Shape::TURNS != 0 {
                pool.quat(step.end.rotation);
            }
            if shape & Shape::ENDS_AWAY != 0 {
                pool.vec(step.end.translation);
            }
        }
        [codes.counts[2], codes.counts[3]] = (pool.len as u16).to_le_bytes();
        for (code, p) in codes.points.iter_mut().zip(chain.points) {
            let at_origin = p.offset == Vec3::zero();
            *code = [p.body as u8, u8::from(at_origin)];
            if !at_origin {
                pool.vec(p.offset);
            }
        }
        for (k, s) in splines.iter().enumerate() {
            let (x, y) = s.knots();
            let first = (0..k).find(|&j| splines[j].same_abscissae(s));
            let at = match first {
                Some(j) => spline_x[j],
                None => {
                    let at = pool.len as u16;
                    pool.push(x);
                    at
                }
            };
            spline_x[k] = at;
            let [x0, x1] = at.to_le_bytes();
            let [v0, v1] = (pool.len as u16).to_le_bytes();
            codes.splines[k] = [
                x0,
                x1,
                v0,
                v1,
                x.len() as u8,
                u8::from(s.is_piecewise_linear()),
            ];
            pool.push(y);
            pool.push(s.slopes());
        }
        for (code, p) in codes.polynomials.iter_mut().zip(chain.polynomials) {
            let [s0, s1] = (pool.len as u16).to_le_bytes();
            *code = [s0, s1, p.coefficients().len() as u8];
            pool.push(p.coefficients());
        }
        if pool.len > W || pool.len > usize::from(u16::MAX) {
            return Err(PackError::Words { needed: pool.len });
        }
        [codes.counts[4], codes.counts[5]] = (pool.len as u16).to_le_bytes();
        Ok(table)
    }

    /// How many of the pool's numbers are in use.
    pub fn used(&self) -> usize {
        le16(&self.codes.counts, 4)
    }

    /// The pool's numbers in use.
    pub fn numbers(&self) -> &[T] {
        &self.words[..self.used().min(W)]
    }

    /// Whether the table's counts are within its sizes, as [`CustomChain::packed`](super::CustomChain::packed) makes them:
    /// its drives at most `D`, its coupled coordinates at most [`MAX_COUPLERS`] and its drives,
    /// its numbers in use at most `W`. (Any table evaluates without panicking; this is what a
    /// hub checks of an uploaded one beside its CRC.)
    pub fn is_usable(&self) -> bool {
        let counts = &self.codes.counts;
        usize::from(counts[0]) <= D
            && usize::from(counts[1]) <= usize::from(counts[0]).min(MAX_COUPLERS)
            && self.used() <= W
    }

    /// The joint codes.
    pub fn joints(&self) -> impl Iterator<Item = JointCode> + '_ {
        self.codes.joints.iter().map(|&c| JointCode(c))
    }

    /// The drives in use.
    pub fn drives(&self) -> impl Iterator<Item = Drive> + '_ {
        let count = usize::from(self.codes.counts[0]).min(D);
        self.codes.drives[..count].iter().map(|&d| Drive(d))
    }

    /// The spline codes.
    pub fn splines(&self) -> impl Iterator<Item = SplineCode> + '_ {
        self.codes.splines.iter().map(|&s| SplineCode(s))
    }

    /// Every body's frame in ground for input coordinates `q`.
    pub fn frames(&self, q: &[T; N]) -> [BodyFrame<T>; B] {
        self.carried(|i| q[i])
    }

    /// The output points in ground for input coordinates `q`: forward kinematics.
    #[inline]
    pub fn forward(&self, q: &[T; N]) -> [Vec3<T>; P] {
        let frames: [BodyFrame<T>; B] = self.carried(|i| q[i]);
        self.points(&frames, |f, offset| match offset {
            Some(offset) => f.origin + f.rotation.rotate(offset),
            None => f.origin,
        })
    }

    /// Every body's motion in ground ([`FrameMotion`]: orientation, origin, the origin's
    /// velocity and acceleration, angular velocity and acceleration, ground axes) for input
    /// coordinates `q`, speeds `qd` and accelerations `qdd`. The orientations and origins are
    /// [`frames`](Self::frames)'.
    pub fn motions(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [FrameMotion<T>; B] {
        self.moving(q, qd, qdd)
    }

    /// The output points' positions, velocities and accelerations in ground (the time
    /// derivatives of [`forward`](Self::forward)'s points).
    #[inline]
    pub fn forward_motion(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [PointMotion<T>; P] {
        let frames: [FrameMotion<T>; B] = self.moving(q, qd, qdd);
        self.points(&frames, point_motion)
    }

    /// The output points' positions and velocities (as [`forward_motion`](Self::forward_motion),
    /// the accelerations neither computed nor carried): `(positions, velocities)`.
    #[inline]
    pub fn forward_velocities(&self, q: &[T; N], qd: &[T; N]) -> ([Vec3<T>; P], [Vec3<T>; P]) {
        let frames: [Twist<T>; B] = self.moving(q, qd, qd);
        let points = self.points(&frames, point_motion);
        let mut positions = [Vec3::zero(); P];
        let mut velocities = [Vec3::zero(); P];
        for (i, p) in points.iter().enumerate() {
            positions[i] = p.position;
            velocities[i] = p.velocity;
        }
        (positions, velocities)
    }

    /// The output points on their bodies' frames as `K` carries them: each `place`d at its
    /// body's origin (`None`) or at its offset in the body (`Some`, read in order from the
    /// pool's points).
    #[inline(always)]
    fn points<K: Carried<T>, X: Default>(
        &self,
        frames: &[K; B],
        place: impl Fn(&K, Option<Vec3<T>>) -> X,
    ) -> [X; P] {
        let mut cursor = le16(&self.codes.counts, 2);
        core::array::from_fn(|k| {
            let [body, at_origin] = self.codes.points[k];
            // A body past the table reads the last one.
            let Some(f) = frames.get(usize::from(body).min(B.saturating_sub(1))) else {
                return X::default();
            };
            let offset = (at_origin == 0).then(|| self.vec(&mut cursor));
            place(f, offset)
        })
    }

    /// The bodies' motions for `q`, `qd`, `qdd`, with their accelerations if `K` carries them
    /// (`qdd` unread otherwise).
    #[inline(always)]
    fn moving<K: Carried<T>>(&self, q: &[T; N], qd: &[T; N], qdd: &[T; N]) -> [K; B] {
        self.carried(|i| Jet {
            value: q[i],
            rate: qd[i],
            accel: qdd[i],
        })
    }

    /// Every body's frame as `K` carries it (its position, or with its rates): every drive's
    /// value first (with its rates if `V` carries them; coordinate `i` is `coordinate(i)`),
    /// then the frames joint by joint.
    #[inline(always)]
    fn carried<K: Carried<T>, V: ChainRule<T>>(&self, coordinate: impl Fn(usize) -> V) -> [K; B] {
        let mut values = [V::ZERO; D];
        self.drive_values(coordinate, &mut values);
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
                *f = self.body(code, parent, v, nr, nt);
            }
        }
        frames
    }

    /// Every drive's value (with its rates if `V` carries them) for coordinate `i` at
    /// `coordinate(i)`, in order (the coupled coordinates first, then the moving axes'), the
    /// linear coefficients read in order from the pool's start. A coupled coordinate is the
    /// value of an earlier drive (0 otherwise).
    #[inline(always)]
    fn drive_values<V: ChainRule<T>>(&self, coordinate: impl Fn(usize) -> V, values: &mut [V; D]) {
        let mut cursor = 0;
        let mut weights = SplineWeights::default();
        let count = usize::from(self.codes.counts[0]).min(D);
        for i in 0..count {
            let [function, argument] = self.codes.drives[i];
            let index = usize::from(argument & Drive::INDEX);
            let x = match argument & Drive::KIND {
                Drive::COORDINATE if index < N => coordinate(index),
                Drive::COUPLED if index < i => values[index],
                _ => V::ZERO,
            };
            values[i] = self.function(function, x, &mut cursor, &mut weights);
        }
    }

    /// The frame of a joint's body on its parent's frame, as [`CustomChain`](super::CustomChain) computes it, and
    /// its rates if `K` carries them: `v` its `nt` translations' drives, then its `nr`
    /// rotations'.
    #[inline(always)]
    fn body<K: Carried<T>, V: ChainRule<T>>(
        &self,
        code: JointCode,
        parent: &K,
        v: &[V],
        nr: usize,
        nt: usize,
    ) -> K {
        let mut cursor = code.words();
        let shape = code.shape();
        let zero = Vec3::zero();
        let Twist {
            rotation: parent_rotation,
            mut origin,
            mut velocity,
            angular_velocity: w,
        } = parent.twist();
        let (mut acceleration, parent_alpha) = parent.accelerations();
        if shape & Shape::START != 0 {
            let start = self.vec(&mut cursor);
            let (mut slide, mut rate, mut accel) = (zero, zero, zero);
            for x in v.iter().take(nt) {
                let axis = self.vec(&mut cursor);
                slide += axis * x.value();
                rate += axis * x.rate();
                if K::ACC {
                    accel += axis * x.accel();
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
            let (s, c) = x.value().half_angle_sin_cos();
            // The axis in ground (unmoved by its own rotation).
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
                alpha += g * x.accel() + omega.cross(g) * x.rate();
            }
            omega += g * x.rate();
        }
        if shape & Shape::TURNS != 0 {
            rotation = rotation * self.quat(&mut cursor);
        }
        let twist = Twist {
            rotation,
            origin,
            velocity,
            angular_velocity: omega,
        };
        let mut body = K::of(twist, (acceleration, alpha));
        if shape & Shape::ENDS_AWAY != 0 {
            let end = body.point_at(rotation.rotate(self.vec(&mut cursor)));
            let twist = Twist {
                rotation,
                origin: end.position,
                velocity: end.velocity,
                angular_velocity: omega,
            };
            body = K::of(twist, (end.acceleration, alpha));
        }
        body
    }

    /// Function code `function` through `x` (with its derivatives if `V` carries rates, by the
    /// chain rule); linear coefficients read at `cursor`, a spline's weights found (into
    /// `weights`) unless it [`Drive::SHARES`] them.
    #[inline(always)]
    fn function<V: ChainRule<T>>(
        &self,
        function: u8,
        x: V,
        cursor: &mut usize,
        weights: &mut SplineWeights<T>,
    ) -> V {
        let index = usize::from(function & Drive::FUNCTION_INDEX);
        let shared = function & Drive::SHARES != 0;
        let zero = T::ZERO;
        match function & Drive::KIND {
            Drive::LINEAR => {
                let [slope, intercept] = self.take::<2>(cursor);
                x.through(slope * x.value() + intercept, slope, zero)
            }
            Drive::SPLINE => {
                let Some(&s) = self.codes.splines.get(index) else {
                    return V::ZERO;
                };
                let s = SplineCode(s);
                if !shared {
                    *weights = self.weights(s, x.value());
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
                let Some(code) = self.codes.polynomials.get(index) else {
                    return V::ZERO;
                };
                let start = le16(code, 0);
                let c = self.words.get(start..start + usize::from(code[2]));
                let (p, dp, ddp) = with_derivatives(c.unwrap_or(&[]), x.value());
                x.through(p, dp, ddp)
            }
            _ => x,
        }
    }

    /// The Hermite weights of spline `s` at `t` and their first and second derivatives by
    /// `t`: the cubic of the last knot at or below `t` (the first below the second knot), or
    /// the end lines outside the knots.
    #[inline(always)]
    fn weights(&self, s: SplineCode, t: T) -> SplineWeights<T> {
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
        // The last knot at or below t, below the last knot (the knots increase), by bisection:
        // x[k] <= t and t < x[end] while they are apart. A NaN t takes the last cubic (the
        // negated comparison), as `Spline::interval`.
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

    /// `M` numbers from `cursor` on, the cursor moved past them; past the pool, its last `M`
    /// (a clamped index: no branch, nothing to panic; zeros if the pool is shorter than `M`).
    #[inline(always)]
    fn take<const M: usize>(&self, cursor: &mut usize) -> [T; M] {
        let at = (*cursor).min(W.saturating_sub(M));
        *cursor = cursor.saturating_add(M);
        match self.words[at..].first_chunk::<M>() {
            Some(w) => *w,
            None => [T::ZERO; M],
        }
    }

    #[inline(always)]
    fn vec(&self, cursor: &mut usize) -> Vec3<T> {
        let [x, y, z] = self.take::<3>(cursor);
        Vec3::new(x, y, z)
    }

    #[inline(always)]
    fn quat(&self, cursor: &mut usize) -> Quat<T> {
        let [w, x, y, z] = self.take::<4>(cursor);
        Quat::new(w, x, y, z)
    }
}

/// A point's motion on its body's frame `f` (as `f` carries it): at the frame's origin
/// (`None`) or at `offset` in the body.
#[inline(always)]
fn point_motion<T: Real, K: Carried<T>>(f: &K, offset: Option<Vec3<T>>) -> PointMotion<T> {
    match offset {
        Some(offset) => f.point_at(f.twist().rotation.rotate(offset)),
        None => f.origin_motion(),
    }
}

/// The code sections of `codes` in image order: with `as_flattened` or, and `mut`,
/// `as_flattened_mut`.
macro_rules! code_sections {
    ($codes:expr, $flat:ident $(, $m:tt)?) => {
        [
            $codes.joints.$flat(),
            $codes.drives.$flat(),
            $codes.points.$flat(),
            $codes.splines.$flat(),
            $codes.polynomials.$flat(),
            &$($m)? $codes.counts[..],
        ]
    };
}

impl<
        const N: usize,
        const B: usize,
        const P: usize,
        const S: usize,
        const Q: usize,
        const D: usize,
        const W: usize,
    > PackedChain<f32, N, B, P, S, Q, D, W>
{
    /// Bytes of the image: the codes, then the numbers (see the module docs).
    pub const IMAGE_LEN: usize = Self::CODES_LEN + 4 * W;

    /// The codes, in image order, in sections.
    pub fn code_sections(&self) -> [&[u8]; 6] {
        code_sections!(self.codes, as_flattened)
    }

    /// The numbers (the image after the codes).
    pub fn words(&self) -> &[f32; W] {
        &self.words
    }

    /// Writes `bytes` into the image from byte `at` on (what lies past
    /// [`IMAGE_LEN`](Self::IMAGE_LEN) is ignored): how a hub fills its slot as an upload's
    /// parts arrive, with no second copy of the table.
    pub fn write_image(&mut self, at: usize, bytes: &[u8]) {
        let (mut at, mut bytes) = (at, bytes);
        for section in code_sections!(self.codes, as_flattened_mut, mut) {
            if let Some(to) = section.get_mut(at..) {
                let n = to.len().min(bytes.len());
                to[..n].copy_from_slice(&bytes[..n]);
                bytes = &bytes[n..];
            }
            at = at.saturating_sub(section.len());
        }
        for (i, &b) in (at..).zip(bytes) {
            if let Some(w) = self.words.get_mut(i / 4) {
                let mut le = w.to_le_bytes();
                le[i % 4] = b;
                *w = f32::from_le_bytes(le);
            }
        }
    }

    /// The image's bytes, in order.
    pub fn image(&self) -> impl Iterator<Item = u8> + '_ {
        self.code_sections()
            .into_iter()
            .flatten()
            .copied()
            .chain(self.words.iter().flat_map(|w| w.to_le_bytes()))
    }

    /// Reads the image from byte `at` on into `out` (as much as there is).
    pub fn read_image(&self, at: usize, out: &mut [u8]) {
        for (o, b) in out.iter_mut().zip(self.image().skip(at)) {
            *o = b;
        }
    }
}

/// The pool as `PackedChain::pack` fills it (numbers past `W` counted, not written).
struct Pool<'a, T, const W: usize> {
    words: &'a mut [T; W],
    len: usize,
}

impl<T: Real, const W: usize> Pool<'_, T, W> {
    fn push<U: Real>(&mut self, values: &[U]) {
        for v in values {
            if let Some(w) = self.words.get_mut(self.len) {
                *w = T::from_f64(v.to_f64());
            }
            self.len += 1;
        }
    }

    fn vec<U: Real>(&mut self, v: Vec3<U>) {
        self.push(&v.to_array());
    }

    fn quat<U: Real>(&mut self, q: Quat<U>) {
        self.push(&[q.w, q.x, q.y, q.z]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::fixtures::walker_chain;
    use crate::models::LowerLimb;

    type Packed<T> = PackedChain<T, 17, 11, 12, 12, 12, 66, 512>;

    /// Poses over and past the fixture's spline range (knees -1 to 2.5 rad: its knots span 0 to
    /// 2.1), every other coordinate moving.
    fn poses() -> impl Iterator<Item = [f64; 17]> {
        (0..60).map(|k| {
            core::array::from_fn(|i| {
                let s = Real::sin_cos(0.37 * (k * 17 + i) as f64 + 0.1 * k as f64).0;
                if i == 6 || i == 13 {
                    0.75 + 1.75 * s
                } else {
                    0.9 * s
                }
            })
        })
    }

    fn assert_same(packed: &Packed<f64>, chain: &LowerLimb<f64>, tolerance: f64) {
        for q in poses() {
            for (p, r) in packed.forward(&q).iter().zip(&chain.forward(&q)) {
                assert!(p.max_abs_diff(*r) <= tolerance, "{q:?}: {p:?} {r:?}");
            }
        }
    }

    #[test]
    fn a_chain_packed_into_other_sizes_is_the_same_chain() {
        // Oriented frames, general and coordinate axes, a cubic and a straight spline through
        // the same abscissae, a coupler, welds: the chain's own table (of the host's sizes)
        // and one of just the sizes it needs give the same frames and points.
        let chain = walker_chain();
        let packed = chain.packed::<f64, 12, 12, 66, 512>().unwrap();
        assert_same(&packed, &chain, 0.0);
        for q in poses() {
            for (p, r) in packed.frames(&q).iter().zip(&chain.frames(&q)) {
                assert_eq!(p, r);
            }
        }
        // Its abscissae are stored once.
        let mut splines = packed.splines();
        let (a, b) = (splines.next().unwrap(), splines.next().unwrap());
        assert_eq!(a.x(), b.x());
        assert_ne!(a.values(), b.values());
        // The straight spline takes the cubic's knot but not its weights.
        let shares = packed
            .drives()
            .filter(|d| d.function() & Drive::SHARES != 0)
            .count();
        assert_eq!(shares, 0);
    }

    #[test]
    fn a_packed_chain_in_f32_is_its_chain_within_f32_rounding() {
        let chain = walker_chain();
        let packed = chain.packed::<f32, 12, 12, 66, 512>().unwrap();
        for q in poses() {
            let q32 = q.map(|v| v as f32);
            for (p, r) in packed.forward(&q32).iter().zip(&chain.forward(&q)) {
                assert!(p.cast::<f64>().max_abs_diff(*r) < 2e-6, "{p:?} {r:?}");
            }
        }
    }

    #[test]
    fn a_pool_too_small_is_refused_saying_how_much_it_needs() {
        let chain = walker_chain();
        let full = chain.packed::<f64, 12, 12, 66, 512>().unwrap();
        let small = chain.packed::<f64, 12, 12, 66, 16>();
        assert_eq!(
            small,
            Err(PackError::Words {
                needed: full.used()
            })
        );
        let no_splines = chain.packed::<f64, 1, 12, 66, 512>();
        assert_eq!(no_splines, Err(PackError::Functions));
        let few_drives = chain.packed::<f64, 12, 12, 4, 512>();
        assert_eq!(few_drives, Err(PackError::Drives));
    }

    #[test]
    fn an_image_written_in_any_pieces_is_the_table() {
        let packed = walker_chain().packed::<f32, 12, 12, 66, 512>().unwrap();
        let mut image = [0u8; Packed::<f32>::IMAGE_LEN];
        packed.read_image(0, &mut image);
        // The numbers are the pool's, little-endian, after the codes.
        let at = Packed::<f32>::CODES_LEN;
        assert_eq!(image[at..at + 4], packed.numbers()[0].to_le_bytes());
        for piece in [1, 7, 64, 150, image.len()] {
            let mut table = Packed::<f32>::EMPTY;
            for (k, chunk) in image.chunks(piece).enumerate() {
                table.write_image(k * piece, chunk);
            }
            assert_eq!(table, packed, "pieces of {piece}");
            // Read back in pieces too.
            let mut again = [0u8; Packed::<f32>::IMAGE_LEN];
            for (k, chunk) in again.chunks_mut(piece).enumerate() {
                table.read_image(k * piece, chunk);
            }
            assert_eq!(again, image);
        }
        // Past the end: nothing written, nothing read.
        let mut table = packed;
        table.write_image(image.len(), &[0xff; 8]);
        assert_eq!(table, packed);
        let mut out = [7u8; 4];
        table.read_image(image.len(), &mut out);
        assert_eq!(out, [7; 4]);
    }

    #[test]
    fn a_table_with_counts_past_its_sizes_is_not_usable() {
        let packed = walker_chain().packed::<f32, 12, 12, 66, 512>().unwrap();
        assert!(packed.is_usable());
        let counts = Packed::<f32>::CODES_LEN - 6;
        let mut bad = packed;
        bad.write_image(counts, &[67]);
        assert!(!bad.is_usable(), "drives past D");
        let mut bad = packed;
        bad.write_image(counts + 1, &[5]);
        assert!(!bad.is_usable(), "couplers past MAX_COUPLERS");
        let mut bad = packed;
        bad.write_image(counts + 4, &513u16.to_le_bytes());
        assert!(!bad.is_usable(), "numbers past W");
        // More coupled coordinates than drives.
        let mut bad = packed;
        bad.write_image(counts, &[1, 2]);
        assert!(!bad.is_usable(), "couplers past the drives");
    }

    #[test]
    fn any_table_evaluates_without_panicking() {
        // Codes pointing past the pool, past the tables, at bodies that do not exist.
        let packed = walker_chain().packed::<f32, 12, 12, 66, 512>().unwrap();
        let mut image = [0u8; Packed::<f32>::CODES_LEN];
        packed.read_image(0, &mut image);
        let mut state = 0x2545_f491u32;
        let mut byte = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as u8
        };
        for round in 0..400 {
            let mut table = packed;
            let mut codes = image;
            // Half the rounds change a few bytes of a good table, half fill it at random.
            if round % 2 == 0 {
                for _ in 0..4 {
                    let at = usize::from(byte()) * 256 + usize::from(byte());
                    let len = codes.len();
                    codes[at % len] = byte();
                }
            } else {
                codes.iter_mut().for_each(|c| *c = byte());
            }
            table.write_image(0, &codes);
            let _ = table.forward(&[0.3; 17]);
            let _ = table.forward(&[f32::NAN; 17]);
        }
    }
}
