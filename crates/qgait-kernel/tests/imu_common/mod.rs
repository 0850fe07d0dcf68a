//! The synthetic IMU recording the IMU tests share.
//!
//! **Generator.** Known gait2392 coordinates (a walk with turns, [`truth`]) go through the
//! kernel's own forward kinematics ([`Chain::frames`]): each sensor's segment orientation is its
//! chain body's frame (the torso: the pelvis frame turned by the lumbar angles about z, x, y).
//! Each sensor sits on its segment at a mounting `M` (a seeded random rotation of up to 30
//! degrees about a random axis; the base IMU, the torso's, with its z axis forward and a
//! random roll about it, as the heading correction assumes), and reports its orientation in the
//! sensors' world frame, whose z is up: `reading = S^-1 B M`, with `S` OpenSense's default
//! sensor-to-OpenSim rotation (space-fixed X-Y-Z (-pi/2, 0, 0)). The calibration pose is the
//! model's default pose facing an arbitrary heading (`pelvis_rotation` = [`HEADING0`], all
//! else zero). Optional disturbances ([`Disturbance`]): rotation noise on every reading
//! (random rotation vectors, given rms angle), on the calibration pose too, and a slow heading
//! drift per sensor (its world turning about the vertical at a constant rate).
#![allow(dead_code)]

use qgait_kernel::imu::{math, Orientations, Segment, SENSORS};
use qgait_kernel::models::fixtures;
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat, Vec3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

pub const DEG: f64 = core::f64::consts::PI / 180.0;
/// Frames per second.
pub const RATE: f64 = 100.0;
/// The subject's heading at calibration (pelvis_rotation, radians).
pub const HEADING0: f64 = fixtures::IMU_WALK_HEADING0;

/// The true coordinates at time `t` (s): the kernel's synthetic walk with turns
/// ([`fixtures::imu_walk`]): the 17 chain coordinates and the 3 lumbar angles.
pub use fixtures::imu_walk as truth;

/// The model the data are generated with (and solved with).
pub fn model() -> Gait2392<f64> {
    Gait2392::new(&Gait2392Geometry::generic()).unwrap()
}

/// Every segment's orientation (segment to OpenSim's ground) for these coordinates.
pub fn segments(model: &Gait2392<f64>, q: &[f64; 17], lumbar: &[f64; 3]) -> [Quat<f64>; SENSORS] {
    let frames = model.chain().frames(q);
    let body = [0, 1, 2, 4, 6, 7, 9];
    let (x, y, z) = (Vec3::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    let torso = frames[0].rotation
        * Quat::from_axis_angle(z, lumbar[0])
        * Quat::from_axis_angle(x, lumbar[1])
        * Quat::from_axis_angle(y, lumbar[2]);
    core::array::from_fn(|i| {
        if i < 7 {
            frames[body[i]].rotation
        } else {
            torso
        }
    })
}

/// A seeded random rotation of up to `max` radians about a uniformly random axis.
pub fn random_rotation(rng: &mut SmallRng, max: f64) -> Quat<f64> {
    let z: f64 = rng.random_range(-1.0..1.0);
    let phi: f64 = rng.random_range(0.0..core::f64::consts::TAU);
    let r = (1.0 - z * z).sqrt();
    let axis = Vec3::new(r * phi.cos(), r * phi.sin(), z);
    Quat::from_axis_angle(axis, rng.random_range(-max..=max))
}

/// A rotation whose rotation vector has independent normal components of rms
/// `rms / sqrt(3)` each (so an rms angle of `rms`).
pub fn noise(rng: &mut SmallRng, rms: f64) -> Quat<f64> {
    let sigma = rms / 3f64.sqrt();
    let mut normal = || {
        // Box-Muller.
        let u: f64 = rng.random_range(f64::MIN_POSITIVE..1.0);
        let v: f64 = rng.random_range(0.0..core::f64::consts::TAU);
        (-2.0 * u.ln()).sqrt() * v.cos() * sigma
    };
    let r = Vec3::new(normal(), normal(), normal());
    let angle = r.norm();
    if angle == 0.0 {
        return Quat::identity();
    }
    Quat::from_axis_angle(r * (1.0 / angle), angle)
}

/// Sensor mountings (sensor frame in segment frame): random up to 30 degrees, the torso's
/// with z forward and a random roll of up to 30 degrees about it.
pub fn mountings(seed: u64) -> [Quat<f64>; SENSORS] {
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut m: [Quat<f64>; SENSORS] =
        core::array::from_fn(|_| random_rotation(&mut rng, 30.0 * DEG));
    let roll = rng.random_range(-30.0 * DEG..=30.0 * DEG);
    m[Segment::Torso as usize] = Quat::from_axis_angle(Vec3::unit_x(), roll)
        * Quat::from_axis_angle(Vec3::unit_y(), 90.0 * DEG);
    m
}

/// OpenSense's default sensor-to-OpenSim rotation.
pub fn sensor_to_opensim() -> Quat<f64> {
    math::space_fixed_xyz([-90.0 * DEG, 0.0, 0.0])
}

/// What disturbs the readings.
#[derive(Clone, Copy, Debug, Default)]
pub struct Disturbance {
    /// Rms rotation noise of every reading, calibration pose included (radians).
    pub noise: f64,
    /// Largest heading drift rate of a sensor's world (radians per second; each sensor's rate
    /// is seeded uniform in +-this).
    pub drift: f64,
    /// Seed of the noise and drift rates.
    pub seed: u64,
}

/// A synthetic recording: the calibration pose's readings, then per frame the readings and
/// the true coordinates.
pub struct Recording {
    pub calibration: Orientations<f64>,
    pub frames: Vec<(Orientations<f64>, [f64; 17], [f64; 3])>,
}

/// `seconds` of [`truth`] read by sensors mounted at `mount` (calibration pose read with
/// `calibration_mount`, normally the same), disturbed by `d`.
pub fn recording(
    seconds: f64,
    mount: &[Quat<f64>; SENSORS],
    calibration_mount: &[Quat<f64>; SENSORS],
    d: Disturbance,
) -> Recording {
    let model = model();
    let s_inv = sensor_to_opensim().conj();
    let mut rng = SmallRng::seed_from_u64(d.seed);
    let rates: [f64; SENSORS] = core::array::from_fn(|_| {
        if d.drift > 0.0 {
            rng.random_range(-d.drift..=d.drift)
        } else {
            0.0
        }
    });
    let mut read = |b: &[Quat<f64>; SENSORS], m: &[Quat<f64>; SENSORS], t: f64| {
        let mut o = Orientations::EMPTY;
        for (i, seg) in Segment::ALL.into_iter().enumerate() {
            let drift = Quat::from_axis_angle(Vec3::unit_y(), rates[i] * t);
            let n = if d.noise > 0.0 {
                noise(&mut rng, d.noise)
            } else {
                Quat::identity()
            };
            o.set(seg, Some(s_inv * drift * b[i] * m[i] * n));
        }
        o
    };
    let mut q0 = [0.0; 17];
    q0[2] = HEADING0;
    let calibration = read(&segments(&model, &q0, &[0.0; 3]), calibration_mount, 0.0);
    let n = (seconds * RATE) as usize;
    let frames = (0..n)
        .map(|k| {
            let t = k as f64 / RATE;
            let (q, lumbar) = truth(t);
            (read(&segments(&model, &q, &lumbar), mount, t), q, lumbar)
        })
        .collect();
    Recording {
        calibration,
        frames,
    }
}

/// The determined coordinates: the 17 chain coordinates but the MTPs, then the lumbar three.
pub fn determined() -> Vec<(usize, &'static str)> {
    let mut v: Vec<(usize, &'static str)> = qgait_kernel::models::gait2392::COORDINATES
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, n)| !n.starts_with("mtp"))
        .collect();
    v.extend(
        qgait_kernel::imu::LUMBAR
            .iter()
            .enumerate()
            .map(|(i, n)| (17 + i, *n)),
    );
    v
}
