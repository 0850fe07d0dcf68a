//! An imported Rajagopal model on the hub, end to end under QEMU: OpenSense's
//! `Rajagopal2015_opensense.osim` imported by `qgait model import`, the firmware built with its
//! `chain` feature, `qgait emulate --model CHAIN.toml --verify` uploads the chain's table,
//! streams a crouch gait through the hub (its knees turned into Rajagopal's signs), and
//! recomputes every frame in `f64`: within 10 µm, nothing out of range, every knee flexed.
//!
//! Skips with a printed reason without `../shared` or QEMU. The chain firmware is built in
//! `firmware/target/chain` (a release build of its own, about a minute the first time).
use qgait_system_tests as common;

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
    // The crouch gait's knees (gait2392's signs) turned into Rajagopal's (flexion > 0), which
    // the hub checks in its mirrored range: nothing out of range.
    assert!(
        out.contains("samples_completed    60")
            && out.contains("config_rejected      0")
            && out.contains("out_of_range         0"),
        "{out}"
    );
    assert!(out.contains("verify: ok"), "{out}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let table = qgait_device::frames_csv::parse(&text, "frames.csv").unwrap();
    assert_eq!(table.seq, (0..60).collect::<Vec<u32>>());
    // Crouched: in every frame each knee is ahead of its hip–ankle line (sagittal plane), as a
    // flexed knee is (by 8 to 22 cm here); a hyperextended one would be behind it.
    for (seq, p) in table.seq.iter().zip(&table.points) {
        for leg in [0, 4] {
            let [hip, knee, ankle] = [p[leg], p[leg + 1], p[leg + 2]];
            let t = (knee[1] - hip[1]) / (ankle[1] - hip[1]);
            let ahead = knee[0] - (hip[0] + t * (ankle[0] - hip[0]));
            assert!(
                ahead > 0.05,
                "seq {seq}, leg {leg}: knee {ahead} m ahead of the line"
            );
        }
    }
    assert!(out.contains("chain"), "frames of the chain model: {out}");
}
