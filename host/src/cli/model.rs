//! `qgait model import`: an OpenSim model's leg chain as a SUBJECT.toml (gait2392's family) or a
//! chain file (any other lower-limb model) for `--model`.

use std::path::PathBuf;

use anyhow::Context;
use clap::Subcommand;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::output::refuse_overwrite;
use qgait_model::choice::Model;
use qgait_model::subject;

/// `qgait model` subcommands.
#[derive(Debug, Subcommand)]
pub enum ModelCommand {
    /// Reads the leg chain of an OpenSim model (.osim, 3.x or 4.x) for `--model`: a
    /// SUBJECT.toml for gait2392's family, a chain file for other lower-limb models
    /// (Rajagopal, gait10dof18musc, ...).
    Import {
        /// The OpenSim model (generic or scaled).
        model: PathBuf,
        /// Output SUBJECT.toml.
        #[arg(short, long, value_name = "SUBJECT.toml")]
        output: PathBuf,
        /// Marker file (OpenSim MarkerSet .xml or a model) with `R.Toe.Tip`/`L.Toe.Tip` on
        /// calcn or toes; default: the model's own markers, else the generic toe tip scaled by
        /// the toes' geometry scale factors.
        #[arg(long, value_name = "MARKERS.xml")]
        markers: Option<PathBuf>,
    },
}

/// Runs `qgait model ...`.
pub fn run_model(c: ModelCommand, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    match c {
        ModelCommand::Import {
            model,
            output,
            markers,
        } => {
            let shown = model.display().to_string();
            let marker_path = markers.as_ref().map(|m| m.display().to_string());
            let mut given = vec![shown.as_str()];
            given.extend(marker_path.as_deref());
            refuse_overwrite([output.as_path()], &given)?;
            let text =
                std::fs::read_to_string(&model).with_context(|| format!("{shown}: cannot read"))?;
            let marker_text = match &markers {
                Some(m) => Some((
                    std::fs::read_to_string(m)
                        .with_context(|| format!("{}: cannot read", m.display()))?,
                    m.display().to_string(),
                )),
                None => None,
            };
            let (model, notes) = Model::import(
                &text,
                &shown,
                marker_text.as_ref().map(|(t, s)| (t.as_str(), s.as_str())),
            )?;
            // The kernel must accept what was read (knot counts, axes).
            model.check()?;
            let text = match &model {
                Model::Gait2392 { geometry, .. } => subject::to_toml(geometry, &notes),
                Model::Chain { chain, .. } => chain.to_toml(&notes),
                _ => unreachable!("an import is a gait2392 or a chain model"),
            };
            std::fs::write(&output, text)
                .with_context(|| format!("{}: cannot write", output.display()))?;
            diagnostics.notes(notes.iter().skip(1));
            diagnostics.done(format!("wrote {}", output.display()));
            Ok(())
        }
    }
}
