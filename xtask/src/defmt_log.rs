//! The firmware's defmt log decoding lives in the host library (`qgait::device::defmt_log`),
//! shared with `qgait emulate`; re-exported here for the xtask commands.

pub use qgait::device::defmt_log::table;
