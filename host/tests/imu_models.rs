//! `qgait imu` with the models other than gait2392: PHAK solved on its own axes (synthetic
//! truth through the whole CLI path; the tutorial recording read back by `fk --model phak`) and
//! an imported chain (Rajagopal2015_opensense, OpenSense's own model) against OpenSense's own
//! Rajagopal solution of the tutorial recording (`host/tests/data/imu/`, made by
//! `scripts/opensense_rajagopal_ik.py`). The accuracy table:
//! `cargo test -p qgait --release --test imu_models -- --nocapture`.

mod common;

use std::fmt::Write as _;
use std::path::Path;

use common::{imu_dir, qgait, run_imu_tutorial, stderr};
use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::imu::math::{space_fixed_xyz, three_axes};
use qgait_kernel::imu::{FitModel, Segment};
use qgait_kernel::models::{Phak, PhakAngles};
use qgait_kernel::{Quat, Vec3};
use qgait_opensim::mot::MotionTable;

/// A line of an orientation `.sto` cell: `w,x,y,z`.
fn cell(q: Quat<f64>) -> String {
    format!("{:?},{:?},{:?},{:?}", q.w, q.x, q.y, q.z)
}

/// Synthetic truth: PHAK's own poses, through sensors mounted at arbitrary rotations (up to
/// ±30 degrees about each axis) in a z-up sensor world, come back from `qgait imu --model phak`
/// within 1e-6 degrees. Generator: each segment's orientation is PHAK's own body orientation
/// (the kernel's chain frames) for known angles; a sensor's raw reading is the inverse
/// sensor-to-OpenSim rotation times that times the sensor's mounting (what a sensor on that
/// segment reports in a z-up world); the calibration pose is PHAK's default pose.
#[test]
fn phak_recovers_known_angles_through_the_cli() {
    let tmp = common::scratch("imu-models", "phak-synthetic");
    let phak = Phak::<f64>::new(&Anthropometry::gait2392()).unwrap();
    let to_opensim = space_fixed_xyz([-core::f64::consts::FRAC_PI_2, 0.0, 0.0]);
    let sensors = [
        Segment::Pelvis,
        Segment::FemurR,
        Segment::TibiaR,
        Segment::CalcnR,
        Segment::FemurL,
        Segment::TibiaL,
        Segment::CalcnL,
    ];
    let mount: Vec<Quat<f64>> = (0..sensors.len())
        .map(|i| {
            let a = |k: usize| 0.5 * ((i * 3 + k) as f64 * 1.7).sin();
            space_fixed_xyz([a(0), a(1), a(2)])
        })
        .collect();
    let reading = |q: &[f64; 8]| -> String {
        let o = phak.orientations(q);
        sensors
            .iter()
            .zip(&mount)
            .map(|(s, m)| cell(to_opensim.conj() * o[*s as usize].unwrap() * *m))
            .collect::<Vec<_>>()
            .join("\t")
    };
    let truth = |t: f64| -> [f64; 8] {
        core::array::from_fn(|i| {
            0.6 * (2.0 * t + i as f64).sin() + if i == 0 { 2.0 * t } else { 0.0 }
        })
    };
    let labels: Vec<&str> = sensors.iter().map(|s| s.imu_label()).collect();
    let header = format!(
        "DataRate=100\nDataType=Quaternion\nversion=3\nendheader\ntime\t{}\n",
        labels.join("\t")
    );
    let pose = tmp.join("pose.sto");
    std::fs::write(&pose, format!("{header}0\t{}\n", reading(&[0.0; 8]))).unwrap();
    let mut walk = header.clone();
    for k in 0..300 {
        let t = k as f64 * 0.01;
        writeln!(walk, "{t}\t{}", reading(&truth(t))).unwrap();
    }
    let walk_path = tmp.join("walk.sto");
    std::fs::write(&walk_path, walk).unwrap();
    let out = tmp.join("phak.mot");
    let o = qgait(&[
        "imu",
        walk_path.to_str().unwrap(),
        "--calibration",
        pose.to_str().unwrap(),
        "--model",
        "phak",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (t, _) = MotionTable::read(&out).unwrap();
    assert_eq!(
        &t.labels()[1..],
        &PhakAngles::<f64>::NAMES.map(String::from)[..]
    );
    let mut worst = 0.0f64;
    for (r, time) in t.time().iter().enumerate() {
        let q = truth(*time);
        for (i, name) in PhakAngles::<f64>::NAMES.iter().enumerate() {
            let e = (t.column(name).unwrap()[r] - q[i].to_degrees()).abs();
            worst = worst.max(e);
        }
    }
    eprintln!("PHAK synthetic truth: largest error {worst:.2e} degrees");
    assert!(worst < 1e-6, "{worst}");
    let _ = std::fs::remove_dir_all(&tmp);
}

/// The tutorial recording through `--model phak`: PHAK's 8 columns, one row per input row,
/// read by `qgait fk --model phak`; the knee (the same axis in both models) within a few
/// degrees of gait2392's solve.
#[test]
fn phak_on_the_tutorial_recording_reads_back_through_fk() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu-models", "phak-tutorial");
    let (phak, g2392) = (tmp.join("phak.mot"), tmp.join("gait2392.mot"));
    run_imu_tutorial(&dir, &phak, &["--model", "phak"]);
    run_imu_tutorial(&dir, &g2392, &[]);
    let (p, _) = MotionTable::read(&phak).unwrap();
    let (g, _) = MotionTable::read(&g2392).unwrap();
    assert_eq!(p.rows(), 2432);
    assert_eq!(p.labels().len(), 9);
    for side in ["r", "l"] {
        let name = format!("knee_angle_{side}");
        let (a, b) = (p.column(&name).unwrap(), g.column(&name).unwrap());
        let rms =
            (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
        eprintln!("{name}: PHAK against gait2392, rms {rms:.2} degrees");
        assert!(rms < 5.0, "{name}: {rms}");
    }
    // Read back by `fk --model phak`; and PHAK's own-axes solve against gait2392's
    // coordinates taken by name: the legs (knee, ankle, toe relative to the hip) nearer
    // gait2392's FK of its own solve.
    let fk = |motion: &Path, model: &str, name: &str| -> (String, Vec<Vec<f64>>) {
        let csv = tmp.join(name);
        let o = qgait(&[
            "-q",
            "fk",
            motion.to_str().unwrap(),
            "--model",
            model,
            "-o",
            csv.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "fk failed: {}", stderr(&o));
        common::parse_fk_csv(&std::fs::read_to_string(&csv).unwrap())
    };
    let (header, own) = fk(&phak, "phak", "own.csv");
    assert_eq!(own.len(), 2432);
    let (_, by_name) = fk(&g2392, "phak", "by_name.csv");
    let (g_header, truth) = fk(&g2392, "gait2392", "gait2392.csv");
    let labels: Vec<&str> = header.split(',').collect();
    let g_labels: Vec<&str> = g_header.split(',').collect();
    let mean_mm = |rows: &[Vec<f64>]| {
        let (mut sum, mut n) = (0.0, 0);
        for point in ["knee", "ankle", "toe"] {
            for side in ["r", "l"] {
                let at = |l: &[&str], axis: &str, p: &str| {
                    l.iter()
                        .position(|x| *x == format!("{p}_{side}_{axis}"))
                        .unwrap()
                };
                for (r, g) in rows.iter().zip(&truth) {
                    let d: f64 = ["x", "y", "z"]
                        .iter()
                        .map(|a| {
                            let ours = r[at(&labels, a, point)] - r[at(&labels, a, "hip")];
                            let theirs = g[at(&g_labels, a, point)] - g[at(&g_labels, a, "hip")];
                            (ours - theirs).powi(2)
                        })
                        .sum();
                    sum += d.sqrt() * 1000.0;
                    n += 1;
                }
            }
        }
        sum / n as f64
    };
    let (own_mm, by_name_mm) = (mean_mm(&own), mean_mm(&by_name));
    eprintln!(
        "PHAK legs against gait2392's FK (hip-relative knee, ankle, toe, mean): own axes {own_mm:.1} mm, gait2392's angles by name {by_name_mm:.1} mm"
    );
    assert!(own_mm < by_name_mm, "{own_mm} {by_name_mm}");
    let _ = std::fs::remove_dir_all(&tmp);
}

/// OpenSense's Rajagopal solution, committed (the first 10 s).
fn opensense_rajagopal() -> MotionTable {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/imu/walking_rajagopal2015_opensense_0-10s.mot");
    MotionTable::read(&path).unwrap().0
}

/// The pelvis angles (degrees, tilt-list-rotation about z, x, y) of the same orientation on
/// the principal branch (list within ±90), the rotation within half a turn of `near`:
/// OpenSense's IK jumps between equivalent branches (tilt and list of ±180 and tens of
/// thousands of degrees) while the orientation stays on the sensors.
fn principal_pelvis(tilt: f64, list: f64, rotation: f64, near: f64) -> [f64; 3] {
    let (x, y, z) = (Vec3::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    let q = Quat::from_axis_angle(z, tilt.to_radians())
        * Quat::from_axis_angle(x, list.to_radians())
        * Quat::from_axis_angle(y, rotation.to_radians());
    let [a, b, c] = three_axes(q, [z, x, y]).map(f64::to_degrees);
    [a, b, c + 360.0 * ((near - c) / 360.0).round()]
}

/// Coordinates OpenSense determines with Rajagopal2015_opensense (its subtalar, MTP and
/// lumbar joints are locked).
const RAJAGOPAL_DETERMINED: [&str; 13] = [
    "pelvis_tilt",
    "pelvis_list",
    "pelvis_rotation",
    "hip_flexion_r",
    "hip_adduction_r",
    "hip_rotation_r",
    "knee_angle_r",
    "ankle_angle_r",
    "hip_flexion_l",
    "hip_adduction_l",
    "hip_rotation_l",
    "knee_angle_l",
    "ankle_angle_l",
];

/// Per determined coordinate: RMSE and max (degrees) of `ours` against OpenSense's over its
/// rows, the pelvis compared on OpenSense's principal branch.
fn against_opensense(ours: &MotionTable, theirs: &MotionTable) -> Vec<(&'static str, f64, f64)> {
    let n = theirs.rows();
    let mut columns: Vec<Vec<f64>> = RAJAGOPAL_DETERMINED
        .iter()
        .map(|c| theirs.column(c).unwrap().to_vec())
        .collect();
    let our_rotation = ours.column("pelvis_rotation").unwrap();
    for r in 0..n {
        let p = principal_pelvis(columns[0][r], columns[1][r], columns[2][r], our_rotation[r]);
        for k in 0..3 {
            columns[k][r] = p[k];
        }
    }
    RAJAGOPAL_DETERMINED
        .iter()
        .zip(&columns)
        .map(|(name, b)| {
            let a = ours.column(name).unwrap();
            let (mut sum, mut max) = (0.0, 0.0f64);
            for r in 0..n {
                assert!((ours.time()[r] - theirs.time()[r]).abs() < 1e-9, "row {r}");
                let e = a[r] - b[r];
                sum += e * e;
                max = max.max(e.abs());
            }
            (*name, (sum / n as f64).sqrt(), max)
        })
        .collect()
}

#[test]
fn rajagopal_chain_matches_opensense_with_its_own_model() {
    let Some(dir) = imu_dir() else { return };
    let osim = dir.join("../opensim/Rajagopal2015_opensense.osim");
    let tmp = common::scratch("imu-models", "rajagopal");
    let chain = tmp.join("rajagopal.toml");
    let o = qgait(&[
        "model",
        "import",
        osim.to_str().unwrap(),
        "-o",
        chain.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = tmp.join("rajagopal.mot");
    run_imu_tutorial(
        &dir,
        &out,
        &["--model", chain.to_str().unwrap(), "--lumbar", "locked"],
    );
    let (ours, _) = MotionTable::read(&out).unwrap();
    assert_eq!(ours.rows(), 2432);
    let theirs = opensense_rajagopal();
    assert_eq!(theirs.rows(), 1001);
    eprintln!(
        "qgait imu --model Rajagopal2015_opensense (CHAIN.toml) --lumbar locked against OpenSense, first 10 s (degrees)"
    );
    eprintln!("| coordinate | RMSE | max |\n|---|---:|---:|");
    let mut failures = Vec::new();
    for (name, rmse, max) in against_opensense(&ours, &theirs) {
        eprintln!("| {name} | {rmse:.2} | {max:.2} |");
        if rmse > 1.0 || max > 3.0 {
            failures.push(format!("{name}: RMSE {rmse:.3}, max {max:.3}"));
        }
    }
    assert!(failures.is_empty(), "beyond 1° RMSE / 3° max: {failures:?}");
    // The locked joints stay at their default; the lumbar joint is not written.
    for c in ["subtalar_angle_r", "mtp_angle_l"] {
        assert!(ours.column(c).unwrap().iter().all(|v| *v == 0.0), "{c}");
    }
    assert!(ours.column("lumbar_extension").is_none());

    // The .osim itself is the same model.
    let direct = tmp.join("direct.mot");
    run_imu_tutorial(
        &dir,
        &direct,
        &["--model", osim.to_str().unwrap(), "--lumbar", "locked"],
    );
    assert_eq!(
        std::fs::read_to_string(&direct).unwrap(),
        std::fs::read_to_string(&out).unwrap()
    );

    // With the lumbar joint free the pelvis follows its own sensor only: not OpenSense's
    // (whose model locks it), by several degrees.
    let free = tmp.join("free.mot");
    run_imu_tutorial(&dir, &free, &["--model", chain.to_str().unwrap()]);
    let (free, _) = MotionTable::read(&free).unwrap();
    let tilt = against_opensense(&free, &theirs)[0];
    assert!(tilt.1 > 1.0, "{tilt:?}");
    assert!(free.column("lumbar_extension").is_some());

    // The output is a motion `qgait fk` takes with the chain.
    let csv = tmp.join("fk.csv");
    let o = qgait(&[
        "fk",
        out.to_str().unwrap(),
        "--model",
        chain.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "fk failed: {}", stderr(&o));
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn options_that_do_not_apply_are_refused() {
    let dir = common::scratch("imu-models", "refusals");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "imu",
            "walk.sto",
            "--calibration",
            "static.sto",
            "-o",
            dir.join("out.mot").to_str().unwrap().to_string().leak(),
        ];
        args.extend_from_slice(extra);
        let o = qgait(&args);
        assert!(!o.status.success());
        stderr(&o)
    };
    let e = run(&["--model", "hak"]);
    assert!(e.contains("--model hak: HAK has no pelvis"), "{e}");
    let e = run(&["--model", "phak", "--mode", "closed-form"]);
    assert!(e.contains("--mode closed-form"), "{e}");
    let e = run(&["--lumbar", "locked"]);
    assert!(e.contains("--lumbar: for an imported chain"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The chain solve in `f32` (the device's precision: its forward differences use a larger
/// step) stays within 0.01 degrees of `f64` on the first 10 s of the recording with
/// Rajagopal2015_opensense.
#[test]
fn rajagopal_chain_solve_in_f32_follows_f64() {
    use qgait_kernel::imu::{Calibration, FitSolver, Orientations, Settings};
    use qgait_opensim::imu_sto::OrientationReader;
    let Some(dir) = imu_dir() else { return };
    let osim = dir.join("../opensim/Rajagopal2015_opensense.osim");
    let text = std::fs::read_to_string(&osim).unwrap();
    let imported = qgait_model::leg_chain::import(&text, "raj", None).unwrap();
    let (min, max) = imported.model.bounds("test").unwrap();
    let chain = imported.model.chain("test").unwrap();
    let chain32 = chain.cast::<f32>();
    let settings = Settings::<f64>::opensense_tutorial();
    let mut pose = OrientationReader::open(&dir.join("placement_orientations.sto")).unwrap();
    let pose = pose.next_row().unwrap().unwrap().readings;
    let calibration = Calibration::for_model(&chain, &pose, &settings).unwrap();
    let mut s64 = FitSolver::<f64, 17>::new();
    let mut s32 = FitSolver::<f32, 17>::new();
    (s64.min, s64.max) = (min, max);
    (s32.min, s32.max) = (min.map(|v| v as f32), max.map(|v| v as f32));
    s64.torso_on_pelvis = true;
    s32.torso_on_pelvis = true;
    let mut walk = OrientationReader::open(&dir.join("walking_orientations.sto")).unwrap();
    let mut worst = 0.0f64;
    while let Some(row) = walk.next_row().unwrap() {
        if row.time > 10.0 {
            break;
        }
        let segments = calibration.segments(&row.readings).unwrap();
        let mut segments32 = Orientations::<f32>::EMPTY;
        for s in Segment::ALL {
            segments32.set(
                s,
                segments
                    .get(s)
                    .map(|q| Quat::new(q.w as f32, q.x as f32, q.y as f32, q.z as f32)),
            );
        }
        let a = s64.solve(&chain, &segments).coordinates;
        let b = s32.solve(&chain32, &segments32).coordinates;
        for (x, y) in a.iter().zip(&b) {
            worst = worst.max((x - f64::from(*y)).abs().to_degrees());
        }
    }
    eprintln!("Rajagopal chain solve, f32 against f64: largest difference {worst:.2e} degrees");
    assert!(worst < 0.01, "{worst}");
}

/// `--pelvis heading-free` with PHAK: the heading is only in `pelvis_rotation` (PHAK turns about
/// the vertical first), so the list and the legs are unchanged and the rotation loses the
/// walking direction (a turning walk's span of more than a turn shrinks to a stride's swing).
#[test]
fn phak_heading_free_pelvis_changes_the_rotation_only() {
    let Some(dir) = imu_dir() else { return };
    let tmp = common::scratch("imu-models", "phak-heading-free");
    let (world, free) = (tmp.join("world.mot"), tmp.join("free.mot"));
    run_imu_tutorial(&dir, &world, &["--model", "phak"]);
    run_imu_tutorial(
        &dir,
        &free,
        &["--model", "phak", "--pelvis", "heading-free"],
    );
    let (w, _) = MotionTable::read(&world).unwrap();
    let (f, _) = MotionTable::read(&free).unwrap();
    for name in &PhakAngles::<f64>::NAMES[1..] {
        assert_eq!(w.column(name), f.column(name), "{name}");
    }
    let span = |c: &[f64]| {
        c.iter().copied().fold(f64::MIN, f64::max) - c.iter().copied().fold(f64::MAX, f64::min)
    };
    let (ws, fs) = (
        span(w.column("pelvis_rotation").unwrap()),
        span(f.column("pelvis_rotation").unwrap()),
    );
    eprintln!("PHAK pelvis_rotation span: world {ws:.1}°, heading-free {fs:.1}°");
    assert!(ws > 360.0 && fs < 120.0, "{ws} {fs}");
    let _ = std::fs::remove_dir_all(&tmp);
}
