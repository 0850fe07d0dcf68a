#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod diagnostics;
pub mod export;
pub mod imu_sto;
pub mod mot;
pub mod osim;
pub mod pelvis_markers;
pub mod vendor;
