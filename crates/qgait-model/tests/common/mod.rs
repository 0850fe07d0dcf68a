//! Helpers shared by the integration tests (included with `mod common;`).
#![allow(dead_code)]

use std::path::PathBuf;

/// `<workspace root>/../shared`, or `$QGAIT_SHARED`; `None` (with the reason printed) when absent.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"));
    if dir.join("data/opensim/normal.mot").is_file() {
        Some(dir)
    } else {
        eprintln!(
            "skipped: shared data not found at {} (set QGAIT_SHARED)",
            dir.display()
        );
        None
    }
}

/// Parses a CSV of a header and rows of numbers (OpenSim's reference files, `qgait fk`'s CSV).
pub fn parse_fk_csv(text: &str) -> (String, Vec<Vec<f64>>) {
    let mut lines = text.lines();
    let header = lines.next().expect("header").to_string();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    (header, rows)
}
