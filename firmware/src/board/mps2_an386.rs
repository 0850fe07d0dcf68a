//! ARM MPS2 AN386 (Cortex-M4F) as emulated by QEMU: CMSDK UART0, SysTick on the 25 MHz core
//! clock, and semihosting to end a run with an exit status.

use core::sync::atomic::{AtomicBool, Ordering};

use defmt_semihosting as _;

use cortex_m_rt::exception;

use super::cmsdk_uart::CmsdkUart;
use super::{Board, SysTickClock};

/// Board name, for logs.
pub const NAME: &str = "mps2-an386";

/// The board's serial port.
pub type Serial = CmsdkUart;

const UART0_BASE: usize = 0x4000_4000;
/// UART0 receive interrupt line.
const UART0_RX_IRQ: i16 = 0;
/// Device interrupt vectors: up to the UART's line (`board::vectors`).
pub const DEVICE_VECTORS: usize = UART0_RX_IRQ as usize + 1;
const CORE_HZ: u32 = 25_000_000;
/// 25 MHz / 217 = 115200 baud (QEMU ignores the rate; hardware honours it).
const BAUDDIV_115200: u32 = 217;

static TAKEN: AtomicBool = AtomicBool::new(false);

/// The board's peripherals, the first time; `None` after.
pub fn take() -> Option<Board> {
    if TAKEN.swap(true, Ordering::AcqRel) {
        return None;
    }
    let mut core = cortex_m::Peripherals::take()?;
    super::vectors::mask_all(&mut core.NVIC);
    // SAFETY: UART0 is used only through this driver, created once (guarded by TAKEN).
    let serial = unsafe { CmsdkUart::new(UART0_BASE, BAUDDIV_115200, UART0_RX_IRQ as u16) }?;
    Some(Board {
        serial,
        clock: SysTickClock::start(core.SYST, CORE_HZ),
    })
}

/// Every device interrupt lands here (the board's vector table, `board::vectors`, points all of
/// them at `DefaultHandler`): UART0's receive interrupt is served, anything else is a bug that ends
/// the run with a failure rather than looping.
#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    if irqn == UART0_RX_IRQ {
        // SAFETY: UART0_BASE is the UART created in `take` with this interrupt.
        unsafe { CmsdkUart::on_interrupt(UART0_BASE) };
    } else {
        defmt::error!("unexpected interrupt {=i16}", irqn);
        exit(crate::fault::UNEXPECTED_INTERRUPT_EXIT_CODE);
    }
}

/// Ends the run: QEMU exits with `code` (semihosting `SYS_EXIT_EXTENDED`).
pub fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}
