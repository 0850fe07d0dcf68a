#![doc = include_str!("../README.md")]
#![no_std]
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod node;
/// The raw input, shared with the hub's (`qgait_hub::raw`): one implementation of the fusion
/// of a sensor's samples.
pub use qgait_hub::raw as raw_input;

pub use crate::node::{Node, NodePoll, DEFAULT_STATUS_PERIOD_MS, NODE_SEGMENTS, TX_LEN};
pub use crate::raw_input::{orientation_packet, RawInput, RawOutcome, MAX_SEQ_STEP};
