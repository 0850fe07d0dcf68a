//! Whole frames: message bytes + CRC-32C (little-endian) → COBS → 0x00.

use crate::{
    cobs, crc::crc32c, decode_message, encode_message, DecodeError, EncodeError, Message, CRC_LEN,
    MAX_MESSAGE_LEN, MIN_PAYLOAD_LEN,
};

/// Encodes `msg` as one complete frame into `out` and returns it, trailing 0x00 included.
///
/// An `out` of [`MAX_FRAME_LEN`](crate::MAX_FRAME_LEN) bytes always suffices.
pub fn encode_frame<'a>(msg: &Message, out: &'a mut [u8]) -> Result<&'a [u8], EncodeError> {
    let mut payload = [0u8; MAX_MESSAGE_LEN];
    let len = encode_message(msg, &mut payload)?.len();
    encode_raw_frame(payload.get(..len).unwrap_or(&[]), out)
}

/// Frames arbitrary `payload` bytes: appends their CRC-32C, COBS-encodes, appends 0x00.
///
/// This is the framing of [`encode_frame`] without the message encoding: for tools and tests
/// that need frames with contents a [`Message`] cannot express (e.g. an unknown joint byte).
pub fn encode_raw_frame<'a>(payload: &[u8], out: &'a mut [u8]) -> Result<&'a [u8], EncodeError> {
    let needed = cobs::max_encoded_len(payload.len() + CRC_LEN) + 1;
    let crc = crc32c(payload).to_le_bytes();
    let bytes = payload.iter().copied().chain(crc);
    let len = cobs::encode(bytes, out).ok_or(EncodeError::BufferTooSmall { needed })?;
    *out.get_mut(len)
        .ok_or(EncodeError::BufferTooSmall { needed })? = 0;
    Ok(out.get(..=len).unwrap_or(&[]))
}

/// Decodes the COBS bytes of one frame, delimiter excluded, in place (`frame` is overwritten).
///
/// Checks, in order: COBS ([`DecodeError::Cobs`]), length ([`DecodeError::TooShort`]),
/// CRC ([`DecodeError::Crc`]), then the message ([`decode_message`]).
pub fn decode_frame(frame: &mut [u8]) -> Result<Message, DecodeError> {
    let len = cobs::decode_in_place(frame).map_err(|_| DecodeError::Cobs)?;
    let payload = frame.get(..len).ok_or(DecodeError::Cobs)?;
    if len < MIN_PAYLOAD_LEN {
        return Err(DecodeError::TooShort);
    }
    let (body, crc_bytes) = payload.split_at(len - CRC_LEN);
    let mut sent = [0u8; CRC_LEN];
    sent.copy_from_slice(crc_bytes);
    if crc32c(body) != u32::from_le_bytes(sent) {
        return Err(DecodeError::Crc);
    }
    decode_message(body)
}
