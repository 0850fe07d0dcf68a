//! Consistent Overhead Byte Stuffing (COBS), strict, in place, allocation-free.
//!
//! Standard COBS (Cheshire & Baker 1999) with 0x00 as the delimiter: the data is cut at every
//! zero byte into blocks; each block is sent as a code byte `n` (1..=255) followed by its `n - 1`
//! non-zero bytes, and a code below 0xFF means "a zero follows" (except at the very end). A
//! block of 254 non-zero bytes has code 0xFF and no implied zero.
//!
//! Hand-written rather than the `cobs` crate's (on which postcard's COBS flavour is built)
//! because the frames are encoded and decoded in place, which on the hub's Cortex-M4F costs a
//! fraction of the crate's instructions: for a PHAK pose frame's 150 bytes 472 against 3,294 to
//! encode, 31 against 2,783 to decode (`cargo xtask bench`, figures `device.cobs.*`).

/// The largest COBS encoding of `len` bytes (without the delimiter): one code byte per started
/// block of 254 bytes, i.e. `len + ceil(len / 254)`, and 1 for empty input. Reached exactly by
/// data without zero bytes.
pub const fn max_encoded_len(len: usize) -> usize {
    if len == 0 {
        1
    } else {
        len + len.div_ceil(254)
    }
}

/// COBS-encodes `src` into `dst` (no delimiter). Returns the encoded length, or `None` if `dst`
/// is too small.
pub fn encode(src: impl IntoIterator<Item = u8>, dst: &mut [u8]) -> Option<usize> {
    let mut src = src.into_iter().peekable();
    let mut code_at = 0;
    let mut out = 1;
    let mut code: u8 = 1;
    dst.get(code_at)?;
    while let Some(byte) = src.next() {
        if byte == 0 {
            *dst.get_mut(code_at)? = code;
            code_at = out;
            *dst.get_mut(code_at)? = 0;
            out += 1;
            code = 1;
        } else {
            *dst.get_mut(out)? = byte;
            out += 1;
            code += 1;
            if code == 0xFF && src.peek().is_some() {
                *dst.get_mut(code_at)? = code;
                code_at = out;
                *dst.get_mut(code_at)? = 0;
                out += 1;
                code = 1;
            }
        }
    }
    *dst.get_mut(code_at)? = code;
    Some(out)
}

/// The longest data [`encode_in_place`] takes: every block then has fewer than 254 non-zero
/// bytes, so no 0xFF code (and no extra code byte) is ever needed.
pub const IN_PLACE_MAX_LEN: usize = 253;

/// COBS-encodes, in place, the `len` data bytes at `buf[1..=len]`, and writes the 0x00
/// delimiter at `buf[len + 1]`: `buf[..len + 2]` is then the whole frame. Returns `len + 2`, or
/// `None` (and `buf` unspecified) if `len > IN_PLACE_MAX_LEN` or `buf` is shorter than `len + 2`.
///
/// With fewer than 254 data bytes COBS replaces each zero byte (and a virtual zero after the
/// data, which becomes the delimiter) by the distance to the next one, the first code byte
/// going in front: one pass, no byte moves.
pub fn encode_in_place(buf: &mut [u8], len: usize) -> Option<usize> {
    if len > IN_PLACE_MAX_LEN {
        return None;
    }
    let frame = buf.get_mut(..len + 2)?;
    let (data, delimiter) = frame.split_at_mut(len + 1);
    *delimiter.first_mut()? = 0;
    let mut code_at = 0;
    let mut i = 1;
    // Eight, then four bytes at a time while none is zero (most bytes of a pose frame's floats).
    while let Some(&[b0, b1, b2, b3, b4, b5, b6, b7]) = data.get(i..i + 8) {
        let w0 = u32::from_le_bytes([b0, b1, b2, b3]);
        let w1 = u32::from_le_bytes([b4, b5, b6, b7]);
        // Both words' zero tests in one: a branch per eight bytes.
        if zero_byte_bits(w0) | zero_byte_bits(w1) != 0 {
            for k in i..i + 8 {
                if data[k] == 0 {
                    // k - code_at <= len <= 253: fits a code byte.
                    data[code_at] = (k - code_at) as u8;
                    code_at = k;
                }
            }
        }
        i += 8;
    }
    while let Some(word) = data.get(i..i + 4) {
        let w = u32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        if has_zero_byte(w) {
            for k in i..i + 4 {
                if data[k] == 0 {
                    // k - code_at <= len <= 253: fits a code byte.
                    data[code_at] = (k - code_at) as u8;
                    code_at = k;
                }
            }
        }
        i += 4;
    }
    while i < data.len() {
        if data[i] == 0 {
            data[code_at] = (i - code_at) as u8;
            code_at = i;
        }
        i += 1;
    }
    data[code_at] = (data.len() - code_at) as u8;
    Some(len + 2)
}

/// Whether any byte of `w` is zero (exact: a borrow into a byte's top bit happens only below
/// a zero byte, and the lowest zero byte always sets its own).
#[inline(always)]
fn has_zero_byte(w: u32) -> bool {
    zero_byte_bits(w) != 0
}

/// Not zero iff a byte of `w` is zero (see [`has_zero_byte`]).
#[inline(always)]
fn zero_byte_bits(w: u32) -> u32 {
    w.wrapping_sub(0x0101_0101) & !w & 0x8080_8080
}

/// The frame's COBS structure is invalid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InvalidCobs;

/// Decodes the COBS bytes of one frame (delimiter excluded) in place; returns the decoded
/// length. Fails on a 0x00 inside the frame or a code byte pointing past its end.
pub fn decode_in_place(buf: &mut [u8]) -> Result<usize, InvalidCobs> {
    let len = buf.len();
    let mut src = 0;
    let mut dst = 0;
    while let Some(&code) = buf.get(src) {
        let code = usize::from(code);
        let end = src + code;
        if code == 0 || end > len {
            return Err(InvalidCobs);
        }
        // dst <= src always holds, so the moves stay inside `buf`. A byte loop: blocks are
        // short (a few bytes between zeros), where a memmove call costs more than the bytes.
        for i in src + 1..end {
            let byte = buf[i];
            buf[dst] = byte;
            dst += 1;
        }
        src = end;
        if code != 0xFF && src < len {
            *buf.get_mut(dst).ok_or(InvalidCobs)? = 0;
            dst += 1;
        }
    }
    Ok(dst)
}

/// [`decode_in_place`] without moving the data when it can: returns where in `buf` the decoded
/// bytes are, with the same errors.
///
/// While the code bytes are below 0xFF (all of them in every frame of up to 254 data bytes:
/// all of this protocol's) the decoded data is `buf[1..]` with each code byte after the first
/// replaced by the zero it stands for: one walk along the code chain, replacing each code as it
/// goes, no byte moved. From a 0xFF code on (no zero stands for it) the rest is decoded as
/// [`decode_in_place`] does, moving bytes.
pub fn decode_in_place_unshifted(buf: &mut [u8]) -> Result<core::ops::Range<usize>, InvalidCobs> {
    let len = buf.len();
    let Some(&first) = buf.first() else {
        return Ok(0..0);
    };
    if first == 0xFF || first == 0 {
        return decode_in_place(buf).map(|n| 0..n);
    }
    // buf[1..at] is the data decoded so far, `at` the position of the next code byte.
    let mut at = usize::from(first);
    while let Some(code) = buf.get_mut(at) {
        let c = *code;
        if c == 0xFF || c == 0 {
            return decode_rest(buf, at).map(|end| 1..end);
        }
        *code = 0;
        at += usize::from(c);
    }
    if at > len {
        return Err(InvalidCobs);
    }
    Ok(1..len)
}

/// [`decode_in_place`] from the code byte at `src`, the data before it decoded unshifted
/// (`buf[1..src]`) and the zero of the previous block (whose code was below 0xFF) still to be
/// written, at `src`; returns the end of the decoded data, which starts at `buf[1]`.
fn decode_rest(buf: &mut [u8], mut src: usize) -> Result<usize, InvalidCobs> {
    let len = buf.len();
    let mut dst = src;
    let mut zero_due = true;
    while let Some(&code) = buf.get(src) {
        let code = usize::from(code);
        let end = src + code;
        if code == 0 || end > len {
            return Err(InvalidCobs);
        }
        // dst <= src always holds (the code byte is read before the zero may take its place).
        if zero_due {
            *buf.get_mut(dst).ok_or(InvalidCobs)? = 0;
            dst += 1;
        }
        for i in src + 1..end {
            let byte = buf[i];
            buf[dst] = byte;
            dst += 1;
        }
        src = end;
        zero_due = code != 0xFF && src < len;
    }
    Ok(dst)
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;

    /// Deterministic pseudo-random bytes with many zeros and long non-zero runs.
    fn sample(seed: u64, len: usize) -> [u8; 700] {
        let mut out = [0u8; 700];
        let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        let zero_rate = (seed % 5) as u32; // zeros in 8 * zero_rate / 256 of the bytes; 0: none
        for b in out.iter_mut().take(len) {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = (x >> 24) as u8;
            *b = if ((x >> 40) & 0xFF) < u64::from(8 * zero_rate) {
                0
            } else {
                v | 1
            };
        }
        out
    }

    #[test]
    fn encode_matches_the_cobs_crate_and_decodes_back() {
        // From 1: the cobs crate encodes empty input as nothing, standard COBS (and we) as 0x01;
        // frames are never empty.
        for len in 1..600usize {
            for seed in 0..5u64 {
                let data = sample(seed + 5 * len as u64, len);
                let data = &data[..len];
                let mut ours = [0u8; 700];
                let mut theirs = [0u8; 700];
                let n = encode(data.iter().copied(), &mut ours).expect("buffer is large enough");
                let m = ::cobs::encode(data, &mut theirs);
                assert_eq!(&ours[..n], &theirs[..m], "len {len} seed {seed}");
                assert!(n <= max_encoded_len(len), "len {len}: {n} > bound");
                assert!(!ours[..n].contains(&0), "encoding contains a zero");
                let decoded = decode_in_place(&mut ours[..n]).expect("valid COBS");
                assert_eq!(&ours[..decoded], data, "len {len} seed {seed}");
            }
        }
    }

    #[test]
    fn in_place_encoding_equals_the_general_encoder() {
        for len in 0..=IN_PLACE_MAX_LEN {
            for seed in 0..8u64 {
                let data = sample(seed + 8 * len as u64, len);
                let data = &data[..len];
                let mut general = [0u8; 700];
                let n = encode(data.iter().copied(), &mut general).expect("fits");
                // Garbage around the data: the encoder must not depend on it.
                let mut buf = [0xA5u8; 300];
                buf[1..=len].copy_from_slice(data);
                assert_eq!(
                    encode_in_place(&mut buf, len),
                    Some(n + 1),
                    "len {len} seed {seed}"
                );
                assert_eq!(&buf[..n], &general[..n], "len {len} seed {seed}");
                assert_eq!(buf[n], 0, "delimiter");
                assert_eq!(buf[n + 1..], [0xA5u8; 300][n + 1..], "wrote past the frame");
            }
        }
    }

    #[test]
    fn in_place_encoding_refuses_long_data_and_short_buffers() {
        let mut buf = [1u8; 300];
        assert_eq!(encode_in_place(&mut buf, IN_PLACE_MAX_LEN + 1), None);
        for size in 0..7 {
            let mut small = [1u8; 7];
            assert_eq!(encode_in_place(&mut small[..size], 5), None, "size {size}");
        }
        assert_eq!(encode_in_place(&mut [1u8; 7], 5), Some(7));
    }

    #[test]
    fn max_encoded_len_is_reached_by_zero_free_data() {
        for len in [0usize, 1, 100, 253, 254, 255, 508, 509, 600] {
            let data = [0x55u8; 600];
            let mut out = [0u8; 700];
            let n = encode(data[..len].iter().copied(), &mut out).expect("fits");
            assert_eq!(n, max_encoded_len(len), "len {len}");
        }
    }

    #[test]
    fn encode_reports_a_short_buffer_instead_of_panicking() {
        let data = [1u8, 0, 2, 3, 0, 0, 4];
        let mut full = [0u8; 16];
        let n = encode(data.iter().copied(), &mut full).expect("fits");
        for size in 0..n {
            let mut out = [0u8; 16];
            assert_eq!(
                encode(data.iter().copied(), &mut out[..size]),
                None,
                "size {size}"
            );
        }
    }

    #[test]
    fn unshifted_decoding_equals_decode_in_place_on_every_frame() {
        // Valid frames of every length (with and without 0xFF codes), then every one-byte
        // corruption of a few: same result, same bytes.
        let mut checked = 0;
        for len in 0..600usize {
            for seed in 0..3u64 {
                let data = sample(seed + 3 * len as u64, len);
                let mut enc = [0u8; 700];
                let n = encode(data[..len].iter().copied(), &mut enc).expect("fits");
                let mut variants = std::vec![enc[..n].to_vec()];
                if len < 40 && seed == 0 {
                    for at in 0..n {
                        for v in [0u8, 1, 2, 3, 0x7F, 0xFE, 0xFF, enc[at] ^ 0x01] {
                            let mut bad = enc[..n].to_vec();
                            bad[at] = v;
                            variants.push(bad);
                        }
                    }
                }
                for frame in variants {
                    let mut a = frame.clone();
                    let mut b = frame.clone();
                    let general = decode_in_place(&mut a).map(|n| a[..n].to_vec());
                    let fast = decode_in_place_unshifted(&mut b).map(|r| b[r].to_vec());
                    assert_eq!(fast, general, "{frame:02x?}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 5_000, "{checked}");
        // Long runs after short blocks: 0xFF codes in the middle of the chain.
        for k in [1usize, 250, 252, 253, 254, 255, 256, 300, 508, 509] {
            for m in [0usize, 1, 37, 253, 254, 255] {
                let mut data = std::vec![1u8, 0, 2, 0, 0];
                data.extend(core::iter::repeat_n(7u8, k));
                data.extend([0, 3]);
                data.extend(core::iter::repeat_n(9u8, m));
                let mut enc = [0u8; 1100];
                let n = encode(data.iter().copied(), &mut enc).expect("fits");
                let mut a = enc[..n].to_vec();
                let mut b = enc[..n].to_vec();
                let n = decode_in_place(&mut a).expect("valid");
                assert_eq!(&a[..n], &data[..]);
                let range = decode_in_place_unshifted(&mut b).expect("valid");
                assert_eq!(&b[range], &data[..], "k {k} m {m}");
            }
        }
    }

    #[test]
    fn decode_rejects_overrunning_code_and_embedded_zero() {
        // 0x05 promises 4 data bytes, only 2 follow: a truncated frame.
        assert_eq!(decode_in_place(&mut [0x05, 1, 2]), Err(InvalidCobs));
        // A zero can never be inside a COBS frame.
        assert_eq!(decode_in_place(&mut [0x02, 1, 0, 1]), Err(InvalidCobs));
        // Empty input decodes to nothing.
        assert_eq!(decode_in_place(&mut []), Ok(0));
        // 03 11 22 02 33 -> 11 22 00 33
        let mut buf = [0x03, 0x11, 0x22, 0x02, 0x33];
        let n = decode_in_place(&mut buf).expect("valid");
        assert_eq!(&buf[..n], &[0x11, 0x22, 0x00, 0x33]);
    }
}
