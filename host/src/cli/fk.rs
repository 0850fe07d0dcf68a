//! `qgait fk`: joint positions (metres) for every row of a motion, as CSV, computed and written
//! one row at a time.

use std::io::{self, IsTerminal};
use std::path::PathBuf;

use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use crate::cli::output::{refuse_overwrite, write_output_with};
use crate::progress::Progress;
use qgait_model::derivatives::{MotionModel, Series};
use qgait_model::error::ModelError;
use qgait_model::motion::source::load_motion;
use qgait_model::motion::source::MotionRows;
use qgait_model::points::{point_names, PointModel, PointsCsv};

/// `qgait fk` arguments.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    pub motion: String,
    /// The model.
    #[command(flatten)]
    pub model: ModelArgs,
    /// Also the subtalar and MTP joint centres (gait2392 models): columns
    /// `subtalar_r_x..z, mtp_r_x..z, subtalar_l_x..z, mtp_l_x..z` after the standard ones.
    #[arg(long)]
    pub points: bool,
    /// Also each point's velocity and acceleration (every model; HAK's pelvis angles and their
    /// speeds count as 0): after its `x,y,z` columns, `<point>_vx,_vy,_vz` (m/s) and
    /// `_ax,_ay,_az` (m/s²), the time derivatives of the positions (ground axes, origin at the
    /// pelvis origin). Speeds come from an OpenSim states .sto's `/speed` columns when present,
    /// otherwise from five-point differences of the coordinates.
    #[arg(long)]
    pub derivatives: bool,
    /// With --derivatives: low-pass filter the coordinates that are differentiated (zero-phase
    /// 4th-order Butterworth, cut-off HZ), as OpenSim's `lowpass_cutoff_frequency`.
    #[arg(long, value_name = "HZ", requires = "derivatives")]
    pub lowpass: Option<f64>,
    /// Output CSV file (default: standard output).
    #[arg(short, long, value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
}

/// The files a motion command reads: the motion, and the model's files.
pub(crate) fn inputs(motion: &str, model: &ModelArgs) -> Vec<String> {
    let mut files = vec![motion.to_string()];
    files.extend(model.inputs());
    files
}

/// The model and the rows of a motion, ready to run.
pub(crate) struct Prepared {
    pub(crate) model: PointModel,
    pub(crate) rows: MotionRows,
}

/// Loads the model and opens the motion (its header warnings shown).
pub(crate) fn prepare(
    motion: &str,
    model: &ModelArgs,
    points: bool,
    diagnostics: &Diagnostics,
) -> anyhow::Result<Prepared> {
    let model = PointModel::new(&model.load(diagnostics)?, points)?;
    let (rows, w) = MotionRows::open(motion)?;
    diagnostics.warn(w);
    Ok(Prepared { model, rows })
}

/// A CSV writer's error as the I/O error it is (so a closed pipe stays a closed pipe).
fn csv_error(e: csv::Error) -> anyhow::Error {
    match e.into_kind() {
        csv::ErrorKind::Io(e) => e.into(),
        other => anyhow::anyhow!("{other:?}"),
    }
}

/// Runs `qgait fk`: each row is computed and written before the next is read.
pub fn run_fk(a: FkArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    if a.derivatives {
        return run_fk_derivatives(a, diagnostics);
    }
    // No bar while CSV goes to the same terminal.
    let csv_on_terminal = a.output.is_none() && io::stdout().is_terminal();
    refuse_overwrite(a.output.as_deref(), &inputs(&a.motion, &a.model))?;
    let Prepared { model, rows } = prepare(&a.motion, &a.model, a.points, diagnostics)?;
    let progress = Progress::new(
        rows.size_hint().unwrap_or(0) as u64,
        "fk",
        diagnostics.quiet() || csv_on_terminal,
    );
    let mut warnings = Vec::new();
    write_output_with(a.output.as_deref(), |out| {
        let mut csv = PointsCsv::new(out, &model.names(), false).map_err(csv_error)?;
        warnings = model.run(rows, &|w| diagnostics.warn(w), |t, p| {
            progress.inc(1);
            csv.row(0, Some(t), p.iter().map(|p| [p.x, p.y, p.z]))
                .map_err(csv_error)
        })?;
        Ok(csv.flush()?)
    })?;
    progress.finish();
    diagnostics.warn(warnings);
    Ok(())
}

/// `qgait fk --derivatives`: the whole motion is read (the differentiator looks ahead), then
/// each row's points with their velocities and accelerations are written.
fn run_fk_derivatives(a: FkArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    refuse_overwrite(a.output.as_deref(), &inputs(&a.motion, &a.model))?;
    let model = MotionModel::new(&a.model.load(diagnostics)?)?;
    if a.points && matches!(model, MotionModel::Stick { .. }) {
        return Err(ModelError::PointsNeedGait2392.into());
    }
    let (table, w) = load_motion(&a.motion)?;
    diagnostics.warn(w);
    let (series, w) = Series::of(&table, a.lowpass, &model)?;
    diagnostics.warn(w);
    let names = point_names(a.points);
    let axes = ["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"];
    write_output_with(a.output.as_deref(), |out| {
        let mut csv = PointsCsv::with_axes(out, &names, false, &axes).map_err(csv_error)?;
        for r in 0..series.time.len() {
            let points = model.points(&series.q[r], &series.qd[r], &series.qdd[r]);
            let values = points[..names.len()]
                .iter()
                .flat_map(|p| [p.position, p.velocity, p.acceleration].map(|v| [v.x, v.y, v.z]));
            csv.row(0, Some(series.time[r]), values)
                .map_err(csv_error)?;
        }
        Ok(csv.flush()?)
    })?;
    Ok(())
}
