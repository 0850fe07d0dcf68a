//! The frame checksum: CRC-32C (Castagnoli), as catalogued by the `crc` crate (`CRC_32_ISCSI`).
//!
//! [`FRAME_CRC`] is the catalogue definition; the frames themselves are checked with
//! [`crc32c`], a table-driven implementation (one 1 KiB table, four bytes per step) that the
//! tests hold equal to [`FRAME_CRC`] on every length and alignment.
//!
//! Hand-written because it costs half the `crc` crate's instructions on the hub's Cortex-M4F
//! (605 against 1,168 for a PHAK pose frame's 146 bytes, 77 against 112 for a packet's 11;
//! `cargo xtask bench`, figures `device.crc.*`): a word a step against the crate's byte a step,
//! with the same 1 KiB table.
//!
//! With the `small-crc` feature the table is 16 entries (64 bytes) and the register takes four
//! bits a step, a byte at a time, in one out-of-line copy: the same CRC in about two and a half
//! times the instructions (1,465 against 605 for the pose frame above), for a hub whose flash
//! counts more than those (the firmware's `chain` build, BENCHMARKS.md).

/// The CRC algorithm of every frame: CRC-32C (Castagnoli), also known as CRC-32/ISCSI.
///
/// Polynomial 0x1EDC6F41 (reflected 0x82F63B78), init 0xFFFFFFFF, input and output reflected,
/// xorout 0xFFFFFFFF, check value (CRC of the ASCII bytes `123456789`) 0xE3069283.
pub const FRAME_CRC: crc::Crc<u32> = crc::Crc::<u32>::new(&crc::CRC_32_ISCSI);

/// The check value of [`FRAME_CRC`]: its CRC of the ASCII bytes `123456789`.
pub const FRAME_CRC_CHECK: u32 = 0xE306_9283;

/// The reflected polynomial.
const POLY: u32 = 0x82F6_3B78;

/// Bits the register takes a step: 8 (a 256-entry table) or, with `small-crc`, 4 (16
/// entries).
const STEP_BITS: u32 = if cfg!(feature = "small-crc") { 4 } else { 8 };

/// Entries of [`TABLE`].
const ENTRIES: usize = 1 << STEP_BITS;

/// `TABLE[i]`: the register after shifting the `STEP_BITS` bits `i` through it.
static TABLE: [u32; ENTRIES] = table();

const fn table() -> [u32; ENTRIES] {
    let mut table = [0u32; ENTRIES];
    let mut i = 0;
    while i < ENTRIES {
        let mut r = i as u32;
        let mut bit = 0;
        while bit < STEP_BITS {
            r = if r & 1 != 0 { (r >> 1) ^ POLY } else { r >> 1 };
            bit += 1;
        }
        table[i] = r;
        i += 1;
    }
    table
}

/// One byte through the register (the low byte of `register` must already hold the input).
#[cfg(not(feature = "small-crc"))]
#[inline(always)]
fn step(register: u32) -> u32 {
    TABLE[(register & 0xFF) as usize] ^ (register >> 8)
}

/// Four bits through the register (its low four bits must already hold the input).
#[cfg(feature = "small-crc")]
#[inline(always)]
fn nibble(register: u32) -> u32 {
    TABLE[(register & 0xF) as usize] ^ (register >> 4)
}

/// Runs `bytes` through the (not inverted) CRC-32C register `register`.
#[cfg(not(feature = "small-crc"))]
#[inline]
pub(crate) fn update(mut register: u32, bytes: &[u8]) -> u32 {
    let words = bytes.chunks_exact(4);
    let rest = words.remainder();
    for word in words {
        register ^= u32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        register = step(register);
        register = step(register);
        register = step(register);
        register = step(register);
    }
    for &byte in rest {
        register = step(register ^ u32::from(byte));
    }
    register
}

/// Runs `bytes` through the (not inverted) CRC-32C register `register`: a byte a step, one
/// copy (flash first).
#[cfg(feature = "small-crc")]
#[inline(never)]
pub(crate) fn update(mut register: u32, bytes: &[u8]) -> u32 {
    for &byte in bytes {
        register = nibble(nibble(register ^ u32::from(byte)));
    }
    register
}

/// The register before any byte.
pub(crate) const INIT: u32 = 0xFFFF_FFFF;

/// The register after a message followed by its own CRC-32C (little-endian), whatever the
/// message: a frame's payload is intact iff running all of it through the register ends here.
pub(crate) const RESIDUE: u32 = residue();

const fn residue() -> u32 {
    // Any message gives the same residue: take the empty one, whose CRC is 0 (init ^ xorout),
    // and shift its four zero CRC bytes through the initial register.
    let mut r = INIT;
    let mut i = 0;
    while i < 4 * 8 / STEP_BITS {
        r = table()[(r as usize) & (ENTRIES - 1)] ^ (r >> STEP_BITS);
        i += 1;
    }
    r
}

/// CRC-32C of `bytes`.
pub fn crc32c(bytes: &[u8]) -> u32 {
    !update(INIT, bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic bytes.
    fn bytes(len: usize, seed: u32) -> [u8; 300] {
        let mut out = [0u8; 300];
        let mut x = seed.wrapping_mul(2_654_435_761) | 1;
        for b in out.iter_mut().take(len) {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            *b = (x >> 11) as u8;
        }
        out
    }

    #[test]
    fn table_driven_crc_equals_the_catalogue_crc_at_every_length_and_offset() {
        assert_eq!(crc32c(b"123456789"), FRAME_CRC_CHECK);
        assert_eq!(crc32c(&[]), FRAME_CRC.checksum(&[]));
        for len in 0..260 {
            for seed in 0..4 {
                let data = bytes(len + 3, seed + 7 * len as u32);
                // Every offset modulo 4, so unaligned words are covered.
                for offset in 0..4 {
                    let slice = &data[offset..offset + len];
                    assert_eq!(
                        crc32c(slice),
                        FRAME_CRC.checksum(slice),
                        "len {len} offset {offset}"
                    );
                }
            }
        }
    }

    #[test]
    fn message_and_its_crc_end_at_the_residue_and_nothing_else_does() {
        for len in 0..100 {
            let mut data = bytes(len + 4, len as u32);
            let crc = crc32c(&data[..len]).to_le_bytes();
            data[len..len + 4].copy_from_slice(&crc);
            assert_eq!(update(INIT, &data[..len + 4]), RESIDUE, "len {len}");
            // Any single wrong CRC bit moves the register off the residue.
            for bit in 0..32 {
                let mut bad = data;
                bad[len + bit / 8] ^= 1 << (bit % 8);
                assert_ne!(
                    update(INIT, &bad[..len + 4]),
                    RESIDUE,
                    "len {len} bit {bit}"
                );
            }
        }
    }
}
