//! The batch (SIMD) path equals the single-frame path for every model, in both precisions, for
//! batch lengths that are and are not multiples of the lane count.

mod common;

use qgait_kernel::lanes::{Simd, LANES};
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

/// Every batch level this CPU runs (portable, and AVX2 / AVX-512 where present: the kernel is
/// built with `std` for its tests) gives the single-frame poses, for lengths around every lane
/// count, every model, both precisions.
#[test]
fn every_simd_level_equals_single_frames() {
    let levels: Vec<Simd> = Simd::ALL.into_iter().filter(|l| l.is_supported()).collect();
    println!(
        "levels run here: {levels:?}; fk_batch uses {:?}",
        Simd::detect()
    );
    assert!(levels.contains(&Simd::Portable) && levels.contains(&Simd::detect()));
    let mut rng = common::rng(32);
    let lengths = [
        0,
        1,
        2,
        3,
        4,
        5,
        7,
        8,
        9,
        15,
        16,
        17,
        31,
        33,
        3 * 16 + 5,
        1000,
    ];
    let phak = Phak::new(&Anthropometry::gait2392()).unwrap();
    let phak32 = Phak::new(&Anthropometry::<f32>::gait2392()).unwrap();
    let hak = Hak::new(&Limb::<f64>::gait2392()).unwrap();
    let g = Gait2392::<f64>::new(&Gait2392Geometry::generic()).unwrap();
    let g32 = Gait2392::<f32>::new(&Gait2392Geometry::generic()).unwrap();
    for level in levels {
        for frames in lengths {
            let q8: Vec<[f64; 8]> = (0..frames)
                .map(|_| common::random_angles(&mut rng))
                .collect();
            let q3: Vec<[f64; 3]> = (0..frames)
                .map(|_| common::random_angles(&mut rng))
                .collect();
            let q17: Vec<[f64; 17]> = (0..frames)
                .map(|_| common::random_angles::<17>(&mut rng).map(|v| v * 1.2))
                .collect();
            // Every frame written exactly once, in order of its index.
            let check = |name: &str, worst: f64, tol: f64, seen: &[usize]| {
                assert!(
                    worst < tol,
                    "{name} {level:?} {frames} frames: off by {worst:e}"
                );
                assert_eq!(seen, (0..frames).collect::<Vec<_>>(), "{name} {level:?}");
            };
            let mut seen = Vec::new();
            let mut w = 0.0f64;
            phak.chain().forward_batch_on(
                level,
                frames,
                |i| q8[i],
                |i, p| {
                    seen.push(i);
                    w = w.max(worst(&phak.fk(&PhakAngles::from_array(q8[i])).points(), &p));
                },
            );
            check("phak f64", w, 1e-14, &seen);
            let (mut seen, mut w) = (Vec::new(), 0.0f64);
            let q8_32: Vec<[f32; 8]> = q8.iter().map(|a| a.map(|v| v as f32)).collect();
            phak32.chain().forward_batch_on(
                level,
                frames,
                |i| q8_32[i],
                |i, p| {
                    seen.push(i);
                    let single = phak32.fk(&PhakAngles::from_array(q8_32[i])).points();
                    w = w.max(worst(&single, &p));
                },
            );
            check("phak f32", w, 1e-6, &seen);
            let (mut seen, mut w) = (Vec::new(), 0.0f64);
            hak.chain().forward_batch_on(
                level,
                frames,
                |i| q3[i],
                |i, p| {
                    seen.push(i);
                    w = w.max(worst(&hak.fk(&HakAngles::from_array(q3[i])).points(), &p));
                },
            );
            check("hak f64", w, 1e-14, &seen);
            let (mut seen, mut w) = (Vec::new(), 0.0f64);
            g.chain().forward_batch_on(
                level,
                frames,
                |i| q17[i],
                |i, p| {
                    seen.push(i);
                    w = w.max(worst(&g.fk(&q17[i]).points, &p));
                },
            );
            check("gait2392 f64", w, 1e-14, &seen);
            let (mut seen, mut w) = (Vec::new(), 0.0f64);
            let q17_32: Vec<[f32; 17]> = q17.iter().map(|a| a.map(|v| v as f32)).collect();
            g32.chain().forward_batch_on(
                level,
                frames,
                |i| q17_32[i],
                |i, p| {
                    seen.push(i);
                    w = w.max(worst(&g32.fk(&q17_32[i]).points, &p));
                },
            );
            check("gait2392 f32", w, 2e-6, &seen);
        }
    }
}

/// The fused-multiply-add form of the half-angle polynomials (the AVX levels) is as accurate
/// as the unfused one.
#[test]
fn fused_half_angle_matches_libm() {
    use qgait_kernel::lanes::LaneScalar;
    let (mut e64, mut e32) = (0.0f64, 0.0f64);
    let n = 100_000;
    for i in 0..=n {
        let x =
            -8.0 * core::f64::consts::PI + 16.0 * core::f64::consts::PI * (i as f64) / (n as f64);
        let (es, ec) = libm::sincos(0.5 * x);
        let (s, c) = x.half_angle_sin_cos_fused();
        let sign = if c * ec + s * es < 0.0 { -1.0 } else { 1.0 };
        e64 = e64.max((sign * s - es).abs()).max((sign * c - ec).abs());
        let x32 = x as f32;
        let (es, ec) = libm::sincos(0.5 * x32 as f64);
        let (s, c) = x32.half_angle_sin_cos_fused();
        let (s, c) = (s as f64, c as f64);
        let sign = if c * ec + s * es < 0.0 { -1.0 } else { 1.0 };
        e32 = e32.max((sign * s - es).abs()).max((sign * c - ec).abs());
    }
    assert!(e64 < 1e-15 && e32 < 3e-7, "f64 {e64:e}, f32 {e32:e}");
}
