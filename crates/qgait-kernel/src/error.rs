//! The kernel's one error type: a model description that cannot be evaluated.

use core::fmt;

/// Why a chain (model) description was rejected. Checked once, when the chain is built, so
/// that evaluating it can never fail or panic.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ModelError {
    /// A joint names a parent that is not an earlier joint, or a joint other than the first
    /// has no parent (a chain has one root, joint 0).
    ParentOrder {
        /// Index of the offending joint.
        joint: usize,
    },
    /// A joint axis or spline translation reads a coordinate index outside the input.
    CoordinateOutOfRange {
        /// Index of the offending joint.
        joint: usize,
    },
    /// A point or spline translation refers to a joint that does not exist.
    BodyOutOfRange {
        /// Index of the offending point or spline.
        index: usize,
    },
    /// A joint rotation axis has zero or non-finite length.
    BadAxis {
        /// Index of the offending joint.
        joint: usize,
    },
    /// A spline needs 2 to [`MAX_KNOTS`](crate::spline::MAX_KNOTS) finite knots with strictly
    /// increasing abscissae.
    SplineKnots,
    /// A segment length is negative, zero where it must not be, or not finite.
    BadLength,
    /// A polynomial needs 1 to [`MAX_COEFFICIENTS`](crate::polynomial::MAX_COEFFICIENTS) finite
    /// coefficients.
    PolynomialCoefficients,
    /// A chain has more moving axes or numbers than its table holds (a
    /// [`CustomChain`](crate::models::CustomChain)'s `D` and `W`).
    TableSize,
}

impl fmt::Display for ModelError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ParentOrder { joint } => {
                write!(
                    f,
                    "joint {joint} has no parent or one that is not an earlier joint"
                )
            }
            Self::CoordinateOutOfRange { joint } => {
                write!(f, "joint {joint} reads a coordinate outside the input")
            }
            Self::BodyOutOfRange { index } => {
                write!(f, "point or spline {index} refers to a missing joint")
            }
            Self::BadAxis { joint } => {
                write!(f, "joint {joint} has a zero or non-finite rotation axis")
            }
            Self::SplineKnots => {
                f.write_str("a spline needs 2 to 12 finite knots with increasing x")
            }
            Self::BadLength => f.write_str("segment lengths must be finite and non-negative"),
            Self::TableSize => {
                f.write_str("the chain has more moving axes or numbers than its table holds")
            }
            // The number is `polynomial::MAX_COEFFICIENTS` (a test there holds them equal).
            Self::PolynomialCoefficients => {
                f.write_str("a polynomial needs 1 to 8 finite coefficients")
            }
        }
    }
}

impl core::error::Error for ModelError {}
