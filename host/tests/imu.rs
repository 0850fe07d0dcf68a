//! `qgait imu`: OpenSense's tutorial recording (`../shared/data/imu`, skipped with a printed
//! reason when absent) against OpenSense's own gait2392 solution, the output read back by
//! `qgait fk`, and errors on bad orientation files naming file, line and column.
//! The accuracy table: `cargo test -p qgait --release --test imu -- --nocapture`.

mod common;

use std::path::{Path, PathBuf};

use common::{imu_dir, qgait, run_imu_tutorial, stderr};
use qgait_opensim::mot::MotionTable;

/// The coordinates OpenSense determines with this IMU set (not the MTP joints, not the pelvis
/// translations).
const DETERMINED: [&str; 18] = [
    "pelvis_tilt",
    "pelvis_list",
    "pelvis_rotation",
    "hip_flexion_r",
    "hip_adduction_r",
    "hip_rotation_r",
    "knee_angle_r",
    "ankle_angle_r",
    "subtalar_angle_r",
    "hip_flexion_l",
    "hip_adduction_l",
    "hip_rotation_l",
    "knee_angle_l",
    "ankle_angle_l",
    "subtalar_angle_l",
    "lumbar_extension",
    "lumbar_bending",
    "lumbar_rotation",
];

#[test]
fn tutorial_recording_matches_opensense_and_reads_back_through_fk() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu", "tutorial");
    let out = tmp.join("angles.mot");
    run_imu_tutorial(&dir, &out, &[]);
    let (ours, _) = MotionTable::read(&out).unwrap();
    let (theirs, _) = MotionTable::read(&dir.join("walking_gait2392_opensense_0-12s.sto")).unwrap();
    assert!(ours.in_degrees() && theirs.in_degrees());
    assert_eq!(ours.rows(), 2432, "one output row per input row");
    let n = theirs.rows();
    assert!(n > 1000);
    for r in 0..n {
        assert!((ours.time()[r] - theirs.time()[r]).abs() < 1e-9, "row {r}");
    }
    let failures = compare(&ours, &theirs, "least squares", 1.0, 3.0);
    assert!(failures.is_empty(), "beyond 1° RMSE / 3° max: {failures:?}");

    // Turning: pelvis_rotation never jumps (OpenSense's goes past +-180 degrees).
    let rot = ours.column("pelvis_rotation").unwrap();
    let step = rot
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    assert!(step < 10.0, "pelvis_rotation jumps by {step}°");

    // The output is a motion `qgait fk` takes: one CSV row per input row.
    let csv = tmp.join("fk.csv");
    let o = qgait(&[
        "fk",
        out.to_str().unwrap(),
        "--model",
        "gait2392",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "fk failed: {}", stderr(&o));
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 1 + 2432);
    // ... and `qgait export`: one marker frame per row.
    let trc = tmp.join("joints.trc");
    let o = qgait(&[
        "export",
        out.to_str().unwrap(),
        "--model",
        "gait2392",
        "--trc",
        trc.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "export failed: {}", stderr(&o));
    let text = std::fs::read_to_string(&trc).unwrap();
    assert!(text.contains("\t2432\t"), "frame count in the .trc header");
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Prints the RMSE and max of every determined coordinate of `ours` against OpenSense's
/// `theirs` over its rows (a Markdown table); the coordinates beyond `rmse` or `max` degrees.
fn compare(
    ours: &MotionTable,
    theirs: &MotionTable,
    what: &str,
    rmse_limit: f64,
    max_limit: f64,
) -> Vec<String> {
    let n = theirs.rows();
    eprintln!("qgait imu ({what}) against OpenSense, gait2392, first {n} rows (degrees)");
    eprintln!("| coordinate | RMSE | max |\n|---|---:|---:|");
    let mut failures = Vec::new();
    for name in DETERMINED {
        let a = ours.column(name).unwrap();
        let b = theirs.column(name).unwrap();
        let (mut sum, mut max) = (0.0, 0.0f64);
        for r in 0..n {
            let e = a[r] - b[r];
            sum += e * e;
            max = max.max(e.abs());
        }
        let rmse = (sum / n as f64).sqrt();
        eprintln!("| {name} | {rmse:.2} | {max:.2} |");
        if rmse > rmse_limit || max > max_limit {
            failures.push(format!("{name}: RMSE {rmse:.3}, max {max:.3}"));
        }
    }
    failures
}

#[test]
fn closed_form_mode_matches_opensense_on_the_pelvis_and_trunk() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu", "closed-form");
    let out = tmp.join("angles.mot");
    run_imu_tutorial(&dir, &out, &["--mode", "closed-form"]);
    let (ours, _) = MotionTable::read(&out).unwrap();
    let (theirs, _) = MotionTable::read(&dir.join("walking_gait2392_opensense_0-12s.sto")).unwrap();
    let failures = compare(&ours, &theirs, "closed form", 0.3, 1.0);
    // The per-joint closed form leaves the legs' misfit on the distal joints: only the pelvis
    // and the lumbar joint (one sensor pair each, no redundancy) agree with OpenSense.
    for f in &failures {
        assert!(!f.starts_with("pelvis") && !f.starts_with("lumbar"), "{f}");
    }
    assert!(
        !failures.is_empty(),
        "the legs differ from OpenSense's least squares"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn heading_free_pelvis_does_not_follow_the_walking_direction() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu", "heading-free");
    let (world, free) = (tmp.join("world.mot"), tmp.join("free.mot"));
    run_imu_tutorial(&dir, &world, &[]);
    run_imu_tutorial(&dir, &free, &["--pelvis", "heading-free"]);
    let (w, _) = MotionTable::read(&world).unwrap();
    let (f, _) = MotionTable::read(&free).unwrap();
    // The legs and the trunk do not depend on the pelvis's convention.
    for name in &DETERMINED[3..] {
        assert_eq!(w.column(name), f.column(name), "{name}");
    }
    // The recording turns round several times: in the world frame the heading spans more
    // than a turn, relative to the progression direction it stays within a stride's swing.
    let span = |c: &[f64]| {
        c.iter().copied().fold(f64::MIN, f64::max) - c.iter().copied().fold(f64::MAX, f64::min)
    };
    let world_rot = span(w.column("pelvis_rotation").unwrap());
    let free_rot = f.column("pelvis_rotation").unwrap();
    eprintln!(
        "pelvis_rotation span: world {world_rot:.1}°, heading-free {:.1}°",
        span(free_rot)
    );
    assert!(world_rot > 360.0);
    let rms = (free_rot.iter().map(|v| v * v).sum::<f64>() / free_rot.len() as f64).sqrt();
    assert!(rms < 30.0, "heading-free pelvis_rotation rms {rms:.1}°");
    // The file says so, and `gait` warns that turns cannot be found in it.
    assert!(f.header().pelvis_heading_free && !w.header().pelvis_heading_free);
    let o = qgait(&[
        "gait",
        free.to_str().unwrap(),
        "-o",
        tmp.join("gait").to_str().unwrap(),
    ]);
    assert!(
        stderr(&o).contains("its pelvis is heading-free (qgait imu --pelvis heading-free)"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Writes an orientation file: `rows` after the header and labels.
fn orientation_file(dir: &Path, name: &str, labels: &str, rows: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(
        &p,
        format!("DataRate=100\nDataType=Quaternion\nversion=3\nendheader\n{labels}\n{rows}"),
    )
    .unwrap();
    p
}

const LABELS: &str = "time\tpelvis_imu\tfemur_r_imu\ttorso_imu";
const GOOD: &str = "0\t1,0,0,0\t1,0,0,0\t1,0,0,0\n";

/// Runs `qgait imu` on a recording with a good calibration; its stderr, after checking it failed.
fn imu_error(dir: &Path, walk: &Path, extra: &[&str]) -> String {
    let pose = orientation_file(dir, "pose.sto", LABELS, GOOD);
    let out = dir.join("out.mot");
    let mut args = vec![
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = qgait(&args);
    assert!(!o.status.success(), "should fail");
    stderr(&o)
}

#[test]
fn bad_orientation_files_name_file_line_and_column() {
    let tmp = common::scratch("imu", "errors");
    // Each case: labels, rows, and what the message must contain.
    let cases: [(&str, &str, &[&str]); 6] = [
        // A cell with three components, on line 7 (header 4 lines, labels, one good row).
        (
            LABELS,
            "0\t1,0,0,0\t1,0,0,0\t1,0,0,0\n0.01\t1,0,0,0\t1,0,0\t1,0,0,0\n",
            &[
                ":7:",
                "column 3",
                "femur_r_imu",
                "character 14",
                "3 components",
            ],
        ),
        // A component that is not a number.
        (
            LABELS,
            "0\t1,0,0,0\t1,0,0,0\t1,0,x,0\n",
            &[":6:", "column 4", "torso_imu", "`x` is not a number"],
        ),
        // Not a unit quaternion.
        (
            LABELS,
            "0\t2,0,0,0\t1,0,0,0\t1,0,0,0\n",
            &[":6:", "column 2", "pelvis_imu", "norm 2"],
        ),
        // A calibrated sensor without a column.
        (
            "time\tpelvis_imu\ttorso_imu",
            "0\t1,0,0,0\t1,0,0,0\n",
            &[":5:", "no column `femur_r_imu`", "pose.sto"],
        ),
        // A row with a missing cell.
        (
            LABELS,
            "0\t1,0,0,0\t1,0,0,0\n",
            &[":6:", "3 cells", "4 columns"],
        ),
        // Time going back.
        (
            LABELS,
            "0.5\t1,0,0,0\t1,0,0,0\t1,0,0,0\n0.1\t1,0,0,0\t1,0,0,0\t1,0,0,0\n",
            &[":7:", "time 0.1", "line 6"],
        ),
    ];
    for (i, (labels, rows, expected)) in cases.iter().enumerate() {
        let walk = orientation_file(&tmp, &format!("walk{i}.sto"), labels, rows);
        let err = imu_error(&tmp, &walk, &[]);
        let file = walk.display().to_string();
        assert!(err.contains(&file), "case {i}: {err}");
        for e in *expected {
            assert!(err.contains(e), "case {i}: `{e}` not in: {err}");
        }
    }

    // Not an orientation file: a joint-angle .mot.
    let mot = tmp.join("angles.mot");
    std::fs::write(
        &mot,
        "walk\nversion=1\ninDegrees=yes\nendheader\ntime\tknee_angle_r\n0\t1\n",
    )
    .unwrap();
    let err = imu_error(&tmp, &mot, &[]);
    assert!(
        err.contains("angles.mot:5:") && err.contains("DataType=Quaternion"),
        "{err}"
    );

    // The base IMU without a reading in the calibration pose.
    let walk = orientation_file(&tmp, "walk.sto", LABELS, GOOD);
    let err = imu_error(&tmp, &walk, &["--base-imu", "calcn_l_imu"]);
    assert!(
        err.contains("pose.sto:6:") && err.contains("calcn_l_imu"),
        "{err}"
    );
    // Settings.
    let err = imu_error(&tmp, &walk, &["--sensor-to-opensim", "1,2"]);
    assert!(err.contains("--sensor-to-opensim"), "{err}");
    let err = imu_error(&tmp, &walk, &["--base-imu", "head_imu"]);
    assert!(err.contains("--base-imu `head_imu`"), "{err}");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn a_sensor_without_a_reading_is_held_and_the_rest_solved() {
    // `nan,nan,nan,nan` is no reading: the row is solved without it.
    let tmp = common::scratch("imu", "nan");
    let walk = orientation_file(
        &tmp,
        "walk.sto",
        LABELS,
        "0\t1,0,0,0\t1,0,0,0\t1,0,0,0\n0.01\t1,0,0,0\tnan,nan,nan,nan\t1,0,0,0\n",
    );
    let pose = orientation_file(&tmp, "pose.sto", LABELS, GOOD);
    let out = tmp.join("out.mot");
    let o = qgait(&[
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (t, _) = MotionTable::read(&out).unwrap();
    assert_eq!(t.rows(), 2);
    for v in t.column("hip_flexion_r").unwrap() {
        assert!(v.abs() < 1e-9, "{v}");
    }
    // --rate is for files without times: said to be ignored here.
    let o = qgait(&[
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "--rate",
        "50",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--rate 50 ignored: the file has its own times"),
        "{}",
        stderr(&o)
    );
    // Said, with where: the held values are not measurements.
    assert!(
        stderr(&o).contains(&format!(
            "{}:7: `femur_r_imu` has no reading (nan) in 1 of 2 rows, the first here",
            walk.display()
        )),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// `--compare` prints every determined coordinate's RMSE and max against OpenSense's solution
/// (the same numbers as this file's own comparison) and `--figures` draws both.
#[test]
fn compare_prints_the_accuracy_table_and_draws_the_figure() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu", "compare");
    let out = tmp.join("angles.mot");
    let reference = dir.join("walking_gait2392_opensense_0-12s.sto");
    let figures = tmp.join("figures");
    let walk = dir.join("walking_orientations.sto");
    let pose = dir.join("placement_orientations.sto");
    let o = qgait(&[
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "--base-imu",
        "torso_imu",
        "-o",
        out.to_str().unwrap(),
        "--compare",
        reference.to_str().unwrap(),
        "--figures",
        figures.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = common::stdout(&o);
    let (ours, _) = MotionTable::read(&out).unwrap();
    let (theirs, _) = MotionTable::read(&reference).unwrap();
    assert!(table.contains("(1201 rows"), "{table}");
    // Every determined coordinate, none of the undetermined (MTP, translations: zero there).
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| `")).collect();
    assert_eq!(rows.len(), DETERMINED.len(), "{table}");
    for name in DETERMINED {
        let line = rows
            .iter()
            .find(|l| l.starts_with(&format!("| `{name}` |")))
            .unwrap_or_else(|| panic!("{name} not in {table}"));
        let numbers: Vec<f64> = line
            .split('|')
            .filter_map(|c| c.trim().parse().ok())
            .collect();
        let (a, b) = (ours.column(name).unwrap(), theirs.column(name).unwrap());
        let n = theirs.rows();
        let rmse = ((0..n).map(|r| (a[r] - b[r]).powi(2)).sum::<f64>() / n as f64).sqrt();
        let max = (0..n).map(|r| (a[r] - b[r]).abs()).fold(0.0, f64::max);
        assert!(
            (numbers[0] - rmse).abs() < 0.006,
            "{name}: {line} vs {rmse}"
        );
        assert!((numbers[1] - max).abs() < 0.006, "{name}: {line} vs {max}");
    }
    let png = std::fs::metadata(figures.join("imu_angles.png")).unwrap();
    assert!(png.len() > 10_000);
    assert!(figures.join("imu_angles.svg").is_file());
    let _ = std::fs::remove_dir_all(&tmp);
}
