//! postcard's primitives as the hand-written encoders and decoders use them: `u32` varints,
//! and postcard's own deserialiser one field at a time.

use serde::de::DeserializeOwned;

use crate::DecodeError;

/// Most bytes of a `u32` varint.
#[cfg(test)]
pub(super) const VARINT_U32_MAX: usize = 5;

/// postcard's varint of `value` (LEB128, 7 bits per byte, least significant first), in `buf`
/// (the tests' reference; the encoders write theirs in place).
#[cfg(test)]
pub(super) fn varint_u32(mut value: u32, buf: &mut [u8; VARINT_U32_MAX]) -> &[u8] {
    let mut len = 0;
    for slot in buf.iter_mut() {
        len += 1;
        if value < 0x80 {
            *slot = value as u8;
            break;
        }
        *slot = (value as u8) | 0x80;
        value >>= 7;
    }
    &buf[..len]
}

/// Reads postcard's varint `u32` at the start of `bytes`; returns it and the bytes after it.
///
/// As postcard: at most 5 bytes, the fifth at most 0x0F (the 4 bits left of a `u32`);
/// over-long encodings of small values (e.g. `80 00` for 0) are accepted.
#[inline(always)]
pub(super) fn take_varint_u32(bytes: &[u8]) -> Result<(u32, &[u8]), DecodeError> {
    // Written out byte by byte (the compiler keeps a loop otherwise): most values end in the
    // first two or three bytes.
    let (&b0, rest) = bytes.split_first().ok_or(DecodeError::Malformed)?;
    let value = u32::from(b0 & 0x7F);
    if b0 < 0x80 {
        return Ok((value, rest));
    }
    let (&b1, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b1 & 0x7F) << 7;
    if b1 < 0x80 {
        return Ok((value, rest));
    }
    let (&b2, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b2 & 0x7F) << 14;
    if b2 < 0x80 {
        return Ok((value, rest));
    }
    let (&b3, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    let value = value | u32::from(b3 & 0x7F) << 21;
    if b3 < 0x80 {
        return Ok((value, rest));
    }
    // The fifth byte holds the last 4 bits and ends the varint.
    let (&b4, rest) = rest.split_first().ok_or(DecodeError::Malformed)?;
    if b4 > 0x0F {
        return Err(DecodeError::Malformed);
    }
    Ok((value | u32::from(b4) << 28, rest))
}

/// Deserialises a `T` at the start of `bytes`; returns it and the bytes after it.
///
/// The bodies are decoded field by field with this: a few small instances of postcard's
/// deserialiser instead of one per message (a kilobyte each on a Cortex-M), for the bytes
/// postcard accepts for the whole message and the same values (the tests hold the decoding to
/// postcard's of the public types).
pub(super) fn take<T: DeserializeOwned>(bytes: &[u8]) -> Result<(T, &[u8]), DecodeError> {
    postcard::take_from_bytes::<T>(bytes).map_err(|_| DecodeError::Malformed)
}

/// `Ok` if `rest` is empty: every byte of a body must be used.
pub(super) fn end(rest: &[u8]) -> Result<(), DecodeError> {
    if rest.is_empty() {
        Ok(())
    } else {
        Err(DecodeError::Malformed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn varints_are_postcards() {
        for v in [
            0,
            1,
            127,
            128,
            300,
            16_383,
            16_384,
            1 << 21,
            (1 << 28) - 1,
            1 << 28,
            u32::MAX,
        ] {
            let mut ours = [0u8; VARINT_U32_MAX];
            let mut theirs = [0u8; VARINT_U32_MAX];
            let theirs = postcard::to_slice(&v, &mut theirs).unwrap();
            assert_eq!(varint_u32(v, &mut ours), &theirs[..], "{v}");
            assert_eq!(take_varint_u32(theirs), Ok((v, &[][..])));
        }
    }
}
