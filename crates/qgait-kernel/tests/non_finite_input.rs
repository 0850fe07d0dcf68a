//! No panic on any input: NaN or infinite angles give NaN positions; bad model data is an error.

use qgait_kernel::metrics::distances;
use qgait_kernel::{Anthropometry, Hak, HakAngles, Limb, ModelError, Phak, PhakAngles};

#[test]
fn nan_and_infinite_angles_give_nan_positions_without_panicking() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let phak = Phak::new(&Anthropometry::gait2392()).unwrap();
        let pose = phak.fk(&PhakAngles {
            pelvis_list: bad,
            ..Default::default()
        });
        assert!(pose
            .points()
            .iter()
            .skip(1)
            .all(|p| p.x.is_nan() || p.y.is_nan() || p.z.is_nan()));
        let d = distances(&pose);
        assert!(d.knee.is_nan());
        let phak32 = Phak::new(&Anthropometry::<f32>::gait2392()).unwrap();
        let pose32 = phak32.fk(&PhakAngles {
            knee_angle_r: bad as f32,
            ..Default::default()
        });
        assert!(pose32.right.ankle.x.is_nan());
        assert!(
            !pose32.right.knee.x.is_nan(),
            "joints above the bad one are unaffected"
        );
        let hak = Hak::new(&Limb::<f32>::gait2392()).unwrap();
        assert!(hak
            .fk(&HakAngles {
                ankle_angle: bad as f32,
                ..Default::default()
            })
            .toe
            .y
            .is_nan());
    }
}

#[test]
fn huge_angles_are_reduced_not_garbage() {
    let hak = Hak::new(&Limb::<f32>::gait2392()).unwrap();
    let a = hak.fk(&HakAngles {
        hip_flexion: 0.3,
        ..Default::default()
    });
    let b = hak.fk(&HakAngles {
        hip_flexion: 0.3 + 2.0 * core::f32::consts::PI * 100.0,
        ..Default::default()
    });
    assert!(a.toe.max_abs_diff(b.toe) < 1e-4, "{a:?} {b:?}");
}

#[test]
fn bad_lengths_are_rejected() {
    let mut limb = Limb::<f64>::gait2392();
    limb.tibia = f64::NAN;
    assert_eq!(Hak::new(&limb).unwrap_err(), ModelError::BadLength);
    limb.tibia = -0.1;
    assert_eq!(
        Phak::new(&Anthropometry::symmetric(limb)).unwrap_err(),
        ModelError::BadLength
    );
}
