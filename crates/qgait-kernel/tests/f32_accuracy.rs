//! The f32 path (the device's) stays within 10 µm of the f64 path for every point of every
//! frame of the shared motions and of seeded random angles in [-pi, pi].

mod common;

use qgait_kernel::{Anthropometry, Hak, HakAngles, Limb, Phak, PhakAngles};

const BOUND_M: f64 = 10e-6;

fn phak_error(q: [f64; 8]) -> f64 {
    let phak64 = Phak::new(&Anthropometry::<f64>::gait2392()).unwrap();
    let phak32 = Phak::new(&Anthropometry::<f32>::gait2392()).unwrap();
    let p64 = phak64.fk(&PhakAngles::from_array(q));
    let p32 = phak32.fk(&PhakAngles::from_array(q.map(|v| v as f32)));
    p64.points()
        .iter()
        .zip(p32.points())
        .map(|(a, b)| a.max_abs_diff(b.cast()))
        .fold(0.0, f64::max)
}

#[test]
fn random_angles_phak_and_hak() {
    let mut rng = common::rng(20);
    let mut worst = 0.0f64;
    for _ in 0..100_000 {
        worst = worst.max(phak_error(common::random_angles(&mut rng)));
    }
    let hak64 = Hak::new(&Limb::<f64>::gait2392()).unwrap();
    let hak32 = Hak::new(&Limb::<f32>::gait2392()).unwrap();
    for _ in 0..100_000 {
        let q: [f64; 3] = common::random_angles(&mut rng);
        let a = hak64.fk(&HakAngles::from_array(q));
        let b = hak32.fk(&HakAngles::from_array(q.map(|v| v as f32)));
        for (p, r) in a.points().iter().zip(b.points()) {
            worst = worst.max(p.max_abs_diff(r.cast()));
        }
    }
    eprintln!("f32 vs f64, random angles: max error {:.3} µm", worst * 1e6);
    assert!(worst < BOUND_M, "{worst:e}");
}

#[test]
fn shared_motions_phak() {
    let Some(motions) = common::shared_motions() else {
        return;
    };
    assert!(!motions.is_empty());
    for (name, header, rows) in motions {
        let mut worst = 0.0f64;
        for row in &rows {
            let q = PhakAngles::<f64>::NAMES.map(|c| common::column_rad(&header, row, c));
            worst = worst.max(phak_error(q));
        }
        eprintln!(
            "f32 vs f64, {name} ({} rows): max error {:.3} µm",
            rows.len(),
            worst * 1e6
        );
        assert!(worst < BOUND_M, "{name}: {worst:e}");
    }
}
