//! `qgait imu` on the vendor exports OpenSense reads (Xsens MT Manager `.txt`, APDM `.csv`),
//! against the same files read by OpenSim 4.6's own `XsensDataReader` and `APDMDataReader`
//! (`host/tests/data/imu/vendor/`, made by `scripts/imu_vendor_files.py` from 1 s of the
//! tutorial recording), and their errors naming file, line and column.

mod common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use common::{qgait, stderr};
use qgait_opensim::mot::MotionTable;

fn vendor() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/imu/vendor")
}

/// Runs `qgait imu` (tutorial settings) and reads its output; panics with stderr on failure.
fn solve(walk: &Path, calibration: &Path, out: &Path, extra: &[&str]) -> MotionTable {
    common::run_imu(walk, calibration, out, extra);
    MotionTable::read(out).unwrap().0
}

/// The largest difference between two outputs (every column, time included).
fn largest_difference(a: &MotionTable, b: &MotionTable) -> f64 {
    assert_eq!(a.labels(), b.labels());
    assert_eq!(a.rows(), b.rows());
    let mut worst = 0.0f64;
    for l in a.labels() {
        for (x, y) in a.column(l).unwrap().iter().zip(b.column(l).unwrap()) {
            worst = worst.max((x - y).abs());
        }
    }
    worst
}

/// The failing run's stderr.
fn error(args: &[&str]) -> String {
    let o = qgait(args);
    assert!(!o.status.success(), "should fail: {args:?}");
    stderr(&o)
}

#[test]
fn xsens_trial_is_what_opensims_reader_reads() {
    let v = vendor();
    let tmp = common::scratch("imu-vendor", "xsens");
    let mapping = v.join("xsens/mappings.xml");
    let m = mapping.to_str().unwrap();
    let ours = solve(
        &v.join("xsens/walk-000"),
        &v.join("xsens/static-000"),
        &tmp.join("ours.mot"),
        &["--imu-mapping", m],
    );
    let opensim = solve(
        &v.join("xsens_walk_opensim.sto"),
        &v.join("xsens_static_opensim.sto"),
        &tmp.join("opensim.mot"),
        &[],
    );
    assert_eq!(ours.rows(), 100);
    let d = largest_difference(&ours, &opensim);
    assert!(d < 1e-9, "{d}");
    // The folder alone: the settings' trial prefix (walk-000).
    let folder = solve(
        &v.join("xsens"),
        &v.join("xsens/static-000"),
        &tmp.join("folder.mot"),
        &["--imu-mapping", m],
    );
    assert_eq!(largest_difference(&folder, &ours), 0.0);
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn apdm_csv_is_what_opensims_reader_reads() {
    let v = vendor();
    let tmp = common::scratch("imu-vendor", "apdm");
    let ours = solve(
        &v.join("apdm/walk.csv"),
        &v.join("apdm/static.csv"),
        &tmp.join("ours.mot"),
        &[
            "--imu-mapping",
            v.join("apdm/mappings.xml").to_str().unwrap(),
        ],
    );
    let opensim = solve(
        &v.join("apdm_walk_opensim.sto"),
        &v.join("apdm_static_opensim.sto"),
        &tmp.join("opensim.mot"),
        &[],
    );
    let d = largest_difference(&ours, &opensim);
    assert!(d < 1e-9, "{d}");
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Xsens files with quaternion columns (`Quat_q0`..) and no `Update Rate` comment, written
/// here from OpenSim's reading of the matrix files: the same angles with `--rate 100`, a clear
/// error without a rate.
#[test]
fn xsens_quaternion_columns_and_the_rate() {
    let v = vendor();
    let tmp = common::scratch("imu-vendor", "xsens-quat");
    let mapping = v.join("xsens/mappings.xml");
    let text = std::fs::read_to_string(&mapping).unwrap();
    let ids: Vec<(String, String)> = text
        .split("<ExperimentalSensor name=\"")
        .skip(1)
        .map(|s| {
            let id = s.split('"').next().unwrap().to_string();
            let name = s
                .split("<name_in_model>")
                .nth(1)
                .unwrap()
                .split('<')
                .next()
                .unwrap()
                .to_string();
            (id, name)
        })
        .collect();
    assert_eq!(ids.len(), 8);
    for trial in ["walk", "static"] {
        let sto = std::fs::read_to_string(v.join(format!("xsens_{trial}_opensim.sto"))).unwrap();
        let mut lines = sto.lines().skip_while(|l| *l != "endheader").skip(1);
        let labels: Vec<&str> = lines.next().unwrap().split('\t').collect();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split('\t').collect()).collect();
        for (id, name) in &ids {
            let c = labels.iter().position(|l| l == name).unwrap();
            let mut f = String::from("// Start Time: Unknown\nPacketCounter\tQuat_q0\tQuat_q1\tQuat_q2\tQuat_q3\tAcc_X\n");
            for (k, r) in rows.iter().enumerate() {
                writeln!(f, "{k}\t{}\t0.5", r[c].replace(',', "\t")).unwrap();
            }
            std::fs::write(tmp.join(format!("{trial}-000{id}.txt")), f).unwrap();
        }
    }
    let reference = solve(
        &v.join("xsens_walk_opensim.sto"),
        &v.join("xsens_static_opensim.sto"),
        &tmp.join("opensim.mot"),
        &[],
    );
    let m = mapping.to_str().unwrap();
    let walk = tmp.join("walk-000");
    let calibration = tmp.join("static-000");
    let ours = solve(
        &walk,
        &calibration,
        &tmp.join("ours.mot"),
        &["--imu-mapping", m, "--rate", "100"],
    );
    let d = largest_difference(&ours, &reference);
    assert!(d < 1e-9, "{d}");
    let e = error(&[
        "imu",
        walk.to_str().unwrap(),
        "--calibration",
        calibration.to_str().unwrap(),
        "--imu-mapping",
        m,
        "-o",
        tmp.join("x.mot").to_str().unwrap(),
    ]);
    assert!(e.contains("Update Rate") && e.contains("--rate"), "{e}");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn bad_vendor_files_name_file_line_and_column() {
    let v = vendor();
    let tmp = common::scratch("imu-vendor", "errors");
    // An Xsens folder copied, one value broken, one file cut short.
    let x = tmp.join("xsens");
    std::fs::create_dir_all(&x).unwrap();
    for e in std::fs::read_dir(v.join("xsens")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), x.join(e.file_name())).unwrap();
    }
    let m = x.join("mappings.xml");
    let broken = x.join("walk-000_00B4227B.txt");
    let text = std::fs::read_to_string(&broken).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // Line 9 (5 comments, labels, 2 samples): its first matrix value (column 12).
    let cells: Vec<&str> = lines[8].split('\t').collect();
    let column = cells[..11].iter().map(|c| c.len() + 1).sum::<usize>() + 1;
    lines[8] = lines[8].replacen(cells[11], "0.9x", 1);
    std::fs::write(&broken, lines.join("\n")).unwrap();
    let out = tmp.join("out.mot");
    let run = |walk: &Path, extra: &[&str]| {
        let mut args = vec![
            "imu",
            walk.to_str().unwrap(),
            "--calibration",
            x.join("static-000").to_str().unwrap().to_string().leak(),
            "-o",
            out.to_str().unwrap().to_string().leak(),
        ];
        args.extend_from_slice(extra);
        error(&args)
    };
    let walk = x.join("walk-000");
    let e = run(&walk, &["--imu-mapping", m.to_str().unwrap()]);
    let at = format!("{}:9:{column}", broken.display());
    assert!(e.contains(&at) && e.contains("Mat[1][1]"), "{at}: {e}");
    // Without the settings.
    let e = run(&walk, &[]);
    assert!(e.contains("--imu-mapping"), "{e}");
    // A file with fewer samples than the others.
    lines.truncate(50);
    lines[8] = text.lines().nth(8).unwrap().to_string();
    std::fs::write(&broken, lines.join("\n")).unwrap();
    let e = run(&walk, &["--imu-mapping", m.to_str().unwrap()]);
    assert!(
        e.contains("walk-000_00B4227B.txt") && e.contains("ends after 44 samples"),
        "{e}"
    );
    // A mapped sensor without its file.
    std::fs::remove_file(&broken).unwrap();
    let e = run(&walk, &["--imu-mapping", m.to_str().unwrap()]);
    assert!(e.contains("mappings.xml") && e.contains("no file"), "{e}");

    // APDM: a mapped sensor without orientation columns; a bad quaternion value.
    let apdm_map = tmp.join("apdm.xml");
    let map_text = std::fs::read_to_string(v.join("apdm/mappings.xml"))
        .unwrap()
        .replace("name=\"Lumbar\"", "name=\"Waist\"");
    std::fs::write(&apdm_map, map_text).unwrap();
    let csv = v.join("apdm/walk.csv");
    let e = error(&[
        "imu",
        csv.to_str().unwrap(),
        "--calibration",
        v.join("apdm/static.csv").to_str().unwrap(),
        "--imu-mapping",
        apdm_map.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(e.contains("apdm.xml") && e.contains("`Waist`"), "{e}");
    let bad = tmp.join("walk.csv");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // Line 6: the first sensor's orientation scalar, column 11 of the row.
    let cells: Vec<&str> = lines[5].split(',').collect();
    let column = cells[..10].iter().map(|c| c.len() + 1).sum::<usize>() + 1;
    lines[5] = {
        let mut c: Vec<String> = cells.iter().map(|s| s.to_string()).collect();
        c[10] = "w".into();
        c.join(",")
    };
    std::fs::write(&bad, lines.join("\n")).unwrap();
    let e = error(&[
        "imu",
        bad.to_str().unwrap(),
        "--calibration",
        v.join("apdm/static.csv").to_str().unwrap(),
        "--imu-mapping",
        v.join("apdm/mappings.xml").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let at = format!("{}:6:{column}", bad.display());
    assert!(
        e.contains(&at) && e.contains("Lumbar/Orientation/Scalar"),
        "{at}: {e}"
    );
    let _ = std::fs::remove_dir_all(&tmp);
}

/// APDM's `Format=7` layout (sensor names on the first line, 14 columns a sensor: acceleration,
/// angular velocity, magnetic field, pressure, orientation S, X, Y, Z), written here from
/// OpenSim's reading of the older layout: the same angles with `--rate 100`.
#[test]
fn apdm_format_7() {
    let v = vendor();
    let tmp = common::scratch("imu-vendor", "apdm7");
    let sensors = [
        ("Lumbar", "pelvis_imu"),
        ("Right Thigh", "femur_r_imu"),
        ("Right Shank", "tibia_r_imu"),
        ("Right Foot", "calcn_r_imu"),
        ("Left Thigh", "femur_l_imu"),
        ("Left Shank", "tibia_l_imu"),
        ("Left Foot", "calcn_l_imu"),
        ("Sternum", "torso_imu"),
    ];
    for trial in ["walk", "static"] {
        let sto = std::fs::read_to_string(v.join(format!("apdm_{trial}_opensim.sto"))).unwrap();
        let mut lines = sto.lines().skip_while(|l| *l != "endheader").skip(1);
        let labels: Vec<&str> = lines.next().unwrap().split('\t').collect();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split('\t').collect()).collect();
        let mut first = String::from("Format=7");
        let mut second = String::from("Time");
        let mut third = String::new();
        for (k, (apdm, _)) in sensors.iter().enumerate() {
            write!(first, ",I{},,,{apdm},,,,,,,,,,", k + 1).unwrap();
            second.push_str(",Accelerometer,,,Gyroscope,,,Magnetometer,,,Barometer,Orientation,,,");
            third.push_str(",X,Y,Z,X,Y,Z,X,Y,Z,,S,X,Y,Z");
        }
        let mut f = format!("{first}\n{second}\n{third}\n");
        for (r, row) in rows.iter().enumerate() {
            write!(f, "{}", r as f64 / 100.0).unwrap();
            for (_, name) in &sensors {
                let c = labels.iter().position(|l| l == name).unwrap();
                write!(f, ",0.1,0.2,9.8,0,0,0,20,5,-40,1013,{}", row[c]).unwrap();
            }
            f.push('\n');
        }
        std::fs::write(tmp.join(format!("{trial}.csv")), f).unwrap();
    }
    let reference = solve(
        &v.join("apdm_walk_opensim.sto"),
        &v.join("apdm_static_opensim.sto"),
        &tmp.join("opensim.mot"),
        &[],
    );
    let ours = solve(
        &tmp.join("walk.csv"),
        &tmp.join("static.csv"),
        &tmp.join("ours.mot"),
        &[
            "--imu-mapping",
            v.join("apdm/mappings.xml").to_str().unwrap(),
            "--rate",
            "100",
        ],
    );
    let d = largest_difference(&ours, &reference);
    assert!(d < 1e-9, "{d}");
    let _ = std::fs::remove_dir_all(&tmp);
}
