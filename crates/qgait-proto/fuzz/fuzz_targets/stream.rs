//! Coverage-guided fuzz of the stream decoder. The first input byte picks the chunk size; the
//! rest is the stream. Checks: no panic; chunked `feed` and byte-wise `push` give the same
//! results; every decoded message re-encodes into a frame that decodes to the same bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;
use qgait_proto::{
    encode_frame, encode_message, DecodeError, FrameDecoder, Message, MAX_FRAME_LEN,
    MAX_MESSAGE_LEN,
};

fn bytes_of(result: &Result<Message, DecodeError>) -> Result<([u8; MAX_MESSAGE_LEN], usize), DecodeError> {
    let msg = result.as_ref().map_err(|e| *e)?;
    let mut buf = [0u8; MAX_MESSAGE_LEN];
    let len = encode_message(msg, &mut buf).expect("a decoded message re-encodes").len();
    Ok((buf, len))
}

fuzz_target!(|data: &[u8]| {
    let Some((&chunk, stream)) = data.split_first() else { return };
    let chunk = usize::from(chunk).max(1);

    let mut by_chunks = FrameDecoder::new();
    let mut chunked = Vec::new();
    for piece in stream.chunks(chunk) {
        chunked.extend(by_chunks.feed(piece).map(|r| bytes_of(&r)));
    }
    let mut by_bytes = FrameDecoder::new();
    let single: Vec<_> = stream.iter().filter_map(|&b| by_bytes.push(b)).map(|r| bytes_of(&r)).collect();
    assert_eq!(chunked, single);

    let mut decoder = FrameDecoder::new();
    for result in stream.iter().filter_map(|&b| decoder.push(b)) {
        if let Ok(msg) = result {
            let mut frame = [0u8; MAX_FRAME_LEN];
            let frame = encode_frame(&msg, &mut frame).expect("a decoded message re-frames");
            let mut again = FrameDecoder::new();
            let back: Vec<_> = frame.iter().filter_map(|&b| again.push(b)).collect();
            assert_eq!(back.len(), 1);
            assert_eq!(bytes_of(&back[0]), bytes_of(&Ok(msg)));
        }
    }
});
