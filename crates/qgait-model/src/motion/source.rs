//! Where a motion comes from: a `.mot`/`.sto` path, or a `builtin:` spec (see [`crate::motion::builtin`]).

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use crate::motion::builtin::{self, BuiltinSpec};
use qgait_opensim::diagnostics::Warning;
use qgait_opensim::mot::{Header, MotError, MotionReader, MotionTable, Row};

/// Why a motion cannot be loaded: its file, or its `builtin:` spec.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SourceError {
    /// The file cannot be read or is not a motion.
    #[error(transparent)]
    File(#[from] MotError),
    /// The `builtin:` spec names no built-in gait.
    #[error(transparent)]
    Builtin(#[from] builtin::BuiltinError),
}

/// Prefix that selects the built-in gait generator instead of a file.
pub const BUILTIN_PREFIX: &str = "builtin:";

/// Loads a motion from a path or a `builtin:` spec.
pub fn load_motion(spec: &str) -> Result<(MotionTable, Vec<Warning>), SourceError> {
    if let Some(rest) = spec.strip_prefix(BUILTIN_PREFIX) {
        let spec = BuiltinSpec::parse(rest)?;
        Ok((builtin::generate(&spec), Vec::new()))
    } else {
        Ok(MotionTable::read(Path::new(spec))?)
    }
}

/// A short label for a motion spec: the file stem, or the spec itself for `builtin:`.
pub fn default_label(spec: &str) -> String {
    if spec.starts_with(BUILTIN_PREFIX) {
        spec.to_string()
    } else {
        Path::new(spec)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| spec.to_string())
    }
}

/// The rows of a motion, one at a time: a file read as it goes ([`MotionReader`], memory
/// independent of its length), or a table in memory (a `builtin:` gait).
pub struct MotionRows {
    inner: Inner,
}

enum Inner {
    File(Box<MotionReader<BufReader<File>>>),
    Table { table: MotionTable, next: usize },
}

impl MotionRows {
    /// Opens a path or a `builtin:` spec and reads its header; the header's warnings are
    /// returned, the rest come from [`MotionRows::take_warnings`] as rows are read.
    pub fn open(spec: &str) -> Result<(Self, Vec<Warning>), SourceError> {
        if spec.starts_with(BUILTIN_PREFIX) {
            let (table, w) = load_motion(spec)?;
            return Ok((Self::from_table(table), w));
        }
        let mut reader = MotionReader::open(Path::new(spec))?;
        let w = reader.take_warnings();
        Ok((
            Self {
                inner: Inner::File(Box::new(reader)),
            },
            w,
        ))
    }

    /// The rows of a table.
    pub fn from_table(table: MotionTable) -> Self {
        Self {
            inner: Inner::Table { table, next: 0 },
        }
    }

    /// The header.
    pub fn header(&self) -> &Header {
        match &self.inner {
            Inner::File(r) => r.header(),
            Inner::Table { table, .. } => table.header(),
        }
    }

    /// The number of rows if known in advance (a table's, or the file's declared count).
    pub fn size_hint(&self) -> Option<usize> {
        match &self.inner {
            Inner::File(r) => r.header().declared_rows(),
            Inner::Table { table, .. } => Some(table.rows()),
        }
    }

    /// The next row and where it is (`line N` in a file, `row N` in a generated table).
    pub fn next_row(&mut self) -> Result<Option<(Row, Location)>, MotError> {
        match &mut self.inner {
            Inner::File(r) => Ok(r.next_row()?.map(|row| {
                let at = Location::Line(row.line);
                (row, at)
            })),
            Inner::Table { table, next } => {
                if *next >= table.rows() {
                    return Ok(None);
                }
                let r = *next;
                *next += 1;
                let values: Vec<f64> = (0..table.labels().len())
                    .map(|c| table.value(r, c))
                    .collect();
                let line = table.line(r);
                let non_finite = values
                    .iter()
                    .enumerate()
                    .filter(|(_, v)| !v.is_finite())
                    .filter_map(|(c, _)| table.non_finite_at(r, c).map(|nf| (c, nf.clone())))
                    .collect();
                let at = line.map_or(Location::Row(r + 1), Location::Line);
                Ok(Some((
                    Row {
                        line: line.unwrap_or(0),
                        values,
                        non_finite,
                    },
                    at,
                )))
            }
        }
    }

    /// Warnings found since the last call (a repeated time, the declared row count at the end).
    pub fn take_warnings(&mut self) -> Vec<Warning> {
        match &mut self.inner {
            Inner::File(r) => r.take_warnings(),
            Inner::Table { .. } => Vec::new(),
        }
    }
}

/// Where a row is, for messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// 1-based line of a file.
    Line(usize),
    /// 1-based row of a generated table.
    Row(usize),
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::Line(n) => write!(f, "line {n}"),
            Location::Row(n) => write!(f, "row {n}"),
        }
    }
}
