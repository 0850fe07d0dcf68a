//! The byte stream the IMU nodes send for a motion: one `JointAngle` packet per joint the model
//! needs per row, sequence number = row index (`qgait packets`). [`write_stream`] writes it row
//! by row as the motion is read (any length in constant memory); [`Samples`] holds a motion's
//! samples for the emulator.

use qgait_proto::{JointAngle, Message, ModelId, MAX_FRAME_LEN};

use std::cell::RefCell;

use qgait_model::coords::KneeFlexion;
use qgait_model::error::ModelError;
use qgait_model::motion::source::MotionRows;
use qgait_model::points::drive;
use qgait_opensim::diagnostics::Warning;
use qgait_opensim::mot::MotionTable;

/// The samples of a motion as a node network would measure them: per row, the angle of every
/// joint the model needs, in [`ModelId::required_joints`] order (radians), and a timestamp.
#[derive(Debug, Clone, PartialEq)]
pub struct Samples {
    /// The model whose joints are sent.
    pub model: ModelId,
    /// Sensor time of each row (µs; wraps after 2^32 - 1 like the wire field).
    pub timestamps_us: Vec<u32>,
    /// Per row, one angle per joint of `model.required_joints()` (radians).
    pub angles: Vec<Vec<f64>>,
}

/// Where the timestamps come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Timing {
    /// The motion's `time` column, relative to its first row.
    TimeColumn,
    /// Row `i` at `i / rate` seconds.
    Rate(f64),
}

/// Microseconds as the wire's wrapping `u32`.
fn wire_us(seconds: f64) -> u32 {
    (seconds * 1e6).round().rem_euclid(4_294_967_296.0) as u32
}

impl Samples {
    /// The joints of `model` from every row of `table` (missing optional columns count as 0,
    /// with a warning each, as for `qgait fk`), for a hub model whose knee flexes with `knee`
    /// angles ([`HubModel::knee_flexion`](qgait_proto::HubModel::knee_flexion)): a motion in
    /// gait2392's signs (`builtin:`) has its knees turned into the model's, and the ranges are
    /// checked as that hub checks them.
    pub fn from_motion(
        table: &MotionTable,
        model: ModelId,
        knee: KneeFlexion,
        timing: Timing,
    ) -> Result<(Samples, Vec<Warning>), PacketsError> {
        let warnings = RefCell::new(Vec::new());
        let mut timestamps_us = Vec::with_capacity(table.rows());
        let mut angles = Vec::with_capacity(table.rows());
        let end = for_each_sample(
            MotionRows::from_table(table.clone()),
            model,
            knee,
            timing,
            &|w| warnings.borrow_mut().extend(w),
            |_, ts, a| {
                timestamps_us.push(ts);
                angles.push(a.to_vec());
                Ok::<_, PacketsError>(())
            },
        )?;
        let mut warnings = warnings.into_inner();
        warnings.extend(end);
        Ok((
            Samples {
                model,
                timestamps_us,
                angles,
            },
            warnings,
        ))
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.angles.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.angles.is_empty()
    }

    /// The packets of row `row` (sequence number `row`, wrapping), in joint order.
    pub fn packets(&self, row: usize) -> impl Iterator<Item = JointAngle> + '_ {
        let joints = self.model.required_joints();
        joints
            .iter()
            .zip(&self.angles[row])
            .map(move |(&joint, &angle)| {
                packet(row as u32, self.timestamps_us[row], joint, angle as f32)
            })
    }

    /// Every packet, row after row.
    pub fn all_packets(&self) -> impl Iterator<Item = JointAngle> + '_ {
        (0..self.len()).flat_map(move |row| self.packets(row))
    }
}

/// Why a motion's packets cannot be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PacketsError {
    /// `--rate` is not a positive number of samples per second.
    #[error("--rate {0}: expected a positive number of samples per second")]
    Rate(f64),
    /// The motion does not fit the model (a missing column, a `nan`, an unreadable row).
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The stream could not be written.
    #[error(transparent)]
    Write(#[from] std::io::Error),
}

/// Reads every row of `rows` as a sample of `model` (whose knee flexes with `knee` angles, as
/// in [`Samples::from_motion`]) and hands `each` its sequence number (the
/// row index, wrapping), timestamp and angles (radians, [`ModelId::required_joints`] order);
/// memory does not grow with the number of rows. `warn` gets the warnings about the columns
/// before the first row; the warnings found while reading are returned. An error of `each`
/// ends the reading and is returned.
pub fn for_each_sample<E: From<PacketsError> + From<ModelError>>(
    rows: MotionRows,
    model: ModelId,
    knee: KneeFlexion,
    timing: Timing,
    warn: &dyn Fn(Vec<Warning>),
    mut each: impl FnMut(u32, u32, &[f64]) -> Result<(), E>,
) -> Result<Vec<Warning>, E> {
    if let Timing::Rate(hz) = timing {
        if !(hz.is_finite() && hz > 0.0) {
            return Err(PacketsError::Rate(hz).into());
        }
    }
    let mut row = 0usize;
    let mut t0 = None;
    let mut sample = |t: f64, angles: &[f64]| {
        let seconds = match timing {
            Timing::TimeColumn => t - *t0.get_or_insert(t),
            Timing::Rate(hz) => row as f64 / hz,
        };
        let seq = row as u32;
        row += 1;
        each(seq, wire_us(seconds), angles)
    };
    // The coordinates are read in the model's joint order (its `required_joints`, the order of
    // its packets and of a pose frame's angles), their ranges checked as the hub checks them.
    match model {
        ModelId::Hak => drive(rows, &joint_names::<6>(model), knee, warn, |t, q| {
            sample(t, &q)
        }),
        ModelId::Phak => drive(rows, &joint_names::<8>(model), knee, warn, |t, q| {
            sample(t, &q)
        }),
        ModelId::Gait2392 | ModelId::Chain => {
            drive(rows, &joint_names::<17>(model), knee, warn, |t, q| {
                sample(t, &q)
            })
        }
    }
}

/// The OpenSim names of `model`'s joints, in [`ModelId::required_joints`] order (`N` of them).
fn joint_names<const N: usize>(model: ModelId) -> [&'static str; N] {
    let joints = model.required_joints();
    core::array::from_fn(|i| joints.get(i).map_or("", |j| j.name()))
}

/// What [`write_stream`] wrote.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StreamCounts {
    /// Rows (samples).
    pub samples: u64,
    /// Packets.
    pub packets: u64,
    /// Bytes.
    pub bytes: u64,
}

/// Writes the stream of [`stream`] for every row of `rows` as it is read: a 0x00, then each
/// sample's packets (as [`Samples::packets`] makes them).
pub fn write_stream(
    rows: MotionRows,
    model: ModelId,
    timing: Timing,
    warn: &dyn Fn(Vec<Warning>),
    out: &mut dyn std::io::Write,
) -> Result<(StreamCounts, Vec<Warning>), PacketsError> {
    let joints = model.required_joints();
    let mut counts = StreamCounts {
        bytes: 1,
        ..StreamCounts::default()
    };
    out.write_all(&[0])?;
    let mut buf = Vec::with_capacity(joints.len() * MAX_FRAME_LEN);
    // `qgait packets` sends HAK, PHAK and gait2392, whose knees flex with negative angles.
    let knee = KneeFlexion::Negative;
    let warnings = for_each_sample(rows, model, knee, timing, warn, |seq, ts, angles| {
        buf.clear();
        for (&joint, &angle) in joints.iter().zip(angles) {
            push_frame(
                &mut buf,
                &Message::JointAngle(packet(seq, ts, joint, angle as f32)),
            );
        }
        out.write_all(&buf)?;
        counts.samples += 1;
        counts.packets += joints.len() as u64;
        counts.bytes += buf.len() as u64;
        Ok::<_, PacketsError>(())
    })?;
    Ok((counts, warnings))
}

pub use qgait_emulate::{packet, push_frame};

/// The stream of `packets`: a 0x00 first (so the first frame survives any earlier line noise),
/// then each packet's frame.
pub fn stream<'a>(packets: impl IntoIterator<Item = &'a JointAngle>) -> Vec<u8> {
    let mut out = vec![0u8];
    for p in packets {
        push_frame(&mut out, &Message::JointAngle(*p));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_proto::{FrameDecoder, JointId};

    fn table() -> MotionTable {
        // PHAK's columns with the pelvis's two swapped: columns are read by name.
        let mut labels = vec!["time"];
        labels.extend(qgait_kernel::PhakAngles::<f64>::NAMES);
        labels.swap(1, 2);
        let cols = (0..9)
            .map(|c| {
                (0..3)
                    .map(|r| {
                        if c == 0 {
                            10.0 + 0.01 * r as f64
                        } else {
                            (c * 10 + r) as f64
                        }
                    })
                    .collect()
            })
            .collect();
        MotionTable::new(
            "t",
            "t.mot",
            true,
            labels.iter().map(|s| s.to_string()).collect(),
            cols,
        )
        .unwrap()
    }

    #[test]
    fn one_packet_per_joint_per_row_with_the_row_as_seq() {
        let (s, w) = Samples::from_motion(
            &table(),
            ModelId::Phak,
            KneeFlexion::Negative,
            Timing::TimeColumn,
        )
        .unwrap();
        // The test angles put both knees and ankles out of range (40-80 degrees): warned only.
        assert_eq!(w.len(), 4, "{w:?}");
        assert!(
            w.iter()
                .all(|w| w.to_string().contains("outside its range")),
            "{w:?}"
        );
        let packets: Vec<JointAngle> = s.all_packets().collect();
        assert_eq!(packets.len(), 3 * 8);
        let bytes = stream(&packets);
        let decoded: Vec<_> = FrameDecoder::new()
            .feed(&bytes)
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(decoded.len(), 24);
        for (i, m) in decoded.iter().enumerate() {
            let Message::JointAngle(p) = m else {
                panic!("{m:?}")
            };
            assert_eq!(p.seq as usize, i / 8);
            assert_eq!(p.joint, ModelId::Phak.required_joints()[i % 8]);
            assert_eq!(p.timestamp_us, [0, 10_000, 20_000][i / 8]);
        }
        // hip_flexion_r of row 1 is column 3: 31 degrees.
        let Message::JointAngle(p) = &decoded[8 + 2] else {
            unreachable!()
        };
        assert_eq!(p.angle, 31f64.to_radians() as f32);
    }

    #[test]
    fn the_columns_read_are_the_kernels_inputs_in_wire_order() {
        use qgait_kernel::models::gait2392::COORDINATES;
        use qgait_kernel::PhakAngles;
        assert_eq!(joint_names::<8>(ModelId::Phak), PhakAngles::<f64>::NAMES);
        assert_eq!(
            joint_names::<6>(ModelId::Hak),
            qgait_model::kinematics::HAK_NAMES
        );
        assert_eq!(joint_names::<17>(ModelId::Gait2392), COORDINATES);
    }

    #[test]
    fn a_chain_whose_knee_flexes_with_positive_angles_gets_its_signs_and_its_range() {
        let from = |table: &MotionTable, knee| {
            Samples::from_motion(table, ModelId::Chain, knee, Timing::TimeColumn).unwrap()
        };
        let joints = ModelId::Chain.required_joints();
        let at = |j: JointId| joints.iter().position(|&k| k == j).unwrap();
        let knees = [at(JointId::KneeAngleR), at(JointId::KneeAngleL)];
        // The file's knees (40-72°) are flexed in this model's signs: in range, sent as they are.
        let (s, w) = from(&table(), KneeFlexion::Positive);
        assert!(
            w.iter().all(|w| !w.to_string().contains("`knee_angle")),
            "{w:?}"
        );
        assert!(
            w.iter().any(|w| w.to_string().contains("`ankle_angle_r")),
            "{w:?}"
        );
        assert_eq!(s.angles[0][knees[0]], 40f64.to_radians());
        let (_, w) = from(&table(), KneeFlexion::Negative);
        assert!(
            w.iter().any(|w| w.to_string().contains("`knee_angle_r")),
            "{w:?}"
        );
        // A builtin motion (gait2392's signs) has its knees negated, nothing else changed.
        let (builtin, _) =
            qgait_model::motion::source::load_motion("builtin:crouch=0.5,rows=5").unwrap();
        let (positive, w) = from(&builtin, KneeFlexion::Positive);
        assert!(
            w.iter().all(|w| !w.to_string().contains("outside")),
            "{w:?}"
        );
        let (negative, _) = from(&builtin, KneeFlexion::Negative);
        for (p, n) in positive.angles.iter().zip(&negative.angles) {
            for (k, (a, b)) in p.iter().zip(n).enumerate() {
                let b = if knees.contains(&k) { -b } else { *b };
                assert_eq!(*a, b);
            }
            assert!(p[knees[0]] > 0.3 && p[knees[1]] > 0.3, "{p:?}");
        }
    }

    #[test]
    fn rate_sets_the_timestamps_and_hak_sends_six_joints() {
        let (s, _) = Samples::from_motion(
            &table(),
            ModelId::Hak,
            KneeFlexion::Negative,
            Timing::Rate(200.0),
        )
        .unwrap();
        assert_eq!(s.timestamps_us, [0, 5000, 10_000]);
        assert_eq!(s.packets(2).count(), 6);
        assert!(Samples::from_motion(
            &table(),
            ModelId::Hak,
            KneeFlexion::Negative,
            Timing::Rate(0.0)
        )
        .is_err());
        let (g, w) = Samples::from_motion(
            &table(),
            ModelId::Gait2392,
            KneeFlexion::Negative,
            Timing::TimeColumn,
        )
        .unwrap();
        assert_eq!(g.packets(0).count(), 17);
        assert_eq!(w.len(), 9 + 4, "{w:?}");
    }
}
