//! VQF is insensitive to the magnetic field's scale, so Xsens' normalised magnetometer units
//! fuse as µT do: a shared BROAD trial fused with its field in µT and divided by 44 (about
//! Xsens' normalisation of a 44 µT field to 1) gives the same orientations. Skips with a
//! printed reason when the shared data are absent.

use std::path::PathBuf;

use qgait_fusion::{fuse, read_csv, Mode};

#[test]
fn the_field_in_any_unit_gives_the_same_orientations() {
    let dir = std::env::var_os("QGAIT_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"))
        .join("data/broad");
    // Trial 34: a magnet attached next to the sensor (disturbance detection and the
    // acceptance of a new field both act on the field's norm).
    let path = dir.join("34_disturbed_attached_magnet_3cm.csv");
    if !path.is_file() {
        eprintln!("SKIPPED: {} not found (set QGAIT_SHARED)", path.display());
        return;
    }
    let rec = read_csv(&path).unwrap();
    let mut scaled = rec.clone();
    for m in scaled.mag.as_mut().unwrap() {
        *m = m.map(|c| c / 44.0);
    }
    let a = fuse(&rec, Mode::NineD, |_| {}).unwrap();
    let b = fuse(&scaled, Mode::NineD, |_| {}).unwrap();
    let worst = a
        .iter()
        .zip(&b)
        .map(|(p, q)| {
            let dot = (p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3]).abs();
            2.0 * dot.min(1.0).acos().to_degrees()
        })
        .fold(0.0, f64::max);
    eprintln!(
        "µT against µT/44 over {} samples: at most {worst:.2e}°",
        a.len()
    );
    assert!(worst < 1e-4, "{worst}° apart");
}
