#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod anthropometry;
pub mod builtin;
pub mod cli;
pub mod fk_csv;
pub mod kinematics;
pub mod mot;
pub mod progress;
pub mod report;
pub mod source;
