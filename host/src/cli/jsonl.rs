//! `qgait decode --format jsonl`: one JSON object per line for each frame of a hub log, with
//! `serde_json`. Objects: `{"type":"pose","seq","model","flags","angles","points","distances"}`,
//! `{"type":"status", <counter>: n, ...}` (the counters in wire order),
//! `{"type":"other","tag"}` and `{"type":"damaged","offset","error"}`. A non-finite number is
//! `null`.

use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

use qgait_proto::{DecodeError, PoseFrame, Status};

#[derive(Serialize)]
struct Pose {
    r#type: &'static str,
    seq: u32,
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

#[derive(Serialize)]
struct Other {
    r#type: &'static str,
    tag: u32,
}

/// Another message (its tag).
pub fn other(tag: u32) -> String {
    to_line(&Other {
        r#type: "other",
        tag,
    })
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
        assert!(v["distances"][0].is_null());
        assert_eq!(v["distances"][1], 0.25);
        assert_eq!(v["points"][7][2], 0.5);
        frame.angles[0] = 0.1;
        let v: serde_json::Value = serde_json::from_str(&pose(&frame)).unwrap();
        assert_eq!(v["angles"][0].as_f64(), Some(f64::from(0.1f32)));
    }
}
