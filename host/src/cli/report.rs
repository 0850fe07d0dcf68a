//! `qgait report`: the paper's figures and metrics of one or more gaits overlaid (crate
//! `qgait_figures`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::progress::Progress;
use qgait_figures::{self as report, Analysis};
use qgait_model::motion::source::{default_label, load_motion};
use qgait_opensim::diagnostics::Warning;

/// `qgait report` arguments.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// Motion files (.mot/.sto), `builtin:...`, or frames CSVs of a device (`qgait emulate
    /// --frames-csv`, drawn as they are); the first is the reference for the hip shift.
    #[arg(required = true)]
    pub motions: Vec<String>,
    /// Label of each motion in legends and tables, in order (default: the file stem).
    #[arg(long = "label", value_name = "NAME")]
    pub labels: Vec<String>,
    /// The model: hak or phak (default), with its segment lengths.
    #[command(flatten)]
    pub model: crate::cli::model_args::ModelArgs,
    /// Output directory (created if needed).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
}

/// Runs `qgait report`.
pub fn run_report(args: ReportArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let warn = |warnings: Vec<Warning>| diagnostics.warn(warnings);
    let ReportArgs {
        motions,
        labels,
        model,
        output,
    } = args;
    if labels.len() > motions.len() {
        anyhow::bail!(
            "{} --label values for {} motions",
            labels.len(),
            motions.len()
        );
    }
    let model = model.load(diagnostics)?;
    let mut tables = Vec::new();
    // Frames CSVs (a device's poses, `qgait emulate --frames-csv`) by position.
    let mut frames = Vec::new();
    for (i, spec) in motions.iter().enumerate() {
        let label = labels
            .get(i)
            .cloned()
            .unwrap_or_else(|| default_label(spec));
        if qgait_device::frames_csv::is_frames_csv(spec) {
            let text =
                std::fs::read_to_string(spec).with_context(|| format!("{spec}: cannot read"))?;
            let mut table = qgait_device::frames_csv::parse(&text, spec)?;
            // Timed frames in time order, as `gait` takes them.
            if table.time.iter().any(Option::is_some) {
                let (ordered, w) = table.in_time_order(spec)?;
                warn(w);
                table = ordered;
            }
            frames.push((i, label, spec.clone(), table));
            continue;
        }
        let (table, w) = load_motion(spec)?;
        warn(w);
        tables.push((label, table));
    }
    let rows: usize = tables.iter().map(|(_, t)| t.rows()).sum();
    let progress = Progress::new(
        rows as u64 + report::FIGURE_COUNT,
        "report",
        diagnostics.quiet(),
    );
    let (mut analysis, w) = Analysis::new(&tables, &model, &|n| progress.inc(n))?;
    warn(w);
    for (i, label, spec, table) in &frames {
        analysis.insert_frames(*i, label, spec, table)?;
    }
    let files = report::write_report(&analysis, &output, &|n| progress.inc(n))?;
    progress.finish();
    diagnostics.done(format!(
        "wrote {} files to {}",
        files.len(),
        output.display()
    ));
    Ok(())
}
