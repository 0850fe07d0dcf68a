//! `Chain::new` orders the spline translations by joint, keeping the given order among a
//! joint's splines, whatever order they come in.

use qgait_kernel::{Chain, JointSpec, PointSpec, Spline, SplineTranslation, Vec3};

fn spline(slope: f64) -> Spline<f64> {
    Spline::new(&[-1.0, 0.0, 1.0], &[-slope, 0.0, slope * 1.5]).unwrap()
}

fn translation(
    joint: usize,
    direction: Vec3<f64>,
    coordinate: usize,
    slope: f64,
) -> SplineTranslation<f64> {
    SplineTranslation {
        joint,
        direction,
        coordinate,
        spline: spline(slope),
    }
}

fn chain(splines: [SplineTranslation<f64>; 5]) -> Chain<f64, 3, 3, 3, 5> {
    let joints = [
        JointSpec::new(None, Vec3::zero(), &[(Vec3::unit_z(), 0)]),
        JointSpec::new(Some(0), Vec3::new(0.1, -0.4, 0.0), &[(Vec3::unit_z(), 1)]),
        JointSpec::new(
            Some(1),
            Vec3::new(0.0, -0.4, 0.02),
            &[(Vec3::new(0.2, 0.1, 1.0), 2)],
        ),
    ];
    let points = [0, 1, 2].map(|body| PointSpec {
        body,
        offset: Vec3::new(0.05, 0.0, 0.0),
    });
    Chain::new(joints, points, splines).unwrap()
}

#[test]
fn splines_are_sorted_by_joint_stably() {
    let s = [
        translation(2, Vec3::unit_x(), 0, 0.01),
        translation(1, Vec3::unit_y(), 1, 0.02),
        translation(2, Vec3::unit_y(), 2, 0.03),
        translation(0, Vec3::unit_z(), 1, 0.04),
        translation(1, Vec3::unit_x(), 2, 0.05),
    ];
    let shuffled = chain(s);
    let sorted = chain([s[3], s[1], s[4], s[0], s[2]]);
    assert_eq!(shuffled.splines(), &[s[3], s[1], s[4], s[0], s[2]]);
    assert_eq!(shuffled, sorted);
    let q = [0.3, -0.7, 0.4];
    assert_eq!(shuffled.forward(&q), sorted.forward(&q));
    // The splines do move the points: not a chain whose splines are ignored.
    let still = chain(s.map(|t| SplineTranslation {
        spline: spline(0.0),
        ..t
    }));
    assert_ne!(shuffled.forward(&q), still.forward(&q));
}
