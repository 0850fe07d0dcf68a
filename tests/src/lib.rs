#![doc = include_str!("../README.md")]

use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The workspace root (this package is `tests/` in it).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The `qgait` binary, built once per test process by cargo (a no-op when it is up to date) in
/// the profile of this test build and into the same target directory (no `--target`, which
/// would build everything again under a directory of its own): the system tests run the binary
/// exactly as a user does, from any state of the target directory.
pub fn qgait_bin() -> &'static std::path::Path {
    static BIN: OnceLock<PathBuf> = OnceLock::new();
    BIN.get_or_init(|| {
        escargot::CargoBuild::new()
            .manifest_path(root().join("Cargo.toml"))
            .package("qgait")
            .bin("qgait")
            .current_release()
            .run()
            .expect("cargo builds the qgait binary")
            .path()
            .to_path_buf()
    })
}

/// Runs the `qgait` binary with arguments.
pub fn qgait(args: &[&str]) -> Output {
    Command::new(qgait_bin())
        .args(args)
        .output()
        .expect("qgait runs")
}

/// stdout as text.
pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).expect("utf-8 stdout")
}

/// stderr as text.
pub fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).expect("utf-8 stderr")
}

/// `<workspace root>/../shared`, or `$QGAIT_SHARED`; `None` (with the reason printed) when absent.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared"));
    if dir.join("data/opensim/normal.mot").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "skipped: shared data not found at {} (set QGAIT_SHARED)",
            dir.display()
        );
        None
    }
}

/// Parses the CSV written by `qgait fk` (header, rows of numbers).
pub fn parse_fk_csv(text: &str) -> (String, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines.next().expect("header").to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    (header, rows)
}

/// The release firmware ELF (`QGAIT_FIRMWARE_ELF`, else the default build location), when it
/// and `qemu-system-arm` are there; `None` (with the reason printed) when either is missing.
pub fn firmware_elf() -> Option<PathBuf> {
    use qgait_emulate::{firmware, qemu};
    let root = root();
    let elf = std::env::var_os("QGAIT_FIRMWARE_ELF")
        .map(PathBuf::from)
        .unwrap_or_else(|| firmware::default_elf(&root));
    if !qemu::available() {
        eprintln!(
            "skipped: {} is not installed (cargo xtask test installs it)",
            qemu::QEMU
        );
        return None;
    }
    if !elf.is_file() {
        eprintln!(
            "skipped: no firmware at {} (build it: {}; cargo xtask test does)",
            elf.display(),
            firmware::build_command(&root)
        );
        return None;
    }
    Some(elf)
}

/// The firmware built with the cargo feature `feature` (its own target directory,
/// `qgait_emulate::firmware::feature_elf`), or the ELF the environment variable `env` names;
/// built (or brought up to date: cargo does nothing when it is) every time, so that a change of
/// the hub is never tested on an old build. `None` (the reason printed) without QEMU or a
/// build.
pub fn feature_firmware_elf(feature: &str, env: &str) -> Option<PathBuf> {
    use qgait_emulate::{firmware, qemu};
    if !qemu::available() {
        eprintln!("skipped: {} is not installed", qemu::QEMU);
        return None;
    }
    if let Some(p) = std::env::var_os(env) {
        return Some(PathBuf::from(p));
    }
    let root = root();
    eprintln!(
        "building {}",
        firmware::feature_elf(&root, feature).display()
    );
    match firmware::build_feature(&root, feature) {
        Ok(elf) => Some(elf),
        Err(e) => {
            eprintln!(
                "skipped: {e} (build it: {})",
                firmware::feature_build_command(&root, feature)
            );
            None
        }
    }
}

/// A fresh scratch directory for one test, `<temp>/qgait-<test>-<pid>-<name>`.
pub fn scratch(test: &str, name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("qgait-{test}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("a scratch directory");
    d
}

/// `../shared/data/imu` (OpenSense's tutorial recording); `None` (the reason printed) when
/// absent.
pub fn imu_dir() -> Option<PathBuf> {
    let dir = shared_dir()?.join("data/imu");
    if dir.join("walking_orientations.sto").is_file() {
        Some(dir)
    } else {
        eprintln!("skipped: {} has no walking_orientations.sto", dir.display());
        None
    }
}

/// Runs `qgait imu` on the tutorial recording in `dir` ([`run_imu`]).
pub fn run_imu_tutorial(dir: &std::path::Path, out: &std::path::Path, extra: &[&str]) {
    run_imu(
        &dir.join("walking_orientations.sto"),
        &dir.join("placement_orientations.sto"),
        out,
        extra,
    );
}

/// Runs `qgait imu` on the recording `walk` calibrated by `calibration` with the tutorial's
/// settings (base IMU `torso_imu`, heading axis z, the default sensor-to-OpenSim rotation) and
/// `extra` arguments, writing `out`; checks that it succeeds and prints no warning (the files
/// are well formed; units do not apply to quaternions).
pub fn run_imu(
    walk: &std::path::Path,
    calibration: &std::path::Path,
    out: &std::path::Path,
    extra: &[&str],
) {
    let mut args = vec![
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        calibration.to_str().unwrap(),
        "--base-imu",
        "torso_imu",
        "--base-heading-axis",
        "z",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = qgait(&args);
    assert!(o.status.success(), "qgait imu failed: {}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}
