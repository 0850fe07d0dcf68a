//! The paper's own check: q = 0, l1 = l2 = l3 = 1 gives the toe at (1, -2, 0), by all three
//! HAK methods (and PHAK's legs, shifted by the hips).

use qgait_kernel::reference::{hak_denavit_hartenberg, hak_geometric};
use qgait_kernel::{Anthropometry, Hak, HakAngles, Limb, Phak, PhakAngles, Vec3};

const UNIT: Limb<f64> = Limb {
    pelvis_half_width: 0.1,
    femur: 1.0,
    tibia: 1.0,
    foot: 1.0,
};

fn assert_close(a: Vec3<f64>, b: Vec3<f64>, tol: f64) {
    assert!(a.max_abs_diff(b) <= tol, "{a:?} != {b:?}");
}

#[test]
fn toe_at_one_minus_two_zero_by_all_three_methods() {
    let q = HakAngles::default();
    let expected = Vec3::new(1.0, -2.0, 0.0);
    assert_close(Hak::new(&UNIT).unwrap().fk(&q).toe, expected, 1e-15);
    assert_close(hak_geometric(&UNIT, &q).toe, expected, 1e-15);
    assert_close(hak_denavit_hartenberg(&UNIT, &q).toe, expected, 1e-15);
    let f32_toe = Hak::new(&UNIT.cast::<f32>())
        .unwrap()
        .fk(&HakAngles::default())
        .toe;
    assert_eq!(f32_toe, Vec3::new(1.0f32, -2.0, 0.0));
}

#[test]
fn neutral_phak_hangs_both_legs_straight_down() {
    let pose = Phak::new(&Anthropometry::symmetric(UNIT))
        .unwrap()
        .fk(&PhakAngles::default());
    assert_close(pose.right.toe, Vec3::new(1.0, -2.0, 0.1), 1e-15);
    assert_close(pose.left.toe, Vec3::new(1.0, -2.0, -0.1), 1e-15);
    assert_close(pose.right.knee, Vec3::new(0.0, -1.0, 0.1), 1e-15);
}

#[test]
fn opensim_sign_conventions_hold() {
    let hak = Hak::new(&Limb::gait2392()).unwrap();
    let base = hak.fk(&HakAngles::default());
    let flexed_hip = hak.fk(&HakAngles {
        hip_flexion: 0.3,
        ..Default::default()
    });
    assert!(
        flexed_hip.knee.x > base.knee.x,
        "hip flexion > 0 swings the knee forward"
    );
    let flexed_knee = hak.fk(&HakAngles {
        knee_angle: -0.5,
        ..Default::default()
    });
    assert!(
        flexed_knee.ankle.x < base.ankle.x,
        "knee_angle < 0 (flexion) moves the ankle back"
    );
    let dorsi = hak.fk(&HakAngles {
        ankle_angle: 0.2,
        ..Default::default()
    });
    assert!(
        dorsi.toe.y > base.toe.y,
        "ankle > 0 (dorsiflexion) lifts the toe"
    );
}
