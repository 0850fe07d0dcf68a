//! Models for the tests of the crates built on the kernel (cargo feature `fixtures`): one
//! definition each, shared by the kernel's, the protocol's, the hub's and the firmware's tests.

use crate::models::custom::{
    Argument, BodyPoint, Coupler, CustomJoint, Driven, Function, Functions, Offset,
};
use crate::models::LowerLimb;
use crate::{Spline, Vec3};

const DEG: f64 = core::f64::consts::PI / 180.0;

/// The subject's heading (`pelvis_rotation`, radians) at the start of [`imu_walk`]: where the
/// synthetic IMU recordings put their calibration pose.
pub const IMU_WALK_HEADING0: f64 = -115.0 * DEG;

/// The true coordinates of the synthetic IMU recordings at time `t` (s): a gait-like cycle of
/// 1.1 s on every coordinate eight IMUs determine, the legs half a cycle apart,
/// `pelvis_rotation` turning from [`IMU_WALK_HEADING0`] by 50 degrees a second (one and a half
/// turns in 10 s) plus a sway; MTP zero (no sensor). Returns the 17 gait2392 chain coordinates
/// and the 3 lumbar angles. The kernel's IMU tests and the hub's checks generate their sensor
/// readings from these through the kernel's own forward kinematics.
pub fn imu_walk(t: f64) -> ([f64; 17], [f64; 3]) {
    let w = core::f64::consts::TAU / 1.1;
    let s = |amp: f64, phase: f64| amp * DEG * libm::sin(w * t + phase);
    let mut q = [0.0; 17];
    q[0] = s(6.0, 0.3) + 3.0 * DEG;
    q[1] = s(5.0, 1.1);
    q[2] = IMU_WALK_HEADING0 + 50.0 * DEG * t + s(6.0, 0.7);
    for (c, phase) in [(3, 0.0), (10, core::f64::consts::PI)] {
        q[c] = s(30.0, phase) + 10.0 * DEG;
        q[c + 1] = s(8.0, phase + 0.4) - 2.0 * DEG;
        q[c + 2] = s(12.0, phase + 1.3) + 4.0 * DEG;
        q[c + 3] = s(30.0, phase + 0.9) - 32.0 * DEG;
        q[c + 4] = s(15.0, phase + 2.0);
        q[c + 5] = s(10.0, phase + 0.5) + 3.0 * DEG;
    }
    let lumbar = [s(5.0, 0.2) - 4.0 * DEG, s(3.0, 1.5), s(8.0, 2.5)];
    (q, lumbar)
}

/// A Rajagopal-shaped lower-limb chain: oriented offset frames, a walker knee whose second
/// rotation is a `SimmSpline` and whose translation a piecewise linear function of its angle,
/// the MTP coupled to the ankle (a `CoordinateCouplerConstraint`).
pub fn walker_chain() -> LowerLimb<f64> {
    let linear = |i: usize| {
        (
            Function::Linear {
                slope: 1.0,
                intercept: 0.0,
            },
            Argument::Coordinate(i),
        )
    };
    let axis = |v: [f64; 3], (function, argument): (Function<f64>, Argument)| Driven {
        axis: Vec3::from_f64(v),
        function,
        argument,
    };
    let x = [0.0, 0.3, 0.7, 1.1, 1.6, 2.1];
    let (Ok(s0), Ok(s1)) = (
        Spline::from_knots(&x, &[0.0, 0.02, 0.03, 0.033, 0.02, 0.0]),
        Spline::piecewise_linear(&x, &[0.0, 0.001, 0.0013, 0.0014, 0.0015, 0.0016]),
    ) else {
        unreachable!("increasing knots")
    };
    let couplers = [Coupler {
        independent: 7, // ankle_angle_r
        function: Function::Linear {
            slope: 0.5,
            intercept: 0.01,
        },
    }];
    let mut joints = [CustomJoint::WELD; 11];
    joints[0].rotations = [
        axis([0., 0., 1.], linear(0)),
        axis([1., 0., 0.], linear(1)),
        axis([0., 1., 0.], linear(2)),
    ];
    let mut points = [BodyPoint {
        body: 0,
        offset: Vec3::zero(),
    }; 12];
    for side in 0..2 {
        let (b, c) = (1 + 5 * side, 3 + 7 * side);
        let z = if side == 0 { 1.0 } else { -1.0 };
        joints[b].parent = Some(0);
        joints[b].in_parent = Offset::from_xyz(Vec3::new(-0.06, -0.08, 0.08 * z), [0.0; 3]);
        joints[b].rotations = [
            axis([0., 0., 1.], linear(c)),
            axis([1., 0., 0.], linear(c + 1)),
            axis([0., 1., 0.], linear(c + 2)),
        ];
        let knee = [-1.64, 1.45, 1.57];
        joints[b + 1].parent = Some(b);
        joints[b + 1].in_parent = Offset::from_xyz(Vec3::new(-0.008, -0.405, -0.0027), knee);
        joints[b + 1].in_child = Offset::from_xyz(Vec3::new(-0.008, -0.004, -0.0015), knee);
        joints[b + 1].rotations[0] = axis([1., 0., 0.], linear(c + 3));
        joints[b + 1].rotations[1] = axis(
            [0., 0., 1.],
            (Function::Spline(0), Argument::Coordinate(c + 3)),
        );
        joints[b + 1].translations[0] = axis(
            [0., 1., 0.],
            (Function::Spline(1), Argument::Coordinate(c + 3)),
        );
        let mtp = (
            Function::Linear {
                slope: 1.0,
                intercept: 0.0,
            },
            Argument::Coupled(0),
        );
        for (k, (t, o, arg)) in [
            ([-0.01, -0.43, 0.0], [0.17, -0.1, 0.02], linear(c + 4)),
            ([-0.044, -0.042, 0.008], [-1.77, 0.9, 1.8], linear(c + 5)),
            ([0.16, -0.002, 0.001], [-3.1, 0.62, 0.0], mtp),
        ]
        .into_iter()
        .enumerate()
        {
            let j = &mut joints[b + 2 + k];
            j.parent = Some(b + 1 + k);
            j.in_parent = Offset::from_xyz(Vec3::from_f64(t), o);
            j.in_child = Offset::from_xyz(Vec3::zero(), o);
            j.rotations[0] = axis([0., 0., 1.], arg);
        }
        for k in 0..5 {
            points[6 * side + k] = BodyPoint {
                body: b + k,
                offset: joints[b + k].in_child.translation,
            };
        }
        points[6 * side + 5] = BodyPoint {
            body: b + 4,
            offset: Vec3::new(0.058, 0.007, 0.001 * z),
        };
    }
    match LowerLimb::new(joints, points, Functions::splines(&[s0, s1]), &couplers) {
        Ok(chain) => chain,
        Err(_) => unreachable!("a valid table"),
    }
}
