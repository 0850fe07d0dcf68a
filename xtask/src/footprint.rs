//! `cargo xtask footprint`: flash and static RAM of the release firmware for both boards, the
//! peak stack measured by stack painting during the UART session under QEMU, and an upper
//! bound of the stack from the disassembly.

use anyhow::anyhow;
use std::path::PathBuf;
use std::process::ExitCode;

use qgait_emulate::firmware::default_elf;

use crate::cargo::step;
use crate::elf_size::{footprint, Footprint};
use crate::repo_root;

fn elf_path() -> PathBuf {
    default_elf(&repo_root())
}

fn build_and_measure(name: &str, args: &[&str]) -> anyhow::Result<Footprint> {
    let s = step(
        &format!("firmware build, {name}"),
        &repo_root().join("firmware"),
        args,
        &[],
    );
    if !s.ok {
        return Err(anyhow!("building for {name} failed"));
    }
    let bytes =
        std::fs::read(elf_path()).map_err(|e| anyhow!("reading {}: {e}", elf_path().display()))?;
    footprint(&bytes)
}

/// Builds, measures and prints; `chain`, `imu`: the mps2-an386 firmware with those features;
/// `raw`: both boards' with it and those.
pub fn run(chain: bool, imu: bool, raw: bool) -> anyhow::Result<ExitCode> {
    let features: Vec<&str> = [("chain", chain), ("imu", imu), ("raw", raw)]
        .into_iter()
        .filter_map(|(f, on)| on.then_some(f))
        .collect();
    let nrf_features = if raw {
        format!("nrf52840,{}", features.join(","))
    } else {
        "nrf52840".to_owned()
    };
    let nrf = build_and_measure(
        "nrf52840",
        &[
            "build",
            "--release",
            "--no-default-features",
            "--features",
            &nrf_features,
        ],
    )?;
    let mps2 = if features.is_empty() {
        build_and_measure("mps2-an386", &["build", "--release"])?
    } else {
        let list = features.join(",");
        build_and_measure(
            &format!("mps2-an386 with {}", features.join(" and ")),
            &["build", "--release", "--features", &list],
        )?
    };
    let report = crate::session::run(&elf_path())?;
    let bound = crate::stack_bound::bound(&elf_path())?;
    println!(
        "\n{:<12} {:>10} {:>16} {:>16}",
        "board", "flash (B)", "static RAM (B)", "peak stack (B)"
    );
    let peak = report.stack_peak.map_or("?".into(), |p| p.to_string());
    println!(
        "{:<12} {:>10} {:>16} {:>16}",
        "mps2-an386", mps2.flash, mps2.static_ram, peak
    );
    println!(
        "{:<12} {:>10} {:>16} {:>16}",
        "nrf52840", nrf.flash, nrf.static_ram, "(not run)"
    );
    println!(
        "\nmps2-an386 stack bound (disassembly): {} bytes, RAM bound {} bytes; deepest path from Reset:",
        bound.bytes,
        mps2.static_ram + bound.bytes
    );
    for (function, frame) in &bound.main_path {
        println!("  {frame:>6}  {function}");
    }
    for (handler, depth) in &bound.handlers {
        println!("  handler {handler}: {depth} bytes + the exception frame");
    }
    Ok(if report.passed() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// `cargo xtask footprint --node`: the IMU node's flash and static RAM on both boards and its
/// stack bound from the disassembly (its peak stack is logged by the node under `qgait emulate
/// --node`).
pub fn run_node() -> anyhow::Result<ExitCode> {
    let node_elf = qgait_emulate::firmware::node_elf(&repo_root());
    let measure = |name: &str, args: &[&str]| -> anyhow::Result<Footprint> {
        let s = step(
            &format!("node build, {name}"),
            &repo_root().join("firmware"),
            args,
            &[],
        );
        if !s.ok {
            return Err(anyhow!("building the node for {name} failed"));
        }
        let bytes =
            std::fs::read(&node_elf).map_err(|e| anyhow!("reading {}: {e}", node_elf.display()))?;
        footprint(&bytes)
    };
    let node = ["--features", "node", "--bin", "qgait-node"];
    let nrf = measure(
        "nrf52840",
        &[
            &["build", "--release", "--no-default-features"][..],
            &node[..],
            &["--features", "nrf52840"][..],
        ]
        .concat(),
    )?;
    let mps2 = measure(
        "mps2-an386",
        &[&["build", "--release"][..], &node[..]].concat(),
    )?;
    let bound = crate::stack_bound::bound(&node_elf)?;
    println!(
        "\n{:<12} {:>10} {:>16} {:>16}",
        "node board", "flash (B)", "static RAM (B)", "RAM bound (B)"
    );
    println!(
        "{:<12} {:>10} {:>16} {:>16}",
        "mps2-an386",
        mps2.flash,
        mps2.static_ram,
        mps2.static_ram + bound.bytes
    );
    println!(
        "{:<12} {:>10} {:>16} {:>16}",
        "nrf52840", nrf.flash, nrf.static_ram, "(not run)"
    );
    println!(
        "\nmps2-an386 stack bound (disassembly): {} bytes; deepest path from Reset:",
        bound.bytes
    );
    for (function, frame) in &bound.main_path {
        println!("  {frame:>6}  {function}");
    }
    for (handler, depth) in &bound.handlers {
        println!("  handler {handler}: {depth} bytes + the exception frame");
    }
    let fits = |f: &Footprint| f.flash <= 32 * 1024;
    Ok(
        if fits(&mps2) && fits(&nrf) && mps2.static_ram + bound.bytes <= 8 * 1024 {
            ExitCode::SUCCESS
        } else {
            eprintln!("the node is over its 32 KiB / 8 KiB budget");
            ExitCode::FAILURE
        },
    )
}
