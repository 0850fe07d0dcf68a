//! Host throughput of reading a hub log: frame decoding alone, and decoding plus verification
//! of every pose against the kernel recomputed in `f64`.
//!
//! `cargo bench -p qgait-device --bench decode_verify` (criterion; medians in target/criterion).
//! The log is what the hub sends for a PHAK session: one `PoseFrame` per sample (the hub's
//! own `Kinematics`, in `f32`) and a `Status` every 100 samples.
//! Element throughput = frames: criterion prints frames per second per core.
//!
//! It benches the library functions behind `qgait decode` and `qgait verify`
//! ([`HubLog::decode`], [`Verification::run`]).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use qgait_device::log::HubLog;
use qgait_device::verify::{Expected, Verification};
use qgait_proto::device_model::sample_angles;
use qgait_proto::{encode_frame, Kinematics, Message, ModelId, PoseModels, Status, MAX_FRAME_LEN};
use std::hint::black_box;

/// Samples in the log (100 s at 100 Hz).
const SAMPLES: u32 = 10_000;
/// Largest accepted |f32 point - f64 point| (metres), as in the firmware's end-to-end test.
const TOLERANCE_M: f64 = 5e-6;

/// A PHAK session log: pose frames computed in f32, a status frame every 100 samples.
fn log() -> Vec<u8> {
    let hub = Kinematics::new(ModelId::Phak, None).expect("the hub's default model");
    let mut bytes = Vec::new();
    let mut buf = [0u8; MAX_FRAME_LEN];
    for seq in 0..SAMPLES {
        let angles: [f32; 8] =
            core::array::from_fn(|c| 0.6 * ((seq as f32 * 0.05) + c as f32).sin());
        let frame = hub.pose_frame(seq, seq * 10_000, &sample_angles(ModelId::Phak, &angles), 0);
        bytes.extend_from_slice(encode_frame(&Message::PoseFrame(frame), &mut buf).expect("fits"));
        if seq % 100 == 99 {
            let status = Status {
                samples_completed: seq + 1,
                frames_sent: seq + 1,
                ..Status::default()
            };
            bytes
                .extend_from_slice(encode_frame(&Message::Status(status), &mut buf).expect("fits"));
        }
    }
    bytes
}

/// `qgait decode`: the whole log decoded; returns the number of pose frames.
fn decode(log: &[u8]) -> usize {
    HubLog::decode(log).poses.len()
}

/// `qgait verify`: decoded, then every pose recomputed by the f64 kernel and compared (points
/// and distances), every sequence number accounted for; returns whether it passed.
fn decode_and_verify(log: &[u8], model: &PoseModels<f64>) -> bool {
    let log = HubLog::decode(log);
    Verification::run(
        model,
        &log.poses,
        Expected::Range {
            first: 0,
            count: SAMPLES,
        },
    )
    .passed(TOLERANCE_M)
}

fn benches(c: &mut Criterion) {
    let log = log();
    let model = PoseModels::defaults();
    assert_eq!(decode(&log), SAMPLES as usize);
    assert!(decode_and_verify(&log, &model), "the log verifies");
    let mut group = c.benchmark_group("log");
    group.throughput(Throughput::Elements(u64::from(SAMPLES)));
    group.bench_function("decode", |b| b.iter(|| decode(black_box(&log))));
    group.bench_function("decode_verify", |b| {
        b.iter(|| decode_and_verify(black_box(&log), &model))
    });
    group.finish();
    eprintln!("log: {} bytes, {} pose frames", log.len(), SAMPLES);
}

criterion_group!(decode_verify, benches);
criterion_main!(decode_verify);
