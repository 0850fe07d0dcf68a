//! PHAK's structure: with the pelvis level it is two HAKs hung from the hips; left and right
//! mirror each other.

mod common;

use qgait_kernel::metrics::distances;
use qgait_kernel::{Anthropometry, Hak, HakAngles, Limb, Phak, PhakAngles, Side, Vec3};

/// HAK for both legs ([`Phak::fk_hak`]): each leg is [`Hak`] hung at its hip, ±w on the z
/// axis, whatever the pelvis angles given (ignored), and equal to PHAK with a level pelvis.
#[test]
fn zero_pelvis_angles_equal_hak_per_side_shifted_by_the_hip() {
    let a = Anthropometry {
        right: Limb::gait2392(),
        left: Limb {
            femur: 0.41,
            tibia: 0.42,
            foot: 0.2,
            pelvis_half_width: 0.09,
        },
    };
    let phak = Phak::new(&a).unwrap();
    let mut rng = common::rng(3);
    for _ in 0..2000 {
        let tilted = PhakAngles::from_array(common::random_angles(&mut rng));
        let hak = phak.fk_hak(&tilted);
        let mut q = tilted;
        q.pelvis_rotation = 0.0;
        q.pelvis_list = 0.0;
        let pose = phak.fk(&q);
        assert_eq!(hak, pose);
        for (side, angles) in [
            (
                Side::Right,
                HakAngles {
                    hip_flexion: q.hip_flexion_r,
                    knee_angle: q.knee_angle_r,
                    ankle_angle: q.ankle_angle_r,
                },
            ),
            (
                Side::Left,
                HakAngles {
                    hip_flexion: q.hip_flexion_l,
                    knee_angle: q.knee_angle_l,
                    ankle_angle: q.ankle_angle_l,
                },
            ),
        ] {
            let limb = a.limb(side);
            let hip = Vec3::new(0.0, 0.0, side.sign::<f64>() * limb.pelvis_half_width);
            let expected = Hak::new(limb).unwrap().fk(&angles).translated(hip);
            for (p, e) in pose.leg(side).points().iter().zip(expected.points()) {
                assert!(p.max_abs_diff(e) < 1e-14, "{side:?}: {p:?} vs {e:?}");
            }
        }
    }
}

#[test]
fn left_and_right_mirror_each_other() {
    // Reflecting through z = 0 negates rotations about x and y (axes in the mirror plane) and
    // keeps rotations about z: so swapping the legs' angles and negating the pelvis angles
    // mirrors the pose and swaps the sides.
    let phak = Phak::new(&Anthropometry::gait2392()).unwrap();
    let mirror = |v: Vec3<f64>| Vec3::new(v.x, v.y, -v.z);
    let mut rng = common::rng(4);
    for _ in 0..2000 {
        let q = PhakAngles::from_array(common::random_angles(&mut rng));
        let m = PhakAngles {
            pelvis_rotation: -q.pelvis_rotation,
            pelvis_list: -q.pelvis_list,
            hip_flexion_r: q.hip_flexion_l,
            knee_angle_r: q.knee_angle_l,
            ankle_angle_r: q.ankle_angle_l,
            hip_flexion_l: q.hip_flexion_r,
            knee_angle_l: q.knee_angle_r,
            ankle_angle_l: q.ankle_angle_r,
        };
        let (p, pm) = (phak.fk(&q), phak.fk(&m));
        for (a, b) in p.right.points().iter().zip(pm.left.points()) {
            assert!(mirror(*a).max_abs_diff(b) < 1e-14);
        }
        for (a, b) in p.left.points().iter().zip(pm.right.points()) {
            assert!(mirror(*a).max_abs_diff(b) < 1e-14);
        }
        let (d, dm) = (distances(&p), distances(&pm));
        assert!((d.knee - dm.knee).abs() < 1e-14 && (d.toe - dm.toe).abs() < 1e-14);
    }
}

#[test]
fn hip_distance_is_constant_and_segment_lengths_are_kept() {
    let a = Anthropometry::<f64>::gait2392();
    let phak = Phak::new(&a).unwrap();
    let mut rng = common::rng(5);
    for _ in 0..2000 {
        let p = phak.fk(&PhakAngles::from_array(common::random_angles(&mut rng)));
        assert!((Vec3::distance(p.right.hip, p.left.hip) - 0.167).abs() < 1e-14);
        for leg in [p.right, p.left] {
            assert!((Vec3::distance(leg.hip, leg.knee) - a.right.femur).abs() < 1e-14);
            assert!((Vec3::distance(leg.knee, leg.ankle) - a.right.tibia).abs() < 1e-14);
            assert!((Vec3::distance(leg.ankle, leg.toe) - a.right.foot).abs() < 1e-14);
        }
    }
}

#[test]
fn pelvis_list_tilts_the_hips_about_the_forward_axis() {
    let phak = Phak::new(&Anthropometry::<f64>::gait2392()).unwrap();
    let p = phak.fk(&PhakAngles {
        pelvis_list: 0.1,
        ..Default::default()
    });
    // Right-handed about +x: y turns towards z and z towards -y, so the right hip drops.
    assert!(p.right.hip.y < 0.0 && p.left.hip.y > 0.0);
    assert!(p.right.hip.x.abs() < 1e-15);
    let p = phak.fk(&PhakAngles {
        pelvis_rotation: 0.1,
        ..Default::default()
    });
    // Right-handed about +y: z turns towards x, so the right hip goes forward.
    assert!(p.right.hip.x > 0.0 && p.left.hip.x < 0.0 && p.right.hip.y.abs() < 1e-15);
}
