#![doc = include_str!("../README.md")]
#![no_std]
#![warn(missing_docs)]
// Two exceptions, allowed where they are with a SAFETY comment: `Hub::init` (and
// `RawInput::write_new` for it) writing the hub's
// fields in place into its uninitialised static.
#![deny(unsafe_code)]

pub mod assembly;
pub mod clock;
pub mod counters;
pub mod hub;
pub mod limits;
pub mod line;
pub mod memory_serial;
pub mod orientation;
mod output;
#[cfg(feature = "fusion")]
pub mod raw;
pub mod velocity;

pub use crate::assembly::{
    Assembler, JointSet, PacketOutcome, Sample, SampleEvent, SegmentAssembler, SegmentSample,
    MAX_WINDOW,
};
pub use crate::clock::{Clock, ManualClock};
pub use crate::hub::{
    Hub, DEFAULT_CONFIG, DEFAULT_STATUS_PERIOD_MS, MAX_BYTES_PER_POLL, READ_CHUNK,
};
pub use crate::line::PollSummary;
pub use crate::memory_serial::MemorySerial;
pub use crate::velocity::Differentiator;
pub use qgait_proto::device_model::{parts_of, ChainUpload, ConfigError, Kinematics, SubjectParts};
