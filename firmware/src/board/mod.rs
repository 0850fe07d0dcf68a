//! The board: memory layout (`memory.x`), the UART, the millisecond clock and how a run ends.
//! Exactly one board feature is enabled: `mps2-an386` (QEMU, the default) or `nrf52840`.
//!
//! Every board module offers the same items: `Serial`, `take() -> Option<Board>`,
//! `exit(code) -> !` and `DEVICE_VECTORS` (how many device interrupt vectors it needs).

#[cfg(all(feature = "mps2-an386", feature = "nrf52840"))]
compile_error!("enable exactly one board feature: `mps2-an386` or `nrf52840`");
#[cfg(not(any(feature = "mps2-an386", feature = "nrf52840")))]
compile_error!("enable one board feature: `mps2-an386` (default) or `nrf52840`");

mod embedded_io_impl;
mod mmio;
pub mod rx_ring;
pub mod systick_clock;
mod vectors;

#[cfg(feature = "mps2-an386")]
pub mod cmsdk_uart;
#[cfg(feature = "mps2-an386")]
mod mps2_an386;
#[cfg(feature = "mps2-an386")]
pub use mps2_an386::{exit, take, Serial, DEVICE_VECTORS, NAME};

#[cfg(feature = "nrf52840")]
mod nrf52840;
#[cfg(feature = "nrf52840")]
pub mod nrf_uart;
#[cfg(feature = "nrf52840")]
pub use nrf52840::{exit, take, Serial, DEVICE_VECTORS, NAME};

pub use systick_clock::SysTickClock;

/// The peripherals the application uses.
pub struct Board {
    /// The serial port to the IMU nodes and the host.
    pub serial: Serial,
    /// Milliseconds since boot.
    pub clock: SysTickClock,
}
