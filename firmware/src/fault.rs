//! Panic and HardFault handlers: log through defmt, then end the run with a failure status
//! (under QEMU the emulator exits with it, so a panic fails any test; see [`board::exit`]).

use cortex_m_rt::{exception, ExceptionFrame};

use crate::board::{self, HARDFAULT_EXIT_CODE, PANIC_EXIT_CODE};

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
