//! Why a report cannot be made or written, and why one of its figures cannot be drawn.

use std::io;

use crate::normative::NormativeError;

/// Why the report cannot be made or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// The normative data cannot be used.
    #[error(transparent)]
    Normative(#[from] NormativeError),
    /// A reference motion was named but not analysed.
    #[error("--reference {0}: not analysed")]
    ReferenceNotAnalysed(String),
    /// A file or directory of the report could not be written (or read back).
    #[error("{path}: cannot {action}: {error}")]
    Io {
        /// The file or directory.
        path: String,
        /// `write`, `create`, `read`.
        action: &'static str,
        /// Why.
        error: io::Error,
    },
    /// A CSV could not be formed.
    #[error("{file}: {error}")]
    Csv {
        /// The file (`events.csv`, ...).
        file: &'static str,
        /// Why.
        error: csv::Error,
    },
    /// A figure could not be drawn.
    #[error(transparent)]
    Figure(#[from] FigureError),
    /// A result outside what a human can do: the input is not what it claims to be.
    #[error("{recordings}: {what} is {value} {unit}, outside what a human can do ({min} to {max} {unit}): the input is not what it claims to be (angles in degrees declared radians? see --angles-in), so no report is made")]
    Impossible {
        /// The recordings.
        recordings: String,
        /// The quantity and side (`cadence (right)`).
        what: String,
        /// Its value.
        value: String,
        /// Its unit.
        unit: &'static str,
        /// The least possible.
        min: f64,
        /// The most possible.
        max: f64,
    },
    /// `report.html` could not be rendered from its template.
    #[error("report.html: {0}")]
    Html(#[from] askama::Error),
}

/// Why a figure of the report cannot be drawn or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FigureError {
    /// Drawing or writing one figure failed (the report room's drawing error, which names the
    /// file).
    #[error("{stem}: {error}")]
    Save {
        /// The figure (`kinematics`, `map`, `events`).
        stem: String,
        /// Why.
        error: Box<dyn std::error::Error + Send + Sync>,
    },
}
