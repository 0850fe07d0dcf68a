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
//! The row count always comes from the data: a declared `nRows`/`datarows` that disagrees only
//! gives a warning (the shared gait2392 files declare the wrong count). A file that does not say
//! `inDegrees` is taken to be in degrees, with a warning. Header lines not understood (free text
//! such as `Units are S.I. units`) are ignored.

use std::fmt;
use std::io::{self, Write};
use std::path::Path;

/// A problem found while reading a motion file. Every variant names the file; the format
/// variants also name the 1-based line (and, for numbers, the 1-based character column).
#[derive(Debug, thiserror::Error)]
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
}

/// A warning about input that was accepted anyway (printed by the CLI as `warning: ...`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning(pub String);

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// A table of motion data: a `time` column and any number of named columns, all kept.
///
/// Values are stored as read; [`MotionTable::in_degrees`] tells whether angle columns are in
/// degrees. Use [`MotionTable::angle_radians`] to read an angle column in radians.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionTable {
    name: String,
    source: String,
    in_degrees: bool,
    labels: Vec<String>,
    /// 1-based line of the column labels in the file (`None` for generated tables).
    labels_line: Option<usize>,
    /// Column-major: `columns[c][row]`.
    columns: Vec<Vec<f64>>,
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
    ) -> Result<Self, String> {
        let source = source.into();
        if labels.len() != columns.len() {
            return Err(format!(
                "{source}: {} labels for {} columns",
                labels.len(),
                columns.len()
            ));
        }
        if labels
            .first()
            .map(|l| !l.eq_ignore_ascii_case("time"))
            .unwrap_or(true)
        {
            return Err(format!("{source}: the first column must be `time`"));
        }
        let rows = columns[0].len();
        if rows == 0 {
            return Err(format!("{source}: no data rows"));
        }
        for (label, col) in labels.iter().zip(&columns) {
            if col.len() != rows {
                return Err(format!(
                    "{source}: column `{label}` has {} rows, `time` has {rows}",
                    col.len()
                ));
            }
            if let Some(i) = col.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "{source}: column `{label}` row {}: value is not finite",
                    i + 1
                ));
            }
        }
        if let Some(i) = columns[0].windows(2).position(|w| w[1] <= w[0]) {
            return Err(format!("{source}: time is not increasing at row {}", i + 2));
        }
        check_unique(&labels).map_err(|l| format!("{source}: column `{l}` appears twice"))?;
        Ok(Self {
            name: name.into(),
            source,
            in_degrees,
            labels,
            labels_line: None,
            columns,
        })
    }

    /// Reads a `.mot`/`.sto` file.
    pub fn read(path: &Path) -> Result<(Self, Vec<Warning>), MotError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|error| MotError::Io {
            path: shown.clone(),
            error,
        })?;
        Self::parse(&text, &shown)
    }

    /// Parses the text of a `.mot`/`.sto` file; `source` names it in errors and warnings.
    pub fn parse(text: &str, source: &str) -> Result<(Self, Vec<Warning>), MotError> {
        let fmt_err = |line: usize, message: String| MotError::Format {
            path: source.to_string(),
            line,
            message,
        };
        let mut warnings = Vec::new();
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim_end()));

        // Header.
        let mut name = String::new();
        let mut in_degrees: Option<bool> = None;
        let mut declared_rows: Option<(usize, &str)> = None;
        let mut declared_cols: Option<(usize, &str)> = None;
        let mut seen_header_line = false;
        let mut found_end = false;
        let mut last_line = 0;
        for (no, line) in lines.by_ref() {
            last_line = no;
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
            if let Some((key, value)) = t.split_once('=') {
                let (key, value) = (key.trim(), value.trim());
                match key.to_ascii_lowercase().as_str() {
                    "nrows" => {
                        declared_rows =
                            parse_count(value, no, source, &mut warnings, key).map(|n| (n, "nRows"))
                    }
                    "ncolumns" => {
                        declared_cols = parse_count(value, no, source, &mut warnings, key)
                            .map(|n| (n, "nColumns"))
                    }
                    "indegrees" => {
                        in_degrees = Some(match value.to_ascii_lowercase().as_str() {
                            "yes" | "true" => true,
                            "no" | "false" => false,
                            _ => {
                                return Err(fmt_err(
                                    no,
                                    format!("inDegrees must be `yes` or `no`, found `{value}`"),
                                ))
                            }
                        })
                    }
                    _ => {}
                }
                continue;
            }
            let mut words = t.split_whitespace();
            match words.next().map(str::to_ascii_lowercase).as_deref() {
                Some("datarows") => {
                    declared_rows = parse_count(
                        words.next().unwrap_or(""),
                        no,
                        source,
                        &mut warnings,
                        "datarows",
                    )
                    .map(|n| (n, "datarows"))
                }
                Some("datacolumns") => {
                    declared_cols = parse_count(
                        words.next().unwrap_or(""),
                        no,
                        source,
                        &mut warnings,
                        "datacolumns",
                    )
                    .map(|n| (n, "datacolumns"))
                }
                _ if first => name = t.to_string(),
                _ => {}
            }
        }
        if !found_end {
            return Err(fmt_err(
                last_line.max(1),
                "no `endheader` line: not an OpenSim .mot/.sto file".into(),
            ));
        }
        let in_degrees = in_degrees.unwrap_or_else(|| {
            warnings.push(Warning(format!(
                "{source}: header does not say inDegrees=yes/no; angles taken to be in degrees"
            )));
            true
        });

        // Column labels.
        let (label_line, labels) = loop {
            match lines.next() {
                None => {
                    return Err(fmt_err(
                        last_line + 1,
                        "no column labels after `endheader`".into(),
                    ))
                }
                Some((_, l)) if l.trim().is_empty() => continue,
                Some((no, l)) => {
                    break (
                        no,
                        l.split_whitespace().map(str::to_string).collect::<Vec<_>>(),
                    )
                }
            }
        };
        if !labels[0].eq_ignore_ascii_case("time") {
            return Err(fmt_err(
                label_line,
                format!("the first column must be `time`, found `{}`", labels[0]),
            ));
        }
        if let Err(dup) = check_unique(&labels) {
            return Err(fmt_err(label_line, format!("column `{dup}` appears twice")));
        }

        // Data.
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); labels.len()];
        let mut prev_time: Option<f64> = None;
        for (no, line) in lines {
            if line.trim().is_empty() {
                continue;
            }
            let mut count = 0;
            for (i, (start, tok)) in tokens(line).enumerate() {
                count = i + 1;
                if i >= labels.len() {
                    continue;
                }
                let value = tok
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| MotError::BadNumber {
                        path: source.to_string(),
                        line: no,
                        column: line[..start].chars().count() + 1,
                        name: labels[i].clone(),
                        text: tok.to_string(),
                    })?;
                columns[i].push(value);
            }
            if count != labels.len() {
                return Err(fmt_err(
                    no,
                    format!(
                        "row has {count} values but the header names {} columns",
                        labels.len()
                    ),
                ));
            }
            let t = *columns[0].last().expect("row has a time value");
            if let Some(p) = prev_time {
                if t <= p {
                    return Err(fmt_err(
                        no,
                        format!("time {t} is not after the previous row's {p}"),
                    ));
                }
            }
            prev_time = Some(t);
        }
        let rows = columns[0].len();
        if rows == 0 {
            return Err(fmt_err(
                label_line,
                "no data rows after the column labels".into(),
            ));
        }
        if let Some((n, key)) = declared_rows {
            if n != rows {
                warnings.push(Warning(format!("{source}: header says {key}={n} but the file has {rows} data rows; using {rows}")));
            }
        }
        if let Some((n, key)) = declared_cols {
            if n != labels.len() {
                warnings.push(Warning(format!(
                    "{source}: header says {key}={n} but the file has {} columns",
                    labels.len()
                )));
            }
        }
        Ok((
            Self {
                name,
                source: source.to_string(),
                in_degrees,
                labels,
                labels_line: Some(label_line),
                columns,
            },
            warnings,
        ))
    }

    /// Writes the table as a `.mot` file (`nRows=` header style, tab separated, values printed
    /// with the shortest representation that reads back to the same `f64`).
    pub fn write_mot<W: Write>(&self, mut w: W) -> io::Result<()> {
        let name = if self.name.is_empty() {
            "motion"
        } else {
            &self.name
        };
        writeln!(
            w,
            "{name}\nversion=1\nnRows={}\nnColumns={}",
            self.rows(),
            self.labels.len()
        )?;
        writeln!(
            w,
            "inDegrees={}\nendheader",
            if self.in_degrees { "yes" } else { "no" }
        )?;
        writeln!(w, "{}", self.labels.join("\t"))?;
        for r in 0..self.rows() {
            for (c, col) in self.columns.iter().enumerate() {
                if c > 0 {
                    w.write_all(b"\t")?;
                }
                write!(w, "{}", col[r])?;
            }
            w.write_all(b"\n")?;
        }
        w.flush()
    }

    /// The name on the header's first line (may be empty).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Where the data came from (a path or a `builtin:` spec).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// Where the column labels are, for messages: `file:line`, or just the source for a
    /// generated table.
    pub fn labels_location(&self) -> String {
        match self.labels_line {
            Some(line) => format!("{}:{line}", self.source),
            None => self.source.clone(),
        }
    }

    /// Whether angle columns are in degrees (`inDegrees=yes`).
    pub fn in_degrees(&self) -> bool {
        self.in_degrees
    }

    /// Number of data rows.
    pub fn rows(&self) -> usize {
        self.columns[0].len()
    }

    /// The column labels, `time` first.
    pub fn labels(&self) -> &[String] {
        &self.labels
    }

    /// The time column (seconds).
    pub fn time(&self) -> &[f64] {
        &self.columns[0]
    }

    /// A column by label, as stored.
    pub fn column(&self, label: &str) -> Option<&[f64]> {
        self.labels
            .iter()
            .position(|l| l == label)
            .map(|i| self.columns[i].as_slice())
    }

    /// An angle column by label, converted to radians if the table is in degrees.
    pub fn angle_radians(&self, label: &str) -> Option<Vec<f64>> {
        let scale = if self.in_degrees {
            std::f64::consts::PI / 180.0
        } else {
            1.0
        };
        self.column(label)
            .map(|c| c.iter().map(|v| v * scale).collect())
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

/// Whitespace-separated tokens with their byte offsets.
fn tokens(line: &str) -> impl Iterator<Item = (usize, &str)> {
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
        warnings.push(Warning(format!(
            "{source}:{line}: `{key}` is not a count (`{value}`); ignored"
        )));
    }
    parsed
}

fn check_unique(labels: &[String]) -> Result<(), String> {
    for (i, l) in labels.iter().enumerate() {
        if labels[..i].contains(l) {
            return Err(l.clone());
        }
    }
    Ok(())
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
        assert!(wb[0].0.contains("inDegrees"));
        assert_eq!(a.name(), "walk");
        assert_eq!(a.labels(), b.labels());
        assert_eq!(a.rows(), 2);
        assert_eq!(a.column("knee_angle_r"), b.column("knee_angle_r"));
        assert_eq!(a.column("pelvis_ty").unwrap(), &[0.9, 0.95]);
        assert_eq!(a.percent_of_cycle(), vec![0.0, 100.0]);
        let rad = a.angle_radians("knee_angle_r").unwrap();
        assert!((rad[1] - (-20.5f64).to_radians()).abs() < 1e-15);
    }

    #[test]
    fn opensim4_sto_without_name_line() {
        let text = "inDegrees=no\nDataType=double\nversion=3\nOpenSimVersion=4.5\nendheader\ntime\tq\n0\t0.25\n1\t0.5\n";
        let (t, w) = MotionTable::parse(text, "x.sto").unwrap();
        assert!(w.is_empty());
        assert!(!t.in_degrees());
        assert_eq!(t.angle_radians("q").unwrap(), vec![0.25, 0.5]);
    }

    #[test]
    fn wrong_declared_row_count_is_a_warning_and_data_wins() {
        let text = NROWS_STYLE.replace("nRows=2", "nRows=7");
        let (t, w) = MotionTable::parse(&text, "a.mot").unwrap();
        assert_eq!(t.rows(), 2);
        assert_eq!(w.len(), 1);
        assert!(
            w[0].0.contains("nRows=7") && w[0].0.contains("2 data rows"),
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
        let spaced = DATAROWS_STYLE.replace("0.5 -20.5 0.95", "0.5 -20.5 nan");
        let err = MotionTable::parse(&spaced, "b.mot")
            .unwrap_err()
            .to_string();
        assert!(
            err.starts_with("b.mot:8:13: bad number `nan` in column `pelvis_ty`"),
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
        let backwards = NROWS_STYLE.replace("0.5\t-20.5", "0\t-20.5");
        assert!(MotionTable::parse(&backwards, "a.mot")
            .unwrap_err()
            .to_string()
            .starts_with("a.mot:9: time 0"));
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
        let bad_degrees = NROWS_STYLE.replace("inDegrees=yes", "inDegrees=maybe");
        assert!(MotionTable::parse(&bad_degrees, "a.mot")
            .unwrap_err()
            .to_string()
            .starts_with("a.mot:5: inDegrees"));
    }

    #[test]
    fn written_mot_reads_back_identically() {
        let (t, _) = MotionTable::parse(DATAROWS_STYLE, "b.mot").unwrap();
        let mut out = Vec::new();
        t.write_mot(&mut out).unwrap();
        let (back, w) = MotionTable::parse(std::str::from_utf8(&out).unwrap(), "b.mot").unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(
            (back.name(), back.in_degrees(), back.labels()),
            (t.name(), t.in_degrees(), t.labels())
        );
        for label in t.labels() {
            assert_eq!(back.column(label), t.column(label));
        }
        assert_eq!(back.labels_location(), "b.mot:7");
    }
}
