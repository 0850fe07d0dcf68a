#![no_std]
#![doc = include_str!("../README.md")]
#![warn(missing_docs)]
// Two exceptions, each allowed in its module with a SAFETY comment: `trig::vfp` (the FPU's
// square root on Arm hard-float targets) and `lanes`' x86-64 module (the batch compiled with
// AVX2 / AVX-512 target features, called after checking the CPU has them).
#![deny(unsafe_code)]

pub mod anthropometry;
pub mod chain;
pub mod differential;
mod error;
pub mod fusion;
pub mod imu;
pub mod lanes;
pub mod metrics;
pub mod models;
pub mod polynomial;
mod pose;
pub mod progression;
mod quat;
#[cfg(feature = "reference")]
pub mod reference;
mod scalar;
pub mod spline;
pub mod trig;
mod vec3;

pub use anthropometry::{Anthropometry, Limb};
pub use chain::{Axis, Chain, Frame, JointSpec, PointSpec, SplineTranslation};
pub use error::ModelError;
pub use models::{Gait2392, Gait2392Geometry, Gait2392Pose, Hak, HakAngles, Phak, PhakAngles};
pub use polynomial::Polynomial;
pub use pose::{BilateralPose, Joint, LegPose, Side};
pub use quat::Quat;
pub use scalar::Real;
pub use spline::Spline;
pub use vec3::Vec3;
