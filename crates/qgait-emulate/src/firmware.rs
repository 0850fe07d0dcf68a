//! Finding the hub firmware's ELF, and building it when it is missing.

use crate::EmulateError;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The firmware's target triple.
pub const TARGET: &str = "thumbv7em-none-eabihf";

/// The repository root: the first directory from the current one upwards that has
/// `firmware/Cargo.toml`, else the one this crate was built from.
pub fn repo_root() -> PathBuf {
    if let Ok(cwd) = std::env::current_dir() {
        for dir in cwd.ancestors() {
            if dir.join("firmware/Cargo.toml").is_file() {
                return dir.to_path_buf();
            }
        }
    }
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Where `cargo build --release` in `firmware/` puts the hub's ELF: under `$CARGO_TARGET_DIR`
/// when it is set, else `firmware/target`.
pub fn default_elf(root: &Path) -> PathBuf {
    release_elf(&target_dir(root))
}

/// The firmware's target directory: `$CARGO_TARGET_DIR` when it is set, else
/// `firmware/target`.
fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("firmware/target"))
}

/// The release hub ELF cargo writes under the target directory `target`.
fn release_elf(target: &Path) -> PathBuf {
    target.join(TARGET).join("release/qgait-firmware")
}

/// Where the firmware with the IMU orientation input (its cargo feature `imu`) is built: its
/// own target directory (`firmware/target/imu`, or `imu` under `$CARGO_TARGET_DIR`), so that
/// it never replaces the default build.
pub fn imu_elf(root: &Path) -> PathBuf {
    feature_elf(root, "imu")
}

/// The command that builds the firmware with the IMU orientation input, for messages.
pub fn imu_build_command(root: &Path) -> String {
    feature_build_command(root, "imu")
}

/// Builds the release firmware with the IMU orientation input ([`imu_elf`]).
pub fn build_imu(root: &Path) -> Result<PathBuf, EmulateError> {
    build_feature(root, "imu")
}

/// Where the firmware with the cargo feature `feature` is kept: its own directory
/// (`firmware/target/<feature>`, or `<feature>` under `$CARGO_TARGET_DIR`), so that it never
/// replaces the default build (`imu`; `velocity`, the points' velocities).
pub fn feature_elf(root: &Path, feature: &str) -> PathBuf {
    release_elf(&target_dir(root).join(feature))
}

/// The target directory every feature set is built in (`firmware/target/features`, or
/// `features` under `$CARGO_TARGET_DIR`): their common dependencies are compiled once, and
/// cargo writes the ELF of the feature set it last built, which [`build_feature`] copies out.
fn features_target_dir(root: &Path) -> PathBuf {
    target_dir(root).join("features")
}

/// The command that builds the firmware with `feature`, for messages.
pub fn feature_build_command(root: &Path, feature: &str) -> String {
    format!(
        "cd {} && cargo build --release --features {feature} --target-dir {} && cp {} {}",
        root.join("firmware").display(),
        features_target_dir(root).display(),
        release_elf(&features_target_dir(root)).display(),
        feature_elf(root, feature).display()
    )
}

/// Builds the release firmware with `feature` ([`feature_elf`]; cargo does nothing when it is
/// up to date): in the shared `features_target_dir`, then copied to the feature's own path.
/// One build at a time, across processes (a lock file there), so that no other feature set's
/// ELF is copied.
pub fn build_feature(root: &Path, feature: &str) -> Result<PathBuf, EmulateError> {
    let shared = features_target_dir(root);
    std::fs::create_dir_all(&shared).map_err(EmulateError::io("creating a target directory"))?;
    let lock_file = std::fs::File::create(shared.join("qgait-build.lock"))
        .map_err(EmulateError::io("creating the build lock"))?;
    let mut lock = fd_lock::RwLock::new(lock_file);
    let _turn = lock
        .write()
        .map_err(EmulateError::io("waiting for the build lock"))?;
    let built = cargo_build(
        root,
        &[
            "build".as_ref(),
            "--release".as_ref(),
            "--features".as_ref(),
            feature.as_ref(),
            "--target-dir".as_ref(),
            shared.as_os_str(),
        ],
        release_elf(&shared),
        || feature_build_command(root, feature),
    )?;
    let elf = feature_elf(root, feature);
    if let Some(dir) = elf.parent() {
        std::fs::create_dir_all(dir).map_err(EmulateError::io("creating a target directory"))?;
    }
    // Through a temporary file, so that a reader never sees half an ELF.
    let partial = elf.with_extension("partial");
    std::fs::copy(&built, &partial).map_err(EmulateError::io("copying the ELF"))?;
    std::fs::rename(&partial, &elf).map_err(EmulateError::io("copying the ELF"))?;
    Ok(elf)
}

/// Runs `cargo ARGS` in `firmware/` (output on stderr); `elf`, which it must make, on success.
fn cargo_build(
    root: &Path,
    args: &[&OsStr],
    elf: PathBuf,
    command: impl FnOnce() -> String,
) -> Result<PathBuf, EmulateError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = Command::new(cargo)
        .args(args)
        .current_dir(root.join("firmware"))
        .status()
        .map_err(EmulateError::io("starting cargo"))?;
    if !status.success() {
        return Err(EmulateError::BuildFailed {
            status,
            command: command(),
        });
    }
    if elf.is_file() {
        Ok(elf)
    } else {
        Err(EmulateError::BuildProducedNothing(elf))
    }
}

/// `elf` if given (it must exist), else `path`, built first by `build` (`what` it is, for the
/// message) if it is missing and `firmware/` is there.
fn locate_or_build(
    elf: Option<&Path>,
    path: PathBuf,
    what: &str,
    build: impl FnOnce(&Path) -> Result<PathBuf, EmulateError>,
) -> Result<PathBuf, EmulateError> {
    if let Some(p) = elf {
        return if p.is_file() {
            Ok(p.to_path_buf())
        } else {
            Err(EmulateError::NoElf(p.to_path_buf()))
        };
    }
    if path.is_file() {
        return Ok(path);
    }
    let root = repo_root();
    if !root.join("firmware/Cargo.toml").is_file() {
        return Err(EmulateError::NothingToBuild(path));
    }
    eprintln!("{} is missing: building {what}", path.display());
    build(&root)
}

/// Where the IMU node's ELF is built (`cargo build --release --features node --bin
/// qgait-node` in `firmware/`): beside the hub's.
pub fn node_elf(root: &Path) -> PathBuf {
    default_elf(root).with_file_name("qgait-node")
}

/// cargo's arguments, in `firmware/`, that build the IMU node ([`node_elf`]).
pub const NODE_BUILD_ARGS: [&str; 6] = [
    "build",
    "--release",
    "--features",
    "node",
    "--bin",
    "qgait-node",
];

/// The command that builds the IMU node, for messages.
pub fn node_build_command(root: &Path) -> String {
    format!(
        "cd {} && cargo {}",
        root.join("firmware").display(),
        NODE_BUILD_ARGS.join(" ")
    )
}

/// The IMU node's ELF to run: `elf` if given (it must exist), else [`node_elf`], built first if
/// it is missing and `firmware/` is there.
pub fn locate_node(elf: Option<&Path>) -> Result<PathBuf, EmulateError> {
    locate_or_build(elf, node_elf(&repo_root()), "the IMU node", build_node)
}

/// Builds the IMU node ([`node_elf`]; cargo does nothing when it is up to date).
pub fn build_node(root: &Path) -> Result<PathBuf, EmulateError> {
    cargo_build(
        root,
        &NODE_BUILD_ARGS.map(OsStr::new),
        node_elf(root),
        || node_build_command(root),
    )
}

/// The command that builds the firmware, for messages.
pub fn build_command(root: &Path) -> String {
    format!(
        "cd {} && cargo build --release   (needs `rustup target add {TARGET}`)",
        root.join("firmware").display()
    )
}

/// Builds the release firmware with cargo (output on stderr); its ELF ([`default_elf`]).
pub fn build(root: &Path) -> Result<PathBuf, EmulateError> {
    cargo_build(
        root,
        &["build", "--release"].map(OsStr::new),
        default_elf(root),
        || build_command(root),
    )
}

/// The ELF to run: `elf` if given (it must exist), else the default release build, built
/// first if it is missing and `firmware/` is there.
pub fn locate(elf: Option<&Path>) -> Result<PathBuf, EmulateError> {
    locate_or_build(elf, default_elf(&repo_root()), "the firmware", build)
}

/// `elf` if given (it must exist), else the firmware with the cargo features `features`
/// ([`feature_elf`]), built first if it is missing.
pub fn locate_feature(elf: Option<&Path>, features: &str) -> Result<PathBuf, EmulateError> {
    let root = repo_root();
    locate_or_build(
        elf,
        feature_elf(&root, features),
        &format!("the firmware with {features}"),
        |root| build_feature(root, features),
    )
}
