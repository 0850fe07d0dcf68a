//! End to end: a BROAD trial through the IMU node firmware under QEMU (mps2-an386, the
//! `qgait-node` binary): `qgait packets --raw` makes the raw node's stream of a slice of the
//! trial (the counts of an ICM-20948), `qgait emulate --node --verify` runs it through the node
//! and checks its orientations against the host's `f64` fusion of the same stream, and then:
//!
//! - the node's orientations are within 0.1° RMS of `qgait fuse`'s (the kernel's VQF in `f64`
//!   on the recording's own numbers) on the same samples;
//! - their BROAD error (total RMSE over the slice's moving rows) is within 0.1° of the host's.
//!
//! The slice (21 s, the end of the trial's rest and the start of its rotations) keeps the run
//! short. Skipped, with the reason printed, without `../shared`, QEMU or a node build.

use qgait_system_tests as common;

use std::path::{Path, PathBuf};

use qgait_device::raw::angle_deg;
use qgait_emulate::{firmware, qemu};
use qgait_fusion::{fuse, read_csv, score, Mode};
use qgait_proto::{FrameDecoder, Message};

/// The trial and its slice: rows `FIRST..FIRST + ROWS` (286 Hz).
const TRIAL: &str = "03_undisturbed_slow_rotation_C.csv";
const FIRST: usize = 11_000;
const ROWS: usize = 6_000;

/// The node firmware (built or brought up to date first); `None` (the reason printed) without
/// QEMU or a build.
fn node_elf() -> Option<PathBuf> {
    if !qemu::available() {
        eprintln!("skipped: {} is not installed", qemu::QEMU);
        return None;
    }
    if let Some(p) = std::env::var_os("QGAIT_NODE_FIRMWARE_ELF") {
        return Some(PathBuf::from(p));
    }
    let root = common::root();
    eprintln!("building {}", firmware::node_elf(&root).display());
    match firmware::build_node(&root) {
        Ok(elf) => Some(elf),
        Err(e) => {
            eprintln!(
                "skipped: {e} (build it: {})",
                firmware::node_build_command(&root)
            );
            None
        }
    }
}

/// Writes the header and rows `first..first + n` of `csv` to `out`.
fn slice(csv: &Path, first: usize, n: usize, out: &Path) {
    let text = std::fs::read_to_string(csv).expect("the trial reads");
    let mut lines = text.lines();
    let header = lines.next().expect("a header");
    let body: Vec<&str> = lines.skip(first).take(n).collect();
    assert_eq!(body.len(), n, "{}: too short", csv.display());
    std::fs::write(out, format!("{header}\n{}\n", body.join("\n"))).expect("the slice writes");
}

#[test]
fn a_broad_trial_through_the_node_matches_the_host_s_fusion() {
    let Some(shared) = common::shared_dir() else {
        return;
    };
    let trial = shared.join("data/broad").join(TRIAL);
    if !trial.is_file() {
        eprintln!("skipped: {} is missing", trial.display());
        return;
    }
    let Some(elf) = node_elf() else {
        return;
    };
    let dir = common::scratch("e2e-node", "broad");
    let csv = dir.join("slice.csv");
    slice(&trial, FIRST, ROWS, &csv);
    let (stream, log) = (dir.join("stream.bin"), dir.join("node.bin"));
    let p = |p: &Path| p.to_str().expect("utf-8 path").to_string();
    let out = common::qgait(&[
        "packets",
        "--raw",
        &p(&csv),
        "--segment",
        "tibia_r",
        "-o",
        &p(&stream),
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let out = common::qgait(&[
        "emulate",
        "--node",
        "--stream",
        &p(&stream),
        "--elf",
        &p(&elf),
        "--verify",
        "--log",
        &p(&log),
    ]);
    let stdout = common::stdout(&out);
    eprintln!("{stdout}");
    assert!(out.status.success(), "{stdout}\n{}", common::stderr(&out));
    assert!(stdout.contains("raw input: 6000 orientations"), "{stdout}");

    // The node's orientations, one per sample, by seq.
    let bytes = std::fs::read(&log).expect("the log reads");
    let mut device = vec![None; ROWS];
    for m in FrameDecoder::new().feed(&bytes).flatten() {
        if let Message::SegmentOrientation(o) = m {
            device[o.header.seq as usize] = Some(o.quaternion().map(f64::from));
        }
    }
    let device: Vec<[f64; 4]> = device
        .into_iter()
        .enumerate()
        .map(|(i, q)| q.unwrap_or_else(|| panic!("no orientation for sample {i}")))
        .collect();

    // `qgait fuse` on the same samples: the recording's own numbers, f64.
    let recording = read_csv(&csv).expect("the slice reads");
    let host = fuse(&recording, Mode::NineD, |_| {}).expect("fuses");
    let sum: f64 = device
        .iter()
        .zip(&host)
        .map(|(d, h)| angle_deg(*d, *h).powi(2))
        .sum();
    let rms = (sum / ROWS as f64).sqrt();
    let (device_score, rows) = score(&recording, &device).expect("moving rows in the slice");
    let (host_score, _) = score(&recording, &host).expect("moving rows in the slice");
    eprintln!(
        "node against `qgait fuse`: {rms:.4}° RMS over {ROWS} samples; BROAD total RMSE over {rows} moving rows: node {:.4}°, host {:.4}°",
        device_score[0], host_score[0]
    );
    assert!(rows > 1000, "{rows} moving rows");
    assert!(rms <= 0.1, "{rms}° RMS from `qgait fuse`");
    assert!(
        (device_score[0] - host_score[0]).abs() <= 0.1,
        "BROAD error {}° against the host's {}°",
        device_score[0],
        host_score[0]
    );
    let _ = std::fs::remove_dir_all(&dir);
}
