//! OpenSim orientation files (`.sto` with `DataType=Quaternion`, as OpenSense reads and writes
//! them): one `<body>_imu` column per sensor (`pelvis_imu`, `femur_r_imu`, ..., `torso_imu`;
//! [`Segment::from_name`]), each cell one unit quaternion `w,x,y,z` (comma separated inside the
//! tab-separated row), the sensor's orientation in its world frame.
//!
//! The header and lines are read by [`MotionReader`] (the one `.mot`/`.sto` parser); this reader
//! only splits each cell into its quaternion. Rows are handed out one at a time (constant
//! memory). Errors name the file, the line and, for a cell, its 1-based character column. A cell
//! of four `nan` is a sensor without a reading in that row (the kernel then holds what it
//! determines); a column whose label is not one of the eight sensors is ignored with a warning.

use std::path::Path;

use qgait_kernel::imu::{unit, Orientations, Segment};
use qgait_kernel::Quat;

use crate::diagnostics::{Location, Warning, WarningText};
use crate::mot::{tokens, MotError, MotionReader, QuaternionFault};

/// One row: its 1-based line, its time and each sensor's reading (raw, in the sensors' world
/// frame, normalised).
#[derive(Debug, Clone, PartialEq)]
pub struct OrientationRow {
    /// 1-based line in the file.
    pub line: usize,
    /// Seconds.
    pub time: f64,
    /// The readings by segment.
    pub readings: Orientations<f64>,
}

/// Reads an orientation `.sto` row by row.
pub struct OrientationReader {
    reader: MotionReader<std::io::BufReader<std::fs::File>>,
    source: String,
    /// The segment of each column after `time` (`None`: ignored column).
    columns: Vec<Option<Segment>>,
    warnings: Vec<Warning>,
    previous_time: Option<(f64, usize)>,
    rows: usize,
}

fn err(source: &str, line: usize, message: String) -> MotError {
    MotError::Format {
        path: source.to_string(),
        line,
        message,
    }
}

impl OrientationReader {
    /// Opens `path` and reads its header: `DataType=Quaternion`, labels `time` and at least
    /// one sensor column, no sensor twice.
    pub fn open(path: &Path) -> Result<Self, MotError> {
        let reader = MotionReader::open(path)?;
        let header = reader.header();
        let source = header.source.clone();
        let labels_line = header.labels_line.unwrap_or(1);
        match reader.data_type() {
            Some(t) if t.eq_ignore_ascii_case("quaternion") => {}
            other => {
                return Err(err(
                    &source,
                    labels_line,
                    format!(
                        "not an orientation file: the header says DataType={} (expected DataType=Quaternion, one `w,x,y,z` cell per IMU)",
                        other.unwrap_or("(none)")
                    ),
                ))
            }
        }
        let mut columns = Vec::new();
        let mut ignored = Vec::new();
        for (i, label) in header.labels.iter().enumerate().skip(1) {
            let segment = Segment::from_name(label);
            if let Some(s) = segment {
                if columns.contains(&Some(s)) {
                    return Err(err(
                        &source,
                        labels_line,
                        format!(
                            "sensor `{s}` has two columns (the second is column {})",
                            i + 1
                        ),
                    ));
                }
            } else {
                ignored.push(label.clone());
            }
            columns.push(segment);
        }
        if columns.iter().all(Option::is_none) {
            return Err(err(
                &source,
                labels_line,
                format!(
                    "no IMU column: expected labels such as {}",
                    Segment::ALL.map(Segment::imu_label).join(", ")
                ),
            ));
        }
        let mut warnings = Vec::new();
        if !ignored.is_empty() {
            warnings.push(Warning::Ignored(WarningText {
 at: Some(Location::line(source.to_string(), labels_line)),
 detail: format!("column(s) {} are not IMUs of the lower-body set (pelvis, femurs, tibias, calcanei, torso); ignored", ignored.join(", ")),
}));
        }
        Ok(Self {
            reader,
            source,
            columns,
            warnings,
            previous_time: None,
            rows: 0,
        })
    }

    /// The file, as it is named in messages.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The sensors that have a column.
    pub fn sensors(&self) -> impl Iterator<Item = Segment> + '_ {
        self.columns.iter().flatten().copied()
    }

    /// Where the column labels are (`file:line`), for messages.
    pub fn labels_location(&self) -> String {
        self.reader.header().labels_location()
    }

    /// Where the column labels are.
    pub fn labels_at(&self) -> Location {
        self.reader.header().labels_at()
    }

    /// Warnings so far (each returned once).
    pub fn take_warnings(&mut self) -> Vec<Warning> {
        let mut w = std::mem::take(&mut self.warnings);
        w.extend(self.reader.take_warnings());
        w
    }

    /// The next row, or `None` after the last (an error if the file has no row at all).
    pub fn next_row(&mut self) -> Result<Option<OrientationRow>, MotError> {
        let Some((line, text)) = self.reader.next_text_line()? else {
            if self.rows == 0 {
                return Err(err(
                    &self.source,
                    self.reader.header().labels_line.unwrap_or(1),
                    "no data rows after the column labels".into(),
                ));
            }
            return Ok(None);
        };
        let labels = &self.reader.header().labels;
        let column = |start: usize| text[..start].chars().count() + 1;
        let mut readings = Orientations::EMPTY;
        let mut time = None;
        let mut count = 0;
        for (i, (start, cell)) in tokens(&text).enumerate() {
            count = i + 1;
            if i >= labels.len() {
                continue;
            }
            if i == 0 {
                let t = cell.parse::<f64>().ok().filter(|t| t.is_finite());
                time = Some(t.ok_or_else(|| MotError::BadNumber {
                    path: self.source.clone(),
                    line,
                    column: column(start),
                    name: labels[0].clone(),
                    text: cell.to_string(),
                })?);
                continue;
            }
            let Some(segment) = self.columns[i - 1] else {
                continue;
            };
            readings.set(
                segment,
                quaternion(cell, segment).map_err(|why| MotError::BadQuaternion {
                    path: self.source.clone(),
                    line,
                    column: column(start),
                    index: i + 1,
                    name: labels[i].clone(),
                    text: cell.to_string(),
                    why: Box::new(why),
                })?,
            );
        }
        if count != labels.len() {
            return Err(err(
                &self.source,
                line,
                format!(
                    "row has {count} cells but the header names {} columns",
                    labels.len()
                ),
            ));
        }
        let time = time.expect("a row has at least one cell");
        if let Some((previous, previous_line)) = self.previous_time {
            if time <= previous {
                return Err(err(
                    &self.source,
                    line,
                    format!("time {time} is not after the previous row's {previous} (line {previous_line})"),
                ));
            }
        }
        self.previous_time = Some((time, line));
        self.rows += 1;
        Ok(Some(OrientationRow {
            line,
            time,
            readings,
        }))
    }
}

/// A cell `w,x,y,z` as a unit quaternion (normalised: [`unit`]), `None` for `nan,nan,nan,nan`
/// (no reading), or why not.
fn quaternion(cell: &str, segment: Segment) -> Result<Option<Quat<f64>>, QuaternionFault> {
    let parts: Vec<&str> = cell.split(',').collect();
    if parts.len() != 4 {
        return Err(QuaternionFault::Components(parts.len()));
    }
    let mut v = [0.0; 4];
    for (k, (p, slot)) in parts.iter().zip(&mut v).enumerate() {
        *slot = p
            .trim()
            .parse::<f64>()
            .map_err(|_| QuaternionFault::NotANumber {
                index: k + 1,
                text: p.to_string(),
            })?;
    }
    if v.iter().all(|c| c.is_nan()) {
        return Ok(None);
    }
    unit(Quat::new(v[0], v[1], v[2], v[3]), segment)
        .map(Some)
        .map_err(|_| QuaternionFault::NotUnit {
            norm: (v.iter().map(|c| c * c).sum::<f64>()).sqrt(),
        })
}
