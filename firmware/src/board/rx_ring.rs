//! The receive ring between a UART's interrupt handler (producer) and the application
//! (consumer), so that bytes arriving while the application is busy (e.g. writing a pose frame)
//! are kept instead of overrunning the UART's one-byte (CMSDK) or six-byte (nRF52) buffer.
//!
//! Two lock-free single-producer single-consumer queues (`heapless::spsc`): the bytes, and the
//! receive errors each stamped with its position in the stream, so the application reads them
//! in order with the bytes. Neither side disables interrupts. [`RxRing::split`] hands out the
//! two ends once; the producer end goes to the interrupt handler through a [`HandlerSlot`].

use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicBool, Ordering};

use heapless::spsc::{Consumer, Producer, Queue};

/// Slots of the byte queue; it holds one byte fewer (255). The longest the hub goes without
/// reading is while it writes a frame (transmission is polled): at most as many bytes arrive as
/// leave, 151 for a PHAK pose frame (172 for gait2392's) at the same baud rate; 255 bytes hold
/// that with room to spare (22 ms at 115200 baud, 2.5 ms at 1 Mbaud), and keep the firmware's
/// RAM within 8 KiB. A power of two, so the queue's index arithmetic is a mask.
pub const RX_RING_LEN: usize = 256;

/// Bytes the ring holds.
pub const RX_RING_CAPACITY: usize = RX_RING_LEN - 1;

/// Slots of the error queue: it holds 4 pending receive errors; beyond that they are dropped.
const ERROR_SLOTS: usize = 5;

/// The queues, split once into the ends an interrupt handler and the application use.
pub struct RxRing<E: 'static> {
    bytes: UnsafeCell<Queue<u8, RX_RING_LEN>>,
    errors: UnsafeCell<Queue<(E, u32), ERROR_SLOTS>>,
    split: AtomicBool,
}

// SAFETY: the queues are only reached through `split`, which hands out their ends once; the ends
// are the lock-free SPSC queue's, safe to use from two contexts.
unsafe impl<E: Send> Sync for RxRing<E> {}

impl<E: Copy> RxRing<E> {
    /// An empty ring.
    pub const fn new() -> Self {
        RxRing {
            bytes: UnsafeCell::new(Queue::new()),
            errors: UnsafeCell::new(Queue::new()),
            split: AtomicBool::new(false),
        }
    }

    /// The producer and consumer ends; `None` after the first call.
    pub fn split(&'static self) -> Option<(RxProducer<E>, RxConsumer<E>)> {
        if self.split.swap(true, Ordering::AcqRel) {
            return None;
        }
        // SAFETY: `split` was false, so this is the only call that gets here: no other
        // reference to the queues exists, now or later (the ends below are the only ones).
        let (bytes, errors) = unsafe { (&mut *self.bytes.get(), &mut *self.errors.get()) };
        let (byte_in, byte_out) = bytes.split();
        let (error_in, error_out) = errors.split();
        Some((
            RxProducer {
                bytes: byte_in,
                errors: error_in,
                received: 0,
            },
            RxConsumer {
                bytes: byte_out,
                errors: error_out,
                taken: 0,
            },
        ))
    }
}

impl<E: Copy> Default for RxRing<E> {
    fn default() -> Self {
        Self::new()
    }
}

/// The interrupt handler's end.
pub struct RxProducer<E: 'static> {
    bytes: Producer<'static, u8>,
    errors: Producer<'static, (E, u32)>,
    /// Bytes stored so far (wrapping): the position in the stream of the next one.
    received: u32,
}

impl<E: Copy> RxProducer<E> {
    /// Stores a received byte. A full ring loses the byte: that is reported as `overrun`, like
    /// a hardware overrun, after the bytes the ring holds.
    pub fn push(&mut self, byte: u8, overrun: E) {
        if self.bytes.enqueue(byte).is_ok() {
            self.received = self.received.wrapping_add(1);
        } else {
            self.push_error(overrun);
        }
    }

    /// Records a receive error after the bytes received so far; beyond a few pending ones they
    /// are dropped.
    pub fn push_error(&mut self, error: E) {
        let _ = self.errors.enqueue((error, self.received));
    }

    /// Whether the ring has no room for another byte.
    pub fn is_full(&self) -> bool {
        !self.bytes.ready()
    }
}

/// The application's end.
pub struct RxConsumer<E: 'static> {
    bytes: Consumer<'static, u8>,
    errors: Consumer<'static, (E, u32)>,
    /// Bytes taken so far (wrapping): the position in the stream of the next one.
    taken: u32,
}

impl<E: Copy> RxConsumer<E> {
    /// Copies the oldest bytes into `buf`, as many as there are up to `buf.len()` and up to the
    /// next pending error; `Ok(0)` if there are none (or `buf` is empty). When the next thing in
    /// the stream is an error, returns it instead (once): errors come in order with the bytes.
    pub fn read(&mut self, buf: &mut [u8]) -> Result<usize, E> {
        // Count the bytes before looking at the errors: an error recorded after this count
        // comes after all of these bytes in the stream.
        let mut n = self.bytes.len().min(buf.len());
        if let Some(&(error, at)) = self.errors.peek() {
            // Bytes before the error (its position is never behind `taken`).
            let before = at.wrapping_sub(self.taken) as usize;
            if before == 0 {
                self.errors.dequeue();
                return Err(error);
            }
            n = n.min(before);
        }
        for slot in buf.iter_mut().take(n) {
            // The first `n` bytes are in the queue (the producer only adds).
            *slot = self.bytes.dequeue().unwrap_or(0);
        }
        self.taken = self.taken.wrapping_add(n as u32);
        Ok(n)
    }

    /// Whether a byte or an error is waiting.
    pub fn is_ready(&self) -> bool {
        self.bytes.ready() || self.errors.ready()
    }
}

impl<E> core::fmt::Debug for RxConsumer<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("RxConsumer")
            .field("taken", &self.taken)
            .finish_non_exhaustive()
    }
}

/// Where an interrupt handler keeps what it alone uses (its [`RxProducer`]): put there before
/// the interrupt is enabled, then used only by the handler.
pub struct HandlerSlot<T>(UnsafeCell<Option<T>>);

// SAFETY: by the contracts of `put` and `get`, one context at a time uses the contents.
unsafe impl<T: Send> Sync for HandlerSlot<T> {}

impl<T> HandlerSlot<T> {
    /// An empty slot.
    pub const fn new() -> Self {
        HandlerSlot(UnsafeCell::new(None))
    }

    /// Puts `value` in the slot.
    ///
    /// # Safety
    /// The handler that [`get`](Self::get)s it must not run during this call (its interrupt is
    /// still masked), and no other `put` may run at the same time.
    pub unsafe fn put(&self, value: T) {
        // SAFETY: the contract above: nothing else reaches the slot now.
        unsafe { *self.0.get() = Some(value) }
    }

    /// The contents, if [`put`](Self::put) was called.
    ///
    /// # Safety
    /// Call only from the one interrupt handler that owns the slot (which does not preempt
    /// itself), and drop the reference before it returns.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn get(&self) -> Option<&mut T> {
        // SAFETY: the contract above: the handler is the only user once the slot is filled.
        unsafe { (*self.0.get()).as_mut() }
    }
}

impl<T> Default for HandlerSlot<T> {
    fn default() -> Self {
        Self::new()
    }
}
