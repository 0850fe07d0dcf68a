//! The commands of the gait2392 work: `fk --model gait2392|SUBJECT.toml [--points]`,
//! `model import`, `export` and `fidelity` (argument definitions and their runs; the command
//! enum in [`crate::cli`] only dispatches here).

use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Args, Subcommand};

use crate::cli::{
    load_anthropometry, refuse_overwrite, with_path, write_output, write_output_with, OutputFile,
};
use crate::model::fidelity;
use crate::model::spec::{self, ModelSpec, PointModel};
use crate::model::subject;
use crate::motion::source::{default_label, load_motion, MotionRows};
use crate::opensim::export;
use crate::opensim::mot::Warning;
use crate::opensim::osim;
use crate::progress::Progress;

/// `qgait fk` arguments.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    pub motion: String,
    /// Kinematic model: `hak`, `phak`, `gait2392` (OpenSim's chain, generic), a SUBJECT.toml
    /// written by `qgait model import`, or an OpenSim model .osim (imported on the fly).
    #[arg(
        long,
        default_value = "phak",
        value_name = "hak|phak|gait2392|SUBJECT.toml|MODEL.osim"
    )]
    pub model: String,
    /// Segment lengths (TOML: pelvis_half_width, femur, tibia, foot, each optionally _r/_l);
    /// default gait2392. HAK and PHAK only.
    #[arg(long, value_name = "FILE.toml")]
    pub anthropometry: Option<PathBuf>,
    /// Also the subtalar and MTP joint centres (gait2392 models): columns
    /// `subtalar_r_x..z, mtp_r_x..z, subtalar_l_x..z, mtp_l_x..z` after the standard ones.
    #[arg(long)]
    pub points: bool,
    /// Output CSV file (default: standard output).
    #[arg(short, long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
}

/// `qgait model` subcommands.
#[derive(Debug, Subcommand)]
pub enum ModelCommand {
    /// Reads the leg chain of a gait2392-family OpenSim model (.osim, 3.x or 4.x) into a
    /// SUBJECT.toml for `--model`.
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

/// `qgait export` arguments.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    pub motion: String,
    /// Kinematic model: hak, phak (the default everywhere), gait2392, a SUBJECT.toml or an
    /// OpenSim model .osim.
    #[arg(
        long,
        default_value = "phak",
        value_name = "hak|phak|gait2392|SUBJECT.toml|MODEL.osim"
    )]
    pub model: String,
    /// Segment lengths for HAK/PHAK (TOML), default gait2392.
    #[arg(long, value_name = "FILE.toml")]
    pub anthropometry: Option<PathBuf>,
    /// Also subtalar and MTP (gait2392 models).
    #[arg(long)]
    pub points: bool,
    /// OpenSim marker file to write.
    #[arg(long, value_name = "OUT.trc", required_unless_present = "sto")]
    pub trc: Option<PathBuf>,
    /// OpenSim table to write.
    #[arg(long, value_name = "OUT.sto")]
    pub sto: Option<PathBuf>,
}

/// `qgait fidelity` arguments.
#[derive(Debug, Args)]
pub struct FidelityArgs {
    /// Motion files (.mot/.sto) or `builtin:...`.
    #[arg(required = true)]
    pub motions: Vec<String>,
    /// Label of each motion, in order (default: the file stem).
    #[arg(long = "label", value_name = "NAME")]
    pub labels: Vec<String>,
    /// Output Markdown file (default: standard output).
    #[arg(short, long, value_name = "OUT.md")]
    pub output: Option<PathBuf>,
}

/// The files a motion command reads: the motion, the model (when a file) and the lengths.
fn inputs<'a>(motion: &'a str, model: &'a str, anthropometry: &'a Option<PathBuf>) -> Vec<&'a str> {
    let mut v = vec![motion, model];
    v.extend(anthropometry.as_ref().and_then(|p| p.to_str()));
    v
}

/// Prints warnings unless quiet.
fn warner(quiet: bool) -> impl Fn(Vec<Warning>) {
    move |warnings: Vec<Warning>| {
        if !quiet {
            for w in warnings {
                eprintln!("warning: {w}");
            }
        }
    }
}

/// The model and the rows of a motion, ready to run.
struct Prepared {
    model: PointModel,
    rows: MotionRows,
}

/// Loads the model and opens the motion (its header warnings printed).
fn prepare(
    motion: &str,
    model: &str,
    anthropometry: Option<&Path>,
    points: bool,
    quiet: bool,
) -> anyhow::Result<Prepared> {
    let warn = warner(quiet);
    let (spec, notes) = ModelSpec::load_with_notes(model).map_err(anyhow::Error::msg)?;
    if !quiet {
        notes.iter().for_each(|n| eprintln!("note: {n}"));
    }
    if anthropometry.is_some() && matches!(spec, ModelSpec::Gait2392 { .. }) {
        anyhow::bail!(
            "--anthropometry sets HAK/PHAK lengths; a gait2392 subject model comes from `qgait model import` (--model SUBJECT.toml)"
        );
    }
    let anthro = load_anthropometry(anthropometry, &warn)?;
    let model = PointModel::new(&spec, &anthro, points).map_err(anyhow::Error::msg)?;
    let (rows, w) = MotionRows::open(motion)?;
    warn(w);
    Ok(Prepared { model, rows })
}

/// Runs `qgait fk`: each row is computed and written before the next is read.
pub fn run_fk(a: FkArgs, quiet: bool) -> anyhow::Result<()> {
    // No bar while CSV goes to the same terminal.
    let csv_on_terminal = a.output.is_none() && io::stdout().is_terminal();
    refuse_overwrite(
        a.output.as_deref(),
        &inputs(&a.motion, &a.model, &a.anthropometry),
    )?;
    let warn = warner(quiet);
    let Prepared { model, rows } = prepare(
        &a.motion,
        &a.model,
        a.anthropometry.as_deref(),
        a.points,
        quiet,
    )?;
    let progress = Progress::new(
        rows.size_hint().unwrap_or(0) as u64,
        "fk",
        quiet || csv_on_terminal,
    );
    let mut warnings = Vec::new();
    write_output_with(a.output.as_deref(), |out| {
        writeln!(out, "{}", spec::csv_header(&model.names()))?;
        warnings = model.run(rows, &warn, |t, points| {
            progress.inc(1);
            Ok(spec::write_csv_row(out, t, points)?)
        })?;
        Ok(())
    })?;
    progress.finish();
    warn(warnings);
    Ok(())
}

/// Runs `qgait model ...`.
pub fn run_model(c: ModelCommand, quiet: bool) -> anyhow::Result<()> {
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
            let imported = osim::import(
                &text,
                &shown,
                marker_text.as_ref().map(|(t, s)| (t.as_str(), s.as_str())),
            )
            .map_err(anyhow::Error::msg)?;
            // The kernel must accept what was read (knot counts, axes).
            qgait_kernel::Gait2392::<f64>::new(&imported.geometry)
                .map_err(|e| anyhow::anyhow!("{shown}: leg chain rejected by the kernel: {e}"))?;
            let text = subject::to_toml(&imported.geometry, &imported.notes);
            std::fs::write(&output, text)
                .with_context(|| format!("{}: cannot write", output.display()))?;
            if !quiet {
                for n in imported.notes.iter().skip(1) {
                    eprintln!("note: {n}");
                }
                eprintln!("wrote {}", output.display());
            }
            Ok(())
        }
    }
}

/// Runs `qgait export`: rows are written as they are computed; for a `.trc` a first pass over
/// the motion counts its rows and reads its first and last time (the header needs them).
pub fn run_export(a: ExportArgs, quiet: bool) -> anyhow::Result<()> {
    refuse_overwrite(
        a.trc.iter().chain(&a.sto).map(PathBuf::as_path),
        &inputs(&a.motion, &a.model, &a.anthropometry),
    )?;
    let warn = warner(quiet);
    let trc_shape = match &a.trc {
        Some(_) => Some(time_span(&a.motion)?),
        None => None,
    };
    let Prepared { model, rows } = prepare(
        &a.motion,
        &a.model,
        a.anthropometry.as_deref(),
        a.points,
        quiet,
    )?;
    let names = model.names();
    let progress = Progress::new(rows.size_hint().unwrap_or(0) as u64, "export", quiet);
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
    let warnings = model.run(rows, &warn, |t, points| {
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
    warn(warnings);
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

/// Runs `qgait fidelity`.
pub fn run_fidelity(a: FidelityArgs, quiet: bool) -> anyhow::Result<()> {
    if a.labels.len() > a.motions.len() {
        anyhow::bail!(
            "{} --label values for {} motions",
            a.labels.len(),
            a.motions.len()
        );
    }
    let specs: Vec<&str> = a.motions.iter().map(String::as_str).collect();
    refuse_overwrite(a.output.as_deref(), &specs)?;
    let warn = warner(quiet);
    let mut results = Vec::new();
    for (i, spec) in a.motions.iter().enumerate() {
        let (table, w) = load_motion(spec)?;
        warn(w);
        let label = a
            .labels
            .get(i)
            .cloned()
            .unwrap_or_else(|| default_label(spec));
        let (r, w) = fidelity::analyse(&label, &table).map_err(anyhow::Error::msg)?;
        warn(w);
        results.push(r);
    }
    let md = fidelity::markdown(&results);
    write_output(a.output.as_deref(), |out| out.write_all(md.as_bytes()))
}
