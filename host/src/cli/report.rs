//! `qgait report`: the paper's figures and metrics of one or more gaits overlaid (crate
//! `qgait_figures`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::progress::Progress;
use qgait_figures::{self as report, Analysis};
use qgait_model::motion::source::{default_label, load_motion};
use qgait_opensim::diagnostics::{Location, Warning, WarningText};

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
        let (table, w) = one_cycle(spec, table);
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

/// The figures are drawn over one gait cycle per motion (0-100 % of its rows' time). A
/// recording of several strides (its events found by `qgait gait`'s rules on gait2392) is cut
/// to its first complete right stride, with a warning that says so; one that holds a single
/// cycle (a `builtin:` gait), or whose strides cannot be found, is drawn whole.
fn one_cycle(
    spec: &str,
    table: qgait_opensim::mot::MotionTable,
) -> (qgait_opensim::mot::MotionTable, Vec<Warning>) {
    // A `builtin:` gait is one cycle by construction.
    if spec.starts_with("builtin:") {
        return (table, Vec::new());
    }
    let strides = qgait_model::choice::Model::load("gait2392", None)
        .ok()
        .and_then(|(model, _)| qgait_gait::trial::load(spec, &model).ok())
        .and_then(|(trial, _)| qgait_gait::analyse(trial, qgait_gait::CycleMode::Auto).ok());
    let Some(walk) = strides else {
        return (table, Vec::new());
    };
    let [right, left] = walk.strides();
    let Some(first) = walk.cycles[0].first() else {
        return (table, Vec::new());
    };
    if right + left < 2 {
        return (table, Vec::new());
    }
    let (t0, t1) = (first.start, first.start + first.duration);
    let time = table.time().to_vec();
    let cut = table.without_rows(|r| time[r] < t0 - 1e-9 || time[r] > t1 + 1e-9);
    let detail = format!(
        "{right} right and {left} left strides; the report draws one gait cycle per motion: the first right stride, heel strike at {t0:.3} s to the next at {t1:.3} s (`qgait gait` averages every stride)"
    );
    let warning = Warning::Limitation(WarningText {
        at: Some(Location::file(spec.to_string())),
        detail,
    });
    (cut, vec![warning])
}
