//! The device commands: `qgait packets`, `decode`, `verify` and `emulate` (crate `qgait_device`).

use std::collections::{BTreeSet, HashMap};
use std::fs::File;
use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use qgait_emulate::faults::Arrivals;
use qgait_emulate::firmware;
use qgait_emulate::qemu::Echo;
use qgait_emulate::session::{self, closing_frames, InputCounts, Limits};
use qgait_proto::{FrameDecoder, Message, MissingPolicy, ModelId, PoseModels};

use crate::cli::config::hub_model;
use crate::cli::diagnostics::Diagnostics;
use crate::cli::jsonl;
use crate::cli::live::LiveView;
use crate::cli::model_args::ModelArgs;
use qgait_device::config::{frames, messages, HubModel, HubSettings};
use qgait_device::frames_csv;
use qgait_device::log::{HubLog, LogDecoder, Record};
use qgait_device::orientations::{OrientationCheck, OrientationStream};
use qgait_device::packets::{PacketsError, Samples, Timing};
use qgait_device::port::{self, Input, Until};
use qgait_device::verify::{Expected, Verification, Verifier, MISSING_LISTED};
use qgait_model::motion::source::load_motion;

/// The model, loaded: what to send the hub ([`HubModel`]), and how to recompute its frames.
struct LoadedModel {
    hub: HubModel,
    device: PoseModels<f64>,
}

impl LoadedModel {
    fn load(args: &ModelArgs, quiet: bool) -> anyhow::Result<LoadedModel> {
        let model = args.load(&Diagnostics::new(quiet))?;
        let name = model.name().to_string();
        let hub = hub_model(model, None)?;
        let device = hub
            .pose_models()
            .map_err(|e| anyhow::anyhow!("{name}: model rejected by the kernel: {e}"))?;
        Ok(LoadedModel { hub, device })
    }
}

/// The IMU orientation input's options of `qgait packets` and `verify` (`qgait imu`'s, with
/// its defaults: OpenSense's).
#[derive(Debug, Args, Clone)]
pub struct OrientationArgs {
    /// An IMU recording (OpenSim orientation .sto) instead of a motion: the segment nodes'
    /// stream (gait2392 and the IMU configuration, the calibration pose as sample 0, the rows
    /// as samples 1, 2, ...), for a hub built with the orientation input.
    #[arg(long, value_name = "ORIENTATIONS.sto", requires = "calibration")]
    pub orientations: Option<PathBuf>,
    /// The static calibration pose of --orientations (its first row).
    #[arg(long, value_name = "STATIC.sto", requires = "orientations")]
    pub calibration: Option<PathBuf>,
    /// Calibration, heading and the hub's solver, as `qgait imu`'s.
    #[command(flatten)]
    pub settings: crate::cli::imu::ImuSettingsArgs,
    /// Only the first N rows of --orientations.
    #[arg(long, value_name = "N")]
    pub rows: Option<usize>,
}

impl OrientationArgs {
    /// The stream of --orientations and --calibration, if given.
    fn stream(&self, quiet: bool) -> anyhow::Result<Option<OrientationStream>> {
        let (Some(orientations), Some(calibration)) = (&self.orientations, &self.calibration)
        else {
            return Ok(None);
        };
        let settings = self.settings.settings()?;
        let mode = self.settings.mode();
        let (stream, warnings) =
            OrientationStream::read(orientations, calibration, &settings, mode, self.rows)?;
        Diagnostics::new(quiet).warn(warnings);
        Ok(Some(stream))
    }
}

/// `qgait packets` arguments.
#[derive(Debug, Args)]
pub struct PacketsArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    #[arg(
        required_unless_present = "orientations",
        conflicts_with = "orientations"
    )]
    pub motion: Option<String>,
    /// Samples per second of MOTION (default: its time column; an orientation recording has
    /// its own times).
    #[arg(long, value_name = "HZ", conflicts_with = "orientations")]
    pub rate: Option<f64>,
    /// Model whose joints are sent (one packet per joint per row).
    #[arg(long, value_enum, default_value = "phak")]
    pub model: WireModel,
    /// Output file (the byte stream, as the nodes send it).
    #[arg(short, long, value_name = "STREAM.bin")]
    pub output: PathBuf,
    /// The IMU orientation input instead of a motion.
    #[command(flatten)]
    pub imu: OrientationArgs,
}

/// A model id on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum WireModel {
    /// 6 joints: hip flexion, knee, ankle of both legs.
    Hak,
    /// 8 joints: HAK plus pelvis rotation and list.
    Phak,
    /// All 17 gait2392 coordinates.
    Gait2392,
}

impl From<WireModel> for ModelId {
    fn from(m: WireModel) -> ModelId {
        match m {
            WireModel::Hak => ModelId::Hak,
            WireModel::Phak => ModelId::Phak,
            WireModel::Gait2392 => ModelId::Gait2392,
        }
    }
}

/// `qgait decode` arguments.
#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// Hub log: a file, `-` for standard input, or a serial port (e.g. /dev/ttyACM0), opened
    /// raw 8N1 at --baud.
    pub log: String,
    /// Output format on standard output.
    #[arg(long, value_enum, default_value = "csv")]
    pub format: Format,
    /// Reading a live hub: baud rate, when to stop, live view.
    #[command(flatten)]
    pub port: PortArgs,
}

/// How a hub log is read when it arrives live (on a serial port); the limits apply to files
/// too. Ctrl-C also stops a reading, with everything decoded so far written out whole.
#[derive(Debug, Args, Clone)]
pub struct PortArgs {
    /// Baud rate of a serial port (LOG a terminal device) [default: 115200, the hub's].
    #[arg(long, value_name = "RATE")]
    pub baud: Option<u32>,
    /// Stop after N pose frames.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Stop after S seconds.
    #[arg(long, value_name = "S", value_parser = positive_seconds)]
    pub seconds: Option<f64>,
    /// Stop when no pose frame has come for S seconds (once one has).
    #[arg(long, value_name = "S", value_parser = positive_seconds)]
    pub idle: Option<f64>,
    /// Live view of the hub's status counters on stderr while frames arrive: `auto` (when
    /// LOG is a serial port and stderr a terminal that the rows do not go to), `on` (one
    /// `status:` line per status when stderr is not such a terminal), `off`.
    #[arg(long, value_enum, default_value = "auto")]
    pub live: Live,
}

/// `--live`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Live {
    /// When the log is a serial port and stderr a terminal.
    Auto,
    /// Always.
    On,
    /// Never.
    Off,
}

/// A warning when `log` ends with `unterminated` bytes of a frame cut off.
fn warn_cut_off(log: &str, unterminated: usize) {
    if unterminated > 0 {
        eprintln!(
            "warning: {log}: the log ends inside a frame ({unterminated} bytes without a delimiter): that frame is lost"
        );
    }
}

/// What a damaged frame the decoder reported at byte `offset` is, for a message.
fn damage_message(offset: u64, error: &qgait_proto::DecodeError) -> String {
    match error {
        qgait_proto::DecodeError::Oversize => format!(
            "a frame longer than {} bytes, at byte {offset}: skipped to the next delimiter",
            qgait_proto::MAX_FRAME_LEN - 1
        ),
        _ => format!("damaged frame ending at byte {offset}: {error} (skipped)"),
    }
}

fn micrometres(s: &str) -> Result<f64, String> {
    crate::cli::amount(s, 0.0, true)
        .ok_or_else(|| format!("`{s}` is not a tolerance in micrometres (a number, 0 or more)"))
}

fn positive_seconds(s: &str) -> Result<f64, String> {
    crate::cli::amount(s, 0.0, false)
        .ok_or_else(|| format!("`{s}` is not a positive number of seconds"))
}

impl PortArgs {
    fn until(&self) -> Until {
        Until {
            frames: self.frames,
            time: self.seconds.map(Duration::from_secs_f64),
            idle: self.idle.map(Duration::from_secs_f64),
        }
    }

    /// Opens `log` (warning when --baud does not apply), installs the Ctrl-C handler, and
    /// makes the live view (`lines` when it should be status lines by default; `rows` when
    /// standard output gets rows as they come, which a view redrawn on the same terminal would
    /// garble).
    fn open(
        &self,
        log: &str,
        lines: bool,
        rows: bool,
        quiet: bool,
    ) -> anyhow::Result<(Input, LiveView)> {
        let (input, warning) = Input::open(log, self.baud)?;
        Diagnostics::new(quiet).warn(warning);
        port::interrupt::install();
        let terminal = io::stderr().is_terminal() && !(rows && io::stdout().is_terminal());
        let live = match self.live {
            Live::Off => false,
            Live::On => true,
            Live::Auto => input.is_serial() && !quiet,
        };
        let view = if live && terminal {
            LiveView::redrawn()
        } else if (live && self.live == Live::On) || lines {
            LiveView::lines()
        } else {
            LiveView::hidden()
        };
        Ok((input, view))
    }
}

/// `qgait decode --format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// One row per pose frame: seq, time (empty), the `fk` columns.
    Csv,
    /// One JSON object per frame (pose, status, other) and per damaged frame.
    Jsonl,
}

/// `qgait verify` arguments.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Hub log (what the hub sent): a file, `-` for standard input, or a serial port.
    pub log: String,
    /// Largest accepted error per point (micrometres).
    #[arg(long, default_value_t = 10.0, value_name = "UM", value_parser = micrometres)]
    pub tol_um: f64,
    /// The model and lengths the hub was configured with.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Reading a live hub: baud rate, when to stop, live view.
    #[command(flatten)]
    pub port: PortArgs,
    /// The IMU recording the hub was sent (as `qgait packets --orientations`): its frames are
    /// also checked against the host's f64 IMU path on the same stream (the rows the hub sent
    /// frames for, so a damaged link's lost samples are skipped on both sides; held frames are
    /// not compared).
    #[command(flatten)]
    pub imu: OrientationArgs,
}

/// `qgait emulate` arguments.
#[derive(Debug, Args)]
pub struct EmulateArgs {
    /// Motion file (.mot/.sto) or `builtin:...` to stream (its packets as `qgait packets`
    /// makes them).
    #[arg(required_unless_present = "stream", conflicts_with = "stream")]
    pub motion: Option<String>,
    /// A byte stream to send as it is (e.g. from `qgait packets`).
    #[arg(long, value_name = "STREAM.bin")]
    pub stream: Option<PathBuf>,
    /// Firmware ELF (default: the release build of firmware/, built if missing).
    #[arg(long, value_name = "PATH")]
    pub elf: Option<PathBuf>,
    /// Samples per second for MOTION (default: its time column).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// The hub's configuration, sent before the stream.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Samples the hub waits for late packets: 1 to 8 (a hub rejects another).
    #[arg(long, default_value_t = 4, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=8))]
    pub window: u8,
    /// Write the frames (the `fk` columns plus `seq`) to this CSV.
    #[arg(long, value_name = "OUT.csv")]
    pub frames_csv: Option<PathBuf>,
    /// Write everything the hub sent (its UART output) to this file.
    #[arg(long, value_name = "LOG.bin")]
    pub log: Option<PathBuf>,
    /// Check every frame against the f64 kernel and that no sample is missing (with --stream:
    /// a frame for exactly the samples whose packets all arrived intact).
    #[arg(long)]
    pub verify: bool,
    /// Tolerance of --verify (micrometres).
    #[arg(long, default_value_t = 10.0, value_name = "UM", value_parser = micrometres)]
    pub tol_um: f64,
}

/// Runs `qgait packets`: each row's packets are written before the next row is read.
pub fn run_packets(args: PacketsArgs, quiet: bool) -> anyhow::Result<()> {
    if let Some(stream) = args.imu.stream(quiet)? {
        return write_orientation_stream(&args, &stream, quiet);
    }
    let Some(motion) = &args.motion else {
        bail!("give either MOTION or --orientations ORIENTATIONS.sto --calibration STATIC.sto");
    };
    crate::cli::refuse_overwrite([args.output.as_path()], &[motion])?;
    let diagnostics = Diagnostics::new(quiet);
    let warn = |w| diagnostics.warn(w);
    let (rows, w) = qgait_model::motion::source::MotionRows::open(motion)?;
    warn(w);
    let timing = args.rate.map_or(Timing::TimeColumn, Timing::Rate);
    let mut file = crate::cli::OutputFile::create(&args.output)?;
    let (counts, w) =
        qgait_device::packets::write_stream(rows, args.model.into(), timing, &warn, file.writer())
            .map_err(|e| match e {
                PacketsError::Write(io) => crate::cli::with_path(io.into(), &args.output),
                other => other.into(),
            })?;
    file.commit()?;
    warn(w);
    if !quiet {
        eprintln!(
            "wrote {} packets ({} samples × {} joints), {} bytes, to {}",
            counts.packets,
            counts.samples,
            ModelId::from(args.model).required_joints().len(),
            counts.bytes,
            args.output.display()
        );
    }
    Ok(())
}

/// `qgait packets --orientations`: the nodes' stream of an IMU recording.
fn write_orientation_stream(
    args: &PacketsArgs,
    stream: &OrientationStream,
    quiet: bool,
) -> anyhow::Result<()> {
    let inputs: Vec<String> = [&args.imu.orientations, &args.imu.calibration]
        .into_iter()
        .flatten()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    crate::cli::refuse_overwrite([args.output.as_path()], &inputs)?;
    let bytes = stream.bytes(4);
    let mut file = crate::cli::OutputFile::create(&args.output)?;
    file.writer()
        .write_all(&bytes)
        .map_err(|e| crate::cli::with_path(e.into(), &args.output))?;
    file.commit()?;
    if !quiet {
        eprintln!(
            "wrote the configuration (gait2392, {:?}), the calibration pose and {} samples of {} segments, {} bytes, to {}",
            stream.imu.mode,
            stream.rows.len(),
            stream.imu.segments.count_ones(),
            bytes.len(),
            args.output.display()
        );
    }
    Ok(())
}

/// Runs `qgait decode`, the output on standard output.
pub fn run_decode(args: DecodeArgs, quiet: bool) -> anyhow::Result<()> {
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    decode_to(&args, &mut out, quiet)
}

/// Where `qgait decode` writes: frame rows of a frames CSV, or JSON lines.
enum DecodeOut<'a> {
    Csv(Box<frames_csv::FramesCsv<&'a mut dyn Write>>),
    Jsonl(&'a mut dyn Write),
}

impl<'a> DecodeOut<'a> {
    /// Starts the output (the CSV's header).
    fn new(format: Format, out: &'a mut dyn Write) -> io::Result<Self> {
        Ok(match format {
            Format::Csv => DecodeOut::Csv(Box::new(frames_csv::FramesCsv::new(out)?)),
            Format::Jsonl => DecodeOut::Jsonl(out),
        })
    }

    /// Writes what `record` gives in this format; whether it gave anything.
    fn record(&mut self, record: &Record) -> io::Result<bool> {
        match self {
            DecodeOut::Csv(csv) => match record {
                Record::Message {
                    message: Message::PoseFrame(p),
                    ..
                } => csv.row(p, None).map(|()| true),
                _ => Ok(false),
            },
            DecodeOut::Jsonl(out) => writeln!(out, "{}", jsonl_line(record)).map(|()| true),
        }
    }

    /// Passes everything written on and flushes the writer.
    fn flush(&mut self) -> io::Result<()> {
        match self {
            DecodeOut::Csv(csv) => csv.flush(),
            DecodeOut::Jsonl(out) => out.flush(),
        }
    }
}

/// The JSON line of `qgait decode` for `record`.
fn jsonl_line(record: &Record) -> String {
    match record {
        Record::Message {
            message: Message::PoseFrame(p),
            ..
        } => jsonl::pose(p),
        Record::Message {
            message: Message::Status(s),
            ..
        } => jsonl::status(s),
        Record::Message { message, .. } => jsonl::other(message.tag()),
        Record::Damaged { offset, error } => jsonl::damaged(*offset, error),
    }
}

/// `qgait decode` writing to `out` (flushed after each chunk read from a serial port, so rows
/// come out as frames arrive). Memory is independent of the log's length.
pub fn decode_to(args: &DecodeArgs, out: &mut dyn Write, quiet: bool) -> anyhow::Result<()> {
    // The `status:` lines of the CSV format are the live view's lines.
    let (mut input, mut view) =
        args.port
            .open(&args.log, args.format == Format::Csv && !quiet, true, quiet)?;
    let mut out = DecodeOut::new(args.format, out)?;
    let live = input.is_serial();
    let mut decoder = LogDecoder::new();
    let mut reported = 0u32;
    let mut write_error = None;
    let mut pending = false;
    let end = port::read_log(&mut input, &mut decoder, args.port.until(), |event| {
        let record = match event {
            port::Event::Record(r) => r,
            port::Event::Chunk => {
                if live && pending && write_error.is_none() {
                    pending = false;
                    if let Err(e) = out.flush() {
                        write_error = Some(e);
                    }
                }
                view.refresh();
                return write_error.is_none();
            }
        };
        view.record(&record);
        if let Record::Damaged { offset, error } = &record {
            if !quiet && reported < 20 {
                view.message(&format!("{}: {}", args.log, damage_message(*offset, error)));
            }
            reported += 1;
        }
        match out.record(&record) {
            Ok(wrote) => pending |= wrote,
            Err(e) => {
                write_error.get_or_insert(e);
            }
        }
        true
    });
    view.finish();
    let flushed = match write_error {
        Some(e) => Err(e),
        None => out.flush(),
    };
    match flushed {
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => return Ok(()),
        other => other.context("cannot write to standard output")?,
    }
    if reported > 20 && !quiet {
        eprintln!("... {} more damaged frames", reported - 20);
    }
    if let Some(why) = end.describe().filter(|_| !quiet) {
        eprintln!("{why}");
    }
    let counts = decoder.counts();
    eprintln!("decoded {counts}");
    warn_cut_off(&args.log, counts.unterminated);
    match end {
        port::End::Failed(e) => Err(e.into()),
        _ => Ok(()),
    }
}

/// Runs `qgait verify`; `Ok(false)` when the check failed. Frames are checked as they arrive
/// ([`Verifier`]): memory is independent of the log's length.
pub fn run_verify(args: VerifyArgs, quiet: bool) -> anyhow::Result<bool> {
    let model = LoadedModel::load(&args.model, quiet)?;
    let (mut input, mut view) = args.port.open(&args.log, false, false, quiet)?;
    let mut decoder = LogDecoder::new();
    let mut verifier = Verifier::new(&model.device, Expected::FirstToLast);
    let imu = args.imu.stream(quiet)?;
    let mut poses = Vec::new();
    let end = port::read_log(&mut input, &mut decoder, args.port.until(), |event| {
        match event {
            port::Event::Record(record) => {
                view.record(&record);
                if let Record::Message {
                    message: Message::PoseFrame(p),
                    ..
                } = &record
                {
                    verifier.add(p);
                    if imu.is_some() {
                        poses.push(p.clone());
                    }
                }
            }
            port::Event::Chunk => view.refresh(),
        }
        true
    });
    view.finish();
    if let Some(why) = end.describe().filter(|_| !quiet) {
        eprintln!("{why}");
    }
    let counts = decoder.counts();
    eprintln!("decoded {counts}");
    warn_cut_off(&args.log, counts.unterminated);
    if let port::End::Failed(e) = end {
        return Err(e.into());
    }
    if verifier.frames() == 0 {
        bail!("{}: no pose frames", args.log);
    }
    let mut v = verifier.finish();
    if args.model.model.is_some() {
        v.expected_model = Some(model.hub.id());
    }
    let tol = args.tol_um * 1e-6;
    println!("{}", v.report(tol));
    let mut passed = v.passed(tol);
    if let Some(imu) = &imu {
        // The rows the hub solved, as it solved them (a lost sample skipped on both sides).
        let solved: std::collections::HashSet<u32> = poses.iter().map(|p| p.seq).collect();
        let host = imu.host_angles_of(|seq| solved.contains(&seq))?;
        let c = OrientationCheck::run(&poses, &host);
        println!("{}", c.report(tol));
        passed &= c.passed(tol);
    }
    Ok(passed)
}

/// What `qgait emulate` sends: the stream, the time (s) of each sample, the number of
/// samples when it made the stream itself (sequence numbers 0..n), and the configuration the
/// stream carries.
struct EmulateInput {
    stream: Vec<u8>,
    times: HashMap<u32, f64>,
    count: Option<u32>,
    /// The last model configuration (`Config`, `SubjectConfig`, `ChainTableConfig`) the stream
    /// carries, if any.
    configuration: Option<Message>,
}

/// The stream and its packets' times for `qgait emulate`.
fn emulate_input(
    args: &EmulateArgs,
    model: &HubModel,
    quiet: bool,
) -> anyhow::Result<EmulateInput> {
    let (stream, count) = match (&args.motion, &args.stream) {
        (Some(motion), None) => {
            let (table, w) = load_motion(motion)?;
            let timing = args.rate.map_or(Timing::TimeColumn, Timing::Rate);
            let (samples, w2) =
                Samples::from_motion(&table, model.id(), model.knee_flexion(), timing)?;
            Diagnostics::new(quiet).warn(w.into_iter().chain(w2));
            let packets: Vec<_> = samples.all_packets().collect();
            (
                qgait_device::packets::stream(&packets),
                Some(samples.len() as u32),
            )
        }
        (None, Some(path)) => (
            std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?,
            None,
        ),
        _ => bail!("give either MOTION or --stream STREAM.bin"),
    };
    let mut times = HashMap::new();
    let mut configuration = None;
    for m in FrameDecoder::new().feed(&stream).flatten() {
        match m {
            Message::JointAngle(p) => {
                times
                    .entry(p.seq)
                    .or_insert(f64::from(p.timestamp_us) * 1e-6);
            }
            Message::Config(_) | Message::SubjectConfig(_) | Message::ChainTableConfig(_) => {
                configuration = Some(m);
            }
            _ => {}
        }
    }
    Ok(EmulateInput {
        stream,
        times,
        count,
        configuration,
    })
}

/// Runs `qgait emulate`; `Ok(false)` when --verify failed or the session did not end normally.
pub fn run_emulate(args: EmulateArgs, quiet: bool) -> anyhow::Result<bool> {
    let paths = |p: &Option<PathBuf>| p.as_deref().map(|p| p.to_string_lossy().into_owned());
    let mut inputs: Vec<String> = [paths(&args.stream), paths(&args.elf), args.motion.clone()]
        .into_iter()
        .flatten()
        .collect();
    inputs.extend(args.model.inputs());
    crate::cli::refuse_overwrite(
        args.frames_csv
            .iter()
            .chain(&args.log)
            .map(PathBuf::as_path),
        &inputs,
    )?;
    let model = LoadedModel::load(&args.model, quiet)?;
    let EmulateInput {
        stream,
        times,
        count,
        configuration,
    } = emulate_input(&args, &model.hub, quiet)?;
    let elf = firmware::locate(args.elf.as_deref())?;
    let settings = HubSettings {
        missing_policy: MissingPolicy::Drop,
        reorder_window: args.window,
        request_status: false,
    };
    let config = messages(&model.hub, settings)?;
    let mut input = frames(&config)?;
    input.extend_from_slice(&stream);
    // The closing request repeats the configuration in force at the end: the stream's own
    // if it carries one (an orientation stream selects gait2392, and a hub in an orientation
    // input mode refuses another model).
    let last = configuration
        .as_ref()
        .or(config.last())
        .context("no configuration message")?;
    input.extend(closing_frames(last)?);
    let expected = InputCounts::of(&input);
    if !quiet {
        eprintln!(
            "running {} under QEMU mps2-an386: {} bytes into UART0",
            elf.display(),
            input.len()
        );
    }
    let echo = if quiet { Echo::Quiet } else { Echo::Stderr };
    let out = session::run(
        &elf,
        input,
        expected,
        echo,
        Limits::for_stream(stream.len()),
    )?;
    if let Some(path) = &args.log {
        std::fs::write(path, &out.uart)
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    let log = HubLog::decode(&out.uart);
    eprintln!(
        "hub sent {} in {:.2} s",
        log.counts,
        out.elapsed.as_secs_f64()
    );
    if let Some(path) = &args.frames_csv {
        write_file(path, |w| frames_csv::write(w, &log.poses, &times))?;
        if !quiet {
            eprintln!("wrote {} frames to {}", log.poses.len(), path.display());
        }
    }
    let mut ok = true;
    // What the stream delivers, as the hub decodes it (for the hint below and --verify):
    // decoded once, when first needed.
    let arrivals = std::cell::OnceCell::new();
    let arrivals = || arrivals.get_or_init(|| Arrivals::of(&stream));
    match &out.status {
        Some(s) => {
            println!("device status:");
            for (k, v) in s.named_counters() {
                println!("  {k:<20} {v}");
            }
            // The hub decodes as the host does: its counters must account for every frame
            // of the input, damaged ones included.
            let (got, want) = (InputCounts::counted_by(s), expected);
            if got == want {
                println!(
                    "input accounted for: {} packets accepted, {} damaged frames counted",
                    got.accepted, got.rejected
                );
            } else {
                ok = false;
                eprintln!(
                    "error: the hub counted {} packets accepted and {} damaged frames; the input has {} and {}",
                    got.accepted, got.rejected, want.accepted, want.rejected
                );
                let orientations = !arrivals().segments.is_empty();
                if orientations && s.malformed > 0 && got.accepted < want.accepted {
                    eprintln!(
                        "(the hub counted the segment orientations as malformed: it is a build \
                         without the `imu` feature; run the IMU firmware, \
                         --elf firmware/target/imu/thumbv7em-none-eabihf/release/qgait-firmware)"
                    );
                }
            }
        }
        None => {
            ok = false;
            eprintln!(
                "error: {}",
                out.problem.as_deref().unwrap_or("no status from the hub")
            );
        }
    }
    if args.verify {
        // A frame is due for exactly the samples whose packets all arrived intact and usable
        // (a stream may have lost packets on the way, a radio link; a motion may hold an angle
        // the hub does not use, protocol.md 8.3), but an orientation stream's calibration pose.
        let expected = match count {
            Some(n) => Expected::Range { first: 0, count: n },
            None => Expected::FirstToLast,
        };
        let mut v = Verification::run(&model.device, &log.poses, expected);
        // (A stream carries its own configuration: its model is checked against --model only
        // when that is given.)
        if args.stream.is_none() || args.model.model.is_some() {
            v.expected_model = Some(model.hub.id());
        }
        let intact = arrivals().framed_samples(model.hub.id());
        let seen: BTreeSet<u32> = log.poses.iter().map(|p| p.seq).collect();
        let missing: Vec<u32> = intact.difference(&seen).copied().collect();
        v.missing = missing.len() as u64;
        v.missing_first = missing.into_iter().take(MISSING_LISTED).collect();
        let unexpected = seen.difference(&intact).count();
        let all_intact = arrivals().intact_samples(model.hub.id()).len();
        let partial = arrivals().partial(model.hub.id());
        if count.is_none() {
            println!(
                "stream: {all_intact} samples with every packet intact{}, {} with packets lost, damaged or unusable",
                if all_intact > intact.len() {
                    " (the first the calibration pose, no frame)"
                } else {
                    ""
                },
                partial.len()
            );
        } else if !partial.is_empty() {
            println!(
                "samples with an angle the hub does not use (not finite, or beyond ±{} rad), no frame due: {}{}",
                qgait_proto::JointAngle::MAX_ANGLE,
                partial.len(),
                qgait_device::verify::preview(&partial[..partial.len().min(MISSING_LISTED)], partial.len() as u64)
            );
        }
        if unexpected > 0 {
            ok = false;
            println!("frames for samples with packets lost, damaged or unusable: {unexpected}");
        }
        let tol = args.tol_um * 1e-6;
        println!("{}", v.report(tol));
        ok &= v.passed(tol);
    }
    Ok(ok)
}

fn write_file(
    path: &Path,
    body: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> anyhow::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create directory", dir.display()))?;
    }
    let mut w = BufWriter::new(
        File::create(path).with_context(|| format!("{}: cannot create", path.display()))?,
    );
    body(&mut w)
        .and_then(|_| w.flush())
        .with_context(|| format!("{}: cannot write", path.display()))
}
