//! First smoke test: every message survives encode_frame -> FrameDecoder.
mod common;

use qgait_proto::FrameDecoder;

#[test]
fn every_message_round_trips_through_the_stream_decoder() {
    let mut decoder = FrameDecoder::new();
    for msg in common::every_message() {
        let bytes = common::frame(&msg);
        assert_eq!(bytes.last(), Some(&0));
        assert_eq!(bytes.iter().filter(|&&b| b == 0).count(), 1);
        let got = common::decode_all(&mut decoder, &bytes);
        assert_eq!(got, vec![Ok(msg)]);
    }
}
