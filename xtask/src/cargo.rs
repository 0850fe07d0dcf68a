//! Running cargo as a step of `cargo xtask test`, echoing its output and keeping the summary
//! lines (libtest's `test result:`, the on-target `N passed, M failed`, the UART session's).

use anyhow::anyhow;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::thread;

/// One finished step.
pub struct Step {
    /// What the step was.
    pub name: String,
    /// Whether cargo succeeded.
    pub ok: bool,
    /// Summary lines seen in its output.
    pub summaries: Vec<String>,
    /// How long it took (wall clock), shown in the summary so each step's share of CI's time
    /// is visible.
    pub seconds: f64,
}

/// The firmware's cargo runner for steps started from here: this very executable, so the
/// firmware's own runner command (which builds xtask for the host first) is not needed.
pub fn firmware_runner_env() -> anyhow::Result<(&'static str, String)> {
    let exe = std::env::current_exe().map_err(|e| anyhow!("locating xtask: {e}"))?;
    Ok((
        "CARGO_TARGET_THUMBV7EM_NONE_EABIHF_RUNNER",
        format!("{} qemu-run", exe.display()),
    ))
}

fn is_summary(line: &str) -> bool {
    let on_target = {
        let words: Vec<&str> = line.split(' ').collect();
        words.len() == 4
            && words[1] == "passed,"
            && words[3] == "failed"
            && words[0].parse::<u32>().is_ok()
            && words[2].parse::<u32>().is_ok()
    };
    on_target || line.starts_with("test result:") || line.starts_with("uart session: ")
}

/// `cargo ARGS` in `dir`, all of its output to stderr.
pub fn cargo(dir: &Path, args: &[&str]) -> anyhow::Result<()> {
    eprintln!("==> cargo {} (in {})", args.join(" "), dir.display());
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::from(std::io::stderr()))
        .status()
        .map_err(|e| anyhow!("starting cargo: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(anyhow!("cargo {} failed", args.join(" ")))
    }
}

/// The environment variable naming a `qgait` binary to run instead of building the release
/// one: `cargo xtask test` points it at the binary its host workspace step has just built, so
/// the UART session does not build the whole CLI a second time in another profile.
pub const QGAIT_BIN: &str = "QGAIT_BIN";

/// Builds the release `qgait` binary (cargo's output on stderr) and returns its path, or the
/// binary [`QGAIT_BIN`] names when that file exists: the tasks that need the CLI's work
/// (packets of the built-in gait, hub configurations, `emulate`, `verify`, figures) run it
/// rather than link the `qgait` library.
pub fn qgait_binary() -> anyhow::Result<PathBuf> {
    if let Some(exe) = std::env::var_os(QGAIT_BIN).map(PathBuf::from) {
        if exe.is_file() {
            return Ok(exe);
        }
    }
    let root = crate::repo_root();
    cargo(
        &root,
        &["build", "--release", "-p", "qgait", "--bin", "qgait"],
    )?;
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    Ok(target.join("release/qgait"))
}

/// Runs `cargo ARGS` in `dir` with extra environment `env`, streaming its output.
pub fn step(name: &str, dir: &Path, args: &[&str], env: &[(&str, String)]) -> Step {
    let started = std::time::Instant::now();
    println!(
        "\n==> {name}: cargo {} (in {})",
        args.join(" "),
        display(dir)
    );
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = match cmd.spawn() {
        Ok(c) => c,
        Err(e) => {
            eprintln!("xtask: cannot start cargo: {e}");
            return Step {
                name: name.into(),
                ok: false,
                summaries: Vec::new(),
                seconds: started.elapsed().as_secs_f64(),
            };
        }
    };
    let (tx, rx) = mpsc::channel::<String>();
    let mut readers = Vec::new();
    if let Some(out) = child.stdout.take() {
        let tx = tx.clone();
        readers.push(thread::spawn(move || {
            for line in BufReader::new(out).lines().map_while(Result::ok) {
                println!("{line}");
                let _ = tx.send(line);
            }
        }));
    }
    if let Some(err) = child.stderr.take() {
        let tx = tx.clone();
        readers.push(thread::spawn(move || {
            for line in BufReader::new(err).lines().map_while(Result::ok) {
                eprintln!("{line}");
                let _ = tx.send(line);
            }
        }));
    }
    drop(tx);
    let summaries: Vec<String> = rx.iter().filter(|l| is_summary(l)).collect();
    for r in readers {
        let _ = r.join();
    }
    let ok = child.wait().is_ok_and(|s| s.success());
    Step {
        name: name.into(),
        ok,
        summaries,
        seconds: started.elapsed().as_secs_f64(),
    }
}

fn display(dir: &Path) -> String {
    dir.canonicalize()
        .unwrap_or_else(|_| PathBuf::from(dir))
        .display()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::is_summary;

    #[test]
    fn summary_lines_are_recognised() {
        assert!(is_summary("21 passed, 0 failed"));
        assert!(is_summary("test result: ok. 3 passed; 0 failed; 0 ignored"));
        assert!(!is_summary("INFO  21 passed, 0 failed"));
        assert!(!is_summary("x passed, 0 failed"));
    }
}
