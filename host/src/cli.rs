//! The `qgait` command line: argument definitions and the commands.

use std::fs::File;
use std::io::{self, BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Parser, Subcommand};
use qgait_kernel::anthropometry::Anthropometry;

use crate::kinematics::{self, Evaluator, Model};
use crate::mot::Warning;
use crate::progress::Progress;
use crate::report::{self, Analysis};
use crate::source::{default_label, load_motion};
use crate::{anthropometry, fk_csv};

/// Forward kinematics of the human lower limbs with quaternions (HAK and PHAK models).
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
    Fk {
        /// Motion file (.mot/.sto) or `builtin:...`.
        motion: String,
        /// Kinematic model.
        #[arg(long, value_enum, default_value = "phak")]
        model: Model,
        /// Segment lengths (TOML: pelvis_half_width, femur, tibia, foot, each optionally _r/_l);
        /// default gait2392.
        #[arg(long, value_name = "FILE.toml")]
        anthropometry: Option<PathBuf>,
        /// Output CSV file (default: standard output).
        #[arg(short, long, value_name = "OUT.csv")]
        output: Option<PathBuf>,
    },
    /// Figures and metrics of one or more gaits overlaid (the paper's Figs 5-10).
    Report {
        /// Motion files (.mot/.sto) or `builtin:...`; the first is the reference for the hip shift.
        #[arg(required = true)]
        motions: Vec<String>,
        /// Label of each motion in legends and tables, in order (default: the file stem).
        #[arg(long = "label", value_name = "NAME")]
        labels: Vec<String>,
        /// Segment lengths (TOML), default gait2392.
        #[arg(long, value_name = "FILE.toml")]
        anthropometry: Option<PathBuf>,
        /// Output directory (created if needed).
        #[arg(short, long, value_name = "DIR")]
        output: PathBuf,
    },
    /// Writes a motion (e.g. a built-in gait) as an OpenSim .mot file.
    Motion {
        /// Motion file (.mot/.sto) or `builtin:...`.
        motion: String,
        /// Output .mot file (default: standard output).
        #[arg(short, long, value_name = "OUT.mot")]
        output: Option<PathBuf>,
    },
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let warn = |warnings: Vec<Warning>| {
        if !cli.quiet {
            for w in warnings {
                eprintln!("warning: {w}");
            }
        }
    };
    match cli.command {
        Command::Fk {
            motion,
            model,
            anthropometry,
            output,
        } => {
            let anthro = load_anthropometry(anthropometry.as_deref(), &warn)?;
            let (table, w) = load_motion(&motion)?;
            warn(w);
            let (angles, w) = kinematics::phak_angles(&table).map_err(anyhow::Error::msg)?;
            if model == Model::Phak {
                warn(w);
            }
            let evaluator = Evaluator::new(model, &anthro).map_err(anyhow::Error::msg)?;
            // No bar while CSV goes to the same terminal.
            let csv_on_terminal = output.is_none() && io::stdout().is_terminal();
            let progress = Progress::new(angles.len() as u64, "fk", cli.quiet || csv_on_terminal);
            write_output(output.as_deref(), |out| {
                fk_csv::write_header(out)?;
                for (t, a) in table.time().iter().zip(&angles) {
                    fk_csv::write_row(out, *t, &evaluator.pose(a))?;
                    progress.inc(1);
                }
                Ok(())
            })?;
            progress.finish();
        }
        Command::Report {
            motions,
            labels,
            anthropometry,
            output,
        } => {
            if labels.len() > motions.len() {
                anyhow::bail!(
                    "{} --label values for {} motions",
                    labels.len(),
                    motions.len()
                );
            }
            let anthro = load_anthropometry(anthropometry.as_deref(), &warn)?;
            let mut tables = Vec::new();
            for (i, spec) in motions.iter().enumerate() {
                let (table, w) = load_motion(spec)?;
                warn(w);
                let label = labels
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| default_label(spec));
                tables.push((label, table));
            }
            let rows: usize = tables.iter().map(|(_, t)| t.rows()).sum();
            let progress = Progress::new(rows as u64 + report::FIGURE_COUNT, "report", cli.quiet);
            let (analysis, w) = Analysis::new(&tables, &anthro, &progress)?;
            warn(w);
            let files = report::write_report(&analysis, &output, &progress)?;
            progress.finish();
            if !cli.quiet {
                eprintln!("wrote {} files to {}", files.len(), output.display());
            }
        }
        Command::Motion { motion, output } => {
            let (table, w) = load_motion(&motion)?;
            warn(w);
            write_output(output.as_deref(), |out| table.write_mot(out))?;
        }
    }
    Ok(())
}

fn load_anthropometry(
    path: Option<&Path>,
    warn: &impl Fn(Vec<Warning>),
) -> anyhow::Result<Anthropometry<f64>> {
    match path {
        None => Ok(Anthropometry::gait2392()),
        Some(p) => {
            let (a, w) = anthropometry::read(p).map_err(anyhow::Error::msg)?;
            warn(w);
            Ok(a)
        }
    }
}

/// Writes to a file, or to stdout when `path` is `None`. A closed stdout pipe (e.g. `| head`) is
/// not an error.
fn write_output(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> anyhow::Result<()> {
    match path {
        Some(p) => {
            let file =
                File::create(p).with_context(|| format!("{}: cannot create", p.display()))?;
            let mut out = BufWriter::new(file);
            body(&mut out)
                .and_then(|_| out.flush())
                .with_context(|| format!("{}: cannot write", p.display()))
        }
        None => {
            let stdout = io::stdout();
            let mut out = BufWriter::new(stdout.lock());
            match body(&mut out).and_then(|_| out.flush()) {
                Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Ok(()),
                other => other.context("cannot write to standard output"),
            }
        }
    }
}
