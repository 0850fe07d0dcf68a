//! The `qgait` command line: argument definitions and the commands.

pub(crate) mod config;
pub mod device;
pub(crate) mod diagnostics;
pub(crate) mod export;
pub(crate) mod fidelity;
pub(crate) mod fk;
pub(crate) mod gait;
pub(crate) mod imu;
pub(crate) mod jsonl;
pub(crate) mod live;
pub(crate) mod model;
pub(crate) mod model_args;

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Parser, Subcommand};

use crate::cli::diagnostics::Diagnostics;
use crate::progress::Progress;
use qgait_figures::{self as report, Analysis};
use qgait_model::motion::source::{default_label, load_motion};
use qgait_opensim::diagnostics::Warning;

/// Forward kinematics of the human lower limbs with quaternions (HAK, PHAK, gait2392 and imported OpenSim leg models).
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
    Fk(crate::cli::fk::FkArgs),
    /// Figures and metrics of one or more gaits overlaid (the paper's Figs 5-10).
    Report {
        /// Motion files (.mot/.sto), `builtin:...`, or frames CSVs of a device (`qgait emulate
        /// --frames-csv`, drawn as they are); the first is the reference for the hip shift.
        #[arg(required = true)]
        motions: Vec<String>,
        /// Label of each motion in legends and tables, in order (default: the file stem).
        #[arg(long = "label", value_name = "NAME")]
        labels: Vec<String>,
        /// The model: hak or phak (default), with its segment lengths.
        #[command(flatten)]
        model: crate::cli::model_args::ModelArgs,
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
    /// OpenSim models: `model import MODEL.osim -o SUBJECT.toml|CHAIN.toml`.
    #[command(subcommand)]
    Model(crate::cli::model::ModelCommand),
    /// Computed joint centres as an OpenSim marker file (.trc) and table (.sto).
    Export(crate::cli::export::ExportArgs),
    /// How far PHAK (8 DoF) is from gait2392, per point, and what each feature costs (Markdown).
    Fidelity(crate::cli::fidelity::FidelityArgs),
    /// The frames that configure a hub (model, lengths, policy, window), to send to its UART.
    Config(crate::cli::config::ConfigArgs),
    /// The byte stream the IMU nodes send for a motion (one JointAngle packet per joint per row).
    Packets(crate::cli::device::PacketsArgs),
    /// Decodes a hub log (pose frames, status; damaged frames reported and skipped).
    Decode(crate::cli::device::DecodeArgs),
    /// Recomputes every pose frame of a hub log with the f64 kernel; fails on errors or gaps.
    Verify(crate::cli::device::VerifyArgs),
    /// Runs the hub firmware under QEMU with a motion streamed into its UART.
    Emulate(crate::cli::device::EmulateArgs),
    /// Joint angles (gait2392, .mot in degrees) from IMU segment orientations (OpenSim
    /// orientation .sto), calibrated on a static pose as OpenSim's OpenSense does it.
    Imu(crate::cli::imu::ImuArgs),
    /// Clinical gait analysis: events, cycles, spatiotemporal parameters, normative bands and
    /// the Gait Profile Score, as one HTML report and CSVs.
    Gait(crate::cli::gait::GaitArgs),
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let diagnostics = Diagnostics::new(cli.quiet);
    let warn = |warnings: Vec<Warning>| diagnostics.warn(warnings);
    match cli.command {
        Command::Fk(args) => crate::cli::fk::run_fk(args, &diagnostics)?,
        Command::Imu(args) => crate::cli::imu::run_imu(args, &diagnostics)?,
        Command::Gait(args) => crate::cli::gait::run_gait(args, &diagnostics)?,
        Command::Report {
            motions,
            labels,
            model,
            output,
        } => {
            if labels.len() > motions.len() {
                anyhow::bail!(
                    "{} --label values for {} motions",
                    labels.len(),
                    motions.len()
                );
            }
            let model = model.load(&diagnostics)?;
            let mut tables = Vec::new();
            // Frames CSVs (a device's poses, `qgait emulate --frames-csv`) by position.
            let mut frames = Vec::new();
            for (i, spec) in motions.iter().enumerate() {
                let label = labels
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| default_label(spec));
                if qgait_device::frames_csv::is_frames_csv(spec) {
                    let text = std::fs::read_to_string(spec)
                        .with_context(|| format!("{spec}: cannot read"))?;
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
            let progress = Progress::new(rows as u64 + report::FIGURE_COUNT, "report", cli.quiet);
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
        }
        Command::Motion { motion, output } => {
            refuse_overwrite(output.as_deref(), &[&motion])?;
            let (table, w) = load_motion(&motion)?;
            warn(w);
            write_output(output.as_deref(), |out| table.write_mot(out))?;
        }
        Command::Model(c) => crate::cli::model::run_model(c, &diagnostics)?,
        Command::Export(args) => crate::cli::export::run_export(args, &diagnostics)?,
        Command::Fidelity(args) => crate::cli::fidelity::run_fidelity(args, &diagnostics)?,
        Command::Config(args) => crate::cli::config::run_config(args, &diagnostics)?,
        Command::Packets(args) => crate::cli::device::run_packets(args, cli.quiet)?,
        Command::Decode(args) => crate::cli::device::run_decode(args, cli.quiet)?,
        Command::Verify(args) => {
            if !crate::cli::device::run_verify(args, cli.quiet)? {
                anyhow::bail!("verification failed");
            }
        }
        Command::Emulate(args) => {
            if !crate::cli::device::run_emulate(args, cli.quiet)? {
                anyhow::bail!("emulation failed");
            }
        }
    }
    Ok(())
}

/// Refuses to write any of `outputs` over one of `inputs` (motion specs, model or other files
/// given on the same command line): `qgait fk x.mot -o x.mot` would destroy its own input.
/// Paths that do not exist yet (and `builtin:` specs) cannot be the same file as an input.
/// Also refuses one file given as two outputs (`export --trc x --sto x`): the second would
/// replace the first.
pub(crate) fn refuse_overwrite<'a>(
    outputs: impl IntoIterator<Item = &'a Path>,
    inputs: &[impl AsRef<str>],
) -> anyhow::Result<()> {
    let outputs: Vec<&Path> = outputs.into_iter().collect();
    let identities: Vec<Option<PathBuf>> = outputs.iter().map(|o| file_identity(o)).collect();
    for (i, a) in identities.iter().enumerate() {
        let same = identities[i + 1..].iter().any(|b| a.is_some() && a == b);
        if same {
            anyhow::bail!(
                "{}: given as two outputs; the second would replace the first",
                outputs[i].display()
            );
        }
    }
    for out in outputs {
        let Ok(out_real) = out.canonicalize() else {
            continue;
        };
        for input in inputs.iter().map(AsRef::as_ref) {
            if Path::new(input).canonicalize().is_ok_and(|i| i == out_real) {
                anyhow::bail!(
                    "{}: this output is also an input ({input}); refusing to overwrite it",
                    out.display()
                );
            }
        }
    }
    Ok(())
}

/// `text` as a finite number above `min`, or equal to it if `or_equal`: what the options that
/// take an amount (seconds, micrometres, years) accept.
pub(crate) fn amount(text: &str, min: f64, or_equal: bool) -> Option<f64> {
    let x: f64 = text.trim().parse().ok()?;
    (x.is_finite() && (x > min || or_equal && x == min)).then_some(x)
}

/// Where `path` is, whether or not it exists yet: its canonical form, or its directory's with
/// its name, or (a directory still to be made) the path made absolute. `None` for a file that
/// is not a regular one (`/dev/null`, a pipe: written directly, any number of times).
fn file_identity(path: &Path) -> Option<PathBuf> {
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        return None;
    }
    if let Ok(real) = path.canonicalize() {
        return Some(real);
    }
    let name = path.file_name()?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    match dir.canonicalize() {
        Ok(dir) => Some(dir.join(name)),
        Err(_) => std::path::absolute(path).ok(),
    }
}

/// A file being written: rows go to a temporary file beside it, renamed to `path` by
/// [`OutputFile::commit`], so that an error half way (a bad row deep in a long motion) leaves no
/// truncated output behind and an earlier file of that name untouched.
/// A path that is not a regular file (`/dev/null`, a named pipe) is written directly.
pub(crate) struct OutputFile {
    path: PathBuf,
    temp: Option<PathBuf>,
    out: Option<BufWriter<File>>,
}

impl OutputFile {
    /// Creates the temporary file for `path`.
    pub(crate) fn create(path: &Path) -> anyhow::Result<Self> {
        let special = std::fs::metadata(path).is_ok_and(|m| !m.is_file());
        let temp = (!special).then(|| {
            let name = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            path.with_file_name(format!(".{name}.qgait-partial"))
        });
        let file = File::create(temp.as_deref().unwrap_or(path))
            .with_context(|| format!("{}: cannot create", path.display()))?;
        Ok(Self {
            path: path.to_path_buf(),
            temp,
            out: Some(BufWriter::with_capacity(1 << 16, file)),
        })
    }

    /// The writer.
    pub(crate) fn writer(&mut self) -> &mut BufWriter<File> {
        self.out.as_mut().expect("not committed")
    }

    /// The file's path, for messages.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes and renames the temporary file to the final path.
    pub(crate) fn commit(mut self) -> anyhow::Result<()> {
        let out = self.out.take().expect("committed once");
        out.into_inner()
            .map_err(|e| e.into_error())
            .with_context(|| format!("{}: cannot write", self.path.display()))?;
        match &self.temp {
            Some(temp) => std::fs::rename(temp, &self.path)
                .with_context(|| format!("{}: cannot write", self.path.display())),
            None => Ok(()),
        }
    }
}

impl Drop for OutputFile {
    fn drop(&mut self) {
        if let (Some(_), Some(temp)) = (self.out.take(), &self.temp) {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Runs `body` on a file (written through an [`OutputFile`]) or on stdout when `path` is
/// `None`. A closed stdout pipe (e.g. `| head`) ends the body without an error.
pub(crate) fn write_output_with(
    path: Option<&Path>,
    body: impl FnOnce(&mut dyn Write) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    match path {
        Some(p) => {
            let mut file = OutputFile::create(p)?;
            body(file.writer()).map_err(|e| with_path(e, p))?;
            file.commit()
        }
        None => {
            let stdout = io::stdout();
            let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
            let result = match body(&mut out) {
                Ok(()) => out.flush().map_err(anyhow::Error::from),
                Err(e) => {
                    // What is still buffered is not passed on: a short motion with an error
                    // leaves standard output empty (a long one has passed on its first rows).
                    let _ = out.into_parts();
                    Err(e)
                }
            };
            match result {
                Err(e) if is_broken_pipe(&e) => Ok(()),
                Err(e) if e.downcast_ref::<io::Error>().is_some() => {
                    Err(e.context("cannot write to standard output"))
                }
                other => other,
            }
        }
    }
}

/// An I/O error of writing `path` gets the path in front; other errors are the input's own.
pub(crate) fn with_path(e: anyhow::Error, path: &Path) -> anyhow::Error {
    if e.downcast_ref::<io::Error>().is_some() {
        e.context(format!("{}: cannot write", path.display()))
    } else {
        e
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.downcast_ref::<io::Error>()
        .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe)
}

/// Writes to a file, or to stdout when `path` is `None`. A closed stdout pipe (e.g. `| head`) is
/// not an error.
pub(crate) fn write_output(
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
