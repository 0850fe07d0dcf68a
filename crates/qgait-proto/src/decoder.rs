//! [`FrameDecoder`]: the streaming, resynchronising frame decoder.

use crate::frame::check_frame;
use crate::{decode_message, DecodeError, Message, MAX_FRAME_LEN};

/// Bytes a frame may have before its delimiter.
const BUFFER_LEN: usize = MAX_FRAME_LEN - 1;

/// `len` while an oversize frame is discarded: past the buffer, so the per-byte path's one
/// bounds check sends every byte to [`FrameDecoder::overflow`].
const DISCARDING: usize = BUFFER_LEN + 1;

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
    /// Bytes of the partial frame in `buf`, or [`DISCARDING`].
    len: usize,
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
        }
    }

    /// Takes one byte; returns `Some` when it completes a frame (or overflows one).
    #[inline]
    pub fn push(&mut self, byte: u8) -> Option<Result<Message, DecodeError>> {
        self.push_frame(byte)
            .map(|frame| frame.and_then(decode_message))
    }

    /// Takes one byte, like [`push`](Self::push), but stops short of decoding the message:
    /// when the byte completes a frame that passes the frame checks (COBS, length, CRC) it
    /// returns the message bytes, borrowed from the decoder, to be given to
    /// [`decode_message`] (or [`decode_packet`](crate::decode_packet) first). The results and
    /// errors are otherwise those of [`push`](Self::push).
    ///
    /// The per-byte path is one comparison with 0x00 and one bounds check.
    #[inline(always)]
    pub fn push_frame(&mut self, byte: u8) -> Option<Result<&[u8], DecodeError>> {
        if byte == 0 {
            return self.end_frame();
        }
        self.push_data(byte).map(Err)
    }

    /// A byte that is not the 0x00 delimiter: `Some(`[`DecodeError::Oversize`]`)` once when
    /// the frame outgrows the buffer, otherwise `None`.
    #[inline(always)]
    fn push_data(&mut self, byte: u8) -> Option<DecodeError> {
        match self.buf.get_mut(self.len) {
            Some(slot) => {
                *slot = byte;
                self.len += 1;
                None
            }
            None => self.overflow(),
        }
    }

    /// Takes the run of data bytes at the start of `chunk`, up to its first 0x00 (not taken):
    /// what [`push_frame`](Self::push_frame) does with data bytes, for a slice (the hub reads
    /// its serial port in blocks). The caller gives the 0x00, if the run stopped at one, to
    /// [`end_frame`](Self::end_frame) and goes on after it.
    ///
    /// Returns how many bytes of `chunk` the run has (all of them if it holds no 0x00), and
    /// `Some(`[`DecodeError::Oversize`]`)` once when the frame outgrows the buffer; the rest of
    /// an oversize frame's bytes are discarded, here and in later runs, up to the next 0x00.
    ///
    /// The data bytes go four at a time (a word loaded, tested for a 0x00 byte and stored);
    /// the word holding the 0x00 is stored whole and the run ends at its first 0x00 byte
    /// (the bytes stored past the frame's length are scratch, overwritten by the next data
    /// bytes); the last few bytes of a chunk or of the buffer's room one at a time.
    #[inline(always)]
    pub fn push_run(&mut self, chunk: &[u8]) -> (usize, Option<DecodeError>) {
        let start = self.len;
        // Empty while discarding (`start` past the buffer).
        let room = self.buf.get_mut(start..).unwrap_or_default();
        // Four bytes at a time while none of them is 0x00 (one word load, test and store on
        // a 32-bit MCU), then byte by byte up to the 0x00 or the end of the room or chunk.
        let mut taken = 0;
        for (slots, bytes) in room.chunks_exact_mut(4).zip(chunk.chunks_exact(4)) {
            let Ok(word) = <[u8; 4]>::try_from(bytes) else {
                break;
            };
            slots.copy_from_slice(bytes);
            let word = u32::from_le_bytes(word);
            // The top bit of each 0x00 byte, and perhaps of bytes above one; the lowest set
            // bit is exactly the first 0x00's (a borrow only runs upwards from a 0x00).
            let zeros = word.wrapping_sub(0x0101_0101) & !word & 0x8080_8080;
            if zeros != 0 {
                // The run ends before that 0x00: the bytes after it in the word, stored
                // past the frame's length, are not taken.
                taken += (zeros.trailing_zeros() / 8) as usize;
                self.len = start + taken;
                return (taken, None);
            }
            taken += 4;
        }
        let rest = room.get_mut(taken..).unwrap_or_default();
        for (slot, &byte) in rest.iter_mut().zip(chunk.get(taken..).unwrap_or_default()) {
            if byte == 0 {
                break;
            }
            *slot = byte;
            taken += 1;
        }
        self.len = start + taken;
        let rest = chunk.get(taken..).unwrap_or_default();
        match rest.first() {
            None | Some(0) => (taken, None),
            // No room for the next data byte: the frame is oversize (reported once), and the
            // rest of the run is discarded.
            Some(_) => {
                let run = rest.iter().position(|&b| b == 0).unwrap_or(rest.len());
                (taken + run, self.overflow())
            }
        }
    }

    /// The 0x00 delimiter arrived: checks the frame in the buffer, if any, as
    /// [`push_frame`](Self::push_frame) does for a 0x00.
    #[inline(never)]
    pub fn end_frame(&mut self) -> Option<Result<&[u8], DecodeError>> {
        let len = core::mem::take(&mut self.len);
        if len == 0 || len == DISCARDING {
            return None;
        }
        Some(check_frame(self.buf.get_mut(..len)?))
    }

    /// A non-zero byte found the buffer full: the frame is oversize (reported once), or is
    /// being discarded already.
    #[cold]
    #[inline(never)]
    fn overflow(&mut self) -> Option<DecodeError> {
        if self.len == DISCARDING {
            return None;
        }
        self.len = DISCARDING;
        Some(DecodeError::Oversize)
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
    }

    /// Bytes of the current partial frame held in the buffer (0 while discarding).
    pub fn pending_len(&self) -> usize {
        if self.is_discarding() {
            0
        } else {
            self.len
        }
    }

    /// `true` while an oversize frame is being discarded up to the next 0x00.
    pub fn is_discarding(&self) -> bool {
        self.len == DISCARDING
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
