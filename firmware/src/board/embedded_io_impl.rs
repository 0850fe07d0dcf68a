//! embedded-io for the UART drivers, in one place: block reads straight out of the receive
//! ring, block writes through the transmit register byte by byte (the UARTs have no transmit
//! FIFO to fill at once).

/// Implements `embedded_io::{ErrorType, ReadReady, Read, WriteReady, Write}` for a UART type
/// `$uart` with error `$error` whose receive ring's consumer end is its field `rx` (an
/// `RxConsumer<$error>`), given its methods `tx_ready(&mut self) -> bool` (the transmit register takes a byte),
/// `put(&mut self, byte: u8)` (writes it there) and `after_read(&mut self)` (called after each
/// read that took something from the ring).
macro_rules! impl_embedded_io {
    ($uart:ty, $error:ty) => {
        impl embedded_io::ErrorType for $uart {
            type Error = $error;
        }

        impl embedded_io::ReadReady for $uart {
            /// Whether a byte or a receive error is waiting: a `read` then does not block.
            fn read_ready(&mut self) -> Result<bool, $error> {
                Ok(self.rx.is_ready())
            }
        }

        impl embedded_io::Read for $uart {
            /// Blocks until at least one byte arrived, then returns what is there, at most
            /// `buf.len()`, taken out of the ring. A receive error
            /// (hardware, or ring full) is reported once, in order with the bytes: a read
            /// stops short at it and the next read returns it.
            fn read(&mut self, buf: &mut [u8]) -> Result<usize, $error> {
                if buf.is_empty() {
                    return Ok(0);
                }
                loop {
                    let result = self.rx.read(buf);
                    if !matches!(result, Ok(0)) {
                        self.after_read();
                        return result;
                    }
                    core::hint::spin_loop();
                }
            }
        }

        impl embedded_io::WriteReady for $uart {
            fn write_ready(&mut self) -> Result<bool, $error> {
                Ok(self.tx_ready())
            }
        }

        impl embedded_io::Write for $uart {
            /// Writes all of `buf`, each byte as soon as the transmit register takes it.
            fn write(&mut self, buf: &[u8]) -> Result<usize, $error> {
                for &byte in buf {
                    while !self.tx_ready() {
                        core::hint::spin_loop();
                    }
                    self.put(byte);
                }
                Ok(buf.len())
            }

            fn flush(&mut self) -> Result<(), $error> {
                while !self.tx_ready() {
                    core::hint::spin_loop();
                }
                Ok(())
            }
        }
    };
}

pub(crate) use impl_embedded_io;
