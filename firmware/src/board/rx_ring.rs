//! The receive ring shared by a UART's interrupt handler (producer) and the application
//! (consumer), so that bytes arriving while the application is busy (e.g. writing a pose frame)
//! are kept instead of overrunning the UART's one-byte (CMSDK) or six-byte (nRF52) buffer.

use core::cell::RefCell;

use critical_section::Mutex;
use heapless::Deque;

/// Bytes the ring holds: 5 ms of input at 1 Mbaud.
pub const RX_RING_LEN: usize = 512;

/// Receive errors kept until the application reads them.
const PENDING_ERRORS: usize = 4;

struct State<E> {
    bytes: Deque<u8, RX_RING_LEN>,
    errors: Deque<E, PENDING_ERRORS>,
}

/// Bytes and receive errors, in a critical section on each access.
pub struct RxRing<E> {
    state: Mutex<RefCell<State<E>>>,
}

impl<E: Copy> RxRing<E> {
    /// An empty ring.
    pub const fn new() -> Self {
        RxRing { state: Mutex::new(RefCell::new(State { bytes: Deque::new(), errors: Deque::new() })) }
    }

    /// Stores a received byte (interrupt side). A full ring loses the byte: that is reported
    /// as `overrun`, like a hardware overrun.
    pub fn push(&self, byte: u8, overrun: E) {
        critical_section::with(|cs| {
            let mut s = self.state.borrow_ref_mut(cs);
            if s.bytes.push_back(byte).is_err() {
                let _ = s.errors.push_back(overrun);
            }
        });
    }

    /// Records a receive error (interrupt side); beyond a few pending ones they are merged.
    pub fn push_error(&self, error: E) {
        critical_section::with(|cs| {
            let _ = self.state.borrow_ref_mut(cs).errors.push_back(error);
        });
    }

    /// The oldest pending error if any, else the oldest byte (application side).
    pub fn pop(&self) -> Option<Result<u8, E>> {
        critical_section::with(|cs| {
            let mut s = self.state.borrow_ref_mut(cs);
            match s.errors.pop_front() {
                Some(e) => Some(Err(e)),
                None => s.bytes.pop_front().map(Ok),
            }
        })
    }

    /// Whether the ring has no room for another byte.
    pub fn is_full(&self) -> bool {
        critical_section::with(|cs| self.state.borrow_ref(cs).bytes.is_full())
    }

    /// Whether a byte or an error is waiting.
    pub fn is_ready(&self) -> bool {
        critical_section::with(|cs| {
            let s = self.state.borrow_ref(cs);
            !s.bytes.is_empty() || !s.errors.is_empty()
        })
    }
}

impl<E: Copy> Default for RxRing<E> {
    fn default() -> Self {
        Self::new()
    }
}

/// An interrupt number for [`cortex_m::peripheral::NVIC`] (the boards have no PAC here).
#[derive(Debug, Clone, Copy)]
pub struct Irq(pub u16);

// SAFETY: the number is a device interrupt line of the board that creates it.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}
