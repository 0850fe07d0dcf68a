//! `qgait export`: computed joint centres as an OpenSim marker file (`.trc`) and table (`.sto`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::fk::{inputs, prepare, Prepared};
use crate::cli::model_args::ModelArgs;
use crate::cli::output::{refuse_overwrite, with_path, OutputFile};
use crate::progress::Progress;
use qgait_model::motion::source::MotionRows;
use qgait_opensim::export;

/// `qgait export` arguments.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    pub motion: String,
    /// The model.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Also subtalar and MTP (gait2392-family and chain models).
    #[arg(long)]
    pub points: bool,
    /// OpenSim marker file to write.
    #[arg(long, value_name = "OUT.trc", required_unless_present = "sto")]
    pub trc: Option<PathBuf>,
    /// OpenSim table to write.
    #[arg(long, value_name = "OUT.sto")]
    pub sto: Option<PathBuf>,
}

/// Runs `qgait export`: rows are written as they are computed; for a `.trc` a first pass over
/// the motion counts its rows and reads its first and last time (the header needs them).
pub fn run_export(a: ExportArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    refuse_overwrite(
        a.trc.iter().chain(&a.sto).map(PathBuf::as_path),
        &inputs(&a.motion, &a.model),
    )?;
    let trc_shape = match &a.trc {
        Some(_) => Some(time_span(&a.motion)?),
        None => None,
    };
    let Prepared { model, rows } = prepare(&a.motion, &a.model, a.points, diagnostics)?;
    let names = model.names();
    let progress = Progress::new(
        rows.size_hint().unwrap_or(0) as u64,
        "export",
        diagnostics.quiet(),
    );
    let mut trc = match (&a.trc, trc_shape) {
        (Some(p), Some((frames, first, last))) => {
            let mut f = OutputFile::create(p)?;
            let file_name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let rate = export::rate(frames, first, last);
            export::write_trc_header(f.writer(), &names, &file_name, frames, rate)
                .with_context(|| format!("{}: cannot write", p.display()))?;
            Some(f)
        }
        _ => None,
    };
    let mut sto = match &a.sto {
        Some(p) => {
            let mut f = OutputFile::create(p)?;
            export::write_sto_header(f.writer(), &names)
                .with_context(|| format!("{}: cannot write", p.display()))?;
            Some(f)
        }
        None => None,
    };
    let mut frame = 0;
    let warnings = model.run::<anyhow::Error>(rows, &|w| diagnostics.warn(w), |t, points| {
        progress.inc(1);
        frame += 1;
        if let Some(f) = &mut trc {
            export::write_trc_row(f.writer(), frame, t, points)
                .map_err(|e| with_path(e.into(), f.path()))?;
        }
        if let Some(f) = &mut sto {
            export::write_sto_row(f.writer(), t, points)
                .map_err(|e| with_path(e.into(), f.path()))?;
        }
        Ok(())
    })?;
    progress.finish();
    if let Some(f) = trc {
        f.commit()?;
    }
    if let Some(f) = sto {
        f.commit()?;
    }
    diagnostics.warn(warnings);
    Ok(())
}

/// The number of rows of a motion and its first and last time, read as it goes.
fn time_span(motion: &str) -> anyhow::Result<(usize, f64, f64)> {
    let (mut rows, _) = MotionRows::open(motion)?;
    let (mut n, mut first, mut last) = (0, 0.0, 0.0);
    while let Some((row, _)) = rows.next_row()? {
        if n == 0 {
            first = row.values[0];
        }
        last = row.values[0];
        n += 1;
    }
    Ok((n, first, last))
}
