//! `qgait emulate`: the hub firmware under QEMU with a motion streamed into its UART.

use std::collections::BTreeSet;
use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::Args;
use qgait_emulate::faults::Arrivals;
use qgait_emulate::firmware;
use qgait_emulate::qemu::Echo;
use qgait_emulate::session::{self, closing_frames, InputCounts, Limits};
use qgait_proto::{FrameDecoder, Message, MissingPolicy, Status};

use crate::cli::config::ReorderWindow;
use crate::cli::device_args::{LoadedModel, PointTolerance};
use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use qgait_device::config::{frames, messages, HubModel, HubSettings};
use qgait_device::frames_csv;
use qgait_device::log::HubLog;
use qgait_device::orientations::OrientationCheck;
use qgait_device::packets::{Samples, Timing};
use qgait_device::raw_hub::RawHubHost;
use qgait_device::verify::{Expected, Verifier, MISSING_LISTED};
use qgait_model::motion::source::load_motion;

/// `qgait emulate` arguments, in the order `--help` lists them: what runs on what input, the
/// hub's settings, what is written, what is checked.
#[derive(Debug, Args)]
pub struct EmulateArgs {
    /// Motion file (.mot/.sto) or `builtin:...` to stream (its packets as `qgait packets`
    /// makes them).
    #[arg(required_unless_present = "stream", conflicts_with = "stream")]
    pub motion: Option<String>,
    /// A byte stream to send as it is (e.g. from `qgait packets`).
    #[arg(long, value_name = "STREAM.bin")]
    pub stream: Option<PathBuf>,
    /// Samples per second for MOTION (default: its time column).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Firmware ELF (default: the release build of firmware/, built if missing; for a stream of
    /// raw samples, the build with the features `imu` and `raw`).
    #[arg(long, value_name = "PATH")]
    pub elf: Option<PathBuf>,
    /// Run the IMU node firmware (`qgait-node`) instead of the hub, with --stream a raw stream
    /// (`qgait packets --raw`): it fuses the samples and sends orientations; --verify checks
    /// them against the host's f64 fusion of the same stream.
    #[arg(long, requires = "stream", conflicts_with_all = ["frames_csv", "motion"])]
    pub node: bool,
    /// The hub's configuration, sent before the stream.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The hub's reorder window.
    #[command(flatten)]
    pub reorder: ReorderWindow,
    /// Write the frames (the `fk` columns plus `seq`) to this CSV.
    #[arg(long, value_name = "OUT.csv")]
    pub frames_csv: Option<PathBuf>,
    /// Write everything the hub sent (its UART output) to this file.
    #[arg(long, value_name = "LOG.bin")]
    pub log: Option<PathBuf>,
    /// Check every frame against the f64 kernel and that no sample is missing (with --stream:
    /// a frame for exactly the samples whose packets all arrived intact), and the points'
    /// velocities when the hub sends them.
    #[arg(long)]
    pub verify: bool,
    /// The tolerances of --verify on the points and their velocities.
    #[command(flatten)]
    pub points: PointTolerance,
    /// Tolerance of --verify on a raw stream (degrees): with --node, the RMS angle between the
    /// device's orientations and the host's; a hub with raw input (a stream of `qgait packets
    /// --raw --hub`), the RMS difference of its joint angles from the host's f64 fusion and IMU
    /// path of the same stream.
    #[arg(long, default_value_t = 0.1, value_name = "DEG")]
    pub tol_deg: f64,
}

/// `qgait emulate --node`: a raw stream through the IMU node firmware.
fn run_node(args: &EmulateArgs, quiet: bool) -> anyhow::Result<bool> {
    use qgait_device::raw::{host_orientations, RawCheck};
    let Some(path) = &args.stream else {
        bail!("--node runs a raw stream: give --stream STREAM.bin (from `qgait packets --raw`)");
    };
    let inputs = [path.to_string_lossy().into_owned()];
    crate::cli::output::refuse_overwrite(args.log.iter().map(PathBuf::as_path), &inputs)?;
    let stream = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let config = FrameDecoder::new()
        .feed(&stream)
        .flatten()
        .filter_map(|m| match m {
            Message::RawImuConfig(c) => Some(c),
            _ => None,
        })
        .last()
        .with_context(|| {
            format!(
                "{}: no RawImuConfig: not a raw stream (`qgait packets --raw`)",
                path.display()
            )
        })?;
    let elf = firmware::locate_node(args.elf.as_deref())?;
    let mut input = stream.clone();
    input.extend(closing_frames(&Message::RawImuConfig(config))?);
    let expected = InputCounts::of(&input);
    let out = run_session(&elf, input, expected, stream.len(), args, quiet)?;
    let mut orientations = Vec::new();
    let mut raw_status = None;
    for m in FrameDecoder::new().feed(&out.uart).flatten() {
        match m {
            Message::SegmentOrientation(o) => orientations.push(o),
            Message::RawImuStatus(s) => raw_status = Some(s),
            _ => {}
        }
    }
    eprintln!(
        "node sent {} orientations in {:.2} s",
        orientations.len(),
        out.elapsed.as_secs_f64()
    );
    let mut ok = true;
    match status_of(&out, "node") {
        Some(s) => {
            if let Some(r) = raw_status {
                print_counters("raw input", r.named_counters());
            }
            ok &= accounted(s, expected, "node", "raw samples taken").is_ok();
            if s.config_rejected > 0 {
                ok = false;
                eprintln!(
                    "error: the node rejected {} configurations (a node fuses one sensor: give `qgait packets --raw` one file)",
                    s.config_rejected
                );
            }
        }
        None => ok = false,
    }
    if args.verify {
        let c = RawCheck::run(&orientations, &host_orientations(&stream));
        println!("{}", c.report(args.tol_deg));
        ok &= c.passed(args.tol_deg);
    }
    Ok(ok)
}

/// What `qgait emulate` sends: the stream, the number of samples when it made the stream
/// itself (sequence numbers 0..n), and the configuration the stream carries.
struct EmulateInput {
    stream: Vec<u8>,
    count: Option<u32>,
    /// The last model configuration (`Config`, `SubjectConfig`, `ChainTableConfig`) the stream
    /// carries, if any.
    configuration: Option<Message>,
}

/// The stream for `qgait emulate`.
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
    let mut configuration = None;
    for m in FrameDecoder::new().feed(&stream).flatten() {
        if let Message::Config(_) | Message::SubjectConfig(_) | Message::ChainTableConfig(_) = m {
            configuration = Some(m);
        }
    }
    Ok(EmulateInput {
        stream,
        count,
        configuration,
    })
}

/// Runs `qgait emulate`; `Ok(false)` when --verify failed or the session did not end normally.
pub fn run_emulate(args: EmulateArgs, quiet: bool) -> anyhow::Result<bool> {
    if args.node {
        return run_node(&args, quiet);
    }
    let paths = |p: &Option<PathBuf>| p.as_deref().map(|p| p.to_string_lossy().into_owned());
    let mut inputs: Vec<String> = [paths(&args.stream), paths(&args.elf), args.motion.clone()]
        .into_iter()
        .flatten()
        .collect();
    inputs.extend(args.model.inputs());
    crate::cli::output::refuse_overwrite(
        args.frames_csv
            .iter()
            .chain(&args.log)
            .map(PathBuf::as_path),
        &inputs,
    )?;
    let model = LoadedModel::load(&args.model, quiet)?;
    let EmulateInput {
        stream,
        count,
        configuration,
    } = emulate_input(&args, &model.hub, quiet)?;
    // A stream of raw samples is for a hub with raw input: the host's f64 path of it says
    // which frames are due and what they hold.
    let raw = FrameDecoder::new()
        .feed(&stream)
        .flatten()
        .any(|m| matches!(m, Message::RawImuSample(_)));
    let raw = raw.then(|| RawHubHost::of(&stream)).transpose()?;
    let elf = match raw {
        Some(_) => firmware::locate_feature(args.elf.as_deref(), RAW_HUB_FEATURES)?,
        None => firmware::locate(args.elf.as_deref())?,
    };
    let settings = HubSettings {
        missing_policy: MissingPolicy::Drop,
        reorder_window: args.reorder.window,
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
    let expected = match &raw {
        Some(host) => host.input_counts(&input),
        None => InputCounts::of(&input),
    };
    let out = run_session(&elf, input, expected, stream.len(), &args, quiet)?;
    // --verify's checker sees the pose frames, and the velocities after them, in the order the
    // hub sent them, as the log is decoded. A frame is due for exactly the samples whose
    // packets all arrived intact and usable (a stream may have lost packets on the way, a
    // radio link; a motion may hold an angle the hub does not use, protocol.md 8.3), but an
    // orientation stream's calibration pose.
    let mut verifier = args.verify.then(|| {
        let due = match count {
            Some(n) => Expected::Range { first: 0, count: n },
            None => Expected::FirstToLast,
        };
        Verifier::new(&model.device, due)
    });
    let log = HubLog::decode_with(&out.uart, |message| {
        if let Some(verifier) = &mut verifier {
            verifier.add_message(message);
        }
    });
    eprintln!(
        "hub sent {} in {:.2} s",
        log.counts,
        out.elapsed.as_secs_f64()
    );
    if let Some(path) = &args.frames_csv {
        write_file(path, |w| frames_csv::write(w, &log.poses))?;
        if !quiet {
            eprintln!("wrote {} frames to {}", log.poses.len(), path.display());
        }
    }
    let mut ok = true;
    // What the stream delivers, as the hub decodes it (for the hint below and --verify):
    // decoded once, when first needed.
    let arrivals = std::cell::OnceCell::new();
    let arrivals = || arrivals.get_or_init(|| Arrivals::of(&stream));
    match status_of(&out, "hub") {
        Some(s) => {
            // The hub decodes as the host does: its counters must account for every frame
            // of the input, damaged ones included.
            if let Err((got, want)) = accounted(s, expected, "hub", "packets accepted") {
                ok = false;
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
        None => ok = false,
    }
    if let Some(verifier) = verifier {
        let mut v = verifier.finish();
        v.velocity_tolerance = args.points.metres_per_second();
        // (A stream carries its own configuration: its model is checked against --model only
        // when that is given.)
        if args.stream.is_none() || args.model.model.is_some() {
            v.expected_model = Some(model.hub.id());
        }
        let intact = match &raw {
            Some(host) => host.frames_due(),
            None => arrivals().framed_samples(model.hub.id()),
        };
        let seen: BTreeSet<u32> = log.poses.iter().map(|p| p.seq).collect();
        let missing: Vec<u32> = intact.difference(&seen).copied().collect();
        v.missing = missing.len() as u64;
        v.missing_first = missing.into_iter().take(MISSING_LISTED).collect();
        let unexpected = seen.difference(&intact).count();
        let all_intact = arrivals().intact_samples(model.hub.id()).len();
        let partial = arrivals().partial(model.hub.id());
        if let Some(host) = &raw {
            println!(
                "stream: {} samples with every sensor fused (the first, seq {}, the calibration pose, no frame)",
                host.samples.len(),
                host.calibration
            );
        } else if count.is_none() {
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
        let tol = args.points.metres();
        println!("{}", v.report(tol));
        ok &= v.passed(tol);
        if let Some(host) = &raw {
            let c = OrientationCheck::run(&log.poses, &host.angles_of(|seq| seen.contains(&seq))?);
            println!("{}", c.angles_report(args.tol_deg));
            ok &= c.angles_passed(args.tol_deg);
        }
    }
    Ok(ok)
}

/// The firmware features of a hub with raw input.
const RAW_HUB_FEATURES: &str = "imu,raw";

/// Prints `title:` and one line per counter.
fn print_counters<'a>(title: &str, counters: impl IntoIterator<Item = (&'a str, u32)>) {
    println!("{title}:");
    for (k, v) in counters {
        println!("  {k:<20} {v}");
    }
}

/// Whether the `device`'s status `s` accounts for the `expected` input (its accepted count
/// counting `taken`), said on standard output, or on standard error with what was counted and
/// what was due.
fn accounted(
    s: &Status,
    expected: InputCounts,
    device: &str,
    taken: &str,
) -> Result<(), (InputCounts, InputCounts)> {
    let got = InputCounts::counted_by(s);
    if got == expected {
        println!(
            "input accounted for: {} {taken}, {} damaged frames counted",
            got.accepted, got.rejected
        );
        Ok(())
    } else {
        eprintln!(
            "error: the {device} counted {} {taken} and {} damaged frames; the input has {} and {}",
            got.accepted, got.rejected, expected.accepted, expected.rejected
        );
        Err((got, expected))
    }
}

/// Runs `elf` under QEMU on `input` (`expected`: what it holds; `stream_len` bytes of it the
/// stream, for the time limits), writing what it sent to `--log` if `args` ask.
fn run_session(
    elf: &Path,
    input: Vec<u8>,
    expected: InputCounts,
    stream_len: usize,
    args: &EmulateArgs,
    quiet: bool,
) -> anyhow::Result<session::SessionOutput> {
    if !quiet {
        eprintln!(
            "running {} under QEMU mps2-an386: {} bytes into UART0",
            elf.display(),
            input.len()
        );
    }
    let echo = if quiet { Echo::Quiet } else { Echo::Stderr };
    let out = session::run(elf, input, expected, echo, Limits::for_stream(stream_len))?;
    if let Some(log) = &args.log {
        std::fs::write(log, &out.uart)
            .with_context(|| format!("{}: cannot write", log.display()))?;
    }
    Ok(out)
}

/// The device's status at the end of the session, its counters printed; `None`, with why
/// printed, when it sent none.
fn status_of<'a>(out: &'a session::SessionOutput, device: &str) -> Option<&'a Status> {
    match &out.status {
        Some(s) => {
            print_counters("device status", s.named_counters());
            Some(s)
        }
        None => {
            let why = out.problem.clone();
            eprintln!(
                "error: {}",
                why.unwrap_or_else(|| format!("no status from the {device}"))
            );
            None
        }
    }
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
