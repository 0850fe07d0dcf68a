//! Consistent Overhead Byte Stuffing (COBS), strict, in place, allocation-free.
//!
//! Standard COBS (Cheshire & Baker 1999) with 0x00 as the delimiter: the data is cut at every
//! zero byte into blocks; each block is sent as a code byte `n` (1..=255) followed by its `n - 1`
//! non-zero bytes, and a code below 0xFF means "a zero follows" (except at the very end). A
//! block of 254 non-zero bytes has code 0xFF and no implied zero.

/// The largest COBS encoding of `len` bytes (without the delimiter).
pub const fn max_encoded_len(len: usize) -> usize {
    len + len / 254 + 1
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
        // dst <= src always holds, so the copy stays inside `buf`.
        buf.copy_within(src + 1..end, dst);
        dst += code - 1;
        src = end;
        if code != 0xFF && src < len {
            *buf.get_mut(dst).ok_or(InvalidCobs)? = 0;
            dst += 1;
        }
    }
    Ok(dst)
}
