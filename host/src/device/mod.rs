//! The hub as a device: the byte streams its IMU nodes send ([`packets`]), what it sends back
//! ([`log`], [`frames_csv`]), checking its poses against the `f64` kernel ([`verify`]). A real
//! hub is read from its serial port as frames arrive ([`port`]; the CLI shows it live,
//! `cli::live`). Running its firmware under QEMU, and damaging streams as a radio link does, is
//! the `qgait-emulate` crate's.

pub mod config;
pub mod frames_csv;
pub mod log;
pub mod orientations;
pub mod packets;
pub(crate) mod port;
pub mod verify;
