//! `qgait fk --derivatives` and `qgait imu-signals` against OpenSim 4.6, through the binary, on
//! `scripts/opensim_derivatives.py`'s analytic motion (crates/qgait-kernel/tests/data/derivatives/:
//! a 1 kHz `.mot` in degrees, a states `.sto` with the exact speeds, OpenSim's velocities,
//! accelerations from its exact velocities, and its `IMU` components' signals), on gait2392 and
//! on the imported Rajagopal 2015 model (../shared/data/opensim, skipped when absent):
//! - states file: point velocities within 1e-9 m/s, accelerations (the file's speeds
//!   differentiated) within 1e-2 m/s²;
//! - the 1 kHz `.mot`: velocities within 1e-4 m/s, accelerations within 1e-2 m/s²;
//! - `imu-signals` from the `.mot`: gyroscope within 1e-4 rad/s, accelerometer within
//!   1e-2 m/s², orientations within 1e-9; noise options change the signals by what they say.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use common::{qgait, scratch, shared_dir, stderr};

const POINTS: [&str; 8] = [
    "hip_r", "knee_r", "ankle_r", "toe_r", "hip_l", "knee_l", "ankle_l", "toe_l",
];

/// The script's IMUs, as PLACEMENT.toml.
const PLACEMENT: &str = r#"
[[imu]]
name = "pelvis_imu"
body = "pelvis"
translation = [-0.14, 0.03, 0.0]
orientation = [0.51, -0.70, 0.40]

[[imu]]
name = "femur_r_imu"
body = "femur_r"
translation = [0.02, -0.20, 0.06]
orientation = [0.10, 0.30, -0.20]

[[imu]]
name = "tibia_l_imu"
body = "tibia_l"
translation = [0.03, -0.15, -0.05]
orientation = [-0.30, 0.20, 0.60]

[[imu]]
name = "calcn_r_imu"
body = "calcn_r"
translation = [0.10, 0.05, 0.0]
orientation = [1.20, -0.40, 0.30]
"#;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../crates/qgait-kernel/tests/data/derivatives")
        .join(name)
}

/// A CSV of a header and numbers, rows keyed by time (to the microsecond).
struct Table {
    columns: HashMap<String, usize>,
    rows: Vec<Vec<f64>>,
}

impl Table {
    fn csv(text: &str) -> Self {
        let mut lines = text.lines();
        let columns = lines
            .next()
            .unwrap()
            .split(',')
            .enumerate()
            .map(|(i, c)| (c.to_string(), i))
            .collect();
        let rows = lines
            .filter(|l| !l.is_empty())
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        Self { columns, rows }
    }

    /// An `.sto` of `x,y,z` (or `w,x,y,z`) cells as columns `<name>_0, _1, ...`.
    fn sto(text: &str) -> Self {
        let mut lines = text.lines().skip_while(|l| *l != "endheader").skip(1);
        let labels: Vec<&str> = lines.next().unwrap().split('\t').collect();
        let mut columns = HashMap::from([("time".to_string(), 0)]);
        let rows: Vec<Vec<f64>> = lines
            .filter(|l| !l.is_empty())
            .map(|l| {
                let cells: Vec<&str> = l.split('\t').collect();
                let mut row = vec![cells[0].parse().unwrap()];
                for (label, cell) in labels[1..].iter().zip(&cells[1..]) {
                    for (k, v) in cell.split(',').enumerate() {
                        columns.insert(format!("{label}_{k}"), row.len());
                        row.push(v.parse().unwrap());
                    }
                }
                row
            })
            .collect();
        Self { columns, rows }
    }

    fn row_at(&self, t: f64) -> Option<&Vec<f64>> {
        self.rows.iter().find(|r| (r[0] - t).abs() < 1e-6)
    }

    fn get(&self, row: &[f64], column: &str) -> f64 {
        row[*self.columns.get(column).unwrap_or_else(|| panic!("no {column}"))]
    }
}

/// Runs `fk --derivatives` on `motion` and returns the largest velocity and acceleration
/// differences from OpenSim's (relative to the pelvis origin), over the reference rows the
/// motion covers.
fn fk_against_opensim(test: &str, model: &str, motion: &Path, reference: &Table) -> (f64, f64) {
    let out = scratch(test, "fk").join("out.csv");
    let o = qgait(&[
        "fk",
        motion.to_str().unwrap(),
        "--model",
        model,
        "--derivatives",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ours = Table::csv(&std::fs::read_to_string(&out).unwrap());
    let (mut v, mut a, mut compared) = (0.0f64, 0.0f64, 0);
    for r in &reference.rows {
        let Some(row) = ours.row_at(r[0]) else { continue };
        compared += 1;
        for p in POINTS {
            // OpenSim's name of the toe tip.
            let theirs = p.replace("toe_", "toetip_");
            for axis in ["x", "y", "z"] {
                let rv = reference.get(r, &format!("{theirs}_v{axis}"))
                    - reference.get(r, &format!("qd_pelvis_t{axis}"));
                let ra = reference.get(r, &format!("{theirs}_a{axis}"))
                    - reference.get(r, &format!("qdd_pelvis_t{axis}"));
                v = v.max((ours.get(row, &format!("{p}_v{axis}")) - rv).abs());
                a = a.max((ours.get(row, &format!("{p}_a{axis}")) - ra).abs());
            }
        }
    }
    assert!(compared >= 6, "{compared} reference rows in the motion");
    (v, a)
}

/// Runs `imu-signals` on `motion`; the largest gyroscope, accelerometer and orientation
/// differences from OpenSim's `IMU` components.
fn imu_against_opensim(test: &str, model: &str, motion: &Path, reference: &Table) -> [f64; 3] {
    let dir = scratch(test, "imu");
    let placement = scratch(test, "placement").join("placement.toml");
    std::fs::write(&placement, PLACEMENT).unwrap();
    let o = qgait(&[
        "imu-signals",
        motion.to_str().unwrap(),
        "--model",
        model,
        "--imus",
        placement.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |f: &str| Table::sto(&std::fs::read_to_string(dir.join(f)).unwrap());
    let (gyro, acc, orient) = (
        read("angular_velocity.sto"),
        read("linear_acceleration.sto"),
        read("orientations.sto"),
    );
    let mut worst = [0.0f64; 3];
    for r in &reference.rows {
        let (Some(g), Some(a), Some(q)) = (gyro.row_at(r[0]), acc.row_at(r[0]), orient.row_at(r[0]))
        else {
            continue;
        };
        for name in ["pelvis_imu", "femur_r_imu", "tibia_l_imu", "calcn_r_imu"] {
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                let rg = reference.get(r, &format!("{name}_gyro_{axis}"));
                let ra = reference.get(r, &format!("{name}_acc_{axis}"));
                worst[0] = worst[0].max((gyro.get(g, &format!("{name}_{k}")) - rg).abs());
                worst[1] = worst[1].max((acc.get(a, &format!("{name}_{k}")) - ra).abs());
            }
            // Orientation: the same rotation (q or -q).
            let ours: Vec<f64> = (0..4).map(|k| orient.get(q, &format!("{name}_{k}"))).collect();
            let theirs: Vec<f64> = ["w", "x", "y", "z"]
                .iter()
                .map(|c| reference.get(r, &format!("{name}_q{c}")))
                .collect();
            let dot: f64 = ours.iter().zip(&theirs).map(|(a, b)| a * b).sum();
            worst[2] = worst[2].max(1.0 - dot.abs());
        }
    }
    worst
}

fn check(model: &str, name: &str, test: &str) {
    let reference = Table::csv(
        &std::fs::read_to_string(fixture(&format!("{name}_reference.csv"))).unwrap(),
    );
    let (v, a) = fk_against_opensim(
        &format!("{test}_states"),
        model,
        &fixture(&format!("{name}_states.sto")),
        &reference,
    );
    println!("{name}, states .sto: velocities {v:.1e} m/s, accelerations {a:.1e} m/s^2");
    assert!(v < 1e-9 && a < 1e-2, "{v} {a}");
    let (v, a) = fk_against_opensim(
        &format!("{test}_mot"),
        model,
        &fixture(&format!("{name}.mot")),
        &reference,
    );
    println!("{name}, 1 kHz .mot: velocities {v:.1e} m/s, accelerations {a:.1e} m/s^2");
    assert!(v < 1e-4 && a < 1e-2, "{v} {a}");
    let [g, acc, q] = imu_against_opensim(test, model, &fixture(&format!("{name}.mot")), &reference);
    println!(
        "{name}, imu-signals from the 1 kHz .mot: gyroscope {g:.1e} rad/s, accelerometer {acc:.1e} m/s^2, orientation 1-|q.q'| {q:.1e}"
    );
    assert!(g < 1e-4 && acc < 1e-2 && q < 1e-9, "{g} {acc} {q}");
}

#[test]
fn gait2392_derivatives_and_imu_signals_are_opensims() {
    check("gait2392", "gait2392", "deriv_gait2392");
}

#[test]
fn rajagopal_derivatives_and_imu_signals_are_opensims() {
    let Some(shared) = shared_dir() else { return };
    let model = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    check(model.to_str().unwrap(), "rajagopal2015", "deriv_rajagopal");
}
