//! `--model` and `--anthropometry`: declared once, flattened into every command that takes a
//! model, loaded into the one [`Model`] type.

use std::path::PathBuf;

use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use qgait_model::anthropometry;
use qgait_model::choice::Model;
use qgait_model::error::ModelError;
use qgait_opensim::diagnostics::Warning;

/// The model a command computes with.
#[derive(Debug, Args, Clone, Default)]
pub struct ModelArgs {
    /// Kinematic model: `hak`, `phak`, `gait2392` (OpenSim's chain, generic), a SUBJECT.toml or
    /// CHAIN.toml written by `qgait model import`, or an OpenSim lower-limb model .osim
    /// (gait2392's family, Rajagopal, gait10dof18musc, ...: its leg chain imported on the fly).
    /// Default: phak (for `imu` and `gait`: gait2392).
    #[arg(
        long,
        value_name = "hak|phak|gait2392|SUBJECT.toml|CHAIN.toml|MODEL.osim"
    )]
    pub model: Option<String>,
    /// Segment lengths of HAK and PHAK (TOML: pelvis_half_width, femur, tibia, foot, each
    /// optionally per side with _r/_l). Default: gait2392's (for `config`: the hub keeps the
    /// lengths it has).
    #[arg(long, value_name = "FILE.toml")]
    pub anthropometry: Option<PathBuf>,
}

impl ModelArgs {
    /// The default model of most commands.
    pub const DEFAULT: &'static str = "phak";

    /// `--model` as given, or `default`.
    pub fn name_or<'a>(&'a self, default: &'a str) -> &'a str {
        self.model.as_deref().unwrap_or(default)
    }

    /// The files given (model, lengths), which no output may overwrite.
    pub fn inputs(&self) -> Vec<String> {
        let mut files: Vec<String> = self.model.iter().cloned().collect();
        files.extend(
            self.anthropometry
                .as_ref()
                .map(|p| p.to_string_lossy().into_owned()),
        );
        files
    }

    /// Loads the model (`default` when `--model` is not given), showing the import's notes
    /// and the lengths file's warnings. Lengths for a gait2392 model are refused before the
    /// lengths file is read.
    pub fn load_or(&self, default: &str, diagnostics: &Diagnostics) -> anyhow::Result<Model> {
        Ok(self.load_or_keeping(default, diagnostics)?.0)
    }

    /// [`ModelArgs::load_or`], also returning the warnings it showed (for a report that lists
    /// them).
    pub fn load_or_keeping(
        &self,
        default: &str,
        diagnostics: &Diagnostics,
    ) -> anyhow::Result<(Model, Vec<Warning>)> {
        let (mut model, notes) = Model::load(self.name_or(default), None)?;
        diagnostics.notes(notes);
        let mut kept = Vec::new();
        if let Some(path) = &self.anthropometry {
            let (Model::Hak { stated } | Model::Phak { stated }) = &mut model else {
                return Err(ModelError::LengthsNotApplicable(model.name().to_string()).into());
            };
            let (lengths, warnings) = anthropometry::read(path)?;
            diagnostics.warn(warnings.iter().cloned());
            kept = warnings;
            *stated = Some(lengths);
        }
        Ok((model, kept))
    }

    /// [`ModelArgs::load_or`] with the default model, [`ModelArgs::DEFAULT`].
    pub fn load(&self, diagnostics: &Diagnostics) -> anyhow::Result<Model> {
        self.load_or(Self::DEFAULT, diagnostics)
    }
}
