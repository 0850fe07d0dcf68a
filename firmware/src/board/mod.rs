//! The board: memory layout (`memory.x`), the UART, the millisecond clock and how a run ends.
//! Exactly one board feature is enabled: `mps2-an386` (QEMU, the default) or `nrf52840`.
//!
//! Every board module offers the same items: `NAME`, `Serial`, `take() -> Option<Board>`,
//! `exit(code) -> !` and `UART_IRQ` (its serial port's interrupt line, which sets how many
//! device interrupt vectors it needs: [`DEVICE_VECTORS`]); the exit statuses of a failed run
//! are here too.

#[cfg(all(feature = "mps2-an386", feature = "nrf52840"))]
compile_error!("enable exactly one board feature: `mps2-an386` or `nrf52840`");
#[cfg(not(any(feature = "mps2-an386", feature = "nrf52840")))]
compile_error!("enable one board feature: `mps2-an386` (default) or `nrf52840`");

mod embedded_io_impl;
#[cfg(feature = "mps2-an386")]
mod mmio;
pub mod rx_ring;
pub mod systick_clock;
mod vectors;

#[cfg(feature = "mps2-an386")]
pub mod cmsdk_uart;
#[cfg(feature = "mps2-an386")]
mod mps2_an386;
#[cfg(feature = "mps2-an386")]
pub use mps2_an386::{exit, take, Serial, NAME, UART_IRQ};

#[cfg(feature = "nrf52840")]
mod nrf52840;
#[cfg(feature = "nrf52840")]
pub mod nrf_uart;
#[cfg(feature = "nrf52840")]
pub use nrf52840::{exit, take, Serial, NAME, UART_IRQ};

pub use systick_clock::SysTickClock;

/// Device interrupt vectors the board needs: up to its UART's line (`board::vectors`).
pub const DEVICE_VECTORS: usize = UART_IRQ as usize + 1;

/// Exit status after a panic ([`fault`](crate::fault)).
pub const PANIC_EXIT_CODE: i32 = 101;
/// Exit status after a HardFault ([`fault`](crate::fault)).
pub const HARDFAULT_EXIT_CODE: i32 = 102;
/// Exit status after an interrupt or exception that nothing handles.
pub const UNEXPECTED_INTERRUPT_EXIT_CODE: i32 = 103;

use core::sync::atomic::{AtomicBool, Ordering};

/// The peripherals the application uses.
pub struct Board {
    /// The serial port to the IMU nodes and the host.
    pub serial: Serial,
    /// Milliseconds since boot.
    pub clock: SysTickClock,
}

/// The board's peripherals the first time it is called, `None` after: every device interrupt
/// masked, the serial port `serial` makes, SysTick counting milliseconds of a `core_hz` clock.
fn take_once(core_hz: u32, serial: impl FnOnce() -> Option<Serial>) -> Option<Board> {
    static TAKEN: AtomicBool = AtomicBool::new(false);
    if TAKEN.swap(true, Ordering::AcqRel) {
        return None;
    }
    let mut core = cortex_m::Peripherals::take()?;
    vectors::mask_all(&mut core.NVIC);
    let serial = serial()?;
    Some(Board {
        serial,
        clock: SysTickClock::start(core.SYST, core_hz),
    })
}

/// The board's `DefaultHandler`: every device interrupt lands there (the board's vector table,
/// `board::vectors`, points all of them at it). The UART's (line `$irq`) is served by
/// `$serve`, the board's `unsafe` block calling that UART's interrupt work; anything else is a
/// bug that ends the run with a failure rather than looping.
macro_rules! serve_uart_interrupt {
    ($irq:expr, $serve:expr) => {
        #[cortex_m_rt::exception]
        unsafe fn DefaultHandler(irqn: i16) {
            if irqn == $irq as i16 {
                $serve;
            } else {
                defmt::error!("unexpected interrupt {=i16}", irqn);
                exit($crate::board::UNEXPECTED_INTERRUPT_EXIT_CODE);
            }
        }
    };
}
use serve_uart_interrupt;
