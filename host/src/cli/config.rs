//! `qgait config`: writes the frames that configure a hub (model, segment lengths, missing-joint
//! policy, reorder window) to a file, for a host to send to the hub's UART as they are.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use qgait_proto::{MissingPolicy, ModelId, VelocityConfig, MAX_REORDER_WINDOW};

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use qgait_device::config::{frames, messages, HubModel, HubSettings};
use qgait_model::choice::Model;

/// `qgait config` arguments.
#[derive(Debug, Args)]
pub struct ConfigArgs {
    /// The model (a SUBJECT.toml or MODEL.osim is sent as six parts and a `SubjectConfig`)
    /// and, for HAK and PHAK, the lengths (without `--anthropometry` the hub keeps its own).
    #[command(flatten)]
    pub model: ModelArgs,
    /// What the hub does with a sample missing a joint.
    #[arg(long, value_enum, default_value = "drop")]
    pub policy: Policy,
    /// The hub's reorder window.
    #[command(flatten)]
    pub reorder: ReorderWindow,
    /// Upload id of a subject model's or a chain's parts (default: derived from the model's
    /// numbers).
    #[arg(long, value_name = "ID")]
    pub upload: Option<u8>,
    /// Do not ask the hub for a `Status` in answer (by default it is asked, so that a refused
    /// configuration shows in its `config_rejected` counter).
    #[arg(long)]
    pub no_status_request: bool,
    /// Turn on the hub's points' velocities (protocol.md 4.11) for nodes sampling at HZ: a
    /// `VelocityConfig` with the period 1/HZ (rounded to the µs), sent first so that the status
    /// asked for after the model shows a refusal (a hub built without the firmware's `velocity`
    /// feature refuses it, `config_rejected`).
    #[arg(long, value_name = "HZ", value_parser = sample_rate)]
    pub velocities: Option<f64>,
    /// Output file: the frames, each after a 0x00.
    #[arg(short, long, value_name = "CONFIG.bin")]
    pub output: PathBuf,
}

/// The hub's reorder window (`qgait config`, `emulate`).
#[derive(Debug, Args, Clone, Copy)]
pub struct ReorderWindow {
    /// Samples the hub waits for late packets: 1 to 8 (a hub rejects another).
    #[arg(
        long,
        default_value_t = 4,
        value_name = "N",
        value_parser = clap::value_parser!(u8).range(1..=i64::from(MAX_REORDER_WINDOW))
    )]
    pub window: u8,
}

/// `--policy`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Policy {
    /// Drop the sample (counted by the hub).
    Drop,
    /// Use the last value of each missing joint (frames flagged).
    Hold,
}

/// The configuration a hub gets for `model`; `upload` is a subject model's or a chain's upload
/// id.
pub(crate) fn hub_model(model: Model, upload: Option<u8>) -> anyhow::Result<HubModel> {
    let hub = match model {
        Model::Hak { stated } => HubModel::Stick {
            model: ModelId::Hak,
            anthropometry: stated,
        },
        Model::Phak { stated } => HubModel::Stick {
            model: ModelId::Phak,
            anthropometry: stated,
        },
        Model::Gait2392 { name, .. } if name == "gait2392" => HubModel::Gait2392,
        Model::Gait2392 { geometry, .. } => HubModel::Subject { geometry, upload },
        Model::Chain { name, chain } => HubModel::Chain {
            chain: Box::new(
                chain
                    .chain(&name)
                    .map_err(|e| anyhow::anyhow!("--model {e}"))?,
            ),
            upload,
        },
    };
    if upload.is_some() && !matches!(hub, HubModel::Subject { .. } | HubModel::Chain { .. }) {
        anyhow::bail!("--upload applies to a SUBJECT.toml or chain model only");
    }
    Ok(hub)
}

/// `--velocities`: a rate whose period is 1 µs to 1 s.
fn sample_rate(s: &str) -> anyhow::Result<f64> {
    crate::cli::amount(s, 1.0, true)
        .filter(|hz| *hz <= 1e6)
        .ok_or_else(|| anyhow::anyhow!("`{s}` is not a sampling rate of 1 to 1,000,000 Hz"))
}

/// Runs `qgait config`.
pub fn run_config(args: ConfigArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    crate::cli::output::refuse_overwrite([args.output.as_path()], &args.model.inputs())?;
    let model = hub_model(args.model.load(diagnostics)?, args.upload)?;
    let settings = HubSettings {
        missing_policy: match args.policy {
            Policy::Drop => MissingPolicy::Drop,
            Policy::Hold => MissingPolicy::HoldLast,
        },
        reorder_window: args.reorder.window,
        request_status: !args.no_status_request,
    };
    let mut sent = messages(&model, settings)?;
    if let Some(hz) = args.velocities {
        let velocities = VelocityConfig {
            enabled: true,
            period_us: (1e6 / hz).round() as u32,
            request_status: false,
        };
        sent.insert(0, velocities.into());
    }
    let bytes = frames(&sent)?;
    std::fs::write(&args.output, &bytes)
        .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", args.output.display()))?;
    diagnostics.done(format!(
        "wrote {} frame(s), {} bytes, to {}",
        sent.len(),
        bytes.len(),
        args.output.display()
    ));
    Ok(())
}
