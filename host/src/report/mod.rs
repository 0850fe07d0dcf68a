//! `qgait report`: the paper's results (Figs 5-10 and the metrics) for one or more gaits.
//!
//! Files written to the output directory (figures as both `.png` and `.svg`):
//! - `stick_sagittal`, `stick_frontal`, `stick_transverse`: both legs at 0, 20, 40, 60, 80 and
//!   100 % of the cycle, one row per gait, equal scale on both axes (Figs 5-7);
//! - `paths_sagittal`: hip, knee, ankle and toe paths in the sagittal plane, right and left
//!   limb, gaits overlaid (Figs 8-9);
//! - `distances`: knee-knee, ankle-ankle and toe-toe distance over the cycle (Fig 10);
//! - `metrics.csv`, `hip_shift.csv`, `distance_stats.csv` and `metrics.md` (see [`metrics`]).
//!
//! The model is PHAK (origin at the pelvis origin, ground axes); percent of cycle is the time
//! normalised from the first to the last row of each motion.

mod distances;
mod figure;
mod font;
pub mod metrics;
mod paths;
mod stick;

use std::path::{Path, PathBuf};

use anyhow::Context;
use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::metrics::{self as kmetrics, Distances};
use qgait_kernel::models::PhakAngles;
use qgait_kernel::BilateralPose;

use crate::kinematics::{self, Evaluator, Model};
use crate::mot::{MotionTable, Warning};
use crate::progress::Progress;

/// Percentages of the cycle shown in the stick figures.
pub const STICK_PERCENTS: [f64; 6] = [0.0, 20.0, 40.0, 60.0, 80.0, 100.0];

/// One gait, analysed.
pub struct Gait {
    /// Label used in legends and tables.
    pub label: String,
    /// Where it came from.
    pub source: String,
    /// Percent of the cycle of each row.
    pub percent: Vec<f64>,
    /// PHAK angles (radians) of each row.
    pub angles: Vec<PhakAngles<f64>>,
    /// Joint positions (metres) of each row.
    pub poses: Vec<BilateralPose<f64>>,
    /// Inter-limb distances of each row.
    pub distances: Vec<Distances<f64>>,
}

/// All gaits of a report and the model that computed them.
pub struct Analysis {
    /// The kernel model (PHAK).
    pub evaluator: Evaluator,
    /// The gaits, in the order given (the first is the reference for the hip shift).
    pub gaits: Vec<Gait>,
}

impl Analysis {
    /// Runs PHAK on every row of every motion.
    pub fn new(
        motions: &[(String, MotionTable)],
        anthropometry: &Anthropometry<f64>,
        progress: &Progress,
    ) -> anyhow::Result<(Self, Vec<Warning>)> {
        let evaluator = Evaluator::new(Model::Phak, anthropometry).map_err(anyhow::Error::msg)?;
        let mut warnings = Vec::new();
        let mut gaits = Vec::new();
        for (label, table) in motions {
            let (angles, w) = kinematics::phak_angles(table).map_err(anyhow::Error::msg)?;
            warnings.extend(w);
            let poses: Vec<_> = angles
                .iter()
                .map(|a| {
                    progress.inc(1);
                    evaluator.pose(a)
                })
                .collect();
            let distances = poses.iter().map(kmetrics::distances).collect();
            gaits.push(Gait {
                label: label.clone(),
                source: table.source().to_string(),
                percent: table.percent_of_cycle(),
                angles,
                poses,
                distances,
            });
        }
        Ok((Self { evaluator, gaits }, warnings))
    }

    /// The pose of a gait at a percent of its cycle (angles interpolated between rows, then FK).
    pub fn pose_at(&self, gait: &Gait, percent: f64) -> BilateralPose<f64> {
        self.evaluator
            .pose(&kinematics::angles_at(&gait.percent, &gait.angles, percent))
    }
}

/// Number of figures a report draws (for progress).
pub const FIGURE_COUNT: u64 = 5;

/// Writes every figure and table into `dir` (created if needed); returns the files written.
pub fn write_report(
    analysis: &Analysis,
    dir: &Path,
    progress: &Progress,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create directory", dir.display()))?;
    let mut files = Vec::new();
    for plane in kmetrics::Plane::ALL {
        files.extend(figure::save(
            &stick::StickFigure::new(analysis, plane),
            dir,
        )?);
        progress.inc(1);
    }
    files.extend(figure::save(&paths::SagittalPaths { analysis }, dir)?);
    progress.inc(1);
    files.extend(figure::save(&distances::DistanceFigure { analysis }, dir)?);
    progress.inc(1);
    files.extend(metrics::write_all(analysis, dir)?);
    Ok(files)
}
