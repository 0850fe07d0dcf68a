//! OpenSim files read as OpenSim 4.6 reads them, and the command-line edges around them: units
//! per header version, implausible angles, what OpenSim accepts (duplicated or `nan` columns a
//! model does not use, a repeated last time, Latin-1 comments), `.osim` models wherever a model
//! is accepted, outputs that would overwrite an input, one default model, marker files.

mod common;

use std::path::Path;

use common::{parse_fk_csv, qgait, shared_dir, stderr, stdout};

const LABELS: &str = "time\tpelvis_list\tpelvis_rotation\thip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l";
const ROWS_DEG: [[f64; 9]; 3] = [
    [0.0, -0.47, 2.43, 24.61, -3.94, -1.7, -16.56, -8.2, 9.81],
    [0.02, -0.87, 2.56, 24.45, -66.6, -3.25, -16.82, -11.29, 8.26],
    [0.04, -1.4, 2.52, 24.13, -9.45, -4.68, -16.53, -15.19, 5.52],
];

/// The rows, tab separated, in degrees or radians, with `extra` appended to each row.
fn rows(radians: bool, extra: &str) -> String {
    ROWS_DEG
        .iter()
        .map(|r| {
            let v: Vec<String> = r
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    if radians && i > 0 {
                        v.to_radians().to_string()
                    } else {
                        v.to_string()
                    }
                })
                .collect();
            format!("{}{extra}\n", v.join("\t"))
        })
        .collect()
}

fn degrees_mot() -> String {
    format!(
        "walk\nversion=1\nnRows=3\nnColumns=9\ninDegrees=yes\nendheader\n{LABELS}\n{}",
        rows(false, "")
    )
}

fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> String {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p.to_str().unwrap().to_string()
}

fn run_ok(args: &[&str]) -> (String, String) {
    let out = qgait(args);
    assert!(out.status.success(), "qgait {args:?}: {}", stderr(&out));
    (stdout(&out), stderr(&out))
}

fn fk_rows(args: &[&str]) -> (Vec<Vec<f64>>, String) {
    let (out, err) = run_ok(args);
    (parse_fk_csv(&out).1, err)
}

fn assert_close(a: &[Vec<f64>], b: &[Vec<f64>], tol: f64) {
    assert_eq!(a.len(), b.len());
    for (ra, rb) in a.iter().zip(b) {
        for (x, y) in ra.iter().zip(rb) {
            assert!((x - y).abs() <= tol, "{x} vs {y}");
        }
    }
}

#[test]
fn an_opensim4_sto_without_indegrees_is_radians_as_opensim_reads_it() {
    let dir = tempfile::tempdir().unwrap();
    let deg = write(dir.path(), "deg.mot", degrees_mot());
    let sto = write(
        dir.path(),
        "rad.sto",
        format!(
            "DataType=double\nversion=3\nOpenSimVersion=4.5\nendheader\n{LABELS}\n{}",
            rows(true, "")
        ),
    );
    let (expected, _) = fk_rows(&["fk", &deg]);
    let (got, err) = fk_rows(&["fk", &sto]);
    assert_close(&got, &expected, 1e-12);
    assert!(
        err.contains("read as radians, as OpenSim reads a `version=3` file"),
        "{err}"
    );
    // A header with no version (the SIMM style) is still degrees, as OpenSim reads it.
    let simm = write(
        dir.path(),
        "simm.mot",
        format!(
            "walk\ndatacolumns 9\ndatarows 3\nrange 0 0.04\nendheader\n{LABELS}\n{}",
            rows(false, "")
        ),
    );
    let (got, _) = fk_rows(&["fk", &simm]);
    assert_close(&got, &expected, 1e-12);
}

#[test]
fn degrees_under_indegrees_no_are_warned_naming_file_and_columns() {
    let dir = tempfile::tempdir().unwrap();
    let cmc = write(
        dir.path(),
        "Kinematics_q.sto",
        format!(
            "Coordinates\nversion=1\nnRows=3\nnColumns=9\ninDegrees=no\nendheader\n{LABELS}\n{}",
            rows(false, "")
        ),
    );
    let (_, err) = fk_rows(&["fk", &cmc]);
    assert!(
        err.contains(&format!(
            "{cmc}: column `knee_angle_r`: 3 of 3 values outside its range"
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "{cmc}: the angles are read as radians (the header does not say inDegrees=yes)"
        )) && err.contains("set inDegrees=yes"),
        "{err}"
    );
    // The same rows in degrees under inDegrees=yes are all plausible: no range warning.
    let ok = write(dir.path(), "ok.mot", degrees_mot());
    let (_, err) = fk_rows(&["fk", &ok]);
    assert!(!err.contains("range"), "{err}");
}

#[test]
fn an_angle_outside_its_range_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    let text = degrees_mot()
        .replace("\t-66.6\t", "\t-200\t")
        .replace("\t-15.19\t", "\t1e300\t");
    let m = write(dir.path(), "wild.mot", text);
    for model in ["phak", "hak", "gait2392"] {
        let (_, err) = fk_rows(&["fk", &m, "--model", model]);
        assert!(
            err.contains(&format!("{m}: column `knee_angle_r`: 1 of 3 values outside its range -120..10° (± 10°), the first -200.00° at line 9")),
            "{model}: {err}"
        );
        assert!(
            err.contains(&format!("{m}: column `knee_angle_l`: 1 of 3 values outside its range -120..10° (± 10°), the first 1e300° at line 10")),
            "{model}: {err}"
        );
    }
    let (_, err) = run_ok(&[
        "packets",
        &m,
        "-o",
        &dir.path().join("p.bin").to_string_lossy(),
    ]);
    assert!(err.contains("column `knee_angle_r`: 1 of 3"), "{err}");
}

#[test]
fn what_opensim_reads_is_read_with_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let (expected, _) = fk_rows(&["fk", &write(dir.path(), "plain.mot", degrees_mot())]);
    // IK + GRF + markers merged: `ground_force_vx` twice, a marker column with nan, the last
    // time written twice and a Latin-1 comment in the header.
    let mut text = format!(
        "walk\nversion=1\nnRows=4\nnColumns=12\ninDegrees=yes\nMesures de l'\u{1}quipe\nendheader\n{LABELS}\tground_force_vx\tground_force_vx\tR.Heel_x\n{}",
        rows(false, "\t1\t2\t0.5")
    );
    let last = text.lines().last().unwrap().to_string();
    text.push_str(&format!("{last}\n"));
    let text = text.replacen("\t0.5\n", "\tnan\n", 1);
    let mut bytes = text.into_bytes();
    let at = bytes.iter().position(|&b| b == 1).unwrap();
    bytes[at] = 0xE9; // Latin-1 é
    let m = write(dir.path(), "merged.mot", bytes);
    let (got, err) = fk_rows(&["fk", &m]);
    assert_close(&got, &expected, 0.0);
    for said in [
        "not UTF-8; read as Latin-1",
        "column `ground_force_vx` appears more than once",
        "repeats the previous row's (line 11); this row replaces it",
    ] {
        assert!(err.contains(said), "{said}: {err}");
    }
    // A model that needs the duplicated or nan column refuses, naming file, line and column.
    let dup = std::fs::read(&m).unwrap();
    let dup = String::from_utf8_lossy(&dup).replace(
        "\tground_force_vx\tground_force_vx",
        "\tknee_angle_l\tground_force_vx",
    );
    let out = qgait(&["fk", &write(dir.path(), "dup.mot", dup)]);
    assert!(!out.status.success());
    assert!(
        stderr(&out)
            .contains("column `knee_angle_l` appears more than once and the model needs it"),
        "{}",
        stderr(&out)
    );
    let nan = degrees_mot().replace("\t-66.6\t", "\tNaN\t");
    let nan = write(dir.path(), "nan.mot", nan);
    let out = qgait(&["fk", &nan]);
    assert!(!out.status.success());
    assert_eq!(
        stderr(&out).trim_end(),
        format!("error: {nan}:9:23: value `NaN` in column `knee_angle_r` is not a finite number, and the model needs this column")
    );
}

#[test]
fn an_osim_model_is_accepted_wherever_a_model_is() {
    let Some(shared) = shared_dir() else { return };
    let osim = shared.join("data/opensim/gait2392_simbody.osim");
    let osim = osim.to_str().unwrap();
    let motion = "builtin:normal,rows=7";
    let (generic, _) = fk_rows(&["fk", motion, "--model", "gait2392"]);
    let (imported, err) = fk_rows(&["fk", motion, "--model", osim]);
    assert_close(&imported, &generic, 1e-12);
    assert!(err.contains("note: toe tip"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let sto = dir.path().join("x.sto");
    run_ok(&[
        "-q",
        "export",
        motion,
        "--model",
        osim,
        "--sto",
        sto.to_str().unwrap(),
    ]);
    let cfg = qgait(&[
        "config",
        "--model",
        osim,
        "-o",
        dir.path().join("c.bin").to_str().unwrap(),
    ]);
    assert!(cfg.status.success(), "{}", stderr(&cfg));
}

#[test]
fn an_output_that_is_also_an_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let text = degrees_mot();
    let m = write(dir.path(), "x.mot", &text);
    let same_by_another_name = format!("{}/./x.mot", dir.path().display());
    for args in [
        vec!["fk", &m, "-o", &m],
        vec!["fk", &m, "-o", &same_by_another_name],
        vec!["motion", &m, "-o", &m],
        vec!["export", &m, "--trc", &m],
        vec!["export", &m, "--sto", &m],
        vec!["packets", &m, "-o", &m],
        vec!["fidelity", &m, "-o", &m],
        vec!["emulate", &m, "--frames-csv", &m],
        vec!["emulate", &m, "--log", &m],
        vec!["config", "--model", "phak", "--anthropometry", &m, "-o", &m],
    ] {
        let out = qgait(&args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains("this output is also an input"),
            "{args:?}: {}",
            stderr(&out)
        );
        assert_eq!(std::fs::read_to_string(&m).unwrap(), text, "{args:?}");
    }
}

#[test]
fn one_file_given_as_two_outputs_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let m = write(dir.path(), "x.mot", degrees_mot());
    let old = write(dir.path(), "b.out", "old\n");
    let same_by_another_name = format!("{}/./b.out", dir.path().display());
    let new = dir.path().join("new.out");
    let new = new.to_str().unwrap();
    let in_new_dir = dir.path().join("d/f.out");
    let in_new_dir = in_new_dir.to_str().unwrap();
    for args in [
        vec!["export", &m, "--trc", &old, "--sto", &old],
        vec!["export", &m, "--trc", &old, "--sto", &same_by_another_name],
        vec!["export", &m, "--trc", new, "--sto", new],
        vec!["emulate", &m, "--frames-csv", &old, "--log", &old],
        vec![
            "emulate",
            &m,
            "--frames-csv",
            in_new_dir,
            "--log",
            in_new_dir,
        ],
    ] {
        let out = qgait(&args);
        assert!(!out.status.success(), "{args:?}");
        assert!(
            stderr(&out).contains("given as two outputs"),
            "{args:?}: {}",
            stderr(&out)
        );
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "old\n", "{args:?}");
        assert!(!Path::new(new).exists(), "{args:?}");
        assert!(!dir.path().join("d").exists(), "{args:?}");
    }
    // /dev/null is not a file one output would replace: given twice, it is taken.
    let o = qgait(&["export", &m, "--trc", "/dev/null", "--sto", "/dev/null"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn export_and_fk_default_to_the_same_model() {
    let dir = tempfile::tempdir().unwrap();
    let motion = "builtin:crouch=0.3,rows=5";
    let default = dir.path().join("d.sto");
    let phak = dir.path().join("p.sto");
    run_ok(&["-q", "export", motion, "--sto", default.to_str().unwrap()]);
    run_ok(&[
        "-q",
        "export",
        motion,
        "--model",
        "phak",
        "--sto",
        phak.to_str().unwrap(),
    ]);
    let (d, p) = (
        std::fs::read_to_string(&default).unwrap(),
        std::fs::read_to_string(&phak).unwrap(),
    );
    assert_eq!(d, p);
    // ... which is what `fk` computes by default.
    let (fk, _) = fk_rows(&["-q", "fk", motion]);
    let first: Vec<f64> = d
        .lines()
        .nth(5)
        .unwrap()
        .split('\t')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(first, fk[0]);
}

#[test]
fn a_marker_file_given_as_a_motion_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let trc = dir.path().join("walk.trc");
    run_ok(&[
        "-q",
        "export",
        "builtin:normal,rows=3",
        "--trc",
        trc.to_str().unwrap(),
    ]);
    let out = qgait(&["fk", trc.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        stderr(&out)
            .contains("walk.trc:1: this is a marker file (.trc: marker positions), not a motion"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn an_error_deep_in_a_motion_leaves_no_truncated_output() {
    let dir = tempfile::tempdir().unwrap();
    // 20,000 good rows (more than any write buffer), then a bad number.
    let mut text = String::from("walk\nversion=1\ninDegrees=yes\nendheader\n");
    text.push_str(LABELS);
    text.push('\n');
    for r in 0..20_000 {
        text.push_str(&format!(
            "{}\t0\t0\t10\t-20\t5\t-10\t-30\t0\n",
            r as f64 * 0.01
        ));
    }
    text.push_str("200\t0\t0\t1O\t-20\t5\t-10\t-30\t0\n");
    let m = write(dir.path(), "bad.mot", text);
    let csv = dir.path().join("out.csv");
    std::fs::write(&csv, "earlier\n").unwrap();
    let out = qgait(&["fk", &m, "-o", csv.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("bad.mot:20006:9: bad number `1O`"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(&csv).unwrap(), "earlier\n");
    let left: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 2, "{left:?}");
    // A good run replaces the file.
    let good = write(dir.path(), "good.mot", degrees_mot());
    run_ok(&["fk", &good, "-o", csv.to_str().unwrap()]);
    assert!(std::fs::read_to_string(&csv).unwrap().starts_with("time,"));
}
