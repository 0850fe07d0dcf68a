//! Host throughput of reading a hub log: frame decoding alone, and decoding plus verification
//! of every pose against the kernel recomputed in `f64`.
//!
//! `cargo bench -p qgait --bench decode_verify` (criterion; medians in target/criterion).
//! The log is what the hub sends for a PHAK session: one `PoseFrame` per sample (points from
//! the kernel in `f32`, as the firmware computes them) and a `Status` every 100 samples.
//! Element throughput = frames: criterion prints frames per second per core.
//!
//! This benches qgait-proto's `FrameDecoder` and the kernel directly (the `qgait decode` /
//! `verify` library functions did not exist when it was written).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait_kernel::{Anthropometry, Phak, PhakAngles};
use qgait_proto::{encode_frame, FrameDecoder, Message, ModelId, PoseFrame, Status, MAX_FRAME_LEN};
use std::hint::black_box;

/// Samples in the log (100 s at 100 Hz).
const SAMPLES: u32 = 10_000;
/// Largest accepted |f32 point - f64 point| (metres), as in the firmware's end-to-end test.
const TOLERANCE_M: f64 = 5e-6;

/// A PHAK session log: pose frames computed in f32, a status frame every 100 samples.
fn log() -> Vec<u8> {
    let phak = Phak::<f32>::new(&Anthropometry::gait2392()).expect("gait2392 anthropometry");
    let mut bytes = Vec::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    for seq in 0..SAMPLES {
        let angles: [f32; 8] = core::array::from_fn(|c| 0.6 * ((seq as f32 * 0.05) + c as f32).sin());
        let pose = phak.fk(&PhakAngles::from_array(angles));
        let d = qgait_kernel::metrics::distances(&pose);
        let frame = PoseFrame {
            seq,
            model: ModelId::Phak,
            angles: heapless::Vec::from_slice(&angles).expect("8 angles fit"),
            points: pose.points().map(|p| p.to_array()),
            distances: [d.knee, d.ankle, d.toe],
            flags: 0,
        };
        bytes.extend_from_slice(encode_frame(&Message::PoseFrame(frame), &mut buf).expect("fits"));
        if seq % 100 == 99 {
            let status = Status { samples_completed: seq + 1, frames_sent: seq + 1, ..Status::default() };
            bytes.extend_from_slice(encode_frame(&Message::Status(status), &mut buf).expect("fits"));
        }
    }
    bytes
}

/// Decodes the log; returns the number of pose frames.
fn decode(log: &[u8]) -> usize {
    let mut decoder = FrameDecoder::new();
    decoder.feed(log).filter(|m| matches!(m, Ok(Message::PoseFrame(_)))).count()
}

/// Decodes the log and recomputes every pose in f64; returns the number of poses beyond
/// tolerance (0 for this log).
fn decode_and_verify(log: &[u8], phak: &Phak<f64>) -> usize {
    let mut decoder = FrameDecoder::new();
    let mut bad = 0;
    for message in decoder.feed(log) {
        let Ok(Message::PoseFrame(frame)) = message else { continue };
        let Ok(angles) = <[f32; 8]>::try_from(frame.angles.as_slice()) else {
            bad += 1;
            continue;
        };
        let pose = phak.fk(&PhakAngles::from_array(angles.map(f64::from)));
        let worst = pose
            .points()
            .iter()
            .zip(&frame.points)
            .flat_map(|(want, got)| {
                let w = want.to_array();
                (0..3).map(move |k| (w[k] - f64::from(got[k])).abs())
            })
            .fold(0.0, f64::max);
        if worst > TOLERANCE_M {
            bad += 1;
        }
    }
    bad
}

fn benches(c: &mut Criterion) {
    let log = log();
    let phak = Phak::<f64>::new(&Anthropometry::gait2392()).expect("gait2392 anthropometry");
    assert_eq!(decode(&log), SAMPLES as usize);
    assert_eq!(decode_and_verify(&log, &phak), 0);
    let mut group = c.benchmark_group("log");
    group.throughput(Throughput::Elements(u64::from(SAMPLES)));
    group.bench_function("decode", |b| b.iter(|| decode(black_box(&log))));
    group.bench_function("decode_verify", |b| b.iter(|| decode_and_verify(black_box(&log), &phak)));
    group.finish();
    eprintln!("log: {} bytes, {} pose frames", log.len(), SAMPLES);
}

criterion_group!(decode_verify, benches);
criterion_main!(decode_verify);
