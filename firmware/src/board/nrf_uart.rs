//! Driver of the nRF52840's UART0 (the legacy, non-DMA UART), implementing the `embedded-io`
//! serial traits (`Read` and `ReadReady`: what the ring holds;
//! `Write` and `WriteReady`: byte by byte). Its error also implements `embedded-hal-nb`'s
//! serial `Error`, whose kinds the hub counts by. 8N1, no flow control. Reception is
//! interrupt-driven into an [`RxRing`]; transmission is polled. One instance per program (the
//! ring is a static).

use cortex_m::peripheral::NVIC;

use super::mmio::Registers;
use super::rx_ring::{HandlerSlot, Irq, RxConsumer, RxProducer, RxRing};

const TASKS_STARTRX: usize = 0x000;
const TASKS_STARTTX: usize = 0x008;
const EVENTS_RXDRDY: usize = 0x108;
const EVENTS_TXDRDY: usize = 0x11C;
const EVENTS_ERROR: usize = 0x124;
const INTENSET: usize = 0x304;
const INTENCLR: usize = 0x308;
const ERRORSRC: usize = 0x480;
const ENABLE: usize = 0x500;
const PSEL_RTS: usize = 0x508;
const PSEL_TXD: usize = 0x50C;
const PSEL_CTS: usize = 0x510;
const PSEL_RXD: usize = 0x514;
const RXD: usize = 0x518;
const TXD: usize = 0x51C;
const BAUDRATE: usize = 0x524;
const CONFIG: usize = 0x56C;

const ENABLE_UART: u32 = 4;
const PSEL_DISCONNECTED: u32 = 1 << 31;
const ERRORSRC_OVERRUN: u32 = 1 << 0;
const ERRORSRC_PARITY: u32 = 1 << 1;
const INT_RXDRDY: u32 = 1 << 2;
const INT_ERROR: u32 = 1 << 9;

static RX: RxRing<UartError> = RxRing::new();
/// The ring's producer end, used by the interrupt handler alone.
static RX_PRODUCER: HandlerSlot<RxProducer<UartError>> = HandlerSlot::new();

/// BAUDRATE register value for 115200 baud.
pub const BAUD_115200: u32 = 0x01D7_E000;
/// BAUDRATE register value for 1 Mbaud.
pub const BAUD_1M: u32 = 0x1000_0000;

/// A receive error reported by ERRORSRC.
#[derive(Debug, Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum UartError {
    /// A byte arrived before the previous one was read.
    Overrun,
    /// Parity error.
    Parity,
    /// Framing error or break.
    Framing,
}

impl embedded_hal_nb::serial::Error for UartError {
    fn kind(&self) -> embedded_hal_nb::serial::ErrorKind {
        use embedded_hal_nb::serial::ErrorKind;
        match self {
            UartError::Overrun => ErrorKind::Overrun,
            UartError::Parity => ErrorKind::Parity,
            UartError::Framing => ErrorKind::FrameFormat,
        }
    }
}

impl embedded_io::Error for UartError {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

/// UART0 with its receiver and transmitter started.
#[derive(Debug)]
pub struct NrfUart {
    regs: Registers,
    tx_busy: bool,
    rx: RxConsumer<UartError>,
}

impl NrfUart {
    /// Enables the UART at `base` on GPIO `tx_pin` / `rx_pin` (port 0 pin numbers) at
    /// `baudrate` (a BAUDRATE register value such as [`BAUD_115200`]), with its interrupt
    /// `irq`, whose handler must call [`on_interrupt`](Self::on_interrupt). `None` if an
    /// `NrfUart` was made before (the receive ring is a static, split once).
    ///
    /// # Safety
    /// `base` must be the address of an nRF52 UART that nothing else uses and `irq` its
    /// interrupt.
    pub unsafe fn new(
        base: usize,
        tx_pin: u32,
        rx_pin: u32,
        baudrate: u32,
        irq: u16,
    ) -> Option<NrfUart> {
        let (producer, rx) = RX.split()?;
        // SAFETY: the interrupt is still masked (unmasked below, once), and `split` let only
        // this call get here.
        unsafe { RX_PRODUCER.put(producer) };
        // SAFETY: the contract above: `base` is this driver's UART.
        let uart = unsafe { Registers::at(base) };
        uart.write_reg(PSEL_TXD, tx_pin & 0x3F);
        uart.write_reg(PSEL_RXD, rx_pin & 0x3F);
        uart.write_reg(PSEL_RTS, PSEL_DISCONNECTED);
        uart.write_reg(PSEL_CTS, PSEL_DISCONNECTED);
        uart.write_reg(BAUDRATE, baudrate);
        uart.write_reg(CONFIG, 0);
        uart.write_reg(ENABLE, ENABLE_UART);
        uart.write_reg(INTENSET, INT_RXDRDY | INT_ERROR);
        uart.write_reg(TASKS_STARTRX, 1);
        uart.write_reg(TASKS_STARTTX, 1);
        // SAFETY: the handler only touches the ring's producer end, which is its own.
        unsafe { NVIC::unmask(Irq(irq)) };
        Some(NrfUart {
            regs: uart,
            tx_busy: false,
            rx,
        })
    }

    /// The interrupt handler's work: records receive errors and moves every received byte
    /// (the FIFO holds up to six) into the ring.
    ///
    /// # Safety
    /// `base` must be the UART given to [`new`](Self::new); call it only from its interrupt.
    pub unsafe fn on_interrupt(base: usize) {
        // SAFETY: the contract above: `base` is this driver's UART.
        let uart = unsafe { Registers::at(base) };
        // SAFETY: called from the UART's interrupt only (the contract above), the slot's owner.
        let Some(rx) = (unsafe { RX_PRODUCER.get() }) else {
            // No ring end (the interrupt was enabled by something other than `new`): stop
            // receiving rather than interrupt forever.
            uart.write_reg(INTENCLR, INT_RXDRDY | INT_ERROR);
            return;
        };
        if uart.read_reg(EVENTS_ERROR) != 0 {
            uart.write_reg(EVENTS_ERROR, 0);
            let source = uart.read_reg(ERRORSRC);
            uart.write_reg(ERRORSRC, source); // write 1 to clear
            rx.push_error(if source & ERRORSRC_OVERRUN != 0 {
                UartError::Overrun
            } else if source & ERRORSRC_PARITY != 0 {
                UartError::Parity
            } else {
                UartError::Framing
            });
        }
        while uart.read_reg(EVENTS_RXDRDY) != 0 {
            // Clear the event before reading RXD, as the reference manual requires; it is set
            // again while the FIFO holds more.
            uart.write_reg(EVENTS_RXDRDY, 0);
            rx.push(uart.read_reg(RXD) as u8, UartError::Overrun);
        }
        // Read back so the cleared events reach the peripheral before the handler returns
        // (otherwise the interrupt fires again at once).
        let _ = uart.read_reg(EVENTS_ERROR);
    }

    fn tx_ready(&mut self) -> bool {
        if self.tx_busy && self.regs.read_reg(EVENTS_TXDRDY) != 0 {
            self.tx_busy = false;
        }
        !self.tx_busy
    }

    /// Writes `byte` to TXD (which has room: [`tx_ready`](Self::tx_ready)).
    fn put(&mut self, byte: u8) {
        self.regs.write_reg(EVENTS_TXDRDY, 0);
        self.regs.write_reg(TXD, byte as u32);
        self.tx_busy = true;
    }

    /// Nothing to do after a read: the handler never pauses reception (a full ring counts the
    /// lost bytes as overruns).
    fn after_read(&mut self) {}
}

super::embedded_io_impl::impl_embedded_io!(NrfUart, UartError);
