//! A recording ready for gait analysis: per frame the time, the points the analysis needs
//! (hips, heels, ankles, forefeet, toe tips, from the kernel's FK) and, where the source has
//! them, gait2392's coordinates and the pelvis translation. This is the one place of the gait
//! room that evaluates a model.

use qgait_kernel::differential::differentiate;
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::models::ranges::KNEES;
use qgait_kernel::Vec3;
use qgait_model::derivatives::MotionModel;

use crate::variables::Seen;

use qgait_device::frames_csv::FramesCsvError;
use qgait_model::choice::Model;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};

use qgait_model::error::ModelError;
use qgait_model::motion::source::{default_label, load_motion, MotionRows, SourceError};
use qgait_model::points::{self, PointModel};
use qgait_opensim::mot::MotionTable;

/// Why a recording cannot be loaded for gait analysis.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TrialError {
    /// The file could not be read.
    #[error("{path}: cannot read: {error}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        error: std::io::Error,
    },
    /// A device's frames CSV is malformed.
    #[error(transparent)]
    Frames(#[from] FramesCsvError),
    /// A device's frames CSV has no times.
    #[error("{0}: the frames have no times (a `time` column is needed for events and cadence: `qgait decode` writes the times a hub's frames carry, `qgait decode --rate HZ` times from the nodes' sampling rate)")]
    NoTimes(String),
    /// The motion cannot be read.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// The model cannot be used, or the motion does not fit it.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The angles cannot be in the unit the header declares.
    #[error(transparent)]
    Units(#[from] Box<UnitsError>),
}

/// A motion declared in radians whose angles are too large for radians.
#[derive(Debug, thiserror::Error)]
#[error("{at}: the header declares the angles in radians (`{declared}`), but `{column}` reaches {value:.1} rad ({:.1}°; no joint turns more than {:.2} rad): the angles are in degrees, as in OpenSim's CMC/RRA `Kinematics_q.sto`; state the unit with --angles-in deg (or --angles-in rad to keep the header's)", .value.to_degrees(), MAX_RADIANS)]
pub struct UnitsError {
    /// `file:line` of the header's `inDegrees` (or of the column labels without one).
    pub at: String,
    /// The header line as written.
    pub declared: String,
    /// The column.
    pub column: String,
    /// Its largest magnitude (rad as declared).
    pub value: f64,
}

/// The unit of a motion's angles, stated over its header (`--angles-in`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum AngleUnit {
    /// Degrees.
    Deg,
    /// Radians.
    Rad,
}

/// No joint angle of gait2392's coordinates reaches this many radians (a full turn): a file
/// whose angles do, declared in radians, is in degrees.
pub const MAX_RADIANS: f64 = std::f64::consts::TAU;

/// [`TrialError::Units`] when `table` declares radians and a gait2392 coordinate reaches more
/// than [`MAX_RADIANS`]; `stated` overrides the header (no check).
pub fn check_units(
    table: MotionTable,
    source: &str,
    stated: Option<AngleUnit>,
) -> Result<MotionTable, TrialError> {
    if let Some(unit) = stated {
        return Ok(table.with_in_degrees(unit == AngleUnit::Deg));
    }
    if table.in_degrees() {
        return Ok(table);
    }
    let worst = COORDINATES
        .iter()
        .filter_map(|name| {
            let c = table.column(name)?;
            let m = c
                .iter()
                .filter(|v| v.is_finite())
                .fold(0.0f64, |m, v| m.max(v.abs()));
            Some((*name, m))
        })
        .max_by(|a, b| a.1.total_cmp(&b.1));
    let Some((column, value)) = worst.filter(|w| w.1 > MAX_RADIANS) else {
        return Ok(table);
    };
    // The header's line that declares the unit (the header only: the file may be a day long).
    let found = std::fs::File::open(source).ok().and_then(|f| {
        use std::io::BufRead;
        std::io::BufReader::new(f)
            .lines()
            .map_while(Result::ok)
            .enumerate()
            .take_while(|(_, l)| !l.trim().eq_ignore_ascii_case("endheader"))
            .find(|(_, l)| l.trim_start().to_ascii_lowercase().starts_with("indegrees"))
    });
    let (at, declared) = match found {
        Some((i, l)) => (format!("{source}:{}", i + 1), l.trim().to_string()),
        None => (
            table.labels_location(),
            "no inDegrees line: radians by default".to_string(),
        ),
    };
    Err(TrialError::Units(Box::new(UnitsError {
        at,
        declared,
        column: column.to_string(),
        value,
    })))
}

/// The points of one foot and its hip in one frame (metres; origin at the pelvis origin,
/// ground axes: x forward, y up, z right).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Limb {
    /// Hip centre.
    pub hip: Vec3<f64>,
    /// The heel: gait2392's subtalar joint centre (its calcaneus origin, at the back of the
    /// heel); the ankle centre for models without a foot (HAK, PHAK, a device's frames).
    pub heel: Vec3<f64>,
    /// Ankle centre.
    pub ankle: Vec3<f64>,
    /// The forefoot end of the foot's long axis (from the heel): gait2392's MTP joint centre;
    /// the toe tip for models without a foot.
    pub forefoot: Vec3<f64>,
    /// Toe tip.
    pub toe: Vec3<f64>,
}

/// One frame: right limb, then left ([`qgait_kernel::Side::ALL`] order).
pub type Frame = [Limb; 2];

/// The point of a foot that bears the weight as the foot rolls: its heel, then its forefoot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FootPoint {
    /// [`Limb::heel`].
    Heel,
    /// [`Limb::forefoot`].
    Forefoot,
}

/// Velocities (m/s) relative to the pelvis origin, in ground axes, of one foot's points.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FootVelocity {
    /// Heel (gait2392's subtalar centre).
    pub heel: Vec3<f64>,
    /// Forefoot (gait2392's MTP centre).
    pub forefoot: Vec3<f64>,
    /// Toe tip.
    pub toe: Vec3<f64>,
}

impl FootVelocity {
    /// The velocity of `point`.
    pub fn at(&self, point: FootPoint) -> Vec3<f64> {
        match point {
            FootPoint::Heel => self.heel,
            FootPoint::Forefoot => self.forefoot,
        }
    }
}

impl Limb {
    /// Its `point`.
    pub fn at(&self, point: FootPoint) -> Vec3<f64> {
        match point {
            FootPoint::Heel => self.heel,
            FootPoint::Forefoot => self.forefoot,
        }
    }
}

/// Of both feet's heels and forefeet, the lowest relative to the pelvis in `frame`: the point
/// on the ground as the feet roll from heel to forefoot. Its side and which point; of equals,
/// the right before the left and the heel before the forefoot.
pub fn lowest_point(frame: &Frame) -> (usize, FootPoint) {
    [
        (0, FootPoint::Heel),
        (0, FootPoint::Forefoot),
        (1, FootPoint::Heel),
        (1, FootPoint::Forefoot),
    ]
    .into_iter()
    .min_by(|a, b| frame[a.0].at(a.1).y.total_cmp(&frame[b.0].at(b.1).y))
    .unwrap_or((0, FootPoint::Heel))
}

/// One recording.
pub struct Trial {
    /// Label (the file stem).
    pub label: String,
    /// Where it came from (the path or `builtin:` spec).
    pub source: String,
    /// Time of each frame (s).
    pub time: Vec<f64>,
    /// Points of each frame.
    pub frames: Vec<Frame>,
    /// gait2392's 17 coordinates of each frame (radians, [`COORDINATES`] order, gait2392's signs:
    /// the knee of a model that flexes it with positive angles negated; absent ones 0);
    /// `None` for a source with points only (a device's frames CSV).
    pub coordinates: Option<Vec<[f64; 17]>>,
    /// `pelvis_tx` and `pelvis_tz` of each frame (metres), when the motion has both and they
    /// change.
    pub translation: Option<Vec<[f64; 2]>>,
    /// The frames that begin a new stretch of the recording, in order: after a gap in time
    /// ([`gaps`]) or after rows left out. No event or stride spans one.
    pub breaks: Vec<usize>,
    /// Which variables (and whether step width) the model can move, from the coordinates it
    /// reads ([`Seen::from_reads`]): the report leaves out the others and says why
    /// ([`Seen::note`]). A planar model (gait10dof18musc) sees the sagittal four only.
    pub seen: Seen,
    /// The feet's velocities relative to the pelvis of each frame, from the kernel's
    /// differential kinematics ([`foot_velocities`]); `None` where they cannot be had that way
    /// (a device's frames, HAK or PHAK, a variable-step file): the rules then differentiate the
    /// positions.
    pub velocities: Option<Vec<[FootVelocity; 2]>>,
}

/// How a recording's last row leads back into its first: a file of one gait cycle, which
/// `--cycle whole` takes as periodic, ends where it starts, up to the stride-to-stride
/// variability of a cycle cut from a walk (OpenSim's single-cycle examples: 4-14 % of the
/// range the legs' points move through); a file that ends a tenth of a cycle or more away in
/// phase from its start (part of a cycle, or a cycle and a bit) leaves the swinging foot about
/// a third of that range or more from where it started.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wrap {
    /// The largest distance any point of the legs has from the last row to the first (m).
    pub jump: f64,
    /// The largest range any point of the legs moves through along an axis (m).
    pub range: f64,
}

impl Wrap {
    /// The jump back is at most a quarter of the range: the recording can be one cycle.
    pub fn leads_back(&self) -> bool {
        self.jump <= 0.25 * self.range
    }

    /// Its words, for a message.
    pub fn describe(&self) -> String {
        format!(
            "it does not end where it starts as a single cycle does (a point of the legs ends {:.1} cm from where it starts; the legs' points move through {:.1} cm)",
            100.0 * self.jump,
            100.0 * self.range
        )
    }
}

impl Trial {
    /// [`Wrap`]: how the last row leads back into the first; `None` with fewer than 3 rows.
    pub fn wrap(&self) -> Option<Wrap> {
        let f = &self.frames;
        if f.len() < 3 {
            return None;
        }
        let points = |fr: &Frame| {
            fr.iter()
                .flat_map(|l| [l.hip, l.heel, l.ankle, l.forefoot, l.toe])
                .collect::<Vec<_>>()
        };
        let (first, last) = (points(&f[0]), points(&f[f.len() - 1]));
        let jump = first
            .iter()
            .zip(&last)
            .map(|(p, q)| Vec3::distance(*p, *q))
            .fold(0.0f64, f64::max);
        let mut lo = first.clone();
        let mut hi = first;
        for fr in f {
            for (k, p) in points(fr).into_iter().enumerate() {
                lo[k] = Vec3::new(lo[k].x.min(p.x), lo[k].y.min(p.y), lo[k].z.min(p.z));
                hi[k] = Vec3::new(hi[k].x.max(p.x), hi[k].y.max(p.y), hi[k].z.max(p.z));
            }
        }
        let range = lo
            .iter()
            .zip(&hi)
            .map(|(a, b)| (b.x - a.x).max(b.y - a.y).max(b.z - a.z))
            .fold(0.0f64, f64::max);
        Some(Wrap { jump, range })
    }

    /// The stretches of frames between [`Trial::breaks`], in order (one when there is none).
    pub fn segments(&self) -> Vec<std::ops::Range<usize>> {
        let n = self.time.len();
        let mut out = Vec::with_capacity(self.breaks.len() + 1);
        let mut start = 0;
        for &b in self.breaks.iter().filter(|&&b| b > 0 && b < n) {
            if b > start {
                out.push(start..b);
                start = b;
            }
        }
        out.push(start..n);
        out
    }
}

/// A step in time longer than this many times the median step between frames is a gap in the
/// recording (lost frames, or a cut): no event or stride is formed across it. A step of twice
/// the median is one frame lost; sampling jitter stays well below half a step.
pub const GAP_FACTOR: f64 = 1.5;

/// A step in time shorter than this (s) is never a gap: events are sought to 25 ms, and a
/// variable-step file (OpenSim's CMC output) has steps of any length below it. A frame lost at
/// 60 Hz (33 ms) is interpolated over like any other step.
pub const MIN_GAP: f64 = 0.05;

/// Where row `r` of a table from `source` is: its line (a file), or the file and `row N: ` to
/// say before the rest (a generated table, which has no lines).
pub fn row_at(source: &str, line: Option<usize>, r: usize) -> (Location, String) {
    match line {
        Some(line) => (Location::line(source, line), String::new()),
        None => (Location::file(source), format!("row {}: ", r + 1)),
    }
}

/// The frames that follow a gap in `time` ([`GAP_FACTOR`] and [`MIN_GAP`]), merged with the breaks `known`
/// already (rows left out: not warned about again), in order; a warning for each new one.
/// `at(i)` says where frame `i` is: its location, and what to say before the rest when that is
/// not all ([`row_at`]).
pub fn gaps(
    time: &[f64],
    known: &[usize],
    at: impl Fn(usize) -> (Location, String),
) -> (Vec<usize>, Vec<Warning>) {
    let mut breaks = known.to_vec();
    let mut warnings = Vec::new();
    if let Some(median) = median_step(time) {
        let secs = |x: f64| (x * 1e6).round() / 1e6;
        for i in 1..time.len() {
            let step = time[i] - time[i - 1];
            if step > GAP_FACTOR * median && step > MIN_GAP && !known.contains(&i) {
                breaks.push(i);
                let (location, row) = at(i);
                warnings.push(Warning::Gap(WarningText {
                    at: Some(location),
                    detail: format!(
                    "{row}time jumps from {} s to {} s, a gap of {} s (the median step is {} s): no event or stride is formed across it",
                    secs(time[i - 1]),
                    secs(time[i]),
                    secs(step),
                    secs(median)
                ),
                }));
            }
        }
    }
    breaks.sort_unstable();
    breaks.dedup();
    (breaks, warnings)
}

/// Loads `source` (a `.mot`/`.sto` motion, `builtin:...`, or a device's frames CSV) and
/// evaluates `model` on every row. A frames CSV's rows are taken in time order as a `.mot`'s
/// ([`FramesTable::in_time_order`](qgait_device::frames_csv::FramesTable::in_time_order)).
pub fn load(source: &str, model: &Model) -> Result<(Trial, Vec<Warning>), TrialError> {
    load_with(source, model, None)
}

/// [`load`], the motion's angles in `angles_in` whatever its header says (`None`: the
/// header's, checked by [`check_units`]).
pub fn load_with(
    source: &str,
    model: &Model,
    angles_in: Option<AngleUnit>,
) -> Result<(Trial, Vec<Warning>), TrialError> {
    let label = default_label(source);
    if qgait_device::frames_csv::is_frames_csv(source) {
        let text = std::fs::read_to_string(source).map_err(|error| TrialError::Read {
            path: source.to_string(),
            error,
        })?;
        let table = qgait_device::frames_csv::parse(&text, source)?;
        if !table.time.is_empty() && table.time.iter().all(Option::is_none) {
            return Err(TrialError::NoTimes(source.to_string()));
        }
        let (table, mut warnings) = table.in_time_order(source)?;
        let time: Vec<f64> = table.time.iter().flatten().copied().collect();
        let (breaks, w) = gaps(&time, &[], |i| {
            (Location::line(source, table.at[i].0), String::new())
        });
        warnings.extend(w);
        let frames = table
            .points
            .iter()
            .map(|p| {
                let v = |i: usize| Vec3::new(p[i][0], p[i][1], p[i][2]);
                [0, 4].map(|b| Limb {
                    hip: v(b),
                    heel: v(b + 2),
                    ankle: v(b + 2),
                    forefoot: v(b + 3),
                    toe: v(b + 3),
                })
            })
            .collect();
        return Ok((
            Trial {
                label,
                source: source.to_string(),
                time,
                frames,
                coordinates: None,
                translation: None,
                breaks,
                seen: Seen::ALL,
                velocities: None,
            },
            warnings,
        ));
    }
    let (table, warnings) = load_motion(source)?;
    from_table(source, label, table, warnings, model, angles_in)
}

/// The recording of the motion `table` read from `source` (the whole file, or one window of
/// it: [`crate::stream`]), evaluated with `model`; `warnings` are the reader's so far, to which
/// the loading's are added.
pub fn from_table(
    source: &str,
    label: String,
    table: MotionTable,
    mut warnings: Vec<Warning>,
    model: &Model,
    angles_in: Option<AngleUnit>,
) -> Result<(Trial, Vec<Warning>), TrialError> {
    let table = check_units(table, source, angles_in)?;
    if table.header().pelvis_heading_free {
        warnings.push(Warning::Limitation(WarningText {
            at: Some(Location::file(source)),
            detail: "its pelvis is heading-free (qgait imu --pelvis heading-free): the walking direction is not in it, so turns cannot be found and strides taken while turning are analysed as straight walking; for gait analysis, solve with the default pelvis".to_string(),
        }));
    }
    let foot = model.lengths().is_none();
    let points = PointModel::new(model, foot)?;
    let seen = Seen::from_reads(points.reads());
    let (table, left_out, w) = leave_out_non_finite(table, points.reads());
    warnings.extend(w);
    let mut time = Vec::with_capacity(table.rows());
    let mut frames = Vec::with_capacity(table.rows());
    let column_warnings = std::cell::RefCell::new(Vec::new());
    let w = points.run::<TrialError>(
        MotionRows::from_table(table.clone()),
        &|w| column_warnings.borrow_mut().extend(w),
        |t, p| {
            time.push(t);
            // hip, knee, ankle, toe per side, then (gait2392) subtalar and MTP per side.
            frames.push([0, 1].map(|s| {
                let b = 4 * s;
                let (heel, forefoot) = if foot {
                    (p[8 + 2 * s], p[9 + 2 * s])
                } else {
                    (p[b + 2], p[b + 3])
                };
                Limb {
                    hip: p[b],
                    heel,
                    ankle: p[b + 2],
                    forefoot,
                    toe: p[b + 3],
                }
            }));
            Ok(())
        },
    );
    let w = w?;
    warnings.extend(column_warnings.into_inner());
    warnings.extend(w);
    // The joint angles of the recording (the model's FK gives the points only); their missing
    // columns were reported above or are not needed by the points.
    let knee = points.knee();
    let (mut coordinates, coordinate_warnings) =
        points::gait2392_coordinates(&table, knee, points.reads())?;
    // Rajagopal's knee flexes with positive angles; the trial's are gait2392's signs.
    for row in &mut coordinates {
        for k in KNEES {
            row[k] = knee.in_gait2392_signs(k, row[k]);
        }
    }
    for w in coordinate_warnings {
        if !warnings.contains(&w) {
            warnings.push(w);
        }
    }
    // A translation that never changes (an IMU solution writes zeros) says nothing.
    let moves = |c: &[f64]| c.iter().any(|v| (v - c[0]).abs() > 1e-6);
    let translation = match (table.column("pelvis_tx"), table.column("pelvis_tz")) {
        (Some(x), Some(z)) if moves(x) || moves(z) => {
            Some(x.iter().zip(z).map(|(&x, &z)| [x, z]).collect())
        }
        _ => None,
    };
    let (breaks, w) = gaps(&time, &left_out, |i| row_at(source, table.line(i), i));
    warnings.extend(w);
    // The kernel's velocities need the model's own signs back.
    let velocities = MotionModel::new(model).ok().and_then(|m| {
        let own: Vec<[f64; 17]> = coordinates
            .iter()
            .map(|row| {
                let mut row = *row;
                for k in KNEES {
                    row[k] = knee.in_gait2392_signs(k, row[k]);
                }
                row
            })
            .collect();
        foot_velocities(&m, &time, &own, &breaks)
    });
    Ok((
        Trial {
            label,
            source: source.to_string(),
            time,
            frames,
            coordinates: Some(coordinates),
            translation,
            breaks,
            seen,
            velocities,
        },
        warnings,
    ))
}

/// `table` without its rows that have a value that is not a finite number (`nan`, `inf`) in a
/// column the analysis reads: the coordinates of [`COORDINATES`] with `reads` true (the model's
/// and the joint angles'); a column it does not read does not matter. Each run of such rows
/// gets one warning naming the file, line and column of its first bad value. Also the rows
/// (of the table returned) that follow a run left out: breaks ([`Trial::breaks`]).
fn leave_out_non_finite(
    table: MotionTable,
    reads: [bool; 17],
) -> (MotionTable, Vec<usize>, Vec<Warning>) {
    let header = table.header();
    let columns: Vec<(usize, &str)> = COORDINATES
        .iter()
        .zip(reads)
        .filter(|(_, r)| *r)
        .filter_map(|(name, _)| header.index_of(name).map(|c| (c, *name)))
        .collect();
    let bad: Vec<Option<(usize, &str)>> = (0..table.rows())
        .map(|r| {
            columns
                .iter()
                .copied()
                .find(|&(c, _)| !table.value(r, c).is_finite())
        })
        .collect();
    if bad.iter().all(Option::is_none) {
        return (table, Vec::new(), Vec::new());
    }
    let source = table.source();
    let row_at = |r: usize| match table.line(r) {
        Some(line) => format!("line {line}"),
        None => format!("row {}", r + 1),
    };
    let (mut warnings, mut breaks) = (Vec::new(), Vec::new());
    let (mut r, mut kept) = (0, 0);
    while r < bad.len() {
        let Some((c, name)) = bad[r] else {
            r += 1;
            kept += 1;
            continue;
        };
        let end = (r..bad.len())
            .find(|&k| bad[k].is_none())
            .unwrap_or(bad.len());
        let (at, row, text) = match table.non_finite_at(r, c) {
            Some(nf) => (
                Location {
                    path: source.to_string(),
                    line: Some(nf.line),
                    column: Some(nf.column),
                },
                String::new(),
                nf.text.clone(),
            ),
            None => (
                Location::file(source),
                format!("{}: ", row_at(r)),
                table.value(r, c).to_string(),
            ),
        };
        let rows = if end - r == 1 {
            "this row is left out, with the strides that include it".to_string()
        } else {
            format!(
                "this row and the next {} to {} are left out, with the strides that include them",
                end - r - 1,
                row_at(end - 1)
            )
        };
        warnings.push(Warning::RowsLeftOut(WarningText {
            at: Some(at),
            detail: format!(
                "{row}value `{text}` in column `{name}` is not a finite number: {rows}"
            ),
        }));
        if kept > 0 && end < bad.len() {
            breaks.push(kept);
        }
        r = end;
    }
    let table = table.without_rows(|r| bad[r].is_some());
    (table, breaks, warnings)
}

/// The index of a coordinate in [`COORDINATES`].
pub fn coordinate(name: &str) -> usize {
    COORDINATES
        .iter()
        .position(|c| *c == name)
        .unwrap_or_else(|| panic!("`{name}` is not a gait2392 coordinate"))
}

/// The median step between frames (s); `None` for fewer than two frames.
pub fn median_step(time: &[f64]) -> Option<f64> {
    let mut dt: Vec<f64> = time.windows(2).map(|w| w[1] - w[0]).collect();
    dt.sort_by(f64::total_cmp);
    dt.get(dt.len() / 2).copied()
}

/// The feet's velocities relative to the pelvis (ground axes) of every frame: the kernel's
/// differential kinematics of `model` at each frame's coordinates (the model's own signs) and
/// their speeds, the speeds from the kernel's five-point [`differentiate`] within each stretch
/// between the rows left out. `None` when a stretch is not evenly sampled (the differentiator
/// needs one step: OpenSim's variable-step CMC output) or shorter than five frames.
pub fn foot_velocities(
    model: &MotionModel,
    time: &[f64],
    coordinates: &[[f64; 17]],
    breaks: &[usize],
) -> Option<Vec<[FootVelocity; 2]>> {
    let n = time.len();
    let mut cuts: Vec<usize> = breaks.iter().copied().filter(|&b| b > 0 && b < n).collect();
    cuts.sort_unstable();
    cuts.dedup();
    let mut out = Vec::with_capacity(n);
    let mut start = 0;
    for end in cuts.into_iter().chain([n]) {
        let t = &time[start..end];
        let m = t.len();
        if m < 5 {
            return None;
        }
        let dt = (t[m - 1] - t[0]) / (m - 1) as f64;
        if dt.is_nan()
            || dt <= 0.0
            || t.windows(2)
                .any(|w| ((w[1] - w[0]) - dt).abs() > 1e-6 * dt.max(1e-3))
        {
            return None;
        }
        let (mut qd, mut qdd) = (vec![[0.0; 17]; m], vec![[0.0; 17]; m]);
        let (mut col, mut d1, mut d2) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
        for k in 0..17 {
            for (c, q) in col.iter_mut().zip(&coordinates[start..end]) {
                *c = q[k];
            }
            differentiate(&col, dt, &mut d1, &mut d2);
            for i in 0..m {
                qd[i][k] = d1[i];
                qdd[i][k] = d2[i];
            }
        }
        for i in 0..m {
            let p = model.points(&coordinates[start + i], &qd[i], &qdd[i]);
            // `point_names(true)`: hip, knee, ankle, toe tip per side, then subtalar and MTP
            // per side (HAK and PHAK have neither: no velocities of the heel and forefoot).
            if p.len() < 12 {
                return None;
            }
            out.push([0, 1].map(|s| FootVelocity {
                heel: p[8 + 2 * s].velocity,
                forefoot: p[9 + 2 * s].velocity,
                toe: p[3 + 4 * s].velocity,
            }));
        }
        start = end;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_with_a_bad_value_in_a_column_read_are_left_out() {
        let head =
            "m\nversion=1\ninDegrees=yes\nendheader\ntime\thip_flexion_r\tknee_angle_r\tforce\n";
        let rows = [
            "0\t1\t-5\t1",
            "0.01\t1\tnan\t1",
            "0.02\t1\t-inf\t1",
            "0.03\t1\t-5\tnan",
            "0.04\tNaN\tnan\t1",
            "0.05\t1\t-5\t1",
            "0.06\t1\tnan\t1",
        ];
        let text = format!("{head}{}\n", rows.join("\n"));
        let (table, _) = MotionTable::parse(&text, "m.mot").unwrap();
        let (kept, breaks, w) = leave_out_non_finite(table.clone(), [true; 17]);
        // `force` is read by nothing: its `nan` does not matter.
        assert_eq!(kept.time(), &[0.0, 0.03, 0.05]);
        assert_eq!(kept.line(1), Some(9));
        assert_eq!(breaks, [1, 2]);
        assert_eq!(w.len(), 3, "{w:?}");
        assert_eq!(
            w[0].to_string(),
            "m.mot:7:8: value `nan` in column `knee_angle_r` is not a finite number: this row and the next 1 to line 8 are left out, with the strides that include them"
        );
        assert!(
            w[1].to_string()
                .starts_with("m.mot:10:6: value `NaN` in column `hip_flexion_r`"),
            "{w:?}"
        );
        assert!(w[2].to_string().starts_with("m.mot:12:8: value `nan` in column `knee_angle_r` is not a finite number: this row is left out"), "{w:?}");
        // A column the model does not read (an imported chain's locked one) does not matter.
        let mut reads = [true; 17];
        reads[coordinate("knee_angle_r")] = false;
        let (kept, breaks, w) = leave_out_non_finite(table.clone(), reads);
        assert_eq!(kept.rows(), 6);
        assert_eq!(breaks, [4]);
        assert_eq!(w.len(), 1, "{w:?}");
        // Nothing bad: the table as it is.
        let (kept, breaks, w) = leave_out_non_finite(kept, reads);
        assert_eq!(kept.rows(), 6);
        assert!(breaks.is_empty() && w.is_empty());
    }

    #[test]
    fn a_step_longer_than_one_and_a_half_frames_is_a_gap() {
        // 100 Hz with a jitter of 0.2 ms, 2 s missing after 8 s.
        let mut time: Vec<f64> = (0..=800).map(|i| i as f64 * 0.01).collect();
        time.extend((1000..=1200).map(|i| i as f64 * 0.01));
        time[10] += 0.0002;
        let (breaks, w) = gaps(&time, &[], |i| {
            (Location::line("w.mot", i + 7), String::new())
        });
        assert_eq!(breaks, [801]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(
            w[0].to_string(),
            "w.mot:808: time jumps from 8 s to 10 s, a gap of 2 s (the median step is 0.01 s): no event or stride is formed across it"
        );
        // A break known already is not warned about again; others are merged in order.
        let (breaks, w) = gaps(&time, &[801, 3], |i| {
            (Location::file(i.to_string()), String::new())
        });
        assert_eq!(breaks, [3, 801]);
        assert!(w.is_empty(), "{w:?}");
        let trial = Trial {
            label: "w".into(),
            source: "w.mot".into(),
            time: time.clone(),
            frames: vec![[Limb::default(); 2]; time.len()],
            coordinates: None,
            translation: None,
            breaks,
            seen: Seen::ALL,
            velocities: None,
        };
        assert_eq!(trial.segments(), [0..3, 3..801, 801..1002]);
        // Steady sampling: no gap.
        let (breaks, w) = gaps(&time[..801], &[], |i| {
            (Location::file(i.to_string()), String::new())
        });
        assert!(breaks.is_empty() && w.is_empty());
        // A variable step (CMC output: 1 to 20 ms): no gap; a 0.3 s jump in it is one.
        let mut t = vec![0.0];
        for k in 0..2000 {
            let step = [0.001, 0.004, 0.02, 0.0025, 0.012][k % 5];
            t.push(t[k] + if k == 1000 { 0.3 } else { step });
        }
        let (breaks, w) = gaps(&t, &[], |i| (Location::file(i.to_string()), String::new()));
        assert_eq!(breaks, [1001], "{w:?}");
    }
}
