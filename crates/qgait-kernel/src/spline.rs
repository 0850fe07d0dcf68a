//! OpenSim's `SimmSpline`: the cubic spline that drives gait2392's knee translations.

use crate::{ModelError, Real};

/// Most knots a [`Spline`] holds (gait2392's knee uses 12 and 7).
pub const MAX_KNOTS: usize = 12;

/// A cubic spline through up to `K` knots ([`MAX_KNOTS`] unless said: gait2392's size), exactly as OpenSim's `SimmSpline`: the
/// Forsythe-Malcolm-Moler construction, not a natural spline (tridiagonal system; at each end
/// the third derivative equals that of the cubic through the four end knots; two knots give a
/// line, three a zero third derivative at the ends) and linear extrapolation with the end slope
/// outside the knots. `docs/protocol.md` section 9.3 writes the algorithm out.
///
/// Coefficients are computed once (in `f64` by [`Spline::new`], in `T` by
/// [`Spline::from_knots`]) and stored in `T`; evaluation is allocation-free and branch-free.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spline<T, const K: usize = MAX_KNOTS> {
    /// Index of the last knot (the knot count less one; 0 for [`EMPTY`](Self::EMPTY), which has
    /// none): what evaluation reads, with no arithmetic on it.
    last: usize,
    x: [T; K],
    y: [T; K],
    b: [T; K],
    c: [T; K],
    d: [T; K],
}

impl<T: Real, const K: usize> Spline<T, K> {
    /// The spline without knots (all zero bits): zero everywhere. What an unset chain
    /// ([`Chain::EMPTY`](crate::Chain::EMPTY)) holds; the constructors never return it.
    pub const EMPTY: Self = Self {
        last: 0,
        x: [T::ZERO; K],
        y: [T::ZERO; K],
        b: [T::ZERO; K],
        c: [T::ZERO; K],
        d: [T::ZERO; K],
    };

    /// Builds the spline through knots `(x[i], y[i])`; `x` strictly increasing, 2 to
    /// [`MAX_KNOTS`] knots, all finite. The coefficients are computed in `f64`, then rounded to
    /// `T` (see [`from_knots`](Self::from_knots) for the same in `T`).
    pub fn new(x: &[f64], y: &[f64]) -> Result<Self, ModelError> {
        Spline::<f64, K>::from_knots(x, y).map(|s| s.cast())
    }

    /// The same spline as [`new`](Self::new), with its coefficients computed in `T` itself:
    /// identical for `f64`; for `f32` it needs no double-precision arithmetic (a
    /// microcontroller with a single-precision FPU builds it without software `f64`), and
    /// differs from `new`'s rounded coefficients by a few `f32` ulps.
    pub fn from_knots(x: &[T], y: &[T]) -> Result<Self, ModelError> {
        let n = x.len();
        if n != y.len() || !(2..=K).contains(&n) {
            return Err(ModelError::SplineKnots);
        }
        if x.iter().chain(y).any(|v| !v.is_finite()) || x.windows(2).any(|w| w[1] <= w[0]) {
            return Err(ModelError::SplineKnots);
        }
        let mut s = Self {
            last: n - 1,
            x: [T::ZERO; K],
            y: [T::ZERO; K],
            b: [T::ZERO; K],
            c: [T::ZERO; K],
            d: [T::ZERO; K],
        };
        s.x[..n].copy_from_slice(x);
        s.y[..n].copy_from_slice(y);
        fmm_coefficients(&mut s);
        Ok(s)
    }

    /// OpenSim's `PiecewiseLinearFunction` through knots `(x[i], y[i])` (same conditions as
    /// [`from_knots`](Self::from_knots)): straight lines between the knots, continued outside
    /// them with the first and last segments' slopes. Stored as a spline whose quadratic and
    /// cubic coefficients are zero, so it evaluates as [`eval`](Self::eval) does.
    pub fn piecewise_linear(x: &[T], y: &[T]) -> Result<Self, ModelError> {
        let mut s = Self::from_knots(x, y)?;
        let last = s.last;
        for i in 0..last {
            s.b[i] = (s.y[i + 1] - s.y[i]) / (s.x[i + 1] - s.x[i]);
        }
        s.b[last] = s.b[last - 1];
        s.c = [T::ZERO; K];
        s.d = [T::ZERO; K];
        Ok(s)
    }

    /// Number of knots.
    pub fn len(&self) -> usize {
        if self.last == 0 {
            0
        } else {
            self.last + 1
        }
    }

    /// The knots' abscissae and values (empty for [`EMPTY`](Self::EMPTY)).
    pub fn knots(&self) -> (&[T], &[T]) {
        let n = self.len().min(K);
        (&self.x[..n], &self.y[..n])
    }

    /// The slope at each knot (the cubics' first coefficients; for
    /// [`piecewise_linear`](Self::piecewise_linear), each segment's slope, the last one's at the
    /// last knot): with the knots, the spline in Hermite form.
    pub fn slopes(&self) -> &[T] {
        &self.b[..self.len().min(K)]
    }

    /// Whether it is straight between its knots (no quadratic or cubic terms): what
    /// [`piecewise_linear`](Self::piecewise_linear) builds, and what `SimmSpline` is through
    /// knots on one line.
    pub fn is_piecewise_linear(&self) -> bool {
        self.c.iter().chain(&self.d).all(|v| *v == T::ZERO)
    }

    /// Whether this is [`EMPTY`](Self::EMPTY): a built spline has at least two knots.
    pub fn is_empty(&self) -> bool {
        self.last == 0
    }

    /// The spline's value at `t` (linear extrapolation outside the knots; NaN for NaN).
    /// Branch-free: the interval is chosen by [`Real::lt_select`], so it also runs lane-wise.
    // Always inlined with `simd`, so the batch path's AVX functions compile it with their
    // target features (an out-of-line copy is baseline SSE2 code, taking and returning lane
    // arrays through memory); a plain hint without it (the device: flash size).
    #[cfg_attr(feature = "simd", inline(always))]
    #[cfg_attr(not(feature = "simd"), inline)]
    pub fn eval(&self, t: T) -> T {
        // (`EMPTY`, all zeros, evaluates to zero.)
        let last = self.last;
        // The cubic of the last knot at or below t (the first one below x[1]).
        let (mut x, mut y, mut b, mut c, mut d) =
            (self.x[0], self.y[0], self.b[0], self.c[0], self.d[0]);
        for k in 1..last {
            let xk = self.x[k];
            x = t.lt_select(xk, x, xk);
            y = t.lt_select(xk, y, self.y[k]);
            b = t.lt_select(xk, b, self.b[k]);
            c = t.lt_select(xk, c, self.c[k]);
            d = t.lt_select(xk, d, self.d[k]);
        }
        self.between_or_outside(last, t, (x, y, b, c, d))
    }

    /// The value of [`eval`](Self::eval), the cubic found by counting the knots at or below
    /// `t` and read by index (one compare a knot, five loads) instead of selected lane-wise
    /// (five selects a knot): for scalar code such as a device's, not for lanes.
    #[inline]
    pub fn eval_scalar(&self, t: T) -> T {
        self.eval_in(self.interval(t), t)
    }

    /// The cubic [`eval_scalar`](Self::eval_scalar) evaluates at `t`: the last knot at or below
    /// `t` (0 below the second knot; the last cubic for NaN). It depends on the knots'
    /// abscissae only, so splines through the same abscissae share it (a knee's four).
    #[inline]
    pub fn interval(&self, t: T) -> usize {
        let last = self.last.min(K - 1);
        let mut k = 0;
        for j in 1..last {
            // As `eval`: the last knot at or below t (a NaN t takes the last cubic, hence the
            // negated comparison).
            #[allow(clippy::neg_cmp_op_on_partial_ord)]
            if !(t < self.x[j]) {
                k = j;
            }
        }
        k
    }

    /// [`eval_scalar`](Self::eval_scalar) at `t` with its cubic `k` found already
    /// ([`interval`](Self::interval) of `t`, of this spline or of one through the same
    /// abscissae): bit for bit `eval_scalar(t)`.
    #[inline]
    pub fn eval_in(&self, k: usize, t: T) -> T {
        let last = self.last.min(K - 1);
        let (x, y, b, c, d) = (self.x[k], self.y[k], self.b[k], self.c[k], self.d[k]);
        self.between_or_outside(last, t, (x, y, b, c, d))
    }

    /// The cubic `(x, y, b, c, d)` at `t` between the knots, the end lines outside them.
    #[inline(always)]
    fn between_or_outside(&self, last: usize, t: T, (x, y, b, c, d): (T, T, T, T, T)) -> T {
        let dx = t - x;
        let inside = y + dx * (b + dx * (c + dx * d));
        let below = self.y[0] + (t - self.x[0]) * self.b[0];
        let above = self.y[last] + (t - self.x[last]) * self.b[last];
        let v = t.lt_select(self.x[0], below, inside);
        self.x[last].lt_select(t, above, v)
    }

    /// The value of [`eval_scalar`](Self::eval_scalar) at `t` and its first and second
    /// derivatives, analytic: the cubic's between the knots, the end lines' outside them (the
    /// second derivative 0 there, and between the knots of a piecewise-linear function).
    #[inline]
    pub fn eval_derivatives(&self, t: T) -> (T, T, T) {
        let last = self.last.min(K - 1);
        let k = self.interval(t);
        let (x, y, b, c, d) = (self.x[k], self.y[k], self.b[k], self.c[k], self.d[k]);
        let dx = t - x;
        let three = T::TWO + T::ONE;
        let inside = (
            y + dx * (b + dx * (c + dx * d)),
            b + dx * (T::TWO * c + three * d * dx),
            T::TWO * (c + three * d * dx),
        );
        let zero = T::ZERO;
        if t < self.x[0] {
            (self.y[0] + (t - self.x[0]) * self.b[0], self.b[0], zero)
        } else if self.x[last] < t {
            (
                self.y[last] + (t - self.x[last]) * self.b[last],
                self.b[last],
                zero,
            )
        } else {
            inside
        }
    }

    /// Whether `interval` is the same function for both: the same knot count and abscissae.
    pub fn same_abscissae(&self, other: &Self) -> bool {
        self.last == other.last && self.knots().0 == other.knots().0
    }

    /// Converts to another precision.
    pub fn cast<U: Real>(&self) -> Spline<U, K> {
        let conv = |a: &[T; K]| a.map(|v| U::from_f64(v.to_f64()));
        Spline {
            last: self.last,
            x: conv(&self.x),
            y: conv(&self.y),
            b: conv(&self.b),
            c: conv(&self.c),
            d: conv(&self.d),
        }
    }
}

/// Forsythe, Malcolm & Moler, *Computer Methods for Mathematical Computations* (1977),
/// subroutine SPLINE, as used by OpenSim's SimmSpline: `y ≈ y[i] + b dx + c dx² + d dx³`.
/// Fills `s.b`, `s.c`, `s.d` from the `s.last + 1` knots in `s.x`, `s.y` (`2 <= n <= MAX_KNOTS`,
/// checked by the caller), in `T`.
fn fmm_coefficients<T: Real, const K: usize>(s: &mut Spline<T, K>) {
    let n = (s.last + 1).clamp(2, K);
    let (x, y) = (&s.x, &s.y);
    let (b, c, d) = (&mut s.b, &mut s.c, &mut s.d);
    if n < 3 {
        let slope = (y[1] - y[0]) / (x[1] - x[0]);
        b[0] = slope;
        b[1] = slope;
        return;
    }
    let two = T::TWO;
    let three = T::TWO + T::ONE;
    let nm1 = n - 1;
    let nm2 = n - 2;
    // Tridiagonal system: b = diagonal, d = off-diagonal, c = right-hand side.
    d[0] = x[1] - x[0];
    c[1] = (y[1] - y[0]) / d[0];
    for i in 1..nm1 {
        d[i] = x[i + 1] - x[i];
        b[i] = two * (d[i - 1] + d[i]);
        c[i + 1] = (y[i + 1] - y[i]) / d[i];
        c[i] = c[i + 1] - c[i];
    }
    // End conditions: third derivatives from divided differences of the end knots.
    b[0] = -d[0];
    b[nm1] = -d[nm2];
    c[0] = T::ZERO;
    c[nm1] = T::ZERO;
    if n > 3 {
        c[0] = c[2] / (x[3] - x[1]) - c[1] / (x[2] - x[0]);
        c[nm1] = c[nm2] / (x[nm1] - x[n - 3]) - c[n - 3] / (x[nm2] - x[n - 4]);
        c[0] = c[0] * d[0] * d[0] / (x[3] - x[0]);
        c[nm1] = -c[nm1] * d[nm2] * d[nm2] / (x[nm1] - x[n - 4]);
    }
    // Forward elimination, then back substitution.
    for i in 1..n {
        let t = d[i - 1] / b[i - 1];
        b[i] -= t * d[i - 1];
        c[i] -= t * c[i - 1];
    }
    c[nm1] = c[nm1] / b[nm1];
    for i in (0..nm1).rev() {
        c[i] = (c[i] - d[i] * c[i + 1]) / b[i];
    }
    // Polynomial coefficients.
    b[nm1] = (y[nm1] - y[nm2]) / d[nm2] + d[nm2] * (c[nm2] + two * c[nm1]);
    for i in 0..nm1 {
        b[i] = (y[i + 1] - y[i]) / d[i] - d[i] * (c[i + 1] + two * c[i]);
        d[i] = (c[i + 1] - c[i]) / d[i];
        c[i] *= three;
    }
    c[nm1] *= three;
    d[nm1] = d[nm2];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_its_knots_and_reproduces_cubics() {
        // A cubic is reproduced exactly by the FMM end conditions.
        let f = |x: f64| 0.3 - 0.2 * x + 0.5 * x * x - 0.1 * x * x * x;
        let xs = [-2.0, -1.2, -0.3, 0.4, 1.0, 2.5, 3.0];
        let ys = xs.map(f);
        let s = Spline::<f64>::new(&xs, &ys).unwrap();
        for i in 0..=100 {
            let t = -2.0 + 5.0 * i as f64 / 100.0;
            assert!((s.eval(t) - f(t)).abs() < 1e-12, "{t}");
        }
        for (x, y) in xs.iter().zip(ys) {
            assert!((s.eval(*x) - y).abs() < 1e-14);
        }
    }

    #[test]
    fn extrapolates_linearly_with_end_slopes() {
        let xs = [0.0, 1.0, 2.0, 4.0];
        let ys = [0.0, 1.0, 0.5, 2.0];
        let s = Spline::<f64>::new(&xs, &ys).unwrap();
        let h = 1e-6;
        let left_slope = (s.eval(h) - s.eval(0.0)) / h;
        assert!((s.eval(-1.0) - (0.0 - left_slope)).abs() < 1e-5);
        let right_slope = (s.eval(4.0) - s.eval(4.0 - h)) / h;
        assert!((s.eval(5.0) - (2.0 + right_slope)).abs() < 1e-5);
        assert!(s.eval(f64::NAN).is_nan());
    }

    #[test]
    fn piecewise_linear_joins_its_knots_with_lines_and_continues_the_end_ones() {
        let xs = [0.0, 1.0, 3.0];
        let ys = [1.0, 3.0, 2.0];
        let s = Spline::<f64, 4>::piecewise_linear(&xs, &ys).unwrap();
        for (t, v) in [
            (-1.0, -1.0),
            (0.0, 1.0),
            (0.5, 2.0),
            (1.0, 3.0),
            (2.0, 2.5),
            (3.0, 2.0),
            (5.0, 1.0),
        ] {
            assert!((s.eval(t) - v).abs() < 1e-15, "{t}: {}", s.eval(t));
        }
        assert!(Spline::<f64, 2>::piecewise_linear(&xs, &ys).is_err());
    }

    /// The scalar evaluation is the lane-wise one, bit for bit, inside, outside, on the knots
    /// and for NaN, at every knot count.
    #[test]
    fn eval_scalar_is_eval() {
        let xs = [-2.0, -1.2, -0.3, 0.4, 1.0, 2.5, 3.0, 3.5];
        let ys = [0.1, -0.4, 0.3, 0.35, -0.2, 0.0, 0.6, 0.2];
        for n in 2..=8 {
            let s = Spline::<f64, 8>::from_knots(&xs[..n], &ys[..n]).unwrap();
            let (x32, y32) = (xs.map(|v| v as f32), ys.map(|v| v as f32));
            let l = Spline::<f32, 8>::piecewise_linear(&x32[..n], &y32[..n]).unwrap();
            for i in 0..=300 {
                let t = -3.0 + 7.5 * f64::from(i) / 300.0;
                assert_eq!(s.eval_scalar(t).to_bits(), s.eval(t).to_bits(), "{n} {t}");
                let t = t as f32;
                assert_eq!(l.eval_scalar(t).to_bits(), l.eval(t).to_bits(), "{n} {t}");
            }
            for x in &xs[..n] {
                assert_eq!(s.eval_scalar(*x).to_bits(), s.eval(*x).to_bits());
            }
            assert!(s.eval_scalar(f64::NAN).is_nan());
        }
        assert_eq!(Spline::<f32, 4>::EMPTY.eval_scalar(1.5), 0.0);
    }

    #[test]
    fn rejects_bad_knots() {
        assert!(Spline::<f64>::new(&[0.0], &[1.0]).is_err());
        assert!(Spline::<f64>::new(&[0.0, 0.0], &[1.0, 2.0]).is_err());
        assert!(Spline::<f64>::new(&[0.0, f64::NAN], &[1.0, 2.0]).is_err());
        assert!(Spline::<f64>::new(&[0.0; 13], &[0.0; 13]).is_err());
        assert!(Spline::<f64>::new(&[0.0, 1.0], &[1.0]).is_err());
    }

    #[test]
    // The knots are gait2392's data (rounded degrees in radians), not approximations of pi.
    #[allow(clippy::approx_constant)]
    fn from_knots_is_new_in_f64_and_within_f32_rounding_in_f32() {
        let xs = [
            -2.0944, -1.74533, -1.39626, -1.0472, -0.698132, -0.349066, -0.174533, 0.197344,
            0.337395, 0.490178, 1.52146, 2.0944,
        ];
        let ys = [
            -0.0032, 0.00179, 0.00411, 0.0041, 0.00212, -0.001, -0.0031, -0.005227, -0.005435,
            -0.005574, -0.005435, -0.00525,
        ];
        for n in [2, 3, 4, 7, 12] {
            let (x, y) = (&xs[..n], &ys[..n]);
            assert_eq!(Spline::<f64>::from_knots(x, y), Spline::<f64>::new(x, y));
            let x32: [f32; MAX_KNOTS] = xs.map(|v| v as f32);
            let y32: [f32; MAX_KNOTS] = ys.map(|v| v as f32);
            let s32 = Spline::<f32>::from_knots(&x32[..n], &y32[..n]).unwrap();
            let s64 = Spline::<f64>::new(x, y).unwrap();
            for i in 0..=400 {
                let t = -2.5 + 5.0 * i as f64 / 400.0;
                let err = (f64::from(s32.eval(t as f32)) - s64.eval(t)).abs();
                assert!(err < 1e-8, "{n} knots at {t}: {err}");
            }
        }
        assert!(Spline::<f32>::from_knots(&[0.0, 0.0], &[1.0, 2.0]).is_err());
        assert!(Spline::<f32>::from_knots(&[0.0, f32::INFINITY], &[1.0, 2.0]).is_err());
    }
}
