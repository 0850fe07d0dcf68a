//! The models. The built-in ones ([`Hak`], [`Phak`], [`Gait2392`]) are each a
//! [`Chain`](crate::Chain) table built from a subject's numbers and evaluated by
//! [`Chain::forward`](crate::Chain::forward) (coordinate-axis fast paths, no general functions);
//! any other OpenSim lower-limb chain is a [`CustomChain`] (its joints as OpenSim states them),
//! packed into a [`PackedChain`](packed::PackedChain) that evaluates it on the host and the hub.
//!
//! | model | inputs (OpenSim coordinates, radians) | outputs |
//! |---|---|---|
//! | [`Hak`] | `hip_flexion`, `knee_angle`, `ankle_angle` of one leg | hip (origin), knee, ankle, toe |
//! | [`Gait2392`] | the 17 gait2392 coordinates ([`gait2392::COORDINATES`]) | hip, knee, ankle, subtalar, MTP, toe tip of both legs, as OpenSim computes them |
//! | [`LowerLimb`] ([`CustomChain`]) | the 17 gait2392 coordinates | the same 12 points, for any OpenSim lower-limb chain (oriented frames, spline rotations, couplers) |
//! | [`Phak`] | `pelvis_rotation`, `pelvis_list`, then `hip_flexion`, `knee_angle`, `ankle_angle` right and left | hip, knee, ankle, toe of both legs, origin at the pelvis origin, ground axes |

pub mod custom;
#[cfg(feature = "fixtures")]
pub mod fixtures;
pub mod gait2392;
mod hak;
pub mod packed;
pub(crate) mod parts;
mod phak;
pub mod ranges;

pub use custom::{CustomChain, LowerLimb};
pub use gait2392::{Gait2392, Gait2392Geometry, Gait2392Pose};
pub use hak::{Hak, HakAngles, HakChain};
pub use phak::{Phak, PhakAngles, PhakChain};

use crate::Real;
use crate::Vec3;

/// Unit axes, for model tables.
pub(crate) fn x<T: Real>() -> Vec3<T> {
    Vec3::unit_x()
}
pub(crate) fn y<T: Real>() -> Vec3<T> {
    Vec3::unit_y()
}
pub(crate) fn z<T: Real>() -> Vec3<T> {
    Vec3::unit_z()
}
