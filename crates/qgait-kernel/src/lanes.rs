//! Lane arrays: `L` numbers computed in lock-step ([`LANES`] on the portable path, a register's
//! worth on the x86-64 [`Simd`] levels). [`Lanes<f64, L>`](Lanes) and `Lanes<f32, L>`
//! implement [`Real`], so the one chain evaluator ([`Chain::forward`]) runs over a batch of
//! frames in structure-of-arrays form, and the compiler turns each lane-wise loop into SIMD
//! instructions. This is how the batch API is fast without a second copy of the maths.

use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::{trig, Chain, Real, Vec3};

/// Frames evaluated together by the portable batch path (every target, `no_std`); the x86-64
/// paths of [`Simd`] use wider lane arrays (see [`LaneScalar::lanes`]).
pub const LANES: usize = 4;

/// `L` values of `T` ([`LANES`] unless said otherwise), one per frame of a batch. Comparisons
/// (`PartialOrd`) are lexicographic and meaningless here: lane-wise choices go through
/// [`Real::lt_select`].
///
/// Aligned to 32 bytes (a whole AVX register for 4 `f64` or 8 `f32`; measured: the AVX-512
/// level's PHAK `f64` batch took about 20 % longer with the arrays at their natural 8-byte
/// alignment, whose 64-byte loads and stores then straddle cache lines).
///
/// `FUSED` lane arrays evaluate the half-angle polynomials with fused multiply-adds
/// ([`LaneScalar::half_angle_sin_cos_fused`]); only the FMA levels of [`Simd`] use them.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
#[repr(align(32))]
pub struct Lanes<T, const L: usize = LANES, const FUSED: bool = false>(pub [T; L]);

impl<T: Default + Copy, const L: usize, const F: bool> Default for Lanes<T, L, F> {
    fn default() -> Self {
        Lanes([T::default(); L])
    }
}

/// A scalar whose half-angle sine/cosine has a branch-free, library-free form (so it
/// vectorises): `f32` and `f64`. Also fixes the lane count of each [`Simd`] level (a
/// register's worth: 4 `f64` or 8 `f32` with AVX2, 8 or 16 with AVX-512).
pub trait LaneScalar: Real {
    /// `(sin(x/2), cos(x/2))` up to a common sign, branch-free.
    fn half_angle_sin_cos_branchless(self) -> (Self, Self);

    /// [`half_angle_sin_cos_branchless`](Self::half_angle_sin_cos_branchless) with fused
    /// multiply-adds in the polynomials (the FMA levels of [`Simd`]; rounding differs from the
    /// unfused form by about an ulp). Without the `simd` feature (no fused multiply-add in `core`), unfused.
    fn half_angle_sin_cos_fused(self) -> (Self, Self);

    /// Frames evaluated together at `level`.
    fn lanes(level: Simd) -> usize;

    /// [`Chain::forward_batch_on`] for this scalar: runs the batch at `level` (at
    /// [`Simd::Portable`] if this CPU does not support `level`).
    fn forward_batch_on<const N: usize, const J: usize, const P: usize, const S: usize>(
        chain: &Chain<Self, N, J, P, S>,
        level: Simd,
        frames: usize,
        q: &impl Fn(usize) -> [Self; N],
        points: &mut impl FnMut(usize, [Vec3<Self>; P]),
    );
}

macro_rules! lane_scalar {
    ($t:ty, $half_angle:path, $half_angle_with:path, avx2: $avx2:literal, avx512: $avx512:literal) => {
        impl LaneScalar for $t {
            #[inline(always)]
            fn half_angle_sin_cos_branchless(self) -> (Self, Self) {
                $half_angle(self)
            }

            #[inline(always)]
            fn half_angle_sin_cos_fused(self) -> (Self, Self) {
                #[cfg(feature = "simd")]
                {
                    extern crate std;
                    $half_angle_with(self, <$t>::mul_add)
                }
                #[cfg(not(feature = "simd"))]
                {
                    $half_angle(self)
                }
            }

            fn lanes(level: Simd) -> usize {
                match level {
                    Simd::Portable => LANES,
                    Simd::Avx2 => $avx2,
                    Simd::Avx512 => $avx512,
                }
            }

            fn forward_batch_on<const N: usize, const J: usize, const P: usize, const S: usize>(
                chain: &Chain<Self, N, J, P, S>,
                level: Simd,
                frames: usize,
                q: &impl Fn(usize) -> [Self; N],
                points: &mut impl FnMut(usize, [Vec3<Self>; P]),
            ) {
                #[cfg(all(feature = "simd", target_arch = "x86_64"))]
                match level {
                    Simd::Avx512 if level.is_supported() => {
                        return x86::avx512::<_, N, J, P, S, $avx512, true>(
                            chain, frames, q, points,
                        )
                    }
                    Simd::Avx2 if level.is_supported() => {
                        return x86::avx2::<_, N, J, P, S, $avx2, true>(chain, frames, q, points)
                    }
                    _ => {}
                }
                let _ = level;
                batch::<_, N, J, P, S, LANES, false>(chain, frames, q, points)
            }
        }
    };
}
lane_scalar!(f32, trig::half_angle_sin_cos_f32, trig::half_angle_sin_cos_f32_with, avx2: 8, avx512: 16);
lane_scalar!(f64, trig::half_angle_sin_cos_f64, trig::half_angle_sin_cos_f64_with, avx2: 4, avx512: 8);

/// The instruction sets the batch path is compiled for. [`Chain::forward_batch`] (and every
/// model's `fk_batch`) runs at [`Simd::detect`]: the same generic code, instantiated once per
/// level with the level's target features, chosen at run time, so a baseline x86-64 binary
/// uses AVX2 or AVX-512 where the CPU has them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simd {
    /// The build's own target features (SSE2 on baseline x86-64), [`LANES`] lanes. Every
    /// target, with or without `simd`.
    Portable,
    /// x86-64 with AVX2 and FMA (the `x86-64-v3` level). The half-angle polynomials use fused
    /// multiply-adds ([`LaneScalar::half_angle_sin_cos_fused`]); the rest of the evaluator's
    /// `a * b + c` stays unfused (Rust does not contract), so results differ from `Portable`
    /// by rounding only.
    Avx2,
    /// x86-64 with AVX-512F (and AVX2, FMA).
    Avx512,
}

impl Simd {
    /// Every level, slowest first.
    pub const ALL: [Simd; 3] = [Simd::Portable, Simd::Avx2, Simd::Avx512];

    /// Whether this CPU runs `self`: always for `Portable`; the others need x86-64, the
    /// kernel's `simd` feature (run-time CPU feature detection) and the CPU features.
    pub fn is_supported(self) -> bool {
        match self {
            Simd::Portable => true,
            #[cfg(all(feature = "simd", target_arch = "x86_64"))]
            Simd::Avx2 => x86::has_avx2(),
            #[cfg(all(feature = "simd", target_arch = "x86_64"))]
            Simd::Avx512 => x86::has_avx512(),
            #[cfg(not(all(feature = "simd", target_arch = "x86_64")))]
            _ => false,
        }
    }

    /// The fastest supported level (the CPU is queried once; the answer is cached by `std`).
    pub fn detect() -> Simd {
        if Simd::Avx512.is_supported() {
            Simd::Avx512
        } else if Simd::Avx2.is_supported() {
            Simd::Avx2
        } else {
            Simd::Portable
        }
    }
}

/// A function with the batch loop's signature, generic over the chain and the lanes (`L`
/// lanes, fused multiply-add if `F`): the chain, how many frames, frame `i`'s coordinates and
/// the sink of each frame's points, their names given by the caller.
macro_rules! batch_fn {
    ($(#[$attr:meta])* $vis:vis fn $name:ident($chain:ident, $frames:ident, $q:ident, $points:ident) $body:block) => {
        $(#[$attr])*
        $vis fn $name<T: LaneScalar, const N: usize, const J: usize, const P: usize, const S: usize, const L: usize, const F: bool>(
            $chain: &Chain<T, N, J, P, S>,
            $frames: usize,
            $q: &impl Fn(usize) -> [T; N],
            $points: &mut impl FnMut(usize, [Vec3<T>; P]),
        ) $body
    };
}

batch_fn! {
    /// The batch loop at `L` lanes, to be inlined into each level's entry point (so it is
    /// compiled with that level's target features).
    #[inline(always)]
    fn batch(chain, frames, q, points) {
        let lanes: Chain<Lanes<T, L, F>, N, J, P, S> = chain.cast();
        let mut start = 0;
        while start < frames {
            let n = (frames - start).min(L);
            // Gather: lane l holds frame start + l (the last frame repeated to fill the batch).
            let inputs: [[T; N]; L] = core::array::from_fn(|l| q(start + l.min(n - 1)));
            let ql: [Lanes<T, L, F>; N] =
                core::array::from_fn(|c| Lanes(core::array::from_fn(|l| inputs[l][c])));
            let out = lanes.forward(&ql);
            // Scatter, reading each lane in place (a by-value `out.map` copies every point's
            // lane arrays once per lane).
            for l in 0..n {
                let frame: [Vec3<T>; P] = core::array::from_fn(|i| {
                    let p = &out[i];
                    Vec3::new(p.x.0[l], p.y.0[l], p.z.0[l])
                });
                points(start + l, frame);
            }
            start += n;
        }
    }
}

/// The x86-64 levels, one of the kernel's two unsafe modules. Written out rather than generated
/// with the `multiversion` crate: its dispatcher only ever runs the best target (the tests and
/// benches run each level by name), compiles one body for every target (the levels differ in
/// lane count and fusing), and picks AVX-512 only on CPUs with Ice Lake's extensions.
#[cfg(all(feature = "simd", target_arch = "x86_64"))]
#[allow(unsafe_code)]
mod x86 {
    extern crate std;

    use super::{batch, LaneScalar};
    use crate::{Chain, Vec3};

    pub(super) fn has_avx2() -> bool {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }

    pub(super) fn has_avx512() -> bool {
        has_avx2() && std::is_x86_feature_detected!("avx512f")
    }

    /// A level: `$name` runs the batch compiled with `$features` (`$inner`), after `$has`
    /// confirms the CPU has them (it panics otherwise).
    macro_rules! level {
        ($(#[$doc:meta])* $name:ident, $inner:ident, $features:literal, $has:ident) => {
            batch_fn! {
                #[target_feature(enable = $features)]
                fn $inner(chain, frames, q, points) {
                    batch::<T, N, J, P, S, L, F>(chain, frames, q, points)
                }
            }

            batch_fn! {
                $(#[$doc])*
                pub(super) fn $name(chain, frames, q, points) {
                    assert!($has());
                    // SAFETY: the CPU has the level's features (checked just above), the only
                    // requirement for calling a function compiled with `target_feature` for
                    // them.
                    unsafe { $inner::<T, N, J, P, S, L, F>(chain, frames, q, points) }
                }
            }
        };
    }

    level!(
        /// The batch compiled for AVX2 + FMA. Panics unless [`has_avx2`].
        avx2, avx2_impl, "avx2,fma", has_avx2
    );
    level!(
        /// The batch compiled for AVX-512F. Panics unless [`has_avx512`].
        avx512, avx512_impl, "avx512f,avx2,fma", has_avx512
    );
}

impl<T: Copy, const L: usize, const F: bool> Lanes<T, L, F> {
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
        impl<T: Real, const L: usize, const F: bool> $trait for Lanes<T, L, F> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, o: Self) -> Self {
                self.zip(o, |a, b| a $op b)
            }
        }
        impl<T: Real, const L: usize, const F: bool> $assign_trait for Lanes<T, L, F> {
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

impl<T: Real, const L: usize, const F: bool> Div for Lanes<T, L, F> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.zip(o, |a, b| a / b)
    }
}

impl<T: Real, const L: usize, const F: bool> Neg for Lanes<T, L, F> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<T: LaneScalar, const L: usize, const F: bool> Real for Lanes<T, L, F> {
    const ZERO: Self = Lanes([T::ZERO; L]);
    const ONE: Self = Lanes([T::ONE; L]);
    const TWO: Self = Lanes([T::TWO; L]);
    const HALF: Self = Lanes([T::HALF; L]);
    /// Broadcast to every lane.
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        Lanes([T::from_f64(x); L])
    }
    /// Broadcast to every lane.
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        Lanes([T::from_f32(x); L])
    }
    fn round(self) -> Self {
        self.map(T::round)
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
        let mut s = [T::ZERO; L];
        let mut c = [T::ZERO; L];
        for i in 0..L {
            (s[i], c[i]) = if F {
                self.0[i].half_angle_sin_cos_fused()
            } else {
                self.0[i].half_angle_sin_cos_branchless()
            };
        }
        (Lanes(s), Lanes(c))
    }
}

impl<T: LaneScalar, const N: usize, const J: usize, const P: usize, const S: usize>
    Chain<T, N, J, P, S>
{
    /// Forward kinematics of many frames: `points(i, q(i))` for `i` in `0..frames`, in groups
    /// of [`LaneScalar::lanes`] frames through [`Lanes`] (the same evaluator as
    /// [`forward`](Chain::forward)), at the fastest [`Simd`] level this CPU supports
    /// ([`Simd::detect`]). Results equal `forward` to within the half-angle sine/cosine's
    /// rounding: the batch always uses the branch-free polynomial, the scalar `f64` path libm.
    /// Every call builds the lane copy of the chain (measured about 0.9 µs for PHAK `f64` at
    /// AVX-512, some 25 frames of batch time), so use it from a few dozen frames on.
    pub fn forward_batch(
        &self,
        frames: usize,
        q: impl Fn(usize) -> [T; N],
        mut points: impl FnMut(usize, [Vec3<T>; P]),
    ) {
        T::forward_batch_on(self, Simd::detect(), frames, &q, &mut points)
    }

    /// [`forward_batch`](Self::forward_batch) at a given [`Simd`] level ([`Simd::Portable`] if
    /// this CPU does not support it): for tests and benchmarks of each level.
    pub fn forward_batch_on(
        &self,
        level: Simd,
        frames: usize,
        q: impl Fn(usize) -> [T; N],
        mut points: impl FnMut(usize, [Vec3<T>; P]),
    ) {
        T::forward_batch_on(self, level, frames, &q, &mut points)
    }
}
