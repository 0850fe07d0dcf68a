//! The UART receive ring's block read (`RxRing::read`), on the target (it takes the
//! Cortex-M's critical section): bytes in order across the end of its array, at most the
//! buffer's length, and each error reported once, after the bytes received before it.

use qgait_firmware::board::rx_ring::{RxRing, RX_RING_LEN};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum E {
    Overrun,
    Line,
}

/// Bytes in order through many wrap-arounds of the array, in reads of every length from 1 to
/// 70 (several copies straddle the end of the array), none lost, none repeated.
pub fn rx_ring_block_read_wraps_around() {
    let ring: RxRing<E> = RxRing::new();
    let mut buf = [0u8; 70];
    defmt::assert!(ring.read(&mut buf) == Ok(0) && !ring.is_ready());
    let (mut sent, mut got, mut len) = (0u32, 0u32, 1);
    while got < 5 * RX_RING_LEN as u32 {
        // Keep the ring between half and nearly full, so reads wrap at every offset.
        while sent - got < (RX_RING_LEN - 3) as u32 {
            ring.push(sent as u8, E::Overrun);
            sent += 1;
        }
        defmt::assert!(ring.is_ready());
        let n = ring.read(&mut buf[..len]);
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
        let Ok(n) = ring.read(&mut buf) else {
            defmt::panic!("an error in a clean ring");
        };
        defmt::assert!(n > 0 && n as u32 <= left);
        for &b in &buf[..n] {
            defmt::assert!(b == got as u8);
            got += 1;
        }
        left -= n as u32;
    }
    defmt::assert!(ring.read(&mut buf) == Ok(0) && !ring.is_ready());
    defmt::assert!(ring.read(&mut []) == Ok(0));
}

/// An error comes after the bytes received before it and before those received after it, once;
/// a read stops short at it. A full ring's lost byte is an overrun after every byte it holds.
pub fn rx_ring_errors_come_after_the_bytes_before_them() {
    let ring: RxRing<E> = RxRing::new();
    let mut buf = [0u8; 16];
    for b in 1..=5 {
        ring.push(b, E::Overrun);
    }
    ring.push_error(E::Line);
    for b in 6..=8 {
        ring.push(b, E::Overrun);
    }
    ring.push_error(E::Overrun);
    // A read asks for more than the bytes before the error: it stops there.
    defmt::assert!(ring.read(&mut buf[..3]) == Ok(3) && buf[..3] == [1, 2, 3]);
    defmt::assert!(ring.read(&mut buf) == Ok(2) && buf[..2] == [4, 5]);
    defmt::assert!(ring.read(&mut buf) == Err(E::Line));
    defmt::assert!(ring.read(&mut buf) == Ok(3) && buf[..3] == [6, 7, 8]);
    defmt::assert!(ring.is_ready());
    defmt::assert!(ring.read(&mut buf) == Err(E::Overrun));
    defmt::assert!(ring.read(&mut buf) == Ok(0) && !ring.is_ready());
    // An error with no byte before it (twice in a row, too).
    ring.push_error(E::Line);
    ring.push_error(E::Overrun);
    ring.push(9, E::Overrun);
    defmt::assert!(ring.read(&mut buf) == Err(E::Line));
    defmt::assert!(ring.read(&mut buf) == Err(E::Overrun));
    defmt::assert!(ring.read(&mut buf) == Ok(1) && buf[0] == 9);
    // Full, then one more byte: lost, and reported after the RX_RING_LEN bytes held, which
    // straddle the end of the array (the reads above moved its start).
    for i in 0..RX_RING_LEN {
        ring.push(i as u8, E::Overrun);
    }
    defmt::assert!(ring.is_full());
    ring.push(0xEE, E::Overrun);
    let mut got = 0;
    loop {
        match ring.read(&mut buf) {
            Ok(0) => defmt::panic!("the overrun was not reported"),
            Ok(n) => {
                for &b in &buf[..n] {
                    defmt::assert!(b == got as u8);
                    got += 1;
                }
            }
            Err(e) => {
                defmt::assert!(e == E::Overrun && got == RX_RING_LEN);
                break;
            }
        }
    }
    defmt::assert!(ring.read(&mut buf) == Ok(0) && !ring.is_ready());
}
