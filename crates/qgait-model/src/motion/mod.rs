//! Where a motion comes from: a file or a built-in gait ([`source`], [`builtin`]).

pub mod builtin;
pub mod source;
