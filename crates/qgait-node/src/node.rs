//! The [`Node`]: serial bytes in, raw samples fused, segment orientations and status out.

use qgait_hub::counters::bump;
use qgait_hub::line::{self, write_frame, Line, LineDevice, SerialPort};
use qgait_hub::{Clock, PollSummary};
use qgait_proto::{
    cobs_max_encoded_len, decode_node_message, encode_raw_imu_status_frame,
    encode_segment_orientation_frame, NodeMessage, RawImuConfig, RawImuSample, Status, CRC_LEN,
    STATUS_MAX_LEN,
};

use crate::raw_input::{orientation_packet, RawInput, RawOutcome};

/// Bytes read by one [`Node::poll`] at most, so periodic work is never starved by a busy line.
pub const MAX_BYTES_PER_POLL: usize = 256;

/// Bytes the node asks the serial port for in one read.
pub const READ_CHUNK: usize = 64;

/// The node's transmit buffer: its longest frame, a `Status` (a `SegmentOrientation` and a
/// `RawImuStatus` are shorter).
pub const TX_LEN: usize = cobs_max_encoded_len(STATUS_MAX_LEN + CRC_LEN) + 1;

/// The segments one node fuses: its own IMU's.
pub const NODE_SEGMENTS: usize = 1;

/// Default period of unsolicited status frames (milliseconds), as the hub's.
pub const DEFAULT_STATUS_PERIOD_MS: u32 = qgait_hub::DEFAULT_STATUS_PERIOD_MS;

/// What one [`Node::poll`] did, as a hub's poll says it: bytes read, frames written
/// (orientations and status), and whether a status was among them.
pub type NodePoll = PollSummary;

/// A node fusing its own IMU, generic over its serial port and clock, as the hub is
/// (`qgait_hub::Hub`): feed it by calling [`poll`](Node::poll) in the main loop.
///
/// It takes [`RawImuSample`]s (its sensor's FIFO; under QEMU streamed into its UART) and
/// [`RawImuConfig`]s, fuses each sample of its configured segment with the kernel's VQF in
/// `f32` ([`RawInput`]) and writes a `SegmentOrientation` frame for every `output_every`-th.
/// It never panics and never blocks on input: every byte, frame and message is counted in
/// its [`Status`] (`packets_accepted`: raw samples decoded; `samples_completed`: orientations
/// sent; `malformed`: any other well-formed message, which a node does not take; the decode
/// errors as a hub counts them) and its raw input's counters
/// ([`RawImuStatus`](qgait_proto::RawImuStatus)).
pub struct Node<S, C> {
    /// The serial port, clock, frame decoder, counters, status schedule, receive buffer.
    line: Line<S, C, READ_CHUNK>,
    input: RawInput<f32, NODE_SEGMENTS>,
    tx: [u8; TX_LEN],
}

impl<S: SerialPort, C: Clock> Node<S, C> {
    /// A node with no raw segment until a [`RawImuConfig`], sending a status every
    /// `status_period_ms` (0: only on request).
    pub fn new(serial: S, clock: C, status_period_ms: u32) -> Self {
        Node {
            line: Line::new(serial, clock, status_period_ms),
            input: RawInput::new(),
            tx: [0; TX_LEN],
        }
    }

    /// Reads what the serial port has (at most [`MAX_BYTES_PER_POLL`] bytes), handles it, and
    /// sends a periodic status when due.
    pub fn poll(&mut self) -> NodePoll {
        line::poll(self, MAX_BYTES_PER_POLL)
    }

    /// The first `n` bytes of the receive buffer, through the frame decoder.
    fn on_bytes(&mut self, n: usize) {
        let mut pos = 0;
        // `frame_end` and the decoder's `end_frame` apart, not `Line::next_frame` (which
        // joins them for the hub's instruction count): 150 B less of the node's flash.
        while self.line.frame_end(&mut pos, n) {
            match self.line.decoder.end_frame() {
                None => {}
                Some(Ok(message)) => match decode_node_message(message) {
                    Ok(NodeMessage::RawImuSample(sample)) => self.on_sample(&sample),
                    Ok(NodeMessage::RawImuConfig(config)) => self.on_config(&config),
                    Ok(NodeMessage::NotTaken(_)) => bump(&mut self.line.status.malformed),
                    Err(error) => self.line.status.count_decode_error(&error),
                },
                Some(Err(error)) => self.line.status.count_decode_error(&error),
            }
        }
    }

    fn on_sample(&mut self, sample: &RawImuSample) {
        bump(&mut self.line.status.packets_accepted);
        if let RawOutcome::Fused(Some(q)) = self.input.push(sample) {
            let packet = orientation_packet(sample, q);
            if let Ok(frame) = encode_segment_orientation_frame(&packet, &mut self.tx) {
                write_frame(&mut self.line.serial, &mut self.line.status, frame);
                bump(&mut self.line.status.samples_completed);
            }
        }
    }

    fn on_config(&mut self, config: &RawImuConfig) {
        if !self.input.configure(config) {
            bump(&mut self.line.status.config_rejected);
        }
        if config.request_status {
            self.send_status();
        }
    }

    /// The counters, with the current uptime.
    pub fn status(&self) -> Status {
        self.line.status()
    }

    /// The raw input: its settings and counters.
    pub fn input(&self) -> &RawInput<f32, NODE_SEGMENTS> {
        &self.input
    }

    /// The serial port, e.g. to inspect a test double.
    pub fn serial_mut(&mut self) -> &mut S {
        &mut self.line.serial
    }

    /// A `Status` (counting itself in `frames_sent`), then the raw input's `RawImuStatus`.
    fn send_status(&mut self) {
        self.line.send_status(&mut self.tx);
        if let Ok(frame) = encode_raw_imu_status_frame(&self.input.status(), &mut self.tx) {
            write_frame(&mut self.line.serial, &mut self.line.status, frame);
        }
    }
}

impl<S: SerialPort, C: Clock> LineDevice<S, C, READ_CHUNK> for Node<S, C> {
    fn line(&mut self) -> &mut Line<S, C, READ_CHUNK> {
        &mut self.line
    }

    fn on_bytes(&mut self, n: usize) {
        Node::on_bytes(self, n)
    }

    fn send_status(&mut self) {
        Node::send_status(self)
    }
}
