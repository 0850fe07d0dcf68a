//! [`MemorySerial`]: an in-memory serial port for tests, on the host and on the target.

use embedded_hal_nb::serial::{self, ErrorKind};
use heapless::{Deque, Vec};

/// Error of [`MemorySerial`]: the only one it reports is a receive overrun, on demand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Overrun;

impl serial::Error for Overrun {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Overrun
    }
}

/// An in-memory serial port: a receive queue of `RX` bytes and a transmit buffer of `TX` bytes.
#[derive(Debug, Default)]
pub struct MemorySerial<const RX: usize, const TX: usize> {
    rx: Deque<RxItem, RX>,
    tx: Vec<u8, TX>,
    tx_overflow: bool,
}

#[derive(Debug, Clone, Copy)]
enum RxItem {
    Byte(u8),
    Overrun,
}

impl<const RX: usize, const TX: usize> MemorySerial<RX, TX> {
    /// Empty buffers.
    pub const fn new() -> Self {
        MemorySerial { rx: Deque::new(), tx: Vec::new(), tx_overflow: false }
    }

    /// Queues `bytes` for reception; returns how many fit.
    pub fn receive(&mut self, bytes: &[u8]) -> usize {
        bytes.iter().take_while(|&&b| self.rx.push_back(RxItem::Byte(b)).is_ok()).count()
    }

    /// Queues a receive overrun: the read after the bytes queued so far reports it.
    pub fn receive_overrun(&mut self) -> bool {
        self.rx.push_back(RxItem::Overrun).is_ok()
    }

    /// Bytes still waiting to be read.
    pub fn pending(&self) -> usize {
        self.rx.len()
    }

    /// Everything written so far.
    pub fn transmitted(&self) -> &[u8] {
        &self.tx
    }

    /// Whether a write found the transmit buffer full (those bytes were lost).
    pub fn tx_overflowed(&self) -> bool {
        self.tx_overflow
    }
}

impl<const RX: usize, const TX: usize> serial::ErrorType for MemorySerial<RX, TX> {
    type Error = Overrun;
}

impl<const RX: usize, const TX: usize> serial::Read<u8> for MemorySerial<RX, TX> {
    fn read(&mut self) -> nb::Result<u8, Overrun> {
        match self.rx.pop_front() {
            Some(RxItem::Byte(b)) => Ok(b),
            Some(RxItem::Overrun) => Err(nb::Error::Other(Overrun)),
            None => Err(nb::Error::WouldBlock),
        }
    }
}

impl<const RX: usize, const TX: usize> serial::Write<u8> for MemorySerial<RX, TX> {
    fn write(&mut self, byte: u8) -> nb::Result<(), Overrun> {
        if self.tx.push(byte).is_err() {
            self.tx_overflow = true;
        }
        Ok(())
    }

    fn flush(&mut self) -> nb::Result<(), Overrun> {
        Ok(())
    }
}
