//! Peak stack use by stack painting.
//!
//! cortex-m-rt's `paint-stack` feature fills the whole stack region, from `_stack_end` (just
//! above the statics) to `_stack_start` (the top of RAM), with [`cortex_m_rt::STACK_PAINT_VALUE`]
//! before `main`. The stack grows down from the top and scrubs the paint off; the lowest word
//! that is no longer paint marks the deepest the stack has ever been.

use cortex_m_rt::STACK_PAINT_VALUE;

extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
}

fn bounds() -> (usize, usize) {
    // Only the addresses of the linker symbols are taken, never their contents.
    (
        core::ptr::addr_of!(_stack_end) as usize,
        core::ptr::addr_of!(_stack_start) as usize,
    )
}

/// Size of the stack region (bytes).
pub fn size() -> u32 {
    let (bottom, top) = bounds();
    (top - bottom) as u32
}

/// The deepest the stack has been since reset (bytes), found by scanning the paint upwards
/// from the bottom of the stack region.
pub fn peak() -> u32 {
    let (bottom, top) = bounds();
    let mut addr = bottom;
    while addr < top {
        // SAFETY: `addr` is a word-aligned address inside the stack region, which is RAM.
        // Words below the current stack pointer are not in use by anyone; reading them is fine.
        let word = unsafe { core::ptr::read_volatile(addr as *const u32) };
        if word != STACK_PAINT_VALUE {
            break;
        }
        addr += 4;
    }
    (top - addr) as u32
}

/// Logs the stack's peak and size (`stack peak N bytes of M`, the figure `cargo xtask
/// footprint` reads from the log).
pub fn log_peak() {
    defmt::info!("stack peak {=u32} bytes of {=u32}", peak(), size());
}
