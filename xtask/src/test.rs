//! `cargo xtask test`: every suite in order, then one summary.

use std::process::ExitCode;

use qgait_emulate::firmware::default_elf;

use crate::cargo::{firmware_runner_env, step, Step};
use crate::repo_root;

/// The budget step of the ELF that `build` built, or why it did not run.
fn budget(build: &Step, name: &str, elf: &std::path::Path) -> Step {
    if build.ok {
        crate::stack_bound::budget_step(name, elf)
    } else {
        Step {
            name: name.into(),
            ok: false,
            summaries: vec!["not run: the firmware did not build".into()],
            seconds: 0.0,
        }
    }
}

/// Runs the suites; fails if any did.
pub fn run() -> anyhow::Result<ExitCode> {
    crate::toolchain::ensure()?;
    let root = repo_root();
    let firmware = root.join("firmware");
    let runner = [firmware_runner_env()?];
    // The firmware is built first: the host workspace tests include the end-to-end tests
    // (tests/e2e_qemu.rs), which run this ELF under QEMU.
    let mps2 = step(
        "firmware build, mps2-an386",
        &firmware,
        &["build", "--release"],
        &[],
    );
    let elf_path = default_elf(&root);
    let elf = [("QGAIT_FIRMWARE_ELF", elf_path.display().to_string())];
    // Flash within 32 KiB and static RAM plus the stack bound within 8 KiB (issue 8's target),
    // for the default build and the one with imported chains (issue 17's).
    let default_budget = budget(&mps2, "budget, default build", &elf_path);
    // In the directory tests/e2e_chain.rs builds it in: one build for both.
    let chain_elf = firmware.join("target/chain/thumbv7em-none-eabihf/release/qgait-firmware");
    let chain = step(
        "firmware build, mps2-an386, chain",
        &firmware,
        &["build", "--release", "--features", "chain"],
        &[(
            "CARGO_TARGET_DIR",
            firmware.join("target/chain").display().to_string(),
        )],
    );
    let chain_budget = budget(&chain, "budget, chain build", &chain_elf);
    // The IMU node (its own binary, `--features node`): within the same 32 KiB / 8 KiB.
    let node = step(
        "firmware build, node, mps2-an386",
        &firmware,
        &qgait_emulate::firmware::NODE_BUILD_ARGS,
        &[],
    );
    let node_elf = qgait_emulate::firmware::node_elf(&root);
    let node_budget = budget(&node, "budget, node", &node_elf);
    // The UART session runs the `qgait` binary the host workspace step builds (the system
    // tests build it in the test profile), not a release build of its own.
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let session_qgait = (
        crate::cargo::QGAIT_BIN,
        target.join("debug/qgait").display().to_string(),
    );
    let steps: Vec<Step> = vec![
        mps2,
        default_budget,
        chain,
        chain_budget,
        node,
        node_budget,
        step(
            "node on-target tests under QEMU",
            &firmware,
            &[
                "test",
                "--release",
                "--features",
                "node",
                "--test",
                "node_on_target",
            ],
            &runner,
        ),
        // Every crate of the root workspace, the hub's host tests and scenario checks included.
        step(
            "host workspace tests",
            &root,
            &["test", "--workspace"],
            &elf,
        ),
        // The protocol crate as the default hub links it: without `orientation` and `chain`
        // (which the workspace turns on), so `decode_hub_message` reports those messages
        // undecoded.
        step(
            "protocol tests, the default hub's decoders",
            &root,
            &["test", "-p", "qgait-proto"],
            &elf,
        ),
        // The hub's raw input (feature `raw`, which no workspace crate turns on).
        step(
            "hub raw input tests",
            &root,
            &[
                "test",
                "-p",
                "qgait-hub",
                "--features",
                "raw",
                "--test",
                "raw_input",
            ],
            &elf,
        ),
        step(
            "firmware build, nrf52840",
            &firmware,
            &[
                "build",
                "--release",
                "--no-default-features",
                "--features",
                "nrf52840",
            ],
            &[],
        ),
        // The wearable's build with every option (imported chains, the IMU input): beyond the
        // 32 KiB / 8 KiB budget, within the nRF52840's 1 MiB / 256 KiB (BENCHMARKS.md).
        step(
            "firmware build, nrf52840, chain + imu",
            &firmware,
            &[
                "build",
                "--release",
                "--no-default-features",
                "--features",
                "nrf52840,chain,imu",
            ],
            &[],
        ),
        step(
            "on-target tests under QEMU",
            &firmware,
            &["test", "--release"],
            &runner,
        ),
        step(
            "UART session under QEMU",
            &firmware,
            &["run", "--release"],
            &[runner[0].clone(), session_qgait],
        ),
    ];
    let steps: Vec<Step> = steps
        .into_iter()
        .chain(lint_steps(&root, &firmware))
        .collect();
    println!("\n==> summary");
    for s in &steps {
        println!(
            "{:<34} {:<6} {:>5.0} s",
            s.name,
            if s.ok { "ok" } else { "FAILED" },
            s.seconds
        );
        for line in &s.summaries {
            println!("    {line}");
        }
    }
    let failed = steps.iter().filter(|s| !s.ok).count();
    let total: f64 = steps.iter().map(|s| s.seconds).sum();
    println!(
        "{} of {} steps passed in {:.0} s",
        steps.len() - failed,
        steps.len(),
        total
    );
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

/// Formatting, lints and docs, in both workspaces: `cargo fmt --check`, clippy on every target
/// and `cargo doc` with warnings denied (the root workspace on the host, the hub and its checks
/// included; the firmware for its own target, its on-target tests included).
fn lint_steps(root: &std::path::Path, firmware: &std::path::Path) -> Vec<Step> {
    const DENY: [&str; 2] = ["--", "-Dwarnings"];
    let clippy = |extra: &[&'static str]| -> Vec<&'static str> {
        let mut args = vec!["clippy"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&DENY);
        args
    };
    vec![
        step(
            "format, host workspace",
            root,
            &["fmt", "--all", "--check"],
            &[],
        ),
        step(
            "format, firmware workspace",
            firmware,
            &["fmt", "--all", "--check"],
            &[],
        ),
        step(
            "clippy, host workspace",
            root,
            &clippy(&["--workspace", "--all-targets"]),
            &[],
        ),
        step(
            "clippy, hub with raw input",
            root,
            &clippy(&["-p", "qgait-hub", "--features", "raw", "--all-targets"]),
            &[],
        ),
        step(
            "clippy, firmware",
            firmware,
            &clippy(&["--all-targets"]),
            &[],
        ),
        step(
            "clippy, firmware, node",
            firmware,
            &clippy(&["--all-targets", "--features", "node"]),
            &[],
        ),
        step(
            "clippy, firmware, raw",
            firmware,
            &clippy(&["--all-targets", "--features", "imu,raw"]),
            &[],
        ),
        // The wearable's board (its UART on the nRF52840's PAC), with every option it builds
        // with.
        step(
            "clippy, firmware, nrf52840",
            firmware,
            &clippy(&[
                "--all-targets",
                "--no-default-features",
                "--features",
                "nrf52840,chain,imu",
            ]),
            &[],
        ),
        // The crate docs (each crate's README among them) with their links resolved.
        step(
            "docs, host workspace",
            root,
            &["doc", "--workspace", "--no-deps"],
            &[("RUSTDOCFLAGS", "-Dwarnings".to_string())],
        ),
        step(
            "docs, firmware",
            firmware,
            &["doc", "--no-deps"],
            &[("RUSTDOCFLAGS", "-Dwarnings".to_string())],
        ),
    ]
}
