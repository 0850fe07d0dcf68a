//! The kernel's differential kinematics of an imported Rajagopal 2015 chain (walker knees: three
//! rotations and two translations driven by splines of one coordinate; oriented frames), against
//! OpenSim 4.6 on `scripts/opensim_derivatives.py`'s analytic motion
//! (`crates/qgait-kernel/tests/data/derivatives/rajagopal2015_reference.csv`; the model from
//! ../shared/data/opensim, skipped when absent): with the exact speeds, the joint centres' and
//! toe tips' velocities and the bodies' angular velocities within 1e-9; accelerations (OpenSim's
//! velocities differenced at 1e-5 s, error about 1e-9) within 1e-7; its `IMU` components'
//! gyroscope within 1e-9 rad/s and accelerometer within 1e-7 m/s²; and the same in the packed
//! table a hub holds, in `f32`, within a stated bound.

mod common;

use std::collections::HashMap;

use common::shared_dir;
use qgait_kernel::differential::{imu_signals, ImuMount, PointMotion};
use qgait_kernel::models::gait2392::{COORDINATES, POINTS};
use qgait_kernel::Vec3;
use qgait_model::choice::Model;

struct Reference {
    columns: HashMap<String, usize>,
    rows: Vec<Vec<f64>>,
}

impl Reference {
    fn load(name: &str) -> Self {
        let path = format!(
            "{}/../qgait-kernel/tests/data/derivatives/{name}_reference.csv",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let mut lines = text.lines();
        let columns = lines
            .next()
            .unwrap()
            .split(',')
            .enumerate()
            .map(|(i, c)| (c.to_string(), i))
            .collect();
        let rows = lines
            .filter(|l| !l.is_empty())
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        Self { columns, rows }
    }

    fn get(&self, row: usize, column: &str) -> f64 {
        let i = self
            .columns
            .get(column)
            .unwrap_or_else(|| panic!("no {column}"));
        self.rows[row][*i]
    }

    fn vec(&self, row: usize, prefix: &str) -> Vec3<f64> {
        Vec3::new(
            self.get(row, &format!("{prefix}x")),
            self.get(row, &format!("{prefix}y")),
            self.get(row, &format!("{prefix}z")),
        )
    }

    fn coordinates(&self, row: usize) -> [[f64; 17]; 3] {
        ["q", "qd", "qdd"]
            .map(|k| std::array::from_fn(|i| self.get(row, &format!("{k}_{}", COORDINATES[i]))))
    }

    fn pelvis(&self, row: usize) -> PointMotion<f64> {
        let [position, velocity, acceleration] =
            ["q", "qd", "qdd"].map(|k| self.vec(row, &format!("{k}_pelvis_t")));
        PointMotion {
            position,
            velocity,
            acceleration,
        }
    }
}

const BODIES: [&str; 11] = [
    "pelvis", "femur_r", "tibia_r", "talus_r", "calcn_r", "toes_r", "femur_l", "tibia_l",
    "talus_l", "calcn_l", "toes_l",
];

/// The script's IMUs: name, body (index in BODIES), translation, body-fixed X-Y-Z orientation.
const IMUS: [(&str, usize, [f64; 3], [f64; 3]); 4] = [
    ("pelvis_imu", 0, [-0.14, 0.03, 0.0], [0.51, -0.70, 0.40]),
    ("femur_r_imu", 1, [0.02, -0.20, 0.06], [0.10, 0.30, -0.20]),
    ("tibia_l_imu", 7, [0.03, -0.15, -0.05], [-0.30, 0.20, 0.60]),
    ("calcn_r_imu", 4, [0.10, 0.05, 0.0], [1.20, -0.40, 0.30]),
];

#[test]
fn rajagopal_velocities_accelerations_and_imu_signals_are_opensims() {
    let Some(shared) = shared_dir() else { return };
    let path = shared.join("data/opensim/Rajagopal2015_opensense.osim");
    let (model, _) = Model::load(path.to_str().unwrap(), None).unwrap();
    let Model::Chain { chain, .. } = model else {
        panic!("Rajagopal 2015 imports as a chain");
    };
    let chain = chain.chain("test").unwrap();
    // The hub's model slot's sizes (as tests/opensim_models.rs packs it), in f32.
    let device = chain.packed::<f32, 8, 0, 24, 384>().unwrap();
    let reference = Reference::load("rajagopal2015");
    // [velocity, acceleration, angular velocity, angular acceleration, gyroscope,
    // accelerometer], f64 then the device's f32.
    let mut worst = [0.0f64; 6];
    let mut worst32 = [0.0f64; 6];
    let mut knee_speed = 0.0f64;
    for row in 0..reference.rows.len() {
        let [q, qd, qdd] = reference.coordinates(row);
        knee_speed = knee_speed.max(qd[6].abs());
        let pelvis = reference.pelvis(row);
        let c = |a: [f64; 17]| a.map(|v| v as f32);
        let points = chain.forward_motion(&q, &qd, &qdd);
        let points32 = device.forward_motion(&c(q), &c(qd), &c(qdd));
        let frames = chain.motions(&q, &qd, &qdd);
        let frames32 = device.motions(&c(q), &c(qd), &c(qdd));
        for ((p, p32), name) in points.iter().zip(&points32).zip(POINTS) {
            let v = reference.vec(row, &format!("{name}_v"));
            let a = reference.vec(row, &format!("{name}_a"));
            let p = p.moved_by(&pelvis);
            worst[0] = worst[0].max(p.velocity.max_abs_diff(v));
            worst[1] = worst[1].max(p.acceleration.max_abs_diff(a));
            worst32[0] = worst32[0].max((p32.velocity.cast() + pelvis.velocity).max_abs_diff(v));
            worst32[1] =
                worst32[1].max((p32.acceleration.cast() + pelvis.acceleration).max_abs_diff(a));
        }
        for ((f, f32_), name) in frames.iter().zip(&frames32).zip(BODIES) {
            let w = reference.vec(row, &format!("{name}_w"));
            let dw = reference.vec(row, &format!("{name}_dw"));
            worst[2] = worst[2].max(f.angular_velocity.max_abs_diff(w));
            worst[3] = worst[3].max(f.angular_acceleration.max_abs_diff(dw));
            worst32[2] = worst32[2].max(f32_.angular_velocity.cast().max_abs_diff(w));
            worst32[3] = worst32[3].max(f32_.angular_acceleration.cast().max_abs_diff(dw));
        }
        for (name, body, t, o) in IMUS {
            let gyro = reference.vec(row, &format!("{name}_gyro_"));
            let acc = reference.vec(row, &format!("{name}_acc_"));
            let s = imu_signals(
                &frames[body].moved_by(&pelvis),
                &ImuMount::from_xyz(Vec3::from_f64(t), o),
            );
            worst[4] = worst[4].max(s.gyroscope.max_abs_diff(gyro));
            worst[5] = worst[5].max(s.accelerometer.max_abs_diff(acc));
            let pelvis32 = PointMotion {
                position: pelvis.position.cast(),
                velocity: pelvis.velocity.cast(),
                acceleration: pelvis.acceleration.cast(),
            };
            let s = imu_signals(
                &frames32[body].moved_by(&pelvis32),
                &ImuMount::from_xyz(Vec3::<f32>::from_f64(t), o.map(|v| v as f32)),
            );
            worst32[4] = worst32[4].max(s.gyroscope.cast().max_abs_diff(gyro));
            worst32[5] = worst32[5].max(s.accelerometer.cast().max_abs_diff(acc));
        }
    }
    let show = |w: &[f64; 6]| {
        format!(
            "velocity {:.1e} m/s, acceleration {:.1e} m/s^2, angular velocity {:.1e} rad/s, \
             angular acceleration {:.1e} rad/s^2, gyroscope {:.1e} rad/s, accelerometer {:.1e} m/s^2",
            w[0], w[1], w[2], w[3], w[4], w[5]
        )
    };
    println!("Rajagopal 2015 against OpenSim 4.6, f64: {}", show(&worst));
    println!("the hub's packed table in f32: {}", show(&worst32));
    // The motion moves the walker knee (its spline-driven rotations and translations).
    assert!(knee_speed > 1.0, "{knee_speed}");
    for (i, bound) in [1e-9, 1e-7, 1e-9, 1e-7, 1e-9, 1e-7].into_iter().enumerate() {
        assert!(worst[i] < bound, "{}", show(&worst));
    }
    for (i, bound) in [2e-5, 5e-4, 2e-5, 5e-4, 2e-5, 5e-4].into_iter().enumerate() {
        assert!(worst32[i] < bound, "{}", show(&worst32));
    }
}
