//! Driver of the ARM CMSDK APB UART (the UARTs of the MPS2 boards and QEMU's `mps2-an386`),
//! implementing the `embedded-io` serial traits (`Read` and `ReadReady`, `Write` and
//! `WriteReady`): a read copies what the ring holds, a write sends a buffer byte by byte.
//! Reception is interrupt-driven into an [`RxRing`]; transmission is polled. One instance per
//! program (the ring is a static). Its error also implements
//! `embedded-hal-nb`'s serial `Error`, whose kind (overrun) the hub counts by.
//!
//! Back-pressure: when the ring is full the interrupt handler leaves the next byte in the UART
//! and masks the receive interrupt; the application unmasks it (and re-runs the handler) as soon
//! as it has taken bytes. On hardware a sender that keeps going then overruns the UART's
//! one-byte buffer, which is counted (`RXOVR`) like any overrun; under QEMU, whose UART only
//! accepts a host byte when its buffer is empty, the host sender is simply held back, so a test
//! loses nothing however slowly the emulated CPU runs on a loaded machine.

use core::sync::atomic::{AtomicBool, Ordering};

use cortex_m::peripheral::NVIC;

use super::mmio::Registers;
use super::rx_ring::{HandlerSlot, RxConsumer, RxProducer, RxRing};

const DATA: usize = 0x00;
const STATE: usize = 0x04;
const CTRL: usize = 0x08;
const INTCLEAR: usize = 0x0C;
const BAUDDIV: usize = 0x10;

const STATE_TXFULL: u32 = 1 << 0;
const STATE_RXFULL: u32 = 1 << 1;
const STATE_RXOVR: u32 = 1 << 3;

const CTRL_TXEN: u32 = 1 << 0;
const CTRL_RXEN: u32 = 1 << 1;
const CTRL_RXIE: u32 = 1 << 3;
const INT_RX: u32 = 1 << 1;

/// An interrupt number for [`cortex_m::peripheral::NVIC`] (the MPS2 board has no PAC).
#[derive(Debug, Clone, Copy)]
struct Irq(u16);

// SAFETY: the number is a device interrupt line of the board that creates it.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}

static RX: RxRing<Overrun> = RxRing::new();
/// The ring's producer end, used by the interrupt handler alone.
static RX_PRODUCER: HandlerSlot<RxProducer<Overrun>> = HandlerSlot::new();
/// Set by the interrupt handler when it stopped receiving because the ring was full.
static RX_PAUSED: AtomicBool = AtomicBool::new(false);

/// The only error the UART reports: a received byte was lost because the previous one had not
/// been read yet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub struct Overrun;

impl embedded_hal_nb::serial::Error for Overrun {
    fn kind(&self) -> embedded_hal_nb::serial::ErrorKind {
        embedded_hal_nb::serial::ErrorKind::Overrun
    }
}

impl embedded_io::Error for Overrun {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

/// One CMSDK UART, transmitter and receiver enabled.
#[derive(Debug)]
pub struct CmsdkUart {
    regs: Registers,
    irq: u16,
    rx: RxConsumer<Overrun>,
}

impl CmsdkUart {
    /// Enables the UART at `base` with baud divider `bauddiv` (>= 16; the baud rate is the APB
    /// clock divided by it) and its receive interrupt `irq`, whose handler must call
    /// [`on_interrupt`](Self::on_interrupt). `None` if a `CmsdkUart` was made before (the
    /// receive ring is a static, split once).
    ///
    /// # Safety
    /// `base` must be the address of a CMSDK UART that nothing else uses and `irq` its receive
    /// interrupt.
    pub unsafe fn new(base: usize, bauddiv: u32, irq: u16) -> Option<CmsdkUart> {
        let (producer, rx) = RX.split()?;
        // SAFETY: the interrupt is still masked (unmasked below, once), and `split` let only
        // this call get here.
        unsafe { RX_PRODUCER.put(producer) };
        let uart = CmsdkUart {
            // SAFETY: `new`'s contract: `base` is this driver's UART.
            regs: unsafe { Registers::at(base) },
            irq,
            rx,
        };
        uart.regs.write_reg(BAUDDIV, bauddiv.max(16));
        uart.regs.write_reg(CTRL, CTRL_TXEN | CTRL_RXEN | CTRL_RXIE);
        // QEMU 7.2 may not deliver host bytes that arrived before RX was enabled until DATA is
        // read once (see qemu-notes.md); harmless on hardware (the byte would be stale anyway).
        let _ = uart.regs.read_reg(DATA);
        // SAFETY: the handler only touches the ring's producer end, which is its own.
        unsafe { NVIC::unmask(Irq(irq)) };
        Some(uart)
    }

    /// The receive interrupt handler's work: moves every received byte into the ring and
    /// records overruns.
    ///
    /// # Safety
    /// `base` must be the UART given to [`new`](Self::new); call it only from its interrupt.
    pub unsafe fn on_interrupt(base: usize) {
        // SAFETY: the contract above: `base` is this driver's UART.
        let uart = unsafe { Registers::at(base) };
        // Clear first: a byte arriving after the drain below raises the interrupt again.
        uart.write_reg(INTCLEAR, INT_RX);
        // SAFETY: called from the UART's interrupt only (the contract above), the slot's owner.
        let Some(rx) = (unsafe { RX_PRODUCER.get() }) else {
            // No ring end (the interrupt was unmasked by something other than `new`): stop
            // receiving rather than interrupt forever.
            uart.write_reg(CTRL, uart.read_reg(CTRL) & !CTRL_RXIE);
            return;
        };
        loop {
            let state = uart.read_reg(STATE);
            if state & STATE_RXOVR != 0 {
                uart.write_reg(STATE, STATE_RXOVR); // write 1 to clear
                rx.push_error(Overrun);
            }
            if state & STATE_RXFULL == 0 {
                break;
            }
            if rx.is_full() {
                // Leave the byte in the UART and stop until the application makes room.
                RX_PAUSED.store(true, Ordering::Release);
                uart.write_reg(CTRL, uart.read_reg(CTRL) & !CTRL_RXIE);
                break;
            }
            rx.push(uart.read_reg(DATA) as u8, Overrun);
        }
    }

    fn tx_ready(&mut self) -> bool {
        self.regs.read_reg(STATE) & STATE_TXFULL == 0
    }

    /// Writes `byte` to the transmit register (which has room: [`tx_ready`](Self::tx_ready)).
    fn put(&mut self, byte: u8) {
        self.regs.write_reg(DATA, byte as u32);
    }

    /// After a read took bytes or an error from the ring: if the interrupt handler paused
    /// reception because the ring was full, there is room again, so it unmasks the receive
    /// interrupt and runs the handler for the byte waiting in the UART (unmasking alone does
    /// not raise the interrupt for it).
    fn after_read(&mut self) {
        if RX_PAUSED.swap(false, Ordering::AcqRel) {
            self.regs
                .write_reg(CTRL, self.regs.read_reg(CTRL) | CTRL_RXIE);
            NVIC::pend(Irq(self.irq));
        }
    }
}

super::embedded_io_impl::impl_embedded_io!(CmsdkUart, Overrun);
