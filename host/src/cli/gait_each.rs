//! `qgait gait --each`: many recordings, each analysed on its own (its own report, CSVs and
//! `summary.json` in `DIR/<name>/`), on every core (rayon), and `DIR/recordings.csv` with every
//! recording's headline figures. A recording that fails is a row with its error; the others
//! go on. A study beyond one machine runs one `qgait gait` per recording under the scheduler it
//! has (GNU parallel, Slurm, a cloud batch service): the command holds no state between
//! recordings.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use rayon::prelude::*;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::gait::{run_gait, GaitArgs};
use crate::progress::Progress;

/// The columns of `recordings.csv` after `recording,output,error`: `summary.json`'s figures.
const FIGURES: [&str; 6] = qgait_gait::files::HEADLINE;

/// One output folder per recording: its file stem, made unique by a number where two
/// recordings share one.
fn folders(motions: &[String]) -> Vec<String> {
    let stems: Vec<String> = motions
        .iter()
        .map(|m| qgait_model::motion::source::default_label(m))
        .map(|s| {
            s.chars()
                .map(|c| {
                    if c.is_alphanumeric() || "-_.".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect()
        })
        .collect();
    stems
        .iter()
        .enumerate()
        .map(|(i, s)| {
            if stems.iter().filter(|t| *t == s).count() > 1 {
                format!("{s}-{}", i + 1)
            } else {
                s.clone()
            }
        })
        .collect()
}

/// Runs `qgait gait --each`.
pub fn run(args: GaitArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let folders = folders(&args.motions);
    let progress = Progress::new(
        args.motions.len() as u64,
        "gait --each",
        diagnostics.quiet(),
    );
    let failed = AtomicUsize::new(0);
    let rows: Vec<Vec<String>> = args
        .motions
        .par_iter()
        .zip(&folders)
        .map(|(motion, folder)| {
            let out = args.output.join(folder);
            let one = GaitArgs {
                motions: vec![motion.clone()],
                output: out.clone(),
                each: false,
                ..args.clone()
            };
            // Each recording's warnings are in its own report; the terminal gets the table.
            let result = run_gait(one, &Diagnostics::new(true));
            progress.inc(1);
            let mut row = vec![motion.clone(), out.display().to_string()];
            match result {
                Ok(()) => {
                    row.push(String::new());
                    row.extend(figures(&out));
                }
                Err(e) => {
                    failed.fetch_add(1, Ordering::Relaxed);
                    row.push(format!("{e:#}"));
                    row.extend(FIGURES.iter().map(|_| String::new()));
                }
            }
            row
        })
        .collect();
    progress.finish();
    std::fs::create_dir_all(&args.output)?;
    let table = args.output.join("recordings.csv");
    write_table(&table, &rows)?;
    let failed = failed.into_inner();
    diagnostics.done(format!(
        "analysed {} of {} recordings; every recording's figures in {}",
        rows.len() - failed,
        rows.len(),
        table.display()
    ));
    if failed > 0 {
        anyhow::bail!(
            "{failed} of {} recordings failed (their errors are in {})",
            rows.len(),
            table.display()
        );
    }
    Ok(())
}

/// The headline figures of a recording's `summary.json` (empty where absent).
fn figures(out: &Path) -> Vec<String> {
    let summary: Option<serde_json::Value> = std::fs::read_to_string(out.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    FIGURES
        .iter()
        .map(|f| {
            summary
                .as_ref()
                .and_then(|s| s["headline"][f]["value"].as_f64())
                .map_or(String::new(), |v| format!("{v:.4}"))
        })
        .collect()
}

/// `recordings.csv`.
fn write_table(path: &PathBuf, rows: &[Vec<String>]) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    let mut header = vec!["recording", "output", "error"];
    header.extend(FIGURES);
    w.write_record(&header)?;
    for r in rows {
        w.write_record(r)?;
    }
    w.flush()?;
    Ok(())
}
