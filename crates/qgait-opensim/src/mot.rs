//! OpenSim motion and storage files (`.mot`, `.sto`): reading, writing, and the [`MotionTable`]
//! that keeps every column by name.
//!
//! Accepted layout: a header that ends with a line `endheader`, then one line of column labels
//! (the first must be `time`), then one row of numbers per line. Values are separated by tabs or
//! spaces (any run of whitespace). Both header styles are read:
//!
//! ```text
//! normal_gait            name                 OpenSim 4 .sto:    or the old SIMM style:
//! version=1                                   inDegrees=no       normal_gait
//! nRows=51                                    DataType=double    datacolumns 18
//! nColumns=18                                 version=3          datarows 51
//! inDegrees=yes                               endheader          range 0 1
//! endheader                                                      endheader
//! ```
//!
//! The rules are OpenSim 4.6's (its `Storage` reader, checked on files written for the purpose):
//!
//! - **Units.** `inDegrees=yes` (any case) means degrees; any other value means radians (OpenSim
//!   reads `true` or `maybe` as no: a warning says so unless the value is `no`). A header without
//!   `inDegrees` is in radians when it has a `version=` line with a version of 1 or more (every
//!   OpenSim 4 `.sto`, `version=3`, and the `.mot` files OpenSim writes, `version=1`), and in
//!   degrees otherwise (no version line or `version=0`: the SIMM `datacolumns` style and older
//!   files). Either default comes with a warning that says which rule was applied.
//! - **Rows.** The row count always comes from the data: a declared `nRows`/`datarows` that
//!   disagrees only gives a warning (the shared gait2392 files declare the wrong count).
//! - **Repeated time.** A row with the same time as the one before replaces it (as OpenSim does;
//!   tools often write the last time twice), with a warning; a time that goes back is an error.
//! - **Columns.** A label that appears twice gives a warning; it is an error only for a model that
//!   needs that column (see `qgait_model::coords`). `nan` and `inf` values are kept: they are an error
//!   (with file, line and column) only in a column a model needs, or in `time` (`qgait gait`
//!   leaves such a row out instead, `qgait_gait::trial`).
//! - **Text.** A UTF-8 byte order mark at the start of the file is skipped (OpenSim does not
//!   skip it, and then misses a first-line `inDegrees=`). Lines that are not UTF-8 (a Latin-1 `é` in a header comment) are read as Latin-1,
//!   with one warning. Header lines not understood (free text such as `Units are S.I. units`)
//!   are ignored.
//!
//! [`MotionReader`] reads the header, then hands out one row at a time (constant memory, for
//! files of any length); [`MotionTable::read`] is the same reader collecting every row.

use std::io::{self, BufRead, Write};
use std::path::Path;

use crate::diagnostics::{Location, Warning, WarningText};

/// A problem found while reading a motion file. Every variant names the file; the format
/// variants also name the 1-based line (and, for numbers, the 1-based character column).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MotError {
    /// The file could not be read.
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        error: io::Error,
    },
    /// The layout is wrong (no `endheader`, no labels, wrong number of values, ...).
    #[error("{path}:{line}: {message}")]
    Format {
        /// The file.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A value is not a finite decimal number.
    #[error("{path}:{line}:{column}: bad number `{text}` in column `{name}` (expected a finite decimal number)")]
    BadNumber {
        /// The file.
        path: String,
        /// 1-based line number.
        line: usize,
        /// 1-based character column where the value starts.
        column: usize,
        /// The column label.
        name: String,
        /// The text that is not a number.
        text: String,
    },
    /// A cell of an orientation `.sto` is not a rotation `w,x,y,z`.
    #[error("{path}:{line}: column {index} (`{name}`, character {column}): bad quaternion `{text}`: {why}")]
    BadQuaternion {
        /// The file.
        path: String,
        /// 1-based line number.
        line: usize,
        /// 1-based character column where the cell starts.
        column: usize,
        /// 1-based index of the column.
        index: usize,
        /// The column label.
        name: String,
        /// The cell as written.
        text: String,
        /// Why it is not a rotation.
        why: Box<QuaternionFault>,
    },
}

/// Why a cell `w,x,y,z` is not a rotation ([`MotError::BadQuaternion`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum QuaternionFault {
    /// Not 4 components.
    #[error("{0} components (expected 4: w,x,y,z)")]
    Components(usize),
    /// A component is not a number.
    #[error("component {index} `{text}` is not a number")]
    NotANumber {
        /// 1-based index of the component.
        index: usize,
        /// The component as written.
        text: String,
    },
    /// The norm is too far from 1.
    #[error(
        "norm {norm} is not within {} of 1 (not a rotation)",
        qgait_kernel::imu::UNIT_TOLERANCE
    )]
    NotUnit {
        /// The norm.
        norm: f64,
    },
}

/// Why labelled columns do not make a motion table ([`MotionTable::new`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    /// Labels and columns are not as many.
    #[error("{origin}: {labels} labels for {columns} columns")]
    LabelCount {
        /// Where the data came from.
        origin: String,
        /// Number of labels.
        labels: usize,
        /// Number of columns.
        columns: usize,
    },
    /// The first column is not `time`.
    #[error("{0}: the first column must be `time`")]
    FirstNotTime(String),
    /// There are no rows.
    #[error("{0}: no data rows")]
    NoRows(String),
    /// A column is longer or shorter than `time`.
    #[error("{origin}: column `{label}` has {rows} rows, `time` has {time_rows}")]
    Length {
        /// Where the data came from.
        origin: String,
        /// The column.
        label: String,
        /// Its rows.
        rows: usize,
        /// Rows of `time`.
        time_rows: usize,
    },
    /// A value is `nan` or infinite.
    #[error("{origin}: column `{label}` row {row}: value is not finite")]
    NotFinite {
        /// Where the data came from.
        origin: String,
        /// The column.
        label: String,
        /// 1-based row.
        row: usize,
    },
    /// Time does not increase.
    #[error("{origin}: time is not increasing at row {row}")]
    TimeNotIncreasing {
        /// Where the data came from.
        origin: String,
        /// 1-based row.
        row: usize,
    },
    /// A label appears twice.
    #[error("{origin}: column `{label}` appears twice")]
    Duplicate {
        /// Where the data came from.
        origin: String,
        /// The label.
        label: String,
    },
}

/// A value that is not a finite number (`nan`, `inf`), where it was read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NonFinite {
    /// 1-based line.
    pub line: usize,
    /// 1-based character column where the value starts.
    pub column: usize,
    /// The text of the value.
    pub text: String,
}

/// What a motion says about its columns: everything but the rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// The name on the header's first line (may be empty).
    pub name: String,
    /// Where the data came from (a path or a `builtin:` spec), for messages.
    pub source: String,
    /// Whether angle columns are in degrees.
    pub in_degrees: bool,
    /// The column labels, `time` first.
    pub labels: Vec<String>,
    /// 1-based line of the column labels in the file (`None` for generated tables).
    pub labels_line: Option<usize>,
    /// Whether the angles are in gait2392's signs whatever the model (a `builtin:` motion: its
    /// knee flexes with negative angles), not in the model's own.
    pub gait2392_signs: bool,
    /// Whether the pelvis is relative to the direction of progression, not to ground
    /// (`qgaitPelvis=heading-free` in the header, what `qgait imu --pelvis heading-free`
    /// writes): the walking direction, and so turns, are not in the motion.
    pub pelvis_heading_free: bool,
    /// The declared row count and the key that declared it.
    declared_rows: Option<(usize, &'static str)>,
}

impl Header {
    /// Where the column labels are, for messages: `file:line`, or just the source for a
    /// generated table.
    pub fn labels_location(&self) -> String {
        self.labels_at().to_string()
    }

    /// [`labels_location`](Self::labels_location) as a [`Location`].
    pub fn labels_at(&self) -> Location {
        Location {
            path: self.source.clone(),
            line: self.labels_line,
            column: None,
        }
    }

    /// The index of the first column labelled `label`.
    pub fn index_of(&self, label: &str) -> Option<usize> {
        self.labels.iter().position(|l| l == label)
    }

    /// Whether `label` names more than one column.
    pub fn is_duplicated(&self, label: &str) -> bool {
        self.labels.iter().filter(|l| *l == label).count() > 1
    }

    /// The number of rows the header declares (`nRows`, `datarows`), if it does.
    pub fn declared_rows(&self) -> Option<usize> {
        self.declared_rows.map(|(n, _)| n)
    }
}

/// One data row as read: its 1-based line and one value per label (non-finite values of
/// columns other than `time` kept as they are).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// 1-based line in the file.
    pub line: usize,
    /// One value per column, `time` first.
    pub values: Vec<f64>,
    /// Where each non-finite value of this row is: (column index, location).
    pub non_finite: Vec<(usize, NonFinite)>,
}

/// Reads a motion file's header, then its rows one at a time: the one parser of `.mot`/`.sto`
/// files (see the module documentation for the rules). Memory does not grow with the number
/// of rows: one row is held back to replace it when the next repeats its time.
pub struct MotionReader<R> {
    header: Header,
    input: R,
    line_no: usize,
    buf: Vec<u8>,
    warnings: Vec<Warning>,
    latin1_warned: bool,
    pending: Option<Row>,
    rows: usize,
    finished: bool,
    /// The header's `DataType=` value.
    data_type: Option<String>,
}

fn fmt_err(source: &str, line: usize, message: String) -> MotError {
    MotError::Format {
        path: source.to_string(),
        line,
        message,
    }
}

impl MotionReader<io::BufReader<std::fs::File>> {
    /// Opens a file and reads its header.
    pub fn open(path: &Path) -> Result<Self, MotError> {
        let shown = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|error| MotError::Io {
            path: shown.clone(),
            error,
        })?;
        Self::new(io::BufReader::with_capacity(1 << 16, file), &shown)
    }
}

impl<R: BufRead> MotionReader<R> {
    /// Reads the header from `input`; `source` names it in errors and warnings.
    pub fn new(input: R, source: &str) -> Result<Self, MotError> {
        let mut reader = Self {
            header: Header {
                name: String::new(),
                source: source.to_string(),
                in_degrees: true,
                labels: Vec::new(),
                labels_line: None,
                gait2392_signs: false,
                pelvis_heading_free: false,
                declared_rows: None,
            },
            input,
            line_no: 0,
            buf: Vec::new(),
            warnings: Vec::new(),
            latin1_warned: false,
            pending: None,
            rows: 0,
            finished: false,
            data_type: None,
        };
        reader.read_header()?;
        Ok(reader)
    }

    /// The header (labels, units, name).
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// The header's `DataType=` value (`double`, `Quaternion`, ...), if it has one.
    pub fn data_type(&self) -> Option<&str> {
        self.data_type.as_deref()
    }

    /// Warnings so far (taken: each is returned once).
    pub fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }

    /// The next line (without its line ending), decoded as UTF-8 or else Latin-1; `None` at
    /// the end of the input.
    fn next_line(&mut self) -> Result<Option<String>, MotError> {
        self.buf.clear();
        let n = self
            .input
            .read_until(b'\n', &mut self.buf)
            .map_err(|error| MotError::Io {
                path: self.header.source.clone(),
                error,
            })?;
        if n == 0 {
            return Ok(None);
        }
        self.line_no += 1;
        while matches!(self.buf.last(), Some(b'\n' | b'\r')) {
            self.buf.pop();
        }
        // A UTF-8 byte order mark (as some Windows editors write) is not part of the first line.
        if self.line_no == 1 && self.buf.starts_with(b"\xEF\xBB\xBF") {
            self.buf.drain(..3);
        }
        Ok(Some(match std::str::from_utf8(&self.buf) {
            Ok(s) => s.to_string(),
            Err(_) => {
                if !self.latin1_warned {
                    self.latin1_warned = true;
                    self.warnings.push(Warning::Encoding(WarningText {
                        at: Some(Location::line(self.header.source.clone(), self.line_no)),
                        detail: "not UTF-8; read as Latin-1".to_string(),
                    }));
                }
                self.buf.iter().map(|&b| char::from(b)).collect()
            }
        }))
    }

    fn read_header(&mut self) -> Result<(), MotError> {
        let source = self.header.source.clone();
        let mut in_degrees: Option<bool> = None;
        let mut version: Option<(f64, String)> = None;
        let mut declared_cols: Option<(usize, &'static str)> = None;
        let mut seen_header_line = false;
        let mut found_end = false;
        while let Some(line) = self.next_line()? {
            let no = self.line_no;
            let t = line.trim();
            if t.eq_ignore_ascii_case("endheader") {
                found_end = true;
                break;
            }
            if t.is_empty() {
                continue;
            }
            let first = !seen_header_line;
            seen_header_line = true;
            if first && t.starts_with("PathFileType") {
                return Err(fmt_err(
                    &source,
                    no,
                    "this is a marker file (.trc: marker positions), not a motion (joint angles): OpenSim's inverse kinematics turns it into a .mot".into(),
                ));
            }
            if first && t.starts_with('<') {
                return Err(fmt_err(
                    &source,
                    no,
                    "this is an XML file (an OpenSim model or setup?), not a motion (.mot/.sto); a model goes after --model".into(),
                ));
            }
            if let Some((key, value)) = t.split_once('=') {
                let (key, value) = (key.trim(), value.trim());
                match key.to_ascii_lowercase().as_str() {
                    "nrows" => {
                        self.header.declared_rows =
                            parse_count(value, no, &source, &mut self.warnings, key)
                                .map(|n| (n, "nRows"))
                    }
                    "ncolumns" => {
                        declared_cols = parse_count(value, no, &source, &mut self.warnings, key)
                            .map(|n| (n, "nColumns"))
                    }
                    "datatype" => self.data_type = Some(value.to_string()),
                    "qgaitpelvis" => {
                        self.header.pelvis_heading_free = value.eq_ignore_ascii_case(HEADING_FREE)
                    }
                    "version" => {
                        version = Some((value.parse::<f64>().unwrap_or(0.0), value.to_string()))
                    }
                    "indegrees" => {
                        let yes = value.eq_ignore_ascii_case("yes");
                        if !yes && !value.eq_ignore_ascii_case("no") {
                            self.warnings.push(Warning::UnitsAssumed(WarningText {
 at: Some(Location::line(source.to_string(), no)),
 detail: format!("inDegrees=`{value}` is neither yes nor no; read as no (radians), as OpenSim reads it"),
}));
                        }
                        in_degrees = Some(yes);
                    }
                    _ => {}
                }
                continue;
            }
            let mut words = t.split_whitespace();
            match words.next().map(str::to_ascii_lowercase).as_deref() {
                Some("datarows") => {
                    self.header.declared_rows = parse_count(
                        words.next().unwrap_or(""),
                        no,
                        &source,
                        &mut self.warnings,
                        "datarows",
                    )
                    .map(|n| (n, "datarows"))
                }
                Some("datacolumns") => {
                    declared_cols = parse_count(
                        words.next().unwrap_or(""),
                        no,
                        &source,
                        &mut self.warnings,
                        "datacolumns",
                    )
                    .map(|n| (n, "datacolumns"))
                }
                _ if first => self.header.name = t.to_string(),
                _ => {}
            }
        }
        if !found_end {
            return Err(fmt_err(
                &source,
                self.line_no.max(1),
                "no `endheader` line: not an OpenSim .mot/.sto file".into(),
            ));
        }
        // Units do not apply to a table of quaternions: no warning about them.
        let quaternions = self
            .data_type
            .as_deref()
            .is_some_and(|t| t.eq_ignore_ascii_case("quaternion"));
        self.header.in_degrees = match (in_degrees, &version) {
            (Some(d), _) => d,
            (None, _) if quaternions => false,
            (None, Some((v, text))) if *v >= 1.0 => {
                self.warnings.push(Warning::UnitsAssumed(WarningText {
 at: Some(Location::file(source.to_string())),
 detail: format!("header does not say inDegrees=yes/no; angles read as radians, as OpenSim reads a `version={text}` file"),
}));
                false
            }
            (None, _) => {
                self.warnings.push(Warning::UnitsAssumed(WarningText {
 at: Some(Location::file(source.to_string())),
 detail: "header does not say inDegrees=yes/no and has no version; angles read as degrees, as OpenSim reads such a file".to_string(),
}));
                true
            }
        };

        // Column labels.
        let (label_line, labels) = loop {
            match self.next_line()? {
                None => {
                    return Err(fmt_err(
                        &source,
                        self.line_no + 1,
                        "no column labels after `endheader`".into(),
                    ))
                }
                Some(l) if l.trim().is_empty() => continue,
                Some(l) => {
                    break (
                        self.line_no,
                        l.split_whitespace().map(str::to_string).collect::<Vec<_>>(),
                    )
                }
            }
        };
        if !labels[0].eq_ignore_ascii_case("time") {
            let comma = labels[0].to_ascii_lowercase().starts_with("time,");
            return Err(fmt_err(
                &source,
                label_line,
                if comma {
                    format!("the file is comma-separated (`{}`): a .mot/.sto needs tab- or space-separated columns, the first `time`", labels[0].chars().take(60).collect::<String>())
                } else {
                    format!("the first column must be `time`, found `{}`", labels[0])
                },
            ));
        }
        for (i, l) in labels.iter().enumerate() {
            if let Some(first) = labels[..i].iter().position(|p| p == l) {
                if labels[..first].contains(l) || labels[first + 1..i].contains(l) {
                    continue;
                }
                self.warnings.push(Warning::DuplicateColumn(WarningText {
 at: Some(Location::line(source.to_string(), label_line)),
 detail: format!("column `{l}` appears more than once (columns {} and {}); only a model that needs it refuses the file", first + 1, i + 1),
}));
            }
        }
        if let Some((n, key)) = declared_cols {
            if n != labels.len() {
                self.warnings.push(Warning::HeaderMismatch(WarningText {
                    at: Some(Location::file(source.to_string())),
                    detail: format!(
                        "header says {key}={n} but the file has {} columns",
                        labels.len()
                    ),
                }));
            }
        }
        self.header.labels = labels;
        self.header.labels_line = Some(label_line);
        Ok(())
    }

    /// The next non-empty line after the column labels, as text, with its 1-based line number
    /// (for tables whose cells are not single numbers, such as the quaternion cells of an
    /// orientation `.sto`); `None` at the end of the input. [`tokens`] splits it into cells.
    pub fn next_text_line(&mut self) -> Result<Option<(usize, String)>, MotError> {
        loop {
            match self.next_line()? {
                None => return Ok(None),
                Some(l) if l.trim().is_empty() => continue,
                Some(l) => return Ok(Some((self.line_no, l))),
            }
        }
    }

    /// Parses the next non-empty line as a row.
    fn parse_row(&mut self) -> Result<Option<Row>, MotError> {
        let Some((no, line)) = self.next_text_line()? else {
            return Ok(None);
        };
        let labels = &self.header.labels;
        let mut values = Vec::with_capacity(labels.len());
        let mut non_finite = Vec::new();
        let mut count = 0;
        for (i, (start, tok)) in tokens(&line).enumerate() {
            count = i + 1;
            if i >= labels.len() {
                continue;
            }
            let column = || line[..start].chars().count() + 1;
            let bad = || MotError::BadNumber {
                path: self.header.source.clone(),
                line: no,
                column: column(),
                name: labels[i].clone(),
                text: tok.to_string(),
            };
            let value = tok.parse::<f64>().map_err(|_| bad())?;
            if !value.is_finite() {
                if i == 0 {
                    return Err(bad());
                }
                non_finite.push((
                    i,
                    NonFinite {
                        line: no,
                        column: column(),
                        text: tok.to_string(),
                    },
                ));
            }
            values.push(value);
        }
        if count != labels.len() {
            return Err(fmt_err(
                &self.header.source,
                no,
                format!(
                    "row has {count} values but the header names {} columns",
                    labels.len()
                ),
            ));
        }
        Ok(Some(Row {
            line: no,
            values,
            non_finite,
        }))
    }

    /// The next row, or `None` after the last. A row whose time repeats the previous row's
    /// replaces it (with a warning); a time that goes back is an error.
    pub fn next_row(&mut self) -> Result<Option<Row>, MotError> {
        if self.finished {
            return Ok(None);
        }
        loop {
            let Some(row) = self.parse_row()? else {
                self.finished = true;
                let last = self.pending.take();
                self.finish_checks(last.is_some())?;
                return Ok(last);
            };
            let Some(prev) = self.pending.take() else {
                self.pending = Some(row);
                continue;
            };
            let (t, p) = (row.values[0], prev.values[0]);
            if t < p {
                return Err(fmt_err(
                    &self.header.source,
                    row.line,
                    format!("time {t} is before the previous row's {p}"),
                ));
            }
            if t == p {
                self.warnings.push(Warning::RowReplaced(WarningText {
 at: Some(Location::line(self.header.source.clone(), row.line)),
 detail: format!("time {t} repeats the previous row's (line {}); this row replaces it, as in OpenSim", prev.line),
}));
                self.pending = Some(row);
                continue;
            }
            self.pending = Some(row);
            self.rows += 1;
            return Ok(Some(prev));
        }
    }

    fn finish_checks(&mut self, last: bool) -> Result<(), MotError> {
        let rows = self.rows + usize::from(last);
        if rows == 0 {
            return Err(fmt_err(
                &self.header.source,
                self.header.labels_line.unwrap_or(1),
                "no data rows after the column labels".into(),
            ));
        }
        if let Some((n, key)) = self.header.declared_rows {
            if n != rows {
                self.warnings.push(Warning::HeaderMismatch(WarningText {
                    at: Some(Location::file(self.header.source.clone())),
                    detail: format!(
                        "header says {key}={n} but the file has {rows} data rows; using {rows}"
                    ),
                }));
            }
        }
        Ok(())
    }
}

/// A table of motion data: a `time` column and any number of named columns, all kept.
///
/// Values are stored as read; [`MotionTable::in_degrees`] tells whether angle columns are in
/// degrees (`model::coords` converts a model's coordinates to radians as it reads them).
#[derive(Debug, Clone, PartialEq)]
pub struct MotionTable {
    header: Header,
    /// Column-major: `columns[c][row]`.
    columns: Vec<Vec<f64>>,
    /// 1-based line of each row (empty for generated tables).
    lines: Vec<usize>,
    /// Every non-finite value of each column, in row order.
    non_finite: Vec<Vec<NonFinite>>,
}

impl MotionTable {
    /// Builds a table from labelled columns (the first label must be `time`, every column the
    /// same non-zero length, all values finite, time strictly increasing). `source` names where
    /// the data came from, for messages.
    pub fn new(
        name: impl Into<String>,
        source: impl Into<String>,
        in_degrees: bool,
        labels: Vec<String>,
        columns: Vec<Vec<f64>>,
    ) -> Result<Self, TableError> {
        let source = source.into();
        if labels.len() != columns.len() {
            return Err(TableError::LabelCount {
                origin: source,
                labels: labels.len(),
                columns: columns.len(),
            });
        }
        if labels
            .first()
            .map(|l| !l.eq_ignore_ascii_case("time"))
            .unwrap_or(true)
        {
            return Err(TableError::FirstNotTime(source));
        }
        let rows = columns[0].len();
        if rows == 0 {
            return Err(TableError::NoRows(source));
        }
        for (label, col) in labels.iter().zip(&columns) {
            if col.len() != rows {
                return Err(TableError::Length {
                    origin: source,
                    label: label.clone(),
                    rows: col.len(),
                    time_rows: rows,
                });
            }
            if let Some(i) = col.iter().position(|v| !v.is_finite()) {
                return Err(TableError::NotFinite {
                    origin: source,
                    label: label.clone(),
                    row: i + 1,
                });
            }
        }
        if let Some(i) = columns[0].windows(2).position(|w| w[1] <= w[0]) {
            return Err(TableError::TimeNotIncreasing {
                origin: source,
                row: i + 2,
            });
        }
        for (i, l) in labels.iter().enumerate() {
            if labels[..i].contains(l) {
                return Err(TableError::Duplicate {
                    origin: source,
                    label: l.clone(),
                });
            }
        }
        let n = labels.len();
        Ok(Self {
            header: Header {
                name: name.into(),
                source,
                in_degrees,
                labels,
                labels_line: None,
                gait2392_signs: false,
                pelvis_heading_free: false,
                declared_rows: None,
            },
            columns,
            lines: Vec::new(),
            non_finite: vec![Vec::new(); n],
        })
    }

    /// This table with its angle columns declared in degrees (`true`) or radians: for a file
    /// whose header states the wrong unit.
    pub fn with_in_degrees(mut self, in_degrees: bool) -> Self {
        self.header.in_degrees = in_degrees;
        self
    }

    /// This table, its angles in gait2392's signs whatever the model ([`Header::gait2392_signs`]).
    pub fn in_gait2392_signs(mut self) -> Self {
        self.header.gait2392_signs = true;
        self
    }

    /// Reads a `.mot`/`.sto` file.
    pub fn read(path: &Path) -> Result<(Self, Vec<Warning>), MotError> {
        Self::collect(MotionReader::open(path)?)
    }

    /// Parses the text of a `.mot`/`.sto` file; `source` names it in errors and warnings.
    pub fn parse(text: &str, source: &str) -> Result<(Self, Vec<Warning>), MotError> {
        Self::collect(MotionReader::new(text.as_bytes(), source)?)
    }

    /// Every row of a reader, as a table.
    pub fn collect<R: BufRead>(
        mut reader: MotionReader<R>,
    ) -> Result<(Self, Vec<Warning>), MotError> {
        let n = reader.header().labels.len();
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); n];
        let mut lines = Vec::new();
        let mut non_finite: Vec<Vec<NonFinite>> = vec![Vec::new(); n];
        while let Some(row) = reader.next_row()? {
            for (c, v) in row.values.into_iter().enumerate() {
                columns[c].push(v);
            }
            for (c, at) in row.non_finite {
                non_finite[c].push(at);
            }
            lines.push(row.line);
        }
        let warnings = reader.take_warnings();
        Ok((
            Self {
                header: reader.header,
                columns,
                lines,
                non_finite,
            },
            warnings,
        ))
    }

    /// A table of some rows of a motion read with `header` (e.g. one window of a long
    /// recording read by [`MotionReader::next_row`]), in the order given; rows of a generated
    /// table (line 0) get no lines. The header's declared row count is dropped: the table is
    /// not the whole file.
    pub fn from_rows(header: &Header, rows: &[Row]) -> Self {
        let n = header.labels.len();
        let mut columns: Vec<Vec<f64>> = vec![Vec::with_capacity(rows.len()); n];
        let mut lines = Vec::with_capacity(rows.len());
        let mut non_finite: Vec<Vec<NonFinite>> = vec![Vec::new(); n];
        for row in rows {
            for (c, v) in row.values.iter().enumerate().take(n) {
                columns[c].push(*v);
            }
            for (c, at) in &row.non_finite {
                if let Some(list) = non_finite.get_mut(*c) {
                    list.push(at.clone());
                }
            }
            lines.push(row.line);
        }
        if lines.iter().all(|&l| l == 0) {
            lines.clear();
        }
        let mut header = header.clone();
        header.declared_rows = None;
        Self {
            header,
            columns,
            lines,
            non_finite,
        }
    }

    /// Writes the table as a `.mot` file (`nRows=` header style, tab separated, values printed
    /// with the shortest representation that reads back to the same `f64`).
    pub fn write_mot<W: Write>(&self, mut w: W) -> io::Result<()> {
        write_mot_header(
            &mut w,
            &self.header.name,
            &self.header.labels,
            self.header.in_degrees,
            Some(self.rows()),
            self.header.pelvis_heading_free,
        )?;
        let mut row = vec![0.0; self.columns.len()];
        for r in 0..self.rows() {
            for (v, col) in row.iter_mut().zip(&self.columns) {
                *v = col[r];
            }
            write_mot_row(&mut w, &row)?;
        }
        w.flush()
    }

    /// The header (labels, units, name, source).
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Where the data came from (a path or a `builtin:` spec).
    pub fn source(&self) -> &str {
        &self.header.source
    }

    /// Where the column labels are (`file:line`), for errors about columns.
    pub fn labels_location(&self) -> String {
        self.header.labels_location()
    }

    /// Where the column labels are, as a [`Location`].
    pub fn labels_at(&self) -> Location {
        self.header.labels_at()
    }

    /// Whether angle columns are in degrees (`inDegrees=yes`).
    pub fn in_degrees(&self) -> bool {
        self.header.in_degrees
    }

    /// Number of data rows.
    pub fn rows(&self) -> usize {
        self.columns[0].len()
    }

    /// The column labels, `time` first.
    pub fn labels(&self) -> &[String] {
        &self.header.labels
    }

    /// The time column (seconds).
    pub fn time(&self) -> &[f64] {
        &self.columns[0]
    }

    /// A column by label, as stored (the first of that label).
    pub fn column(&self, label: &str) -> Option<&[f64]> {
        self.header
            .index_of(label)
            .map(|i| self.columns[i].as_slice())
    }

    /// The value of column `c` in row `r`.
    pub fn value(&self, r: usize, c: usize) -> f64 {
        self.columns[c][r]
    }

    /// The 1-based line of row `r` in its file (`None` for a generated table).
    pub fn line(&self, r: usize) -> Option<usize> {
        self.lines.get(r).copied()
    }

    /// The first value of column `c` that is not a finite number, if any.
    pub fn non_finite(&self, c: usize) -> Option<&NonFinite> {
        self.non_finite[c].first()
    }

    /// Where the value of column `c` in row `r` was read, if it is not a finite number.
    pub fn non_finite_at(&self, r: usize, c: usize) -> Option<&NonFinite> {
        let line = self.line(r)?;
        // In row order, so in line order.
        let column = self.non_finite.get(c)?;
        let k = column.binary_search_by_key(&line, |nf| nf.line).ok()?;
        column.get(k)
    }

    /// This table without the rows `r` for which `leave(r)` is true.
    pub fn without_rows(&self, leave: impl Fn(usize) -> bool) -> Self {
        let keep: Vec<usize> = (0..self.rows()).filter(|&r| !leave(r)).collect();
        let lines: Vec<usize> = keep.iter().filter_map(|&r| self.line(r)).collect();
        Self {
            header: self.header.clone(),
            columns: self
                .columns
                .iter()
                .map(|c| keep.iter().map(|&r| c[r]).collect())
                .collect(),
            non_finite: self
                .non_finite
                .iter()
                .map(|c| {
                    c.iter()
                        .filter(|nf| lines.binary_search(&nf.line).is_ok())
                        .cloned()
                        .collect()
                })
                .collect(),
            lines,
        }
    }

    /// Percent of the cycle of every row: time normalised from the first row (0 %) to the last
    /// (100 %). Each motion is taken to be one gait cycle.
    pub fn percent_of_cycle(&self) -> Vec<f64> {
        let t = self.time();
        let (t0, t1) = (t[0], t[t.len() - 1]);
        if t1 > t0 {
            t.iter().map(|v| (v - t0) / (t1 - t0) * 100.0).collect()
        } else {
            vec![0.0; t.len()]
        }
    }
}

/// The value of the header key `qgaitPelvis` that says the pelvis is heading-free
/// ([`Header::pelvis_heading_free`]).
pub const HEADING_FREE: &str = "heading-free";

/// Writes a `.mot` header (name, `version=1`, `nRows=` when `rows` is known, `nColumns=`,
/// `inDegrees=`, `endheader`) and the column labels: [`MotionTable::write_mot`], or a writer
/// that streams its rows with [`write_mot_row`] (no `nRows=`: the reader counts the rows).
/// With `qgaitPelvis=heading-free` when `pelvis_heading_free` (OpenSim reads past a header key
/// it does not know).
pub fn write_mot_header<W: Write>(
    mut w: W,
    name: &str,
    labels: &[String],
    in_degrees: bool,
    rows: Option<usize>,
    pelvis_heading_free: bool,
) -> io::Result<()> {
    let name = if name.is_empty() { "motion" } else { name };
    writeln!(w, "{name}\nversion=1")?;
    if let Some(n) = rows {
        writeln!(w, "nRows={n}")?;
    }
    if pelvis_heading_free {
        writeln!(w, "qgaitPelvis={HEADING_FREE}")?;
    }
    writeln!(w, "nColumns={}", labels.len())?;
    writeln!(
        w,
        "inDegrees={}\nendheader",
        if in_degrees { "yes" } else { "no" }
    )?;
    writeln!(w, "{}", labels.join("\t"))
}

/// Writes one `.mot` row: tab separated, each value with the shortest representation that
/// reads back to the same `f64`.
pub fn write_mot_row<W: Write>(mut w: W, values: &[f64]) -> io::Result<()> {
    for (c, v) in values.iter().enumerate() {
        if c > 0 {
            w.write_all(b"\t")?;
        }
        write!(w, "{v}")?;
    }
    w.write_all(b"\n")
}

/// Whitespace-separated tokens (a row's cells) with their byte offsets.
pub fn tokens(line: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = line.char_indices().peekable();
    std::iter::from_fn(move || {
        while rest.next_if(|(_, c)| c.is_whitespace()).is_some() {}
        let (start, _) = *rest.peek()?;
        let mut end = line.len();
        for (i, c) in rest.by_ref() {
            if c.is_whitespace() {
                end = i;
                break;
            }
        }
        Some((start, &line[start..end]))
    })
}

fn parse_count(
    value: &str,
    line: usize,
    source: &str,
    warnings: &mut Vec<Warning>,
    key: &str,
) -> Option<usize> {
    let parsed = value.trim().parse().ok();
    if parsed.is_none() {
        warnings.push(Warning::HeaderMismatch(WarningText {
            at: Some(Location::line(source.to_string(), line)),
            detail: format!("`{key}` is not a count (`{value}`); ignored"),
        }));
    }
    parsed
}

#[cfg(test)]
mod tests {
    use super::*;

    const NROWS_STYLE: &str = "walk\nversion=1\nnRows=2\nnColumns=3\ninDegrees=yes\nendheader\ntime\tknee_angle_r\tpelvis_ty\n0\t-10\t0.9\n0.5\t-20.5\t0.95\n";
    const DATAROWS_STYLE: &str = "walk\ndatacolumns 3\ndatarows 2\nrange 0 0.5\nendheader\ntime  knee_angle_r  pelvis_ty\n  0   -10   0.9\n  0.5 -20.5 0.95\n";

    #[test]
    fn both_header_styles_read_the_same_data() {
        let (a, wa) = MotionTable::parse(NROWS_STYLE, "a.mot").unwrap();
        let (b, wb) = MotionTable::parse(DATAROWS_STYLE, "b.mot").unwrap();
        assert!(wa.is_empty(), "{wa:?}");
        // The datarows style has no inDegrees: degrees assumed, with a warning.
        assert_eq!(wb.len(), 1, "{wb:?}");
        assert!(wb[0].to_string().contains("inDegrees"));
        assert_eq!(a.header().name, "walk");
        assert!(a.in_degrees() && b.in_degrees());
        assert_eq!(a.labels(), b.labels());
        assert_eq!(a.rows(), 2);
        assert_eq!(a.column("knee_angle_r"), b.column("knee_angle_r"));
        assert_eq!(a.column("pelvis_ty").unwrap(), &[0.9, 0.95]);
        assert_eq!(a.percent_of_cycle(), vec![0.0, 100.0]);
    }

    #[test]
    fn opensim4_sto_without_name_line() {
        let text = "inDegrees=no\nDataType=double\nversion=3\nOpenSimVersion=4.5\nendheader\ntime\tq\n0\t0.25\n1\t0.5\n";
        let (t, w) = MotionTable::parse(text, "x.sto").unwrap();
        assert!(w.is_empty());
        assert!(!t.in_degrees());
        assert_eq!(t.column("q").unwrap(), &[0.25, 0.5]);
    }

    #[test]
    fn a_byte_order_mark_before_the_header_is_skipped() {
        // OpenSim 4 style: the first line is `inDegrees=`, which the mark would hide.
        let text = "\u{FEFF}inDegrees=yes\nversion=3\nendheader\ntime\tq\n0\t30\n1\t45\n";
        let (t, w) = MotionTable::parse(text, "x.sto").unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert!(t.in_degrees());
        assert_eq!(t.column("q").unwrap(), &[30.0, 45.0]);
        // A name line keeps no mark; a mark later in the file is not skipped.
        let (t, w) = MotionTable::parse(&format!("\u{FEFF}{NROWS_STYLE}"), "a.mot").unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(t.header().name, "walk");
        let later = NROWS_STYLE.replace("inDegrees", "\u{FEFF}inDegrees");
        let (t, w) = MotionTable::parse(&later, "a.mot").unwrap();
        assert!(!t.in_degrees(), "{w:?}");
    }

    #[test]
    fn wrong_declared_row_count_is_a_warning_and_data_wins() {
        let text = NROWS_STYLE.replace("nRows=2", "nRows=7");
        let (t, w) = MotionTable::parse(&text, "a.mot").unwrap();
        assert_eq!(t.rows(), 2);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].to_string().contains("nRows=7") && w[0].to_string().contains("2 data rows"),
            "{}",
            w[0]
        );
    }

    #[test]
    fn bad_number_names_file_line_and_column() {
        let text = NROWS_STYLE.replace("0.5\t-20.5", "0.5\t-2O.5");
        let err = MotionTable::parse(&text, "a.mot").unwrap_err();
        assert_eq!(
            err.to_string(),
            "a.mot:9:5: bad number `-2O.5` in column `knee_angle_r` (expected a finite decimal number)"
        );
        let spaced = DATAROWS_STYLE.replace("0.5 -20.5 0.95", "0.5 -20.5 n/a");
        let err = MotionTable::parse(&spaced, "b.mot")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("b.mot:8:13: bad number `n/a` in column `pelvis_ty`"),
            "{err}"
        );
        // `nan` is a number OpenSim writes: kept, with where it is, for a model that needs it.
        let nan = DATAROWS_STYLE.replace("0.5 -20.5 0.95", "0.5 -20.5 nan");
        let (t, _) = MotionTable::parse(&nan, "b.mot").unwrap();
        assert!(t.column("pelvis_ty").unwrap()[1].is_nan());
        let at = t.non_finite(2).unwrap();
        assert_eq!((at.line, at.column, at.text.as_str()), (8, 13, "nan"));
        // ... but never in `time`.
        let bad_time = DATAROWS_STYLE.replace("0.5 -20.5 0.95", "nan -20.5 0.95");
        let err = MotionTable::parse(&bad_time, "b.mot")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("b.mot:8:3: bad number `nan` in column `time`"),
            "{err}"
        );
    }

    #[test]
    fn layout_errors_name_the_line() {
        let missing_value = NROWS_STYLE.replace("0.5\t-20.5\t0.95", "0.5\t-20.5");
        assert_eq!(
            MotionTable::parse(&missing_value, "a.mot")
                .unwrap_err()
                .to_string(),
            "a.mot:9: row has 2 values but the header names 3 columns"
        );
        let no_end = NROWS_STYLE.replace("endheader\n", "");
        assert!(MotionTable::parse(&no_end, "a.mot")
            .unwrap_err()
            .to_string()
            .contains("no `endheader`"));
        let backwards = NROWS_STYLE.replace("0.5\t-20.5", "-1\t-20.5");
        assert!(MotionTable::parse(&backwards, "a.mot")
            .unwrap_err()
            .to_string()
            .starts_with("a.mot:9: time -1 is before the previous row's 0"));
        let not_time = NROWS_STYLE.replace("time\t", "t\t");
        assert!(MotionTable::parse(&not_time, "a.mot")
            .unwrap_err()
            .to_string()
            .starts_with("a.mot:7: the first column"));
        let header_only = "x\nendheader\ntime\ta\n";
        assert!(MotionTable::parse(header_only, "a.mot")
            .unwrap_err()
            .to_string()
            .contains("no data rows"));
    }

    #[test]
    fn written_mot_reads_back_identically() {
        let (t, _) = MotionTable::parse(DATAROWS_STYLE, "b.mot").unwrap();
        let mut out = Vec::new();
        t.write_mot(&mut out).unwrap();
        let (back, w) = MotionTable::parse(std::str::from_utf8(&out).unwrap(), "b.mot").unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(
            (&back.header().name, back.in_degrees(), back.labels()),
            (&t.header().name, t.in_degrees(), t.labels())
        );
        for label in t.labels() {
            assert_eq!(back.column(label), t.column(label));
        }
        assert_eq!(back.header().labels_location(), "b.mot:7");
    }

    /// What OpenSim 4.6's `Storage` makes of each header without `inDegrees` (checked with its
    /// Python package on files like these): radians with a `version=` of 1 or more, degrees
    /// without one.
    #[test]
    fn units_without_indegrees_follow_opensims_rule_per_header_version() {
        let body = "endheader\ntime\tknee_angle_r\n0\t-0.5\n1\t-0.6\n";
        for (header, degrees) in [
            (
                "inDegrees=no\nDataType=double\nversion=3\nOpenSimVersion=4.5\n",
                false,
            ),
            ("DataType=double\nversion=3\nOpenSimVersion=4.5\n", false),
            ("walk\nversion=1\nnRows=2\nnColumns=2\n", false),
            ("walk\nversion = 2\nnRows=2\nnColumns=2\n", false),
            ("walk\nversion=0\nnRows=2\nnColumns=2\n", true),
            ("walk\nnRows=2\nnColumns=2\n", true),
            ("walk\ndatacolumns 2\ndatarows 2\nrange 0 1\n", true),
            (
                "walk\nversion=1\nnRows=2\nnColumns=2\ninDegrees=YES\n",
                true,
            ),
            (
                "walk\nversion=1\nnRows=2\nnColumns=2\ninDegrees=true\n",
                false,
            ),
        ] {
            let (t, w) = MotionTable::parse(&format!("{header}{body}"), "x.sto").unwrap();
            assert_eq!(t.in_degrees(), degrees, "{header:?}");
            let said = header.contains("inDegrees=no") || header.contains("inDegrees=YES");
            assert_eq!(w.is_empty(), said, "{header:?}: {w:?}");
            if !said {
                let unit = if degrees { "degrees" } else { "radians" };
                assert!(w[0].to_string().contains(unit), "{header:?}: {w:?}");
            }
        }
    }

    #[test]
    fn what_opensim_reads_is_read_with_a_warning() {
        // A repeated last time: the later row replaces the earlier, as in OpenSim.
        let repeated = format!("{NROWS_STYLE}0.5\t-21\t0.97\n").replace("nRows=2", "nRows=3");
        let (t, w) = MotionTable::parse(&repeated, "a.mot").unwrap();
        assert_eq!(t.time(), &[0.0, 0.5]);
        assert_eq!(t.column("knee_angle_r").unwrap(), &[-10.0, -21.0]);
        assert!(w.iter().any(|w| w.to_string() == "a.mot:10: time 0.5 repeats the previous row's (line 9); this row replaces it, as in OpenSim"), "{w:?}");
        // A label twice: kept, with a warning.
        let dup = NROWS_STYLE.replace(
            "time\tknee_angle_r\tpelvis_ty",
            "time\tknee_angle_r\tknee_angle_r",
        );
        let (t, w) = MotionTable::parse(&dup, "a.mot").unwrap();
        assert!(t.header().is_duplicated("knee_angle_r"));
        assert_eq!(t.column("knee_angle_r").unwrap(), &[-10.0, -20.5]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].to_string().starts_with(
                "a.mot:7: column `knee_angle_r` appears more than once (columns 2 and 3)"
            ),
            "{w:?}"
        );
        // A Latin-1 byte in a header comment.
        let mut bytes = NROWS_STYLE
            .replace("version=1", "version=1\nCaf\u{1}")
            .into_bytes();
        let at = bytes.iter().position(|&b| b == 1).unwrap();
        bytes[at] = 0xE9;
        let (t, w) = MotionTable::collect(MotionReader::new(&bytes[..], "a.mot").unwrap()).unwrap();
        assert_eq!(t.rows(), 2);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].to_string(), "a.mot:3: not UTF-8; read as Latin-1");
        // Anything but yes/no for inDegrees: radians, as OpenSim reads it, with a warning.
        let maybe = NROWS_STYLE.replace("inDegrees=yes", "inDegrees=maybe");
        let (t, w) = MotionTable::parse(&maybe, "a.mot").unwrap();
        assert!(!t.in_degrees());
        assert!(
            w[0].to_string()
                .starts_with("a.mot:5: inDegrees=`maybe` is neither yes nor no"),
            "{w:?}"
        );
    }

    #[test]
    fn a_marker_file_or_a_model_given_as_a_motion_says_what_it_is() {
        let trc = "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\n100\t100\n";
        let e = MotionTable::parse(trc, "x.trc").unwrap_err().to_string();
        assert!(e.starts_with("x.trc:1: this is a marker file (.trc"), "{e}");
        let osim = "<?xml version=\"1.0\"?>\n<OpenSimDocument Version=\"40000\">\n";
        let e = MotionTable::parse(osim, "m.osim").unwrap_err().to_string();
        assert!(e.starts_with("m.osim:1: this is an XML file"), "{e}");
    }

    /// An input that makes rows as they are read and counts the bytes handed out.
    struct Endless {
        row: u64,
        line: Vec<u8>,
        at: usize,
        served: std::rc::Rc<std::cell::Cell<u64>>,
    }

    impl io::Read for Endless {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = {
                let avail = io::BufRead::fill_buf(self)?;
                let n = avail.len().min(buf.len());
                buf[..n].copy_from_slice(&avail[..n]);
                n
            };
            io::BufRead::consume(self, n);
            Ok(n)
        }
    }

    impl io::BufRead for Endless {
        fn fill_buf(&mut self) -> io::Result<&[u8]> {
            if self.at == self.line.len() {
                self.line = if self.row == 0 {
                    b"m\nversion=1\ninDegrees=yes\nendheader\ntime\tknee_angle_r\n".to_vec()
                } else {
                    format!("{}\t-{}\n", self.row, self.row % 90).into_bytes()
                };
                self.row += 1;
                self.at = 0;
            }
            Ok(&self.line[self.at..])
        }
        fn consume(&mut self, n: usize) {
            self.at += n;
            self.served.set(self.served.get() + n as u64);
        }
    }

    #[test]
    fn the_reader_takes_one_row_at_a_time_from_an_input_of_any_length() {
        let served = std::rc::Rc::new(std::cell::Cell::new(0));
        let input = Endless {
            row: 0,
            line: Vec::new(),
            at: 0,
            served: served.clone(),
        };
        let mut r = MotionReader::new(input, "endless").unwrap();
        let row_bytes = |n: u64| format!("{n}\t-{}\n", n % 90).len() as u64;
        let mut rows_bytes = 0;
        for n in 1..=100_000u64 {
            let row = r.next_row().unwrap().unwrap();
            assert_eq!(row.values, [n as f64, -((n % 90) as f64)]);
            // Read so far: the header, the rows handed out and the one held back after them.
            rows_bytes += row_bytes(n);
            assert_eq!(served.get(), 54 + rows_bytes + row_bytes(n + 1), "{n}");
        }
    }
}

/// What a column of an OpenSim 4 states file (`.sto` of forward simulations, CMC, `Manager`)
/// holds: a coordinate's value or speed. Labels are paths such as
/// `/jointset/hip_r/hip_flexion_r/value`; every other state (a muscle's activation or fibre
/// length, `/forceset/...`) is not a coordinate's and gives `None`, so a reader passes over it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateColumn<'a> {
    /// The coordinate's value (radians or metres; states files are never in degrees).
    Value(&'a str),
    /// The coordinate's speed (radians or metres per second).
    Speed(&'a str),
}

impl<'a> StateColumn<'a> {
    /// The coordinate and quantity of a states-file label, `None` for any other label.
    pub fn parse(label: &'a str) -> Option<Self> {
        let rest = label.strip_prefix("/jointset/")?;
        let mut parts = rest.split('/');
        let (_joint, coordinate, kind) = (parts.next()?, parts.next()?, parts.next()?);
        if parts.next().is_some() || coordinate.is_empty() {
            return None;
        }
        match kind {
            "value" => Some(Self::Value(coordinate)),
            "speed" => Some(Self::Speed(coordinate)),
            _ => None,
        }
    }
}

#[cfg(test)]
mod state_column_tests {
    use super::StateColumn;

    #[test]
    fn coordinates_values_and_speeds_and_nothing_else() {
        assert_eq!(
            StateColumn::parse("/jointset/hip_r/hip_flexion_r/value"),
            Some(StateColumn::Value("hip_flexion_r"))
        );
        assert_eq!(
            StateColumn::parse("/jointset/knee_l/knee_angle_l/speed"),
            Some(StateColumn::Speed("knee_angle_l"))
        );
        for other in [
            "/forceset/soleus_r/activation",
            "/forceset/soleus_r/fiber_length",
            "/jointset/hip_r/hip_flexion_r/value/x",
            "hip_flexion_r",
            "time",
        ] {
            assert_eq!(StateColumn::parse(other), None, "{other}");
        }
    }
}
