//! Test support: seeded random angles and a minimal reader of the shared OpenSim motions.
#![allow(dead_code)]

use std::path::PathBuf;

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// A seeded generator, so every run tests the same angle sets.
pub fn rng(seed: u64) -> SmallRng {
    SmallRng::seed_from_u64(seed)
}

/// `N` angles uniform in [-pi, pi].
pub fn random_angles<const N: usize>(rng: &mut SmallRng) -> [f64; N] {
    core::array::from_fn(|_| rng.random_range(-core::f64::consts::PI..=core::f64::consts::PI))
}

/// `../shared` next to the workspace, or `$QGAIT_SHARED`; `None` (with a printed reason) when
/// absent, so tests that need it skip.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"));
    if dir.join("data/opensim").is_dir() {
        Some(dir)
    } else {
        eprintln!(
            "SKIPPED: shared data not found at {} (set QGAIT_SHARED)",
            dir.display()
        );
        None
    }
}

/// One shared motion: file name, column names, rows of values as written (degrees, metres).
pub type Motion = (String, Vec<String>, Vec<Vec<f64>>);

/// The shared motions (`*.mot`), sorted by name.
pub fn shared_motions() -> Option<Vec<Motion>> {
    let dir = shared_dir()?.join("data/opensim");
    let mut out = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .ok()?
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .collect();
    names.sort();
    for path in names
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "mot"))
    {
        let text = std::fs::read_to_string(&path).unwrap();
        let mut lines = text.lines().skip_while(|l| l.trim() != "endheader").skip(1);
        let header: Vec<String> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(String::from)
            .collect();
        let rows: Vec<Vec<f64>> = lines
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
            .collect();
        out.push((
            path.file_name().unwrap().to_string_lossy().into_owned(),
            header,
            rows,
        ));
    }
    Some(out)
}

/// Column `name` of a motion, converted from degrees to radians.
pub fn column_rad(header: &[String], row: &[f64], name: &str) -> f64 {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    row[i].to_radians()
}
