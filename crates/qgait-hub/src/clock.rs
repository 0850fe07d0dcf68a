//! The [`Clock`] the hub reads for uptime and periodic status frames.

/// A monotonic millisecond clock that wraps at `u32::MAX` (about 49.7 days).
pub trait Clock {
    /// Milliseconds since an arbitrary start.
    fn now_ms(&self) -> u32;
}

impl<C: Clock + ?Sized> Clock for &C {
    fn now_ms(&self) -> u32 {
        (**self).now_ms()
    }
}

/// A clock set by hand: for tests and simulations.
#[derive(Debug, Default)]
pub struct ManualClock {
    now_ms: core::cell::Cell<u32>,
}

impl ManualClock {
    /// A clock reading `start_ms`.
    pub fn new(start_ms: u32) -> ManualClock {
        ManualClock {
            now_ms: core::cell::Cell::new(start_ms),
        }
    }

    /// Moves the clock forward by `ms` (wrapping).
    pub fn advance(&self, ms: u32) {
        self.now_ms.set(self.now_ms.get().wrapping_add(ms));
    }
}

impl Clock for ManualClock {
    fn now_ms(&self) -> u32 {
        self.now_ms.get()
    }
}
