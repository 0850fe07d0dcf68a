//! The `qgait` command line: argument definitions and the commands.

pub mod config;
pub mod decode;
pub mod device_args;
pub(crate) mod diagnostics;
pub mod emulate;
pub(crate) mod export;
pub(crate) mod fidelity;
pub(crate) mod fk;
pub(crate) mod fuse;
pub(crate) mod gait;
pub(crate) mod gait_each;
pub(crate) mod imu;
pub(crate) mod imu_signals;
pub(crate) mod jsonl;
pub(crate) mod live;
pub(crate) mod model;
pub(crate) mod model_args;
pub(crate) mod motion;
pub(crate) mod output;
pub mod packets;
pub(crate) mod report;
pub mod verify;

use clap::{Parser, Subcommand};

use crate::cli::diagnostics::Diagnostics;

/// Forward kinematics of the human lower limbs with quaternions (HAK, PHAK, gait2392 and imported OpenSim leg models).
///
/// MOTION is an OpenSim .mot/.sto file, or a built-in normative gait: `builtin:normal`,
/// `builtin:crouch=S` (crouch severity 0..1), optionally followed by `,rows=N`.
#[derive(Debug, Parser)]
#[command(name = "qgait", version, about, long_about)]
pub struct Cli {
    /// No progress bar and no warnings (errors are still printed).
    #[arg(short, long, global = true)]
    pub quiet: bool,
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Joint positions (metres) for every row of a motion, as CSV.
    Fk(crate::cli::fk::FkArgs),
    /// Figures and metrics of one or more gaits overlaid (the paper's Figs 5-10).
    Report(crate::cli::report::ReportArgs),
    /// Writes a motion (e.g. a built-in gait) as an OpenSim .mot file.
    Motion(crate::cli::motion::MotionArgs),
    /// OpenSim models: `model import MODEL.osim -o SUBJECT.toml|CHAIN.toml`.
    #[command(subcommand)]
    Model(crate::cli::model::ModelCommand),
    /// Computed joint centres as an OpenSim marker file (.trc) and table (.sto).
    Export(crate::cli::export::ExportArgs),
    /// How far PHAK (8 DoF) is from gait2392, per point, and what each feature costs (Markdown).
    Fidelity(crate::cli::fidelity::FidelityArgs),
    /// The frames that configure a hub (model, lengths, policy, window), to send to its UART.
    Config(crate::cli::config::ConfigArgs),
    /// The byte stream the IMU nodes send for a motion (one JointAngle packet per joint per row).
    Packets(crate::cli::packets::PacketsArgs),
    /// Decodes a hub log or any stream of frames (every message; damaged ones reported, skipped).
    Decode(crate::cli::decode::DecodeArgs),
    /// Recomputes every pose frame of a hub log with the f64 kernel; fails on errors or gaps.
    Verify(crate::cli::verify::VerifyArgs),
    /// Runs the hub firmware under QEMU with a motion streamed into its UART.
    Emulate(crate::cli::emulate::EmulateArgs),
    /// Joint angles (gait2392, .mot in degrees) from IMU segment orientations (OpenSim
    /// orientation .sto), calibrated on a static pose as OpenSim's OpenSense does it.
    Imu(crate::cli::imu::ImuArgs),
    /// Orientations (OpenSense orientation .sto) from raw IMU recordings (gyroscope,
    /// accelerometer, magnetometer) with the kernel's VQF, one column per sensor.
    Fuse(crate::cli::fuse::FuseArgs),
    /// Clinical gait analysis: events, cycles, spatiotemporal parameters, normative bands and
    /// the Gait Profile Score, as one HTML report and CSVs.
    Gait(crate::cli::gait::GaitArgs),
    /// What IMUs fixed to a model's bodies measure during a motion (orientation, gyroscope,
    /// accelerometer), as OpenSim's IMU component, with optional noise and bias.
    ImuSignals(crate::cli::imu_signals::ImuSignalsArgs),
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let diagnostics = Diagnostics::new(cli.quiet);
    match cli.command {
        Command::Fk(args) => crate::cli::fk::run_fk(args, &diagnostics)?,
        Command::Fuse(args) => crate::cli::fuse::run_fuse(args, &diagnostics)?,
        Command::Imu(args) => crate::cli::imu::run_imu(args, &diagnostics)?,
        Command::ImuSignals(args) => crate::cli::imu_signals::run_imu_signals(args, &diagnostics)?,
        Command::Gait(args) if args.each => crate::cli::gait_each::run(args, &diagnostics)?,
        Command::Gait(args) => crate::cli::gait::run_gait(args, &diagnostics)?,
        Command::Report(args) => crate::cli::report::run_report(args, &diagnostics)?,
        Command::Motion(args) => crate::cli::motion::run_motion(args, &diagnostics)?,
        Command::Model(c) => crate::cli::model::run_model(c, &diagnostics)?,
        Command::Export(args) => crate::cli::export::run_export(args, &diagnostics)?,
        Command::Fidelity(args) => crate::cli::fidelity::run_fidelity(args, &diagnostics)?,
        Command::Config(args) => crate::cli::config::run_config(args, &diagnostics)?,
        Command::Packets(args) => crate::cli::packets::run_packets(args, cli.quiet)?,
        Command::Decode(args) => crate::cli::decode::run_decode(args, cli.quiet)?,
        Command::Verify(args) => {
            if !crate::cli::verify::run_verify(args, cli.quiet)? {
                anyhow::bail!("verification failed");
            }
        }
        Command::Emulate(args) => {
            if !crate::cli::emulate::run_emulate(args, cli.quiet)? {
                anyhow::bail!("emulation failed");
            }
        }
    }
    Ok(())
}

/// `text` as a finite number above `min`, or equal to it if `or_equal`: what the options that
/// take an amount (seconds, micrometres, years) accept.
pub(crate) fn amount(text: &str, min: f64, or_equal: bool) -> Option<f64> {
    let x: f64 = text.trim().parse().ok()?;
    (x.is_finite() && (x > min || or_equal && x == min)).then_some(x)
}

/// `text` as three finite numbers `X,Y,Z`: what the options that take a vector or three angles
/// (`--gyro-bias`, `--magnetic-field`, `--sensor-to-opensim`) accept.
pub(crate) fn three_numbers(text: &str) -> anyhow::Result<[f64; 3]> {
    let mut numbers = [0.0; 3];
    let mut parts = text.split(',');
    for slot in &mut numbers {
        let part = parts
            .next()
            .ok_or_else(|| anyhow::anyhow!("three numbers X,Y,Z are needed"))?;
        *slot = amount(part, f64::NEG_INFINITY, false)
            .ok_or_else(|| anyhow::anyhow!("`{}` is not a number", part.trim()))?;
    }
    anyhow::ensure!(parts.next().is_none(), "three numbers X,Y,Z are needed");
    Ok(numbers)
}

#[cfg(test)]
mod tests {
    use super::three_numbers;

    #[test]
    fn three_numbers_take_exactly_three_finite_numbers() {
        assert_eq!(three_numbers("-1.25, 0,2e-3").unwrap(), [-1.25, 0.0, 2e-3]);
        for bad in ["", "1,2", "1,2,3,4", "1,,3", "1,x,3", "1,inf,3", "NaN,0,0"] {
            assert!(three_numbers(bad).is_err(), "{bad:?} accepted");
        }
    }
}
