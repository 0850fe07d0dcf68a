//! The device interrupt vectors (cortex-m-rt's `__INTERRUPTS`): as many as the board's highest
//! interrupt line in use needs, each `DefaultHandler` (the board's, which serves its UART).
//! cortex-m-rt without a PAC's table would give all 240 a Cortex-M4 can have: 960 B of flash for
//! lines that are never enabled (the nRF52840's PAC is used without its `rt` feature, whose
//! table has all 48 of that chip's lines). A line past the table is never unmasked (only the UART's is, and
//! [`mask_all`] masks every line at boot first), so the core never fetches a vector beyond it.

use super::DEVICE_VECTORS;

unsafe extern "C" {
    /// The board's `#[exception] DefaultHandler`.
    fn DefaultHandler();
}

/// The vectors after the 16 of the core's exceptions.
#[unsafe(link_section = ".vector_table.interrupts")]
#[unsafe(no_mangle)]
static __INTERRUPTS: [unsafe extern "C" fn(); DEVICE_VECTORS] = [DefaultHandler; DEVICE_VECTORS];

/// Masks and unpends every device interrupt line: the table ends at the UART's line, so no line
/// past it may stay enabled from before (a bootloader's). Called once at boot, before the UART
/// unmasks its own.
pub fn mask_all(nvic: &mut cortex_m::peripheral::NVIC) {
    for (icer, icpr) in nvic.icer.iter().zip(&nvic.icpr) {
        // SAFETY: ones written to the clear-enable and clear-pending registers only mask and
        // unpend lines; no handler is running yet.
        unsafe {
            icer.write(u32::MAX);
            icpr.write(u32::MAX);
        }
    }
}
