//! The hub as a device: the byte streams its IMU nodes send ([`packets`]), what it sends back
//! ([`log`], [`frames_csv`]), checking its poses against the `f64` kernel ([`verify`]), and
//! running its firmware under QEMU with a stream fed into its UART ([`qemu`], [`defmt_log`],
//! [`session`], [`firmware`]); [`faults`] damages streams the ways a radio link does. A real
//! hub is read from its serial port as frames arrive ([`port`]; the CLI shows it live, `cli::live`).

pub mod config;
pub mod defmt_log;
pub mod faults;
pub mod firmware;
pub mod frames_csv;
pub mod log;
pub mod packets;
pub mod port;
pub mod qemu;
pub mod session;
pub mod verify;
