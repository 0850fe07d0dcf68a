//! ARM MPS2 AN386 (Cortex-M4F) as emulated by QEMU: CMSDK UART0, SysTick on the 25 MHz core
//! clock, and semihosting to end a run with an exit status.

use defmt_semihosting as _;

use super::cmsdk_uart::CmsdkUart;
use super::Board;

/// Board name, for logs.
pub const NAME: &str = "mps2-an386";

/// The board's serial port.
pub type Serial = CmsdkUart;

const UART0_BASE: usize = 0x4000_4000;
/// The UART's (UART0's receive) interrupt line.
pub const UART_IRQ: u16 = 0;
const CORE_HZ: u32 = 25_000_000;
/// 25 MHz / 217 = 115200 baud (QEMU ignores the rate; hardware honours it).
const BAUDDIV_115200: u32 = 217;

/// The board's peripherals, the first time; `None` after.
pub fn take() -> Option<Board> {
    super::take_once(CORE_HZ, || {
        // SAFETY: UART0 is used only through this driver, created once (`take_once` runs this
        // at most once).
        unsafe { CmsdkUart::new(UART0_BASE, BAUDDIV_115200, UART_IRQ) }
    })
}

super::serve_uart_interrupt!(
    UART_IRQ,
    // SAFETY: `UART0_BASE` is the UART `take` creates with this interrupt, and this is its
    // interrupt's handler.
    unsafe { CmsdkUart::on_interrupt(UART0_BASE) }
);

/// Ends the run: QEMU exits with `code` (semihosting `SYS_EXIT_EXTENDED`).
pub fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}
