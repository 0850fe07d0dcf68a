//! embedded-io for the UART drivers: the byte-wise embedded-hal-nb traits each driver
//! implements, lifted to buffers in one place.

/// Implements `embedded_io::{ErrorType, ReadReady, Read, WriteReady, Write}` for a UART type
/// `$uart` that implements `embedded_hal_nb::serial::{Read, Write}<u8>` with error `$error`,
/// has a `tx_ready(&self) -> bool` method, and whose receive ring is the static `$rx`.
macro_rules! impl_embedded_io {
    ($uart:ty, $error:ty, $rx:path) => {
        impl embedded_io::ErrorType for $uart {
            type Error = $error;
        }

        impl embedded_io::ReadReady for $uart {
            fn read_ready(&mut self) -> Result<bool, $error> {
                Ok($rx.is_ready())
            }
        }

        impl embedded_io::Read for $uart {
            /// Blocks until at least one byte arrived, then returns what is there (at most
            /// `buf.len()`).
            fn read(&mut self, buf: &mut [u8]) -> Result<usize, $error> {
                let mut n = 0;
                while n < buf.len() {
                    match embedded_hal_nb::serial::Read::read(self) {
                        Ok(b) => {
                            buf[n] = b;
                            n += 1;
                        }
                        Err(nb::Error::WouldBlock) if n > 0 => break,
                        Err(nb::Error::WouldBlock) => core::hint::spin_loop(),
                        Err(nb::Error::Other(e)) => return Err(e),
                    }
                }
                Ok(n)
            }
        }

        impl embedded_io::WriteReady for $uart {
            fn write_ready(&mut self) -> Result<bool, $error> {
                Ok(self.tx_ready())
            }
        }

        impl embedded_io::Write for $uart {
            fn write(&mut self, buf: &[u8]) -> Result<usize, $error> {
                for &b in buf {
                    nb::block!(embedded_hal_nb::serial::Write::write(self, b))?;
                }
                Ok(buf.len())
            }

            fn flush(&mut self) -> Result<(), $error> {
                nb::block!(embedded_hal_nb::serial::Write::flush(self))
            }
        }
    };
}

pub(crate) use impl_embedded_io;
