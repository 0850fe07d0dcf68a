//! `qgait imu`: IMU segment orientations (OpenSim orientation `.sto`) to gait2392 joint angles
//! (OpenSim `.mot`), with the kernel's OpenSense-style calibration and solver
//! ([`qgait_kernel::imu`]).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use qgait_kernel::imu::{
    heading_free_pelvis, lumbar, Calibration, FitSolver, Heading, HeadingAxis, Mode, Orientations,
    Segment, Settings, Solver, LUMBAR,
};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::models::{LowerLimb, Phak, PhakAngles};
use qgait_kernel::Gait2392;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use crate::cli::output::{refuse_overwrite, write_output_with};
use crate::cli::three_numbers;
use crate::progress::Progress;
use qgait_figures::imu_angles;
use qgait_model::choice::Model;
use qgait_model::error::ModelError;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::mot::{write_mot_header, write_mot_row, MotionTable};
use qgait_opensim::vendor::{self, Mapping};

/// Arguments of `qgait imu`.
#[derive(Debug, Args)]
pub struct ImuArgs {
    /// The recording: OpenSim orientation .sto (DataType=Quaternion, `<body>_imu` columns,
    /// cells `w,x,y,z`), an APDM .csv, or an Xsens MT Manager trial (its folder, or
    /// FOLDER/PREFIX for the files FOLDER/PREFIX<sensor>.txt; with --imu-mapping).
    pub orientations: PathBuf,
    /// The static calibration pose (any of the same formats; its first row is used), the
    /// subject standing in the model's default pose (OpenSense's
    /// `orientation_file_for_calibration`).
    #[arg(long, value_name = "STATIC")]
    pub calibration: PathBuf,
    /// OpenSense's IMU reader settings (XsensDataReaderSettings or APDMDataReaderSettings XML,
    /// `myIMUMappings.xml`): which Xsens file or APDM sensor is which model IMU
    /// (`<ExperimentalSensor name="..."><name_in_model>pelvis_imu</name_in_model>`), the
    /// trial prefix and sampling rate. Needed for Xsens; for APDM unless its sensor labels are
    /// the model's IMU names.
    #[arg(long, value_name = "SETTINGS.xml")]
    pub imu_mapping: Option<PathBuf>,
    /// The sampling rate (Hz) of an Xsens trial whose files and settings give none, or of an
    /// APDM `Format=7` file (OpenSim assumes 128 Hz there).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// The model: gait2392 (the default), a SUBJECT.toml or an OpenSim MODEL.osim of the
    /// gait2392 family (gait2392's 17 coordinates and the lumbar joint are written); `phak`
    /// (the paper's 8 coordinates, solved on PHAK's own axes; `--anthropometry` applies); an
    /// imported chain, CHAIN.toml or any other lower-limb MODEL.osim (Rajagopal, ...: its 17
    /// coordinates, solved on its own joints).
    #[command(flatten)]
    pub model: ModelArgs,
    /// Calibration, heading and solver.
    #[command(flatten)]
    pub settings: ImuSettingsArgs,
    /// The pelvis's convention: `opensense` (in the sensors' world frame, heading in
    /// `pelvis_rotation`, as OpenSense writes it) or `heading-free` (tilt and list relative to
    /// the direction of progression: the centred 2 s mean of `pelvis_rotation`; for analyses
    /// of turning walks).
    #[arg(long, value_enum, default_value_t = PelvisArg::Opensense)]
    pub pelvis: PelvisArg,
    /// The lumbar joint of an imported chain: `free` (the torso sensor gives it; written) or
    /// `locked` (the torso moves with the pelvis, which then fits both sensors: what OpenSense
    /// does with Rajagopal2015_opensense, whose lumbar coordinates are locked). Default free.
    #[arg(long, value_enum, value_name = "free|locked")]
    pub lumbar: Option<LumbarArg>,
    /// A reference solution of the same recording (OpenSense's IK `.mot`/`.sto`, its model's
    /// coordinate names): prints every common coordinate's RMSE and largest difference
    /// against it (a Markdown table on stdout).
    #[arg(long, value_name = "REFERENCE.mot")]
    pub compare: Option<PathBuf>,
    /// With --compare: also draw both over time into DIR (`imu_angles.png` and `.svg`).
    #[arg(long, value_name = "DIR", requires = "compare")]
    pub figures: Option<PathBuf>,
    /// Output .mot (joint angles in degrees).
    #[arg(short, long, value_name = "ANGLES.mot")]
    pub output: PathBuf,
}

/// `--mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// [`Mode::LeastSquares`].
    LeastSquares,
    /// [`Mode::ClosedForm`].
    ClosedForm,
}

/// `--pelvis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PelvisArg {
    /// As OpenSense: in the sensors' world frame.
    Opensense,
    /// Relative to the direction of progression ([`heading_free_pelvis`]).
    HeadingFree,
}

/// The window of the direction of progression for `--pelvis heading-free` (seconds, centred):
/// about two strides, so that the pelvis's rotation within a stride averages out.
pub const PROGRESSION_WINDOW: f64 = 2.0;

/// The calibration, heading and solver options of `qgait imu`, also taken by `qgait packets
/// --orientations` and `verify --orientations` (the defaults: OpenSense's).
#[derive(Debug, Args, Clone)]
pub struct ImuSettingsArgs {
    /// The IMU whose heading axis points forward in the calibration pose (OpenSense's
    /// `base_imu_label`, e.g. `torso_imu` or `pelvis_imu`); default none: no heading
    /// correction, as OpenSense (the subject then faces the sensors' world x at calibration).
    #[arg(long, value_name = "NAME")]
    pub base_imu: Option<String>,
    /// The base IMU's axis that points forward (OpenSense's `base_heading_axis`).
    #[arg(
        long,
        default_value = "z",
        value_name = "x|-x|y|-y|z|-z",
        value_parser = heading_axis,
        allow_hyphen_values = true
    )]
    pub base_heading_axis: HeadingAxis,
    /// Rotation from the sensors' world frame to OpenSim's (y up): space-fixed X, Y, Z Euler
    /// angles in radians, as OpenSense's `sensor_to_opensim_rotations` (the default turns a
    /// z-up world, Xsens or APDM, to OpenSim's y up).
    #[arg(
        long,
        default_value = "-1.5707963267948966,0,0",
        value_name = "RX,RY,RZ",
        value_parser = three_numbers,
        allow_hyphen_values = true
    )]
    pub sensor_to_opensim: [f64; 3],
    /// The solver: per-leg least squares (OpenSense's problem) or the per-joint closed form.
    #[arg(long, value_enum, default_value_t = ModeArg::LeastSquares)]
    pub mode: ModeArg,
}

/// `--base-heading-axis`.
fn heading_axis(text: &str) -> anyhow::Result<HeadingAxis> {
    text.parse()
        .map_err(|()| anyhow::anyhow!("expected x, -x, y, -y, z or -z"))
}

impl ImuSettingsArgs {
    /// The kernel's calibration settings.
    pub(crate) fn settings(&self) -> anyhow::Result<Settings<f64>> {
        let heading = match &self.base_imu {
            None => None,
            Some(name) => Some(Heading {
                base: Segment::from_name(name).with_context(|| {
                    format!(
                        "--base-imu `{name}`: not an IMU of the set ({})",
                        Segment::ALL.map(Segment::imu_label).join(", ")
                    )
                })?,
                axis: self.base_heading_axis,
            }),
        };
        Ok(Settings {
            sensor_to_opensim: self.sensor_to_opensim,
            heading,
        })
    }

    /// The solver's mode.
    pub(crate) fn mode(&self) -> Mode {
        match self.mode {
            ModeArg::LeastSquares => Mode::LeastSquares,
            ModeArg::ClosedForm => Mode::ClosedForm,
        }
    }
}

/// `--lumbar`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LumbarArg {
    /// The lumbar joint follows the torso sensor (gait2392's, and written out).
    Free,
    /// The lumbar joint is locked (Rajagopal2015_opensense): the torso moves with the pelvis,
    /// whose coordinates then fit the pelvis and torso sensors together, as OpenSense does.
    Locked,
}

/// The model `qgait imu` solves, with what it writes.
enum Solving {
    /// gait2392's family: the analytic solver, 17 coordinates and the lumbar joint.
    Gait2392 {
        model: Box<Gait2392<f64>>,
        solver: Box<Solver<f64>>,
        mode: Mode,
    },
    /// PHAK on its own axes: 8 coordinates.
    Phak {
        model: Box<Phak<f64>>,
        solver: Box<FitSolver<f64, 8>>,
    },
    /// An imported chain: 17 coordinates, and the lumbar joint when it is free.
    Chain {
        model: Box<LowerLimb<f64>>,
        solver: Box<FitSolver<f64, 17>>,
        /// The lumbar joint's last value (held while the pelvis or torso sensor is missing,
        /// as gait2392's solver holds it).
        lumbar: [f64; 3],
    },
}

impl Solving {
    /// The output's columns after `time`.
    fn labels(&self) -> Vec<&'static str> {
        match self {
            Self::Gait2392 { .. } => COORDINATES.iter().chain(&LUMBAR).copied().collect(),
            Self::Phak { .. } => PhakAngles::<f64>::NAMES.to_vec(),
            Self::Chain { solver, .. } => {
                let lumbar: &[&str] = if solver.torso_on_pelvis { &[] } else { &LUMBAR };
                COORDINATES.iter().chain(lumbar).copied().collect()
            }
        }
    }

    /// Index in a row (after `time`) of the heading coordinate.
    fn heading_column(&self) -> usize {
        match self {
            Self::Phak { .. } => 0,
            _ => 2,
        }
    }

    /// One frame: the coordinates in degrees, in [`labels`](Self::labels) order.
    fn solve(&mut self, segments: &Orientations<f64>, row: &mut Vec<f64>) {
        let start = row.len();
        match self {
            Self::Gait2392 {
                model,
                solver,
                mode,
            } => {
                let solved = solver.solve(model, segments, *mode);
                row.extend(solved.coordinates.iter().chain(&solved.lumbar));
            }
            Self::Phak { model, solver } => {
                row.extend(solver.solve(&**model, segments).coordinates);
            }
            Self::Chain {
                model,
                solver,
                lumbar: held,
            } => {
                row.extend(solver.solve(&**model, segments).coordinates);
                if !solver.torso_on_pelvis {
                    if let (Some(p), Some(t)) =
                        (segments.get(Segment::Pelvis), segments.get(Segment::Torso))
                    {
                        *held = lumbar(p, t);
                    }
                    row.extend(*held);
                }
            }
        }
        for v in &mut row[start..] {
            *v = v.to_degrees();
        }
    }

    /// The pelvis of `row` (degrees, after `time`) made relative to the direction of
    /// progression `heading` (degrees).
    fn heading_free(&self, row: &mut [f64], heading: f64) {
        match self {
            Self::Gait2392 { model, .. } => {
                let pelvis = [0, 1, 2].map(|c| row[c].to_radians());
                let p = heading_free_pelvis(model, pelvis, heading.to_radians());
                for (k, v) in p.into_iter().enumerate() {
                    row[k] = v.to_degrees();
                }
            }
            // PHAK turns about the vertical first: the heading is only in the rotation.
            Self::Phak { .. } => row[0] -= heading,
            Self::Chain { .. } => unreachable!("refused before solving"),
        }
    }
}

/// Runs `qgait imu`.
pub fn run_imu(a: ImuArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let mut inputs: Vec<String> = [
        Some(&a.orientations),
        Some(&a.calibration),
        a.imu_mapping.as_ref(),
    ]
    .into_iter()
    .flatten()
    .map(|p| p.to_string_lossy().into_owned())
    .collect();
    inputs.extend(a.model.inputs());
    refuse_overwrite([a.output.as_path()], &inputs)?;
    let chosen = a.model.load_or("gait2392", diagnostics)?;
    let settings = a.settings.settings()?;
    let rejected = |error| ModelError::Rejected {
        name: chosen.name().to_string(),
        error,
    };
    let mode = a.settings.mode();
    let heading_free = a.pelvis == PelvisArg::HeadingFree;
    let gait2392 = matches!(chosen, Model::Gait2392 { .. });
    if !gait2392 && mode == Mode::ClosedForm {
        bail!(
            "--mode closed-form: the closed form decomposes gait2392's joints; --model {} is solved by least squares only",
            chosen.name()
        );
    }
    if a.lumbar.is_some() && !matches!(chosen, Model::Chain { .. }) {
        bail!(
            "--lumbar: for an imported chain (CHAIN.toml, MODEL.osim); --model {} has its own lumbar joint (gait2392: free) or none (PHAK)",
            chosen.name()
        );
    }
    let mut solving = match &chosen {
        Model::Gait2392 { geometry, .. } => Solving::Gait2392 {
            model: Box::new(Gait2392::<f64>::new(geometry).map_err(rejected)?),
            solver: Box::default(),
            mode,
        },
        Model::Phak { .. } => Solving::Phak {
            model: Box::new(
                Phak::<f64>::new(&chosen.lengths().expect("PHAK has lengths")).map_err(rejected)?,
            ),
            solver: Box::default(),
        },
        Model::Chain { chain, name } => {
            if heading_free {
                bail!(
                    "--pelvis heading-free: for gait2392 and PHAK; --model {name} writes the pelvis as OpenSense does"
                );
            }
            let model = chain.chain(name)?;
            let (min, max) = chain.bounds(name)?;
            let mut solver = FitSolver::new();
            (solver.min, solver.max) = (min, max);
            solver.torso_on_pelvis = a.lumbar == Some(LumbarArg::Locked);
            Solving::Chain {
                model: Box::new(model),
                solver: Box::new(solver),
                lumbar: [0.0; 3],
            }
        }
        Model::Hak { .. } => bail!(
            "--model hak: HAK has no pelvis for the pelvis sensor; `qgait imu` solves phak, a gait2392-family model or an imported chain (CHAIN.toml, MODEL.osim)"
        ),
    };
    if let Some(r) = a.rate {
        if !(r > 0.0 && r.is_finite()) {
            bail!("--rate {r}: expected a sampling rate in Hz");
        }
    }
    let mapping = a.imu_mapping.as_deref().map(Mapping::read).transpose()?;
    let mut warnings: Vec<Warning> = Vec::new();
    let calibration = calibrate(
        &a.calibration,
        mapping.as_ref(),
        a.rate,
        &solving,
        &settings,
        &mut warnings,
    )?;
    let mut reader = vendor::open(&a.orientations, mapping.as_ref(), a.rate)?;
    if let (Some(r), true) = (a.rate, reader.has_times()) {
        warnings.push(Warning::OptionIgnored(WarningText {
 at: Some(Location::file(reader.source())),
 detail: format!("--rate {r} ignored: the file has its own times (--rate is for an Xsens trial or an APDM file that gives none)"),
}));
    }
    for s in &calibration.1 {
        if !reader.sensors().contains(s) {
            bail!(
                "{}: no column `{s}`, but the calibration pose ({}) has it",
                reader.labels_location(),
                a.calibration.display()
            );
        }
    }
    for s in reader.sensors() {
        if !calibration.1.contains(&s) {
            warnings.push(Warning::Ignored(WarningText {
                at: Some(reader.labels_at()),
                detail: format!(
                    "`{s}` has no reading in the calibration pose ({}); its column is ignored",
                    a.calibration.display()
                ),
            }));
        }
    }
    let present = calibration.1.clone();
    let calibration = calibration.0;
    // Rows without a reading of each sensor the calibration pose has: (count, first line).
    let mut gaps: Vec<(Segment, usize, usize)> = Vec::new();
    let mut rows = 0usize;

    let name = a
        .orientations
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let labels: Vec<String> = std::iter::once("time")
        .chain(solving.labels())
        .map(String::from)
        .collect();
    let progress = Progress::new(0, "imu", diagnostics.quiet());
    let mut window = ProgressionWindow::new(PROGRESSION_WINDOW, 1 + solving.heading_column());
    write_output_with(Some(&a.output), |out| {
        write_mot_header(&mut *out, &name, &labels, true, None, heading_free)?;
        let mut emit =
            |row: &Row, heading: Option<f64>, solving: &Solving| -> std::io::Result<()> {
                let mut row = row.clone();
                if let Some(h) = heading {
                    solving.heading_free(&mut row[1..], h);
                }
                write_mot_row(&mut *out, &row)
            };
        while let Some(r) = reader.next_row()? {
            rows += 1;
            for &sensor in &present {
                if r.readings.get(sensor).is_none() {
                    match gaps.iter_mut().find(|(s, ..)| *s == sensor) {
                        Some((_, n, _)) => *n += 1,
                        None => gaps.push((sensor, 1, r.line)),
                    }
                }
            }
            let segments = calibration
                .segments(&r.readings)
                .map_err(|e| anyhow::anyhow!("{}:{}: {e}", reader.source(), r.line))?;
            let mut row: Row = Vec::with_capacity(labels.len());
            row.push(r.time);
            solving.solve(&segments, &mut row);
            if heading_free {
                window.push(Some(row), &mut |r, h| emit(r, h, &solving))?;
            } else {
                emit(&row, None, &solving)?;
            }
            progress.inc(1);
        }
        if heading_free {
            window.push(None, &mut |r, h| emit(r, h, &solving))?;
        }
        Ok(())
    })?;
    progress.finish();
    warnings.extend(reader.take_warnings());
    for (sensor, n, line) in gaps {
        warnings.push(Warning::ReadingsMissing(WarningText {
 at: Some(Location::line(reader.source(), line)),
 detail: format!("`{sensor}` has no reading (nan) in {n} of {rows} rows, the first here: what only it determines keeps its previous value there (0 before its first reading), not a measurement"),
}));
    }
    diagnostics.warn(warnings);
    if let Some(reference) = &a.compare {
        let (ours, _) = MotionTable::read(&a.output)?;
        let (theirs, w) = MotionTable::read(reference)?;
        diagnostics.warn(w);
        let comparison = imu_angles::compare(&ours, &theirs)?;
        println!(
            "qgait imu against {} ({} rows, {:.2} s to {:.2} s):\n",
            reference.display(),
            comparison.time.len(),
            comparison.time.first().copied().unwrap_or(0.0),
            comparison.time.last().copied().unwrap_or(0.0)
        );
        print!("{}", comparison.markdown("°"));
        if let Some(dir) = &a.figures {
            let label = format!("qgait imu --model {}", chosen.name());
            let theirs_label = reference
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            for f in imu_angles::draw(&comparison, [&label, &theirs_label], "degrees", dir)? {
                diagnostics.notes([format!("wrote {}", f.display())]);
            }
        }
    }
    Ok(())
}

/// One output row (time, then degrees).
type Row = Vec<f64>;

/// The rows within half a window of the next row to write, for the direction of progression:
/// the mean heading (column `column`) over the rows within `window / 2` seconds of a row's time
/// (a centred moving average). Memory is bounded by the window, not by the recording.
struct ProgressionWindow {
    half: f64,
    column: usize,
    rows: std::collections::VecDeque<Row>,
    /// Index in `rows` of the next row to write.
    next: usize,
}

impl ProgressionWindow {
    fn new(window: f64, column: usize) -> Self {
        Self {
            half: window / 2.0,
            column,
            rows: std::collections::VecDeque::new(),
            next: 0,
        }
    }

    /// Adds `row` (or, with `None`, ends the recording) and hands every row whose window is
    /// now complete to `emit` with its direction of progression (degrees).
    fn push(
        &mut self,
        row: Option<Row>,
        emit: &mut impl FnMut(&Row, Option<f64>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let last = row.is_none();
        let t_new = row.as_ref().map_or(f64::INFINITY, |r| r[0]);
        if let Some(row) = row {
            self.rows.push_back(row);
        }
        while self.next < self.rows.len() {
            let t = self.rows[self.next][0];
            if !last && t + self.half >= t_new {
                break;
            }
            let (sum, n) = self
                .rows
                .iter()
                .filter(|r| (r[0] - t).abs() <= self.half)
                .fold((0.0, 0), |(s, n), r| (s + r[self.column], n + 1));
            emit(&self.rows[self.next], Some(sum / n as f64))?;
            self.next += 1;
            while self.next < self.rows.len()
                && self.rows[0][0] < self.rows[self.next][0] - self.half
            {
                self.rows.pop_front();
                self.next -= 1;
            }
        }
        Ok(())
    }
}

/// The calibration from the first row of `path`, and the sensors it has.
fn calibrate(
    path: &Path,
    mapping: Option<&Mapping>,
    rate: Option<f64>,
    solving: &Solving,
    settings: &Settings<f64>,
    warnings: &mut Vec<Warning>,
) -> anyhow::Result<(Calibration<f64>, Vec<Segment>)> {
    let mut reader = vendor::open(path, mapping, rate)?;
    let row = reader
        .next_row()?
        .expect("the reader refuses a file without rows");
    if reader.next_row()?.is_some() {
        warnings.push(Warning::RowsLeftOut(WarningText {
            at: Some(Location::file(reader.source())),
            detail: format!(
                "the calibration pose has more than one row; the first (line {}) is used",
                row.line
            ),
        }));
    }
    warnings.extend(reader.take_warnings());
    let present: Vec<Segment> = Segment::ALL
        .into_iter()
        .filter(|&s| row.readings.get(s).is_some())
        .collect();
    let calibration = match solving {
        Solving::Gait2392 { model, .. } => Calibration::new(model, &row.readings, settings),
        Solving::Phak { model, .. } => Calibration::for_model(&**model, &row.readings, settings),
        Solving::Chain { model, .. } => Calibration::for_model(&**model, &row.readings, settings),
    }
    .map_err(|e| anyhow::anyhow!("{}:{}: {e}", reader.source(), row.line))?;
    Ok((calibration, present))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window's means are the centred means over the whole recording, every row is written
    /// once in order, and it holds no more than a window of rows.
    #[test]
    fn progression_window_is_the_centred_mean_in_bounded_memory() {
        let n = 1000;
        let time: Vec<f64> = (0..n)
            .map(|i| i as f64 * 0.01 + (i % 7) as f64 * 1e-4)
            .collect();
        let rot: Vec<f64> = time
            .iter()
            .map(|t| 90.0 * t + 5.0 * (7.0 * t).sin())
            .collect();
        let mut window = ProgressionWindow::new(0.5, 3);
        let mut got = Vec::new();
        let mut most = 0;
        let mut emit = |r: &Row, h: Option<f64>| {
            got.push((r[0], h.unwrap()));
            Ok(())
        };
        for (t, v) in time.iter().zip(&rot) {
            let mut row = vec![0.0; 21];
            row[0] = *t;
            row[3] = *v;
            window.push(Some(row), &mut emit).unwrap();
            most = most.max(window.rows.len());
        }
        window.push(None, &mut emit).unwrap();
        assert_eq!(got.len(), n);
        for (i, (t, h)) in got.iter().enumerate() {
            assert_eq!(*t, time[i]);
            let near: Vec<f64> = (0..n)
                .filter(|&j| (time[j] - t).abs() <= 0.25)
                .map(|j| rot[j])
                .collect();
            let mean = near.iter().sum::<f64>() / near.len() as f64;
            assert!((h - mean).abs() < 1e-9, "row {i}: {h} vs {mean}");
        }
        assert!(most <= 60, "held {most} rows for a 0.5 s window at 100 Hz");
    }
}
