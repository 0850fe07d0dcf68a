//! [`FrameDecoder`]: the streaming, resynchronising frame decoder.

use crate::{decode_frame, DecodeError, Message, MAX_FRAME_LEN};

/// Bytes a frame may have before its delimiter.
const BUFFER_LEN: usize = MAX_FRAME_LEN - 1;

/// Streaming decoder: takes bytes as they arrive (one at a time or in chunks of any size) and
/// yields one result per frame.
///
/// - A 0x00 ends a frame; empty frames (several 0x00 in a row) are skipped silently, so a
///   sender may put an extra 0x00 before a frame to force resynchronisation.
/// - A frame longer than [`MAX_FRAME_LEN`]` - 1` bytes is reported once as
///   [`DecodeError::Oversize`], then bytes are discarded up to the next 0x00.
/// - Any other bad frame is reported with its [`DecodeError`] and decoding goes on with the
///   next byte: garbage costs at most the frame it touches and the one it runs into.
///
/// It holds one fixed buffer of `MAX_FRAME_LEN - 1` bytes, never allocates and never panics.
#[derive(Debug, Clone)]
pub struct FrameDecoder {
    buf: [u8; BUFFER_LEN],
    len: usize,
    discarding: bool,
}

impl Default for FrameDecoder {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameDecoder {
    /// A decoder waiting for the start of a frame.
    pub const fn new() -> Self {
        FrameDecoder {
            buf: [0; BUFFER_LEN],
            len: 0,
            discarding: false,
        }
    }

    /// Takes one byte; returns `Some` when it completes a frame (or overflows one).
    pub fn push(&mut self, byte: u8) -> Option<Result<Message, DecodeError>> {
        if byte == 0 {
            let len = core::mem::take(&mut self.len);
            if core::mem::take(&mut self.discarding) || len == 0 {
                return None;
            }
            return Some(decode_frame(self.buf.get_mut(..len)?));
        }
        if self.discarding {
            return None;
        }
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                *slot = byte;
                self.len += 1;
                None
            }
            None => {
                self.len = 0;
                self.discarding = true;
                Some(Err(DecodeError::Oversize))
            }
        }
    }

    /// Takes a chunk of bytes; the returned iterator yields one result per completed frame.
    ///
    /// The bytes are consumed as the iterator advances: drive it to the end (e.g. `for` over
    /// it) or the rest of the chunk is not consumed.
    pub fn feed<'a>(&'a mut self, chunk: &'a [u8]) -> Feed<'a> {
        Feed {
            decoder: self,
            rest: chunk,
        }
    }

    /// Forgets any partial frame (e.g. after a UART overrun): the next byte starts a new frame.
    pub fn reset(&mut self) {
        self.len = 0;
        self.discarding = false;
    }

    /// Bytes of the current partial frame held in the buffer (0 while discarding).
    pub fn pending_len(&self) -> usize {
        self.len
    }

    /// `true` while an oversize frame is being discarded up to the next 0x00.
    pub fn is_discarding(&self) -> bool {
        self.discarding
    }
}

/// Iterator returned by [`FrameDecoder::feed`].
#[derive(Debug)]
pub struct Feed<'a> {
    decoder: &'a mut FrameDecoder,
    rest: &'a [u8],
}

impl Feed<'_> {
    /// The bytes of the chunk not consumed yet.
    pub fn remaining(&self) -> &[u8] {
        self.rest
    }
}

impl Iterator for Feed<'_> {
    type Item = Result<Message, DecodeError>;

    fn next(&mut self) -> Option<Self::Item> {
        while let Some((&byte, rest)) = self.rest.split_first() {
            self.rest = rest;
            if let Some(result) = self.decoder.push(byte) {
                return Some(result);
            }
        }
        None
    }
}
