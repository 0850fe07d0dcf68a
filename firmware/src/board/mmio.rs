//! A peripheral's memory-mapped 32-bit registers, for the CMSDK UART driver (the nRF52840's come
//! from its PAC).

use core::ptr::{read_volatile, write_volatile};

/// The register block at a base address.
#[derive(Debug)]
pub(crate) struct Registers(usize);

impl Registers {
    /// The registers at `base`.
    ///
    /// # Safety
    /// `base` must be the address of a peripheral's register block that the caller's driver
    /// owns, and every offset it reads or writes must be one of that peripheral's registers.
    pub(crate) unsafe fn at(base: usize) -> Registers {
        Registers(base)
    }

    /// Reads the register at `offset`.
    pub(crate) fn read_reg(&self, offset: usize) -> u32 {
        // SAFETY: `at`'s contract: a register of a peripheral the driver owns.
        unsafe { read_volatile((self.0 + offset) as *const u32) }
    }

    /// Writes `value` to the register at `offset`.
    pub(crate) fn write_reg(&self, offset: usize, value: u32) {
        // SAFETY: as in `read_reg`.
        unsafe { write_volatile((self.0 + offset) as *mut u32, value) }
    }
}
