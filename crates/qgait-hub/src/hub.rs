//! The [`Hub`]: serial bytes in, decoded packets, sample assembly, poses and status out.

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use qgait_kernel::{Gait2392Geometry, Limb};
use qgait_proto::{
    decode_hub_message, decode_packet, Config, DecodeError, FrameDecoder, HubMessage, ImuConfig,
    JointAngle, MissingPolicy, ModelId, Status, SubjectConfig, VelocityConfig, MAX_FRAME_LEN,
    MAX_REORDER_WINDOW,
};

use crate::assembly::Assembler;
use crate::clock::Clock;
use crate::counters::{bump, count_outcome};
use crate::limits::in_range;
#[cfg(feature = "raw")]
use crate::line::write_frame;
use crate::line::{self, Line, LineDevice, PollSummary, SerialPort, StatusSchedule};
#[cfg(feature = "imu")]
use crate::orientation::ImuInput;
use crate::output::Output;
#[cfg(feature = "raw")]
use crate::raw::{orientation_packet, RawInput, RawOutcome};
use crate::velocity::Differentiator;
use crate::SubjectParts;
use crate::{ConfigError, Kinematics};
#[cfg(feature = "raw")]
use qgait_proto::{
    decode_node_message, encode_raw_imu_status_frame, NodeMessage, RawImuConfig, RawImuSample,
    RAW_IMU_CONFIG_TAG, RAW_IMU_SAMPLE_TAG,
};
#[cfg(feature = "chain")]
use qgait_proto::{ChainTable, ChainTableConfig};
#[cfg(feature = "imu")]
use {crate::assembly::SegmentAssembler, qgait_proto::WireByte};

/// Bytes read by one [`Hub::poll`] at most, so periodic work is never starved by a busy line.
pub const MAX_BYTES_PER_POLL: usize = 256;

/// Bytes the hub asks the serial port for in one read (its receive buffer, in the hub).
pub const READ_CHUNK: usize = 128;

/// The raw segments a hub fuses at most: every segment (protocol.md 4.7's eight).
#[cfg(feature = "raw")]
pub const RAW_SEGMENTS: usize = 8;

/// Default reorder window (samples).
pub const DEFAULT_WINDOW: u8 = 4;

/// Default period of unsolicited [`Status`] frames (milliseconds).
pub const DEFAULT_STATUS_PERIOD_MS: u32 = 1000;

/// The configuration the hub starts with: PHAK, gait2392 anthropometry (`None`), drop
/// incomplete samples, a window of [`DEFAULT_WINDOW`].
pub const DEFAULT_CONFIG: Config = Config {
    model: ModelId::Phak,
    anthropometry: None,
    missing_policy: MissingPolicy::Drop,
    reorder_window: DEFAULT_WINDOW,
    request_status: false,
};

// `Hub::init` builds the default model as a PHAK chain.
const _: () = assert!(matches!(DEFAULT_CONFIG.model, ModelId::Phak));

/// The sample assembly of the input in force: joint angles, or segment orientations (one or
/// the other, in the same memory).
#[derive(Debug, Clone)]
// One lives in the hub for its whole life; the variants are about the same size.
#[allow(clippy::large_enum_variant)]
enum Input {
    /// [`JointAngle`] packets.
    Joints(Assembler),
    /// [`SegmentOrientation`] packets (the orientation modes of [`ImuConfig`]).
    #[cfg(feature = "imu")]
    Segments(SegmentAssembler),
}

/// The hub application, generic over its serial port and clock.
///
/// The serial port is an `embedded-io` one: the hub reads what it has in blocks of up to
/// [`READ_CHUNK`] bytes (`ReadReady::read_ready` first, so a read never blocks) and writes each
/// frame in one `write` call (or as many as the port needs). Its errors classify themselves
/// as `embedded-hal-nb` serial errors do: an overrun is counted as such, any other line error
/// as a framing error.
///
/// Feed it by calling [`poll`](Hub::poll) in the main loop. It never panics and never blocks
/// on input: every malformed byte, frame or packet is counted in [`Status`] and decoding
/// resumes at the next frame delimiter. It does block while writing a frame, as a UART
/// always drains.
pub struct Hub<S, C> {
    /// The serial port, clock, frame decoder, counters, status schedule, receive buffer.
    line: Line<S, C, READ_CHUNK>,
    config: Config,
    /// The upload of the subject model in force, if the model is a subject's gait2392.
    subject: Option<u8>,
    /// The [`SubjectParts::generation`] the subject model in force was built from.
    subject_generation: u32,
    subject_parts: SubjectParts,
    kinematics: Kinematics,
    input: Input,
    /// The IMU settings, calibration and solver (kept whatever the input in force).
    #[cfg(feature = "imu")]
    imu: ImuInput,
    /// The points' velocities: their setting and the last sample posed.
    velocity: Differentiator,
    /// The raw input: one kernel VQF per raw segment, whose orientations enter the
    /// orientation input as `SegmentOrientation`s would.
    #[cfg(feature = "raw")]
    raw: RawInput<f32, RAW_SEGMENTS>,
    tx: [u8; MAX_FRAME_LEN],
}

impl<S: SerialPort, C: Clock> Hub<S, C> {
    /// A hub with [`DEFAULT_CONFIG`] sending a status frame every `status_period_ms`
    /// (0 disables the periodic status).
    ///
    /// Fails only if the kernel refuses the default model, which its tests rule out.
    pub fn new(serial: S, clock: C, status_period_ms: u32) -> Result<Self, ConfigError> {
        let kinematics = Kinematics::new(DEFAULT_CONFIG.model, DEFAULT_CONFIG.anthropometry)?;
        Ok(Self::with_kinematics(
            serial,
            clock,
            status_period_ms,
            kinematics,
        ))
    }

    /// The same hub as [`new`](Self::new), built in `slot` (e.g. a static): neither the hub (4 KB
    /// on a Cortex-M) nor its model's chain is ever a temporary on the stack on its way there.
    /// Each field is written where it lives, the model as an empty one (a memset), which is
    /// then built in place.
    pub fn init(
        slot: &mut MaybeUninit<Self>,
        serial: S,
        clock: C,
        status_period_ms: u32,
    ) -> Result<&mut Self, ConfigError> {
        let anthropometry = Kinematics::anthropometry(DEFAULT_CONFIG.anthropometry)?;
        let now = clock.now_ms();
        let config = DEFAULT_CONFIG;
        let hub = slot.as_mut_ptr();
        // SAFETY: `hub` points to memory valid for a `Hub` (the slot). Each field is written
        // once through a pointer to it, never read and never referenced before; `assume_init`
        // comes after the last field is written. `every_field_is_written` below names every
        // field of `Hub` without `..`, so adding a field without writing it here does not
        // compile.
        #[allow(unsafe_code)]
        let hub = unsafe {
            addr_of_mut!((*hub).line.serial).write(serial);
            addr_of_mut!((*hub).line.clock).write(clock);
            addr_of_mut!((*hub).line.decoder).write(FrameDecoder::new());
            addr_of_mut!((*hub).line.status).write(Status::default());
            addr_of_mut!((*hub).line.schedule).write(StatusSchedule::new(now, status_period_ms));
            addr_of_mut!((*hub).line.rx).write([0; READ_CHUNK]);
            addr_of_mut!((*hub).config).write(config);
            addr_of_mut!((*hub).subject).write(None);
            addr_of_mut!((*hub).subject_generation).write(0);
            addr_of_mut!((*hub).subject_parts).write(SubjectParts::new());
            addr_of_mut!((*hub).kinematics).write(Kinematics::EMPTY);
            addr_of_mut!((*hub).input).write(Input::Joints(assembler_for(&config)));
            #[cfg(feature = "imu")]
            addr_of_mut!((*hub).imu).write(ImuInput::new());
            addr_of_mut!((*hub).velocity).write(Differentiator::OFF);
            #[cfg(feature = "raw")]
            RawInput::write_new(addr_of_mut!((*hub).raw));
            addr_of_mut!((*hub).tx).write([0; MAX_FRAME_LEN]);
            slot.assume_init_mut()
        };
        hub.kinematics.set_phak(config.model, &anthropometry)?;
        Ok(hub)
    }

    /// The fields [`init`](Self::init) writes, named without `..`: a field added to `Hub` must
    /// be added here, which is the reminder to write it in `init`.
    #[allow(dead_code)]
    fn every_field_is_written(self) {
        let Hub {
            line:
                Line {
                    serial: _,
                    clock: _,
                    decoder: _,
                    status: _,
                    schedule: _,
                    rx: _,
                },
            config: _,
            subject: _,
            subject_generation: _,
            subject_parts: _,
            kinematics: _,
            input: _,
            #[cfg(feature = "imu")]
                imu: _,
            velocity: _,
            #[cfg(feature = "raw")]
                raw: _,
            tx: _,
        } = self;
    }

    #[inline(always)]
    fn with_kinematics(serial: S, clock: C, status_period_ms: u32, kinematics: Kinematics) -> Self {
        let config = DEFAULT_CONFIG;
        Hub {
            line: Line::new(serial, clock, status_period_ms),
            kinematics,
            input: Input::Joints(assembler_for(&config)),
            #[cfg(feature = "imu")]
            imu: ImuInput::new(),
            #[cfg(feature = "raw")]
            raw: RawInput::new(),
            config,
            subject: None,
            subject_generation: 0,
            subject_parts: SubjectParts::new(),
            velocity: Differentiator::OFF,
            tx: [0; MAX_FRAME_LEN],
        }
    }

    /// Reads what the serial port has (at most [`MAX_BYTES_PER_POLL`] bytes), handles it, and
    /// sends a periodic status frame when due.
    pub fn poll(&mut self) -> PollSummary {
        line::poll(self, MAX_BYTES_PER_POLL)
    }

    /// Handles the first `n` bytes of the receive buffer: runs of data bytes straight into the
    /// decoder's buffer, and at each 0x00 the frame they make. A frame may span reads: the
    /// decoder keeps its part until the next.
    #[inline(always)]
    fn on_bytes(&mut self, n: usize) {
        let mut pos = 0;
        while let Some(frame) = self.line.next_frame(&mut pos, n) {
            let Some(message) = frame else {
                continue;
            };
            // Joint-angle packets, one per frame on a busy line, decoded straight from the
            // decoder's buffer; anything else through the general decoder, out of line.
            match decode_packet(message) {
                Some(Ok(packet)) => self.on_packet(&packet),
                Some(Err(error)) => self.line.status.count_decode_error(&error),
                None => {
                    let decoded = decode_hub_message(message);
                    // The raw IMU messages, which the hub's decoder leaves undecoded: the
                    // node's decoder decodes them.
                    #[cfg(feature = "raw")]
                    if let Ok(HubMessage::NotTaken(RAW_IMU_SAMPLE_TAG | RAW_IMU_CONFIG_TAG)) =
                        decoded
                    {
                        let raw = decode_node_message(message);
                        self.on_raw(raw);
                        continue;
                    }
                    self.on_message(decoded)
                }
            }
        }
    }

    /// The counters, with the current uptime.
    pub fn status(&self) -> Status {
        self.line.status()
    }

    /// The configuration in force (its `request_status` is always `false`). With a subject
    /// model its model is gait2392 and [`subject`](Self::subject) says which. Its
    /// `anthropometry` is the HAK and PHAK segment lengths the hub keeps (`None`: gait2392's),
    /// also while gait2392 is in force: a `Config` without lengths keeps them.
    pub fn config(&self) -> Config {
        self.config
    }

    /// The upload of the subject gait2392 model in force, `None` with a built-in model.
    pub fn subject(&self) -> Option<u8> {
        self.subject
    }

    /// The subject-model parts held (see [`SubjectParts`]).
    pub fn subject_parts(&self) -> &SubjectParts {
        &self.subject_parts
    }

    /// The IMU input's configuration in force (its `calibrate` and `request_status` always
    /// `false`): the joint-angle input's ([`ImuConfig`] mode 0) in a hub built without it.
    pub fn imu_config(&self) -> ImuConfig {
        #[cfg(feature = "imu")]
        return self.imu.config();
        #[cfg(not(feature = "imu"))]
        return crate::orientation::DEFAULT_IMU_CONFIG;
    }

    /// The IMU input's state: its calibration and whether a calibration pose is awaited.
    #[cfg(feature = "imu")]
    pub fn imu(&self) -> &ImuInput {
        &self.imu
    }

    /// The raw input: its settings and counters.
    #[cfg(feature = "raw")]
    pub fn raw(&self) -> &RawInput<f32, RAW_SEGMENTS> {
        &self.raw
    }

    /// The serial port, e.g. to inspect a test double.
    pub fn serial_mut(&mut self) -> &mut S {
        &mut self.line.serial
    }

    /// The clock.
    pub fn clock(&self) -> &C {
        &self.line.clock
    }

    /// A frame that is not a joint-angle packet (rare: configuration, or errors).
    #[inline(never)]
    fn on_message(&mut self, message: Result<HubMessage, DecodeError>) {
        match message {
            Ok(message) => self.handle(message),
            Err(error) => self.line.status.count_decode_error(&error),
        }
    }

    fn handle(&mut self, message: HubMessage) {
        match message {
            HubMessage::JointAngle(packet) => self.on_packet(&packet),
            HubMessage::Config(config) => self.on_config(&config),
            HubMessage::SubjectLeg(part) => self.subject_parts.add_leg(&part),
            HubMessage::SubjectKnee(part) => self.subject_parts.add_knee(&part),
            HubMessage::SubjectConfig(config) => self.on_subject_config(&config),
            #[cfg(feature = "imu")]
            HubMessage::SegmentOrientation(packet) => self.on_orientation(&packet),
            HubMessage::ImuConfig(config) => self.on_imu_config(&config),
            HubMessage::VelocityConfig(config) => self.on_velocity_config(&config),
            #[cfg(feature = "chain")]
            HubMessage::ChainTable(part) => self.on_chain_table(&part),
            #[cfg(feature = "chain")]
            HubMessage::ChainTableConfig(config) => self.on_chain_config(&config),
            // Messages this hub does not take: a segment orientation without the orientation
            // input, the chain messages without chain support, the raw IMU sample and
            // configuration (taken by `on_raw` before they get here, with raw input).
            HubMessage::NotTaken(_) => bump(&mut self.line.status.malformed),
            // A pose frame, a status or a raw input's status (well-formed or not: its body is
            // not decoded): only a hub or a raw input sends these, nothing to do with them
            // here.
            HubMessage::FromHub(_) => bump(&mut self.line.status.malformed),
            // A message the protocol crate decodes because another crate of the build turned
            // on its `orientation` or `chain` feature, but this hub's build does not take (its
            // `imu` or `chain` off): not taken, as above. Features add: no feature set of the
            // two crates fails to build.
            #[allow(unreachable_patterns)]
            _ => bump(&mut self.line.status.malformed),
        }
    }

    #[inline(always)]
    fn on_packet(&mut self, packet: &JointAngle) {
        if !packet.usable() {
            bump(&mut self.line.status.out_of_range);
            return;
        }
        bump(&mut self.line.status.packets_accepted);
        // Judged here, once per packet: the assembler carries the judgement to the samples
        // that use this angle (held ones included), so no sample re-checks its angles.
        let out_of_range = !in_range(packet.joint, packet.angle, self.kinematics.knee_flexion());
        if out_of_range {
            bump(&mut self.line.status.out_of_range);
        }
        // The samples the packet completes or pushes out of the window are handled as the
        // assembler reports them (it and the output are disjoint parts of the hub), not
        // collected first: no copies of the events.
        let (input, mut output) = self.split();
        // The orientation input in force: a joint angle is not used, as a joint the model does
        // not use is not.
        #[allow(irrefutable_let_patterns)]
        let Input::Joints(assembler) = input
        else {
            return;
        };
        let outcome = assembler.push(
            packet.seq,
            packet.timestamp_us,
            packet.joint,
            packet.angle,
            out_of_range,
            &mut |e| output.on_sample(e),
        );
        count_outcome(&mut self.line.status, outcome);
    }

    /// A segment orientation: unit-length checked, then placed in its sample, as a joint
    /// angle is (see [`orientation`](crate::orientation)).
    #[cfg(feature = "imu")]
    #[inline(never)]
    fn on_orientation(&mut self, packet: &qgait_proto::SegmentOrientation) {
        if qgait_proto::device_model::packet_quat::<f32>(packet).is_err() {
            bump(&mut self.line.status.orientation_not_unit);
            return;
        }
        bump(&mut self.line.status.packets_accepted);
        let (input, mut output) = self.split();
        // The joint-angle input in force: not used, as a joint the model does not use is not.
        let Input::Segments(assembler) = input else {
            return;
        };
        let outcome = assembler.push_key(
            packet.header.seq,
            packet.header.timestamp_us,
            packet.header.segment.wire_byte(),
            packet.q14,
            false,
            &mut |e| output.on_segment_sample(e),
        );
        count_outcome(&mut self.line.status, outcome);
    }

    /// A raw IMU message (decoded by the node's decoder: a sample or a configuration).
    #[cfg(feature = "raw")]
    #[inline(never)]
    fn on_raw(&mut self, message: Result<NodeMessage, DecodeError>) {
        match message {
            Ok(NodeMessage::RawImuSample(sample)) => self.on_raw_sample(&sample),
            Ok(NodeMessage::RawImuConfig(config)) => self.on_raw_config(&config),
            // Not a raw tag: never, as only those are passed here.
            Ok(NodeMessage::NotTaken(_)) => bump(&mut self.line.status.malformed),
            Err(error) => self.line.status.count_decode_error(&error),
        }
    }

    /// A raw sample, fused by the raw input (protocol.md 4.10, counted there); an orientation
    /// it gives enters the orientation input as the `SegmentOrientation` a smart node would
    /// send for it (the node's [`orientation_packet`]: Q14, same node, segment, `seq`).
    #[cfg(feature = "raw")]
    fn on_raw_sample(&mut self, sample: &RawImuSample) {
        if let RawOutcome::Fused(Some(q)) = self.raw.push(sample) {
            self.on_orientation(&orientation_packet(sample, q));
        }
    }

    /// The raw input's settings: refused ones counted in `config_rejected`.
    #[cfg(feature = "raw")]
    fn on_raw_config(&mut self, config: &RawImuConfig) {
        let result = if self.raw.configure(config) {
            Ok(())
        } else {
            Err(ConfigError::ImuSettings)
        };
        self.after_config(result, config.request_status);
        // In answer to a request, its counters even without raw segments (protocol.md 4.10).
        if config.request_status && self.raw.config().segments == 0 {
            self.send_raw_status();
        }
    }

    /// The raw input's counters, as a `RawImuStatus` frame.
    #[cfg(feature = "raw")]
    fn send_raw_status(&mut self) {
        if let Ok(frame) = encode_raw_imu_status_frame(&self.raw.status(), &mut self.tx) {
            write_frame(&mut self.line.serial, &mut self.line.status, frame);
        }
    }

    /// The input mode and IMU settings.
    #[inline(never)]
    fn on_imu_config(&mut self, config: &ImuConfig) {
        let result = self.apply_imu(config);
        self.after_config(result, config.request_status);
    }

    /// Makes `config` the IMU configuration in force: the orientation input needs the pelvis
    /// and gait2392; a change of input (or of the segments it waits for) closes the samples
    /// open under the old one and starts an empty window.
    #[cfg(feature = "imu")]
    fn apply_imu(&mut self, config: &ImuConfig) -> Result<(), ConfigError> {
        let orientations = config.mode.orientations();
        if !config.sensor_to_opensim.iter().all(|r| r.is_finite()) {
            return Err(ConfigError::ImuSettings);
        }
        if orientations {
            if config.segments & qgait_proto::segment_bit(qgait_proto::SegmentId::Pelvis) == 0 {
                return Err(ConfigError::ImuWithoutPelvis);
            }
            if self.kinematics.gait2392_model().is_none() {
                return Err(ConfigError::ImuNeedsGait2392);
            }
        }
        let old = self.imu.config();
        let new_input = orientations != old.mode.orientations()
            || (orientations && config.segments != old.segments);
        if new_input {
            self.close_open_samples();
        }
        self.imu.set(config);
        if new_input {
            self.restart_input();
        }
        Ok(())
    }

    /// A hub without the orientation input takes only the joint-angle mode (which changes
    /// nothing).
    #[cfg(not(feature = "imu"))]
    fn apply_imu(&mut self, config: &ImuConfig) -> Result<(), ConfigError> {
        if config.mode.orientations() {
            Err(ConfigError::ImuNotBuiltIn)
        } else {
            Ok(())
        }
    }

    // A configuration that changes nothing (e.g. one only asking for a status) is handled
    // here, in a small frame: the frames that build a model (kilobytes of temporaries) are in
    // `switch`, entered only when the configuration changes.
    #[inline(never)]
    fn on_config(&mut self, config: &Config) {
        // A configuration the hub cannot use is counted and ignored; the old one stays.
        let result = if config.model == ModelId::Gait2392 && config.anthropometry.is_some() {
            // gait2392's lengths are those of its model.
            Err(ConfigError::AnthropometryWithGait2392)
        } else if config.model == ModelId::Chain {
            // A chain comes with its `ChainTableConfig`.
            Err(ConfigError::ChainIncomplete { upload: 0 })
        } else {
            // Without lengths, the HAK and PHAK lengths in force stay. gait2392's generic
            // lengths stated in full are the same configuration as none given (`None`), so
            // resending what is in force changes nothing.
            let generic = Limb::<f32>::gait2392().to_array();
            let anthropometry = config
                .anthropometry
                .or(self.config.anthropometry)
                .filter(|legs| *legs != [generic, generic]);
            self.apply(
                Config {
                    anthropometry,
                    request_status: false,
                    ..*config
                },
                None,
            )
        };
        self.after_config(result, config.request_status);
    }

    /// A [`VelocityConfig`]: the points' velocities on or off (protocol.md 4.11).
    #[inline(never)]
    fn on_velocity_config(&mut self, config: &VelocityConfig) {
        let result = self.velocity.configure(config);
        self.after_config(result, config.request_status);
    }

    /// The velocity setting in force.
    pub fn velocity_config(&self) -> VelocityConfig {
        self.velocity.config()
    }

    /// A part of a chain's table: written into the model slot, the model in force stopped
    /// first (its open samples closed under it); counted in `malformed` if it reaches past
    /// the image.
    #[cfg(feature = "chain")]
    #[inline(never)]
    fn on_chain_table(&mut self, part: &ChainTable) {
        if !Kinematics::takes_chain_part(part) {
            bump(&mut self.line.status.malformed);
            return;
        }
        if self.kinematics.computes() {
            self.close_open_samples();
        }
        self.kinematics.write_chain(part);
    }

    /// A `ChainTableConfig`: the table held, checked against it every time (a part rewritten
    /// since takes effect).
    #[cfg(feature = "chain")]
    #[inline(never)]
    fn on_chain_config(&mut self, config: &ChainTableConfig) {
        let new = self.uploaded_model(ModelId::Chain, config.missing_policy, config.reorder_window);
        let result = self.switch_chain(new, config);
        self.after_config(result, config.request_status);
    }

    /// Switches to the table `config` describes, with the settings of `new`: checked first
    /// (nothing changes if it is refused), then, unless this table with these settings is what
    /// is in force, the open samples are closed under what is in force (no pose while a table
    /// is being written) and the table becomes the model.
    #[cfg(feature = "chain")]
    #[inline(always)]
    fn switch_chain(&mut self, new: Config, config: &ChainTableConfig) -> Result<(), ConfigError> {
        if !(1..=MAX_REORDER_WINDOW).contains(&new.reorder_window) {
            return Err(ConfigError::ReorderWindow(new.reorder_window));
        }
        // The orientation input solves gait2392's coordinates only.
        #[cfg(feature = "imu")]
        if self.imu.config().mode.orientations() {
            return Err(ConfigError::ImuNeedsGait2392);
        }
        let checked = self.kinematics.check_chain(config)?;
        // `new` keeps the lengths in force: the model and the settings say whether it changes.
        let c = &self.config;
        if self.kinematics.computes()
            && c.model == new.model
            && c.missing_policy == new.missing_policy
            && c.reorder_window == new.reorder_window
        {
            return Ok(());
        }
        self.close_open_samples();
        self.kinematics.take_chain(checked);
        self.config = new;
        self.restart_input();
        self.subject = None;
        Ok(())
    }

    #[inline(never)]
    fn on_subject_config(&mut self, config: &SubjectConfig) {
        let new = self.uploaded_model(
            ModelId::Gait2392,
            config.missing_policy,
            config.reorder_window,
        );
        let result = self.apply(new, Some(config.upload));
        self.after_config(result, config.request_status);
    }

    /// The configuration of an uploaded `model` (a subject's gait2392, a chain table) with its
    /// own settings: the HAK and PHAK lengths in force are kept for a later HAK or PHAK.
    #[inline(always)]
    fn uploaded_model(
        &self,
        model: ModelId,
        missing_policy: MissingPolicy,
        reorder_window: u8,
    ) -> Config {
        Config {
            model,
            anthropometry: self.config.anthropometry,
            missing_policy,
            reorder_window,
            request_status: false,
        }
    }

    /// Makes `new` with the subject model `subject` the configuration in force, unless it
    /// already is.
    #[inline(always)]
    fn apply(&mut self, new: Config, subject: Option<u8>) -> Result<(), ConfigError> {
        if self.in_force(&new, subject) {
            Ok(())
        } else {
            self.switch(new, subject)
        }
    }

    fn after_config(&mut self, result: Result<(), ConfigError>, request_status: bool) {
        if result.is_err() {
            bump(&mut self.line.status.config_rejected);
        }
        if request_status {
            self.send_status();
        }
    }

    /// Whether `new` with the subject model `subject` is what is in force, a subject model's
    /// parts included (a host may resend a part under the same upload id).
    fn in_force(&self, new: &Config, subject: Option<u8>) -> bool {
        *new == self.config
            && subject == self.subject
            && (subject.is_none() || self.subject_parts.generation() == self.subject_generation)
    }

    /// Switches to `new` with the subject model `subject` (the upload whose parts make the
    /// gait2392 model), or to `new`'s built-in model if `None`. The new model is checked first
    /// (the old one stays if it is refused), then the samples still open are closed under the
    /// old one, then the new one is built in place of the old (see
    /// [`Kinematics::set_phak`]): no chain is ever a temporary on the stack.
    // Never inlined: its frame exists only while switching.
    #[inline(never)]
    fn switch(&mut self, new: Config, subject: Option<u8>) -> Result<(), ConfigError> {
        if !(1..=MAX_REORDER_WINDOW).contains(&new.reorder_window) {
            return Err(ConfigError::ReorderWindow(new.reorder_window));
        }
        #[cfg(feature = "imu")]
        if self.imu.config().mode.orientations() && new.model != ModelId::Gait2392 {
            return Err(ConfigError::ImuNeedsGait2392);
        }
        if new.model == ModelId::Chain {
            // A chain comes with its `ChainTableConfig`, never by a `Config`.
            return Err(ConfigError::ChainIncomplete { upload: 0 });
        }
        if subject.is_none() && new.model != ModelId::Gait2392 {
            let anthropometry = Kinematics::anthropometry(new.anthropometry)?;
            self.close_open_samples();
            self.kinematics.set_phak(new.model, &anthropometry)?;
        } else {
            self.switch_gait2392(subject)?;
        }
        self.config = new;
        self.restart_input();
        self.subject = subject;
        self.subject_generation = self.subject_parts.generation();
        Ok(())
    }

    /// An empty window for the input and configuration in force, and no velocity across the
    /// change.
    fn restart_input(&mut self) {
        #[cfg(feature = "imu")]
        set_input(&mut self.input, &self.config, &self.imu);
        #[cfg(not(feature = "imu"))]
        set_input(&mut self.input, &self.config);
        self.velocity.reset();
    }

    /// The model part of [`switch`](Self::switch) for gait2392, generic or a subject's.
    #[inline(never)]
    fn switch_gait2392(&mut self, subject: Option<u8>) -> Result<(), ConfigError> {
        Kinematics::check_gait2392(gait2392_geometry(&self.subject_parts, subject)?)?;
        self.close_open_samples();
        // Asked again (the samples closed borrowed the hub): the same reference.
        let geometry = gait2392_geometry(&self.subject_parts, subject)?;
        self.kinematics.set_gait2392(geometry)
    }

    /// Closes (and counts, and sends) the samples open under the configuration in force.
    #[inline(never)]
    fn close_open_samples(&mut self) {
        // As in `on_packet`: the samples are handled as the assembler reports them.
        let (input, mut output) = self.split();
        match input {
            Input::Joints(assembler) => assembler.flush(&mut |e| output.on_sample(e)),
            #[cfg(feature = "imu")]
            Input::Segments(assembler) => assembler.flush(&mut |e| output.on_segment_sample(e)),
        }
    }

    /// The hub borrowed apart: the input, whose assembler reports the samples, and the parts
    /// that turn them into frames.
    #[inline(always)]
    fn split(&mut self) -> (&mut Input, Output<'_, S>) {
        let output = Output {
            kinematics: &self.kinematics,
            status: &mut self.line.status,
            serial: &mut self.line.serial,
            tx: &mut self.tx,
            velocity: &mut self.velocity,
            #[cfg(feature = "imu")]
            imu: &mut self.imu,
        };
        (&mut self.input, output)
    }

    fn send_status(&mut self) {
        // A status fits MAX_FRAME_LEN.
        self.line.send_status(&mut self.tx);
        // Then the raw input's counters, while it has raw segments (protocol.md 4.10).
        #[cfg(feature = "raw")]
        if self.raw.config().segments != 0 {
            self.send_raw_status();
        }
    }
}

impl<S: SerialPort, C: Clock> LineDevice<S, C, READ_CHUNK> for Hub<S, C> {
    #[inline(always)]
    fn line(&mut self) -> &mut Line<S, C, READ_CHUNK> {
        &mut self.line
    }

    #[inline(always)]
    fn on_bytes(&mut self, n: usize) {
        Hub::on_bytes(self, n)
    }

    fn send_status(&mut self) {
        Hub::send_status(self)
    }
}

/// The gait2392 numbers asked for: the generic model's, or by reference the subject's upload
/// `subject`, where its parts were written.
fn gait2392_geometry(
    parts: &SubjectParts,
    subject: Option<u8>,
) -> Result<&Gait2392Geometry<f32>, ConfigError> {
    match subject {
        None => Ok(Kinematics::generic_gait2392()),
        Some(upload) => parts.geometry(upload),
    }
}

/// The empty window of the input in force, in a frame of its own (not the model switch's).
#[cfg(feature = "imu")]
#[inline(never)]
fn set_input(input: &mut Input, config: &Config, imu: &ImuInput) {
    *input = if imu.config().mode.orientations() {
        Input::Segments(SegmentAssembler::with_keys(
            imu.required(),
            config.reorder_window,
            config.missing_policy == MissingPolicy::HoldLast,
        ))
    } else {
        Input::Joints(assembler_for(config))
    };
}

/// The empty window of the joint-angle input, in a frame of its own (not the model switch's).
#[cfg(not(feature = "imu"))]
#[inline(never)]
fn set_input(input: &mut Input, config: &Config) {
    *input = Input::Joints(assembler_for(config));
}

fn assembler_for(config: &Config) -> Assembler {
    Assembler::new(
        config.model.required_joints(),
        config.reorder_window,
        config.missing_policy == MissingPolicy::HoldLast,
    )
}
