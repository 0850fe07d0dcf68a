#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod cli;
pub(crate) mod progress;
