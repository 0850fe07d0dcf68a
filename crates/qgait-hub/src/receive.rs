//! Reading the serial port, as the hub and the node both do: what the port has, in blocks of
//! the receive buffer, a bounded number of bytes a poll, line errors counted.

use embedded_hal_nb::serial::Error as LineError;
use embedded_io::{ErrorType, Read, ReadReady};
use qgait_proto::Status;

use crate::counters::count_line_error;

/// An application reading frames from a serial port (the [`Hub`](crate::Hub), the IMU node):
/// its port, its receive buffer and what it does with the bytes read.
/// [`receive`](Receiver::receive) is the reading loop.
pub trait Receiver {
    /// The serial port.
    type Port: Read + ReadReady;

    /// The port and the receive buffer (a read's block at most), borrowed together.
    fn port_and_buffer(&mut self) -> (&mut Self::Port, &mut [u8]);

    /// The counters a line error goes to.
    fn counters(&mut self) -> &mut Status;

    /// Handles the first `n` bytes of the receive buffer.
    fn on_received(&mut self, n: usize);

    /// Reads what the port has, at most `max` bytes, in blocks of at most the receive buffer's
    /// length, each handled ([`on_received`](Receiver::on_received)) before the next read; a
    /// line error counted ([`count_line_error`]). Stops at `max`, when nothing is ready, or at
    /// a read of nothing (a port at its end). Returns the bytes read.
    #[inline(always)]
    fn receive(&mut self, max: usize) -> usize
    where
        <Self::Port as ErrorType>::Error: LineError,
    {
        let mut bytes = 0;
        while bytes < max {
            let (port, rx) = self.port_and_buffer();
            // Only what is there: `read` would block on an empty port.
            if !matches!(port.read_ready(), Ok(true)) {
                break;
            }
            let want = rx.len().min(max - bytes);
            match port.read(&mut rx[..want]) {
                // Nothing after all (a port at its end): as if nothing was ready.
                Ok(0) => break,
                Ok(n) => {
                    let n = n.min(want);
                    bytes += n;
                    self.on_received(n);
                }
                Err(e) => count_line_error(self.counters(), e.kind()),
            }
        }
        bytes
    }
}
