//! `qgait decode --format jsonl`: one JSON object per line for each frame of a log (what a hub
//! sends, what nodes send it, what the host sends it), with `serde_json`. Objects:
//! `{"type":"pose","seq","timestamp_us","model","flags","angles","points","distances"}`,
//! `{"type":"status", <counter>: n, ...}` (the counters in wire order),
//! `{"type":"damaged","offset","error"}`, and every other message as
//! `{"type": <its kind>, <field>: value, ...}`: the kind is
//! [`qgait_device::log::kind`] (`joint_angle`, `raw_imu_sample`, ...), the fields the message's
//! own, in their order, by its serde derive, with these changes: a joint is its OpenSim name
//! and a model its lower-case name (as in a pose line), a segment orientation also gives its
//! `quaternion` decoded (not normalised), a chain-table part gives its `bytes` as a count and
//! their `hex`, and a raw-input status is its counters in wire order. Enumerations otherwise
//! are their variant names (`"Right"`, `"HoldLast"`, `"FemurR"`). Numbers are the `f32` values
//! written as `f64` (exactly the value sent); a non-finite number is `null`.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

use serde_json::{Map, Value};

use qgait_device::log::kind;
use qgait_proto::{DecodeError, Message, PoseFrame, Status};

#[derive(Serialize)]
struct Pose {
    r#type: &'static str,
    seq: u32,
    timestamp_us: u32,
    model: String,
    flags: u8,
    angles: Vec<f64>,
    points: Vec<[f64; 3]>,
    distances: [f64; 3],
}

/// A pose frame. Numbers are the hub's `f32` values written as `f64` (exactly the value the hub
/// sent, e.g. `0.10000000149011612`, not the shorter `0.1` that only reads back as `f32`).
pub fn pose(p: &PoseFrame) -> String {
    to_line(&Pose {
        r#type: "pose",
        seq: p.seq,
        timestamp_us: p.timestamp_us,
        model: p.model.to_string(),
        flags: p.flags,
        angles: p.angles.iter().map(|&a| f64::from(a)).collect(),
        points: p.points.iter().map(|q| q.map(f64::from)).collect(),
        distances: p.distances.map(f64::from),
    })
}

struct Counters<'a>(&'a Status);

impl Serialize for Counters<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let counters = self.0.named_counters();
        let mut map = s.serialize_map(Some(counters.len() + 1))?;
        map.serialize_entry("type", "status")?;
        for (name, value) in counters {
            map.serialize_entry(name, &value)?;
        }
        map.end()
    }
}

/// A status frame.
pub fn status(s: &Status) -> String {
    to_line(&Counters(s))
}

/// Any message: a pose or status line for those, else the message's fields (module docs).
pub fn message(m: &Message) -> String {
    let mut line = Map::new();
    line.insert("type".into(), kind(m).into());
    match m {
        Message::PoseFrame(p) => return pose(p),
        Message::Status(s) => return status(s),
        Message::RawImuStatus(s) => {
            for (name, value) in s.named_counters() {
                line.insert(name.into(), value.into());
            }
        }
        Message::JointAngle(a) => {
            fields(&mut line, a);
            line.insert("joint".into(), a.joint.name().into());
        }
        Message::Config(c) => {
            fields(&mut line, c);
            line.insert("model".into(), c.model.to_string().into());
        }
        Message::SubjectLeg(l) => fields(&mut line, l),
        Message::SubjectKnee(k) => fields(&mut line, k),
        Message::SubjectConfig(c) => fields(&mut line, c),
        Message::SegmentOrientation(o) => {
            fields(&mut line, o);
            let quality = line.remove("quality");
            let q = o.quaternion().map(f64::from);
            line.insert("quaternion".into(), q.to_vec().into());
            line.extend(quality.map(|v| ("quality".into(), v)));
        }
        Message::ImuConfig(c) => fields(&mut line, c),
        Message::ChainTable(t) => {
            fields(&mut line, t);
            line.insert("bytes".into(), t.bytes.len().into());
            line.insert("hex".into(), hex(&t.bytes).into());
        }
        Message::ChainTableConfig(c) => fields(&mut line, c),
        Message::RawImuSample(r) => fields(&mut line, r),
        Message::RawImuConfig(c) => fields(&mut line, c),
        Message::VelocityConfig(c) => fields(&mut line, c),
        Message::PoseVelocities(v) => fields(&mut line, v),
    }
    to_line(&line)
}

/// Appends the fields of `value` (a struct whose numbers are integers and `f32`s) to `line`, in
/// their order, each `f32` as the `f64` of the same value; a node sample's `header`
/// ([`SampleHeader`](qgait_proto::SampleHeader)) as its fields, in place, as on the wire.
fn fields(line: &mut Map<String, Value>, value: &impl Serialize) {
    match serde_json::to_value(value).expect("the messages serialise to JSON") {
        Value::Object(o) => {
            for (name, mut value) in o {
                widen(&mut value);
                match value {
                    Value::Object(header) if name == "header" => line.extend(header),
                    value => {
                        line.insert(name, value);
                    }
                }
            }
        }
        other => unreachable!("a message is a struct, not {other}"),
    }
}

/// Rewrites every float in `v` (an `f32` that `serde_json` holds as its shortest decimal, e.g.
/// `0.1`) as the `f64` of that `f32` (`0.10000000149011612`), as in a pose line.
fn widen(v: &mut Value) {
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().expect("a float") as f32;
            *v = Value::from(f64::from(x));
        }
        Value::Array(a) => a.iter_mut().for_each(widen),
        Value::Object(o) => o.values_mut().for_each(widen),
        _ => {}
    }
}

/// `bytes` as lower-case hex pairs, no separator.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

#[derive(Serialize)]
struct Damaged {
    r#type: &'static str,
    offset: u64,
    error: String,
}

/// A damaged frame ending at byte `offset` of the log.
pub fn damaged(offset: u64, error: &DecodeError) -> String {
    to_line(&Damaged {
        r#type: "damaged",
        offset,
        error: format!("{:?}", error.kind()),
    })
}

fn to_line(value: &impl Serialize) -> String {
    serde_json::to_string(value).expect("plain numbers and strings always serialise")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_status_line_keeps_the_wire_order_and_a_pose_line_writes_nan_as_null() {
        let line = status(&Status {
            packets_accepted: 7,
            ..Status::default()
        });
        assert!(
            line.starts_with(r#"{"type":"status","packets_accepted":7,"crc_errors":0,"#),
            "{line}"
        );
        let v: serde_json::Value = serde_json::from_str(&line).unwrap();
        assert_eq!(
            v.as_object().unwrap().len(),
            Status::default().named_counters().len() + 1
        );
        let mut frame = PoseFrame {
            seq: 3,
            timestamp_us: 30_000,
            model: qgait_proto::ModelId::Hak,
            angles: heapless::Vec::new(),
            points: [[0.5; 3]; qgait_proto::point::COUNT],
            distances: [f32::NAN, 0.25, 1.0],
            flags: 0,
        };
        frame.angles.extend_from_slice(&[0.5; 6]).unwrap();
        let v: serde_json::Value = serde_json::from_str(&pose(&frame)).unwrap();
        assert_eq!(v["type"], "pose");
        assert_eq!(v["seq"], 3);
        assert_eq!(v["timestamp_us"], 30_000);
        assert!(v["distances"][0].is_null());
        assert_eq!(v["distances"][1], 0.25);
        assert_eq!(v["points"][7][2], 0.5);
        frame.angles[0] = 0.1;
        let v: serde_json::Value = serde_json::from_str(&pose(&frame)).unwrap();
        assert_eq!(v["angles"][0].as_f64(), Some(f64::from(0.1f32)));
    }

    #[test]
    fn a_chain_part_is_its_bytes_in_hex_and_a_knee_its_knots() {
        let mut bytes = heapless::Vec::new();
        bytes.extend_from_slice(&[0x00, 0xab, 0x10]).unwrap();
        let line = message(&Message::ChainTable(qgait_proto::ChainTable {
            upload: 7,
            at: 256,
            bytes,
        }));
        assert_eq!(
            line,
            r#"{"type":"chain_table","upload":7,"at":256,"bytes":3,"hex":"00ab10"}"#
        );
        let mut knots = heapless::Vec::new();
        knots
            .extend_from_slice(&[[-2.0, 0.1], [0.0, f32::NAN]])
            .unwrap();
        let v: serde_json::Value =
            serde_json::from_str(&message(&Message::SubjectKnee(qgait_proto::SubjectKnee {
                upload: 7,
                leg: qgait_proto::Leg::Left,
                direction: qgait_proto::KneeDirection::Ty,
                knots,
            })))
            .unwrap();
        assert_eq!(v["type"], "subject_knee");
        assert_eq!(v["leg"], "Left");
        assert_eq!(v["direction"], "Ty");
        assert_eq!(v["knots"][0][1].as_f64(), Some(f64::from(0.1f32)));
        assert!(v["knots"][1][1].is_null());
    }
}
