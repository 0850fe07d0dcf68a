#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

mod distances;
pub mod figure;
pub mod font;
pub mod imu_angles;
pub mod metrics;
mod paths;
mod stick;

use std::path::{Path, PathBuf};

use qgait_kernel::metrics::{self as kmetrics, Distances};
use qgait_kernel::models::PhakAngles;
use qgait_kernel::{BilateralPose, LegPose, Vec3};

use qgait_device::frames_csv::FramesTable;

use qgait_model::choice::Model;
use qgait_model::error::ModelError;
use qgait_model::kinematics::{self, Evaluator};
use qgait_model::motion::source::MotionRows;
use qgait_model::points::PointModel;
use qgait_opensim::diagnostics::Warning;
use qgait_opensim::mot::MotionTable;

/// Why a report or a comparison of two solutions cannot be made or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// The model cannot run the motions.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A frames CSV has fewer than two rows (no cycle to normalise).
    #[error("{file}: a frames CSV needs at least 2 rows")]
    TooFewFrames {
        /// The frames CSV.
        file: String,
    },
    /// A frames CSV's times (or sequence numbers) go back or never advance.
    #[error("{file}: rows must be in increasing time (or seq) order")]
    FramesOutOfOrder {
        /// The frames CSV.
        file: String,
    },
    /// One file is in degrees and the other in radians.
    #[error("{location}: in {theirs}, but the output is in {ours}")]
    Units {
        /// The reference's labels line.
        location: String,
        /// The reference's unit.
        theirs: &'static str,
        /// Ours.
        ours: &'static str,
    },
    /// A reference time has no row of ours within 1 µs.
    #[error("{location}: time {time} has no row in the output (the reference must be a solution of the same recording)")]
    NoRow {
        /// The reference's labels line.
        location: String,
        /// The reference's time.
        time: f64,
    },
    /// No coordinate is in both files (with a reference not zero throughout).
    #[error("{location}: no coordinate in common with the output")]
    NothingInCommon {
        /// The reference's labels line.
        location: String,
    },
    /// The output directory cannot be created.
    #[error("{}: cannot create directory", path.display())]
    CreateDir {
        /// The directory.
        path: PathBuf,
        /// Why.
        #[source]
        error: std::io::Error,
    },
    /// A figure cannot be drawn or written.
    #[error(transparent)]
    Figure(#[from] figure::FigureError),
    /// A table cannot be written.
    #[error("{}: cannot write", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        error: std::io::Error,
    },
}

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
    /// PHAK angles (radians) of each row; empty for a gait given as points (a device's frames).
    pub angles: Vec<PhakAngles<f64>>,
    /// Joint positions (metres) of each row.
    pub poses: Vec<BilateralPose<f64>>,
    /// Inter-limb distances of each row.
    pub distances: Vec<Distances<f64>>,
}

/// All gaits of a report and the model that computed them.
pub struct Analysis {
    /// The model as the figures and `metrics.md` name it, with where its origin is (e.g.
    /// "PHAK model, origin at the pelvis origin (midway between the hips)"), and whether a
    /// device's frames are drawn as well.
    pub model: String,
    /// The kernel model when it is HAK or PHAK (poses between rows come from interpolated
    /// angles); `None` for a gait2392 model (poses between rows interpolate its points).
    pub evaluator: Option<Evaluator>,
    /// The gaits, in the order given (the first is the reference for the hip shift).
    pub gaits: Vec<Gait>,
}

impl Analysis {
    /// Runs the model on every row of every motion; `progress` is told of each row done.
    pub fn new(
        motions: &[(String, MotionTable)],
        model: &Model,
        progress: &dyn Fn(u64),
    ) -> Result<(Self, Vec<Warning>), ModelError> {
        // HAK and PHAK keep their angles (poses between rows from interpolated angles); other
        // models give their points only.
        let evaluator = match model.lengths() {
            Some(_) => Some(Evaluator::new(model, "report")?),
            None => None,
        };
        let mut warnings = Vec::new();
        let mut gaits = Vec::new();
        for (label, table) in motions {
            let (angles, poses) = match &evaluator {
                Some(evaluator) => {
                    let (angles, w) = kinematics::stick_angles(table, model)?;
                    warnings.extend(w);
                    let poses = angles
                        .iter()
                        .map(|a| {
                            progress(1);
                            evaluator.pose(a)
                        })
                        .collect();
                    (angles, poses)
                }
                None => {
                    let points = PointModel::new(model, false)?;
                    let column_warnings = std::cell::RefCell::new(Vec::new());
                    let mut poses = Vec::with_capacity(table.rows());
                    let w = points.run::<ModelError>(
                        MotionRows::from_table(table.clone()),
                        &|w| column_warnings.borrow_mut().extend(w),
                        |_, p| {
                            progress(1);
                            poses
                                .push(pose_from_points(&core::array::from_fn(|i| p[i].to_array())));
                            Ok(())
                        },
                    )?;
                    warnings.extend(column_warnings.into_inner());
                    warnings.extend(w);
                    (Vec::new(), poses)
                }
            };
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
        let described = match model {
            Model::Hak { .. } => {
                "HAK model, origin at the pelvis origin (midway between the hips)".to_string()
            }
            Model::Phak { .. } => {
                "PHAK model, origin at the pelvis origin (midway between the hips)".to_string()
            }
            // A model file by its name, without the directories.
            other => format!(
                "{} model, origin at its pelvis origin",
                Path::new(other.name())
                    .file_name()
                    .map_or(other.name().into(), |n| n.to_string_lossy())
            ),
        };
        Ok((
            Self {
                model: described,
                evaluator,
                gaits,
            },
            warnings,
        ))
    }

    /// The pose of a gait at a percent of its cycle (angles interpolated between rows, then FK;
    /// for a gait given as points, the points interpolated).
    pub fn pose_at(&self, gait: &Gait, percent: f64) -> BilateralPose<f64> {
        match &self.evaluator {
            Some(evaluator) if !gait.angles.is_empty() => {
                evaluator.pose(&kinematics::angles_at(&gait.percent, &gait.angles, percent))
            }
            _ => points_at(gait, percent),
        }
    }

    /// Adds a gait given as the points of a frames CSV (`qgait emulate --frames-csv`), at
    /// position `index`. Percent of the cycle from its times (or sequence numbers if it has none).
    pub fn insert_frames(
        &mut self,
        index: usize,
        label: &str,
        source: &str,
        table: &FramesTable,
    ) -> Result<(), ReportError> {
        if table.points.len() < 2 {
            return Err(ReportError::TooFewFrames {
                file: source.to_string(),
            });
        }
        let x: Vec<f64> = match table.time.iter().copied().collect::<Option<Vec<f64>>>() {
            Some(t) => t,
            None => table.seq.iter().map(|&s| f64::from(s)).collect(),
        };
        let (first, last) = (x[0], x[x.len() - 1]);
        if last <= first || x.windows(2).any(|w| w[1] < w[0]) {
            return Err(ReportError::FramesOutOfOrder {
                file: source.to_string(),
            });
        }
        let percent = x
            .iter()
            .map(|v| 100.0 * (v - first) / (last - first))
            .collect();
        let poses: Vec<BilateralPose<f64>> = table.points.iter().map(pose_from_points).collect();
        let distances = poses.iter().map(kmetrics::distances).collect();
        let gait = Gait {
            label: label.to_string(),
            source: source.to_string(),
            percent,
            angles: Vec::new(),
            poses,
            distances,
        };
        self.gaits.insert(index.min(self.gaits.len()), gait);
        // Its points are the device's, computed with whatever model the hub had.
        const DEVICE: &str = " (a device's frames: as the hub computed them)";
        if !self.model.ends_with(DEVICE) {
            self.model.push_str(DEVICE);
        }
        Ok(())
    }
}

fn pose_from_points(p: &[[f64; 3]; 8]) -> BilateralPose<f64> {
    let v = |i: usize| Vec3::new(p[i][0], p[i][1], p[i][2]);
    BilateralPose {
        right: LegPose {
            hip: v(0),
            knee: v(1),
            ankle: v(2),
            toe: v(3),
        },
        left: LegPose {
            hip: v(4),
            knee: v(5),
            ankle: v(6),
            toe: v(7),
        },
    }
}

/// The points of a point-only gait at `percent`, linearly interpolated between rows.
fn points_at(gait: &Gait, percent: f64) -> BilateralPose<f64> {
    let n = gait.percent.len();
    let i = gait
        .percent
        .partition_point(|&p| p <= percent)
        .clamp(1, n - 1);
    let (p0, p1) = (gait.percent[i - 1], gait.percent[i]);
    let w = ((percent - p0) / (p1 - p0)).clamp(0.0, 1.0);
    let (a, b) = (gait.poses[i - 1].points(), gait.poses[i].points());
    let mut q = [[0.0; 3]; 8];
    for k in 0..8 {
        let (pa, pb) = (a[k].to_array(), b[k].to_array());
        q[k] = core::array::from_fn(|c| pa[c] + w * (pb[c] - pa[c]));
    }
    pose_from_points(&q)
}

/// Number of figures a report draws (for progress).
pub const FIGURE_COUNT: u64 = 5;

/// Writes every figure and table into `dir` (created if needed); returns the files written.
/// `progress` is told of each figure done ([`FIGURE_COUNT`] in all).
pub fn write_report(
    analysis: &Analysis,
    dir: &Path,
    progress: &dyn Fn(u64),
) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(dir).map_err(|error| ReportError::CreateDir {
        path: dir.to_path_buf(),
        error,
    })?;
    let mut files = Vec::new();
    for plane in kmetrics::Plane::ALL {
        files.extend(figure::save(
            &stick::StickFigure::new(analysis, plane),
            dir,
        )?);
        progress(1);
    }
    files.extend(figure::save(&paths::SagittalPaths { analysis }, dir)?);
    progress(1);
    files.extend(figure::save(&distances::DistanceFigure { analysis }, dir)?);
    progress(1);
    files.extend(metrics::write_all(analysis, dir)?);
    Ok(files)
}
