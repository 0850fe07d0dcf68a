//! A [`CustomChain`] packed for a device: the same forward kinematics from a table that holds
//! only what is not the identity. [`PackedChain::pack`] builds it (on the host, from the
//! validated chain); [`PackedChain::forward`] evaluates it.
//!
//! The table is byte codes and a pool of numbers ([`PackedChain::words`]):
//! - per joint a [`JointCode`]: its parent, how many rotations and translations move, which
//!   parts of the joint are not the identity ([`CustomChain`]'s evaluation steps), and per moving
//!   axis what drives it ([`Drive`]); the joint's numbers follow in the pool in a fixed order
//!   (see [`JointCode`]);
//! - splines in Hermite form: per knot its value and slope (the same cubic between two knots as
//!   the Forsythe-Malcolm-Moler coefficients, two numbers a knot instead of four), splines
//!   through the same abscissae (a knee's four) sharing them;
//! - polynomials' coefficients, couplers' functions, and the output points.
//!
//! Numbers are read with bounds checks that cannot panic (a short pool reads as zeros), so a
//! table of any content evaluates without panicking.

use super::custom::{
    Argument, AxisKind, BodyFrame, CustomChain, Function, Offset, Shape, MAX_COUPLERS,
};
use crate::{Quat, Real, Vec3};

/// What drives one moving axis: its function ([`Drive::function`]) and the argument it is
/// evaluated at ([`Drive::argument`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Drive {
    /// Bits 6-7: [`Drive::LINEAR`] (two numbers in the pool: slope, value at 0),
    /// [`Drive::SPLINE`], [`Drive::POLYNOMIAL`] (bits 0-4: which), or [`Drive::IDENTITY`] (the
    /// argument itself); bit 5, [`Drive::SHARES`]: a spline that takes the weights of the
    /// spline-driven axis evaluated before it (the same argument and abscissae).
    pub function: u8,
    /// Bits 6-7: [`Drive::NONE`] (0), [`Drive::COORDINATE`] or [`Drive::COUPLED`]; bits 0-5:
    /// which.
    pub argument: u8,
}

impl Drive {
    /// `slope · x + intercept`.
    pub const LINEAR: u8 = 0;
    /// Spline `k` of the table.
    pub const SPLINE: u8 = 1 << 6;
    /// Polynomial `k` of the table.
    pub const POLYNOMIAL: u8 = 2 << 6;
    /// `x`.
    pub const IDENTITY: u8 = 3 << 6;
    /// Evaluated at 0.
    pub const NONE: u8 = 0;
    /// Input coordinate `i`.
    pub const COORDINATE: u8 = 1 << 6;
    /// Coupled coordinate `k`.
    pub const COUPLED: u8 = 2 << 6;
    /// With [`Drive::SPLINE`]: the weights of the spline before it.
    pub const SHARES: u8 = 1 << 5;
    const KIND: u8 = 3 << 6;
    const INDEX: u8 = 0x3f;
    const FUNCTION_INDEX: u8 = 0x1f;
}

/// One joint. Its moving axes' drives are the next `moving` of [`PackedChain::drives`],
/// translations first, then rotations; their [`Drive::LINEAR`] slopes and intercepts are at the
/// pool's start (after the couplers', in the drives' order). Its geometry, from [`words`](Self::words)
/// on: for a joint that does not move, the fixed offset (translation 3, rotation 4); otherwise,
/// in order,
/// - `START`: the parent frame's origin `t_F` (3), then each moving translation's axis (3);
/// - `ORIENTED`: the parent frame's orientation `R_F` (4), which turns the translation axes;
/// - each moving rotation about a general axis: the axis in the parent body's frame (3);
/// - `TURNS`: the rotation after the joint's own, `R_F R_M⁻¹` (4);
/// - `ENDS_AWAY`: `−t_M` (3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct JointCode {
    /// The parent body (ignored for body 0, which hangs on ground).
    pub parent: u8,
    /// Moving rotations (bits 0-1) and translations (bits 2-3).
    pub moving: u8,
    /// Bits: 1 `START`, 2 `ORIENTED`, 4 `TURNS`, 8 `ENDS_AWAY` (see above).
    pub shape: u8,
    /// Each moving rotation's axis, two bits each from bit 0: 0 general, 1 +x, 2 +y, 3 +z.
    pub kinds: u8,
    /// The joint's first geometry number in the pool.
    pub words: u16,
}

/// One spline in Hermite form: `knots` abscissae at [`x`](Self::x), then `knots` values and
/// `knots` slopes at [`values`](Self::values). Outside the knots, lines with the end slopes
/// (as OpenSim's `SimmSpline` and `PiecewiseLinearFunction`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SplineCode {
    /// First abscissa in the pool.
    pub x: u16,
    /// First value in the pool (the slopes follow the values).
    pub values: u16,
    /// Knot count (2 or more; 0: no spline, zero everywhere).
    pub knots: u8,
    /// 1: straight between the knots (a `PiecewiseLinearFunction`), the slopes each segment's.
    pub linear: u8,
}

/// One polynomial: `len` coefficients, highest power first, at `start` in the pool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PolynomialCode {
    /// First coefficient in the pool.
    pub start: u16,
    /// Coefficient count.
    pub len: u8,
}

/// A coupled coordinate: `function` (a [`Drive`] function byte) of input `independent`. Its
/// linear coefficients, if any, are first in the pool, couplers in order.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CouplerCode {
    /// The input coordinate it follows.
    pub independent: u8,
    /// Its function.
    pub function: u8,
}

/// An output point: fixed in `body`, its offset three numbers in the pool (none if
/// `at_origin`), points in order from [`PackedChain::points_at`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PointCode {
    /// The body.
    pub body: u8,
    /// 1: the body's origin.
    pub at_origin: u8,
}

/// What [`PackedChain::pack`] cannot pack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PackError {
    /// The numbers need more than the pool's `W`.
    Words {
        /// How many it needs.
        needed: usize,
    },
    /// More splines or polynomials than the table's `S` or `Q`, or an index past 31.
    Functions,
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
    /// By body.
    pub joints: [JointCode; B],
    /// The moving axes' drives, by joint (see [`JointCode`]).
    pub drives: [Drive; D],
    /// How many of `drives` are in use.
    pub drive_count: u8,
    /// The output points.
    pub points: [PointCode; P],
    /// The splines [`Drive::SPLINE`] refers to.
    pub splines: [SplineCode; S],
    /// The polynomials [`Drive::POLYNOMIAL`] refers to.
    pub polynomials: [PolynomialCode; Q],
    /// The coupled coordinates [`Drive::COUPLED`] refers to.
    pub couplers: [CouplerCode; MAX_COUPLERS],
    /// How many of `couplers` are in use.
    pub coupler_count: u8,
    /// Where the points' offsets start in the pool.
    pub points_at: u16,
    /// How many of the pool's numbers are in use.
    pub used: u16,
    /// The pool.
    pub words: [T; W],
}

/// Where a spline's cubic is, and the weights of its two knots' values and slopes at the
/// argument: `y[k] + (y[k+1] − y[k]) w + m[k] a + m[k+1] b`.
#[derive(Clone, Copy)]
struct Weights<T> {
    k: usize,
    w: T,
    a: T,
    b: T,
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
        joints: [JointCode {
            parent: 0,
            moving: 0,
            shape: 0,
            kinds: 0,
            words: 0,
        }; B],
        drives: [Drive {
            function: 0,
            argument: 0,
        }; D],
        drive_count: 0,
        points: [PointCode {
            body: 0,
            at_origin: 0,
        }; P],
        splines: [SplineCode {
            x: 0,
            values: 0,
            knots: 0,
            linear: 0,
        }; S],
        polynomials: [PolynomialCode { start: 0, len: 0 }; Q],
        couplers: [CouplerCode {
            independent: 0,
            function: 0,
        }; MAX_COUPLERS],
        coupler_count: 0,
        points_at: 0,
        used: 0,
        words: [T::ZERO; W],
    };

    /// Packs `chain`, its numbers rounded to `T`.
    pub fn pack<U: Real, const S2: usize, const K: usize, const Q2: usize>(
        chain: &CustomChain<U, N, B, P, S2, K, Q2>,
    ) -> Result<Self, PackError> {
        let mut table = Self::EMPTY;
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
        let couplers = chain.couplers();
        for (code, c) in table.couplers.iter_mut().zip(couplers) {
            *code = CouplerCode {
                independent: c.independent as u8,
                function: drive_function(&c.function, Argument::Coordinate(0), &mut pool)?,
            };
        }
        table.coupler_count = couplers.len() as u8;
        // Abscissae first seen (their pool position) for each spline, to share them.
        let splines = chain.splines();
        if splines.len() > S || chain.polynomials().len() > Q {
            return Err(PackError::Functions);
        }
        let mut previous: Option<(u8, u8)> = None;
        let mut spline_x = [u16::MAX; S];
        let mut count = 0;
        // The drives (their linear coefficients after the couplers'), by joint, translations
        // first, then rotations; then the geometry.
        for (joint, step) in chain.joints().iter().zip(chain.steps()) {
            let (nr, nt) = step.moving;
            let moving = joint.translations[..usize::from(nt)]
                .iter()
                .chain(&joint.rotations[..usize::from(nr)]);
            for d in moving {
                let mut function = drive_function(&d.function, d.argument, &mut pool)?;
                let argument = match d.argument {
                    Argument::None => Drive::NONE,
                    Argument::Coordinate(k) => Drive::COORDINATE | index(k, N)?,
                    Argument::Coupled(k) => Drive::COUPLED | index(k, MAX_COUPLERS)?,
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
                let slot = table.drives.get_mut(count).ok_or(PackError::Drives)?;
                *slot = Drive { function, argument };
                count += 1;
            }
        }
        table.drive_count = count as u8;
        for (b, (joint, step)) in chain.joints().iter().zip(chain.steps()).enumerate() {
            let code = &mut table.joints[b];
            code.parent = joint.parent.unwrap_or(0) as u8;
            code.words = pool.len as u16;
            let (nr, nt) = step.moving;
            if (nr, nt) == (0, 0) {
                pool.offset(&step.end);
                continue;
            }
            code.moving = nr | nt << 2;
            let mut shape = step.shape;
            if nt == 0 {
                shape &= !Shape::ORIENTED;
            }
            code.shape = shape;
            if shape & Shape::START != 0 {
                pool.vec(joint.in_parent.translation);
            }
            for d in &joint.translations[..usize::from(nt)] {
                pool.vec(d.axis);
            }
            if shape & Shape::ORIENTED != 0 {
                pool.quat(joint.in_parent.rotation);
            }
            for (r, kind) in step.kinds[..usize::from(nr)].iter().enumerate() {
                code.kinds |= (*kind as u8) << (2 * r);
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
        table.points_at = pool.len as u16;
        for (code, p) in table.points.iter_mut().zip(chain.points()) {
            *code = PointCode {
                body: p.body as u8,
                at_origin: (p.offset == Vec3::zero()) as u8,
            };
            if code.at_origin == 0 {
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
            table.splines[k] = SplineCode {
                x: at,
                values: pool.len as u16,
                knots: x.len() as u8,
                linear: s.is_piecewise_linear() as u8,
            };
            pool.push(y);
            pool.push(s.slopes());
        }
        for (code, p) in table.polynomials.iter_mut().zip(chain.polynomials()) {
            *code = PolynomialCode {
                start: pool.len as u16,
                len: p.coefficients().len() as u8,
            };
            pool.push(p.coefficients());
        }
        if pool.len > W {
            return Err(PackError::Words { needed: pool.len });
        }
        table.used = pool.len as u16;
        Ok(table)
    }

    /// The output points in ground for input coordinates `q`: forward kinematics.
    pub fn forward(&self, q: &[T; N]) -> [Vec3<T>; P] {
        let mut values = [T::ZERO; D];
        self.values(q, &mut values);
        let mut frames = [BodyFrame::GROUND; B];
        let mut rest = &values[..];
        for (b, code) in self.joints.iter().enumerate() {
            let (nr, nt) = (
                usize::from(code.moving & 3),
                usize::from(code.moving >> 2 & 3),
            );
            let (v, after) = rest.split_at((nr + nt).min(rest.len()));
            rest = after;
            let (done, todo) = frames.split_at_mut(b);
            let parent = match done.get(usize::from(code.parent)) {
                Some(p) if b > 0 => p,
                _ => &BodyFrame::GROUND,
            };
            if let Some(f) = todo.first_mut() {
                *f = self.frame(code, parent, v, nr, nt);
            }
        }
        let mut cursor = usize::from(self.points_at);
        core::array::from_fn(|k| {
            let p = &self.points[k];
            let offset = if p.at_origin != 0 {
                None
            } else {
                Some(self.vec(&mut cursor))
            };
            match (frames.get(usize::from(p.body)), offset) {
                (Some(f), None) => f.origin,
                (Some(f), Some(o)) => f.origin + f.rotation.rotate(o),
                (None, _) => Vec3::zero(),
            }
        })
    }

    /// Every moving axis's value for `q`, in drive order; the couplers' first, the linear
    /// coefficients read in order from the pool's start.
    #[inline(always)]
    fn values(&self, q: &[T; N], values: &mut [T; D]) {
        let mut cursor = 0;
        let mut coupled = [T::ZERO; MAX_COUPLERS];
        let mut weights = Weights {
            k: 0,
            w: T::ZERO,
            a: T::ZERO,
            b: T::ZERO,
        };
        let count = usize::from(self.coupler_count).min(MAX_COUPLERS);
        for (v, c) in coupled[..count].iter_mut().zip(&self.couplers) {
            let x = q
                .get(usize::from(c.independent))
                .copied()
                .unwrap_or(T::ZERO);
            *v = self.function(c.function, x, &mut cursor, &mut weights);
        }
        let count = usize::from(self.drive_count).min(D);
        for (v, d) in values[..count].iter_mut().zip(&self.drives) {
            let index = usize::from(d.argument & Drive::INDEX);
            let x = match d.argument & Drive::KIND {
                Drive::COORDINATE => q.get(index).copied().unwrap_or(T::ZERO),
                Drive::COUPLED => coupled.get(index).copied().unwrap_or(T::ZERO),
                _ => T::ZERO,
            };
            *v = self.function(d.function, x, &mut cursor, &mut weights);
        }
    }

    /// The frame of a joint's body on its parent's frame, as [`CustomChain`] computes it: `v`
    /// its `nt` translations' values, then its `nr` rotations'.
    #[inline(always)]
    fn frame(
        &self,
        code: &JointCode,
        parent: &BodyFrame<T>,
        v: &[T],
        nr: usize,
        nt: usize,
    ) -> BodyFrame<T> {
        let mut cursor = usize::from(code.words);
        if nr == 0 && nt == 0 {
            let translation = self.vec(&mut cursor);
            let rotation = self.quat(&mut cursor);
            return parent.then(&Offset {
                translation,
                rotation,
            });
        }
        let mut origin = parent.origin;
        if code.shape & Shape::START != 0 {
            let start = self.vec(&mut cursor);
            let mut slide = Vec3::zero();
            for &x in v.iter().take(nt) {
                slide += self.vec(&mut cursor) * x;
            }
            if code.shape & Shape::ORIENTED != 0 {
                slide = self.quat(&mut cursor).rotate(slide);
            }
            origin += parent.rotation.rotate(start + slide);
        }
        let mut rotation = parent.rotation;
        for (r, &x) in v.iter().skip(nt).take(nr).enumerate() {
            let (s, c) = x.half_angle_sin_cos();
            rotation = match code.kinds >> (2 * r) & 3 {
                1 => rotation.then_about_x(s, c),
                2 => rotation.then_about_y(s, c),
                3 => rotation.then_about_z(s, c),
                _ => rotation * Quat::from_axis_half_sin_cos(self.vec(&mut cursor), s, c),
            };
        }
        if code.shape & Shape::TURNS != 0 {
            rotation = rotation * self.quat(&mut cursor);
        }
        if code.shape & Shape::ENDS_AWAY != 0 {
            origin += rotation.rotate(self.vec(&mut cursor));
        }
        BodyFrame { rotation, origin }
    }

    /// The value of function code `function` at `x`; linear coefficients read at `cursor`, a
    /// spline's weights found (into `weights`) unless it [`Drive::SHARES`] them.
    #[inline(always)]
    fn function(&self, function: u8, x: T, cursor: &mut usize, weights: &mut Weights<T>) -> T {
        let index = usize::from(function & Drive::FUNCTION_INDEX);
        let shared = function & Drive::SHARES != 0;
        match function & Drive::KIND {
            Drive::LINEAR => {
                let [slope, intercept] = self.take::<2>(cursor);
                slope * x + intercept
            }
            Drive::SPLINE => {
                let Some(s) = self.splines.get(index) else {
                    return T::ZERO;
                };
                if !shared {
                    *weights = self.weights(s, x);
                }
                let at = usize::from(s.values) + weights.k;
                let n = usize::from(s.knots);
                let [y0, y1] = self.take::<2>(&mut at.clone());
                let [m0, m1] = self.take::<2>(&mut (at + n));
                y0 + (y1 - y0) * weights.w + m0 * weights.a + m1 * weights.b
            }
            Drive::POLYNOMIAL => {
                let Some(p) = self.polynomials.get(index) else {
                    return T::ZERO;
                };
                let start = usize::from(p.start);
                let c = self.words.get(start..start + usize::from(p.len));
                c.unwrap_or(&[])
                    .iter()
                    .fold(T::ZERO, |value, &c| value * x + c)
            }
            _ => x,
        }
    }

    /// The weights of spline `s`'s knots at `t`: the cubic of the last knot at or below `t`
    /// (the first below the second knot), or the end lines outside the knots.
    #[inline(always)]
    fn weights(&self, s: &SplineCode, t: T) -> Weights<T> {
        let n = usize::from(s.knots);
        let start = usize::from(s.x);
        let zero = T::ZERO;
        let Some(x) = self.words.get(start..start + n).filter(|x| x.len() >= 2) else {
            return Weights {
                k: 0,
                w: zero,
                a: zero,
                b: zero,
            };
        };
        let last = n - 1;
        if t < x[0] {
            return Weights {
                k: 0,
                w: zero,
                a: t - x[0],
                b: zero,
            };
        }
        if x[last] < t {
            return Weights {
                k: last - 1,
                w: T::ONE,
                a: zero,
                b: t - x[last],
            };
        }
        // The last knot at or below t, below the last knot (the knots increase), by bisection:
        // x[k] <= t and t < x[end] while they are apart. A NaN t takes the last cubic (the
        // negated comparison), as `Spline::interval`.
        let (mut k, mut end) = (0, last);
        while end - k > 1 {
            let mid = (k + end) / 2;
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(t < x[mid]) {
                k = mid;
            } else {
                end = mid;
            }
        }
        let dx = t - x[k];
        let s_ = dx / (x[k + 1] - x[k]);
        if s.linear != 0 {
            return Weights {
                k,
                w: s_,
                a: zero,
                b: zero,
            };
        }
        let r = T::ONE - s_;
        Weights {
            k,
            w: s_ * s_ * (T::TWO + T::ONE - T::TWO * s_),
            a: dx * r * r,
            b: -(dx * s_ * r),
        }
    }

    /// `M` numbers from `cursor` on (zeros past the pool), the cursor moved past them.
    #[inline(always)]
    fn take<const M: usize>(&self, cursor: &mut usize) -> [T; M] {
        let at = *cursor;
        *cursor = at + M;
        match self.words.get(at..).and_then(|w| w.first_chunk::<M>()) {
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

/// The pool as [`PackedChain::pack`] fills it (numbers past `W` counted, not written).
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

    fn offset<U: Real>(&mut self, o: &Offset<U>) {
        self.vec(o.translation);
        self.quat(o.rotation);
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
                assert!(p.max_abs_diff(*r) < tolerance, "{q:?}: {p:?} {r:?}");
            }
        }
    }

    #[test]
    fn a_packed_chain_is_its_chain() {
        // Oriented frames, general and coordinate axes, a cubic and a straight spline through
        // the same abscissae, a coupler, welds.
        let chain = walker_chain();
        let packed = Packed::<f64>::pack(&chain).unwrap();
        assert_same(&packed, &chain, 1e-14);
        // Its abscissae are stored once.
        assert_eq!(packed.splines[0].x, packed.splines[1].x);
        assert_ne!(packed.splines[0].values, packed.splines[1].values);
        // The straight spline takes the cubic's knot but not its weights.
        let shares = packed.drives[..usize::from(packed.drive_count)]
            .iter()
            .filter(|d| d.function & Drive::SHARES != 0)
            .count();
        assert_eq!(shares, 0);
    }

    #[test]
    fn a_packed_chain_in_f32_is_its_chain_within_f32_rounding() {
        let chain = walker_chain();
        let packed = PackedChain::<f32, 17, 11, 12, 12, 12, 66, 512>::pack(&chain).unwrap();
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
        let full = Packed::<f64>::pack(&chain).unwrap();
        let small = PackedChain::<f64, 17, 11, 12, 12, 12, 66, 16>::pack(&chain);
        assert_eq!(
            small,
            Err(PackError::Words {
                needed: usize::from(full.used)
            })
        );
        let no_splines = PackedChain::<f64, 17, 11, 12, 1, 12, 66, 512>::pack(&chain);
        assert_eq!(no_splines, Err(PackError::Functions));
    }

    #[test]
    fn any_table_evaluates_without_panicking() {
        // Codes pointing past the pool, past the tables, at bodies that do not exist.
        let mut packed = Packed::<f32>::pack(&walker_chain()).unwrap();
        let mut state = 0x2545_f491u32;
        let mut byte = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as u8
        };
        for _ in 0..200 {
            for j in &mut packed.joints {
                j.parent = byte();
                j.moving = byte();
                j.shape = byte();
                j.kinds = byte();
                j.words = u16::from(byte()) * 3;
            }
            for d in &mut packed.drives {
                *d = Drive {
                    function: byte(),
                    argument: byte(),
                };
            }
            packed.drive_count = byte();
            for s in &mut packed.splines {
                s.x = u16::from(byte()) * 2;
                s.values = u16::from(byte()) * 2;
                s.knots = byte();
            }
            for p in &mut packed.points {
                p.body = byte() % 16;
            }
            packed.coupler_count = byte();
            packed.points_at = u16::from(byte()) * 2;
            let _ = packed.forward(&[0.3; 17]);
        }
    }
}
