//! The receive ring shared by a UART's interrupt handler (producer) and the application
//! (consumer), so that bytes arriving while the application is busy (e.g. writing a pose frame)
//! are kept instead of overrunning the UART's one-byte (CMSDK) or six-byte (nRF52) buffer.

use core::cell::RefCell;

use critical_section::Mutex;
use heapless::Deque;

/// Bytes the ring holds. The longest the hub goes without reading is while it writes a frame
/// (transmission is polled): at most as many bytes arrive as leave, 151 for a PHAK pose frame
/// (172 for gait2392's) at the same baud rate; 256 bytes hold that with room to spare (22 ms
/// at 115200 baud, 2.5 ms at 1 Mbaud), and keep the firmware's RAM within 8 KiB.
pub const RX_RING_LEN: usize = 256;

/// Receive errors kept until the application reads them.
const PENDING_ERRORS: usize = 4;

struct State<E> {
    bytes: [u8; RX_RING_LEN],
    /// Index in `bytes` of the oldest byte.
    head: usize,
    /// Bytes held, from `head` on (wrapping).
    len: usize,
    /// Bytes taken by the application so far (wrapping): with `len`, the position in the
    /// stream of the next byte received.
    taken: u32,
    /// Each error with the position in the stream where it happened: the bytes received before
    /// it are read before it is reported.
    errors: Deque<(E, u32), PENDING_ERRORS>,
}

/// Bytes and receive errors, in a critical section on each access.
pub struct RxRing<E> {
    state: Mutex<RefCell<State<E>>>,
}

impl<E: Copy> RxRing<E> {
    /// An empty ring.
    pub const fn new() -> Self {
        RxRing {
            state: Mutex::new(RefCell::new(State {
                bytes: [0; RX_RING_LEN],
                head: 0,
                len: 0,
                taken: 0,
                errors: Deque::new(),
            })),
        }
    }

    /// Stores a received byte (interrupt side). A full ring loses the byte: that is reported
    /// as `overrun`, like a hardware overrun, after the bytes the ring holds.
    pub fn push(&self, byte: u8, overrun: E) {
        critical_section::with(|cs| {
            let mut s = self.state.borrow_ref_mut(cs);
            if s.len < RX_RING_LEN {
                let tail = (s.head + s.len) % RX_RING_LEN;
                if let Some(slot) = s.bytes.get_mut(tail) {
                    *slot = byte;
                }
                s.len += 1;
            } else {
                s.error_here(overrun);
            }
        });
    }

    /// Records a receive error (interrupt side), after the bytes received so far; beyond a few
    /// pending ones they are dropped.
    pub fn push_error(&self, error: E) {
        critical_section::with(|cs| self.state.borrow_ref_mut(cs).error_here(error));
    }

    /// Application side: copies the oldest bytes into `buf`, as many as there are up to
    /// `buf.len()` and up to the next pending error, in one critical section; `Ok(0)` if there
    /// are none (or `buf` is empty). When the next thing in the stream is an error, returns it
    /// instead (once): errors come in order with the bytes.
    pub fn read(&self, buf: &mut [u8]) -> Result<usize, E> {
        critical_section::with(|cs| {
            let mut s = self.state.borrow_ref_mut(cs);
            let mut n = s.len.min(buf.len());
            if let Some(&(error, at)) = s.errors.front() {
                // Bytes before the error (its position is never behind `taken`).
                let before = at.wrapping_sub(s.taken) as usize;
                if before == 0 {
                    s.errors.pop_front();
                    return Err(error);
                }
                n = n.min(before);
            }
            // At most two pieces: up to the end of the array, then from its start.
            let head = s.head;
            let first = n.min(RX_RING_LEN - head);
            if let (Some(dst), Some(src)) = (buf.get_mut(..first), s.bytes.get(head..head + first))
            {
                dst.copy_from_slice(src);
            }
            if let (Some(dst), Some(src)) = (buf.get_mut(first..n), s.bytes.get(..n - first)) {
                dst.copy_from_slice(src);
            }
            s.head = (head + n) % RX_RING_LEN;
            s.len -= n;
            s.taken = s.taken.wrapping_add(n as u32);
            Ok(n)
        })
    }

    /// Whether the ring has no room for another byte.
    pub fn is_full(&self) -> bool {
        critical_section::with(|cs| self.state.borrow_ref(cs).len == RX_RING_LEN)
    }

    /// Whether a byte or an error is waiting.
    pub fn is_ready(&self) -> bool {
        critical_section::with(|cs| {
            let s = self.state.borrow_ref(cs);
            s.len != 0 || !s.errors.is_empty()
        })
    }
}

impl<E: Copy> State<E> {
    /// Records `error` after the bytes received so far.
    fn error_here(&mut self, error: E) {
        let at = self.taken.wrapping_add(self.len as u32);
        let _ = self.errors.push_back((error, at));
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
