#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod defmt_log;
mod error;
pub mod faults;
pub mod firmware;
pub mod qemu;
pub mod session;

pub use error::EmulateError;

use qgait_proto::{encode_frame, JointAngle, JointId, Message, MAX_FRAME_LEN, PROTOCOL_VERSION};

/// One packet as a node sends it: node id = joint id (one node per joint), quality 0 (good).
pub fn packet(seq: u32, timestamp_us: u32, joint: JointId, angle: f32) -> JointAngle {
    JointAngle {
        version: PROTOCOL_VERSION,
        node: joint.index(),
        joint,
        seq,
        timestamp_us,
        angle,
        quality: 0,
    }
}

/// Appends one framed message (its trailing 0x00 included).
pub fn push_frame(out: &mut Vec<u8>, message: &Message) {
    let mut buf = [0u8; MAX_FRAME_LEN];
    // Every message of the protocol fits MAX_FRAME_LEN, and these have the right angle counts.
    let frame = encode_frame(message, &mut buf).expect("a protocol message fits MAX_FRAME_LEN");
    out.extend_from_slice(frame);
}
