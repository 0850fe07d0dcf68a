//! The quaternion path, the closed form, Denavit-Hartenberg and homogeneous matrices agree to
//! 1e-12 m in f64 on 10,000 seeded random angle sets (and random segment lengths).

mod common;

use qgait_kernel::reference::{
    chain_by_matrices, hak_denavit_hartenberg, hak_geometric, phak_homogeneous,
};
use qgait_kernel::{Anthropometry, Hak, HakAngles, LegPose, Limb, Phak, PhakAngles};
use rand::Rng;

const SETS: usize = 10_000;
const TOL: f64 = 1e-12;

fn max_diff(a: &LegPose<f64>, b: &LegPose<f64>) -> f64 {
    a.points()
        .iter()
        .zip(b.points())
        .map(|(p, q)| p.max_abs_diff(q))
        .fold(0.0, f64::max)
}

fn random_limb(rng: &mut impl Rng) -> Limb<f64> {
    Limb::from_array(core::array::from_fn(|_| rng.random_range(0.05..0.6)))
}

#[test]
fn hak_three_methods_agree() {
    let mut rng = common::rng(1);
    let mut worst = 0.0f64;
    for i in 0..SETS {
        let limb = if i % 2 == 0 {
            Limb::gait2392()
        } else {
            random_limb(&mut rng)
        };
        let q = HakAngles::from_array(common::random_angles(&mut rng));
        let hak = Hak::new(&limb).unwrap();
        let quat = hak.fk(&q);
        let geo = hak_geometric(&limb, &q);
        let dh = hak_denavit_hartenberg(&limb, &q);
        let mat = LegPose::from_points(chain_by_matrices(hak.chain(), &q.to_array()));
        for other in [&geo, &dh, &mat] {
            worst = worst.max(max_diff(&quat, other));
        }
    }
    eprintln!("HAK: worst disagreement over {SETS} sets: {worst:e} m");
    assert!(worst <= TOL, "{worst:e}");
}

#[test]
fn phak_quaternions_agree_with_homogeneous_matrices() {
    let mut rng = common::rng(2);
    let mut worst = 0.0f64;
    for i in 0..SETS {
        let a = if i % 2 == 0 {
            Anthropometry::gait2392()
        } else {
            Anthropometry {
                right: random_limb(&mut rng),
                left: random_limb(&mut rng),
            }
        };
        let q = PhakAngles::from_array(common::random_angles(&mut rng));
        let phak = Phak::new(&a).unwrap();
        let quat = phak.fk(&q);
        let hand = phak_homogeneous(&a, &q);
        let table = chain_by_matrices(phak.chain(), &q.to_array());
        for (k, p) in quat.points().iter().enumerate() {
            worst = worst
                .max(p.max_abs_diff(hand.points()[k]))
                .max(p.max_abs_diff(table[k]));
        }
    }
    eprintln!("PHAK: worst disagreement over {SETS} sets: {worst:e} m");
    assert!(worst <= TOL, "{worst:e}");
}
