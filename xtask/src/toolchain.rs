//! Making sure what the tests need is installed: the rustup target, clippy and rustfmt, and QEMU (installed when
//! missing: `rustup target add`, and `apt-get install qemu-system-arm` when running as root).

use anyhow::anyhow;
use std::process::{Command, Stdio};

use qgait_emulate::firmware::TARGET;
use qgait_emulate::qemu;

fn run(program: &str, args: &[&str]) -> anyhow::Result<()> {
    println!("==> {program} {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .status()
        .map_err(|e| anyhow!("starting {program}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(anyhow!("`{program} {}` failed ({status})", args.join(" ")))
    }
}

fn target_installed() -> bool {
    Command::new("rustup")
        .args(["target", "list", "--installed"])
        .stderr(Stdio::null())
        .output()
        .is_ok_and(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .any(|l| l.trim() == TARGET)
        })
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

fn components_installed() -> bool {
    Command::new("rustup")
        .args(["component", "list", "--installed"])
        .stderr(Stdio::null())
        .output()
        .is_ok_and(|o| {
            let list = String::from_utf8_lossy(&o.stdout);
            ["clippy", "rustfmt"]
                .iter()
                .all(|c| list.lines().any(|l| l.starts_with(c)))
        })
}

/// Installs the firmware target, the lint tools (clippy, rustfmt) and QEMU if they are missing.
pub fn ensure() -> anyhow::Result<()> {
    if !target_installed() {
        run("rustup", &["target", "add", TARGET])?;
    }
    if !components_installed() {
        run("rustup", &["component", "add", "clippy", "rustfmt"])?;
    }
    if crate::stack_bound::objdump().is_none() {
        // For the stack bound (`stack_bound`): Debian's llvm has llvm-objdump.
        if !is_root() {
            return Err(anyhow!("llvm-objdump is not installed and this is not root: install it (Debian/Ubuntu: `sudo apt-get install -y llvm`) and run again"));
        }
        run("apt-get", &["update"])?;
        run("apt-get", &["install", "-y", "llvm"])?;
    }
    if !qemu::available() {
        if !is_root() {
            return Err(anyhow!(
                "{} is not installed and this is not root: install it (Debian/Ubuntu: `sudo apt-get install -y qemu-system-arm`) and run again",
                qemu::QEMU
            ));
        }
        run("apt-get", &["update"])?;
        run("apt-get", &["install", "-y", "qemu-system-arm"])?;
        if !qemu::available() {
            return Err(anyhow!(
                "{} still does not start after installing it",
                qemu::QEMU
            ));
        }
    }
    Ok(())
}
