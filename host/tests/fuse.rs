//! `qgait fuse` through the binary: BROAD's metric on copies of the shared trials whose
//! ground truth is emptied (the figures of the kernel's VQF test), raw data in → `fuse` →
//! `imu` → joint angles, Xsens raw exports, and errors that name file, line and column.

mod common;

use std::path::{Path, PathBuf};

use common::{qgait, scratch, stderr, stdout};
use qgait_kernel::imu::Segment;
use qgait_opensim::imu_sto::OrientationReader;

/// The reference VQF's figures on the shared trials (`vqf` 2.1.2, default parameters;
/// `scripts/vqf_fixtures.py broad`), as in `crates/qgait-kernel/tests/fusion_broad.rs`: 9D
/// total, heading and inclination RMSE and 6D inclination RMSE, degrees, to 4 decimals.
const REFERENCE: [(&str, [f64; 4]); 10] = [
    (
        "03_undisturbed_slow_rotation_C",
        [1.9305, 1.8842, 0.4203, 0.4203],
    ),
    (
        "05_undisturbed_slow_rotation_with_breaks_B",
        [0.9858, 0.9204, 0.3531, 0.3531],
    ),
    (
        "06_undisturbed_fast_rotation_A",
        [4.0338, 3.9529, 0.8041, 0.8041],
    ),
    (
        "11_undisturbed_slow_translation_B",
        [0.8993, 0.7952, 0.4198, 0.4198],
    ),
    (
        "14_undisturbed_slow_translation_with_breaks_B",
        [0.7329, 0.6056, 0.4127, 0.4127],
    ),
    (
        "16_undisturbed_fast_translation_B",
        [0.7425, 0.5101, 0.5395, 0.5395],
    ),
    ("24_disturbed_tapping_A", [1.5458, 1.4216, 0.6073, 0.6073]),
    (
        "27_disturbed_phone_vibration_B",
        [6.7328, 6.7227, 0.3702, 0.3702],
    ),
    (
        "30_disturbed_stationary_magnet_C",
        [2.5740, 2.2499, 1.2503, 1.2503],
    ),
    (
        "34_disturbed_attached_magnet_3cm",
        [3.3504, 3.2876, 0.6459, 0.6459],
    ),
];

/// The shared BROAD trials, or `None` with the reason printed.
fn broad_trials() -> Option<Vec<PathBuf>> {
    let dir = common::shared_dir()?.join("data/broad");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "csv"));
    files.sort();
    if files.is_empty() {
        eprintln!("skipped: no BROAD trials in {}", dir.display());
        return None;
    }
    Some(files)
}

/// A copy of a BROAD CSV with every `opt_*` cell emptied (what an estimator is given).
fn without_truth(from: &Path, to: &Path) {
    let text = std::fs::read_to_string(from).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let opt: Vec<usize> = header
        .split(',')
        .enumerate()
        .filter(|(_, h)| h.starts_with("opt_"))
        .map(|(i, _)| i)
        .collect();
    assert_eq!(opt.len(), 4, "{}: opt_w..z", from.display());
    let mut out = String::with_capacity(text.len());
    out.push_str(header);
    out.push('\n');
    for l in lines {
        let cells: Vec<&str> = l
            .split(',')
            .enumerate()
            .map(|(i, c)| if opt.contains(&i) { "" } else { c })
            .collect();
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    std::fs::write(to, out).unwrap();
}

/// The quaternions of one sensor's column of an orientation `.sto`, read by `qgait imu`'s
/// own reader.
fn read_column(path: &Path, segment: Segment) -> (Vec<f64>, Vec<[f64; 4]>) {
    let mut r = OrientationReader::open(path).unwrap_or_else(|e| panic!("{e}"));
    let (mut times, mut q) = (Vec::new(), Vec::new());
    while let Some(row) = r.next_row().unwrap_or_else(|e| panic!("{e}")) {
        let s = row.readings.get(segment).expect("a reading");
        times.push(row.time);
        q.push([s.w, s.x, s.y, s.z]);
    }
    (times, q)
}

/// `qgait fuse` on every shared trial with its truth emptied, 9D and 6D, scored against the
/// original's truth with the kernel's BROAD metric: the reference VQF's figures (to their 4
/// decimals), and the same as `--score` prints on the original.
#[test]
fn broad_trials_fused_by_the_binary_score_as_the_reference_vqf() {
    let Some(files) = broad_trials() else { return };
    let dir = scratch("fuse", "broad");
    let mut scored = 0;
    for path in &files {
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let Some((_, reference)) = REFERENCE.iter().find(|(n, _)| *n == stem) else {
            eprintln!("{stem}: no reference figures, not scored");
            continue;
        };
        let blank = dir.join(format!("{stem}.csv"));
        without_truth(path, &blank);
        let truth = qgait_fusion::read_csv(path).unwrap();
        for (mode, figures) in [
            ("9d", [reference[0], reference[1], reference[2]]),
            ("6d", [f64::NAN, f64::NAN, reference[3]]),
        ] {
            let out = dir.join(format!("{stem}_{mode}.sto"));
            let o = qgait(&[
                "fuse",
                blank.to_str().unwrap(),
                "--mode",
                mode,
                "--name",
                "pelvis_imu",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let (times, q) = read_column(&out, Segment::Pelvis);
            assert_eq!(times.len(), truth.len(), "one row per input row");
            assert_eq!(times, truth.times, "the input's times");
            let (errors, rows) = qgait_fusion::score(&truth, &q).expect("scored rows");
            eprintln!(
                "{stem} {mode}: total {:.4}° heading {:.4}° inclination {:.4}° over {rows} rows",
                errors[0], errors[1], errors[2]
            );
            for (k, want) in figures.iter().enumerate() {
                if want.is_finite() {
                    assert!(
                        (errors[k] - want).abs() <= 0.6e-4,
                        "{stem} {mode}: error {k} {:.6}° against the reference's {want}°",
                        errors[k]
                    );
                }
            }
            std::fs::remove_file(&out).unwrap();
        }
        if stem.starts_with("03_") {
            // --score on the original prints the same 9D figures.
            let out = dir.join("scored.sto");
            let o = qgait(&[
                "fuse",
                path.to_str().unwrap(),
                "--mode",
                "9d",
                "--score",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            let table = stdout(&o);
            let row = format!(
                "| {stem} | 34385 | {:.4} | {:.4} | {:.4} |",
                reference[0], reference[1], reference[2]
            );
            assert!(table.contains(&row), "{table}\nexpected {row}");
            let o = qgait(&[
                "fuse",
                blank.to_str().unwrap(),
                "--mode",
                "9d",
                "--score",
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(!o.status.success());
            assert!(
                stderr(&o).contains("no file has reference orientations"),
                "{}",
                stderr(&o)
            );
            // --truth: the copy (same stem) scored against the original: the same figures.
            let o = qgait(&[
                "fuse",
                blank.to_str().unwrap(),
                "--mode",
                "9d",
                "--truth",
                path.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            assert!(stdout(&o).contains(&row), "{}\nexpected {row}", stdout(&o));
        }
        std::fs::remove_file(&blank).unwrap();
        scored += 1;
    }
    assert!(scored > 0, "no trial scored");
}

fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

fn conj(q: [f64; 4]) -> [f64; 4] {
    [q[0], -q[1], -q[2], -q[3]]
}

/// `v` in the sensor frame of `q` (sensor to earth): `q* ⊗ (0, v) ⊗ q`.
fn to_sensor(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let r = qmul(qmul(conj(q), [0.0, v[0], v[1], v[2]]), q);
    [r[1], r[2], r[3]]
}

/// The rotation angle between two orientations, degrees.
fn angle_deg(a: [f64; 4], b: [f64; 4]) -> f64 {
    let e = qmul(a, conj(b));
    let v = (e[1] * e[1] + e[2] * e[2] + e[3] * e[3]).sqrt();
    (2.0 * v.atan2(e[0].abs())).to_degrees()
}

/// The angular rate (sensor frame, rad/s) that turns `a` into `b` in `dt`.
fn rate(a: [f64; 4], b: [f64; 4], dt: f64) -> [f64; 3] {
    let mut d = qmul(conj(a), b);
    if d[0] < 0.0 {
        d = d.map(|c| -c);
    }
    let v = (d[1] * d[1] + d[2] * d[2] + d[3] * d[3]).sqrt();
    if v < 1e-300 {
        return [0.0; 3];
    }
    let angle = 2.0 * v.atan2(d[0]);
    [1, 2, 3].map(|k| d[k] / v * angle / dt)
}

/// The rows of a `.mot` after its header: (labels, rows of numbers).
fn read_mot(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().skip_while(|l| l.trim() != "endheader").skip(1);
    let labels = lines
        .next()
        .unwrap()
        .split('\t')
        .map(str::to_string)
        .collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split('\t').map(|c| c.trim().parse().unwrap()).collect())
        .collect();
    (labels, rows)
}

/// Raw data in, joint angles out: raw gyroscope, accelerometer and magnetometer signals
/// synthesised from OpenSense's tutorial orientations (8 sensors, 24 s of walking at 100 Hz,
/// after 10 s standing still in the first pose; gravity and a field of (0, 20, −40) µT in the
/// sensors' earth frame, y north), one CSV per sensor named after its IMU, fused by `qgait
/// fuse` (9D), then `qgait imu` with OpenSense's tutorial settings: the orientations follow the
/// true ones and the joint angles those `qgait imu` gives from the true orientations.
#[test]
fn raw_data_fused_then_imu_gives_the_joint_angles_of_the_true_orientations() {
    let Some(imu) = common::imu_dir() else { return };
    let dir = scratch("fuse", "pipeline");
    let text = std::fs::read_to_string(imu.join("walking_orientations.sto")).unwrap();
    let mut lines = text.lines().skip_while(|l| l.trim() != "endheader").skip(1);
    let labels: Vec<String> = lines
        .next()
        .unwrap()
        .split('\t')
        .map(str::to_string)
        .collect();
    let walk: Vec<Vec<[f64; 4]>> = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split('\t')
                .skip(1)
                .map(|c| {
                    let v: Vec<f64> = c.split(',').map(|x| x.parse().unwrap()).collect();
                    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                    [v[0] / n, v[1] / n, v[2] / n, v[3] / n]
                })
                .collect()
        })
        .collect();
    let dt = 0.01;
    let still = 1000;
    let rows: Vec<&Vec<[f64; 4]>> = std::iter::repeat_n(&walk[0], still).chain(&walk).collect();
    let times: Vec<f64> = (0..rows.len()).map(|k| k as f64 * dt).collect();
    let (g, field) = ([0.0, 0.0, 9.81], [0.0, 20.0, -40.0]);
    let mut inputs = Vec::new();
    for (s, label) in labels.iter().enumerate().skip(1) {
        let s = s - 1;
        let mut csv = String::from("time,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z,mag_x,mag_y,mag_z\n");
        for (k, row) in rows.iter().enumerate() {
            let q = row[s];
            let w = if k == 0 {
                [0.0; 3]
            } else {
                rate(rows[k - 1][s], q, dt)
            };
            let a = to_sensor(q, g);
            let m = to_sensor(q, field);
            csv += &format!(
                "{},{},{},{},{},{},{},{},{},{}\n",
                times[k], w[0], w[1], w[2], a[0], a[1], a[2], m[0], m[1], m[2]
            );
        }
        let p = dir.join(format!("{label}.csv"));
        std::fs::write(&p, csv).unwrap();
        inputs.push(p);
    }
    let fused = dir.join("fused.sto");
    let mut args = vec!["fuse".to_string()];
    args.extend(inputs.iter().map(|p| p.display().to_string()));
    args.extend(["--mode", "9d", "-o", fused.to_str().unwrap()].map(String::from));
    let o = qgait(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    // The fused orientations against the true ones, over the walk.
    let mut worst: f64 = 0.0;
    for (s, label) in labels.iter().enumerate().skip(1) {
        let segment = Segment::from_name(label).unwrap();
        let (t, q) = read_column(&fused, segment);
        assert_eq!(t, times);
        for k in still..rows.len() {
            worst = worst.max(angle_deg(q[k], rows[k][s - 1]));
        }
    }
    eprintln!("fused against true orientations over the walk: at most {worst:.4}°");
    assert!(
        worst < 0.5,
        "fused orientations {worst}° from the true ones"
    );
    // The true orientations in the same file layout, then both through `qgait imu`.
    let truth = dir.join("truth.sto");
    let columns: Vec<Vec<[f64; 4]>> = (0..labels.len() - 1)
        .map(|s| rows.iter().map(|r| r[s]).collect())
        .collect();
    let names: Vec<&str> = labels[1..].iter().map(String::as_str).collect();
    let refs: Vec<&[[f64; 4]]> = columns.iter().map(Vec::as_slice).collect();
    qgait_fusion::write_orientations(
        std::fs::File::create(&truth).unwrap(),
        100.0,
        &times,
        &names,
        &refs,
    )
    .unwrap();
    let calibration = imu.join("placement_orientations.sto");
    let (a, b) = (dir.join("fused.mot"), dir.join("truth.mot"));
    common::run_imu(&fused, &calibration, &a, &[]);
    common::run_imu(&truth, &calibration, &b, &[]);
    let ((la, ra), (lb, rb)) = (read_mot(&a), read_mot(&b));
    assert_eq!(la, lb);
    assert_eq!(ra.len(), rows.len());
    let mut worst_angle: f64 = 0.0;
    for (x, y) in ra[still..].iter().zip(&rb[still..]) {
        for (u, v) in x.iter().zip(y).skip(1) {
            worst_angle = worst_angle.max((u - v).abs());
        }
    }
    eprintln!("joint angles from fused against true orientations: at most {worst_angle:.4}°");
    assert!(worst_angle < 1.0, "joint angles {worst_angle}° apart");
}

/// Xsens MT Manager exports with raw channels (`Acc_*`, `Gyr_*`, `Mag_*` in Xsens' normalised
/// units, the rate from `// Update Rate`), two sensors named by `--name`: at rest, each
/// orientation maps the measured specific force to the vertical and the field into the y-z
/// plane (north and down).
#[test]
fn xsens_raw_exports_fuse_with_their_update_rate() {
    let xsens = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/imu/vendor/xsens");
    let files = ["walk-000_00B421AF.txt", "walk-000_00B421D3.txt"].map(|f| xsens.join(f));
    let dir = scratch("fuse", "xsens");
    let out = dir.join("xsens.sto");
    let o = qgait(&[
        "fuse",
        files[0].to_str().unwrap(),
        files[1].to_str().unwrap(),
        "--mode",
        "9d",
        "--name",
        "pelvis_imu",
        "--name",
        "femur_r_imu",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.starts_with("DataRate=100.000000\nDataType=Quaternion\n"),
        "{text}"
    );
    for (file, segment) in files.iter().zip([Segment::Pelvis, Segment::FemurR]) {
        let raw = qgait_fusion::read_xsens(file, None).unwrap();
        let (times, q) = read_column(&out, segment);
        assert_eq!(times.len(), raw.len());
        assert!((times[1] - 0.01).abs() < 1e-12);
        let last = q.len() - 1;
        let a = raw.acc[last];
        let up = qmul(qmul(q[last], [0.0, a[0], a[1], a[2]]), conj(q[last]));
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        assert!(
            up[3] / n > 0.9999,
            "{segment}: the specific force maps to {up:?}"
        );
        let m = raw.mag.as_ref().unwrap()[last];
        let e = qmul(qmul(q[last], [0.0, m[0], m[1], m[2]]), conj(q[last]));
        assert!(
            e[1].abs() < 1e-3 * (e[2] * e[2] + e[3] * e[3]).sqrt(),
            "{segment}: field {e:?}"
        );
        assert!(e[2] > 0.0, "{segment}: the field points north: {e:?}");
    }
}

/// Errors: a bad cell names file, line and column; 9D without a magnetometer; a gap in the
/// times; several files whose times differ; a name `qgait imu` does not read is warned about.
#[test]
fn fuse_errors_name_file_line_and_column() {
    let dir = scratch("fuse", "errors");
    let good = "time,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z,mag_x,mag_y,mag_z\n\
                0,0,0,0,0,0,9.8,0,20,-40\n0.01,0,0,0,0,0,9.8,0,20,-40\n0.02,0,0,0,0,0,9.8,0,20,-40\n";
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p.display().to_string()
    };
    let out = dir.join("o.sto").display().to_string();
    let run = |args: &[&str]| {
        let mut all = vec!["fuse"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", &out]);
        qgait(&all)
    };
    let bad = write(
        "bad.csv",
        &good.replace("0.01,0,0,0,0,0,9.8", "0.01,0,0,0,0,x,9.8"),
    );
    let o = run(&[&bad, "--mode", "9d"]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("bad.csv:3:") && e.contains("column 6 (`acc_y`)") && e.contains("`x`"),
        "{e}"
    );
    let six = write(
        "six.csv",
        &good
            .replace(",mag_x,mag_y,mag_z", "")
            .replace(",0,20,-40", ""),
    );
    let o = run(&[&six, "--mode", "9d"]);
    assert!(
        stderr(&o).contains("no magnetometer columns") && stderr(&o).contains("6d"),
        "{}",
        stderr(&o)
    );
    let o = run(&[&six, "--mode", "6d", "--name", "pelvis_imu"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let gap = write("gap.csv", &format!("{good}0.05,0,0,0,0,0,9.8,0,20,-40\n"));
    let o = run(&[&gap, "--mode", "9d"]);
    assert!(
        stderr(&o).contains("gap.csv:") && stderr(&o).contains("irregular sampling"),
        "{}",
        stderr(&o)
    );
    let a = write("a.csv", good);
    let b = write("b.csv", &good.replace("0.02,", "0.03,"));
    let o = run(&[
        &a,
        &b,
        "--mode",
        "9d",
        "--name",
        "pelvis_imu",
        "--name",
        "torso_imu",
    ]);
    assert!(!o.status.success());
    let o = run(&[&a, &a.replace("a.csv", "b.csv"), "--mode", "9d"]);
    assert!(!o.status.success());
    let c = write("c.csv", &good.replace("0.02,", "0.025,"));
    let o = run(&[
        &a,
        &c,
        "--mode",
        "9d",
        "--name",
        "pelvis_imu",
        "--name",
        "torso_imu",
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("c.csv:") && (e.contains("same times") || e.contains("irregular")),
        "{e}"
    );
    let o = run(&[&a, "--mode", "9d"]);
    assert!(o.status.success());
    assert!(
        stderr(&o).contains("warning") && stderr(&o).contains("--name"),
        "{}",
        stderr(&o)
    );
}
