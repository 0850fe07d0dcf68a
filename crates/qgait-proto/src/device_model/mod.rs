//! The device model: what a wire configuration means to the kernel, written once for the hub,
//! the host and the tools.
//!
//! - [`Kinematics`]: a wire model ([`ModelId`](crate::ModelId)) and its numbers (segment
//!   lengths, or a gait2392 geometry) as a kernel chain, in `f32` as the hub computes; a
//!   sample's angles (indexed by [`JointId`](crate::JointId)) to the kernel's pose, and the
//!   pose to a [`PoseFrame`](crate::PoseFrame) (built, or encoded straight into bytes).
//! - [`PoseModels`]: every model at once in any precision (the host recomputes a hub's frames
//!   in `f64` with it); [`stick_pose`] and [`gait2392_pose`] are the one mapping from a wire
//!   model and a sample's angles to the kernel's pose that both use. "HAK" is PHAK with a
//!   level, forward-facing pelvis everywhere ([`Phak::fk_hak`](qgait_kernel::Phak::fk_hak)).
//! - [`SubjectParts`] and [`parts_of`]: a subject gait2392 geometry as the six
//!   [`SubjectLeg`](crate::SubjectLeg)/[`SubjectKnee`](crate::SubjectKnee) parts it travels in,
//!   and back.
//! - the IMU input ([`kernel_settings`], [`kernel_mode`], [`packet_quat`] and their inverses):
//!   the wire's heading settings, modes and Q14 quaternions as the kernel's `imu` types, for the
//!   hub and the host alike (segments and heading axes are the kernel's own types).
//! - [`ChainUpload`], [`DeviceChain`], [`table_crc`] and [`chain_pose`]: an imported lower-limb chain (the kernel's `CustomChain`) packed
//!   into the hub's table (the kernel's `PackedChain` in `f32`), the
//!   [`ChainTable`](crate::ChainTable) parts its image travels in, and its pose.
//! - [`Status::count_decode_error`](crate::Status::count_decode_error): which counter a
//!   decode error goes to.
//! - `HubModel` (with the `std` feature): the one model choice of a host configuring a hub
//!   (what to send, and what to recompute its frames with).
//!
//! It lives in the protocol crate because the protocol crate already depends on the kernel and
//! every caller (the hub crate, the firmware, the host, xtask) already depends on the protocol
//! crate: a crate of its own would have had the same dependencies and the same callers, and
//! one more manifest. It is `no_std` and allocates nothing (but `HubModel`, host-only).

mod chain;
mod error;
mod imu;
mod kinematics;
#[cfg(feature = "std")]
mod model;
mod subject;

pub use chain::{
    chain_pose, table_crc, ChainUpload, DeviceChain, LowerLimbChain, CHAIN_IMAGE_LEN, CHAIN_POINTS,
};
pub use error::{ConfigError, MAX_SEGMENT_M};
pub use imu::{input_mode, kernel_mode, kernel_settings, packet_quat, q14_quat, wire_settings};
#[cfg(feature = "chain")]
pub use kinematics::CheckedChain;
pub use kinematics::{
    gait2392_pose, phak_angles, pose_distances, pose_points, sample_angles, stick_pose,
    stick_velocities, Kinematics, PoseModels,
};
#[cfg(feature = "std")]
pub use model::HubModel;
pub use subject::{parts_of, SubjectParts};
