//! `cargo xtask demo`: the main job in one command. Installs what is missing (rustup target,
//! QEMU), builds the release firmware, runs it under QEMU on the built-in normal gait (its
//! packets streamed into UART0), decodes and verifies every frame against the f64 kernel, and
//! draws the device's frames into `out/demo/`; then the IMU path on OpenSense's tutorial recording
//! against OpenSense (the accuracy table and `figures/imu_angles.png`) and its clinical gait
//! report (`gait/report.html`), all with the release `qgait` binary.

use anyhow::anyhow;
use std::path::Path;
use std::process::{Command, ExitCode};

use crate::cargo::{qgait_binary, step};
use crate::repo_root;

/// The folder the demo writes to, relative to the repository root.
pub const OUT: &str = "out/demo";

/// Runs `qgait ARGS`, its output through.
fn qgait(exe: &Path, args: &[&str]) -> anyhow::Result<()> {
    println!("\n==> qgait {}", args.join(" "));
    let status = Command::new(exe)
        .args(args)
        .status()
        .map_err(|e| anyhow!("starting {}: {e}", exe.display()))?;
    if status.success() {
        Ok(())
    } else {
        Err(anyhow!("qgait {} failed ({status})", args[0]))
    }
}

/// The IMU path on OpenSense's tutorial recording (`../shared/data/imu`, or `$QGAIT_SHARED`;
/// skipped with the reason when absent): `qgait imu` with the tutorial's settings, compared
/// with OpenSense's own gait2392 solution (the accuracy table on stdout, the joint-angle figure
/// `figures/imu_angles.png`, the README's), then `qgait gait` on the angles: the clinical
/// report in `gait/`.
fn imu_step(exe: &Path, root: &Path, out: &Path) -> anyhow::Result<()> {
    let shared = std::env::var_os("QGAIT_SHARED")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join("../shared"));
    let imu = shared.join("data/imu");
    let reference = imu.join("walking_gait2392_opensense_0-12s.sto");
    if !reference.is_file() {
        println!("\n==> IMU step skipped: {} not found", reference.display());
        return Ok(());
    }
    let s = |p: std::path::PathBuf| p.to_string_lossy().into_owned();
    qgait(
        exe,
        &[
            "imu",
            &s(imu.join("walking_orientations.sto")),
            "--calibration",
            &s(imu.join("placement_orientations.sto")),
            "--base-imu",
            "torso_imu",
            "--base-heading-axis",
            "z",
            "-o",
            &s(out.join("walking_angles.mot")),
            "--compare",
            &s(reference),
            "--figures",
            &s(out.join("figures")),
        ],
    )?;
    // The product's end result: the clinical gait report of that walk.
    let gait = out.join("gait");
    qgait(
        exe,
        &[
            "gait",
            &s(out.join("walking_angles.mot")),
            "--subject-id",
            "OpenSense tutorial subject",
            "--condition",
            "Xsens IMUs (OpenSense tutorial)",
            "-o",
            &s(gait.clone()),
        ],
    )?;
    println!(
        "
==> the clinical gait report of the IMU walk: {}",
        gait.join("report.html").display()
    );
    Ok(())
}

/// Runs the demo.
pub fn run_demo() -> anyhow::Result<ExitCode> {
    crate::toolchain::ensure()?;
    let root = repo_root();
    if !step(
        "firmware build, mps2-an386",
        &root.join("firmware"),
        &["build", "--release"],
        &[],
    )
    .ok
    {
        return Err(anyhow!("building the firmware failed"));
    }
    let exe = qgait_binary()?;
    let out = root.join(OUT);
    std::fs::create_dir_all(&out).map_err(|e| anyhow!("creating {}: {e}", out.display()))?;
    let frames = out.join("frames.csv");
    let log = out.join("hub.bin");
    let figures = out.join("figures");
    let (frames, log, figures) = (
        frames.to_string_lossy(),
        log.to_string_lossy(),
        figures.to_string_lossy(),
    );
    qgait(
        &exe,
        &[
            "emulate",
            "builtin:normal",
            "--verify",
            "--frames-csv",
            &frames,
            "--log",
            &log,
        ],
    )?;
    // The device's frames beside the host's f64 computation of the same gait.
    qgait(
        &exe,
        &[
            "report",
            &frames,
            "builtin:normal",
            "--label",
            "device (QEMU, f32)",
            "--label",
            "host (f64)",
            "-o",
            &figures,
        ],
    )?;
    imu_step(&exe, &root, &out)?;
    println!(
        "\ndemo: frames, hub log and figures in {}",
        out.canonicalize().unwrap_or(out).display()
    );
    Ok(ExitCode::SUCCESS)
}
