//! Panic and HardFault handlers: log through defmt, then end the run with a failure status
//! (under QEMU the emulator exits with it, so a panic fails any test; see [`board::exit`]).

use cortex_m_rt::{exception, ExceptionFrame};

use crate::board;

/// Exit status after a panic.
pub const PANIC_EXIT_CODE: i32 = 101;
/// Exit status after a HardFault.
pub const HARDFAULT_EXIT_CODE: i32 = 102;
/// Exit status after an interrupt or exception that nothing handles.
pub const UNEXPECTED_INTERRUPT_EXIT_CODE: i32 = 103;

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    }
    board::exit(PANIC_EXIT_CODE)
}

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    defmt::error!(
        "HardFault: pc={=u32:#010x} lr={=u32:#010x} xpsr={=u32:#010x}",
        frame.pc(),
        frame.lr(),
        frame.xpsr()
    );
    board::exit(HARDFAULT_EXIT_CODE)
}
