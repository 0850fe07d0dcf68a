//! Every OpenSim lower-limb model qgait imports, against OpenSim 4.6 itself: the joint centres
//! and toe tips of `scripts/opensim_reference.py` (tests/data/opensim_reference/, the models from
//! ../shared/data/opensim/) on every row, within 1 µm, through the library (`Model::load`, the
//! chain importer, `CHAIN.toml`). `qgait model import` and `fidelity` on them through the
//! binary: `host/tests/opensim_models_cli.rs`.

mod common;

use std::path::Path;

use common::{parse_fk_csv, shared_dir};
use qgait_kernel::models::gait2392::{COORDINATES, POINTS};
use qgait_kernel::Vec3;
use qgait_model::choice::Model;

const MODELS: [(&str, &str); 5] = [
    ("gait2392", "gait2392_simbody.osim"),
    ("gait2354", "gait2354_simbody.osim"),
    ("gait10dof18musc", "gait10dof18musc.osim"),
    ("rajagopal2016", "Rajagopal2016.osim"),
    ("rajagopal2015_opensense", "Rajagopal2015_opensense.osim"),
];

/// The reference rows: coordinates (COORDINATES order) and the 12 points (POINTS order).
fn reference(name: &str, motion: &str) -> Vec<([f64; 17], [Vec3<f64>; 12])> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("tests/data/opensim_reference/{name}_{motion}.csv"));
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

/// The largest difference of `fk`'s points from OpenSim's on every row of the reference
/// `name`, `motion`: (metres, row, point).
fn largest_difference(
    fk: &qgait_model::points::ImportedFk,
    name: &str,
    motion: &str,
) -> (f64, usize, &'static str) {
    let mut worst = (0.0f64, 0, "");
    for (row, (q, expected)) in reference(name, motion).iter().enumerate() {
        for ((p, e), n) in fk(q).iter().zip(expected).zip(POINTS) {
            let d = p.max_abs_diff(*e);
            if d > worst.0 {
                worst = (d, row, n);
            }
        }
    }
    worst
}

#[test]
fn every_point_of_every_model_is_within_a_micrometre_of_opensim() {
    let Some(shared) = shared_dir() else { return };
    for (name, file) in MODELS {
        let path = shared.join("data/opensim").join(file);
        let (model, _) = Model::load(path.to_str().unwrap(), None).unwrap();
        let general = matches!(model, Model::Chain { .. });
        let fk = points(&model);
        let mut motions = vec!["normal", "sweep"];
        if name == "rajagopal2015_opensense" {
            // OpenSense's own Rajagopal solution of the IMU walking recording.
            motions.push("opensense");
        }
        for motion in motions {
            let worst = largest_difference(&fk, name, motion);
            println!(
                "{name} ({}) {motion}: largest difference {:.3e} m (row {}, {})",
                if general { "chain" } else { "gait2392 table" },
                worst.0,
                worst.1,
                worst.2
            );
            assert!(worst.0 < 1e-6, "{name} {motion}: {worst:?}");
        }
    }
}

/// Rajagopal2016 with each walker knee's four splines replaced by polynomials (OpenSim
/// `PolynomialFunction`, as Rajagopal-Lai-Uhlrich 2023 drives its knee; the left knee's
/// translation1 inside a `MultiplierFunction`): the numbers and the edit of
/// `scripts/opensim_reference.py`'s `polynomial_knee`, made here by text.
fn polynomial_knee(rajagopal2016: &str) -> String {
    const POLYNOMIALS: [(&str, &str); 4] = [
        ("rotation2", "0.004 -0.02 -0.01 0.07 0.0"),
        ("rotation3", "0.0 0.02 -0.12 0.33 0.0"),
        ("translation1", "0.0 0.0004 -0.0019 0.0029 0.0"),
        ("translation2", "0.0001 -0.0006 0.0001 0.0055 0.0"),
    ];
    let mut text = rajagopal2016.to_string();
    for side in ["r", "l"] {
        let joint = text
            .find(&format!("<CustomJoint name=\"walker_knee_{side}\""))
            .expect("Rajagopal's walker knee");
        for (axis, coefficients) in POLYNOMIALS {
            let at = joint
                + text[joint..]
                    .find(&format!("<TransformAxis name=\"{axis}\">"))
                    .unwrap();
            let start = at + text[at..].find("<SimmSpline").unwrap();
            let end = start + text[start..].find("</SimmSpline>").unwrap() + "</SimmSpline>".len();
            let mut polynomial = format!(
                "<PolynomialFunction name=\"function\"><coefficients>{coefficients}</coefficients></PolynomialFunction>"
            );
            if (side, axis) == ("l", "translation1") {
                polynomial = format!(
                    "<MultiplierFunction name=\"function\"><function>{polynomial}</function><scale>1.1</scale></MultiplierFunction>"
                );
            }
            text.replace_range(start..end, &polynomial);
        }
    }
    text
}

#[test]
fn a_polynomial_knee_is_within_a_micrometre_of_opensim_and_not_sent_to_a_hub() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    let (model, _) = Model::import(&polynomial_knee(&text), "polynomial_knee.osim", None).unwrap();
    let Model::Chain { chain, .. } = &model else {
        panic!("a chain model")
    };
    let table = chain.chain("test").unwrap();
    assert_eq!(table.polynomials().len(), 8);
    assert!(table.splines().is_empty());
    let fk = points(&model);
    for motion in ["normal", "sweep"] {
        let worst = largest_difference(&fk, "rajagopal2016_polynomial_knee", motion);
        println!(
            "Rajagopal2016, polynomial knee, {motion}: largest difference {:.3e} m (row {}, {})",
            worst.0, worst.1, worst.2
        );
        assert!(worst.0 < 1e-6, "{motion}: {worst:?}");
    }
    // The chain messages carry constants, lines and splines only.
    assert_eq!(
        qgait_proto::device_model::ChainUpload::of_chain(&table, 1),
        Err(qgait_proto::ConfigError::ChainPolynomial)
    );
}

#[test]
fn rajagopal_and_gait10dof_are_chains_and_gait2354_stays_gait2392s_table() {
    let Some(shared) = shared_dir() else { return };
    let load = |f: &str| {
        let p = shared.join("data/opensim").join(f);
        Model::load(p.to_str().unwrap(), None).unwrap()
    };
    assert!(matches!(
        load("gait2354_simbody.osim").0,
        Model::Gait2392 { .. }
    ));
    let (raj, notes) = load("Rajagopal2016.osim");
    assert!(matches!(raj, Model::Chain { .. }));
    let all = notes.join("\n");
    assert!(all.contains("patella_r"), "{all}");
    assert!(all.contains("subtalar_angle_r is locked"), "{all}");
    let (planar, notes) = load("gait10dof18musc.osim");
    assert!(matches!(planar, Model::Chain { .. }));
    assert!(notes
        .iter()
        .any(|n| n.contains("pelvis translations left out")));
}

#[test]
fn a_ball_joint_in_the_chain_is_refused_naming_it() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    let start = text
        .find("<PinJoint name=\"ankle_r\"")
        .expect("Rajagopal's ankle_r");
    let end = start + text[start..].find("</PinJoint>").unwrap() + "</PinJoint>".len();
    let ball = text[start..end]
        .replace("<PinJoint", "<BallJoint")
        .replace("</PinJoint>", "</BallJoint>");
    let edited = format!("{}{}{}", &text[..start], ball, &text[end..]);
    let err = Model::import(&edited, "edited.osim", None)
        .unwrap_err()
        .to_string();
    assert!(err.contains("joint `ankle_r` is a BallJoint"), "{err}");
}

#[test]
fn a_leg_coordinate_that_is_not_an_input_is_refused_unless_locked() {
    // leg39 calls its hip flexion `hip_angle_r`: held at its default, the femur would not
    // follow the motion's `hip_flexion_r`.
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    let renamed = text.replace("hip_flexion_r", "hip_angle_r");
    let err = Model::import(&renamed, "renamed.osim", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(
            "coordinate `hip_angle_r` moves `femur_r` but is not one of the chain's inputs"
        ),
        "{err}"
    );
    // Locked, it is held at its default, as OpenSim holds it.
    let start = renamed.find("<Coordinate name=\"hip_angle_r\">").unwrap();
    let end = start + renamed[start..].find("</Coordinate>").unwrap();
    let locked = format!(
        "{}{}{}",
        &renamed[..start],
        renamed[start..end].replace("<locked>false</locked>", "<locked>true</locked>"),
        &renamed[end..]
    );
    let (model, notes) = Model::import(&locked, "locked.osim", None).unwrap();
    assert!(matches!(model, Model::Chain { .. }));
    assert!(
        notes.iter().any(|n| n.contains("hip_angle_r is locked")),
        "{notes:?}"
    );
}

#[test]
fn a_chain_file_refused_for_what_it_says_names_the_line_and_column() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    let (Model::Chain { chain, .. }, _) = Model::import(&text, "raj.osim", None).unwrap() else {
        panic!("Rajagopal is a chain");
    };
    let toml = chain.to_toml(&[]);
    // Each edit: what it replaces (its first occurrence), with what, and what the error says;
    // the error must name the line and column where the replacement starts.
    for (from, to, says) in [
        (
            "coordinate = \"pelvis_tilt\"",
            "coordinate = \"pelvis_tlt\"",
            "coordinate `pelvis_tlt` is neither an input",
        ),
        (
            "body = \"toes_r\"\nlocation",
            "body = \"toe_r\"\nlocation",
            "toe tip on `toe_r`",
        ),
        (
            "min = -1.57079633",
            "min = 3",
            "range of `pelvis_tilt`: min 3 above max",
        ),
        (
            "body = \"femur_l\"",
            "body = \"femur_x\"",
            "joint `hip_l` moves `femur_x`",
        ),
    ] {
        let start = toml
            .find(from)
            .unwrap_or_else(|| panic!("{from} in the file"));
        let edited = toml.replacen(from, to, 1);
        // The value's line and column (1-based): where `=` is followed by the value.
        let value = start + to.find('=').unwrap() + 2;
        let line = edited[..value].matches('\n').count() + 1;
        let column = value - edited[..value].rfind('\n').map_or(0, |i| i + 1) + 1;
        let err = qgait_model::chain::ChainModel::parse(&edited, "raj.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with(&format!("raj.toml:{line}:{column}: ")) && err.contains(says),
            "{to}: {err}"
        );
    }
}

#[test]
fn a_single_leg_model_is_refused_saying_so() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    // Without the left hip, no joint moves `femur_l`.
    let start = text.find("<CustomJoint name=\"hip_l\">").unwrap();
    let end = start + text[start..].find("</CustomJoint>").unwrap() + "</CustomJoint>".len();
    let one_leg = format!("{}{}", &text[..start], &text[end..]);
    let err = Model::import(&one_leg, "one_leg.osim", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("a single-leg model: no joint moves `femur_l` (only `femur_r`)"),
        "{err}"
    );
}

#[test]
fn rajagopal_in_f32_stays_within_ten_micrometres_of_f64() {
    let Some(shared) = shared_dir() else { return };
    let path = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    let (model, _) = Model::load(path.to_str().unwrap(), None).unwrap();
    let Model::Chain { chain, .. } = model else {
        panic!("Rajagopal is a chain model")
    };
    let c64 = chain.chain("test").unwrap();
    let c32 = c64.cast::<f32>();
    let mut worst = 0.0f64;
    // (Not `opensense`: OpenSense's pelvis angles there wander to hundreds of radians, equivalent
    // rotations whose f32 inputs alone are 3e-5 rad apart.)
    for motion in ["normal", "sweep"] {
        for (q, _) in reference("rajagopal2015_opensense", motion) {
            let p32 = c32.forward(&q.map(|v| v as f32));
            for (a, b) in p32.iter().zip(c64.forward(&q)) {
                worst = worst.max(a.cast::<f64>().max_abs_diff(b));
            }
        }
    }
    println!("Rajagopal f32 against f64: largest difference {worst:.3e} m");
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn a_weld_constraint_on_a_leg_body_is_refused_and_one_on_the_arm_accepted() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/Rajagopal2016.osim")).unwrap();
    let at = text.find("<ConstraintSet").unwrap();
    let objects = at + text[at..].find("<objects>").unwrap() + "<objects>".len();
    let with = |body: &str| {
        format!(
            "{}<WeldConstraint name=\"weld\"><socket_frame1>/bodyset/{body}</socket_frame1><socket_frame2>/ground</socket_frame2></WeldConstraint>{}",
            &text[..objects],
            &text[objects..]
        )
    };
    let err = Model::import(&with("calcn_r"), "weld.osim", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("WeldConstraint `weld` constrains body `calcn_r` of the leg chain"),
        "{err}"
    );
    assert!(Model::import(&with("hand_r"), "weld.osim", None).is_ok());
}

/// A gait2392 model with a leg coordinate locked is imported as a general chain, which holds
/// the coordinate at its default as OpenSim does (gait2392's table would move it); one with a
/// leg coordinate clamped too.
#[test]
fn a_locked_coordinate_of_a_gait2392_model_is_held_at_its_default() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/gait2392_simbody.osim")).unwrap();
    let at = text.find("<Coordinate name=\"hip_flexion_r\">").unwrap();
    let lock = at + text[at..].find("<locked>false</locked>").unwrap();
    let locked = format!(
        "{}<locked>true</locked>{}",
        &text[..lock],
        &text[lock + "<locked>false</locked>".len()..]
    );
    let (model, notes) = Model::import(&locked, "locked.osim", None).unwrap();
    assert!(matches!(model, Model::Chain { .. }));
    let all = notes.join("\n");
    assert!(all.contains("hip_flexion_r is locked"), "{all}");
    let fk = points(&model);
    let mut q = [0.0; 17];
    let still = fk(&q);
    q[3] = 0.6; // hip_flexion_r
    assert_eq!(fk(&q), still);
    let (free, _) = Model::import(&text, "free.osim", None).unwrap();
    assert!(matches!(free, Model::Gait2392 { .. }));
    assert_ne!(points(&free)(&q)[1], still[1]);
    // A clamped one takes the general chain too (its range bounds `qgait imu`).
    let clamp = at + text[at..].find("<clamped>false</clamped>").unwrap();
    let clamped = format!(
        "{}<clamped>true</clamped>{}",
        &text[..clamp],
        &text[clamp + "<clamped>false</clamped>".len()..]
    );
    let (model, _) = Model::import(&clamped, "clamped.osim", None).unwrap();
    assert!(matches!(model, Model::Chain { .. }));
    let (a, b) = (points(&model)(&q)[1], points(&free)(&q)[1]);
    assert!(a.max_abs_diff(b) < 1e-12, "{a:?} {b:?}");
}

/// A transform axis turning by a coordinate its joint does not declare is refused, as OpenSim
/// refuses the model.
#[test]
fn an_axis_naming_a_coordinate_its_joint_does_not_declare_is_refused() {
    let Some(shared) = shared_dir() else { return };
    let text = std::fs::read_to_string(shared.join("data/opensim/gait2392_simbody.osim")).unwrap();
    let renamed = text.replacen(
        "<Coordinate name=\"knee_angle_r\">",
        "<Coordinate name=\"knee_r_flex\">",
        1,
    );
    let err = Model::import(&renamed, "renamed.osim", None)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("turns by coordinate `knee_angle_r`, which the joint does not declare (its coordinates: knee_r_flex)"),
        "{err}"
    );
}

/// The packed table a hub holds (`qgait_kernel::models::packed`), of every chain model, against
/// OpenSim on every reference row: within 1 µm in `f64`, and within 10 µm in `f32` in the pool
/// size a hub's model slot has room for.
#[test]
fn every_chain_model_packed_is_within_a_micrometre_of_opensim() {
    let Some(shared) = shared_dir() else { return };
    for (name, file) in MODELS {
        let path = shared.join("data/opensim").join(file);
        let (model, _) = Model::load(path.to_str().unwrap(), None).unwrap();
        let Model::Chain { chain, .. } = model else {
            continue;
        };
        let chain = chain.chain("test").unwrap();
        let packed = chain.packed::<f64, 12, 12, 66, 1024>().unwrap();
        let device = chain.packed::<f32, 8, 0, 24, 384>().unwrap();
        let (mut worst, mut worst32) = (0.0f64, 0.0f64);
        for motion in ["normal", "sweep"] {
            for (q, expected) in reference(name, motion) {
                let p32 = device.forward(&q.map(|v| v as f32));
                for ((p, e), a) in packed.forward(&q).iter().zip(&expected).zip(&p32) {
                    worst = worst.max(p.max_abs_diff(*e));
                    worst32 = worst32.max(a.cast::<f64>().max_abs_diff(*e));
                }
            }
        }
        println!(
            "{name} packed: {} numbers, largest difference {worst:.3e} m in f64, {worst32:.3e} m in f32",
            packed.used()
        );
        assert!(worst < 1e-6, "{name}: {worst}");
        assert!(worst32 < 1e-5, "{name}: {worst32}");
    }
}
