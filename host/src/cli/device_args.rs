//! The options the device commands share: the model a hub runs, the IMU orientation input
//! (`packets`, `verify`) and a live input (`decode`, `verify`: a file, a pipe or a serial port).

use std::io::{self, IsTerminal};
use std::path::PathBuf;
use std::time::Duration;

use clap::{Args, ValueEnum};
use qgait_proto::PoseModels;

use crate::cli::config::hub_model;
use crate::cli::diagnostics::Diagnostics;
use crate::cli::live::LiveView;
use crate::cli::model_args::ModelArgs;
use qgait_device::config::HubModel;
use qgait_device::orientations::OrientationStream;
use qgait_device::port::{self, Input, Until};

/// The model, loaded: what to send the hub ([`HubModel`]), and how to recompute its frames.
pub(crate) struct LoadedModel {
    pub(crate) hub: HubModel,
    pub(crate) device: PoseModels<f64>,
}

impl LoadedModel {
    pub(crate) fn load(args: &ModelArgs, quiet: bool) -> anyhow::Result<LoadedModel> {
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
    pub(crate) fn stream(&self, quiet: bool) -> anyhow::Result<Option<OrientationStream>> {
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
pub(crate) fn warn_cut_off(log: &str, unterminated: usize) {
    if unterminated > 0 {
        eprintln!(
            "warning: {log}: the log ends inside a frame ({unterminated} bytes without a delimiter): that frame is lost"
        );
    }
}

/// How far the hub's points and their velocities may be from the `f64` kernel's: the
/// tolerances of `verify` and `emulate --verify`.
#[derive(Debug, Args, Clone, Copy)]
pub struct PointTolerance {
    /// Largest accepted error per point (micrometres).
    #[arg(long, default_value_t = 10.0, value_name = "UM", value_parser = micrometres)]
    pub tol_um: f64,
    /// Largest accepted error of a point's velocity, when the hub sends velocities
    /// (protocol.md 4.11), millimetres per second: each `PoseVelocities` is recomputed in f64
    /// from the echoed angles of its pose frame and the one before (the same backward
    /// difference).
    #[arg(long, default_value_t = 1.0, value_name = "MM_S", value_parser = millimetres_per_second)]
    pub tol_mm_s: f64,
}

impl PointTolerance {
    /// The points' tolerance, metres.
    pub(crate) fn metres(&self) -> f64 {
        self.tol_um * 1e-6
    }

    /// The velocities' tolerance, metres per second.
    pub(crate) fn metres_per_second(&self) -> f64 {
        self.tol_mm_s * 1e-3
    }
}

/// `--tol-mm-s`: a finite number of mm/s, at least 0.
fn millimetres_per_second(s: &str) -> anyhow::Result<f64> {
    crate::cli::amount(s, 0.0, true)
        .ok_or_else(|| anyhow::anyhow!("`{s}` is not a tolerance in mm/s (a number, 0 or more)"))
}

fn micrometres(s: &str) -> anyhow::Result<f64> {
    crate::cli::amount(s, 0.0, true).ok_or_else(|| {
        anyhow::anyhow!("`{s}` is not a tolerance in micrometres (a number, 0 or more)")
    })
}

pub(crate) fn positive_seconds(s: &str) -> anyhow::Result<f64> {
    crate::cli::amount(s, 0.0, false)
        .ok_or_else(|| anyhow::anyhow!("`{s}` is not a positive number of seconds"))
}

impl PortArgs {
    pub(crate) fn until(&self) -> Until {
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
    pub(crate) fn open(
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
