//! `qgait fidelity`: runs, and its numbers are sane (switching every gait2392 feature off gives
//! PHAK exactly; features a motion does not use cost nothing; known magnitudes).

mod common;

use common::{qgait, shared_dir, stderr, stdout};

fn fidelity(args: &[&str]) -> String {
    let mut all = vec!["-q", "fidelity"];
    all.extend_from_slice(args);
    let out = qgait(&all);
    assert!(out.status.success(), "qgait {all:?}: {}", stderr(&out));
    stdout(&out)
}

/// The numbers of a Markdown table row whose first cell starts with `first` (`/` separates
/// pairs), from the `nth` matching row.
fn row(md: &str, first: &str, nth: usize) -> Vec<f64> {
    let line = md
        .lines()
        .filter(|l| l.starts_with(&format!("| {first}")))
        .nth(nth)
        .unwrap_or_else(|| panic!("no row `{first}` #{nth} in\n{md}"));
    line.split(['|', '/'])
        .skip(2)
        .filter_map(|c| c.trim().parse().ok())
        .collect()
}

#[test]
fn all_features_off_gives_phak_and_absent_features_cost_nothing() {
    let md = fidelity(&[
        "builtin:normal",
        "builtin:crouch=1",
        "--label",
        "N",
        "--label",
        "C",
    ]);
    // Per motion: the ablation with everything off is PHAK itself (raw and hip-relative, max
    // and mean), to rounding.
    for nth in 0..2 {
        let v = row(&md, "all of the above", nth);
        assert_eq!(v.len(), 6, "{v:?}");
        assert!(v[..4].iter().all(|d| *d < 1e-9), "{v:?}");
    }
    // The built-in gaits have no pelvis tilt or hip adduction/rotation: switching them off
    // moves nothing (own-effect summary: mean / max for N, then C).
    assert_eq!(row(&md, "pelvis tilt set to 0", 0), [0.0; 4]);
    assert_eq!(row(&md, "hip adduction and rotation set to 0", 0), [0.0; 4]);
    // PHAK's hips are 96.79 mm from gait2392's ((-0.0707, -0.0661) in the pelvis frame);
    // hip-relative, the hips agree by construction.
    for (nth, label) in ["N", "C"].iter().enumerate() {
        let hip = row(&md, "hip_r", nth);
        assert!((hip[1] - 96.79).abs() < 1.0, "{label}: {hip:?}");
        assert_eq!(hip[2..], [0.0, 0.0], "{label}");
    }
    // The knee's spline translation moves the knee at most 26.81 mm (at -120 degrees).
    let knee = row(&md, "knee translation frozen", 0);
    assert!(knee.iter().all(|v| *v > 0.0 && *v < 26.81), "{knee:?}");
}

#[test]
fn shared_motions_all_features_off_is_zero_and_tilt_dominates_severe_crouch() {
    let Some(shared) = shared_dir() else { return };
    let motions: Vec<String> = ["normal", "crouch4"]
        .iter()
        .map(|m| {
            shared
                .join(format!("data/opensim/{m}.mot"))
                .display()
                .to_string()
        })
        .collect();
    let md = fidelity(&[&motions[0], &motions[1]]);
    for nth in 0..2 {
        let v = row(&md, "all of the above", nth);
        assert!(v[..4].iter().all(|d| *d < 1e-9), "{v:?}");
    }
    // Own effect (mean / max) for normal, then crouch4.
    let tilt = row(&md, "pelvis tilt set to 0", 0);
    let hip = row(&md, "hip adduction and rotation set to 0", 0);
    let ankle = row(&md, "ankle axis replaced by +z", 0);
    assert!(
        hip[0] > tilt[0],
        "normal gait: hip adduction/rotation costs more than tilt"
    );
    assert!(
        tilt[2] > hip[2],
        "severe crouch (tilt -12..-23 deg): tilt costs more"
    );
    assert!(ankle[0] < hip[0] && ankle[2] < tilt[2], "{ankle:?}");
}

#[test]
fn a_motion_whose_knees_flex_with_positive_angles_is_warned_about() {
    // OpenSense's Rajagopal solution: knees 0 to 56° of flexion in Rajagopal's signs.
    let raj = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/imu/walking_rajagopal2015_opensense_0-10s.mot"
    );
    let warned = |motion: &str| {
        let out = qgait(&["fidelity", motion]);
        assert!(out.status.success(), "{}", stderr(&out));
        stderr(&out).contains("the knees flex with positive angles")
    };
    assert!(warned(raj));
    assert!(!warned("builtin:crouch=0.8,rows=20"));
}
