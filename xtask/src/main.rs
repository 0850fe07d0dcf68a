//! Developer tasks of qgait (`cargo xtask <command>` from the repository root).
//!
//! - `demo`: installs the firmware target and QEMU if missing, builds the release firmware, runs
//!   it under QEMU on the built-in normal gait, verifies every frame and draws them (`out/demo`).
//! - `test`: every test suite — host workspace, hub host tests, firmware builds for both
//!   boards, the firmware's RAM bound (static RAM plus the stack bound of [`stack_bound`]
//!   within 8 KiB), on-target tests, the UART end-to-end session and the 100,000-sample
//!   recording under QEMU — then a summary.
//! - `qemu-run ELF`: the firmware's cargo runner (firmware/.cargo/config.toml): runs `ELF` on
//!   QEMU mps2-an386, decodes its defmt logs, exits with QEMU's status. The application ELF
//!   (`qgait-firmware`) gets the end-to-end UART session of [`session`]; any other ELF (the
//!   on-target tests) runs until it exits.
//! - `footprint`: flash and static RAM of the release builds of both boards, the peak stack
//!   measured under QEMU, and an upper bound of the stack from the disassembly
//!   ([`stack_bound`]).

mod bench;
mod cargo;
mod demo;
mod elf_size;
mod footprint;
mod gait;
mod qemu;
mod session;
mod stack_bound;
mod test;
mod toolchain;

use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: cargo xtask <command>
  demo                 the firmware under QEMU on the built-in gait: frames decoded, verified, drawn into out/demo
  test                 run every test suite (host, firmware builds, QEMU, end-to-end) and summarise
  qemu-run ELF [ARGS]  run a firmware ELF under QEMU mps2-an386 with decoded defmt logs
  footprint            flash, static RAM, peak stack and stack bound of the release firmware
  bench [--no-host] [--no-footprint] [--no-large] [--large-only]
                       every benchmark figure (device, footprint, host), one `NAME VALUE` line each";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("test") => test::run(),
        Some("demo") => demo::run_demo(),
        Some("footprint") => footprint::run(),
        Some("bench") => bench::run(&args[1..]),
        Some("qemu-run") => match args.get(1) {
            Some(elf) => qemu::run_elf(&PathBuf::from(elf)),
            None => Err(format!("qemu-run needs the ELF path\n{USAGE}")),
        },
        _ => Err(USAGE.to_string()),
    };
    match result {
        Ok(code) => code,
        Err(message) => {
            eprintln!("xtask: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The repository root (xtask's parent directory).
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}
