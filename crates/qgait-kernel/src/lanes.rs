//! Lane arrays: [`LANES`] numbers computed in lock-step. [`Lanes<f64>`] and [`Lanes<f32>`]
//! implement [`Real`], so the one chain evaluator ([`Chain::forward`]) runs over a batch of
//! frames in structure-of-arrays form, and the compiler turns each lane-wise loop into SIMD
//! instructions. This is how the batch API is fast without a second copy of the maths.

use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::{trig, Chain, Real, Vec3};

/// Frames evaluated together by the batch path.
pub const LANES: usize = 4;

/// [`LANES`] values of `T`, one per frame of a batch. Comparisons (`PartialOrd`) are
/// lexicographic and meaningless here: lane-wise choices go through [`Real::lt_select`].
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Lanes<T>(pub [T; LANES]);

/// A scalar whose half-angle sine/cosine has a branch-free, library-free form (so it
/// vectorises): `f32` and `f64`.
pub trait LaneScalar: Real {
    /// `(sin(x/2), cos(x/2))` up to a common sign, branch-free.
    fn half_angle_sin_cos_branchless(self) -> (Self, Self);
}

impl LaneScalar for f32 {
    #[inline(always)]
    fn half_angle_sin_cos_branchless(self) -> (Self, Self) {
        trig::half_angle_sin_cos_f32(self)
    }
}

impl LaneScalar for f64 {
    #[inline(always)]
    fn half_angle_sin_cos_branchless(self) -> (Self, Self) {
        trig::half_angle_sin_cos_f64(self)
    }
}

impl<T: Copy> Lanes<T> {
    /// Applies `f` lane by lane.
    #[inline(always)]
    fn map(self, f: impl Fn(T) -> T) -> Self {
        Lanes(self.0.map(f))
    }
    /// Combines two lane arrays lane by lane.
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(T, T) -> T) -> Self {
        Lanes(core::array::from_fn(|i| f(self.0[i], o.0[i])))
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt, $assign_trait:ident, $assign_method:ident) => {
        impl<T: Real> $trait for Lanes<T> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
        impl<T: Real> $assign_trait for Lanes<T> {
            #[inline(always)]
            fn $assign_method(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}
lane_op!(Add, add, +, AddAssign, add_assign);
lane_op!(Sub, sub, -, SubAssign, sub_assign);
lane_op!(Mul, mul, *, MulAssign, mul_assign);

impl<T: Real> Div for Lanes<T> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.zip(o, |a, b| a / b)
    }
}

impl<T: Real> Neg for Lanes<T> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<T: LaneScalar> Real for Lanes<T> {
    const ZERO: Self = Lanes([T::ZERO; LANES]);
    const ONE: Self = Lanes([T::ONE; LANES]);
    const TWO: Self = Lanes([T::TWO; LANES]);
    const HALF: Self = Lanes([T::HALF; LANES]);
    /// Broadcast to every lane.
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        Lanes([T::from_f64(x); LANES])
    }
    /// Lane 0 (lane arrays built by [`from_f64`](Real::from_f64) hold one value).
    fn to_f64(self) -> f64 {
        self.0[0].to_f64()
    }
    fn sqrt(self) -> Self {
        self.map(T::sqrt)
    }
    fn abs(self) -> Self {
        self.map(T::abs)
    }
    /// Every lane finite.
    fn is_finite(self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
    fn min(self, o: Self) -> Self {
        self.zip(o, T::min)
    }
    fn max(self, o: Self) -> Self {
        self.zip(o, T::max)
    }
    #[inline(always)]
    fn lt_select(self, other: Self, if_less: Self, otherwise: Self) -> Self {
        Lanes(core::array::from_fn(|i| {
            self.0[i].lt_select(other.0[i], if_less.0[i], otherwise.0[i])
        }))
    }
    fn sin_cos(self) -> (Self, Self) {
        let sc = self.0.map(T::sin_cos);
        (Lanes(sc.map(|p| p.0)), Lanes(sc.map(|p| p.1)))
    }
    #[inline(always)]
    fn half_angle_sin_cos(self) -> (Self, Self) {
        let mut s = [T::ZERO; LANES];
        let mut c = [T::ZERO; LANES];
        for i in 0..LANES {
            (s[i], c[i]) = self.0[i].half_angle_sin_cos_branchless();
        }
        (Lanes(s), Lanes(c))
    }
}

impl<T: LaneScalar, const N: usize, const J: usize, const P: usize, const S: usize>
    Chain<T, N, J, P, S>
{
    /// Forward kinematics of many frames: `points(i, q(i))` for `i` in `0..frames`, in batches
    /// of [`LANES`] through [`Lanes<T>`] (the same evaluator as [`forward`](Chain::forward);
    /// results equal it to within the half-angle sine/cosine's rounding: the batch always uses
    /// the branch-free polynomial, the scalar `f64` path libm). Building the lane copy of the
    /// chain costs about one frame, so use it from a few dozen frames on.
    pub fn forward_batch(
        &self,
        frames: usize,
        q: impl Fn(usize) -> [T; N],
        mut points: impl FnMut(usize, [Vec3<T>; P]),
    ) {
        let lanes: Chain<Lanes<T>, N, J, P, S> = self.cast();
        let mut start = 0;
        while start < frames {
            let n = (frames - start).min(LANES);
            // Gather: lane l holds frame start + l (the last frame repeated to fill the batch).
            let inputs: [[T; N]; LANES] = core::array::from_fn(|l| q(start + l.min(n - 1)));
            let ql: [Lanes<T>; N] =
                core::array::from_fn(|c| Lanes(core::array::from_fn(|l| inputs[l][c])));
            let out = lanes.forward(&ql);
            for l in 0..n {
                points(
                    start + l,
                    out.map(|p| Vec3::new(p.x.0[l], p.y.0[l], p.z.0[l])),
                );
            }
            start += n;
        }
    }
}
