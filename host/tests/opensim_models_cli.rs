//! `qgait model import` and `fidelity` on the OpenSim lower-limb models qgait imports (the
//! models from ../shared/data/opensim/): the chain file written reads back exactly, locked
//! coordinates are ignored saying so, and `fidelity --model` on them. The models against OpenSim
//! itself, through the library: `crates/qgait-model/tests/opensim_models.rs`.

mod common;

use std::path::Path;

use common::{parse_fk_csv, qgait, shared_dir, stderr, stdout};
use qgait_kernel::models::gait2392::{COORDINATES, POINTS};
use qgait_kernel::Vec3;
use qgait_model::choice::Model;

/// The reference rows of `scripts/opensim_reference.py` (in qgait-model's test data):
/// coordinates (COORDINATES order) and the 12 points (POINTS order).
fn reference(name: &str, motion: &str) -> Vec<([f64; 17], [Vec3<f64>; 12])> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!(
        "../crates/qgait-model/tests/data/opensim_reference/{name}_{motion}.csv"
    ));
    let text = std::fs::read_to_string(&path).unwrap();
    let (header, rows) = parse_fk_csv(&text);
    let header: Vec<&str> = header.split(',').collect();
    for (i, c) in COORDINATES.iter().enumerate() {
        assert_eq!(header[1 + i], *c);
    }
    for (i, p) in POINTS.iter().enumerate() {
        assert_eq!(header[18 + 3 * i], format!("{p}_x"));
    }
    rows.iter()
        .map(|r| {
            let q = std::array::from_fn(|i| r[1 + i]);
            let p = std::array::from_fn(|i| Vec3::new(r[18 + 3 * i], r[19 + 3 * i], r[20 + 3 * i]));
            (q, p)
        })
        .collect()
}

/// The 12 points of a loaded model for coordinates `q`.
fn points(model: &Model) -> qgait_model::points::ImportedFk {
    qgait_model::points::imported_fk(model)
        .unwrap()
        .expect("an imported model")
}

#[test]
fn model_import_writes_a_chain_file_that_fk_reads_back_exactly() {
    let Some(shared) = shared_dir() else { return };
    let dir = std::env::temp_dir().join(format!("qgait-chain-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let osim = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    let toml = dir.join("rajagopal.toml");
    let out = qgait(&[
        "model",
        "import",
        osim.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&toml).unwrap();
    assert!(
        text.contains("[[joints]]") && text.contains("walker_knee_r"),
        "{text}"
    );
    let (from_file, _) = Model::load(toml.to_str().unwrap(), None).unwrap();
    let (from_osim, _) = Model::load(osim.to_str().unwrap(), None).unwrap();
    let (a, b) = (points(&from_file), points(&from_osim));
    for (q, _) in reference("rajagopal2015_opensense", "sweep") {
        assert_eq!(a(&q), b(&q));
    }
    let motion = shared.join("data/opensim/normal.mot");
    for model in [toml.to_str().unwrap(), osim.to_str().unwrap()] {
        let csv = dir.join("fk.csv");
        let _ = std::fs::remove_file(&csv);
        let out = qgait(&[
            "fk",
            motion.to_str().unwrap(),
            "--model",
            model,
            "--points",
            "-o",
            csv.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let (header, rows) = parse_fk_csv(&std::fs::read_to_string(&csv).unwrap());
        assert!(header.ends_with(",mtp_l_x,mtp_l_y,mtp_l_z"), "{header}");
        assert_eq!(rows.len(), 51);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_column_of_a_coordinate_the_model_locks_is_ignored_saying_so() {
    // OpenSense's Rajagopal locks the subtalar and MTP joints: their columns move nothing.
    let Some(shared) = shared_dir() else { return };
    let osim = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    let dir = tempfile::tempdir().unwrap();
    let head = "x\nversion=1\nnRows=2\nnColumns=9\ninDegrees=yes\nendheader\n\
                time\thip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l";
    let with = dir.path().join("with.mot");
    let without = dir.path().join("without.mot");
    std::fs::write(
        &with,
        format!("{head}\tsubtalar_angle_r\tmtp_angle_r\n0\t10\t20\t0\t0\t5\t0\t0\t0\n1\t10\t20\t0\t0\t5\t0\t15\t20\n"),
    )
    .unwrap();
    std::fs::write(
        &without,
        format!("{head}\n0\t10\t20\t0\t0\t5\t0\n1\t10\t20\t0\t0\t5\t0\n"),
    )
    .unwrap();
    let fk = |motion: &Path| {
        let out = qgait(&[
            "fk",
            motion.to_str().unwrap(),
            "--model",
            osim.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        (stdout(&out), stderr(&out))
    };
    let (points, err) = fk(&with);
    assert_eq!(points, fk(&without).0);
    // The first value other than 0 and its line; nothing said of the left columns, absent
    // but locked as well.
    assert!(
        err.contains("column `subtalar_angle_r` ignored: the model does not move with it")
            && err.contains("(the first other than 0: 15.00° at line 9)")
            && err.contains("column `mtp_angle_r` ignored"),
        "{err}"
    );
    assert!(
        !err.contains("no `subtalar_angle_l`") && !err.contains("no `mtp_angle_l`"),
        "{err}"
    );
    assert!(err.contains("no `pelvis_tilt` column"), "{err}");
}

#[test]
fn fidelity_compares_phak_with_imported_models_and_agrees_with_its_gait2392_summary() {
    let Some(shared) = shared_dir() else { return };
    let raj = shared.join("data/opensim/Rajagopal2016.osim");
    let out = qgait(&[
        "-q",
        "fidelity",
        "builtin:normal",
        "--model",
        "gait2392",
        "--model",
        raj.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let md = String::from_utf8(out.stdout).unwrap();
    // The summary's gait2392 row (raw max .. hip-relative mean) is the `--model gait2392` row's.
    let summary = md
        .lines()
        .find(|l| l.starts_with("| builtin:normal |"))
        .expect("summary row");
    let numbers = |l: &str| -> Vec<String> {
        l.split('|')
            .map(|c| c.trim().to_string())
            .filter(|c| !c.is_empty())
            .collect()
    };
    let s = numbers(summary);
    let g = numbers(
        md.lines()
            .find(|l| l.starts_with("| gait2392 | builtin:normal |"))
            .expect("gait2392 comparison row"),
    );
    assert_eq!(
        s[1..6],
        g[2..3].iter().chain(&g[4..8]).cloned().collect::<Vec<_>>()[..]
    );
    let r = numbers(
        md.lines()
            .find(|l| l.contains("Rajagopal2016.osim | builtin:normal |"))
            .expect("Rajagopal row"),
    );
    assert_eq!(r[3], "yes", "Rajagopal's knee flexes with positive angles");
    let hip_relative_max: f64 = r[6].parse().unwrap();
    assert!(hip_relative_max > 1.0 && hip_relative_max < 200.0, "{r:?}");
}

#[test]
fn fidelity_model_refuses_a_stick_model() {
    let out = qgait(&["-q", "fidelity", "builtin:normal,rows=5", "--model", "phak"]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("fidelity --model takes an OpenSim leg chain"),
        "{}",
        stderr(&out)
    );
}
