//! Nordic nRF52840 (Cortex-M4F, 64 MHz, 1 MiB flash, 256 KiB RAM), e.g. the nRF52840-DK:
//! UART0 on the DK's interface-MCU pins (TX P0.06, RX P0.08), SysTick on the core clock, defmt
//! over RTT (probe-rs). Built and linked by CI; it cannot run under QEMU.

use defmt_rtt as _;

use nrf52840_pac::uart0::baudrate::BAUDRATE_A;

use super::nrf_uart::{self, NrfUart};
use super::Board;

/// Board name, for logs.
pub const NAME: &str = "nrf52840";

/// The board's serial port.
pub type Serial = NrfUart;

/// The UART's interrupt line.
pub const UART_IRQ: u16 = nrf_uart::INTERRUPT as u16;
const TX_PIN: u8 = 6;
const RX_PIN: u8 = 8;
const CORE_HZ: u32 = 64_000_000;

/// The board's peripherals, the first time; `None` after.
pub fn take() -> Option<Board> {
    super::take_once(CORE_HZ, || {
        // SAFETY: `take_once` runs this at most once, and nothing else takes the PAC's
        // peripherals: UART0 is used only through this driver.
        let device = unsafe { nrf52840_pac::Peripherals::steal() };
        NrfUart::new(device.UART0, TX_PIN, RX_PIN, BAUDRATE_A::BAUD115200)
    })
}

super::serve_uart_interrupt!(
    UART_IRQ,
    // SAFETY: this is UART0's interrupt's handler.
    unsafe { NrfUart::on_interrupt() }
);

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
