//! `qgait fuse`: raw IMU recordings (gyroscope, accelerometer and magnetometer) to an OpenSense
//! orientation `.sto`, one column per sensor, with the kernel's VQF ([`qgait_fusion`]).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use qgait_fusion::{fuse, read_csv, read_xsens, score, write_orientations, Mode, RawRecording};
use qgait_kernel::imu::Segment;
use qgait_opensim::diagnostics::{Warning, WarningText};

use crate::cli::diagnostics::Diagnostics;
use crate::cli::output::{refuse_overwrite, write_output_with};
use crate::progress::Progress;

/// Arguments of `qgait fuse`.
#[derive(Debug, Args)]
pub struct FuseArgs {
    /// One raw recording per sensor: a CSV in the shared layout (header names `time`,
    /// `gyr_x..z` rad/s, `acc_x..z` m/s², `mag_x..z` µT; other columns ignored; the sampling
    /// period from the times) or an Xsens MT Manager .txt with `Acc_*`, `Gyr_*`, `Mag_*`
    /// columns. Several files must have the same times.
    #[arg(required = true, value_name = "RAW")]
    pub inputs: Vec<PathBuf>,
    /// 9d: gyroscope, accelerometer and magnetometer, orientation in ENU (x east, y magnetic
    /// north, z up); 6d: without the magnetometer (z up, heading the sensor's own at the start).
    #[arg(long, value_enum)]
    pub mode: ModeArg,
    /// Each sensor's column name, in the order of the files (default: the file's stem). Name
    /// them as the model's IMUs (`pelvis_imu`, `femur_r_imu`, ...) for `qgait imu`.
    #[arg(long, value_name = "NAME")]
    pub name: Vec<String>,
    /// The sampling rate (Hz) of Xsens files without a `// Update Rate` comment.
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Prints BROAD's error metric (total, heading and inclination RMSE against the files'
    /// `opt_w..z` reference, over the rows with `movement` = 1) for every file that has one,
    /// as a Markdown table on stdout.
    #[arg(long)]
    pub score: bool,
    /// Scores against the reference of other files in the same layout (one per input, in
    /// order, with the same times): the originals of copies whose `opt_*` cells are empty, as
    /// an estimator is given them. Implies --score.
    #[arg(long, value_name = "ORIGINAL.csv")]
    pub truth: Vec<PathBuf>,
    /// Output orientation .sto (DataType=Quaternion, one `w,x,y,z` column per sensor).
    #[arg(short, long, value_name = "ORIENTATIONS.sto")]
    pub output: PathBuf,
}

/// `--mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// Gyroscope, accelerometer, magnetometer.
    #[value(name = "9d")]
    NineD,
    /// Gyroscope and accelerometer.
    #[value(name = "6d")]
    SixD,
}

/// Reads one recording by its kind: an Xsens `.txt`, else the CSV layout.
pub(crate) fn read(path: &Path, rate: Option<f64>) -> anyhow::Result<RawRecording> {
    let xsens = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("txt"));
    Ok(if xsens {
        read_xsens(path, rate)?
    } else {
        read_csv(path)?
    })
}

/// Runs `qgait fuse`.
pub(crate) fn run_fuse(a: FuseArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let inputs: Vec<String> = a.inputs.iter().map(|p| p.display().to_string()).collect();
    refuse_overwrite([a.output.as_path()], &inputs)?;
    if let Some(r) = a.rate {
        if !(r.is_finite() && r > 0.0) {
            bail!("--rate {r}: expected a sampling rate in Hz above 0");
        }
    }
    if !a.name.is_empty() && a.name.len() != a.inputs.len() {
        bail!(
            "{} --name for {} files: give one per file, in their order, or none",
            a.name.len(),
            a.inputs.len()
        );
    }
    let names: Vec<String> = if a.name.is_empty() {
        a.inputs
            .iter()
            .map(|p| {
                p.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default()
            })
            .collect()
    } else {
        a.name.clone()
    };
    for (i, n) in names.iter().enumerate() {
        if n.is_empty() || n.contains(|c: char| c.is_whitespace() || c == ',') {
            bail!("sensor name `{n}` ({}): a column name needs at least one character and no spaces, tabs or commas (give --name)", inputs[i]);
        }
        if names[..i].contains(n) {
            bail!("two sensors named `{n}`: give each file its own --name");
        }
    }
    let unknown: Vec<&str> = names
        .iter()
        .filter(|n| Segment::from_name(n).is_none())
        .map(String::as_str)
        .collect();
    if !unknown.is_empty() {
        diagnostics.warn([Warning::Ignored(WarningText {
 at: None,
 detail: format!("column(s) {} are not IMUs of the lower-body set, which `qgait imu` reads ({}); name them with --name", unknown.join(", "), Segment::ALL.map(Segment::imu_label).join(", ")),
})]);
    }
    if !a.truth.is_empty() && a.truth.len() != a.inputs.len() {
        bail!(
            "{} --truth for {} files: give one per file, in their order",
            a.truth.len(),
            a.inputs.len()
        );
    }
    let mode = match a.mode {
        ModeArg::NineD => Mode::NineD,
        ModeArg::SixD => Mode::SixD,
    };
    let mut recordings = Vec::with_capacity(a.inputs.len());
    for p in &a.inputs {
        let r = read(p, a.rate)?;
        if let Some(first) = recordings.first() {
            same_times(first, &r)?;
        }
        recordings.push(r);
    }
    let total: usize = recordings.iter().map(RawRecording::len).sum();
    let progress = Progress::new(total as u64, "fuse", diagnostics.quiet());
    let mut columns = Vec::with_capacity(recordings.len());
    for r in &recordings {
        let mut last = 0;
        let q = fuse(r, mode, |done| {
            progress.inc((done - last) as u64);
            last = done;
        })?;
        columns.push(q);
    }
    progress.finish();
    let first = &recordings[0];
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let column_refs: Vec<&[[f64; 4]]> = columns.iter().map(Vec::as_slice).collect();
    write_output_with(Some(&a.output), |out| {
        write_orientations(
            out,
            1.0 / first.period,
            &first.times,
            &name_refs,
            &column_refs,
        )?;
        Ok(())
    })?;
    diagnostics.done(format_args!(
        "wrote {} ({} sensor(s), {} rows at {:.3} Hz, {})",
        a.output.display(),
        names.len(),
        first.len(),
        1.0 / first.period,
        match mode {
            Mode::NineD => "9D, ENU",
            Mode::SixD => "6D, z up",
        }
    ));
    if !a.truth.is_empty() {
        let mut truths = Vec::with_capacity(a.truth.len());
        for (p, r) in a.truth.iter().zip(&recordings) {
            let t = read_csv(p)?;
            same_times(r, &t)?;
            truths.push(t);
        }
        print_scores(&truths, &names, &columns, mode, diagnostics)?;
    } else if a.score {
        print_scores(&recordings, &names, &columns, mode, diagnostics)?;
    }
    Ok(())
}

/// Several files must sample at the same times (within a quarter period).
fn same_times(first: &RawRecording, other: &RawRecording) -> anyhow::Result<()> {
    if other.len() != first.len() {
        bail!(
            "{}: {} samples, but {} has {}: several sensors must have the same times",
            other.source,
            other.len(),
            first.source,
            first.len()
        );
    }
    for (k, (a, b)) in first.times.iter().zip(&other.times).enumerate() {
        if (a - b).abs() > 0.25 * first.period {
            bail!(
                "{}:{}: time {b}, but {}:{} has {a} (several sensors must have the same times)",
                other.source,
                other.lines[k],
                first.source,
                first.lines[k]
            );
        }
    }
    Ok(())
}

/// BROAD's metric per sensor with a reference, as a Markdown table.
fn print_scores(
    recordings: &[RawRecording],
    names: &[String],
    columns: &[Vec<[f64; 4]>],
    mode: Mode,
    diagnostics: &Diagnostics,
) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let mut any = false;
    writeln!(
        out,
        "| sensor | rows scored | total RMSE (°) | heading RMSE (°) | inclination RMSE (°) |"
    )?;
    writeln!(out, "|---|---:|---:|---:|---:|")?;
    for ((r, n), q) in recordings.iter().zip(names).zip(columns) {
        if let Some(([total, heading, inclination], rows)) = score(r, q) {
            any = true;
            writeln!(
                out,
                "| {n} | {rows} | {total:.4} | {heading:.4} | {inclination:.4} |"
            )?;
        }
    }
    out.flush().context("cannot write to standard output")?;
    if !any {
        bail!("--score: no file has reference orientations (opt_w..z) in a scored row");
    }
    if mode == Mode::SixD {
        diagnostics
            .notes(["6D: only the inclination RMSE is meaningful (the heading is arbitrary)"]);
    }
    Ok(())
}
