//! `qgait verify`: every pose frame of a hub log recomputed with the `f64` kernel; fails on
//! errors or gaps.

use anyhow::bail;
use clap::Args;
use qgait_proto::Message;

use crate::cli::device_args::{
    warn_cut_off, LoadedModel, OrientationArgs, PointTolerance, PortArgs,
};
use crate::cli::model_args::ModelArgs;
use qgait_device::log::{LogDecoder, Record};
use qgait_device::orientations::OrientationCheck;
use qgait_device::port;
use qgait_device::raw::{host_orientations, RawCheck};
use qgait_device::raw_hub::RawHubHost;
use qgait_device::verify::{Expected, Verifier};

/// `qgait verify` arguments.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// Hub log (what the hub sent): a file, `-` for standard input, or a serial port.
    pub log: String,
    /// The tolerance on the points.
    #[command(flatten)]
    pub points: PointTolerance,
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
    /// The raw stream a node or a hub with raw input was sent (`qgait packets --raw`, `--raw
    /// --hub`): a node's segment orientations are checked against the host's f64 fusion of the
    /// same stream, by the same rules (protocol.md 4.10); a hub's pose frames as any (their
    /// points against the echoed angles), and their angles against the host's f64 fusion and
    /// IMU path of the stream.
    #[arg(long, value_name = "STREAM.bin", conflicts_with = "orientations")]
    pub raw: Option<std::path::PathBuf>,
    /// Tolerance of --raw (degrees): the RMS angle between a node's orientations and the
    /// host's, or the RMS difference of a hub's joint angles from the host's.
    #[arg(long, default_value_t = 0.1, value_name = "DEG", requires = "raw")]
    pub tol_deg: f64,
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
    let mut orientations = Vec::new();
    let end = port::read_log(&mut input, &mut decoder, args.port.until(), |event| {
        match event {
            port::Event::Record(record) => {
                view.record(&record);
                if let Record::Message { message, .. } = &record {
                    verifier.add_message(message);
                    match message {
                        Message::PoseFrame(p) if imu.is_some() || args.raw.is_some() => {
                            poses.push(p.clone())
                        }
                        Message::SegmentOrientation(o) => orientations.push(*o),
                        _ => {}
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
    let raw = match &args.raw {
        Some(path) => Some(
            std::fs::read(path)
                .map_err(|e| anyhow::anyhow!("{}: cannot read: {e}", path.display()))?,
        ),
        None => None,
    };
    if let Some(stream) = raw.as_ref().filter(|_| poses.is_empty()) {
        if orientations.is_empty() {
            bail!("{}: no segment orientations", args.log);
        }
        let c = RawCheck::run(&orientations, &host_orientations(stream));
        println!("{}", c.report(args.tol_deg));
        return Ok(c.passed(args.tol_deg));
    }
    if verifier.frames() == 0 {
        bail!("{}: no pose frames", args.log);
    }
    let mut v = verifier.finish();
    v.velocity_tolerance = args.points.metres_per_second();
    if args.model.model.is_some() {
        v.expected_model = Some(model.hub.id());
    }
    let tol = args.points.metres();
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
    if let Some(stream) = &raw {
        // A hub with raw input: its angles against the host's f64 fusion and IMU path.
        let host = RawHubHost::of(stream)?;
        let solved: std::collections::HashSet<u32> = poses.iter().map(|p| p.seq).collect();
        let c = OrientationCheck::run(&poses, &host.angles_of(|seq| solved.contains(&seq))?);
        println!("{}", c.angles_report(args.tol_deg));
        passed &= c.angles_passed(args.tol_deg);
    }
    Ok(passed)
}
