//! Nordic nRF52840 (Cortex-M4F, 64 MHz, 1 MiB flash, 256 KiB RAM), e.g. the nRF52840-DK:
//! UART0 on the DK's interface-MCU pins (TX P0.06, RX P0.08), SysTick on the core clock, defmt
//! over RTT (probe-rs). Built and linked by CI; it cannot run under QEMU.

use defmt_rtt as _;

use super::nrf_uart::{NrfUart, BAUD_115200};
use super::Board;

/// Board name, for logs.
pub const NAME: &str = "nrf52840";

/// The board's serial port.
pub type Serial = NrfUart;

const UART0_BASE: usize = 0x4000_2000;
/// The UARTE0_UART0 interrupt line.
const UART0_IRQ: i16 = 2;
/// Device interrupt vectors: up to the UART's line (`board::vectors`).
pub const DEVICE_VECTORS: usize = UART0_IRQ as usize + 1;
const TX_PIN: u32 = 6;
const RX_PIN: u32 = 8;
const CORE_HZ: u32 = 64_000_000;

/// The board's peripherals, the first time; `None` after.
pub fn take() -> Option<Board> {
    super::take_once(CORE_HZ, || {
        // SAFETY: UART0 is used only through this driver, created once (`take_once` runs this
        // at most once).
        unsafe { NrfUart::new(UART0_BASE, TX_PIN, RX_PIN, BAUD_115200, UART0_IRQ as u16) }
    })
}

super::serve_uart_interrupt!(NrfUart, UART0_BASE, UART0_IRQ);

/// Ends the run. There is no host to report to: success idles, failure resets the MCU so the
/// wearable comes back (probe-rs shows the defmt log leading to it).
pub fn exit(code: i32) -> ! {
    if code == 0 {
        loop {
            cortex_m::asm::wfi();
        }
    }
    cortex_m::peripheral::SCB::sys_reset()
}
