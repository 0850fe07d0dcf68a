//! Quaternion algebra: norm kept, q conj(q) = 1, rotation keeps lengths, composition equals
//! the matrix product, and the efficient rotation equals q v q*.

mod common;

use qgait_kernel::{Quat, Vec3};
use rand::Rng;

fn random_unit(rng: &mut impl Rng) -> Quat<f64> {
    let axis = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0f64),
    )
    .normalized();
    Quat::from_axis_angle(axis, rng.random_range(-10.0..10.0))
}

fn random_vec(rng: &mut impl Rng) -> Vec3<f64> {
    Vec3::new(
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
        rng.random_range(-2.0..2.0),
    )
}

fn mat_mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

#[test]
fn hamilton_units() {
    let i = Quat::new(0.0, 1.0, 0.0, 0.0);
    let j = Quat::new(0.0, 0.0, 1.0, 0.0);
    let k = Quat::new(0.0, 0.0, 0.0, 1.0);
    assert_eq!(i * j, k);
    assert_eq!(j * k, i);
    assert_eq!(k * i, j);
    assert_eq!(i * i, Quat::new(-1.0, 0.0, 0.0, 0.0));
    assert_eq!(i * j * k, Quat::new(-1.0, 0.0, 0.0, 0.0));
}

#[test]
fn identities_hold_on_random_quaternions() {
    let mut rng = common::rng(10);
    for _ in 0..10_000 {
        let (p, q, v) = (
            random_unit(&mut rng),
            random_unit(&mut rng),
            random_vec(&mut rng),
        );
        // Unit norm from axis-angle, kept by products.
        assert!((q.norm() - 1.0).abs() < 1e-15);
        assert!(((p * q).norm() - 1.0).abs() < 1e-14);
        // q conj(q) = 1.
        let one = q * q.conj();
        assert!((one.w - 1.0).abs() < 1e-15 && one.vector().norm() < 1e-15);
        // Rotation keeps lengths, and the efficient form equals q v q*.
        let r = q.rotate(v);
        assert!((r.norm() - v.norm()).abs() < 1e-14);
        let sandwich = (q * Quat::pure(v) * q.conj()).vector();
        assert!(r.max_abs_diff(sandwich) < 1e-14);
        // Composition equals the matrix product, and rotating by p*q is rotating by q then p.
        let composed = (p * q).to_rotation_matrix();
        let product = mat_mul(p.to_rotation_matrix(), q.to_rotation_matrix());
        for (a, b) in composed.iter().flatten().zip(product.iter().flatten()) {
            assert!((a - b).abs() < 1e-14);
        }
        assert!((p * q).rotate(v).max_abs_diff(p.rotate(q.rotate(v))) < 1e-14);
        // q and -q are the same rotation; normalising a scaled quaternion recovers it.
        let neg = Quat::new(-q.w, -q.x, -q.y, -q.z);
        assert!(neg.rotate(v).max_abs_diff(r) < 1e-14);
        let scaled = Quat::new(3.0 * q.w, 3.0 * q.x, 3.0 * q.y, 3.0 * q.z).normalized();
        assert!((scaled.w - q.w).abs() < 1e-15 && scaled.vector().max_abs_diff(q.vector()) < 1e-15);
    }
}

#[test]
fn axis_angle_is_right_handed() {
    let q = Quat::from_axis_angle(Vec3::unit_z(), core::f64::consts::FRAC_PI_2);
    assert!(q.rotate(Vec3::unit_x()).max_abs_diff(Vec3::unit_y()) < 1e-15);
    let qf = Quat::from_axis_angle(Vec3::<f32>::unit_z(), core::f32::consts::FRAC_PI_2);
    assert!(qf.rotate(Vec3::unit_x()).max_abs_diff(Vec3::unit_y()) < 1e-6);
}
