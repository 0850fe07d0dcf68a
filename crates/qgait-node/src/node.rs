//! The [`Node`]: serial bytes in, raw samples fused, segment orientations and status out.

use embedded_hal_nb::serial::{Error as LineError, ErrorKind as LineErrorKind};
use embedded_io::{Read, ReadReady, Write};
use qgait_hub::counters::bump;
use qgait_hub::Clock;
use qgait_proto::{
    cobs_max_encoded_len, decode_node_message, encode_raw_imu_status_frame,
    encode_segment_orientation_frame, encode_status_frame, FrameDecoder, NodeMessage, RawImuConfig,
    RawImuSample, Status, CRC_LEN, STATUS_MAX_LEN,
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

/// What one [`Node::poll`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct NodePoll {
    /// Bytes read from the serial port.
    pub bytes: u32,
    /// Frames written (orientations and status).
    pub frames_sent: u32,
    /// Whether a status was among them (periodic or requested).
    pub status_sent: bool,
}

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
    serial: S,
    clock: C,
    decoder: FrameDecoder,
    input: RawInput<f32, NODE_SEGMENTS>,
    status: Status,
    started_ms: u32,
    last_status_ms: u32,
    status_period_ms: u32,
    status_frames: u32,
    tx: [u8; TX_LEN],
    rx: [u8; READ_CHUNK],
}

impl<S, C> Node<S, C>
where
    S: Read + ReadReady + Write,
    S::Error: LineError,
    C: Clock,
{
    /// A node with no raw segment until a [`RawImuConfig`], sending a status every
    /// `status_period_ms` (0: only on request).
    pub fn new(serial: S, clock: C, status_period_ms: u32) -> Self {
        let now = clock.now_ms();
        Node {
            serial,
            clock,
            decoder: FrameDecoder::new(),
            input: RawInput::new(),
            status: Status::default(),
            started_ms: now,
            last_status_ms: now,
            status_period_ms,
            status_frames: 0,
            tx: [0; TX_LEN],
            rx: [0; READ_CHUNK],
        }
    }

    /// Reads what the serial port has (at most [`MAX_BYTES_PER_POLL`] bytes), handles it, and
    /// sends a periodic status when due.
    pub fn poll(&mut self) -> NodePoll {
        let sent_before = self.status.frames_sent;
        let status_before = self.status_frames;
        let mut bytes = 0;
        while bytes < MAX_BYTES_PER_POLL {
            if !matches!(self.serial.read_ready(), Ok(true)) {
                break;
            }
            match self.serial.read(&mut self.rx) {
                Ok(0) => break,
                Ok(n) => {
                    let n = n.min(READ_CHUNK);
                    bytes += n;
                    self.on_bytes(n);
                }
                Err(e) => match e.kind() {
                    LineErrorKind::Overrun => bump(&mut self.status.uart_overruns),
                    _ => bump(&mut self.status.framing_errors),
                },
            }
        }
        let now = self.clock.now_ms();
        if self.status_period_ms != 0
            && now.wrapping_sub(self.last_status_ms) >= self.status_period_ms
        {
            self.send_status();
        }
        NodePoll {
            bytes: bytes as u32,
            frames_sent: self.status.frames_sent.wrapping_sub(sent_before),
            status_sent: self.status_frames != status_before,
        }
    }

    /// The first `n` bytes of the receive buffer, through the frame decoder.
    fn on_bytes(&mut self, n: usize) {
        let mut pos = 0;
        while pos < n {
            let (run, oversize) = self
                .decoder
                .push_run(self.rx.get(pos..n).unwrap_or_default());
            if let Some(error) = oversize {
                self.status.count_decode_error(&error);
            }
            pos += run;
            if pos >= n {
                break;
            }
            pos += 1;
            match self.decoder.end_frame() {
                None => {}
                Some(Ok(message)) => match decode_node_message(message) {
                    Ok(NodeMessage::RawImuSample(sample)) => self.on_sample(&sample),
                    Ok(NodeMessage::RawImuConfig(config)) => self.on_config(&config),
                    Ok(NodeMessage::NotTaken(_)) => bump(&mut self.status.malformed),
                    Err(error) => self.status.count_decode_error(&error),
                },
                Some(Err(error)) => self.status.count_decode_error(&error),
            }
        }
    }

    fn on_sample(&mut self, sample: &RawImuSample) {
        bump(&mut self.status.packets_accepted);
        if let RawOutcome::Fused(Some(q)) = self.input.push(sample) {
            let packet = orientation_packet(sample, q);
            if let Ok(frame) = encode_segment_orientation_frame(&packet, &mut self.tx) {
                write_frame(&mut self.serial, &mut self.status, frame);
                bump(&mut self.status.samples_completed);
            }
        }
    }

    fn on_config(&mut self, config: &RawImuConfig) {
        if !self.input.configure(config) {
            bump(&mut self.status.config_rejected);
        }
        if config.request_status {
            self.send_status();
        }
    }

    /// The counters, with the current uptime.
    pub fn status(&self) -> Status {
        Status {
            uptime_ms: self.clock.now_ms().wrapping_sub(self.started_ms),
            ..self.status
        }
    }

    /// The raw input: its settings and counters.
    pub fn input(&self) -> &RawInput<f32, NODE_SEGMENTS> {
        &self.input
    }

    /// The serial port, e.g. to inspect a test double.
    pub fn serial_mut(&mut self) -> &mut S {
        &mut self.serial
    }

    /// A `Status` (counting itself in `frames_sent`), then the raw input's `RawImuStatus`.
    fn send_status(&mut self) {
        self.last_status_ms = self.clock.now_ms();
        let mut status = self.status();
        status.frames_sent = status.frames_sent.wrapping_add(1);
        if let Ok(frame) = encode_status_frame(&status, &mut self.tx) {
            write_frame(&mut self.serial, &mut self.status, frame);
        }
        if let Ok(frame) = encode_raw_imu_status_frame(&self.input.status(), &mut self.tx) {
            write_frame(&mut self.serial, &mut self.status, frame);
        }
        self.status_frames = self.status_frames.wrapping_add(1);
    }
}

/// Writes all of `frame` (a port that takes nothing ends the attempt) and counts it.
fn write_frame<S: Write>(serial: &mut S, status: &mut Status, mut frame: &[u8]) {
    while !frame.is_empty() {
        match serial.write(frame) {
            Ok(n) if n > 0 => frame = frame.get(n..).unwrap_or_default(),
            _ => return,
        }
    }
    bump(&mut status.frames_sent);
}
