//! Seeded stream fuzz of the decoder: random and mutated streams, fed in random chunks.
//!
//! For every stream it checks that the decoder
//! - does not panic,
//! - gives exactly the results of a plain reference model (split the stream at 0x00, skip empty
//!   frames, a frame over MAX_FRAME_LEN - 1 bytes is one Oversize, every other frame goes to
//!   `decode_frame`), whatever the chunking, fed as the hub feeds it (blocks of random
//!   lengths, as a serial read gives them, each through `push_run` and `end_frame`), and fed
//!   byte by byte through `push_frame` and `decode_message`,
//! - decodes every good frame sent after a resynchronising 0x00, in order.
//!
//! `cargo test` runs 20 000 streams. More: `QGAIT_FUZZ_STREAMS=1000000 cargo test --release
//! -p qgait-proto --test fuzz_stream -- --nocapture` (seed: `QGAIT_FUZZ_SEED`), or the ignored
//! test `stream_fuzz_one_million`.
mod common;

use std::collections::BTreeMap;

use common::{random, Rng};
use qgait_proto::{
    decode_frame, decode_message, encode_message, DecodeError, ErrorKind, FrameDecoder, Message,
    MAX_FRAME_LEN, MAX_MESSAGE_LEN,
};

/// A comparable form of a result: messages as their bytes (NaN-safe).
fn key(result: &Result<Message, DecodeError>) -> Result<Vec<u8>, DecodeError> {
    result
        .as_ref()
        .map(|m| {
            let mut buf = [0u8; MAX_MESSAGE_LEN];
            encode_message(m, &mut buf)
                .expect("decoded messages re-encode")
                .to_vec()
        })
        .map_err(|e| *e)
}

/// The reference model of the stream decoder.
fn reference(stream: &[u8]) -> Vec<Result<Message, DecodeError>> {
    let mut segments: Vec<&[u8]> = stream.split(|&b| b == 0).collect();
    let tail = segments.pop().unwrap_or(&[]);
    let mut out = Vec::new();
    for segment in segments.into_iter().filter(|s| !s.is_empty()) {
        if segment.len() > MAX_FRAME_LEN - 1 {
            out.push(Err(DecodeError::Oversize));
        } else {
            out.push(decode_frame(&mut segment.to_vec()));
        }
    }
    if tail.len() > MAX_FRAME_LEN - 1 {
        out.push(Err(DecodeError::Oversize));
    }
    out
}

/// `stream` decoded byte by byte through `push_frame` (the frame checks), each frame's message
/// bytes through `decode_message`.
fn decode_by_bytes(stream: &[u8]) -> Vec<Result<Message, DecodeError>> {
    let mut decoder = FrameDecoder::new();
    stream
        .iter()
        .filter_map(|&b| decoder.push_frame(b).map(|f| f.and_then(decode_message)))
        .collect()
}

/// `stream` decoded as the hub's poll loop feeds the decoder: read in blocks of random lengths
/// (what a serial read returns; a frame is split anywhere, the delimiter included), each
/// block through `push_run` (a run of data bytes up to the next 0x00) and `end_frame` (the
/// 0x00). Checks what each run reports on the way.
fn decode_by_slices(rng: &mut Rng, stream: &[u8]) -> Vec<Result<Message, DecodeError>> {
    let mut decoder = FrameDecoder::new();
    let mut out = Vec::new();
    let mut at = 0;
    while at < stream.len() {
        let len = match rng.below(4) {
            0 => rng.below(3),
            1 => 1 + rng.below(32),
            2 => rng.below(2 * MAX_FRAME_LEN),
            _ => stream.len(),
        };
        let block = &stream[at..(at + len).min(stream.len())];
        at += block.len();
        let mut pos = 0;
        while pos < block.len() {
            let pending = decoder.pending_len();
            let discarding = decoder.is_discarding();
            let (run, oversize) = decoder.push_run(&block[pos..]);
            // The run is every byte up to the next 0x00 of the block, or to its end.
            let want = block[pos..]
                .iter()
                .position(|&b| b == 0)
                .unwrap_or(block.len() - pos);
            assert_eq!(run, want);
            let room = if discarding {
                0
            } else {
                MAX_FRAME_LEN - 1 - pending
            };
            // Oversize once, when the run first finds no room.
            assert_eq!(oversize.is_some(), !discarding && run > room);
            if let Some(e) = oversize {
                assert_eq!(e.kind(), ErrorKind::Oversize);
                out.push(Err(e));
            }
            if !discarding && run <= room {
                assert_eq!(decoder.pending_len(), pending + run);
            } else {
                assert!(decoder.is_discarding());
            }
            pos += run;
            if pos < block.len() {
                pos += 1;
                if let Some(frame) = decoder.end_frame() {
                    out.push(frame.and_then(decode_message));
                }
            }
        }
    }
    out
}

#[derive(Default)]
struct Tally {
    streams: u64,
    bytes: u64,
    good_frames: u64,
    ok: u64,
    errors: BTreeMap<String, u64>,
}

fn run(seed: u64, streams: u64) -> Tally {
    let mut rng = Rng::new(seed);
    // The run lengths from a generator of their own: the streams are those of `seed` alone.
    let mut runs = Rng::new(!seed);
    let mut tally = Tally::default();
    for _ in 0..streams {
        let (stream, goods) = random::stream(&mut rng);
        let mut decoder = FrameDecoder::new();
        let mut results = Vec::new();
        let mut at = 0;
        while at < stream.len() {
            let len = match rng.below(4) {
                0 => 1,
                1 => rng.below(8),
                2 => rng.below(64),
                _ => rng.below(stream.len() + 1),
            };
            let end = (at + len).min(stream.len());
            let mut feed = decoder.feed(&stream[at..end]);
            results.extend(&mut feed);
            assert!(feed.remaining().is_empty());
            at = end;
        }
        let got: Vec<_> = results.iter().map(key).collect();
        let want: Vec<_> = reference(&stream).iter().map(key).collect();
        assert_eq!(got, want, "seed {seed}: stream {stream:02x?}");
        let by_bytes: Vec<_> = decode_by_bytes(&stream).iter().map(key).collect();
        assert_eq!(
            by_bytes, want,
            "seed {seed}: by bytes: stream {stream:02x?}"
        );
        let by_slices: Vec<_> = decode_by_slices(&mut runs, &stream)
            .iter()
            .map(key)
            .collect();
        assert_eq!(
            by_slices, want,
            "seed {seed}: by slices: stream {stream:02x?}"
        );

        let mut expected = goods.iter().map(|m| key(&Ok(m.clone())));
        let mut next = expected.next();
        for r in &got {
            if next.as_ref() == Some(r) {
                next = expected.next();
            }
        }
        assert_eq!(
            next, None,
            "seed {seed}: a good frame was lost in {stream:02x?}"
        );

        tally.streams += 1;
        tally.bytes += stream.len() as u64;
        tally.good_frames += goods.len() as u64;
        for r in &results {
            match r {
                Ok(_) => tally.ok += 1,
                Err(e) => *tally.errors.entry(format!("{:?}", e.kind())).or_default() += 1,
            }
        }
    }
    tally
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn report(tally: &Tally, seed: u64) {
    eprintln!(
        "stream fuzz: seed {seed}: {} streams, {} bytes, {} good frames, {} messages decoded, errors {:?}",
        tally.streams, tally.bytes, tally.good_frames, tally.ok, tally.errors
    );
}

#[test]
fn stream_fuzz() {
    let seed = env_u64("QGAIT_FUZZ_SEED", 0x5EED);
    let streams = env_u64("QGAIT_FUZZ_STREAMS", 20_000);
    let tally = run(seed, streams);
    report(&tally, seed);
    assert_eq!(tally.streams, streams);
    if streams >= 20_000 {
        // The generator reaches every error kind.
        for kind in [
            ErrorKind::Oversize,
            ErrorKind::Cobs,
            ErrorKind::TooShort,
            ErrorKind::Crc,
            ErrorKind::UnknownMessage,
            ErrorKind::UnknownVersion,
            ErrorKind::UnknownJoint,
            ErrorKind::UnknownModel,
            ErrorKind::AngleCount,
            ErrorKind::Malformed,
        ] {
            assert!(
                tally.errors.contains_key(&format!("{kind:?}")),
                "{kind:?} never produced"
            );
        }
    }
}

/// The long run: 1 000 000 streams. `cargo test --release -p qgait-proto --test fuzz_stream
/// -- --ignored --nocapture`.
#[test]
#[ignore = "long: run in release, see the crate README"]
fn stream_fuzz_one_million() {
    let seed = env_u64("QGAIT_FUZZ_SEED", 0x00C0_FFEE);
    let tally = run(seed, 1_000_000);
    report(&tally, seed);
    assert_eq!(tally.streams, 1_000_000);
}

#[test]
fn random_bytes_never_panic_and_match_the_reference() {
    let mut rng = Rng::new(99);
    let mut runs = Rng::new(100);
    for round in 0..2_000 {
        let zeros = [0u32, 1, 3, 10, 50][round % 5];
        let stream: Vec<u8> = (0..rng.below(1_000))
            .map(|_| if rng.chance(zeros) { 0 } else { rng.byte() })
            .collect();
        let got: Vec<_> = common::decode_all(&mut FrameDecoder::new(), &stream)
            .iter()
            .map(key)
            .collect();
        let want: Vec<_> = reference(&stream).iter().map(key).collect();
        assert_eq!(got, want);
        let by_bytes: Vec<_> = decode_by_bytes(&stream).iter().map(key).collect();
        assert_eq!(by_bytes, want);
        let by_slices: Vec<_> = decode_by_slices(&mut runs, &stream)
            .iter()
            .map(key)
            .collect();
        assert_eq!(by_slices, want);
    }
}
