//! The commands of the gait2392 work: `fk --model gait2392|SUBJECT.toml [--points]`,
//! `model import`, `export` and `fidelity` (argument definitions and their runs; the command
//! enum in [`crate::cli`] only dispatches here).

use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Args, Subcommand};

use crate::cli::{load_anthropometry, refuse_overwrite, write_output};
use crate::export;
use crate::fidelity;
use crate::model_spec::{self, ModelSpec, PointTrack};
use crate::mot::Warning;
use crate::osim_import;
use crate::progress::Progress;
use crate::source::{default_label, load_motion};
use crate::subject;

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

/// Loads the motion and computes the model's points.
fn track(
    motion: &str,
    model: &str,
    anthropometry: Option<&Path>,
    points: bool,
    quiet: bool,
    show_progress: bool,
) -> anyhow::Result<PointTrack> {
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
    let (table, w) = load_motion(motion)?;
    warn(w);
    let progress = Progress::new(table.rows() as u64, "fk", quiet || !show_progress);
    let (track, w) = model_spec::compute(&spec, &table, &anthro, points, || progress.inc(1))
        .map_err(anyhow::Error::msg)?;
    progress.finish();
    warn(w);
    Ok(track)
}

/// Runs `qgait fk`.
pub fn run_fk(a: FkArgs, quiet: bool) -> anyhow::Result<()> {
    // No bar while CSV goes to the same terminal.
    let csv_on_terminal = a.output.is_none() && io::stdout().is_terminal();
    refuse_overwrite(
        a.output.as_deref(),
        &inputs(&a.motion, &a.model, &a.anthropometry),
    )?;
    let t = track(
        &a.motion,
        &a.model,
        a.anthropometry.as_deref(),
        a.points,
        quiet,
        !csv_on_terminal,
    )?;
    write_output(a.output.as_deref(), |out| {
        model_spec::write_csv(out, &t, || {})
    })
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
            let imported = osim_import::import(
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

/// Runs `qgait export`.
pub fn run_export(a: ExportArgs, quiet: bool) -> anyhow::Result<()> {
    refuse_overwrite(
        a.trc.iter().chain(&a.sto).map(PathBuf::as_path),
        &inputs(&a.motion, &a.model, &a.anthropometry),
    )?;
    let t = track(
        &a.motion,
        &a.model,
        a.anthropometry.as_deref(),
        a.points,
        quiet,
        true,
    )?;
    if let Some(p) = &a.trc {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        write_output(Some(p), |out| export::write_trc(out, &t, &name))?;
    }
    if let Some(p) = &a.sto {
        write_output(Some(p), |out| export::write_sto(out, &t))?;
    }
    Ok(())
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
