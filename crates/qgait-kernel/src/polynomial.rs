//! OpenSim's `PolynomialFunction`: what Rajagopal-Lai-Uhlrich 2023's walker knee drives its
//! rotations and translations with, where Rajagopal 2015/2016 have splines.

use crate::{ModelError, Real};

/// Most coefficients a [`Polynomial`] holds (degree 7; Rajagopal-Lai-Uhlrich 2023's knee
/// uses 4 and 5).
pub const MAX_COEFFICIENTS: usize = 8;

/// A polynomial of one variable as OpenSim's `PolynomialFunction` (SimTK's
/// `Function::Polynomial`) has it: coefficients highest power first, evaluated by Horner's rule,
/// everywhere (no range, no clamping).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polynomial<T> {
    coefficients: [T; MAX_COEFFICIENTS],
    /// How many of `coefficients` are in use (0 only for [`ZERO`](Self::ZERO)).
    len: u8,
}

impl<T: Real> Polynomial<T> {
    /// No coefficients (all zero bits): zero everywhere. What an unset table holds; [`new`](Self::new)
    /// never returns it.
    pub const ZERO: Self = Polynomial {
        coefficients: [T::ZERO; MAX_COEFFICIENTS],
        len: 0,
    };

    /// The polynomial `c[0] xⁿ + c[1] xⁿ⁻¹ + … + c[n]`: 1 to [`MAX_COEFFICIENTS`] finite
    /// coefficients.
    pub fn new(coefficients: &[T]) -> Result<Self, ModelError> {
        if coefficients.is_empty()
            || coefficients.len() > MAX_COEFFICIENTS
            || !coefficients.iter().all(|c| c.is_finite())
        {
            return Err(ModelError::PolynomialCoefficients);
        }
        let mut p = Self::ZERO;
        p.coefficients[..coefficients.len()].copy_from_slice(coefficients);
        p.len = coefficients.len() as u8;
        Ok(p)
    }

    /// The coefficients, highest power first.
    pub fn coefficients(&self) -> &[T] {
        &self.coefficients[..usize::from(self.len).min(MAX_COEFFICIENTS)]
    }

    /// The value at `x`.
    #[inline]
    pub fn eval(&self, x: T) -> T {
        self.coefficients()
            .iter()
            .fold(T::ZERO, |value, &c| value * x + c)
    }

    /// The value at `x` and the first and second derivatives there.
    #[inline]
    pub fn eval_derivatives(&self, x: T) -> (T, T, T) {
        with_derivatives(self.coefficients(), x)
    }

    /// The same polynomial in another precision.
    pub fn cast<U: Real>(&self) -> Polynomial<U> {
        Polynomial {
            coefficients: self.coefficients.map(|c| U::from_f64(c.to_f64())),
            len: self.len,
        }
    }
}

/// A polynomial's value and first and second derivatives at `x` (coefficients highest power
/// first; Horner's rule for all three).
#[inline(always)]
pub(crate) fn with_derivatives<T: Real>(coefficients: &[T], x: T) -> (T, T, T) {
    let (mut p, mut dp, mut half_ddp) = (T::ZERO, T::ZERO, T::ZERO);
    for &c in coefficients {
        half_ddp = half_ddp * x + dp;
        dp = dp * x + p;
        p = p * x + c;
    }
    (p, dp, half_ddp * T::TWO)
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::string::ToString;

    /// `ModelError`'s message states the most coefficients in words (the error module does not
    /// depend on this one): it must be this module's.
    #[test]
    fn the_error_states_the_most_coefficients() {
        let message = ModelError::PolynomialCoefficients.to_string();
        assert!(
            message.contains(&std::format!("1 to {MAX_COEFFICIENTS} ")),
            "{message}"
        );
    }

    #[test]
    fn evaluates_highest_power_first() {
        // 2x³ - x + 0.5
        let p = Polynomial::new(&[2.0, 0.0, -1.0, 0.5]).unwrap();
        for x in [-2.5f64, -1.0, 0.0, 0.3, 1.0, 2.7] {
            let direct = 2.0 * x * x * x - x + 0.5;
            assert!((p.eval(x) - direct).abs() < 1e-14, "{x}: {}", p.eval(x));
        }
        assert_eq!(p.coefficients(), &[2.0, 0.0, -1.0, 0.5]);
        assert_eq!(Polynomial::new(&[0.25f64]).unwrap().eval(7.0), 0.25);
        assert_eq!(Polynomial::<f64>::ZERO.eval(3.0), 0.0);
    }

    #[test]
    fn refuses_what_it_cannot_evaluate() {
        assert_eq!(
            Polynomial::<f64>::new(&[]),
            Err(ModelError::PolynomialCoefficients)
        );
        assert_eq!(
            Polynomial::new(&[1.0, f64::NAN]),
            Err(ModelError::PolynomialCoefficients)
        );
        assert_eq!(
            Polynomial::new(&[1.0f64; MAX_COEFFICIENTS + 1]),
            Err(ModelError::PolynomialCoefficients)
        );
        assert!(Polynomial::new(&[1.0f64; MAX_COEFFICIENTS]).is_ok());
    }

    #[test]
    fn casts_to_f32() {
        let p = Polynomial::new(&[0.1f64, -0.2, 0.3]).unwrap().cast::<f32>();
        assert_eq!(p.coefficients(), &[0.1f32, -0.2, 0.3]);
    }
}
