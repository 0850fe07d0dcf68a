//! The UART receive ring's block read (`RxConsumer::read`), on the target (its queues use the
//! Cortex-M's atomics): bytes in order across the end of its array, at most the buffer's
//! length, and each error reported once, after the bytes received before it.

use qgait_firmware::board::rx_ring::{RxConsumer, RxProducer, RxRing, RX_RING_CAPACITY};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum E {
    Overrun,
    Line,
}

/// The ends of `ring`, which must not have been split before.
fn ends(ring: &'static RxRing<E>) -> (RxProducer<E>, RxConsumer<E>) {
    defmt::unwrap!(ring.split().ok_or("the ring was split before"))
}

/// Bytes in order through many wrap-arounds of the array, in reads of every length from 1 to
/// 70 (several copies straddle the end of the array), none lost, none repeated.
pub fn rx_ring_block_read_wraps_around() {
    static RING: RxRing<E> = RxRing::new();
    let (mut tx, mut rx) = ends(&RING);
    // The ends exist once.
    defmt::assert!(RING.split().is_none());
    let mut buf = [0u8; 70];
    defmt::assert!(rx.read(&mut buf) == Ok(0) && !rx.is_ready());
    let (mut sent, mut got, mut len) = (0u32, 0u32, 1);
    while got < 5 * RX_RING_CAPACITY as u32 {
        // Keep the ring between half and nearly full, so reads wrap at every offset.
        while sent - got < (RX_RING_CAPACITY - 3) as u32 {
            tx.push(sent as u8, E::Overrun);
            sent += 1;
        }
        defmt::assert!(rx.is_ready());
        let n = rx.read(&mut buf[..len]);
        defmt::assert!(n == Ok(len));
        for &b in &buf[..len] {
            defmt::assert!(b == got as u8);
            got += 1;
        }
        len = len % buf.len() + 1;
    }
    // Drain: exactly what is left, then nothing.
    let mut left = sent - got;
    while left > 0 {
        let Ok(n) = rx.read(&mut buf) else {
            defmt::panic!("an error in a clean ring");
        };
        defmt::assert!(n > 0 && n as u32 <= left);
        for &b in &buf[..n] {
            defmt::assert!(b == got as u8);
            got += 1;
        }
        left -= n as u32;
    }
    defmt::assert!(rx.read(&mut buf) == Ok(0) && !rx.is_ready());
    defmt::assert!(rx.read(&mut []) == Ok(0));
}

/// An error comes after the bytes received before it and before those received after it, once;
/// a read stops short at it. A full ring's lost byte is an overrun after every byte it holds.
pub fn rx_ring_errors_come_after_the_bytes_before_them() {
    static RING: RxRing<E> = RxRing::new();
    let (mut tx, mut rx) = ends(&RING);
    let mut buf = [0u8; 16];
    for b in 1..=5 {
        tx.push(b, E::Overrun);
    }
    tx.push_error(E::Line);
    for b in 6..=8 {
        tx.push(b, E::Overrun);
    }
    tx.push_error(E::Overrun);
    // A read asks for more than the bytes before the error: it stops there.
    defmt::assert!(rx.read(&mut buf[..3]) == Ok(3) && buf[..3] == [1, 2, 3]);
    defmt::assert!(rx.read(&mut buf) == Ok(2) && buf[..2] == [4, 5]);
    defmt::assert!(rx.read(&mut buf) == Err(E::Line));
    defmt::assert!(rx.read(&mut buf) == Ok(3) && buf[..3] == [6, 7, 8]);
    defmt::assert!(rx.is_ready());
    defmt::assert!(rx.read(&mut buf) == Err(E::Overrun));
    defmt::assert!(rx.read(&mut buf) == Ok(0) && !rx.is_ready());
    // An error with no byte before it (twice in a row, too).
    tx.push_error(E::Line);
    tx.push_error(E::Overrun);
    tx.push(9, E::Overrun);
    defmt::assert!(rx.read(&mut buf) == Err(E::Line));
    defmt::assert!(rx.read(&mut buf) == Err(E::Overrun));
    defmt::assert!(rx.read(&mut buf) == Ok(1) && buf[0] == 9);
    // Full, then one more byte: lost, and reported after the RX_RING_CAPACITY bytes held, which
    // straddle the end of the array (the reads above moved its start).
    for i in 0..RX_RING_CAPACITY {
        tx.push(i as u8, E::Overrun);
    }
    defmt::assert!(tx.is_full());
    tx.push(0xEE, E::Overrun);
    let mut got = 0;
    loop {
        match rx.read(&mut buf) {
            Ok(0) => defmt::panic!("the overrun was not reported"),
            Ok(n) => {
                for &b in &buf[..n] {
                    defmt::assert!(b == got as u8);
                    got += 1;
                }
            }
            Err(e) => {
                defmt::assert!(e == E::Overrun && got == RX_RING_CAPACITY);
                break;
            }
        }
    }
    defmt::assert!(rx.read(&mut buf) == Ok(0) && !rx.is_ready());
}
