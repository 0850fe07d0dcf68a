//! `qgait fk`: the CSV contract and the reading of OpenSim motion files, end to end.

mod common;

use std::path::Path;

use common::{parse_fk_csv, qgait, stderr, stdout};

/// The header required by the issue, byte for byte.
const HEADER: &str = "time,hip_r_x,hip_r_y,hip_r_z,knee_r_x,knee_r_y,knee_r_z,ankle_r_x,ankle_r_y,ankle_r_z,toe_r_x,toe_r_y,toe_r_z,hip_l_x,hip_l_y,hip_l_z,knee_l_x,knee_l_y,knee_l_z,ankle_l_x,ankle_l_y,ankle_l_z,toe_l_x,toe_l_y,toe_l_z\n";

const COLUMNS: &str = "time\tpelvis_list\tpelvis_rotation\thip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l";
const ROWS_DEG: [[f64; 9]; 3] = [
    [0.0, -0.47, 2.43, 24.61, -3.94, -1.7, -16.56, -8.2, 9.81],
    [0.02, -0.87, 2.56, 24.45, -6.66, -3.25, -16.82, -11.29, 8.26],
    [0.04, -1.4, 2.52, 24.13, -9.45, -4.68, -16.53, -15.19, 5.52],
];

fn rows_text(radians: bool, sep: &str) -> String {
    ROWS_DEG
        .iter()
        .map(|r| {
            r.iter()
                .enumerate()
                .map(|(i, v)| {
                    if radians && i > 0 {
                        v.to_radians().to_string()
                    } else {
                        v.to_string()
                    }
                })
                .collect::<Vec<_>>()
                .join(sep)
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

fn fk_ok(args: &[&str]) -> (String, Vec<Vec<f64>>, String) {
    let out = qgait(args);
    assert!(
        out.status.success(),
        "qgait {args:?} failed: {}",
        stderr(&out)
    );
    let (h, rows) = parse_fk_csv(&stdout(&out));
    (h, rows, stderr(&out))
}

#[test]
fn header_is_the_contract_and_numbers_round_trip() {
    let out = qgait(&["fk", "builtin:normal,rows=5"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.starts_with(HEADER),
        "header differs:\n{}",
        text.lines().next().unwrap()
    );
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + 5);
    for line in &lines[1..] {
        let fields: Vec<&str> = line.split(',').collect();
        assert_eq!(fields.len(), 25);
        for f in fields {
            let v: f64 = f.parse().unwrap();
            // Shortest round-trip representation: printing the value again gives the same text.
            assert_eq!(v.to_string(), f);
        }
    }
    // -o writes the same bytes to a file.
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("out.csv");
    let out2 = qgait(&["fk", "builtin:normal,rows=5", "-o", csv.to_str().unwrap()]);
    assert!(out2.status.success(), "{}", stderr(&out2));
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), text);
}

#[test]
fn both_header_styles_tabs_or_spaces_give_the_same_positions() {
    let dir = tempfile::tempdir().unwrap();
    let nrows = write(
        dir.path(),
        "a.mot",
        &format!(
            "g\nversion=1\nnRows=3\nnColumns=9\ninDegrees=yes\nendheader\n{COLUMNS}\n{}\n",
            rows_text(false, "\t")
        ),
    );
    let datarows = write(
        dir.path(),
        "b.mot",
        &format!(
            "g\ndatacolumns 9\ndatarows 3\nrange 0 0.04\nendheader\n{}\n{}\n",
            COLUMNS.replace('\t', "   "),
            rows_text(false, "  ")
        ),
    );
    let (_, a, _) = fk_ok(&["fk", &nrows]);
    let (_, b, warn_b) = fk_ok(&["fk", &datarows]);
    assert_eq!(a, b);
    assert_eq!(a.len(), 3);
    assert!(warn_b.contains("inDegrees"), "{warn_b}");
}

#[test]
fn wrong_nrows_warns_and_uses_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        dir.path(),
        "a.mot",
        &format!(
            "g\nversion=1\nnRows=120\nnColumns=9\ninDegrees=yes\nendheader\n{COLUMNS}\n{}\n",
            rows_text(false, "\t")
        ),
    );
    let (_, rows, warn) = fk_ok(&["fk", &f]);
    assert_eq!(rows.len(), 3);
    assert!(
        warn.contains("nRows=120") && warn.contains("3 data rows"),
        "{warn}"
    );
    let quiet = qgait(&["--quiet", "fk", &f]);
    assert!(quiet.status.success());
    assert_eq!(stderr(&quiet), "", "--quiet prints no warnings");
}

#[test]
fn radians_and_degrees_give_the_same_positions() {
    let dir = tempfile::tempdir().unwrap();
    let head = |deg: &str| {
        format!("g\nversion=1\nnRows=3\nnColumns=9\ninDegrees={deg}\nendheader\n{COLUMNS}\n")
    };
    let deg = write(
        dir.path(),
        "deg.mot",
        &format!("{}{}\n", head("yes"), rows_text(false, "\t")),
    );
    let rad = write(
        dir.path(),
        "rad.sto",
        &format!("{}{}\n", head("no"), rows_text(true, "\t")),
    );
    let (_, a, _) = fk_ok(&["fk", &deg]);
    let (_, b, _) = fk_ok(&["fk", &rad]);
    for (ra, rb) in a.iter().zip(&b) {
        for (x, y) in ra.iter().zip(rb) {
            assert!((x - y).abs() < 1e-12, "{x} vs {y}");
        }
    }
    // And a file in degrees read as radians would differ: the flag is honoured.
    let wrong = write(
        dir.path(),
        "wrong.mot",
        &format!("{}{}\n", head("no"), rows_text(false, "\t")),
    );
    let (_, c, _) = fk_ok(&["fk", &wrong]);
    assert!((c[0][4] - a[0][4]).abs() > 0.01);
}

#[test]
fn bad_number_is_one_error_line_with_file_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!(
        "g\nversion=1\nnRows=3\nnColumns=9\ninDegrees=yes\nendheader\n{COLUMNS}\n{}\n",
        rows_text(false, "\t").replace("24.45", "24,45")
    );
    let f = write(dir.path(), "bad.mot", &text);
    let out = qgait(&["fk", &f]);
    assert!(!out.status.success());
    let err = stderr(&out);
    // Line 9 is the second data row; `24,45` starts after "0.02\t-0.87\t2.56\t", at character 17.
    assert_eq!(err, format!("error: {f}:9:17: bad number `24,45` in column `hip_flexion_r` (expected a finite decimal number)\n"));
    assert!(stdout(&out).is_empty());
}

#[test]
fn missing_required_column_is_an_error_and_missing_pelvis_is_zero_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let no_knee = write(
        dir.path(),
        "noknee.mot",
        "g\ninDegrees=yes\nendheader\ntime\thip_flexion_r\n0\t1\n1\t2\n",
    );
    let out = qgait(&["fk", &no_knee]);
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.starts_with(&format!(
            "error: {no_knee}:4: missing required column(s) knee_angle_r, ankle_angle_r"
        )),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");

    let legs_only = COLUMNS.replace("pelvis_list\tpelvis_rotation\t", "");
    let rows: String = ROWS_DEG
        .iter()
        .map(|r| {
            let v: Vec<String> = [r[0], r[3], r[4], r[5], r[6], r[7], r[8]]
                .iter()
                .map(|x| x.to_string())
                .collect();
            v.join("\t") + "\n"
        })
        .collect();
    let f = write(
        dir.path(),
        "legs.mot",
        &format!("g\ninDegrees=yes\nendheader\n{legs_only}\n{rows}"),
    );
    let (_, got, warn) = fk_ok(&["fk", &f]);
    assert!(
        warn.contains("no `pelvis_rotation` column; taken as 0")
            && warn.contains("no `pelvis_list` column"),
        "{warn}"
    );
    // Pelvis angles zero: the hips sit exactly on the z axis at +/- the gait2392 half width.
    assert_eq!(&got[0][1..4], &[0.0, 0.0, 0.0835]);
    assert_eq!(&got[0][13..16], &[0.0, 0.0, -0.0835]);
}

/// HAK is the hub's HAK: each leg a sagittal chain hung at its hip, the hips at +/- the pelvis
/// half-width on the z axis (PHAK with a level pelvis), so its points compare with PHAK's and
/// with the hub's HAK frames.
#[test]
fn hak_hangs_each_leg_at_its_hip_at_plus_minus_the_half_width() {
    let (_, rows, _) = fk_ok(&["fk", "builtin:crouch=0.3,rows=7", "--model", "hak"]);
    for r in &rows {
        for (side, z) in [(0, 0.0835), (1, -0.0835)] {
            let o = 1 + 12 * side;
            assert_eq!(&r[o..o + 3], &[0.0, 0.0, z]);
            for joint in 0..4 {
                assert_eq!(
                    r[o + 3 * joint + 2],
                    z,
                    "HAK's legs are in the planes z = +/-w"
                );
            }
            // Femur length is preserved: |knee - hip| = 0.395846 (gait2392).
            let k = &r[o + 3..o + 6];
            assert!(((k[0] * k[0] + k[1] * k[1]).sqrt() - 0.395846).abs() < 1e-12);
        }
    }
}

#[test]
fn anthropometry_file_changes_the_lengths() {
    let dir = tempfile::tempdir().unwrap();
    let toml = write(
        dir.path(),
        "a.toml",
        "pelvis_half_width = 0.1\nfemur_r = 0.5\nfemur_l = 0.3\ntibia = 0.4\nfoot = 0.2\n",
    );
    let (_, rows, _) = fk_ok(&[
        "fk",
        "builtin:normal,rows=3",
        "--model",
        "hak",
        "--anthropometry",
        &toml,
    ]);
    let femur = |r: &Vec<f64>, o: usize| (r[o + 3].powi(2) + r[o + 4].powi(2)).sqrt();
    assert!((femur(&rows[1], 1) - 0.5).abs() < 1e-12);
    assert!((femur(&rows[1], 13) - 0.3).abs() < 1e-12);
    let (_, phak, _) = fk_ok(&["fk", "builtin:normal,rows=3", "--anthropometry", &toml]);
    let hip = &phak[0][1..4];
    assert!(((hip[0].powi(2) + hip[1].powi(2) + hip[2].powi(2)).sqrt() - 0.1).abs() < 1e-12);

    let bad = write(dir.path(), "bad.toml", "femur = 0.4\nfemur_l = 0.4\n");
    let out = qgait(&["fk", "builtin:normal", "--anthropometry", &bad]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).starts_with(&format!("error: {bad}:2:11: both `femur` and `femur_l`")),
        "{}",
        stderr(&out)
    );
}

#[test]
fn builtin_gait_written_as_mot_gives_the_same_fk() {
    let dir = tempfile::tempdir().unwrap();
    let mot = dir.path().join("crouch.mot");
    let out = qgait(&[
        "motion",
        "builtin:crouch=0.6,rows=21",
        "-o",
        mot.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let (_, from_file, warn) = fk_ok(&["fk", mot.to_str().unwrap()]);
    let (_, direct, _) = fk_ok(&["fk", "builtin:crouch=0.6,rows=21"]);
    assert_eq!(from_file, direct);
    assert_eq!(warn, "");
    assert_eq!(direct.len(), 21);
    assert_eq!(direct[0][0], 0.0);
    assert_eq!(direct[20][0], 1.0);
}

#[test]
fn builtin_gait_is_a_plausible_cycle() {
    let (_, normal, _) = fk_ok(&["fk", "builtin:normal"]);
    let (_, crouch, _) = fk_ok(&["fk", "builtin:crouch=1"]);
    assert_eq!(normal.len(), 101);
    // Periodic: the last row repeats the first.
    for (a, b) in normal[0][1..].iter().zip(&normal[100][1..]) {
        assert!((a - b).abs() < 1e-12);
    }
    // Left limb = right limb half a cycle later: the pelvis-relative knee heights match.
    assert!((normal[0][5] - normal[50][17]).abs() < 1e-9);
    // Crouch brings the ankles up (shorter effective leg): mean ankle height higher.
    let mean_ankle_y =
        |rows: &[Vec<f64>]| rows.iter().map(|r| r[8]).sum::<f64>() / rows.len() as f64;
    assert!(mean_ankle_y(&crouch) > mean_ankle_y(&normal) + 0.05);
    // Normal gait: the ankle stays below 0.65 m under the pelvis origin all cycle long.
    assert!(
        normal.iter().all(|r| r[8] < -0.65),
        "ankle too high in normal gait"
    );
}

#[test]
fn errors_are_one_line_and_non_zero() {
    for args in [
        vec!["fk", "/no/such/file.mot"],
        vec!["fk", "builtin:crouch=2"],
        vec!["fk", "builtin:run"],
        vec![
            "report",
            "builtin:normal",
            "--label",
            "a",
            "--label",
            "b",
            "-o",
            "/tmp/qgait-never",
        ],
    ] {
        let out = qgait(&args);
        assert!(!out.status.success(), "{args:?}");
        let err = stderr(&out);
        assert!(
            err.starts_with("error: ") && err.lines().count() == 1,
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"));
    }
}

/// A motion that moves coordinates the model does not have (PHAK: no pelvis tilt, hip
/// adduction or rotation) gets one warning naming them and the model that has them; the
/// joint centres are PHAK's all the same. gait2392 has them all: no such warning.
#[test]
fn coordinates_the_model_lacks_are_named_in_one_warning() {
    let dir = tempfile::tempdir().unwrap();
    let columns = format!("{COLUMNS}\thip_adduction_r\tpelvis_tilt\thip_rotation_l");
    let rows: String = ROWS_DEG
        .iter()
        .map(|r| {
            let v: Vec<String> = r.iter().map(|x| x.to_string()).collect();
            format!("{}\t0\t0\t0\n", v.join("\t"))
        })
        .collect();
    let still = write(
        dir.path(),
        "still.mot",
        &format!("g\ninDegrees=yes\nendheader\n{columns}\n{rows}"),
    );
    let moving_rows = rows.replacen("\t0\t0\t0\n", "\t-4.9\t0\t7.5\n", 2);
    let moving = write(
        dir.path(),
        "moving.mot",
        &format!("g\ninDegrees=yes\nendheader\n{columns}\n{moving_rows}"),
    );
    let (_, base, warn) = fk_ok(&["fk", &still]);
    assert!(!warn.contains("does not have"), "{warn}");
    let (_, got, warn) = fk_ok(&["fk", &moving]);
    assert_eq!(got, base, "PHAK's joint centres do not depend on them");
    let lines: Vec<&str> = warn
        .lines()
        .filter(|l| l.contains("does not have"))
        .collect();
    assert_eq!(lines.len(), 1, "{warn}");
    assert!(
        lines[0].contains("`hip_adduction_r` (-4.90° at line 5)")
            && lines[0].contains("`hip_rotation_l` (7.50° at line 5)")
            && !lines[0].contains("pelvis_tilt")
            && lines[0].contains("--model gait2392"),
        "{warn}"
    );
    let (_, _, warn) = fk_ok(&["fk", &moving, "--model", "gait2392"]);
    assert!(!warn.contains("does not have"), "{warn}");
}
