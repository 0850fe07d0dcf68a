//! ARM MPS2 AN386 (Cortex-M4F) as emulated by QEMU: CMSDK UART0, SysTick on the 25 MHz core
//! clock, and semihosting to end a run with an exit status.

use core::sync::atomic::{AtomicBool, Ordering};

use defmt_semihosting as _;

use super::cmsdk_uart::CmsdkUart;
use super::{Board, SysTickClock};

/// Board name, for logs.
pub const NAME: &str = "mps2-an386";

/// The board's serial port.
pub type Serial = CmsdkUart;

const UART0_BASE: usize = 0x4000_4000;
const CORE_HZ: u32 = 25_000_000;
/// 25 MHz / 217 = 115200 baud (QEMU ignores the rate; hardware honours it).
const BAUDDIV_115200: u32 = 217;

static TAKEN: AtomicBool = AtomicBool::new(false);

/// The board's peripherals, the first time; `None` after.
pub fn take() -> Option<Board> {
    if TAKEN.swap(true, Ordering::AcqRel) {
        return None;
    }
    let core = cortex_m::Peripherals::take()?;
    // SAFETY: UART0 is used only through this driver, created once (guarded by TAKEN).
    let serial = unsafe { CmsdkUart::new(UART0_BASE, BAUDDIV_115200) };
    Some(Board { serial, clock: SysTickClock::start(core.SYST, CORE_HZ) })
}

/// Ends the run: QEMU exits with `code` (semihosting `SYS_EXIT_EXTENDED`).
pub fn exit(code: i32) -> ! {
    semihosting::process::exit(code)
}
