//! The vendor IMU exports OpenSense reads, with OpenSense's reader settings: Xsens MT Manager
//! `.txt` (one file per sensor) and APDM `.csv` (one file per trial), beside OpenSim's own
//! orientation `.sto` ([`OrientationReader`]). [`open`] picks the reader by what the path is.
//!
//! **Reader settings** ([`Mapping`]): OpenSim's `XsensDataReaderSettings` or
//! `APDMDataReaderSettings` XML (`myIMUMappings.xml` in OpenSense's tutorials), read as OpenSense
//! reads it: each `<ExperimentalSensor name="...">` maps a vendor sensor (an Xsens file-name
//! suffix such as `_00B421AF`, an APDM sensor label such as `Lumbar`) to its IMU in the model
//! (`<name_in_model>pelvis_imu</name_in_model>`); `<trial_prefix>` and `<sampling_rate>` are
//! used when given. A sensor mapped to a name that is not one of the lower-body set is ignored
//! with a warning.
//!
//! **Xsens MT Manager `.txt`** (OpenSim's `XsensDataReader`): a trial is the files
//! `<folder>/<trial prefix><sensor name>.txt`, one per mapped sensor. Each file: any number of
//! comment lines starting with `//` (`// Update Rate: 100.0Hz` gives the sampling rate), a line
//! of tab-separated labels, then one tab-separated line per sample. The orientation is read
//! from `Quat_q0`..`Quat_q3` (w, x, y, z) or, without them, from the rotation matrix
//! `Mat[1][1]`, `Mat[2][1]`, `Mat[3][1]`, `Mat[1][2]`, ... (sensor to world, `Mat[row][column]`).
//! Sample `k` is at `k / rate` seconds, as OpenSim times it. The rate comes from the files'
//! `Update Rate` comment, else the settings' `sampling_rate`, else `--rate`; without any of them
//! the trial is refused (OpenSim would assume 40 Hz, which recent MT Manager versions make wrong
//! for most recordings). All files must have the same rate and the same number of samples.
//!
//! **APDM `.csv`** (OpenSim's `APDMDataReader`), either layout: the older one (`Test Name:`,
//! `Sample Rate:,<Hz>` lines, a label line `Time,<sensor>/Acceleration/X,...,
//! <sensor>/Orientation/Scalar,<sensor>/Orientation/X,<sensor>/Orientation/Y,
//! <sensor>/Orientation/Z,...`, a units line, then samples) or `Format=7` (the sensor names on
//! the first line, the orientation's four columns seven after each name; two more header lines;
//! 128 Hz as OpenSim assumes, unless `--rate`). Sample `k` is at `k / rate` seconds. Without
//! settings, the sensor labels themselves are taken as model IMU names (`pelvis_imu` or
//! `pelvis`).
//!
//! **Xsens raw channels** ([`XsensRaw`], for `qgait fuse`): one MT Manager `.txt` with
//! `Acc_X..Z` (m/s²), `Gyr_X..Z` (rad/s) and optionally `Mag_X..Z` (arbitrary units normalised
//! to about 1), read whole, with the same comment and label rules.
//!
//! Orientation rows are read one at a time (constant memory). Errors name the file, the line and, for a
//! value, its column.

use std::borrow::Cow;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use csv::ByteRecord;
use qgait_kernel::imu::math::from_rotation_matrix;
use qgait_kernel::imu::{unit, Orientations, Segment, UNIT_TOLERANCE};
use qgait_kernel::Quat;

use crate::diagnostics::{Location, Warning, WarningText};
use crate::imu_sto::{OrientationReader, OrientationRow};
use crate::mot::MotError;

/// Where orientation rows come from: an OpenSim `.sto`, an Xsens trial or an APDM `.csv`.
pub trait OrientationSource {
    /// The file (or the Xsens trial's files), as named in messages.
    fn source(&self) -> &str;
    /// The sensors that have a column.
    fn sensors(&self) -> Vec<Segment>;
    /// Where the column labels are (`file:line`), for messages.
    fn labels_location(&self) -> String {
        self.labels_at().to_string()
    }
    /// Where the column labels are.
    fn labels_at(&self) -> Location;
    /// Warnings so far (each returned once).
    fn take_warnings(&mut self) -> Vec<Warning>;
    /// The next row, or `None` after the last (an error if there is no row at all).
    fn next_row(&mut self) -> Result<Option<OrientationRow>, MotError>;
    /// Whether the rows' times are the file's own (a time column), whatever rate is given.
    fn has_times(&self) -> bool {
        false
    }
}

impl OrientationSource for OrientationReader {
    fn source(&self) -> &str {
        OrientationReader::source(self)
    }
    fn has_times(&self) -> bool {
        true
    }
    fn sensors(&self) -> Vec<Segment> {
        OrientationReader::sensors(self).collect()
    }
    fn labels_at(&self) -> Location {
        OrientationReader::labels_at(self)
    }
    fn take_warnings(&mut self) -> Vec<Warning> {
        OrientationReader::take_warnings(self)
    }
    fn next_row(&mut self) -> Result<Option<OrientationRow>, MotError> {
        OrientationReader::next_row(self)
    }
}

fn format_err(path: &str, line: usize, message: String) -> MotError {
    MotError::Format {
        path: path.to_string(),
        line,
        message,
    }
}

/// OpenSense's reader settings (`XsensDataReaderSettings` or `APDMDataReaderSettings`).
#[derive(Debug, Clone, PartialEq)]
pub struct Mapping {
    /// The settings file, as named in messages.
    pub source: String,
    /// `trial_prefix`, if given (Xsens).
    pub trial_prefix: Option<String>,
    /// `sampling_rate` (Hz), if given (Xsens).
    pub sampling_rate: Option<f64>,
    /// Vendor sensor name, the model IMU it is (if one of the set), and the line of its entry.
    pub sensors: Vec<(String, Option<Segment>, usize)>,
    /// Sensors mapped to names outside the lower-body set.
    pub warnings: Vec<Warning>,
}

impl Mapping {
    /// Reads a settings XML file.
    pub fn read(path: &Path) -> Result<Self, MotError> {
        let source = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|error| MotError::Io {
            path: source.clone(),
            error,
        })?;
        let doc = roxmltree::Document::parse(&text)
            .map_err(|e| format_err(&source, e.pos().row as usize, format!("not XML: {e}")))?;
        let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row as usize;
        let text_of = |n: roxmltree::Node, tag: &str| {
            n.children()
                .find(|c| c.has_tag_name(tag))
                .and_then(|c| c.text())
                .map(|t| t.trim().to_string())
                .filter(|t| !t.is_empty())
        };
        let root = doc
            .descendants()
            .find(|n| {
                n.has_tag_name("XsensDataReaderSettings")
                    || n.has_tag_name("APDMDataReaderSettings")
            })
            .ok_or_else(|| {
                format_err(
                    &source,
                    1,
                    "no <XsensDataReaderSettings> or <APDMDataReaderSettings> (OpenSense's IMU reader settings)".into(),
                )
            })?;
        let sampling_rate = match root.children().find(|c| c.has_tag_name("sampling_rate")) {
            None => None,
            Some(n) => {
                let t = n.text().unwrap_or("").trim();
                Some(
                    t.parse::<f64>()
                        .ok()
                        .filter(|r| *r > 0.0 && r.is_finite())
                        .ok_or_else(|| {
                            format_err(
                                &source,
                                line(n),
                                format!("sampling_rate `{t}` is not a rate in Hz"),
                            )
                        })?,
                )
            }
        };
        let mut sensors = Vec::new();
        let mut warnings = Vec::new();
        for n in root
            .descendants()
            .filter(|n| n.has_tag_name("ExperimentalSensor"))
        {
            let at = line(n);
            let name = n.attribute("name").unwrap_or("").to_string();
            let in_model = text_of(n, "name_in_model").ok_or_else(|| {
                format_err(
                    &source,
                    at,
                    format!("sensor `{name}` has no <name_in_model>"),
                )
            })?;
            let segment = Segment::from_name(&in_model);
            if segment.is_none() {
                warnings.push(Warning::Ignored(WarningText {
 at: Some(Location::line(source.to_string(), at)),
 detail: format!("sensor `{name}` is `{in_model}`, not an IMU of the lower-body set ({}); ignored", Segment::ALL.map(Segment::imu_label).join(", ")),
}));
            }
            if sensors
                .iter()
                .any(|(_, s, _)| segment.is_some() && *s == segment)
            {
                return Err(format_err(
                    &source,
                    at,
                    format!("`{in_model}` is mapped from two sensors"),
                ));
            }
            sensors.push((name, segment, at));
        }
        if sensors.is_empty() {
            return Err(format_err(
                &source,
                line(root),
                "no <ExperimentalSensor> in <ExperimentalSensors>".into(),
            ));
        }
        Ok(Self {
            source,
            trial_prefix: text_of(root, "trial_prefix"),
            sampling_rate,
            sensors,
            warnings,
        })
    }
}

/// Opens the orientations at `path`: an OpenSim `.sto`/`.mot`, an APDM `.csv`, or an Xsens
/// trial (a folder, whose trial prefix the settings give, or `FOLDER/PREFIX`: the files
/// `FOLDER/PREFIX<sensor>.txt`; `mapping` required). `rate` (Hz) is used where the files and
/// settings give none.
pub fn open(
    path: &Path,
    mapping: Option<&Mapping>,
    rate: Option<f64>,
) -> Result<Box<dyn OrientationSource>, MotError> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("csv") => Ok(Box::new(ApdmTrial::open(path, mapping, rate)?)),
        Some("sto") | Some("mot") => Ok(Box::new(OrientationReader::open(path)?)),
        _ if path.is_file() => Err(format_err(
            &path.display().to_string(),
            1,
            "not an orientation file qgait reads: an OpenSim orientation .sto, an APDM .csv, or an Xsens trial (its folder or FOLDER/PREFIX, with --imu-mapping)".into(),
        )),
        _ => Ok(Box::new(XsensTrial::open(path, mapping, rate)?)),
    }
}

/// `path` opened for reading.
fn open_file(path: &Path) -> Result<File, MotError> {
    File::open(path).map_err(|error| MotError::Io {
        path: path.display().to_string(),
        error,
    })
}

/// A text file read line by line with its line number (Latin-1 bytes kept as characters).
struct Lines {
    reader: BufReader<File>,
    line: usize,
    buffer: Vec<u8>,
}

impl Lines {
    fn open(path: &Path) -> Result<Self, MotError> {
        let file = open_file(path)?;
        Ok(Self {
            reader: BufReader::new(file),
            line: 0,
            buffer: Vec::new(),
        })
    }

    /// The next line without its end, or `None` at the end of the file.
    fn next(&mut self, path: &str) -> Result<Option<String>, MotError> {
        self.buffer.clear();
        let n = self
            .reader
            .read_until(b'\n', &mut self.buffer)
            .map_err(|error| MotError::Io {
                path: path.to_string(),
                error,
            })?;
        if n == 0 {
            return Ok(None);
        }
        self.line += 1;
        while matches!(self.buffer.last(), Some(b'\n' | b'\r')) {
            self.buffer.pop();
        }
        Ok(Some(match String::from_utf8(self.buffer.clone()) {
            Ok(s) => s,
            Err(_) => self.buffer.iter().map(|&b| b as char).collect(),
        }))
    }

    /// The next line that is not blank.
    fn next_data(&mut self, path: &str) -> Result<Option<String>, MotError> {
        while let Some(l) = self.next(path)? {
            if !l.trim().is_empty() {
                return Ok(Some(l));
            }
        }
        Ok(None)
    }
}

/// The 1-based character column of each cell of `line` split at `separator`.
fn cells(line: &str, separator: char) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut column = 1;
    for cell in line.split(separator) {
        out.push((column, cell));
        column += cell.chars().count() + 1;
    }
    out
}

/// The number in `cells[index]`, or an error naming file, line, column and label.
fn number(
    path: &str,
    line: usize,
    cells: &[(usize, impl AsRef<str>)],
    index: usize,
    label: &str,
) -> Result<f64, MotError> {
    let Some((column, text)) = cells.get(index) else {
        return Err(format_err(
            path,
            line,
            format!(
                "{} values, but `{label}` is column {}",
                cells.len(),
                index + 1
            ),
        ));
    };
    let text = text.as_ref();
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| MotError::BadNumber {
            path: path.to_string(),
            line,
            column: *column,
            name: label.to_string(),
            text: text.to_string(),
        })
}

/// `q` normalised, or an error naming where it is.
fn reading(
    q: Quat<f64>,
    segment: Segment,
    path: &str,
    line: usize,
    column: usize,
    label: &str,
) -> Result<Quat<f64>, MotError> {
    unit(q, segment).map_err(|_| {
        format_err(
            path,
            line,
            format!(
                "column {column} (`{label}`): the orientation's norm {} is not within {UNIT_TOLERANCE} of 1 (not a rotation)",
                q.norm()
            ),
        )
    })
}

/// The `//` comment lines of an Xsens MT Manager `.txt` (the `Update Rate`, if any) and its label
/// line (the first other line that is not blank).
fn xsens_header(lines: &mut Lines, p: &str) -> Result<(Option<f64>, String), MotError> {
    let mut rate = None;
    loop {
        let Some(l) = lines.next(p)? else {
            return Err(format_err(
                p,
                lines.line.max(1),
                "no label line (PacketCounter, ..., Quat_q0 or Mat[1][1], ...) after the // comments".into(),
            ));
        };
        if let Some(comment) = l.strip_prefix("//") {
            if let Some((key, value)) = comment.split_once(':') {
                if key.trim() == "Update Rate" {
                    let v = value.trim().trim_end_matches("Hz").trim();
                    rate = Some(
                        v.parse::<f64>()
                            .ok()
                            .filter(|r| *r > 0.0 && r.is_finite())
                            .ok_or_else(|| {
                                format_err(
                                    p,
                                    lines.line,
                                    format!("Update Rate `{}` is not a rate in Hz", value.trim()),
                                )
                            })?,
                    );
                }
            }
            continue;
        }
        if l.trim().is_empty() {
            continue;
        }
        return Ok((rate, l));
    }
}

/// One Xsens MT Manager `.txt` with the raw inertial channels (`Acc_X`..`Acc_Z` in m/s²,
/// `Gyr_X`..`Gyr_Z` in rad/s and, if exported, `Mag_X`..`Mag_Z` in MT Manager's arbitrary
/// units, normalised to about 1), read whole, in the sensor's frame. The sampling rate is the
/// `// Update Rate` comment's, else the one given; sample `k` is at `k / rate` seconds, as
/// OpenSim times Xsens files.
#[derive(Debug, Clone, PartialEq)]
pub struct XsensRaw {
    /// The file, as named in messages.
    pub source: String,
    /// Hz.
    pub rate: f64,
    /// The 1-based line of each sample.
    pub lines: Vec<usize>,
    /// Specific force, m/s².
    pub acc: Vec<[f64; 3]>,
    /// Angular rate, rad/s.
    pub gyr: Vec<[f64; 3]>,
    /// Magnetic field (arbitrary units), when the file has `Mag_*` columns.
    pub mag: Option<Vec<[f64; 3]>>,
}

impl XsensRaw {
    /// Reads `path`; `rate` (Hz) is used when the file has no `Update Rate` comment.
    pub fn read(path: &Path, rate: Option<f64>) -> Result<Self, MotError> {
        let p = path.display().to_string();
        let mut lines = Lines::open(path)?;
        let (file_rate, header) = xsens_header(&mut lines, &p)?;
        let labels_line = lines.line;
        let labels: Vec<&str> = header.split('\t').map(str::trim).collect();
        let find3 = |prefix: &str| -> Option<[usize; 3]> {
            let f = |a: &str| labels.iter().position(|x| *x == format!("{prefix}_{a}"));
            Some([f("X")?, f("Y")?, f("Z")?])
        };
        let need = |prefix: &str| {
            find3(prefix).ok_or_else(|| {
                format_err(
                    &p,
                    labels_line,
                    format!(
                        "no {prefix}_X, {prefix}_Y, {prefix}_Z columns: export the raw (calibrated) inertial data from MT Manager"
                    ),
                )
            })
        };
        let acc_at = need("Acc")?;
        let gyr_at = need("Gyr")?;
        let mag_at = find3("Mag");
        let rate = file_rate.or(rate).ok_or_else(|| {
            format_err(
                &p,
                1,
                "no `// Update Rate:` comment and no --rate: the sampling rate is unknown".into(),
            )
        })?;
        let mut raw = Self {
            source: p.clone(),
            rate,
            lines: Vec::new(),
            acc: Vec::new(),
            gyr: Vec::new(),
            mag: mag_at.map(|_| Vec::new()),
        };
        while let Some(text) = lines.next_data(&p)? {
            let line = lines.line;
            let c = cells(&text, '\t');
            let v3 = |at: [usize; 3], prefix: &str| -> Result<[f64; 3], MotError> {
                let mut v = [0.0; 3];
                for (k, a) in ["X", "Y", "Z"].iter().enumerate() {
                    v[k] = number(&p, line, &c, at[k], &format!("{prefix}_{a}"))?;
                }
                Ok(v)
            };
            raw.acc.push(v3(acc_at, "Acc")?);
            raw.gyr.push(v3(gyr_at, "Gyr")?);
            if let (Some(at), Some(m)) = (mag_at, &mut raw.mag) {
                m.push(v3(at, "Mag")?);
            }
            raw.lines.push(line);
        }
        if raw.lines.is_empty() {
            return Err(format_err(
                &p,
                labels_line,
                "no samples after the labels".into(),
            ));
        }
        Ok(raw)
    }
}

/// How an Xsens file holds the orientation.
#[derive(Debug, Clone, Copy)]
enum XsensOrientation {
    /// `Quat_q0`..`Quat_q3` columns.
    Quaternion([usize; 4]),
    /// `Mat[r][c]` columns, in `[row][column]` order.
    Matrix([[usize; 3]; 3]),
}

struct XsensFile {
    path: String,
    lines: Lines,
    labels_line: usize,
    segment: Segment,
    orientation: XsensOrientation,
    /// The first orientation column's label, for messages.
    first_label: String,
}

/// An Xsens MT Manager trial: one `.txt` per sensor, read in step.
pub struct XsensTrial {
    source: String,
    files: Vec<XsensFile>,
    rate: f64,
    rows: usize,
    warnings: Vec<Warning>,
}

impl XsensTrial {
    fn open(path: &Path, mapping: Option<&Mapping>, rate: Option<f64>) -> Result<Self, MotError> {
        let shown = path.display().to_string();
        let Some(mapping) = mapping else {
            return Err(format_err(
                &shown,
                1,
                "an Xsens trial (a folder or FOLDER/PREFIX of MT Manager .txt files) needs --imu-mapping SETTINGS.xml (OpenSense's XsensDataReaderSettings: which file is which IMU)".into(),
            ));
        };
        let (folder, prefix): (PathBuf, String) = if path.is_dir() {
            (
                path.to_path_buf(),
                mapping.trial_prefix.clone().unwrap_or_default(),
            )
        } else {
            let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
            let prefix = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            (folder, prefix)
        };
        let source = folder.join(format!("{prefix}*.txt")).display().to_string();
        let mut files = Vec::new();
        let mut file_rate: Option<(f64, String)> = None;
        for (name, segment, at) in &mapping.sensors {
            let Some(segment) = *segment else { continue };
            let file_path = folder.join(format!("{prefix}{name}.txt"));
            let p = file_path.display().to_string();
            if !file_path.is_file() {
                return Err(format_err(
                    &mapping.source,
                    *at,
                    format!("sensor `{name}` ({segment}): no file {p}"),
                ));
            }
            let mut lines = Lines::open(&file_path)?;
            let (this_rate, header) = xsens_header(&mut lines, &p)?;
            if let Some(r) = this_rate {
                match &file_rate {
                    Some((other, other_path)) if *other != r => {
                        return Err(format_err(
                            &p,
                            1,
                            format!("Update Rate {r} Hz, but {other_path} says {other} Hz"),
                        ))
                    }
                    None => file_rate = Some((r, p.clone())),
                    _ => {}
                }
            }
            let labels: Vec<&str> = header.split('\t').map(str::trim).collect();
            let find = |l: &str| labels.iter().position(|x| *x == l);
            let quat: Option<Vec<usize>> = ["Quat_q0", "Quat_q1", "Quat_q2", "Quat_q3"]
                .iter()
                .map(|l| find(l))
                .collect();
            let mat: Option<Vec<usize>> = (1..=3)
                .flat_map(|r| (1..=3).map(move |c| format!("Mat[{r}][{c}]")))
                .map(|l| find(&l))
                .collect();
            let (orientation, first_label) = match (quat, mat) {
                (Some(q), _) => (
                    XsensOrientation::Quaternion([q[0], q[1], q[2], q[3]]),
                    "Quat_q0".to_string(),
                ),
                (None, Some(m)) => (
                    XsensOrientation::Matrix([
                        [m[0], m[1], m[2]],
                        [m[3], m[4], m[5]],
                        [m[6], m[7], m[8]],
                    ]),
                    "Mat[1][1]".to_string(),
                ),
                (None, None) => {
                    return Err(format_err(
                        &p,
                        lines.line,
                        "no orientation columns: export Quat_q0..Quat_q3 or the rotation matrix Mat[1][1]..Mat[3][3] from MT Manager (Euler angles alone are not read)".into(),
                    ))
                }
            };
            files.push(XsensFile {
                path: p,
                labels_line: lines.line,
                lines,
                segment,
                orientation,
                first_label,
            });
        }
        if files.is_empty() {
            return Err(format_err(
                &mapping.source,
                1,
                "no sensor is mapped to an IMU of the lower-body set".into(),
            ));
        }
        let rate = file_rate
            .map(|(r, _)| r)
            .or(mapping.sampling_rate)
            .or(rate)
            .ok_or_else(|| {
                format_err(
                    &files[0].path,
                    1,
                    "no `// Update Rate:` comment, no <sampling_rate> in the settings and no --rate: the sampling rate is unknown".into(),
                )
            })?;
        Ok(Self {
            source,
            files,
            rate,
            rows: 0,
            warnings: mapping.warnings.clone(),
        })
    }
}

impl OrientationSource for XsensTrial {
    fn source(&self) -> &str {
        &self.source
    }
    fn sensors(&self) -> Vec<Segment> {
        self.files.iter().map(|f| f.segment).collect()
    }
    fn labels_at(&self) -> Location {
        Location::line(self.files[0].path.clone(), self.files[0].labels_line)
    }
    fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }
    fn next_row(&mut self) -> Result<Option<OrientationRow>, MotError> {
        // One line from every file: all present, or all at their end.
        let mut texts = Vec::with_capacity(self.files.len());
        for f in &mut self.files {
            texts.push(f.lines.next_data(&f.path)?);
        }
        if let Some(short) = texts.iter().position(Option::is_none) {
            if let Some(long) = texts.iter().position(Option::is_some) {
                let f = &self.files[short];
                return Err(format_err(
                    &f.path,
                    f.lines.line,
                    format!(
                        "ends after {} samples, but {} has more",
                        self.rows, self.files[long].path
                    ),
                ));
            }
            if self.rows == 0 {
                return Err(format_err(
                    &self.files[0].path,
                    self.files[0].labels_line,
                    "no samples after the labels".into(),
                ));
            }
            return Ok(None);
        }
        let mut readings = Orientations::EMPTY;
        for (f, text) in self.files.iter().zip(texts) {
            let text = text.expect("every file has a line");
            let line = f.lines.line;
            let c = cells(&text, '\t');
            let first = match f.orientation {
                XsensOrientation::Quaternion(i) => i[0],
                XsensOrientation::Matrix(m) => m[0][0],
            };
            let column = c.get(first).map_or(0, |x| x.0);
            let q = match f.orientation {
                XsensOrientation::Quaternion(i) => {
                    let mut v = [0.0; 4];
                    for (k, label) in ["Quat_q0", "Quat_q1", "Quat_q2", "Quat_q3"]
                        .iter()
                        .enumerate()
                    {
                        v[k] = number(&f.path, line, &c, i[k], label)?;
                    }
                    Quat::new(v[0], v[1], v[2], v[3])
                }
                XsensOrientation::Matrix(m) => {
                    let mut out = [[0.0; 3]; 3];
                    for (r, row) in out.iter_mut().enumerate() {
                        for (col, v) in row.iter_mut().enumerate() {
                            let label = format!("Mat[{}][{}]", r + 1, col + 1);
                            *v = number(&f.path, line, &c, m[r][col], &label)?;
                        }
                    }
                    let rows_unit = out.iter().all(|r| {
                        let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                        (n - 1.0).abs() <= UNIT_TOLERANCE
                    });
                    if !rows_unit {
                        return Err(format_err(
                            &f.path,
                            line,
                            format!(
                                "column {column} (`Mat[1][1]`..`Mat[3][3]`): not a rotation matrix (a row's length is not within {UNIT_TOLERANCE} of 1)"
                            ),
                        ));
                    }
                    from_rotation_matrix(out)
                }
            };
            readings.set(
                f.segment,
                Some(reading(
                    q,
                    f.segment,
                    &f.path,
                    line,
                    column,
                    &f.first_label,
                )?),
            );
        }
        let time = self.rows as f64 / self.rate;
        self.rows += 1;
        Ok(Some(OrientationRow {
            line: self.files[0].lines.line,
            time,
            readings,
        }))
    }
}

/// An APDM `.csv` read record by record with the `csv` crate: `,`-separated cells, a record a
/// line (no quoting: APDM writes none, and OpenSim's reader reads none), its bytes kept (a line
/// that is not UTF-8 is read as Latin-1), so that each record has its line and each cell its
/// character column.
struct ApdmRecords {
    reader: csv::Reader<io::Chain<File, &'static [u8]>>,
    record: ByteRecord,
    /// The line of `record`.
    line: usize,
    /// `record` is read but not yet taken (the header line asked for was blank).
    held: bool,
}

/// A line's cells, each with its 1-based character column.
type Cells<'a> = Vec<(usize, Cow<'a, str>)>;

impl ApdmRecords {
    fn open(path: &Path) -> Result<Self, MotError> {
        let file = open_file(path)?;
        // Every line ends with `\n` (the last one too, with the `\n` added), so the reader's
        // line after a record is the one after the record's, whatever empty lines it skipped
        // before it (`ByteRecord::position()` is where the reader was before those).
        let reader = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .quoting(false)
            .terminator(csv::Terminator::Any(b'\n'))
            .from_reader(file.chain(&b"\n"[..]));
        Ok(Self {
            reader,
            record: ByteRecord::new(),
            line: 0,
            held: false,
        })
    }

    /// The next record (the held one, if any); false at the end of the file.
    fn advance(&mut self, path: &str) -> Result<bool, MotError> {
        if std::mem::take(&mut self.held) {
            return Ok(true);
        }
        // Bytes, no quoting, any number of cells: only reading the file can fail.
        let read = self
            .reader
            .read_byte_record(&mut self.record)
            .map_err(|e| MotError::Io {
                path: path.to_string(),
                error: e.into(),
            })?;
        if read {
            self.line = self.reader.position().line() as usize - 1;
        }
        Ok(read)
    }

    /// The record's cells (the line's `\r` end dropped).
    fn cells(&self) -> Cells<'_> {
        let utf8 = self.record.iter().all(|b| std::str::from_utf8(b).is_ok());
        let last = self.record.len().saturating_sub(1);
        let mut column = 1;
        let mut out = Vec::with_capacity(self.record.len());
        for (i, mut bytes) in self.record.iter().enumerate() {
            while i == last && bytes.last() == Some(&b'\r') {
                bytes = &bytes[..bytes.len() - 1];
            }
            let text = match std::str::from_utf8(bytes) {
                Ok(s) if utf8 => Cow::Borrowed(s),
                _ => Cow::Owned(bytes.iter().map(|&b| b as char).collect()),
            };
            out.push((column, text));
            column += out[i].1.chars().count() + 1;
        }
        out
    }

    /// The cells of header line `n` (one empty cell if it is blank), or an error if the file
    /// ends before it (`what`).
    fn header(
        &mut self,
        n: usize,
        path: &str,
        what: &str,
    ) -> Result<Vec<(usize, String)>, MotError> {
        let blank = || vec![(1, String::new())];
        if !self.advance(path)? {
            // The file's lines: up to the last record, or to the empty lines after it (the
            // reader's line is 1 + the `\n`s, the added one too).
            let lines = self
                .line
                .max((self.reader.position().line() as usize).saturating_sub(2));
            if lines >= n {
                return Ok(blank());
            }
            return Err(format_err(
                path,
                lines.max(1),
                format!("ends before {what}"),
            ));
        }
        if self.line > n {
            self.held = true;
            return Ok(blank());
        }
        Ok(self
            .cells()
            .into_iter()
            .map(|(c, t)| (c, t.into_owned()))
            .collect())
    }

    /// The next record that is not a blank line, with its line.
    fn next_data(&mut self, path: &str) -> Result<Option<(usize, Cells<'_>)>, MotError> {
        while self.advance(path)? {
            let blank = self.record.len() == 1 && self.cells()[0].1.trim().is_empty();
            if !blank {
                return Ok(Some((self.line, self.cells())));
            }
        }
        Ok(None)
    }
}

/// An APDM `.csv` trial.
pub struct ApdmTrial {
    source: String,
    records: ApdmRecords,
    labels_line: usize,
    /// Per sensor: its segment, the column of its orientation's scalar (w), and its label.
    sensors: Vec<(Segment, usize, String)>,
    rate: f64,
    rows: usize,
    warnings: Vec<Warning>,
}

impl ApdmTrial {
    fn open(path: &Path, mapping: Option<&Mapping>, rate: Option<f64>) -> Result<Self, MotError> {
        let source = path.display().to_string();
        let mut records = ApdmRecords::open(path)?;
        let first_cells: Vec<String> = records
            .header(1, &source, "the header")?
            .into_iter()
            .map(|(_, s)| s.trim().to_string())
            .collect();
        let mut warnings = mapping.map(|m| m.warnings.clone()).unwrap_or_default();
        // The sensors to read: the mapping's, or every label that names an IMU of the set.
        let wanted = |label: &str| -> Option<Option<Segment>> {
            match mapping {
                Some(m) => m
                    .sensors
                    .iter()
                    .find(|(n, _, _)| n == label)
                    .map(|(_, s, _)| *s),
                None => Some(Segment::from_name(label)),
            }
        };
        let (sensors, labels_line, file_rate) = if first_cells[0] == "Format=7" {
            // The sensor names on line 1; the orientation's S, X, Y, Z seven columns after.
            let mut sensors = Vec::new();
            for (i, name) in first_cells.iter().enumerate().skip(1) {
                if name.is_empty() {
                    continue;
                }
                if let Some(Some(segment)) = wanted(name) {
                    sensors.push((segment, i + 7, name.clone()));
                }
            }
            records.header(2, &source, "the second header line")?;
            records.header(3, &source, "the third header line")?;
            (sensors, 1, rate.unwrap_or(128.0))
        } else {
            if first_cells[0] != "Test Name:" {
                return Err(format_err(
                    &source,
                    1,
                    format!(
                        "not an APDM export: the first line starts with `{}` (expected `Test Name:` or `Format=7`)",
                        first_cells[0]
                    ),
                ));
            }
            let c = records.header(2, &source, "the `Sample Rate:` line")?;
            if c.first().map(|x| x.1.trim()) != Some("Sample Rate:") {
                return Err(format_err(
                    &source,
                    2,
                    "expected `Sample Rate:,<Hz>`".into(),
                ));
            }
            let file_rate = number(&source, 2, &c, 1, "Sample Rate")?;
            if file_rate <= 0.0 {
                return Err(format_err(
                    &source,
                    2,
                    format!("sample rate {file_rate} Hz"),
                ));
            }
            let labels = records.header(3, &source, "the labels")?;
            let labels: Vec<&str> = labels.iter().map(|(_, l)| l.trim()).collect();
            if labels.first() != Some(&"Time") {
                return Err(format_err(
                    &source,
                    3,
                    format!("the labels start with `{}` (expected `Time`)", labels[0]),
                ));
            }
            let mut sensors = Vec::new();
            for (i, l) in labels.iter().enumerate() {
                let Some(name) = l.strip_suffix("/Orientation/Scalar") else {
                    continue;
                };
                let rest = ["X", "Y", "Z"].map(|a| format!("{name}/Orientation/{a}"));
                if (0..3).any(|k| labels.get(i + 1 + k) != Some(&rest[k].as_str())) {
                    return Err(format_err(
                        &source,
                        3,
                        format!(
                            "column {}: `{l}` is not followed by {}",
                            i + 1,
                            rest.join(", ")
                        ),
                    ));
                }
                if let Some(Some(segment)) = wanted(name) {
                    sensors.push((segment, i, name.to_string()));
                }
                if mapping.is_none() && Segment::from_name(name).is_none() {
                    warnings.push(Warning::Ignored(WarningText {
 at: Some(Location::line(source.to_string(), 3)),
 detail: format!("sensor `{name}` is not an IMU of the lower-body set; ignored (map APDM sensors with --imu-mapping)"),
}));
                }
            }
            records.header(4, &source, "the units line")?;
            (sensors, 3, file_rate)
        };
        if let Some(m) = mapping {
            for (name, segment, at) in &m.sensors {
                if segment.is_some() && !sensors.iter().any(|(_, _, n)| n == name) {
                    return Err(format_err(
                        &m.source,
                        *at,
                        format!("sensor `{name}` has no orientation columns in {source}"),
                    ));
                }
            }
        }
        if sensors.is_empty() {
            return Err(format_err(
                &source,
                labels_line,
                "no orientation of an IMU of the lower-body set (map the APDM sensors with --imu-mapping)".into(),
            ));
        }
        for (k, (s, _, name)) in sensors.iter().enumerate() {
            if sensors[..k].iter().any(|(o, _, _)| o == s) {
                return Err(format_err(
                    &source,
                    labels_line,
                    format!("`{name}` is a second sensor for {s}"),
                ));
            }
        }
        Ok(Self {
            source,
            records,
            labels_line,
            sensors,
            rate: file_rate,
            rows: 0,
            warnings,
        })
    }
}

impl OrientationSource for ApdmTrial {
    fn source(&self) -> &str {
        &self.source
    }
    fn sensors(&self) -> Vec<Segment> {
        self.sensors.iter().map(|s| s.0).collect()
    }
    fn labels_at(&self) -> Location {
        Location::line(self.source.clone(), self.labels_line)
    }
    fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }
    fn next_row(&mut self) -> Result<Option<OrientationRow>, MotError> {
        let Some((line, c)) = self.records.next_data(&self.source)? else {
            if self.rows == 0 {
                return Err(format_err(
                    &self.source,
                    self.labels_line,
                    "no samples after the header".into(),
                ));
            }
            return Ok(None);
        };
        let mut readings = Orientations::EMPTY;
        for (segment, index, name) in &self.sensors {
            let labels = ["Scalar", "X", "Y", "Z"].map(|a| format!("{name}/Orientation/{a}"));
            let mut v = [0.0; 4];
            for k in 0..4 {
                v[k] = number(&self.source, line, &c, index + k, &labels[k])?;
            }
            let column = c.get(*index).map_or(0, |x| x.0);
            let q = reading(
                Quat::new(v[0], v[1], v[2], v[3]),
                *segment,
                &self.source,
                line,
                column,
                &labels[0],
            )?;
            readings.set(*segment, Some(q));
        }
        let time = self.rows as f64 / self.rate;
        self.rows += 1;
        Ok(Some(OrientationRow {
            line,
            time,
            readings,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LABELS: &[u8] = b"Time,pelvis/Orientation/Scalar,pelvis/Orientation/X,pelvis/Orientation/Y,pelvis/Orientation/Z";

    /// `text` (its pieces) written as an APDM `.csv`, and that file opened (or the error).
    fn apdm(name: &str, text: &[&[u8]]) -> (PathBuf, Result<ApdmTrial, MotError>) {
        let path =
            std::env::temp_dir().join(format!("qgait-vendor-{}-{name}.csv", std::process::id()));
        std::fs::write(&path, text.concat()).unwrap();
        let trial = ApdmTrial::open(&path, None, None);
        (path, trial)
    }

    #[test]
    fn apdm_rows_keep_their_lines_across_crlf_blank_and_empty_lines() {
        let (path, trial) = apdm(
            "lines",
            &[
                b"Test Name:,t\r\nSample Rate:,100,Hz\r\n",
                LABELS,
                b"\r\ns,,,,\r\n0,1,0,0,0\r\n \r\n\n0.01,0,1,0,0",
            ],
        );
        let mut trial = trial.unwrap();
        let mut rows = Vec::new();
        while let Some(row) = trial.next_row().unwrap() {
            rows.push((row.line, row.time));
        }
        assert_eq!(rows, [(5, 0.0), (8, 0.01)]);
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn a_bad_apdm_value_is_named_by_file_line_and_character_column() {
        // Line 6, after an empty line; `été` in Latin-1 is three characters; no `\n` at the end.
        let (path, trial) = apdm(
            "bad",
            &[
                b"Test Name:,t\nSample Rate:,100,Hz\n",
                LABELS,
                b"\ns,,,,\n\n\xe9t\xe9,1,0,0,w\r",
            ],
        );
        let e = trial.unwrap().next_row().unwrap_err().to_string();
        let at = format!(
            "{}:6:11: bad number `w` in column `pelvis/Orientation/Z`",
            path.display()
        );
        assert!(e.starts_with(&at), "{e}");
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn a_blank_or_missing_apdm_header_line_is_named() {
        let (path, trial) = apdm("blank", &[b"Test Name:,t\n\nSample Rate:,100,Hz\n"]);
        let e = trial.err().unwrap().to_string();
        assert_eq!(
            e,
            format!("{}:2: expected `Sample Rate:,<Hz>`", path.display())
        );
        std::fs::remove_file(path).unwrap();
        let (path, trial) = apdm("short", &[b"Test Name:,t\n"]);
        let e = trial.err().unwrap().to_string();
        assert_eq!(
            e,
            format!("{}:1: ends before the `Sample Rate:` line", path.display())
        );
        std::fs::remove_file(path).unwrap();
    }
}
