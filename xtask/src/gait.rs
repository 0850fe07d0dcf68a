//! A synthetic walking pattern for the PHAK joints, to drive the firmware over its UART.

use qgait_proto::JointId;

/// Samples per gait cycle (100 Hz sampling, 1.1 s stride).
const CYCLE: f64 = 110.0;

/// The angle (radians, OpenSim signs) of `joint` at sample `seq`: a smooth periodic gait,
/// the left leg half a cycle behind the right, rounded to f32 as a node would send it.
pub fn angle(joint: JointId, seq: u32) -> f32 {
    let phase = 2.0 * std::f64::consts::PI * f64::from(seq) / CYCLE;
    let right = phase;
    let left = phase + std::f64::consts::PI;
    let hip = |p: f64| 0.2 + 0.45 * p.sin();
    let knee = |p: f64| -0.6 + 0.55 * (p + 0.9).cos();
    let ankle = |p: f64| 0.05 + 0.2 * (p - 0.5).sin();
    let value = match joint {
        JointId::PelvisRotation => 0.08 * phase.sin(),
        JointId::PelvisList => 0.05 * (2.0 * phase).sin(),
        JointId::HipFlexionR => hip(right),
        JointId::KneeAngleR => knee(right),
        JointId::AnkleAngleR => ankle(right),
        JointId::HipFlexionL => hip(left),
        JointId::KneeAngleL => knee(left),
        JointId::AnkleAngleL => ankle(left),
        _ => 0.0,
    };
    value as f32
}
