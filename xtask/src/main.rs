//! Developer tasks of qgait (`cargo xtask <command>` from the repository root).
//!
//! - `demo`: installs the firmware target and QEMU if missing, builds the release firmware, runs
//!   it under QEMU on the built-in normal gait, verifies every frame and draws them (`out/demo`).
//! - `test`: every test suite — host workspace, hub host tests, firmware builds for both
//!   boards, the firmware's RAM bound (static RAM plus the stack bound of [`stack_bound`]
//!   within 8 KiB), on-target tests and the UART end-to-end session under QEMU, formatting,
//!   lints and docs — then a summary with each step's time.
//! - `qemu-run ELF`: the firmware's cargo runner (firmware/.cargo/config.toml): runs `ELF` on
//!   QEMU mps2-an386, decodes its defmt logs, exits with QEMU's status. The application ELF
//!   (`qgait-firmware`) gets the end-to-end UART session of [`session`]; any other ELF (the
//!   on-target tests) runs until it exits.
//! - `footprint`: flash and static RAM of the release builds of both boards, the peak stack
//!   measured under QEMU, and an upper bound of the stack from the disassembly
//!   ([`stack_bound`]).
//!
//! xtask links the emulation harness (`qgait-emulate`), not the `qgait` library: what needs the
//! CLI's work runs the release `qgait` binary ([`cargo::qgait_binary`]).

mod bench;
mod cargo;
mod demo;
mod elf_size;
mod footprint;
mod qemu;
mod session;
mod stack_bound;
mod test;
mod toolchain;

use anyhow::anyhow;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Developer tasks of qgait.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask")]
struct Xtask {
    #[command(subcommand)]
    command: Task,
}

#[derive(Debug, Subcommand)]
enum Task {
    /// The firmware under QEMU on the built-in gait: frames decoded, verified, drawn into out/demo.
    Demo,
    /// Run every test suite (host, firmware builds, QEMU, end-to-end) and summarise.
    Test,
    /// Run a firmware ELF under QEMU mps2-an386 with decoded defmt logs (the firmware's cargo
    /// runner).
    QemuRun {
        /// The firmware ELF.
        elf: PathBuf,
        /// Arguments cargo passes after the ELF (not used).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Flash, static RAM, peak stack and stack bound of the release firmware.
    Footprint {
        /// The firmware with its `chain` feature (imported chains on the hub) instead.
        #[arg(long)]
        chain: bool,
        /// The firmware with its `imu` feature (the IMU orientation input) instead (with
        /// `--chain`: both).
        #[arg(long)]
        imu: bool,
        /// The firmware with its `raw` feature (raw IMU input fused on the hub; implies
        /// `imu`), on both boards.
        #[arg(long)]
        raw: bool,
        /// The IMU node (`qgait-node`, the firmware's `node` feature) instead of the hub.
        #[arg(long, conflicts_with_all = ["chain", "imu", "raw"])]
        node: bool,
    },
    /// Every benchmark figure (device, footprint, host), one `NAME VALUE` line each.
    Bench(bench::BenchArgs),
}

fn main() -> ExitCode {
    let result = match Xtask::parse().command {
        Task::Test => test::run(),
        Task::Demo => demo::run_demo(),
        Task::Footprint {
            chain,
            imu,
            raw,
            node,
        } => {
            if node {
                footprint::run_node()
            } else {
                footprint::run(chain, imu, raw)
            }
        }
        Task::Bench(args) => bench::run(&args),
        Task::QemuRun { elf, .. } => qemu::run_elf(&elf),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            eprintln!("xtask: {message:#}");
            ExitCode::FAILURE
        }
    }
}

/// A temporary directory, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    /// Creates `NAME-PID` in the system's temporary directory.
    fn new(name: &str) -> anyhow::Result<TempDir> {
        let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| anyhow!("{}: {e}", dir.display()))?;
        Ok(TempDir(dir))
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The repository root (xtask's parent directory).
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Task, clap::Error> {
        Xtask::try_parse_from(std::iter::once("xtask").chain(args.iter().copied()))
            .map(|x| x.command)
    }

    #[test]
    fn the_runner_takes_the_elf_and_ignores_what_follows() {
        let Ok(Task::QemuRun { elf, args }) = parse(&["qemu-run", "fw.elf", "--flag", "x"]) else {
            panic!("qemu-run with an ELF parses")
        };
        assert_eq!(
            (elf, args),
            (PathBuf::from("fw.elf"), vec!["--flag".into(), "x".into()])
        );
        assert!(parse(&["qemu-run"]).is_err(), "the ELF is required");
    }

    #[test]
    fn bench_flags_parse_and_unknown_ones_are_refused() {
        let Ok(Task::Bench(b)) = parse(&["bench", "--no-host", "--no-large"]) else {
            panic!("bench flags parse")
        };
        assert!(b.no_host && b.no_large && !b.no_footprint && !b.large_only);
        assert!(parse(&["bench", "--fast"]).is_err());
        assert!(parse(&["frobnicate"]).is_err());
    }
}
