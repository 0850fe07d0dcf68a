//! gait2392 through the CLI: `fk --model gait2392|SUBJECT.toml [--points]` against OpenSim's
//! reference, `model import` of both shared .osim files (generic, scaled, and refused ones), and
//! `export` (.trc/.sto read back).

mod common;

use std::path::{Path, PathBuf};

use common::{parse_fk_csv, qgait, shared_dir, stderr, stdout};
use qgait_kernel::Gait2392Geometry;
use qgait_opensim::mot::MotionTable;

const MODELS: [&str; 2] = ["gait2392_simbody.osim", "gait2392_thelen2003muscle.osim"];

fn run_ok(args: &[&str]) -> (String, String) {
    let out = qgait(args);
    assert!(out.status.success(), "qgait {args:?}: {}", stderr(&out));
    (stdout(&out), stderr(&out))
}

fn run_err(args: &[&str]) -> String {
    let out = qgait(args);
    assert!(!out.status.success(), "qgait {args:?} should fail");
    let e = stderr(&out);
    assert!(
        e.starts_with("error: ") && e.trim_end().lines().count() == 1,
        "{e}"
    );
    e
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `qgait model import` of `osim` (a path) into `dir/name`; returns the TOML path.
fn import(osim: &Path, dir: &Path, name: &str) -> PathBuf {
    let out = dir.join(name);
    run_ok(&["model", "import", s(osim), "-o", s(&out)]);
    out
}

/// The reference CSV's `<point>_<axis>_groundrel` columns.
struct Reference {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Reference {
    fn load(shared: &Path) -> Self {
        let text =
            std::fs::read_to_string(shared.join("data/reference/normal_gait2392_opensim.csv"))
                .expect("reference csv");
        let (header, rows) = parse_fk_csv(&text);
        Self {
            header: header.split(',').map(String::from).collect(),
            rows,
        }
    }
    fn get(&self, row: usize, column: &str) -> f64 {
        let i = self
            .header
            .iter()
            .position(|h| h == column)
            .unwrap_or_else(|| panic!("no reference column {column}"));
        self.rows[row][i]
    }
}

/// Largest difference (m) between `qgait fk --points` output and OpenSim, over every value.
fn worst_vs_opensim(csv: &str, reference: &Reference) -> f64 {
    let (header, rows) = parse_fk_csv(csv);
    let names: Vec<&str> = header.split(',').collect();
    assert_eq!(
        rows.len(),
        reference.rows.len(),
        "one row per reference row"
    );
    let mut worst = 0.0f64;
    for (r, row) in rows.iter().enumerate() {
        assert!((row[0] - reference.get(r, "time")).abs() < 1e-12);
        for (c, name) in names.iter().enumerate().skip(1) {
            // qgait's `toe` is OpenSim's toe tip.
            let column = format!("{}_groundrel", name.replacen("toe_", "toetip_", 1));
            worst = worst.max((row[c] - reference.get(r, &column)).abs());
        }
    }
    worst
}

#[test]
fn fk_gait2392_matches_opensim_within_a_micrometre_through_the_cli() {
    let Some(shared) = shared_dir() else { return };
    let reference = Reference::load(&shared);
    let motion = shared.join("data/opensim/normal.mot");
    let (csv, err) = run_ok(&["fk", s(&motion), "--model", "gait2392", "--points"]);
    let header = csv.lines().next().unwrap();
    assert_eq!(
        header,
        "time,hip_r_x,hip_r_y,hip_r_z,knee_r_x,knee_r_y,knee_r_z,ankle_r_x,ankle_r_y,ankle_r_z,toe_r_x,toe_r_y,toe_r_z,\
hip_l_x,hip_l_y,hip_l_z,knee_l_x,knee_l_y,knee_l_z,ankle_l_x,ankle_l_y,ankle_l_z,toe_l_x,toe_l_y,toe_l_z,\
subtalar_r_x,subtalar_r_y,subtalar_r_z,mtp_r_x,mtp_r_y,mtp_r_z,subtalar_l_x,subtalar_l_y,subtalar_l_z,mtp_l_x,mtp_l_y,mtp_l_z"
    );
    // normal.mot has no subtalar/mtp columns: 0, with one warning each.
    for c in [
        "subtalar_angle_r",
        "mtp_angle_r",
        "subtalar_angle_l",
        "mtp_angle_l",
    ] {
        assert!(
            err.contains(&format!("no `{c}` column; taken as 0")),
            "{err}"
        );
    }
    let worst = worst_vs_opensim(&csv, &reference);
    eprintln!(
        "qgait fk --model gait2392 vs OpenSim: max {:.4} µm",
        worst * 1e6
    );
    assert!(worst < 1e-6, "{worst}");

    // The same through subject files imported from both model files.
    let dir = tempfile::tempdir().unwrap();
    for m in MODELS {
        let toml = import(
            &shared.join("data/opensim").join(m),
            dir.path(),
            &format!("{m}.toml"),
        );
        let (csv, _) = run_ok(&["-q", "fk", s(&motion), "--model", s(&toml), "--points"]);
        let worst = worst_vs_opensim(&csv, &reference);
        eprintln!(
            "qgait fk --model <import of {m}> vs OpenSim: max {:.4} µm",
            worst * 1e6
        );
        assert!(worst < 1e-6, "{m}: {worst}");
    }
}

#[test]
fn fk_gait2392_without_points_has_the_standard_columns_and_warns_for_absent_coordinates() {
    let (csv, err) = run_ok(&["fk", "builtin:normal,rows=3", "--model", "gait2392"]);
    let (_, std_rows) = parse_fk_csv(&run_ok(&["fk", "builtin:normal,rows=3"]).0);
    let (header, rows) = parse_fk_csv(&csv);
    assert_eq!(
        header,
        qgait_model::points::csv_header(&qgait_model::points::point_names(false))
    );
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0].len(), std_rows[0].len());
    // The built-in gait has pelvis list and rotation only.
    for c in [
        "pelvis_tilt",
        "hip_adduction_r",
        "hip_rotation_r",
        "subtalar_angle_r",
        "mtp_angle_l",
    ] {
        assert!(
            err.contains(&format!("no `{c}` column; taken as 0")),
            "{err}"
        );
    }
    assert!(!err.contains("no `pelvis_list`"), "{err}");
    let e = run_err(&["fk", "builtin:normal", "--points"]);
    assert!(
        e.contains("--points (subtalar and MTP) needs an OpenSim leg chain"),
        "{e}"
    );
    let e = run_err(&[
        "fk",
        "builtin:normal",
        "--model",
        "gait2392",
        "--anthropometry",
        "a.toml",
    ]);
    assert!(
        e.contains("--anthropometry applies to hak and phak only: gait2392 has its own"),
        "{e}"
    );
    let e = run_err(&["fk", "builtin:normal", "--model", "gait9999"]);
    assert!(e.contains("unknown model `gait9999`"), "{e}");
}

/// Every number of the generic model, axes included (the kernel's constants are the model
/// file's own digits).
fn assert_generic(g: &Gait2392Geometry, what: &str) {
    let e = Gait2392Geometry::generic();
    for (a, b, side) in [(&g.right, &e.right, "right"), (&g.left, &e.left, "left")] {
        let close = |x: &[f64], y: &[f64], tol: f64, name: &str| {
            assert_eq!(x.len(), y.len(), "{what} {side} {name}");
            for (u, v) in x.iter().zip(y) {
                assert!((u - v).abs() <= tol, "{what} {side} {name}: {x:?} vs {y:?}");
            }
        };
        let dir = |v: [f64; 3]| {
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|c| c / n)
        };
        close(&a.hip_in_pelvis, &b.hip_in_pelvis, 1e-12, "hip_in_pelvis");
        for k in 0..3 {
            close(&a.hip_axes[k], &b.hip_axes[k], 1e-12, "hip_axes");
        }
        close(
            &a.knee_tx.x[..a.knee_tx.n],
            &b.knee_tx.x[..b.knee_tx.n],
            1e-12,
            "knee_tx.x",
        );
        close(
            &a.knee_tx.y[..a.knee_tx.n],
            &b.knee_tx.y[..b.knee_tx.n],
            1e-12,
            "knee_tx.y",
        );
        close(
            &a.knee_ty.x[..a.knee_ty.n],
            &b.knee_ty.x[..b.knee_ty.n],
            1e-12,
            "knee_ty.x",
        );
        close(
            &a.knee_ty.y[..a.knee_ty.n],
            &b.knee_ty.y[..b.knee_ty.n],
            1e-12,
            "knee_ty.y",
        );
        close(
            &a.ankle_in_tibia,
            &b.ankle_in_tibia,
            1e-12,
            "ankle_in_tibia",
        );
        close(
            &a.subtalar_in_talus,
            &b.subtalar_in_talus,
            1e-12,
            "subtalar_in_talus",
        );
        close(&a.mtp_in_calcn, &b.mtp_in_calcn, 1e-12, "mtp_in_calcn");
        close(
            &a.toetip_in_toes,
            &b.toetip_in_toes,
            1e-12,
            "toetip_in_toes",
        );
        close(&dir(a.ankle_axis), &dir(b.ankle_axis), 1e-12, "ankle_axis");
        close(
            &dir(a.subtalar_axis),
            &dir(b.subtalar_axis),
            1e-12,
            "subtalar_axis",
        );
        close(&dir(a.mtp_axis), &dir(b.mtp_axis), 1e-12, "mtp_axis");
    }
}

#[test]
fn importing_both_model_formats_gives_the_generic_geometry_and_the_same_fk() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let mut imported = Vec::new();
    for m in MODELS {
        let toml = import(
            &shared.join("data/opensim").join(m),
            dir.path(),
            &format!("{m}.toml"),
        );
        let g = qgait_model::subject::read(&toml).unwrap();
        assert_generic(&g, m);
        imported.push((toml, g));
    }
    assert_eq!(
        imported[0].1, imported[1].1,
        "3.x and 4.x files give the same numbers"
    );
    // import -> toml -> fk equals the built-in gait2392 (to the axis rounding: nanometres).
    let motion = shared.join("data/opensim/crouch4.mot");
    let builtin =
        parse_fk_csv(&run_ok(&["-q", "fk", s(&motion), "--model", "gait2392", "--points"]).0);
    let subject = parse_fk_csv(
        &run_ok(&[
            "-q",
            "fk",
            s(&motion),
            "--model",
            s(&imported[0].0),
            "--points",
        ])
        .0,
    );
    assert_eq!(builtin.0, subject.0);
    let worst = builtin
        .1
        .iter()
        .flatten()
        .zip(subject.1.iter().flatten())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!("import -> toml -> fk vs built-in gait2392 on crouch4: max {worst:e} m");
    assert!(worst < 1e-7, "{worst}");
}

/// Multiplies every number in the text of each `<tag>...</tag>` element by `k`.
fn scale_elements(xml: &str, tag: &str, k: f64) -> String {
    let (open, close) = (format!("<{tag}>"), format!("</{tag}>"));
    let mut out = String::new();
    let mut rest = xml;
    while let Some(i) = rest.find(&open) {
        let start = i + open.len();
        let end = start + rest[start..].find(&close).unwrap();
        out.push_str(&rest[..start]);
        let scaled: Vec<String> = rest[start..end]
            .split_whitespace()
            .map(|v| (v.parse::<f64>().unwrap() * k).to_string())
            .collect();
        out.push_str(&scaled.join(" "));
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

fn fk_points(motion: &Path, model: &str) -> Vec<Vec<f64>> {
    parse_fk_csv(&run_ok(&["-q", "fk", s(motion), "--model", model, "--points"]).0).1
}

#[test]
fn a_uniformly_scaled_model_scales_every_point() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let motion = shared.join("data/opensim/normal.mot");
    let k = 1.1;
    for m in MODELS {
        let unscaled = import(
            &shared.join("data/opensim").join(m),
            dir.path(),
            "unscaled.toml",
        );
        let generic = fk_points(&motion, s(&unscaled));
        let xml = std::fs::read_to_string(shared.join("data/opensim").join(m)).unwrap();
        // What a uniform scale does: joint offsets (3.x location_in_parent, 4.x offset-frame
        // translation), spline values (the knee's among them) and geometry scale factors.
        let mut scaled = xml.clone();
        for tag in ["location_in_parent", "translation", "y", "scale_factors"] {
            scaled = scale_elements(&scaled, tag, k);
        }
        let path = dir.path().join(format!("scaled_{m}"));
        std::fs::write(&path, scaled).unwrap();
        let toml = import(&path, dir.path(), &format!("scaled_{m}.toml"));
        let text = std::fs::read_to_string(&toml).unwrap();
        assert!(text.contains("toes' geometry scale factors [1.1"), "{text}");
        let subject = fk_points(&motion, s(&toml));
        let mut worst = 0.0f64;
        for (a, b) in generic.iter().zip(&subject) {
            for c in 1..a.len() {
                worst = worst.max((b[c] - k * a[c]).abs());
            }
        }
        eprintln!("{m} scaled by {k}: fk differs from {k} x fk by at most {worst:e} m");
        assert!(worst < 1e-14, "{m}: {worst}");
    }
}

fn distance(row: &[f64], a: usize, b: usize) -> f64 {
    // Columns: time, then x,y,z per point in fk order.
    (0..3)
        .map(|i| (row[1 + 3 * a + i] - row[1 + 3 * b + i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn a_longer_right_femur_written_as_opensim_4_multiplier_functions_moves_only_the_right_knee() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let xml = std::fs::read_to_string(shared.join("data/opensim").join(MODELS[1])).unwrap();
    // OpenSim 4's scale tool wraps the knee translations in MultiplierFunctions.
    let knee = xml.find("<CustomJoint name=\"knee_r\">").unwrap();
    let end = knee + xml[knee..].find("</CustomJoint>").unwrap();
    let k = 1.2;
    let section = xml[knee..end]
        .replace(
            "<SimmSpline name=\"function\">",
            "<MultiplierFunction name=\"function\"><function><SimmSpline>",
        )
        .replace(
            "</SimmSpline>",
            &format!("</SimmSpline></function><scale>{k}</scale></MultiplierFunction>"),
        );
    let scaled = format!("{}{}{}", &xml[..knee], section, &xml[end..]);
    let path = dir.path().join("femur.osim");
    std::fs::write(&path, scaled).unwrap();
    let toml = import(&path, dir.path(), "femur.toml");
    // All angles 0 except pelvis: a one-row motion.
    let mot = dir.path().join("still.mot");
    std::fs::write(
        &mot,
        "still\nnRows=1\nnColumns=7\ninDegrees=yes\nendheader\ntime\thip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l\n0\t0\t0\t0\t0\t0\t0\n",
    )
    .unwrap();
    let g = &fk_points(&mot, "gait2392")[0];
    let f = &fk_points(&mot, s(&toml))[0];
    // Points: 0 hip_r, 1 knee_r, 2 ankle_r, 4 hip_l, 5 knee_l.
    let femur = distance(g, 0, 1);
    assert!(
        (distance(f, 0, 1) - k * femur).abs() < 1e-12,
        "femur scales"
    );
    assert!(
        (distance(f, 1, 2) - distance(g, 1, 2)).abs() < 1e-12,
        "tibia does not"
    );
    assert!(
        (distance(f, 4, 5) - distance(g, 4, 5)).abs() < 1e-12,
        "left femur does not"
    );
}

#[test]
fn unsupported_joints_functions_and_couplers_are_refused_by_name() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let v3 = std::fs::read_to_string(shared.join("data/opensim").join(MODELS[0])).unwrap();
    let v4 = std::fs::read_to_string(shared.join("data/opensim").join(MODELS[1])).unwrap();
    let knee3 = v3.find("<CustomJoint name=\"knee_r\">").unwrap();
    let mtp4 = v4.find("<CustomJoint name=\"mtp_l\">").unwrap();
    let mtp4_end = mtp4 + v4[mtp4..].find("</CustomJoint>").unwrap();
    // Not gait2392's shape but a leg chain: imported as a general chain (CHAIN.toml).
    let chains = [
        (
            // A rotated knee frame (3.x).
            format!(
                "{}{}",
                &v3[..knee3],
                v3[knee3..].replacen(
                    "<orientation_in_parent> 0 0 0</orientation_in_parent>",
                    "<orientation_in_parent> 0 0.1 0</orientation_in_parent>",
                    1
                )
            ),
            "v3",
        ),
        (
            // A weld instead of the left MTP joint (4.x).
            format!(
                "{}<WeldJoint name=\"mtp_l\">{}</WeldJoint>{}",
                &v4[..mtp4],
                &v4[mtp4 + "<CustomJoint name=\"mtp_l\">".len()..mtp4_end],
                &v4[mtp4_end + "</CustomJoint>".len()..]
            ),
            "v4",
        ),
    ];
    for (i, (xml, what)) in chains.into_iter().enumerate() {
        let source = if what == "v3" { &v3 } else { &v4 };
        assert!(xml != *source, "chain case {i} did not change the model");
        let path = dir.path().join(format!("chain{i}.osim"));
        std::fs::write(&path, xml).unwrap();
        let out = dir.path().join(format!("chain{i}.toml"));
        run_ok(&["model", "import", s(&path), "-o", s(&out)]);
        assert!(std::fs::read_to_string(&out)
            .unwrap()
            .contains("[[joints]]"));
    }
    let cases: Vec<(String, String, &str)> = vec![
        (
            // A knee translation as a NaturalCubicSpline (3.x).
            format!(
                "{}{}",
                &v3[..knee3],
                v3[knee3..]
                    .replacen("<SimmSpline>", "<NaturalCubicSpline>", 1)
                    .replacen("</SimmSpline>", "</NaturalCubicSpline>", 1)
            ),
            "joint `knee_r` translation1: function type NaturalCubicSpline is not supported".into(),
            "v3",
        ),
        (
            // A coupler driving the ankle from the knee (4.x).
            {
                let set = v4.find("<ConstraintSet").unwrap();
                let objects = set + v4[set..].find("<objects />").unwrap();
                format!(
                    "{}<objects><CoordinateCouplerConstraint name=\"ankle_coupler\"><independent_coordinate_names>knee_angle_r</independent_coordinate_names><dependent_coordinate_name>ankle_angle_r</dependent_coordinate_name></CoordinateCouplerConstraint></objects>{}",
                    &v4[..objects],
                    &v4[objects + "<objects />".len()..]
                )
            },
            // (A coupler with a function would make the ankle follow the knee.)
            "CoordinateCouplerConstraint `ankle_coupler`: no coupled_coordinates_function".into(),
            "v4",
        ),
    ];
    for (i, (xml, needle, what)) in cases.into_iter().enumerate() {
        let source = if what == "v3" { &v3 } else { &v4 };
        assert!(xml != *source, "case {i} did not change the model");
        let path = dir.path().join(format!("bad{i}.osim"));
        std::fs::write(&path, xml).unwrap();
        let e = run_err(&[
            "model",
            "import",
            s(&path),
            "-o",
            s(&dir.path().join("x.toml")),
        ]);
        assert!(e.contains(&needle), "case {i}: {e}");
    }
}

#[test]
fn a_marker_file_sets_the_toe_tip() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let markers = dir.path().join("markers.xml");
    std::fs::write(
        &markers,
        "<OpenSimDocument Version=\"20302\"><MarkerSet><objects>\
<Marker name=\"R.Toe.Tip\"><body>calcn_r</body><location>0.27 0.005 0</location></Marker>\
</objects></MarkerSet></OpenSimDocument>",
    )
    .unwrap();
    let out = dir.path().join("m.toml");
    let osim = shared.join("data/opensim").join(MODELS[0]);
    let (_, err) = run_ok(&[
        "model",
        "import",
        s(&osim),
        "-o",
        s(&out),
        "--markers",
        s(&markers),
    ]);
    assert!(err.contains("toe tip r: marker R.Toe.Tip from"), "{err}");
    assert!(
        err.contains("toe tip l: no L.Toe.Tip marker; generic"),
        "{err}"
    );
    let g = qgait_model::subject::read(&out).unwrap();
    let tip = g.right.toetip_in_toes;
    let expected = [0.27 - 0.1788, 0.005 + 0.002, -0.00108];
    for i in 0..3 {
        assert!((tip[i] - expected[i]).abs() < 1e-15, "{tip:?}");
    }
    assert_eq!(
        g.left.toetip_in_toes,
        Gait2392Geometry::generic().left.toetip_in_toes
    );
}

#[test]
fn export_writes_a_trc_and_an_sto_that_read_back_as_the_fk_csv() {
    let dir = tempfile::tempdir().unwrap();
    let (trc, sto) = (dir.path().join("out.trc"), dir.path().join("out.sto"));
    let motion = "builtin:crouch=0.5,rows=11";
    run_ok(&[
        "-q",
        "export",
        motion,
        "--model",
        "gait2392",
        "--points",
        "--trc",
        s(&trc),
        "--sto",
        s(&sto),
    ]);
    let (fk_header, fk_rows) =
        parse_fk_csv(&run_ok(&["-q", "fk", motion, "--model", "gait2392", "--points"]).0);
    let columns: Vec<&str> = fk_header.split(',').collect();

    // .trc
    let text = std::fs::read_to_string(&trc).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "PathFileType\t4\t(X/Y/Z)\tout.trc");
    assert_eq!(
        lines[1],
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames"
    );
    let values: Vec<&str> = lines[2].split('\t').collect();
    assert_eq!(values, ["10", "10", "11", "12", "m", "10", "1", "11"]);
    let markers: Vec<&str> = lines[3].split('\t').filter(|m| !m.is_empty()).collect();
    assert_eq!(markers[..2], ["Frame#", "Time"]);
    assert_eq!(markers[2..], qgait_model::points::point_names(true));
    let xyz: Vec<&str> = lines[4].split('\t').collect();
    assert_eq!(xyz.len(), 2 + 3 * 12);
    assert_eq!(xyz[2..5], ["X1", "Y1", "Z1"]);
    assert_eq!(xyz[35..], ["X12", "Y12", "Z12"]);
    assert_eq!(lines[5], "");
    assert_eq!(lines.len(), 6 + 11);
    for (r, line) in lines[6..].iter().enumerate() {
        let v: Vec<f64> = line.split('\t').map(|x| x.parse().unwrap()).collect();
        assert_eq!(v[0], (r + 1) as f64, "frame number");
        assert_eq!(v[1..], fk_rows[r][..], "row {r}");
    }

    // .sto, read by qgait's OpenSim reader.
    let (table, warnings) = MotionTable::read(&sto).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(!table.in_degrees());
    assert_eq!(table.labels(), columns);
    for (c, name) in columns.iter().enumerate() {
        let col = table.column(name).unwrap();
        for (r, row) in fk_rows.iter().enumerate() {
            assert_eq!(col[r], row[c], "{name} row {r}");
        }
    }
    let text = std::fs::read_to_string(&sto).unwrap();
    assert!(
        text.starts_with("inDegrees=no\nDataType=double\nversion=3\nendheader\ntime\t"),
        "{text}"
    );

    let out = qgait(&["export", motion]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("--trc"), "{}", stderr(&out));
}

#[test]
fn a_knee_offset_folds_into_the_splines_and_a_linear_knee_translation_is_a_two_knot_line() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let v3 = std::fs::read_to_string(shared.join("data/opensim").join(MODELS[0])).unwrap();
    let knee = v3.find("<CustomJoint name=\"knee_r\">").unwrap();
    let spline_start = knee + v3[knee..].find("<SimmSpline>").unwrap();
    let spline_end =
        spline_start + v3[spline_start..].find("</SimmSpline>").unwrap() + "</SimmSpline>".len();
    let edited = format!(
        "{}{}{}",
        &v3[..spline_start],
        "<LinearFunction><coefficients> 0.01 -0.004</coefficients></LinearFunction>",
        v3[spline_end..].replacen(
            "<location_in_parent> 0 0 0</location_in_parent>",
            "<location_in_parent> 0.001 -0.002 0</location_in_parent>",
            1
        )
    );
    let path = dir.path().join("knee.osim");
    std::fs::write(&path, edited).unwrap();
    let g = qgait_model::subject::read(&import(&path, dir.path(), "knee.toml")).unwrap();
    let generic = Gait2392Geometry::generic();
    // translation1: the line 0.01 q - 0.004 plus the offset 0.001, as two knots.
    let tx = g.right.knee_tx;
    let line = qgait_kernel::Spline::<f64>::new(&tx.x[..tx.n], &tx.y[..tx.n]).unwrap();
    for q in [-2.0, -0.5, 0.0, 0.3, 1.7] {
        assert!(
            (line.eval(q) - (0.01 * q - 0.004 + 0.001)).abs() < 1e-15,
            "{q}"
        );
    }
    // translation2: the generic spline shifted by the offset -0.002.
    let ty = g.right.knee_ty;
    for k in 0..ty.n {
        assert!((ty.y[k] - (generic.right.knee_ty.y[k] - 0.002)).abs() < 1e-15);
    }
    assert_eq!(
        g.left.knee_tx, generic.left.knee_tx,
        "the left knee is untouched"
    );
}

#[test]
fn a_non_zero_coordinate_default_is_noted() {
    let Some(shared) = shared_dir() else { return };
    let dir = tempfile::tempdir().unwrap();
    let v4 = std::fs::read_to_string(shared.join("data/opensim").join(MODELS[1])).unwrap();
    let c = v4.find("<Coordinate name=\"mtp_angle_r\">").unwrap();
    let edited = format!(
        "{}{}",
        &v4[..c],
        v4[c..].replacen(
            "<default_value>0</default_value>",
            "<default_value>0.25</default_value>",
            1
        )
    );
    let path = dir.path().join("default.osim");
    std::fs::write(&path, edited).unwrap();
    let out = dir.path().join("d.toml");
    let (_, err) = run_ok(&["model", "import", s(&path), "-o", s(&out)]);
    assert!(
        err.contains("note: coordinate mtp_angle_r has default_value 0.25 in the model; qgait takes a coordinate absent from a motion as 0"),
        "{err}"
    );
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("# coordinate mtp_angle_r has default_value 0.25"));
}

/// `export --lab-frame` writes the points in OpenSim's ground frame: against OpenSim 4.6's
/// own positions of normal.mot (its `groundrel` columns plus the pelvis origin in ground),
/// within a micrometre. normal.mot sets `pelvis_ty` only: the other two are 0 with a warning.
/// A motion without any pelvis translation is refused.
#[test]
fn export_in_the_lab_frame_matches_opensims_ground_positions() {
    let Some(shared) = shared_dir() else { return };
    let reference = Reference::load(&shared);
    let dir = tempfile::tempdir().unwrap();
    let sto = dir.path().join("lab.sto");
    let motion = shared.join("data/opensim/normal.mot");
    let (_, err) = run_ok(&[
        "export",
        s(&motion),
        "--model",
        "gait2392",
        "--points",
        "--lab-frame",
        "--sto",
        s(&sto),
    ]);
    assert!(
        err.contains("no `pelvis_tx` column; taken as 0 in the lab frame")
            && err.contains("no `pelvis_tz` column")
            && !err.contains("no `pelvis_ty` column"),
        "{err}"
    );
    let (table, _) = MotionTable::read(&sto).unwrap();
    let mut worst = 0.0f64;
    for name in table.labels().iter().skip(1) {
        let col = table.column(name).unwrap();
        let axis = &name[name.len() - 1..];
        let point = name.replacen("toe_", "toetip_", 1);
        for (r, v) in col.iter().enumerate() {
            let truth = reference.get(r, &format!("{point}_groundrel"))
                + reference.get(r, &format!("pelvis_{axis}_ground"));
            worst = worst.max((v - truth).abs());
        }
    }
    assert!(
        worst < 1e-6,
        "worst {worst} m from OpenSim's ground positions"
    );
    // The pelvis is 0.96 m up: the lab frame is not the pelvis-relative one.
    let hip_y = table.column("hip_r_y").unwrap()[0];
    assert!((hip_y - (0.96 - 0.0661)).abs() < 0.01, "{hip_y}");

    let err = run_err(&[
        "export",
        "builtin:normal",
        "--lab-frame",
        "--sto",
        s(&dir.path().join("b.sto")),
    ]);
    assert!(
        err.contains("--lab-frame needs the pelvis translation"),
        "{err}"
    );
    // Without --lab-frame the translation the motion has is said to be left out.
    let (_, err) = run_ok(&[
        "export",
        s(&motion),
        "--model",
        "gait2392",
        "--sto",
        s(&dir.path().join("rel.sto")),
    ]);
    assert!(
        err.contains("pelvis_ty not applied") && err.contains("--lab-frame adds the translation"),
        "{err}"
    );
    let (_, err) = run_ok(&[
        "export",
        "builtin:normal",
        "--sto",
        s(&dir.path().join("b.sto")),
    ]);
    assert!(!err.contains("not applied"), "{err}");
}
