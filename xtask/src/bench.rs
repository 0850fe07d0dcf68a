//! `cargo xtask bench`: every benchmark figure of BENCHMARKS.md, one machine-readable line per
//! figure on stdout (`NAME VALUE`); builds, QEMU and criterion output go to stderr.
//!
//! - Device: the firmware's `bench` binary under QEMU mps2-an386 with `-icount shift=0,align=off`
//!   (instructions per call), run twice; the two runs must agree to 1 %.
//! - Footprint: flash and static RAM of the release firmware (mps2-an386), its peak stack from
//!   the UART session, and the code size of each measured loop in the bench ELF (the kernel's
//!   share per model and method).
//! - Host: criterion's medians (`target/criterion/**/new/estimates.json`) of the kernel's `fk`
//!   bench and of `qgait-device`'s `decode_verify` bench.
//!
//! - Large files: the release `qgait` on a generated 1,000,000-row motion (in a temporary
//!   directory, removed afterwards): `fk`, `export`, `packets` and `report` on it, `decode` and
//!   `verify` on a hub log of the same million samples; rows per second, MB per second and the
//!   child's peak resident memory (`wait4`) of each (module [`large`]).
//!
//! `--no-host` skips the criterion benches (they take minutes and want a quiet machine);
//! `--no-large` the large files; `--large-only` runs only those.

use anyhow::anyhow;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Duration;

use clap::Args;
use object::{Object, ObjectSymbol};
use qgait_emulate::qemu::{Echo, Qemu};

use crate::cargo::cargo;
use crate::elf_size::footprint;

mod large;
use crate::repo_root;

/// Longest one QEMU run of the bench binary may take.
const QEMU_TIMEOUT: Duration = Duration::from_secs(120);
/// Largest relative difference accepted between the two device runs.
const REPEATABILITY: f64 = 0.01;
/// Frames per call of the kernel's batch benches (`BATCH` in crates/qgait-kernel/benches/fk.rs).
const KERNEL_BATCH: f64 = 4096.0;

/// Pose frames per iteration of the log benches (`SAMPLES` in crates/qgait-device/benches/decode_verify.rs).
const LOG_FRAMES: f64 = 10_000.0;

/// Device figures: (name printed by the bench binary, name printed here).
const DEVICE: &[(&str, &str)] = &[
    ("hak.quat", "device.hak.quat.instructions_per_frame"),
    ("hak.matrix", "device.hak.matrix.instructions_per_frame"),
    ("phak.quat", "device.phak.quat.instructions_per_frame"),
    (
        "phak.velocities",
        "device.phak.velocities.instructions_per_frame",
    ),
    ("phak.motion", "device.phak.motion.instructions_per_frame"),
    (
        "phak.quat_frames",
        "device.phak.quat.joint_frames_instructions",
    ),
    ("phak.matrix", "device.phak.matrix.instructions_per_frame"),
    (
        "gait2392.quat",
        "device.gait2392.quat.instructions_per_frame",
    ),
    (
        "gait2392.quat_frames",
        "device.gait2392.quat.joint_frames_instructions",
    ),
    (
        "gait2392.velocities",
        "device.gait2392.velocities.instructions_per_frame",
    ),
    (
        "gait2392.motion",
        "device.gait2392.motion.instructions_per_frame",
    ),
    (
        "gait2392.matrix",
        "device.gait2392.matrix.instructions_per_frame",
    ),
    (
        "rajagopal.quat",
        "device.rajagopal.quat.instructions_per_frame",
    ),
    (
        "rajagopal.velocities",
        "device.rajagopal.velocities.instructions_per_frame",
    ),
    (
        "rajagopal.motion",
        "device.rajagopal.motion.instructions_per_frame",
    ),
    (
        "trig.half_angle_sin_cos",
        "device.trig.half_angle_sin_cos.instructions_per_call",
    ),
    (
        "trig.libm_sincosf",
        "device.trig.libm_sincosf.instructions_per_call",
    ),
    (
        "trig.sqrt_f32",
        "device.trig.sqrt_f32.instructions_per_call",
    ),
    ("imu.segments", "device.imu.segments_instructions"),
    ("imu.closed_form", "device.imu.closed_form_instructions"),
    ("imu.least_squares", "device.imu.least_squares_instructions"),
    (
        "imu.whole_cf",
        "device.imu.closed_form_and_gait2392_fk_instructions",
    ),
    (
        "imu.whole_ls",
        "device.imu.least_squares_and_gait2392_fk_instructions",
    ),
    // The kernel's VQF (orientation from raw IMU samples), f32: one update and its output.
    ("vqf.update_9d", "device.vqf.update_9d_instructions"),
    ("vqf.update_6d", "device.vqf.update_6d_instructions"),
    ("vqf_rs.update_9d", "device.vqf_rs.update_9d_instructions"),
    ("vqf_rs.update_6d", "device.vqf_rs.update_6d_instructions"),
    ("sample.net", "device.sample.instructions"),
    (
        "sample.gross",
        "device.sample.with_serial_double_instructions",
    ),
    (
        "sample.serial_double",
        "device.sample.serial_double_instructions",
    ),
    (
        "sample.decode_8_packets",
        "device.sample.decode_8_packets_instructions",
    ),
    ("sample.pose_frame", "device.sample.pose_frame_instructions"),
    ("sample.distances", "device.sample.distances_instructions"),
    (
        "sample.encode_pose_frame",
        "device.sample.encode_pose_frame_instructions",
    ),
    (
        "sample.encode_message_pose_frame",
        "device.sample.encode_message_pose_frame_instructions",
    ),
    (
        "sample.crc32c_packet",
        "device.sample.crc32c_packet_instructions",
    ),
    (
        "sample.decode_message_packet",
        "device.sample.decode_message_packet_instructions",
    ),
    ("sample_gait2392.net", "device.sample_gait2392.instructions"),
    (
        "sample_gait2392.serial_double",
        "device.sample_gait2392.serial_double_instructions",
    ),
    // The protocol crate's CRC-32C and COBS beside the crates (see BENCHMARKS.md).
    ("crc.ours_packet", "device.crc.ours_packet_instructions"),
    (
        "crc.crc_crate_packet",
        "device.crc.crc_crate_packet_instructions",
    ),
    (
        "cobs.encode_ours_packet",
        "device.cobs.encode_ours_packet_instructions",
    ),
    (
        "cobs.encode_cobs_crate_packet",
        "device.cobs.encode_cobs_crate_packet_instructions",
    ),
    (
        "cobs.encode_postcard_flavour_packet",
        "device.cobs.encode_postcard_flavour_packet_instructions",
    ),
    (
        "cobs.decode_ours_packet",
        "device.cobs.decode_ours_packet_instructions",
    ),
    (
        "cobs.decode_cobs_crate_packet",
        "device.cobs.decode_cobs_crate_packet_instructions",
    ),
    ("crc.ours_pose", "device.crc.ours_pose_instructions"),
    (
        "crc.crc_crate_pose",
        "device.crc.crc_crate_pose_instructions",
    ),
    (
        "cobs.encode_ours_pose",
        "device.cobs.encode_ours_pose_instructions",
    ),
    (
        "cobs.encode_cobs_crate_pose",
        "device.cobs.encode_cobs_crate_pose_instructions",
    ),
    (
        "cobs.encode_postcard_flavour_pose",
        "device.cobs.encode_postcard_flavour_pose_instructions",
    ),
    (
        "cobs.decode_ours_pose",
        "device.cobs.decode_ours_pose_instructions",
    ),
    (
        "cobs.decode_cobs_crate_pose",
        "device.cobs.decode_cobs_crate_pose_instructions",
    ),
];

/// Code size of each model and method in the bench ELF: (figure name, measured loop function,
/// kernel functions the compiler kept out of line for it, if present). The loop is the kernel
/// call inlined into a counting loop: the empty loop's size is subtracted. libm's `sincosf`,
/// which every matrix method calls, is its own figure.
const CODE: &[(&str, &str, &[&str])] = &[
    (
        "firmware.kernel.hak.quat.code_bytes",
        "bench_hak_quat",
        &["Hak$LT$T$GT$2fk"],
    ),
    (
        "firmware.kernel.hak.matrix.code_bytes",
        "bench_hak_matrix",
        &[],
    ),
    (
        "firmware.kernel.phak.quat.code_bytes",
        "bench_phak_quat",
        &["Phak$LT$T$GT$2fk"],
    ),
    (
        "firmware.kernel.phak.matrix.code_bytes",
        "bench_phak_matrix",
        &[],
    ),
    (
        "firmware.kernel.gait2392.quat.code_bytes",
        "bench_gait2392_quat",
        &["Gait2392$LT$T$GT$2fk", "Spline$LT$T$GT$4eval"],
    ),
    (
        "firmware.kernel.gait2392.matrix.code_bytes",
        "bench_gait2392_matrix",
        &["Spline$LT$T$GT$4eval"],
    ),
    (
        "firmware.kernel.vqf_9d.code_bytes",
        "bench_vqf_9d",
        &[
            "Vqf$LT$T$GT$6update",
            "Vqf$LT$T$GT$10update_gyr",
            "Vqf$LT$T$GT$10update_acc",
            "Vqf$LT$T$GT$13estimate_bias",
            "Vqf$LT$T$GT$10update_mag",
            "fusion3vqf10filter_vec",
            "fusion3vqf11quat_rotate",
            "fusion3vqf13quat_multiply",
            "fusion3vqf16matrix3_multiply",
            "fusion3vqf9normalize",
            "atanf5atanf",
            "asinf5asinf",
            "atan2f6atan2f",
        ],
    ),
    (
        "firmware.libm_sincosf.code_bytes",
        "",
        &[
            "sincosf7sincosf",
            "k_sinf6k_sinf",
            "k_cosf6k_cosf",
            "rem_pio2f",
            "rem_pio2_large",
        ],
    ),
];

/// Samples per iteration of the kernel's `fusion` bench.
const VQF_RUN: f64 = 4096.0;

/// Host figures: (criterion directory under target/criterion, figure name, frames per iteration).
const HOST: &[(&str, &str, f64)] = &[
    ("vqf_f64/update_9d", "host.vqf.f64.update_9d_ns", VQF_RUN),
    ("vqf_f64/update_6d", "host.vqf.f64.update_6d_ns", VQF_RUN),
    (
        "single_frame_f64/hak_quat",
        "host.hak.f64.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f64/hak_matrix",
        "host.hak.f64.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f64/phak_quat",
        "host.phak.f64.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f64/phak_matrix",
        "host.phak.f64.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f64/gait2392_quat",
        "host.gait2392.f64.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f64/gait2392_matrix",
        "host.gait2392.f64.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/hak_quat",
        "host.hak.f32.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/hak_matrix",
        "host.hak.f32.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/phak_quat",
        "host.phak.f32.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/phak_matrix",
        "host.phak.f32.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/gait2392_quat",
        "host.gait2392.f32.quat.single_ns_per_frame",
        1.0,
    ),
    (
        "single_frame_f32/gait2392_matrix",
        "host.gait2392.f32.matrix.single_ns_per_frame",
        1.0,
    ),
    (
        "batch_f64/hak/4096",
        "host.hak.f64.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f64/phak/4096",
        "host.phak.f64.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f64/gait2392/4096",
        "host.gait2392.f64.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f64/phak_loop_of_single/4096",
        "host.phak.f64.loop_of_single_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f32/hak/4096",
        "host.hak.f32.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f32/phak/4096",
        "host.phak.f32.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f32/gait2392/4096",
        "host.gait2392.f32.batch_ns_per_frame",
        KERNEL_BATCH,
    ),
    (
        "batch_f32/phak_loop_of_single/4096",
        "host.phak.f32.loop_of_single_ns_per_frame",
        KERNEL_BATCH,
    ),
    ("log/decode", "host.log.decode_ns_per_frame", LOG_FRAMES),
    (
        "log/decode_verify",
        "host.log.decode_verify_ns_per_frame",
        LOG_FRAMES,
    ),
];

/// `cargo xtask bench` flags.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Skip the criterion benches of the host (they take minutes and want a quiet machine).
    #[arg(long)]
    pub no_host: bool,
    /// Skip the firmware's flash, RAM and stack figures.
    #[arg(long)]
    pub no_footprint: bool,
    /// Skip the large-file figures.
    #[arg(long)]
    pub no_large: bool,
    /// Only the large-file figures.
    #[arg(long)]
    pub large_only: bool,
    /// Only the hub with raw input: the bench binary built with `imu,raw`, instructions per
    /// 100 Hz sample of eight raw 9D sensors (fusion, least squares, pose frame).
    #[arg(long)]
    pub raw: bool,
}

/// Runs every benchmark and prints the figures.
pub fn run(args: &BenchArgs) -> anyhow::Result<ExitCode> {
    if args.large_only {
        large::run()?;
        return Ok(ExitCode::SUCCESS);
    }
    if args.raw {
        device_raw()?;
        return Ok(ExitCode::SUCCESS);
    }
    device()?;
    if !args.no_footprint {
        firmware_footprint()?;
    }
    if !args.no_host {
        host_benches()?;
    }
    if !args.no_large {
        large::run()?;
    }
    Ok(ExitCode::SUCCESS)
}

fn figure(name: &str, value: impl std::fmt::Display) {
    println!("{name} {value}");
}

fn firmware_target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| repo_root().join("firmware/target"))
}

/// Device instruction counts: two runs of the bench binary, compared, then printed.
fn device() -> anyhow::Result<()> {
    cargo(
        &repo_root().join("firmware"),
        &["build", "--release", "--bin", "bench"],
    )?;
    let elf = firmware_target_dir().join("thumbv7em-none-eabihf/release/bench");
    let bytes = std::fs::read(&elf).map_err(|e| anyhow!("reading {}: {e}", elf.display()))?;
    let first = run_bench_elf(&elf)?;
    let second = run_bench_elf(&elf)?;
    for (key, name) in DEVICE {
        let key = format!("{key}.instructions_per_call");
        let (Some(&a), Some(&b)) = (first.get(&key), second.get(&key)) else {
            return Err(anyhow!("the bench binary printed no {key}"));
        };
        if (a - b).abs() > REPEATABILITY * a.abs().max(1.0) {
            return Err(anyhow!("{name}: runs differ by more than 1 %: {a} vs {b}"));
        }
        eprintln!("{name}: run 1 {a}, run 2 {b}");
        figure(name, format!("{:.0}", (a + b) / 2.0));
    }
    let empty = function_size(&bytes, "bench_empty")
        .ok_or_else(|| anyhow!("no bench_empty in the bench ELF"))?;
    for (name, function, helpers) in CODE {
        let mut size = 0;
        if !function.is_empty() {
            size += function_size(&bytes, function)
                .ok_or_else(|| anyhow!("no {function} in the bench ELF"))?;
            size = size.saturating_sub(empty);
        }
        size += helpers
            .iter()
            .filter_map(|h| function_size(&bytes, h))
            .sum::<u64>();
        figure(name, size);
    }
    Ok(())
}

/// The hub with raw input: the bench binary with `imu,raw`, its `raw_sample` figures.
fn device_raw() -> anyhow::Result<()> {
    cargo(
        &repo_root().join("firmware"),
        &[
            "build",
            "--release",
            "--bin",
            "bench",
            "--features",
            "imu,raw",
        ],
    )?;
    let elf = firmware_target_dir().join("thumbv7em-none-eabihf/release/bench");
    let figures = run_bench_elf(&elf)?;
    let mut any = false;
    for (key, value) in figures.iter().filter(|(k, _)| k.contains("raw_")) {
        figure(key, value);
        any = true;
    }
    if any {
        Ok(())
    } else {
        Err(anyhow!("the bench binary printed no raw_sample figure"))
    }
}

/// Runs the bench ELF once under QEMU with instruction counting (the shared runner,
/// `qgait_emulate::qemu`); returns its `bench NAME VALUE` figures.
fn run_bench_elf(elf: &Path) -> anyhow::Result<BTreeMap<String, f64>> {
    eprintln!(
        "==> qemu-system-arm -M mps2-an386 -icount shift=0,align=off -kernel {}",
        elf.display()
    );
    let finished = Qemu::start_with_args(elf, &["-icount", "shift=0,align=off"], Echo::Quiet)
        .map_err(|e| anyhow!("{e}"))?
        .wait(QEMU_TIMEOUT);
    let mut figures = BTreeMap::new();
    for line in &finished.log {
        eprintln!("  {line}");
        let mut words = line.split_whitespace();
        if let (Some("bench"), Some(key), Some(value), None) =
            (words.next(), words.next(), words.next(), words.next())
        {
            if let Ok(v) = value.parse::<f64>() {
                figures.insert(key.to_string(), v);
            }
        }
    }
    match finished.code {
        Some(0) => Ok(figures),
        Some(c) => Err(anyhow!("the bench binary exited with status {c}")),
        None => Err(anyhow!(
            "the bench binary did not finish within {QEMU_TIMEOUT:?}"
        )),
    }
}

/// Size of the first function whose (mangled) name contains `name`, if any.
fn function_size(elf: &[u8], name: &str) -> Option<u64> {
    let file = object::File::parse(elf).ok()?;
    file.symbols()
        .filter(|s| s.kind() == object::SymbolKind::Text)
        .find(|s| s.name().is_ok_and(|n| n.contains(name)))
        .map(|s| s.size())
}

/// Flash, static RAM and peak stack of the release application firmware (mps2-an386).
fn firmware_footprint() -> anyhow::Result<()> {
    cargo(
        &repo_root().join("firmware"),
        &["build", "--release", "--bin", "qgait-firmware"],
    )?;
    let elf = firmware_target_dir().join("thumbv7em-none-eabihf/release/qgait-firmware");
    let bytes = std::fs::read(&elf).map_err(|e| anyhow!("reading {}: {e}", elf.display()))?;
    let f = footprint(&bytes)?;
    // The UART session (which logs the painted stack's peak) in a child xtask, so its log goes
    // to stderr and stdout keeps only the figures.
    let exe = std::env::current_exe().map_err(|e| anyhow!("locating xtask: {e}"))?;
    eprintln!("==> {} qemu-run {}", exe.display(), elf.display());
    let out = Command::new(exe)
        .arg("qemu-run")
        .arg(&elf)
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| anyhow!("running the UART session: {e}"))?;
    let log = String::from_utf8_lossy(&out.stdout);
    eprint!("{log}");
    if !out.status.success() {
        // The peak the firmware logged is its measurement whatever the session's checks say
        // (they can fail on a loaded machine, when the emulated UART's receive ring overruns).
        eprintln!(
            "xtask: warning: the UART session's checks failed; its stack peak is reported anyway"
        );
    }
    let peak = crate::session::stack_peak(&log)
        .map(u64::from)
        .ok_or_else(|| anyhow!("the firmware logged no stack peak"))?;
    figure("firmware.flash_bytes", f.flash);
    figure("firmware.static_ram_bytes", f.static_ram);
    figure("firmware.peak_stack_bytes", peak);
    figure("firmware.ram_bytes", f.static_ram + peak);
    // The bound from the disassembly: what no run can exceed.
    let bound = crate::stack_bound::bound(&elf)?;
    figure("firmware.stack_bound_bytes", bound.bytes);
    figure("firmware.ram_bound_bytes", f.static_ram + bound.bytes);
    Ok(())
}

/// Criterion benches of the root workspace, then their medians.
fn host_benches() -> anyhow::Result<()> {
    let root = repo_root();
    cargo(&root, &["bench", "-p", "qgait-kernel", "--bench", "fk"])?;
    cargo(&root, &["bench", "-p", "qgait-kernel", "--bench", "fusion"])?;
    cargo(
        &root,
        &["bench", "-p", "qgait-device", "--bench", "decode_verify"],
    )?;
    let criterion = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"))
        .join("criterion");
    for (dir, name, frames) in HOST {
        let median = criterion_median_ns(&criterion.join(dir))?;
        figure(name, format!("{:.2}", median / frames));
    }
    Ok(())
}

/// Criterion's median estimate (ns per iteration) of one benchmark directory.
fn criterion_median_ns(dir: &Path) -> anyhow::Result<f64> {
    let path = dir.join("new/estimates.json");
    let text =
        std::fs::read_to_string(&path).map_err(|e| anyhow!("reading {}: {e}", path.display()))?;
    // {"mean":{...},"median":{"confidence_interval":{...},"point_estimate":123.4,...},...}
    let median = text
        .split("\"median\"")
        .nth(1)
        .ok_or_else(|| anyhow!("no median in {}", path.display()))?;
    let value = median
        .split("\"point_estimate\":")
        .nth(1)
        .and_then(|v| v.split([',', '}']).next())
        .and_then(|v| v.trim().parse::<f64>().ok())
        .ok_or_else(|| anyhow!("no median point estimate in {}", path.display()))?;
    Ok(value)
}
