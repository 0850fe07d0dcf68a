//! On-target gait2392 tests: the f32 kernel on the Cortex-M4F against f64 values computed on
//! the host at build time, directly and through the hub with a subject model sent in parts.

use qgait_hub::{parts_of, Hub, ManualClock};
use qgait_hub_checks::{drain, each_output, send, CheckSerial};
use qgait_kernel::metrics::distances;
use qgait_kernel::{Gait2392, Gait2392Geometry, Real};
use qgait_proto::{
    JointAngle, JointId, Message, MissingPolicy, ModelId, SubjectConfig, PROTOCOL_VERSION,
};

mod expected {
    use qgait_kernel::models::gait2392::{Knots, LegGeometry};
    use qgait_kernel::Gait2392Geometry;
    include!(concat!(env!("OUT_DIR"), "/gait2392_cases.rs"));
}

/// Largest accepted distance between an f32 point and its f64 value (metres): 10 µm.
const POINT_TOLERANCE_M: f64 = 1e-5;

/// The kernel points reported in a `PoseFrame`: hip, knee, ankle, toe tip of each leg.
const FRAME_POINTS: [usize; 8] = [0, 1, 2, 5, 6, 7, 8, 11];

/// Generic gait2392 in f32 against f64: every one of the 12 points of every case.
pub fn gait2392_f32_points_match_host_f64() {
    // As the hub builds it: from the f32 numbers, knee splines computed in f32.
    let Ok(model) = Gait2392::<f32>::from_geometry(&Gait2392Geometry::generic().to_f32()) else {
        defmt::panic!("Gait2392::from_geometry refused the generic model");
    };
    let mut worst = 0.0f64;
    let mut cases = 0;
    for (_, q, points, want_d) in expected::CASES.iter().filter(|c| c.0 == 0) {
        let pose = model.fk(q);
        for (got, want) in pose.points.iter().zip(points) {
            let got = got.to_array();
            for k in 0..3 {
                worst = worst.max((f64::from(got[k]) - want[k]).abs());
            }
        }
        let d = distances(&pose.bilateral()).to_array();
        for k in 0..3 {
            worst = worst.max((f64::from(d[k]) - want_d[k]).abs());
        }
        cases += 1;
    }
    defmt::info!(
        "gait2392 f32 vs f64: largest point error {=f64} m over {=usize} cases",
        worst,
        cases
    );
    defmt::assert!(cases > 0, "no generic cases");
    defmt::assert!(
        worst <= POINT_TOLERANCE_M,
        "largest f32 gait2392 point error {=f64} m",
        worst
    );
}

/// A subject model sent to the hub in its 6 parts and switched to by a `SubjectConfig`: every
/// pose frame the hub sends for the cases equals the host's f64 prediction within 10 µm, and
/// differs from the generic model's by centimetres.
pub fn subject_model_on_the_hub_matches_host_f64() {
    let clock = ManualClock::new(0);
    let Ok(mut hub) = Hub::new(CheckSerial::new(), &clock, 0) else {
        defmt::panic!("Hub::new refused the default model");
    };
    let Ok((legs, knees)) = parts_of(&expected::subject(), 42) else {
        defmt::panic!("parts_of refused the subject");
    };
    let config = SubjectConfig {
        upload: 42,
        missing_policy: MissingPolicy::Drop,
        reorder_window: 2,
        request_status: false,
    };
    let sent = legs
        .iter()
        .all(|l| send(hub.serial_mut(), &Message::SubjectLeg(*l)))
        && knees
            .iter()
            .all(|k| send(hub.serial_mut(), &Message::SubjectKnee(k.clone())))
        && send(hub.serial_mut(), &Message::SubjectConfig(config));
    defmt::assert!(sent, "the model did not fit the serial buffer");
    drain(&mut hub);
    defmt::assert!(
        hub.subject() == Some(42),
        "subject model not in force, config_rejected {=u32}",
        hub.status().config_rejected
    );
    let subject_cases: heapless::Vec<_, 32> = expected::CASES.iter().filter(|c| c.0 == 1).collect();
    for (seq, (_, q, _, _)) in subject_cases.iter().enumerate() {
        for joint in JointId::ALL {
            let packet = JointAngle {
                version: PROTOCOL_VERSION,
                node: joint.index(),
                joint,
                seq: seq as u32,
                timestamp_us: 0,
                angle: q[joint.index() as usize],
                quality: 0,
            };
            defmt::assert!(
                send(hub.serial_mut(), &Message::JointAngle(packet)),
                "a packet did not fit the serial buffer"
            );
        }
        drain(&mut hub);
    }
    let (mut worst, mut frames, mut nearest_generic) = (0.0f64, 0usize, f64::MAX);
    let bad = each_output(&mut hub, |m| {
        let Message::PoseFrame(p) = m else { return };
        let Some((_, q, want, want_d)) = subject_cases.get(p.seq as usize) else {
            return;
        };
        frames += usize::from(p.model == ModelId::Gait2392 && p.angles.as_slice() == &q[..]);
        for (got, &i) in p.points.iter().zip(&FRAME_POINTS) {
            for k in 0..3 {
                worst = worst.max((f64::from(got[k]) - want[i][k]).abs());
            }
        }
        for (got, want) in p.distances.iter().zip(want_d) {
            worst = worst.max((f64::from(*got) - want).abs());
        }
        // The same angles in the generic model: the right toe tip moves by centimetres.
        if let Some((_, _, generic, _)) = expected::CASES.iter().find(|c| c.0 == 0 && c.1 == *q) {
            let d = (0..3)
                .map(|k| (want[5][k] - generic[5][k]) * (want[5][k] - generic[5][k]))
                .sum::<f64>();
            nearest_generic = nearest_generic.min(Real::sqrt(d));
        }
    });
    defmt::info!(
        "subject gait2392 on the hub vs f64: largest error {=f64} m over {=usize} frames; toe tip >= {=f64} m from the generic model's",
        worst,
        frames,
        nearest_generic
    );
    defmt::assert!(
        bad == 0 && frames == subject_cases.len() && !subject_cases.is_empty(),
        "{=usize} subject pose frames of {=usize} cases, {=u32} undecodable",
        frames,
        subject_cases.len(),
        bad
    );
    defmt::assert!(
        nearest_generic >= 0.01,
        "subject toe tip only {=f64} m from the generic model's",
        nearest_generic
    );
    defmt::assert!(
        worst <= POINT_TOLERANCE_M,
        "largest subject point error on the hub {=f64} m",
        worst
    );
}
