#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod config;
pub mod frames_csv;
pub mod log;
pub mod orientations;
pub mod packets;
pub mod port;
pub mod raw;
pub mod raw_hub;
pub mod verify;
