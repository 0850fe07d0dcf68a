//! Decoding what a hub sends (a log file, a pipe, a serial port, QEMU's UART): every good frame,
//! every damaged stretch with where it was, and counts.

use std::collections::BTreeMap;
use std::fmt;

use qgait_proto::{DecodeError, ErrorKind, FrameDecoder, Message, PoseFrame, Status};

/// The name of `message`'s kind, snake case (`"joint_angle"`, `"raw_imu_status"`, ...): the
/// `type` of `qgait decode`'s JSON lines and the kinds of [`Counts`]' summary.
pub fn kind(message: &Message) -> &'static str {
    match message {
        Message::JointAngle(_) => "joint_angle",
        Message::PoseFrame(_) => "pose",
        Message::Status(_) => "status",
        Message::Config(_) => "config",
        Message::SubjectLeg(_) => "subject_leg",
        Message::SubjectKnee(_) => "subject_knee",
        Message::SubjectConfig(_) => "subject_config",
        Message::SegmentOrientation(_) => "segment_orientation",
        Message::ImuConfig(_) => "imu_config",
        Message::ChainTable(_) => "chain_table",
        Message::ChainTableConfig(_) => "chain_table_config",
        Message::RawImuSample(_) => "raw_imu_sample",
        Message::RawImuConfig(_) => "raw_imu_config",
        Message::RawImuStatus(_) => "raw_imu_status",
        Message::VelocityConfig(_) => "velocity_config",
        Message::PoseVelocities(_) => "pose_velocities",
    }
}

/// One item of a decoded log, in arrival order.
#[derive(Debug, Clone, PartialEq)]
pub enum Record {
    /// A good frame and the offset of the byte that ended it (its 0x00 delimiter).
    Message {
        /// Byte offset of the frame's delimiter in the input.
        offset: u64,
        /// The message.
        message: Message,
    },
    /// A damaged frame, skipped.
    Damaged {
        /// Byte offset where the decoder reported it (the delimiter, or the byte that made the
        /// frame oversize).
        offset: u64,
        /// Why it was rejected.
        error: DecodeError,
    },
}

/// Counts of a decoded log.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Counts {
    /// Bytes read.
    pub bytes: u64,
    /// `PoseFrame`s.
    pub poses: u64,
    /// `Status` frames.
    pub statuses: u64,
    /// Other good messages (e.g. joint-angle packets when decoding a node stream).
    pub other: u64,
    /// The other messages by [`kind`].
    pub other_kinds: BTreeMap<&'static str, u64>,
    /// Damaged frames by kind (`Cobs`, `Crc`, ...).
    pub damaged: BTreeMap<ErrorKind, u64>,
    /// Bytes at the end that no delimiter closed.
    pub unterminated: usize,
}

impl Counts {
    /// Total damaged frames.
    pub fn damaged_total(&self) -> u64 {
        self.damaged.values().sum()
    }
}

impl fmt::Display for Counts {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} bytes: {} pose frames, {} status frames, {} other messages, {} damaged frames",
            self.bytes,
            self.poses,
            self.statuses,
            self.other,
            self.damaged_total()
        )?;
        if !self.damaged.is_empty() {
            let kinds: Vec<String> = self
                .damaged
                .iter()
                .map(|(k, n)| format!("{k:?} {n}"))
                .collect();
            write!(f, " ({})", kinds.join(", "))?;
        }
        if self.unterminated > 0 {
            write!(
                f,
                ", {} bytes at the end without a delimiter",
                self.unterminated
            )?;
        }
        if !self.other_kinds.is_empty() {
            let kinds: Vec<String> = self
                .other_kinds
                .iter()
                .map(|(k, n)| format!("{k} {n}"))
                .collect();
            write!(f, "; other messages: {}", kinds.join(", "))?;
        }
        Ok(())
    }
}

/// A streaming log decoder: feed chunks as they come, get records.
#[derive(Debug, Default)]
pub struct LogDecoder {
    decoder: FrameDecoder,
    counts: Counts,
}

impl LogDecoder {
    /// A decoder at offset 0.
    pub fn new() -> Self {
        Self::default()
    }

    /// Decodes `chunk`, handing each record to `on_record`.
    pub fn feed(&mut self, chunk: &[u8], mut on_record: impl FnMut(Record)) {
        for &byte in chunk {
            let offset = self.counts.bytes;
            self.counts.bytes += 1;
            match self.decoder.push(byte) {
                None => {}
                Some(Ok(message)) => {
                    match &message {
                        Message::PoseFrame(_) => self.counts.poses += 1,
                        Message::Status(_) => self.counts.statuses += 1,
                        other => {
                            self.counts.other += 1;
                            *self.counts.other_kinds.entry(kind(other)).or_default() += 1;
                        }
                    }
                    on_record(Record::Message { offset, message });
                }
                Some(Err(error)) => {
                    *self.counts.damaged.entry(error.kind()).or_default() += 1;
                    on_record(Record::Damaged { offset, error });
                }
            }
        }
    }

    /// The counts so far, with the bytes still waiting for a delimiter.
    pub fn counts(&self) -> Counts {
        Counts {
            unterminated: self.decoder.pending_len(),
            ..self.counts.clone()
        }
    }
}

/// A whole log decoded at once.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HubLog {
    /// Every pose frame, in arrival order.
    pub poses: Vec<PoseFrame>,
    /// Every status frame, in arrival order.
    pub statuses: Vec<Status>,
    /// Counts.
    pub counts: Counts,
}

impl HubLog {
    /// Decodes `bytes`.
    pub fn decode(bytes: &[u8]) -> HubLog {
        Self::decode_with(bytes, |_| {})
    }

    /// Decodes `bytes`, showing `on_message` every message in the order the hub sent them
    /// (e.g. to a [`Verifier`](crate::verify::Verifier), which takes the velocities after
    /// their pose frames) in the same pass.
    pub fn decode_with(bytes: &[u8], mut on_message: impl FnMut(&Message)) -> HubLog {
        let mut decoder = LogDecoder::new();
        let mut log = HubLog::default();
        decoder.feed(bytes, |record| {
            if let Record::Message { message, .. } = record {
                on_message(&message);
                match message {
                    Message::PoseFrame(p) => log.poses.push(p),
                    Message::Status(s) => log.statuses.push(s),
                    _ => {}
                }
            }
        });
        log.counts = decoder.counts();
        log
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::packets::push_frame;
    use qgait_proto::ModelId;

    fn pose(seq: u32) -> Message {
        let mut angles = heapless::Vec::new();
        for i in 0..8 {
            angles.push(i as f32 * 0.1).unwrap();
        }
        Message::PoseFrame(PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: ModelId::Phak,
            angles,
            points: [[0.5; 3]; 8],
            distances: [0.2; 3],
            flags: 0,
        })
    }

    #[test]
    fn damage_is_reported_with_its_offset_and_every_good_frame_decodes() {
        let mut bytes = vec![0u8];
        push_frame(&mut bytes, &pose(1));
        let damaged_at = bytes.len() + 5;
        push_frame(&mut bytes, &pose(2));
        bytes[damaged_at] ^= 0x10;
        push_frame(
            &mut bytes,
            &Message::Status(Status {
                packets_accepted: 7,
                ..Status::default()
            }),
        );
        push_frame(&mut bytes, &pose(3));
        push_frame(
            &mut bytes,
            &Message::RawImuStatus(qgait_proto::RawImuStatus::default()),
        );
        bytes.extend_from_slice(&[1, 2, 3]);
        let mut records = Vec::new();
        let mut d = LogDecoder::new();
        // Any chunking gives the same records.
        for chunk in bytes.chunks(7) {
            d.feed(chunk, |r| records.push(r));
        }
        assert_eq!(records.len(), 5);
        assert!(
            matches!(records[1], Record::Damaged { offset, .. } if offset as usize > damaged_at),
            "{:?}",
            records[1]
        );
        let log = HubLog::decode(&bytes);
        assert_eq!(log.poses.iter().map(|p| p.seq).collect::<Vec<_>>(), [1, 3]);
        assert_eq!(log.statuses[0].packets_accepted, 7);
        assert_eq!(log.counts.damaged_total(), 1);
        assert_eq!(log.counts.unterminated, 3);
        assert_eq!(d.counts(), log.counts);
        let text = log.counts.to_string();
        assert!(
            text.contains("2 pose frames, 1 status frames, 1 other messages, 1 damaged frames ("),
            "{text}"
        );
        assert!(
            text.ends_with("; other messages: raw_imu_status 1"),
            "{text}"
        );
    }
}
