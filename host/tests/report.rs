//! `qgait report`: files, figures and metrics, on the built-in gait and on the shared motions.

mod common;

use std::collections::HashMap;
use std::path::Path;

use common::{qgait, shared_dir, stderr};

const FIGURES: [&str; 5] = [
    "stick_sagittal",
    "stick_frontal",
    "stick_transverse",
    "paths_sagittal",
    "distances",
];

fn run_report(args: &[&str], dir: &Path) {
    let mut all = vec!["report"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", dir.to_str().unwrap()]);
    let out = qgait(&all);
    assert!(out.status.success(), "qgait {all:?}: {}", stderr(&out));
}

/// Rows of a CSV as maps from header name to field.
fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {}", row[key]))
}

fn check_figures(dir: &Path, labels: &[&str]) {
    for stem in FIGURES {
        let png = std::fs::read(dir.join(format!("{stem}.png"))).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n"),
            "{stem}.png is not a PNG"
        );
        let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
        assert!(svg.starts_with("<svg"), "{stem}.svg");
        // Titles, axis units and every gait label are real text in the SVG.
        assert!(svg.contains("(m)"), "{stem}.svg has no axis unit");
        if stem != "paths_sagittal" && stem != "distances" {
            for label in labels {
                assert!(svg.contains(label), "{stem}.svg lacks label {label}");
            }
        }
    }
    let paths = std::fs::read_to_string(dir.join("paths_sagittal.svg")).unwrap();
    let distances = std::fs::read_to_string(dir.join("distances.svg")).unwrap();
    for label in labels {
        assert!(
            paths.contains(label) && distances.contains(label),
            "legend lacks {label}"
        );
    }
}

#[test]
fn report_on_builtin_gaits_writes_every_file_and_consistent_metrics() {
    let dir = tempfile::tempdir().unwrap();
    run_report(
        &[
            "builtin:normal,rows=41",
            "builtin:crouch=1,rows=41",
            "--label",
            "normal",
            "--label",
            "crouch",
        ],
        dir.path(),
    );
    check_figures(dir.path(), &["normal", "crouch"]);

    let metrics = csv(&dir.path().join("metrics.csv"));
    assert_eq!(
        metrics.len(),
        2 * 2 * 4 * 3,
        "gaits x sides x joints x planes"
    );
    for r in &metrics {
        assert_eq!(num(r, "n"), 41.0);
        for a in ["a", "b"] {
            assert!(num(r, &format!("min_{a}")) <= num(r, &format!("mean_{a}")));
            assert!(num(r, &format!("mean_{a}")) <= num(r, &format!("max_{a}")));
            let range = num(r, &format!("max_{a}")) - num(r, &format!("min_{a}"));
            assert!((num(r, &format!("range_{a}")) - range).abs() < 1e-12);
        }
        assert!(num(r, "area_m2") >= 0.0);
        if r["plane"] != "sagittal" {
            continue;
        }
        assert_eq!((r["axis_a"].as_str(), r["axis_b"].as_str()), ("x", "y"));
    }
    // Crouch raises the knee (more hip flexion): higher mean knee height in the sagittal plane.
    let knee_y = |gait: &str| {
        metrics
            .iter()
            .find(|r| {
                r["gait"] == gait
                    && r["side"] == "right"
                    && r["joint"] == "knee"
                    && r["plane"] == "sagittal"
            })
            .map(|r| num(r, "mean_b"))
            .unwrap()
    };
    assert!(knee_y("crouch") > knee_y("normal") + 0.02);

    // The built-in gaits share the pelvis curves: no hip shift.
    let shift = csv(&dir.path().join("hip_shift.csv"));
    assert_eq!(shift.len(), 4);
    assert!(shift
        .iter()
        .all(|r| r["reference"] == "normal" && num(r, "shift").abs() < 1e-12));

    let dist = csv(&dir.path().join("distance_stats.csv"));
    assert_eq!(dist.len(), 2 * 3);
    for r in &dist {
        assert!(num(r, "min") <= num(r, "mean") && num(r, "mean") <= num(r, "max"));
        // In PHAK each leg moves in its own plane through its hip, parallel to the other leg's
        // plane and 2 x 0.0835 m from it (gait2392): no distance can be smaller.
        assert!(num(r, "min") >= 0.167 - 1e-9, "{r:?}");
    }
    let md = std::fs::read_to_string(dir.path().join("metrics.md")).unwrap();
    assert!(md.contains("## Hip position shift relative to normal"));
    assert!(md.contains("| crouch | right | knee | sagittal |"));
}

#[test]
fn report_on_the_shared_motions() {
    let Some(shared) = shared_dir() else { return };
    let data = shared.join("data/opensim");
    let dir = tempfile::tempdir().unwrap();
    let files: Vec<String> = ["normal", "crouch1", "crouch4"]
        .iter()
        .map(|n| data.join(format!("{n}.mot")).to_str().unwrap().to_string())
        .collect();
    run_report(
        &[
            &files[0], &files[1], &files[2], "--label", "N", "--label", "MC", "--label", "SC",
        ],
        dir.path(),
    );
    check_figures(dir.path(), &["N", "MC", "SC"]);

    let metrics = csv(&dir.path().join("metrics.csv"));
    assert_eq!(metrics.len(), 3 * 2 * 4 * 3);
    let n_rows = |gait: &str| {
        metrics
            .iter()
            .find(|r| r["gait"] == gait)
            .map(|r| num(r, "n"))
            .unwrap()
    };
    // Row counts come from the data (crouch1.mot declares nRows=120 but has 119 rows).
    assert_eq!(
        (n_rows("N"), n_rows("MC"), n_rows("SC")),
        (51.0, 119.0, 101.0)
    );

    // The paper reports a hip shift of about 0.02 m for mild and 0.08 m for severe crouch;
    // ours grows the same way.
    let shift = csv(&dir.path().join("hip_shift.csv"));
    let s = |gait: &str| {
        shift
            .iter()
            .find(|r| r["gait"] == gait && r["side"] == "right")
            .map(|r| num(r, "shift"))
            .unwrap()
    };
    assert_eq!(s("N"), 0.0);
    assert!(s("MC") > 0.005 && s("MC") < 0.04, "MC shift {}", s("MC"));
    assert!(
        s("SC") > 2.0 * s("MC") && s("SC") < 0.12,
        "SC shift {}",
        s("SC")
    );

    // Normal gait: toes and ankles swing wider apart than the knees.
    let dist = csv(&dir.path().join("distance_stats.csv"));
    let max = |gait: &str, m: &str| {
        dist.iter()
            .find(|r| r["gait"] == gait && r["measure"] == m)
            .map(|r| num(r, "max"))
            .unwrap()
    };
    assert!(max("N", "toe-toe") > max("N", "knee-knee") + 0.2);
    // Crouch shortens the step: smaller maximal ankle-ankle distance.
    assert!(max("SC", "ankle-ankle") < max("N", "ankle-ankle") - 0.1);
}

/// A recording of many strides (the gait-lab walk) is drawn over one gait cycle: its first
/// right stride as `qgait gait` finds it, heel strike to heel strike, said in a warning; the
/// metrics are of that stride's rows.
#[test]
fn a_recording_of_many_strides_is_cut_to_its_first_right_stride() {
    let Some(shared) = shared_dir() else { return };
    let walk = shared.join("data/gaitlab/subject01_walk1/subject01_walk1_ik.mot");
    let walk = walk.to_str().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = qgait(&["report", walk, "-o", dir.path().join("r").to_str().unwrap()]);
    let e = stderr(&out);
    assert!(out.status.success(), "{e}");
    let said = e
        .split("the first right stride, heel strike at ")
        .nth(1)
        .unwrap_or_else(|| panic!("no cut said: {e}"));
    let times: Vec<f64> = said
        .split(" s")
        .take(2)
        .map(|t| t.trim_start_matches(" to the next at ").parse().unwrap())
        .collect();
    let gait = dir.path().join("g");
    let o = qgait(&["-q", "gait", walk, "-o", gait.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let strikes: Vec<f64> = csv(&gait.join("events.csv"))
        .iter()
        .filter(|r| r["side"] == "right" && r["event"] == "heel_strike")
        .map(|r| num(r, "time"))
        .collect();
    let k = strikes
        .iter()
        .position(|t| (t - times[0]).abs() < 1e-3)
        .unwrap_or_else(|| panic!("{} not among {strikes:?}", times[0]));
    assert!(
        (strikes[k + 1] - times[1]).abs() < 1e-3,
        "{times:?} {strikes:?}"
    );
    // The metrics count the stride's rows only.
    let text = std::fs::read_to_string(walk).unwrap();
    let rows = text
        .split("endheader")
        .nth(1)
        .unwrap()
        .lines()
        .skip(2)
        .filter_map(|l| l.split_whitespace().next()?.parse::<f64>().ok())
        .filter(|t| *t >= times[0] - 1e-3 && *t <= times[1] + 1e-3)
        .count();
    let metrics = csv(&dir.path().join("r/metrics.csv"));
    let n = num(&metrics[0], "n") as usize;
    assert!(
        n.abs_diff(rows) <= 1,
        "{n} rows in the metrics, {rows} in the stride"
    );
}

#[test]
fn the_figures_of_a_long_recording_stay_the_size_of_the_picture() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let o = qgait(&[
        "-q",
        "report",
        "builtin:normal,rows=100000",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for svg in ["paths_sagittal.svg", "distances.svg"] {
        let size = std::fs::metadata(out.join(svg)).unwrap().len();
        // Every row drawn would be 100,000 segments per curve (tens of MB).
        assert!(size < 3_000_000, "{svg}: {size} bytes");
    }
}

#[test]
fn the_report_takes_every_model_fk_takes() {
    let dir = tempfile::tempdir().unwrap();
    // The right hip's mean position in the sagittal plane: PHAK and HAK hang the legs at the
    // pelvis origin's level, gait2392 has its hip 7 cm behind and 6.6 cm below it.
    let hip_x = |model: &str| {
        let out = dir.path().join(model);
        run_report(
            &["builtin:normal,rows=21", "--label", "n", "--model", model],
            &out,
        );
        check_figures(&out, &["n"]);
        // The figures and the tables name the model that computed them.
        let caption = match model {
            "phak" => "PHAK model, origin at the pelvis origin",
            "hak" => "HAK model, origin at the pelvis origin",
            _ => "gait2392 model, origin at its pelvis origin",
        };
        let md = std::fs::read_to_string(out.join("metrics.md")).unwrap();
        assert!(md.contains(&format!("Model: {caption}")), "{caption}: {md}");
        let svg = std::fs::read_to_string(out.join("stick_sagittal.svg")).unwrap();
        assert!(svg.contains(caption), "{caption}");
        let rows = csv(&out.join("metrics.csv"));
        let hip = rows
            .iter()
            .find(|r| r["side"] == "right" && r["joint"] == "hip" && r["plane"] == "sagittal")
            .expect("a right hip row");
        (num(hip, "mean_a"), num(hip, "mean_b"))
    };
    let (phak_x, phak_y) = hip_x("phak");
    let (hak_x, hak_y) = hip_x("hak");
    let (g_x, g_y) = hip_x("gait2392");
    assert!(
        phak_x.abs() < 0.01 && phak_y.abs() < 0.01,
        "{phak_x} {phak_y}"
    );
    assert!(
        hak_x.abs() < 1e-12 && hak_y.abs() < 1e-12,
        "{hak_x} {hak_y}"
    );
    assert!(
        (g_x + 0.0707).abs() < 0.01 && (g_y + 0.0661).abs() < 0.01,
        "{g_x} {g_y}"
    );
}

#[test]
fn a_devices_frames_are_captioned_as_the_hub_computed_them() {
    let dir = tempfile::tempdir().unwrap();
    // A frames CSV (`emulate --frames-csv`'s columns: `seq` before `fk`'s).
    let fk = common::qgait(&["fk", "builtin:normal,rows=21"]);
    assert!(fk.status.success(), "{}", common::stderr(&fk));
    let frames: String = common::stdout(&fk)
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            0 => format!("seq,{l}\n"),
            _ => format!("{},{l}\n", i - 1),
        })
        .collect();
    let csv_path = dir.path().join("frames.csv");
    std::fs::write(&csv_path, frames).unwrap();
    let out = dir.path().join("out");
    run_report(
        &["builtin:normal,rows=21", csv_path.to_str().unwrap()],
        &out,
    );
    let md = std::fs::read_to_string(out.join("metrics.md")).unwrap();
    assert!(
        md.contains("Model: PHAK model, origin at the pelvis origin (midway between the hips) (a device's frames: as the hub computed them)"),
        "{md}"
    );
    // Its frames in time order, as `gait` takes them: a time going back in sequence order is
    // refused at its line (frames merely out of sequence order are sorted).
    let text = std::fs::read_to_string(&csv_path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines.swap(2, 3);
    let mut cells: Vec<String> = lines[6].split(',').map(String::from).collect();
    cells[1] = "0.01".into();
    lines[6] = cells.join(",");
    let back = dir.path().join("back.csv");
    std::fs::write(&back, lines.join("\n") + "\n").unwrap();
    let o = common::qgait(&[
        "report",
        back.to_str().unwrap(),
        "-o",
        dir.path().join("out2").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = common::stderr(&o);
    assert!(err.contains(&format!("{}:7:", back.display())), "{err}");
}
