//! Driver of the nRF52840's UART0 (the legacy, non-DMA UART), implementing the `embedded-io`
//! serial traits (`Read` and `ReadReady`: what the ring holds;
//! `Write` and `WriteReady`: byte by byte). Its error also implements `embedded-hal-nb`'s
//! serial `Error`, whose kinds the hub counts by. 8N1, no flow control. Reception is
//! interrupt-driven into an [`RxRing`]; transmission is polled. One instance per program (the
//! ring is a static).

use cortex_m::peripheral::NVIC;
use nrf52840_pac::uart0::baudrate::BAUDRATE_A;
use nrf52840_pac::{uart0, Interrupt, UART0};

use super::rx_ring::{HandlerSlot, RxConsumer, RxProducer, RxRing};

static RX: RxRing<UartError> = RxRing::new();
/// The ring's producer end, used by the interrupt handler alone.
static RX_PRODUCER: HandlerSlot<RxProducer<UartError>> = HandlerSlot::new();

/// The interrupt line of UART0 (shared with UARTE0, which this driver does not use).
pub const INTERRUPT: Interrupt = Interrupt::UARTE0_UART0;

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
    uart: UART0,
    tx_busy: bool,
    rx: RxConsumer<UartError>,
}

impl NrfUart {
    /// Enables `uart` on GPIO `tx_pin` / `rx_pin` (port 0 pin numbers, below 32) at
    /// `baudrate`, with its interrupt ([`INTERRUPT`]) unmasked, whose handler must call
    /// [`on_interrupt`](Self::on_interrupt). `None` if an `NrfUart` was made before (the
    /// receive ring is a static, split once).
    pub fn new(uart: UART0, tx_pin: u8, rx_pin: u8, baudrate: BAUDRATE_A) -> Option<NrfUart> {
        let (producer, rx) = RX.split()?;
        // SAFETY: the interrupt is still masked (unmasked below, once), and `split` let only
        // this call get here.
        unsafe { RX_PRODUCER.put(producer) };
        // From zero, not from PSEL's reset value (all ones: port 1, reserved bits set): PIN,
        // PORT 0 and CONNECT are all a PSEL register holds.
        // SAFETY: zero is a valid value of every PSEL field, and PIN takes any 5-bit value
        // (`& 0x1F` keeps it there).
        unsafe {
            uart.psel
                .txd
                .write_with_zero(|w| w.pin().bits(tx_pin & 0x1F).connect().connected());
            uart.psel
                .rxd
                .write_with_zero(|w| w.pin().bits(rx_pin & 0x1F).connect().connected());
            uart.psel
                .rts
                .write_with_zero(|w| w.connect().disconnected());
            uart.psel
                .cts
                .write_with_zero(|w| w.connect().disconnected());
        }
        uart.baudrate.write(|w| w.baudrate().variant(baudrate));
        uart.config.reset();
        uart.enable.write(|w| w.enable().enabled());
        uart.intenset.write(|w| w.rxdrdy().set().error().set());
        uart.tasks_startrx.write(|w| w.tasks_startrx().set_bit());
        uart.tasks_starttx.write(|w| w.tasks_starttx().set_bit());
        // SAFETY: the handler only touches the ring's producer end, which is its own.
        unsafe { NVIC::unmask(INTERRUPT) };
        Some(NrfUart {
            uart,
            tx_busy: false,
            rx,
        })
    }

    /// The interrupt handler's work: records receive errors and moves every received byte
    /// (the FIFO holds up to six) into the ring.
    ///
    /// # Safety
    /// Call it only from UART0's interrupt ([`INTERRUPT`]).
    pub unsafe fn on_interrupt() {
        // SAFETY: the handler's accesses are the ones `NrfUart` leaves to it (events, RXD,
        // ERRORSRC, INTENCLR); the application's `NrfUart` only writes TXD and its event.
        let uart: &uart0::RegisterBlock = unsafe { &*UART0::ptr() };
        // SAFETY: called from the UART's interrupt only (the contract above), the slot's owner.
        let Some(rx) = (unsafe { RX_PRODUCER.get() }) else {
            // No ring end (the interrupt was enabled by something other than `new`): stop
            // receiving rather than interrupt forever.
            uart.intenclr.write(|w| w.rxdrdy().clear().error().clear());
            return;
        };
        if uart.events_error.read().bits() != 0 {
            uart.events_error.reset();
            let source = uart.errorsrc.read();
            // SAFETY: ERRORSRC's bits are cleared by writing them back as read (1 clears).
            uart.errorsrc.write(|w| unsafe { w.bits(source.bits()) });
            rx.push_error(if source.overrun().is_present() {
                UartError::Overrun
            } else if source.parity().is_present() {
                UartError::Parity
            } else {
                UartError::Framing
            });
        }
        while uart.events_rxdrdy.read().bits() != 0 {
            // Clear the event before reading RXD, as the reference manual requires; it is set
            // again while the FIFO holds more.
            uart.events_rxdrdy.reset();
            rx.push(uart.rxd.read().rxd().bits(), UartError::Overrun);
        }
        // Read back so the cleared events reach the peripheral before the handler returns
        // (otherwise the interrupt fires again at once).
        let _ = uart.events_error.read();
    }

    fn tx_ready(&mut self) -> bool {
        if self.tx_busy && self.uart.events_txdrdy.read().bits() != 0 {
            self.tx_busy = false;
        }
        !self.tx_busy
    }

    /// Writes `byte` to TXD (which has room: [`tx_ready`](Self::tx_ready)).
    fn put(&mut self, byte: u8) {
        self.uart.events_txdrdy.reset();
        // SAFETY: TXD's field takes any byte.
        self.uart.txd.write(|w| unsafe { w.txd().bits(byte) });
        self.tx_busy = true;
    }

    /// Nothing to do after a read: the handler never pauses reception (a full ring counts the
    /// lost bytes as overruns).
    fn after_read(&mut self) {}
}

super::embedded_io_impl::impl_embedded_io!(NrfUart, UartError);
