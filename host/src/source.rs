//! Where a motion comes from: a `.mot`/`.sto` path, or a `builtin:` spec (see [`crate::builtin`]).

use std::path::Path;

use crate::builtin::{self, BuiltinSpec};
use crate::mot::{MotionTable, Warning};

/// Prefix that selects the built-in gait generator instead of a file.
pub const BUILTIN_PREFIX: &str = "builtin:";

/// Loads a motion from a path or a `builtin:` spec.
pub fn load_motion(spec: &str) -> anyhow::Result<(MotionTable, Vec<Warning>)> {
    if let Some(rest) = spec.strip_prefix(BUILTIN_PREFIX) {
        let spec = BuiltinSpec::parse(rest).map_err(anyhow::Error::msg)?;
        Ok((builtin::generate(&spec), Vec::new()))
    } else {
        Ok(MotionTable::read(Path::new(spec))?)
    }
}

/// A short label for a motion spec: the file stem, or the spec itself for `builtin:`.
pub fn default_label(spec: &str) -> String {
    if spec.starts_with(BUILTIN_PREFIX) {
        spec.to_string()
    } else {
        Path::new(spec)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| spec.to_string())
    }
}
