//! `qgait export`: computed joint centres as an OpenSim marker file (`.trc`) and table (`.sto`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::fk::{inputs, prepare, Prepared};
use crate::cli::model_args::ModelArgs;
use crate::cli::output::{refuse_overwrite, with_path, OutputFile};
use crate::progress::Progress;
use qgait_kernel::Vec3;
use qgait_model::motion::source::MotionRows;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::export;
use qgait_opensim::mot::Header;

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
    /// Positions in the lab (ground) frame: the motion's pelvis translation
    /// (`pelvis_tx`, `pelvis_ty`, `pelvis_tz`) added to each point, as a `.trc` of joint centres
    /// beside the lab's markers needs. Without it the points are relative to the pelvis origin
    /// (ground axes), as `qgait fk` writes them.
    #[arg(long)]
    pub lab_frame: bool,
}

/// The columns of the pelvis translation, in x, y, z order.
const TRANSLATION: [&str; 3] = ["pelvis_tx", "pelvis_ty", "pelvis_tz"];

/// The motion's pelvis translation of each row, read beside the model's evaluation (a second
/// reader of the same rows, so memory stays independent of the motion's length).
struct Translation {
    rows: MotionRows,
    columns: [Option<usize>; 3],
}

impl Translation {
    /// The reader, and a warning per translation column the motion lacks (taken as 0, as
    /// OpenSim takes a coordinate a motion does not set); none of them is an error.
    fn open(motion: &str) -> anyhow::Result<(Self, Vec<Warning>)> {
        let (rows, _) = MotionRows::open(motion)?;
        let header = rows.header();
        let columns = TRANSLATION.map(|c| header.index_of(c));
        if columns.iter().all(Option::is_none) {
            anyhow::bail!(
                "{}: --lab-frame needs the pelvis translation, and the motion has none of {}",
                header.labels_location(),
                TRANSLATION.join(", ")
            );
        }
        let warnings = TRANSLATION
            .iter()
            .zip(columns)
            .filter(|(_, c)| c.is_none())
            .map(|(name, _)| {
                Warning::MissingDefaulted(WarningText {
                    at: Some(Location::file(header.source.clone())),
                    detail: format!("no `{name}` column; taken as 0 in the lab frame"),
                })
            })
            .collect();
        Ok((Self { rows, columns }, warnings))
    }

    /// The next row's translation (metres).
    fn next(&mut self) -> anyhow::Result<Vec3<f64>> {
        let (row, _) = self
            .rows
            .next_row()?
            .context("the motion ended before the points did")?;
        let [x, y, z] = self.columns.map(|c| c.map_or(0.0, |c| row.values[c]));
        Ok(Vec3::new(x, y, z))
    }
}

/// Without `--lab-frame`: a warning naming the motion's pelvis translation columns, which the
/// points then leave out (none when it has none).
fn translation_not_applied(header: &Header) -> Vec<Warning> {
    let present: Vec<&str> = TRANSLATION
        .into_iter()
        .filter(|c| header.index_of(c).is_some())
        .collect();
    if present.is_empty() {
        Vec::new()
    } else {
        vec![Warning::Ignored(WarningText {
            at: Some(header.labels_at()),
            detail: format!(
                "{} not applied: the points are relative to the pelvis origin (ground axes); --lab-frame adds the translation, for positions in the lab frame",
                present.join(", ")
            ),
        })]
    }
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
    let mut translation = if a.lab_frame {
        let (t, w) = Translation::open(&a.motion)?;
        diagnostics.warn(w);
        Some(t)
    } else {
        diagnostics.warn(translation_not_applied(rows.header()));
        None
    };
    let mut frame = 0;
    let mut moved = Vec::new();
    let warnings = model.run::<anyhow::Error>(rows, &|w| diagnostics.warn(w), |t, points| {
        progress.inc(1);
        frame += 1;
        let points = match &mut translation {
            Some(tr) => {
                let d = tr.next()?;
                moved.clear();
                moved.extend(points.iter().map(|p| *p + d));
                &moved[..]
            }
            None => points,
        };
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
