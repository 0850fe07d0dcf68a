//! [`MemorySerial`]: an in-memory serial port for tests, on the host and on the target.

use embedded_hal_nb::serial::{self, ErrorKind};
use embedded_io::{Read, ReadReady, Write};
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

impl embedded_io::Error for Overrun {
    fn kind(&self) -> embedded_io::ErrorKind {
        embedded_io::ErrorKind::Other
    }
}

/// An in-memory serial port (`embedded-io` `Read`, `ReadReady`, `Write`): a receive queue of
/// `RX` bytes (and overruns, in order with them) and a transmit buffer of `TX` bytes.
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
        MemorySerial {
            rx: Deque::new(),
            tx: Vec::new(),
            tx_overflow: false,
        }
    }

    /// Queues `bytes` for reception; returns how many fit.
    pub fn receive(&mut self, bytes: &[u8]) -> usize {
        bytes
            .iter()
            .take_while(|&&b| self.rx.push_back(RxItem::Byte(b)).is_ok())
            .count()
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

impl<const RX: usize, const TX: usize> embedded_io::ErrorType for MemorySerial<RX, TX> {
    type Error = Overrun;
}

impl<const RX: usize, const TX: usize> ReadReady for MemorySerial<RX, TX> {
    /// Whether a byte or an overrun is queued.
    fn read_ready(&mut self) -> Result<bool, Overrun> {
        Ok(!self.rx.is_empty())
    }
}

impl<const RX: usize, const TX: usize> Read for MemorySerial<RX, TX> {
    /// The bytes queued, up to `buf.len()` and up to the next queued overrun, which the next
    /// read reports (as a UART driver does). Never blocks: with nothing queued it returns 0,
    /// the end of the stream (the hub asks [`ReadReady`] first).
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Overrun> {
        if let Some(RxItem::Overrun) = self.rx.front() {
            self.rx.pop_front();
            return Err(Overrun);
        }
        let mut n = 0;
        for slot in buf.iter_mut() {
            match self.rx.front() {
                Some(&RxItem::Byte(b)) => {
                    *slot = b;
                    self.rx.pop_front();
                    n += 1;
                }
                _ => break,
            }
        }
        Ok(n)
    }
}

impl<const RX: usize, const TX: usize> Write for MemorySerial<RX, TX> {
    /// Takes the whole of `buf`; what does not fit the transmit buffer is lost and recorded
    /// ([`tx_overflowed`](Self::tx_overflowed)), as a line drops what nobody reads.
    fn write(&mut self, buf: &[u8]) -> Result<usize, Overrun> {
        for &byte in buf {
            if self.tx.push(byte).is_err() {
                self.tx_overflow = true;
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Overrun> {
        Ok(())
    }
}
