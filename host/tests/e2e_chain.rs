//! An imported Rajagopal model on the hub, end to end under QEMU: OpenSense's
//! `Rajagopal2015_opensense.osim` imported by `qgait model import`, the firmware built with its
//! `chain` feature, `qgait emulate --model CHAIN.toml --verify` uploads the chain in parts,
//! streams a gait through the hub, and recomputes every frame in `f64`: within 10 µm.
//!
//! Skips with a printed reason without `../shared` or QEMU. The chain firmware is built in
//! `firmware/target/chain` (a release build of its own, about a minute the first time).
mod common;

use std::path::PathBuf;
use std::process::Command;

use common::{qgait, shared_dir, stderr, stdout};

/// The release firmware with chain models, built if missing or stale (cargo decides).
fn chain_firmware() -> Option<PathBuf> {
    use qgait_emulate::qemu;
    if !qemu::available() {
        eprintln!("skipped: {} is not installed", qemu::QEMU);
        return None;
    }
    let firmware = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../firmware");
    let target = firmware.join("target/chain");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(&firmware)
        .args(["build", "--release", "--features", "chain"])
        .env("CARGO_TARGET_DIR", &target)
        .status()
        .expect("cargo runs");
    assert!(status.success(), "building the chain firmware failed");
    Some(target.join("thumbv7em-none-eabihf/release/qgait-firmware"))
}

#[test]
fn imported_rajagopal_on_the_hub_is_within_10_micrometres_of_the_host() {
    let Some(shared) = shared_dir() else { return };
    let osim = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    if !osim.is_file() {
        eprintln!("skipped: {} not found", osim.display());
        return;
    }
    let Some(elf) = chain_firmware() else { return };
    let dir = tempfile::tempdir().unwrap();
    let chain = dir.path().join("rajagopal.toml");
    let o = qgait(&[
        "model",
        "import",
        "-q",
        osim.to_str().unwrap(),
        "-o",
        chain.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = dir.path().join("frames.csv");
    let o = qgait(&[
        "emulate",
        "builtin:crouch=0.5,rows=60",
        "--model",
        chain.to_str().unwrap(),
        "--verify",
        "--tol-um",
        "10",
        "--elf",
        elf.to_str().unwrap(),
        "--frames-csv",
        csv.to_str().unwrap(),
    ]);
    let (out, err) = (stdout(&o), stderr(&o));
    println!("{out}");
    assert!(o.status.success(), "{out}{err}");
    assert!(
        out.contains("samples_completed    60") && out.contains("config_rejected      0"),
        "{out}"
    );
    assert!(out.contains("verify: ok"), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let table = qgait::device::frames_csv::parse(&text, "frames.csv").unwrap();
    assert_eq!(table.seq, (0..60).collect::<Vec<u32>>());
    assert!(out.contains("chain"), "frames of the chain model: {out}");
}
