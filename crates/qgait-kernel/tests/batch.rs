//! The batch (SIMD) path equals the single-frame path for every model, in both precisions, for
//! batch lengths that are and are not multiples of the lane count.

mod common;

use qgait_kernel::lanes::LANES;
use qgait_kernel::{
    Anthropometry, BilateralPose, Gait2392, Gait2392Geometry, Gait2392Pose, Hak, HakAngles,
    LegPose, Limb, Phak, PhakAngles, Vec3,
};

fn worst<T: qgait_kernel::Real>(a: &[Vec3<T>], b: &[Vec3<T>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.max_abs_diff(*q).to_f64())
        .fold(0.0, f64::max)
}

#[test]
fn phak_batch_equals_single_frames() {
    let mut rng = common::rng(30);
    for frames in [0, 1, LANES - 1, LANES, 3 * LANES + 5, 1000] {
        let q: Vec<PhakAngles<f64>> = (0..frames)
            .map(|_| PhakAngles::from_array(common::random_angles(&mut rng)))
            .collect();
        let phak = Phak::new(&Anthropometry::gait2392()).unwrap();
        let mut out = vec![BilateralPose::default(); frames + 3];
        assert_eq!(phak.fk_batch(&q, &mut out), frames);
        for (qi, oi) in q.iter().zip(&out) {
            assert!(worst(&phak.fk(qi).points(), &oi.points()) < 1e-14);
        }
        assert_eq!(
            out[frames],
            BilateralPose::default(),
            "nothing written past the input"
        );
        let q32: Vec<PhakAngles<f32>> = q
            .iter()
            .map(|a| PhakAngles::from_array(a.to_array().map(|v| v as f32)))
            .collect();
        let phak32 = Phak::new(&Anthropometry::<f32>::gait2392()).unwrap();
        let mut out32 = vec![BilateralPose::default(); frames];
        phak32.fk_batch(&q32, &mut out32);
        for (qi, oi) in q32.iter().zip(&out32) {
            assert!(worst(&phak32.fk(qi).points(), &oi.points()) < 1e-6);
        }
    }
}

#[test]
fn hak_and_gait2392_batches_equal_single_frames() {
    let mut rng = common::rng(31);
    let frames = 2 * LANES + 3;
    let hak = Hak::new(&Limb::<f64>::gait2392()).unwrap();
    let q: Vec<HakAngles<f64>> = (0..frames)
        .map(|_| HakAngles::from_array(common::random_angles(&mut rng)))
        .collect();
    let mut out = vec![LegPose::default(); frames];
    assert_eq!(
        hak.fk_batch(&q, &mut out[..frames - 1]),
        frames - 1,
        "stops at the shorter slice"
    );
    for (qi, oi) in q.iter().zip(&out[..frames - 1]) {
        assert!(worst(&hak.fk(qi).points(), &oi.points()) < 1e-14);
    }
    let g = Gait2392::<f64>::new(&Gait2392Geometry::generic()).unwrap();
    // Knee angles across and beyond the spline knots (extrapolation included).
    let q: Vec<[f64; 17]> = (0..frames)
        .map(|_| common::random_angles::<17>(&mut rng).map(|v| v * 1.2))
        .collect();
    let mut out = vec![
        Gait2392Pose {
            points: [Vec3::zero(); 12]
        };
        frames
    ];
    g.fk_batch(&q, &mut out);
    for (qi, oi) in q.iter().zip(&out) {
        assert!(worst(&g.fk(qi).points, &oi.points) < 1e-14);
    }
}
