//! `qgait config`: writes the frames that configure a hub (model, segment lengths, missing-joint
//! policy, reorder window) to a file, for a host to send to the hub's UART as they are.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use qgait_proto::{MissingPolicy, ModelId};

use crate::device::config::{frames, messages, HubModel, HubSettings};
use crate::model::kinematics::Model;
use crate::model::spec::ModelSpec;

/// `qgait config` arguments.
#[derive(Debug, Args)]
pub struct ConfigArgs {
    /// The model: `hak`, `phak`, `gait2392` (generic), a SUBJECT.toml from `qgait model import`
    /// or an OpenSim MODEL.osim (imported on the fly), sent as six parts and a `SubjectConfig`.
    #[arg(long, value_name = "hak|phak|gait2392|SUBJECT.toml|MODEL.osim")]
    pub model: String,
    /// Segment lengths (TOML, as for `qgait fk`); HAK and PHAK only. Default: the hub keeps
    /// its current lengths.
    #[arg(long, value_name = "FILE.toml")]
    pub anthropometry: Option<PathBuf>,
    /// What the hub does with a sample missing a joint.
    #[arg(long, value_enum, default_value = "drop")]
    pub policy: Policy,
    /// Samples the hub waits for late packets: 1 to 8 (a hub rejects another).
    #[arg(long, default_value_t = 4, value_name = "N", value_parser = clap::value_parser!(u8).range(1..=8))]
    pub window: u8,
    /// Upload id of a subject model's parts (default: derived from the model's numbers).
    #[arg(long, value_name = "ID")]
    pub upload: Option<u8>,
    /// Do not ask the hub for a `Status` in answer (by default it is asked, so that a refused
    /// configuration shows in its `config_rejected` counter).
    #[arg(long)]
    pub no_status_request: bool,
    /// Output file: the frames, each after a 0x00.
    #[arg(short, long, value_name = "CONFIG.bin")]
    pub output: PathBuf,
}

/// `--policy`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Policy {
    /// Drop the sample (counted by the hub).
    Drop,
    /// Use the last value of each missing joint (frames flagged).
    Hold,
}

/// Runs `qgait config`.
pub fn run_config(args: ConfigArgs, quiet: bool) -> anyhow::Result<()> {
    let anthropometry = args
        .anthropometry
        .as_deref()
        .map(|p| p.to_string_lossy().into_owned());
    let mut inputs = vec![args.model.as_str()];
    inputs.extend(anthropometry.as_deref());
    crate::cli::refuse_overwrite([args.output.as_path()], &inputs)?;
    let spec = ModelSpec::load(&args.model).map_err(anyhow::Error::msg)?;
    let model = match spec {
        ModelSpec::Stick(m) => {
            let anthropometry = match &args.anthropometry {
                None => None,
                Some(p) => {
                    let (a, warnings) =
                        crate::model::anthropometry::read(p).map_err(anyhow::Error::msg)?;
                    if !quiet {
                        for w in warnings {
                            eprintln!("warning: {w}");
                        }
                    }
                    Some(a)
                }
            };
            let model = match m {
                Model::Hak => ModelId::Hak,
                Model::Phak => ModelId::Phak,
            };
            HubModel::Stick {
                model,
                anthropometry,
            }
        }
        ModelSpec::Gait2392 { geometry, name } => {
            if args.anthropometry.is_some() {
                anyhow::bail!("--anthropometry applies to hak and phak only: {name} has its own segment lengths");
            }
            if name == "gait2392" {
                HubModel::Gait2392
            } else {
                HubModel::Subject {
                    geometry,
                    upload: args.upload,
                }
            }
        }
    };
    if args.upload.is_some() && !matches!(model, HubModel::Subject { .. }) {
        anyhow::bail!("--upload applies to a SUBJECT.toml model only");
    }
    let settings = HubSettings {
        missing_policy: match args.policy {
            Policy::Drop => MissingPolicy::Drop,
            Policy::Hold => MissingPolicy::HoldLast,
        },
        reorder_window: args.window,
        request_status: !args.no_status_request,
    };
    let sent = messages(&model, settings).map_err(anyhow::Error::msg)?;
    let bytes = frames(&sent).map_err(anyhow::Error::msg)?;
    std::fs::write(&args.output, &bytes)
        .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", args.output.display()))?;
    if !quiet {
        eprintln!(
            "wrote {} frame(s), {} bytes, to {}",
            sent.len(),
            bytes.len(),
            args.output.display()
        );
    }
    Ok(())
}
