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
        row[*self
            .columns
            .get(column)
            .unwrap_or_else(|| panic!("no {column}"))]
    }
}

/// Runs `qgait fk` on `motion` with `model` and the `extra` arguments: its CSV.
fn fk(test: &str, model: &str, motion: &Path, extra: &[&str]) -> Table {
    let out = scratch(test, "fk").join("out.csv");
    let mut args = vec!["fk", motion.to_str().unwrap(), "--model", model];
    args.extend_from_slice(extra);
    args.extend_from_slice(&["-o", out.to_str().unwrap()]);
    let o = qgait(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    Table::csv(&std::fs::read_to_string(&out).unwrap())
}

/// Runs `qgait imu-signals` on `motion` with `model` and the IMUs `placement` (TOML text):
/// its orientations, gyroscope and accelerometer.
fn imu_signals(test: &str, model: &str, motion: &Path, placement: &str) -> [Table; 3] {
    let (o, dir) = run_imu_signals(test, model, motion, placement);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |f: &str| Table::sto(&std::fs::read_to_string(dir.join(f)).unwrap());
    [
        read("orientations.sto"),
        read("angular_velocity.sto"),
        read("linear_acceleration.sto"),
    ]
}

/// Runs `qgait imu-signals` (the IMUs written to `placement.toml`): its output and directory.
fn run_imu_signals(
    test: &str,
    model: &str,
    motion: &Path,
    placement: &str,
) -> (std::process::Output, PathBuf) {
    let dir = scratch(test, "imu");
    let toml = scratch(test, "placement").join("placement.toml");
    std::fs::write(&toml, placement).unwrap();
    let o = qgait(&[
        "imu-signals",
        motion.to_str().unwrap(),
        "--model",
        model,
        "--imus",
        toml.to_str().unwrap(),
        "-o",
        dir.to_str().unwrap(),
    ]);
    (o, dir)
}

/// Runs `fk --derivatives` on `motion` and returns the largest velocity and acceleration
/// differences from OpenSim's (relative to the pelvis origin), over the reference rows the
/// motion covers.
fn fk_against_opensim(test: &str, model: &str, motion: &Path, reference: &Table) -> (f64, f64) {
    fk_against_opensim_where(test, model, motion, reference, |_| true)
}

/// [`fk_against_opensim`] over the reference rows whose time `at` accepts.
fn fk_against_opensim_where(
    test: &str,
    model: &str,
    motion: &Path,
    reference: &Table,
    at: impl Fn(f64) -> bool,
) -> (f64, f64) {
    let ours = fk(test, model, motion, &["--derivatives"]);
    let (mut v, mut a, mut compared) = (0.0f64, 0.0f64, 0);
    for r in &reference.rows {
        let Some(row) = ours.row_at(r[0]).filter(|_| at(r[0])) else {
            continue;
        };
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
    assert!(compared >= 4, "{compared} reference rows in the motion");
    (v, a)
}

/// Runs `imu-signals` on `motion`; the largest gyroscope, accelerometer and orientation
/// differences from OpenSim's `IMU` components.
fn imu_against_opensim(test: &str, model: &str, motion: &Path, reference: &Table) -> [f64; 3] {
    let [orient, gyro, acc] = imu_signals(test, model, motion, PLACEMENT);
    let mut worst = [0.0f64; 3];
    for r in &reference.rows {
        let (Some(g), Some(a), Some(q)) =
            (gyro.row_at(r[0]), acc.row_at(r[0]), orient.row_at(r[0]))
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
            let ours: Vec<f64> = (0..4)
                .map(|k| orient.get(q, &format!("{name}_{k}")))
                .collect();
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
    let reference =
        Table::csv(&std::fs::read_to_string(fixture(&format!("{name}_reference.csv"))).unwrap());
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
    let [g, acc, q] =
        imu_against_opensim(test, model, &fixture(&format!("{name}.mot")), &reference);
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

/// The same motion sampled at 100 Hz (every tenth row of the 1 kHz `.mot`): what a 100 Hz
/// recording gives (the reference rows include the first and last, one-sided, samples).
#[test]
fn a_100_hz_motion_is_within_its_stated_accuracy() {
    let reference =
        Table::csv(&std::fs::read_to_string(fixture("gait2392_reference.csv")).unwrap());
    let text = std::fs::read_to_string(fixture("gait2392.mot")).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    let header = lines.iter().position(|l| *l == "endheader").unwrap() + 2;
    let rows: Vec<&str> = lines.split_off(header).into_iter().step_by(10).collect();
    let n = format!("nRows={}", rows.len());
    let mut out: Vec<&str> = lines
        .iter()
        .map(|l| {
            if l.starts_with("nRows=") {
                n.as_str()
            } else {
                l
            }
        })
        .collect();
    out.extend(rows);
    let motion = scratch("deriv_100hz", "mot").join("gait2392_100hz.mot");
    std::fs::write(&motion, out.join("\n") + "\n").unwrap();
    let (v, a) = fk_against_opensim("deriv_100hz", "gait2392", &motion, &reference);
    let inside = |t: f64| t > 0.01 && t < 0.09;
    let (vi, ai) =
        fk_against_opensim_where("deriv_100hz_in", "gait2392", &motion, &reference, inside);
    println!(
        "gait2392, 100 Hz .mot: velocities {v:.1e} m/s, accelerations {a:.1e} m/s^2 (first and \
         last samples included); inside: {vi:.1e} m/s, {ai:.1e} m/s^2"
    );
    assert!(v < 1e-3 && a < 0.3, "{v} {a}");
    assert!(vi < 1e-4 && ai < 1e-2, "{vi} {ai}");
}

/// OpenSim's states files carry every muscle's states: they are passed over.
#[test]
fn other_states_are_passed_over() {
    let text = std::fs::read_to_string(fixture("gait2392_states.sto")).unwrap();
    let widened: Vec<String> = text
        .lines()
        .map(|l| {
            if l.starts_with("time\t") {
                format!("{l}\t/forceset/soleus_r/activation\t/forceset/soleus_r/fiber_length")
            } else if l.starts_with(|c: char| c.is_ascii_digit()) {
                format!("{l}\t0.05\t0.031")
            } else if let Some(n) = l.strip_prefix("nColumns=") {
                format!("nColumns={}", n.parse::<usize>().unwrap() + 2)
            } else {
                l.to_string()
            }
        })
        .collect();
    let dir = scratch("deriv_muscles", "in");
    let wide = dir.join("wide.sto");
    std::fs::write(&wide, widened.join("\n") + "\n").unwrap();
    let run = |motion: &Path, out: &str| {
        let out = dir.join(out);
        let o = qgait(&[
            "fk",
            motion.to_str().unwrap(),
            "--model",
            "gait2392",
            "--derivatives",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read_to_string(out).unwrap()
    };
    assert_eq!(
        run(&wide, "wide.csv"),
        run(&fixture("gait2392_states.sto"), "plain.csv")
    );
}

/// Noise and bias: the same seed gives the same signals; white noise of a stated deviation and
/// a constant bias show in the gyroscope as stated; the output rate takes every k-th row.
#[test]
fn imu_noise_bias_and_rate_are_as_stated() {
    let dir = scratch("deriv_noise", "in");
    let placement = dir.join("placement.toml");
    std::fs::write(&placement, PLACEMENT).unwrap();
    let motion = fixture("gait2392_states.sto");
    let run = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "imu-signals",
            motion.to_str().unwrap(),
            "--model",
            "gait2392",
            "--imus",
            placement.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = qgait(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        Table::sto(&std::fs::read_to_string(out.join("angular_velocity.sto")).unwrap())
    };
    let clean = run("clean", &[]);
    let noisy = [
        "--gyro-noise-std",
        "0.01",
        "--gyro-bias",
        "0.1,-0.2,0.3",
        "--seed",
        "7",
    ];
    let a = run("a", &noisy);
    let b = run("b", &noisy);
    assert_eq!(a.rows, b.rows);
    let mut diffs = [Vec::new(), Vec::new(), Vec::new()];
    for (c, n) in clean.rows.iter().zip(&a.rows) {
        for name in ["pelvis_imu", "femur_r_imu", "tibia_l_imu", "calcn_r_imu"] {
            for (k, d) in diffs.iter_mut().enumerate() {
                let col = format!("{name}_{k}");
                d.push(a.get(n, &col) - clean.get(c, &col));
            }
        }
    }
    for (d, bias) in diffs.iter().zip([0.1, -0.2, 0.3]) {
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64).sqrt();
        // 404 samples: the mean within 5 standard errors, the deviation within 20 %.
        assert!(
            (mean - bias).abs() < 5.0 * 0.01 / (d.len() as f64).sqrt(),
            "{mean}"
        );
        assert!((sd - 0.01).abs() < 0.002, "{sd}");
    }
    let decimated = run("rate", &["--rate", "100"]);
    assert_eq!(decimated.rows.len(), 11);
    assert_eq!(decimated.rows[1], clean.rows[10]);
}

/// `--magnetic-field`: the magnetometer is the field in ground seen from the IMU frame,
/// `q* B q` with `q` the orientation written (within the orientation's printed digits), its
/// norm the field's; and each IMU's `raw/NAME.csv` is `qgait fuse`'s layout of the same
/// gyroscope, accelerometer and magnetometer numbers.
#[test]
fn magnetometer_and_raw_recordings_are_the_signals() {
    let dir = scratch("deriv_mag", "in");
    let placement = dir.join("placement.toml");
    std::fs::write(&placement, PLACEMENT).unwrap();
    let out = dir.join("out");
    let o = qgait(&[
        "imu-signals",
        fixture("gait2392_states.sto").to_str().unwrap(),
        "--imus",
        placement.to_str().unwrap(),
        "--magnetic-field",
        "12,-44,16",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |f: &str| Table::sto(&std::fs::read_to_string(out.join(f)).unwrap());
    let (orientations, gyro, accel, mag) = (
        read("orientations.sto"),
        read("angular_velocity.sto"),
        read("linear_acceleration.sto"),
        read("magnetometer.sto"),
    );
    let field = [12.0, -44.0, 16.0];
    let norm = (12.0f64 * 12.0 + 44.0 * 44.0 + 16.0 * 16.0).sqrt();
    let names = ["pelvis_imu", "femur_r_imu", "tibia_l_imu", "calcn_r_imu"];
    for (k, (o, m)) in orientations.rows.iter().zip(&mag.rows).enumerate() {
        for name in names {
            let [w, x, y, z] = quat(&orientations, o, name);
            // The rotation matrix of q; the field in the IMU frame is its transpose times B.
            let r = [
                [
                    1.0 - 2.0 * (y * y + z * z),
                    2.0 * (x * y - w * z),
                    2.0 * (x * z + w * y),
                ],
                [
                    2.0 * (x * y + w * z),
                    1.0 - 2.0 * (x * x + z * z),
                    2.0 * (y * z - w * x),
                ],
                [
                    2.0 * (x * z - w * y),
                    2.0 * (y * z + w * x),
                    1.0 - 2.0 * (x * x + y * y),
                ],
            ];
            let got = [0, 1, 2].map(|i| mag.get(m, &format!("{name}_{i}")));
            for (i, g) in got.iter().enumerate() {
                let want: f64 = (0..3).map(|j| r[j][i] * field[j]).sum();
                assert!(
                    (g - want).abs() < 1e-9 * norm,
                    "row {k} {name}: {g} against {want}"
                );
            }
            let n = got.iter().map(|v| v * v).sum::<f64>().sqrt();
            assert!((n - norm).abs() < 1e-9 * norm, "row {k} {name}: |m| {n}");
        }
    }
    for name in names {
        let raw =
            Table::csv(&std::fs::read_to_string(out.join(format!("raw/{name}.csv"))).unwrap());
        assert_eq!(raw.rows.len(), gyro.rows.len(), "{name}");
        for (k, row) in raw.rows.iter().enumerate() {
            assert_eq!(raw.get(row, "time"), gyro.rows[k][0]);
            for (i, axis) in ["x", "y", "z"].iter().enumerate() {
                let col = format!("{name}_{i}");
                assert_eq!(
                    raw.get(row, &format!("gyr_{axis}")),
                    gyro.get(&gyro.rows[k], &col)
                );
                assert_eq!(
                    raw.get(row, &format!("acc_{axis}")),
                    accel.get(&accel.rows[k], &col)
                );
                assert_eq!(
                    raw.get(row, &format!("mag_{axis}")),
                    mag.get(&mag.rows[k], &col)
                );
            }
        }
    }
    let o = qgait(&[
        "imu-signals",
        fixture("gait2392_states.sto").to_str().unwrap(),
        "--imus",
        placement.to_str().unwrap(),
        "--magnetic-field",
        "12,-44",
        "-o",
        dir.join("bad").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        stderr(&o)
            .contains("'12,-44' for '--magnetic-field <X,Y,Z>': three numbers X,Y,Z are needed"),
        "{}",
        stderr(&o)
    );
}

/// `--lowpass`: a cut-off well above a motion's components changes its derivatives by what
/// the filter's gain says away from the ends (the built-in gait at 1 kHz, harmonics of 1 Hz up
/// to 6 Hz; a 30 Hz cut-off passes 6 Hz with a gain of 1 − 2.6e-6), and a cut-off below them
/// takes the fast components away.
#[test]
fn lowpass_keeps_what_is_below_the_cut_off() {
    let dir = scratch("deriv_lowpass", "out");
    let run = |extra: &[&str], name: &str| {
        let out = dir.join(name);
        let mut args = vec![
            "fk",
            "builtin:normal,rows=1001",
            "--model",
            "gait2392",
            "--derivatives",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = qgait(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        Table::csv(&std::fs::read_to_string(&out).unwrap())
    };
    let plain = run(&[], "plain.csv");
    let mut worst = Vec::new();
    for hz in ["30", "2"] {
        let filtered = run(&["--lowpass", hz], &format!("{hz}.csv"));
        let (mut v, mut a) = (0.0f64, 0.0f64);
        for (p, f) in plain.rows.iter().zip(&filtered.rows) {
            // Two cut-off periods of 2 Hz from either end.
            if p[0] < 0.25 || p[0] > 0.75 {
                continue;
            }
            for point in POINTS {
                for axis in ["x", "y", "z"] {
                    let c = |k: &str| format!("{point}_{k}{axis}");
                    v = v.max((plain.get(p, &c("v")) - filtered.get(f, &c("v"))).abs());
                    a = a.max((plain.get(p, &c("a")) - filtered.get(f, &c("a"))).abs());
                }
            }
        }
        worst.push((v, a));
    }
    println!(
        "inside, --lowpass 30 against none: {:.1e} m/s, {:.1e} m/s^2; --lowpass 2: {:.1e} m/s",
        worst[0].0, worst[0].1, worst[1].0
    );
    assert!(worst[0].0 < 1e-4 && worst[0].1 < 1e-2, "{worst:?}");
    assert!(worst[1].0 > 1e-2, "{worst:?}");
}

/// HAK's and PHAK's analytic motion: 1 kHz, 0.4 s, PHAK's eight coordinates (degrees) each a
/// mean and two sines (0.9 to 3.7 Hz), the pelvis list and rotation scaled by `list` and
/// `rotation`, and a pelvis translation (walking forward at 1.2 m/s, with sways); no other
/// gait2392 coordinate. Written at full precision.
fn stick_motion(test: &str, list: f64, rotation: f64) -> PathBuf {
    let tau = std::f64::consts::TAU;
    // name, mean, two (amplitude, Hz)
    type Sines = [(f64, f64); 2];
    let coordinates: [(&str, f64, Sines); 8] = [
        (
            "pelvis_rotation",
            0.0,
            [(6.0 * rotation, 1.1), (2.0 * rotation, 2.3)],
        ),
        ("pelvis_list", 0.0, [(4.0 * list, 0.9), (1.5 * list, 2.7)]),
        ("hip_flexion_r", 10.0, [(25.0, 1.0), (5.0, 3.1)]),
        ("knee_angle_r", -35.0, [(25.0, 1.2), (6.0, 2.9)]),
        ("ankle_angle_r", 0.0, [(12.0, 1.3), (3.0, 3.7)]),
        ("hip_flexion_l", 5.0, [(22.0, 0.95), (4.0, 2.6)]),
        ("knee_angle_l", -30.0, [(20.0, 1.05), (5.0, 3.3)]),
        ("ankle_angle_l", 2.0, [(10.0, 1.4), (4.0, 3.5)]),
    ];
    let mut text =
        String::from("stick\nversion=1\nnRows=401\nnColumns=12\ninDegrees=yes\nendheader\ntime");
    for (name, ..) in coordinates {
        text += &format!("\t{name}");
    }
    text += "\tpelvis_tx\tpelvis_ty\tpelvis_tz\n";
    for r in 0..=400 {
        let t = r as f64 * 1e-3;
        text += &format!("{t}");
        for (k, (_, mean, sines)) in coordinates.iter().enumerate() {
            let v = mean
                + sines
                    .iter()
                    .enumerate()
                    .map(|(j, (a, f))| a * (tau * f * t + 0.3 * (k + j) as f64).sin())
                    .sum::<f64>();
            text += &format!("\t{v}");
        }
        let translation = [
            1.2 * t + 0.02 * (tau * 1.8 * t).sin(),
            0.95 + 0.01 * (tau * 2.0 * t).sin(),
            0.01 * (tau * 0.9 * t).sin(),
        ];
        for v in translation {
            text += &format!("\t{v}");
        }
        text += "\n";
    }
    let path = scratch(test, "motion").join(format!("stick_{list}_{rotation}.mot"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Five-point central differences at row `k` of rows `h` apart: first and second derivatives
/// (errors `h⁴ f⁽⁵⁾/30` and `h⁴ f⁽⁶⁾/90`).
fn five_point(f: impl Fn(usize) -> f64, k: usize, h: f64) -> (f64, f64) {
    let [m2, m1, c, p1, p2] = [k - 2, k - 1, k, k + 1, k + 2].map(f);
    (
        (m2 - 8.0 * m1 + 8.0 * p1 - p2) / (12.0 * h),
        (-m2 + 16.0 * m1 - 30.0 * c + 16.0 * p1 - p2) / (12.0 * h * h),
    )
}

/// HAK and PHAK with `--derivatives`: the positions are plain `fk`'s, to the bit; the
/// velocities and accelerations are their time derivatives: against five-point central
/// differences of plain `fk`'s positions at 1 kHz (truncation about 1e-8 m/s and 1e-6 m/s²
/// on this motion), velocities within 1e-6 m/s and accelerations within 1e-4 m/s² (three-point
/// differences, printed, are 1e-4 and 1e-2 off: their own error).
#[test]
fn hak_and_phak_derivatives_are_the_derivatives_of_their_positions() {
    let motion = stick_motion("deriv_stick", 1.0, 1.0);
    for model in ["phak", "hak"] {
        let test = format!("deriv_stick_{model}");
        let plain = fk(&format!("{test}_plain"), model, &motion, &[]);
        let ours = fk(&test, model, &motion, &["--derivatives"]);
        assert_eq!(plain.rows.len(), ours.rows.len());
        let (mut v5, mut a5, mut v3, mut a3, mut moving) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for p in POINTS {
            for axis in ["x", "y", "z"] {
                let c = format!("{p}_{axis}");
                let at = |k: usize| plain.get(&plain.rows[k], &c);
                for (k, row) in ours.rows.iter().enumerate() {
                    assert_eq!(ours.get(row, &c), at(k), "{model} {c} row {k}");
                    if k < 2 || k + 2 >= ours.rows.len() {
                        continue;
                    }
                    let (v, a) = (
                        ours.get(row, &format!("{p}_v{axis}")),
                        ours.get(row, &format!("{p}_a{axis}")),
                    );
                    let (fv, fa) = five_point(at, k, 1e-3);
                    v5 = v5.max((v - fv).abs());
                    a5 = a5.max((a - fa).abs());
                    v3 = v3.max((v - (at(k + 1) - at(k - 1)) / 2e-3).abs());
                    a3 = a3.max((a - (at(k + 1) - 2.0 * at(k) + at(k - 1)) / 1e-6).abs());
                    moving = moving.max(v.abs());
                }
            }
        }
        println!(
            "{model}: |v - five-point| {v5:.1e} m/s, |a - five-point| {a5:.1e} m/s^2; \
             three-point: {v3:.1e} m/s, {a3:.1e} m/s^2 (speeds up to {moving:.2} m/s)"
        );
        assert!(moving > 0.5, "{moving}");
        assert!(v5 < 1e-6 && a5 < 1e-4, "{model}: {v5} {a5}");
    }
}

/// HAK does not read the pelvis angles: a motion whose pelvis list and rotation differ gives
/// the same `fk --derivatives` and `imu-signals`, to the byte; PHAK's differ.
#[test]
fn hak_is_independent_of_the_pelvis_angles() {
    let tilted = stick_motion("deriv_hak_pelvis_a", 1.0, 1.0);
    let other = stick_motion("deriv_hak_pelvis_b", -2.0, 0.5);
    for model in ["hak", "phak"] {
        let run = |motion: &Path, name: &str| {
            let test = format!("deriv_hak_pelvis_{model}_{name}");
            let f = fk(&test, model, motion, &["--derivatives"]);
            let [o, g, a] = imu_signals(&test, model, motion, &stick_placement());
            [f.rows, o.rows, g.rows, a.rows]
        };
        let same = run(&tilted, "a") == run(&other, "b");
        assert_eq!(same, model == "hak", "{model}");
    }
}

/// IMUs on every body of HAK and PHAK: [`PLACEMENT`]'s with its calcaneus IMU on the talus,
/// and three more (the right tibia's at the knee centre).
fn stick_placement() -> String {
    PLACEMENT.replace("calcn_r", "talus_r")
        + r#"
[[imu]]
name = "tibia_r_imu"
body = "tibia_r"
translation = [0.0, 0.0, 0.0]
orientation = [0.20, -0.10, 0.30]

[[imu]]
name = "femur_l_imu"
body = "femur_l"
translation = [0.03, -0.12, -0.05]
orientation = [-0.20, 0.40, 0.10]

[[imu]]
name = "talus_l_imu"
body = "talus_l"
translation = [0.05, -0.02, 0.01]
orientation = [0.0, 0.0, 0.0]
"#
}

const STICK_IMUS: [&str; 7] = [
    "pelvis_imu",
    "femur_r_imu",
    "tibia_r_imu",
    "talus_r_imu",
    "femur_l_imu",
    "tibia_l_imu",
    "talus_l_imu",
];

/// A quaternion `w,x,y,z` as an array.
fn quat(t: &Table, row: &[f64], name: &str) -> [f64; 4] {
    [0, 1, 2, 3].map(|k| t.get(row, &format!("{name}_{k}")))
}

/// `imu-signals --model phak`, on PHAK's analytic motion at 1 kHz:
/// - the gyroscope is the IMU frame's angular velocity in its own axes, `2 vec(q* q̇)` with
///   `q̇` the five-point differences of the orientations written: within 1e-6 rad/s;
/// - the accelerometer of the IMU at the knee centre is the knee's acceleration (five-point
///   differences of plain `fk`'s knee plus the motion's pelvis translation) minus gravity, in
///   the IMU's axes: within 1e-4 m/s²;
/// - with no pelvis rotation (nor gait2392's tilt, hip adduction and rotation), PHAK's pelvis,
///   femurs and tibias turn as gait2392's: the same gyroscope within 1e-9 rad/s (their origins
///   differ, so their accelerometers do; the talus turns about gait2392's oblique ankle axis).
#[test]
fn phak_imu_signals_are_the_derivatives_of_its_orientations() {
    let motion = stick_motion("deriv_phak_imu", 1.0, 1.0);
    let [orient, gyro, acc] = imu_signals("deriv_phak_imu", "phak", &motion, &stick_placement());
    let n = orient.rows.len();
    assert_eq!(n, 401);
    let (mut worst_gyro, mut turning) = (0.0f64, 0.0f64);
    for name in STICK_IMUS {
        // The same sign throughout (q and -q are the same turn).
        let mut qs: Vec<[f64; 4]> = orient.rows.iter().map(|r| quat(&orient, r, name)).collect();
        for k in 1..n {
            if (0..4).map(|i| qs[k][i] * qs[k - 1][i]).sum::<f64>() < 0.0 {
                qs[k] = qs[k].map(|v| -v);
            }
        }
        for k in 2..n - 2 {
            let qd: [f64; 4] = core::array::from_fn(|i| five_point(|j| qs[j][i], k, 1e-3).0);
            let [w, x, y, z] = qs[k];
            // 2 vec(conj(q) ⊗ q̇).
            let omega = [
                2.0 * (w * qd[1] - x * qd[0] - y * qd[3] + z * qd[2]),
                2.0 * (w * qd[2] - y * qd[0] - z * qd[1] + x * qd[3]),
                2.0 * (w * qd[3] - z * qd[0] - x * qd[2] + y * qd[1]),
            ];
            let row = &gyro.rows[k];
            for (i, o) in omega.iter().enumerate() {
                let g = gyro.get(row, &format!("{name}_{i}"));
                worst_gyro = worst_gyro.max((g - o).abs());
                turning = turning.max(g.abs());
            }
        }
    }
    // The tibia IMU sits at the knee centre: plain fk's knee, plus the pelvis translation.
    let plain = fk("deriv_phak_imu_fk", "phak", &motion, &[]);
    let text = std::fs::read_to_string(&motion).unwrap();
    let translation: Vec<[f64; 3]> = text
        .lines()
        .skip_while(|l| !l.starts_with("time"))
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split('\t').map(|v| v.parse().unwrap()).collect();
            [v[9], v[10], v[11]]
        })
        .collect();
    let mut worst_acc = 0.0f64;
    for k in 2..n - 2 {
        let a: [f64; 3] = core::array::from_fn(|i| {
            let axis = ["x", "y", "z"][i];
            let at =
                |j: usize| plain.get(&plain.rows[j], &format!("knee_r_{axis}")) + translation[j][i];
            five_point(at, k, 1e-3).1 - if i == 1 { -9.80665 } else { 0.0 }
        });
        // Into the IMU's axes: R(q)ᵀ a.
        let [w, x, y, z] = quat(&orient, &orient.rows[k], "tibia_r_imu");
        let r = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
            [
                2.0 * (x * z - w * y),
                2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let expected = [0, 1, 2].map(|i| (0..3).map(|j| r[j][i] * a[j]).sum::<f64>());
        for (i, expected) in expected.iter().enumerate() {
            let got = acc.get(&acc.rows[k], &format!("tibia_r_imu_{i}"));
            worst_acc = worst_acc.max((got - expected).abs());
        }
    }
    // gait2392's pelvis, femurs and tibias turn as PHAK's without pelvis rotation.
    let level = stick_motion("deriv_phak_imu_g", 1.0, 0.0);
    let [_, phak, _] = imu_signals("deriv_phak_imu_p", "phak", &level, &stick_placement());
    let [_, g2392, _] = imu_signals("deriv_phak_imu_g", "gait2392", &level, &stick_placement());
    let mut worst_shared = 0.0f64;
    for (p, g) in phak.rows.iter().zip(&g2392.rows) {
        for name in [
            "pelvis_imu",
            "femur_r_imu",
            "tibia_r_imu",
            "femur_l_imu",
            "tibia_l_imu",
        ] {
            for i in 0..3 {
                let c = format!("{name}_{i}");
                worst_shared = worst_shared.max((phak.get(p, &c) - g2392.get(g, &c)).abs());
            }
        }
    }
    println!(
        "phak imu-signals: |gyroscope - 2 vec(q* dq/dt)| {worst_gyro:.1e} rad/s (up to \
         {turning:.2} rad/s), |accelerometer - knee's| {worst_acc:.1e} m/s^2, gyroscope \
         against gait2392's (shared bodies) {worst_shared:.1e} rad/s"
    );
    assert!(turning > 1.0, "{turning}");
    assert!(worst_gyro < 1e-6, "{worst_gyro}");
    assert!(worst_acc < 1e-4, "{worst_acc}");
    assert!(worst_shared < 1e-9, "{worst_shared}");
}

/// An IMU on a body the model does not have: an error naming the placement file, the IMU and
/// the model's bodies.
#[test]
fn an_imu_on_a_body_phak_lacks_is_refused() {
    let heel = "[[imu]]\nname = \"heel\"\nbody = \"calcn_r\"\ntranslation = [0, 0, 0]\norientation = [0, 0, 0]\n";
    let (o, _) = run_imu_signals("deriv_phak_calcn", "phak", &fixture("gait2392.mot"), heel);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("placement.toml: IMU `heel`: unknown body `calcn_r`: phak has the bodies pelvis, femur_r, tibia_r, talus_r, femur_l, tibia_l, talus_l"),
        "{e}"
    );
}
