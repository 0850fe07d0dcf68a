//! `qgait verify` and `qgait decode` hold memory independent of the log's length: on a hub log
//! of several megabytes, the heap they use at their peak (counted by this test binary's
//! allocator) stays far below the log's size. Not a timing: the bound is on bytes.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use clap::Parser;
use qgait::cli::{Cli, Command};
use qgait_device::packets::push_frame;
use qgait_proto::device_model::{pose_distances, pose_points};
use qgait_proto::{Message, ModelId, PoseFrame, PoseModels, Status};

/// Counts the bytes allocated on the heap, now and at the peak since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(n: usize) {
    let now = LIVE.fetch_add(n, Ordering::SeqCst) + n;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

// SAFETY: every call is passed on to the system allocator unchanged.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = System.alloc(layout);
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout);
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = System.realloc(ptr, layout, new_size);
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
            grew(new_size);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One measurement at a time (the counters are the whole process's).
static TURN: Mutex<()> = Mutex::new(());

/// Frames in the log (about 9 MB).
const FRAMES: u32 = 60_000;
/// Most heap a command may add at its peak: a read buffer, the decoder, the model.
const BOUND: usize = 1 << 20;

/// Writes a clean PHAK hub log of `FRAMES` pose frames (a status every 100) to `path`,
/// without holding it; returns its size.
fn write_log(path: &Path) -> u64 {
    let model = PoseModels::<f64>::defaults();
    let mut frame = PoseFrame {
        seq: 0,
        timestamp_us: 0,
        model: ModelId::Phak,
        angles: heapless::Vec::from_slice(&[0.05, -0.02, 0.3, -0.6, 0.1, -0.1, -0.2, 0.05])
            .unwrap(),
        points: [[0.0; 3]; 8],
        distances: [0.0; 3],
        flags: 0,
    };
    let pose = model.frame_pose(&frame).expect("a hub's own model");
    frame.points = pose_points(&pose);
    frame.distances = pose_distances(&pose);
    let mut w = BufWriter::new(std::fs::File::create(path).unwrap());
    let mut bytes = vec![0u8];
    for seq in 0..FRAMES {
        frame.seq = seq;
        frame.timestamp_us = seq * 10_000;
        push_frame(&mut bytes, &Message::PoseFrame(frame.clone()));
        if seq % 100 == 99 {
            push_frame(&mut bytes, &Message::Status(Status::default()));
        }
        w.write_all(&bytes).unwrap();
        bytes.clear();
    }
    w.flush().unwrap();
    std::fs::metadata(path).unwrap().len()
}

/// Runs `f`, returning its result and the most heap it held beyond what was held before.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = LIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let out = f();
    (out, PEAK.load(Ordering::SeqCst).saturating_sub(before))
}

fn command(args: &[&str]) -> Command {
    Cli::try_parse_from(std::iter::once("qgait").chain(args.iter().copied()))
        .unwrap()
        .command
}

#[test]
fn verify_holds_less_than_a_megabyte_of_a_9_mb_log() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hub.bin");
    let size = write_log(&log);
    assert!(size > 8 * BOUND as u64, "{size} bytes");
    let Command::Verify(args) = command(&["verify", log.to_str().unwrap()]) else {
        unreachable!()
    };
    let (passed, peak) = peak_of(|| qgait::cli::verify::run_verify(args, true).unwrap());
    assert!(passed, "the log verifies");
    eprintln!("verify: {peak} bytes of heap at the peak for a {size}-byte log");
    assert!(
        peak < BOUND,
        "verify held {peak} bytes of heap for a {size}-byte log"
    );
}

#[test]
fn decode_holds_less_than_a_megabyte_of_a_9_mb_log() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("hub.bin");
    let size = write_log(&log);
    for format in ["csv", "jsonl"] {
        let Command::Decode(args) = command(&["decode", log.to_str().unwrap(), "--format", format])
        else {
            unreachable!()
        };
        let mut out = CountingSink(0);
        let (result, peak) = peak_of(|| qgait::cli::decode::decode_to(&args, &mut out, true));
        result.unwrap();
        assert!(out.0 > size as usize, "{format}: {} bytes out", out.0);
        eprintln!(
            "decode --format {format}: {peak} bytes of heap at the peak for a {size}-byte log"
        );
        assert!(
            peak < BOUND,
            "decode --format {format} held {peak} bytes of heap for a {size}-byte log"
        );
    }
}

/// Counts what is written to it.
struct CountingSink(usize);

impl Write for CountingSink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0 += buf.len();
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
