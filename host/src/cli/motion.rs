//! `qgait motion`: a motion (e.g. a built-in gait) written as an OpenSim `.mot` file.

use std::path::PathBuf;

use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::output::{refuse_overwrite, write_output};
use qgait_model::motion::source::load_motion;

/// `qgait motion` arguments.
#[derive(Debug, Args)]
pub struct MotionArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    pub motion: String,
    /// Output .mot file (default: standard output).
    #[arg(short, long, value_name = "OUT.mot")]
    pub output: Option<PathBuf>,
}

/// Runs `qgait motion`.
pub fn run_motion(args: MotionArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let MotionArgs { motion, output } = args;
    refuse_overwrite(output.as_deref(), &[&motion])?;
    let (table, w) = load_motion(&motion)?;
    diagnostics.warn(w);
    write_output(output.as_deref(), |out| table.write_mot(out))?;
    Ok(())
}
