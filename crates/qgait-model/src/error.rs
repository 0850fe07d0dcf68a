//! Why a model, or a motion for it, cannot be used: one error type for the model room.

use std::io;

use qgait_opensim::diagnostics::Location;

/// Why a model or a motion for it cannot be used. Each names the file (and where in it).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// `--model` names no model qgait knows.
    #[error("unknown model `{0}` (expected hak, phak, gait2392, a SUBJECT.toml or CHAIN.toml file from `qgait model import`, or an OpenSim model .osim)")]
    Unknown(String),
    /// A model or lengths file could not be read.
    #[error("{path}: cannot read: {error}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        error: io::Error,
    },
    /// A subject or lengths file is not what it must be.
    #[error("{at}: {message}")]
    File {
        /// Where (file, and line and column where known).
        at: Location,
        /// What is wrong.
        message: String,
    },
    /// An OpenSim model's leg chain cannot be imported.
    #[error(transparent)]
    Import(#[from] qgait_opensim::osim::ImportError),
    /// The kernel refuses the model's numbers (a zero axis, a bad length, ...).
    #[error("{name}: model rejected by the kernel: {error}")]
    Rejected {
        /// The model (`hak`, `phak`, or its file).
        name: String,
        /// The kernel's reason.
        error: qgait_kernel::ModelError,
    },
    /// Segment lengths were given for a model with its own geometry.
    #[error("--anthropometry applies to hak and phak only: {0} has its own segment lengths (a subject's gait2392 model comes from `qgait model import`)")]
    LengthsNotApplicable(String),
    /// The subtalar and MTP points were asked of a model without them.
    #[error("--points (subtalar and MTP) needs an OpenSim leg chain (--model gait2392, SUBJECT.toml, CHAIN.toml or MODEL.osim)")]
    PointsNeedGait2392,
    /// This use takes HAK or PHAK only.
    #[error("{what} takes hak or phak, not {name}")]
    StickOnly {
        /// What needs a stick model (e.g. `report`).
        what: &'static str,
        /// The model given.
        name: String,
    },
    /// This use takes an imported OpenSim model (gait2392's family or a chain), not HAK or PHAK.
    #[error("{what} takes an OpenSim leg chain (gait2392, a SUBJECT.toml or CHAIN.toml, an .osim), not {name}")]
    NeedsChain {
        /// What needs an imported model.
        what: &'static str,
        /// The model given.
        name: String,
    },
    /// A motion lacks columns every model needs (the PHAK leg coordinates).
    #[error("{at}: missing required column(s) {}", columns.join(", "))]
    MissingColumns {
        /// The line of labels.
        at: String,
        /// The columns.
        columns: Vec<&'static str>,
    },
    /// A column the model needs appears more than once.
    #[error("{at}: column `{name}` appears more than once and the model needs it: which one to use is ambiguous")]
    AmbiguousColumn {
        /// The line of labels.
        at: String,
        /// The column.
        name: &'static str,
    },
    /// A value the model needs is `nan` or infinite.
    #[error("{at}: value `{text}` in column `{name}` is not a finite number, and the model needs this column")]
    NotFinite {
        /// File, line and column (or row) of the value.
        at: String,
        /// The value as written.
        text: String,
        /// The column.
        name: &'static str,
    },
    /// Reading the motion failed.
    #[error(transparent)]
    Motion(#[from] qgait_opensim::mot::MotError),
}

/// The text of a model or lengths file, `shown` as the name its errors give.
pub(crate) fn read_text(path: &std::path::Path, shown: &str) -> Result<String, ModelError> {
    std::fs::read_to_string(path).map_err(|error| ModelError::Read {
        path: shown.to_string(),
        error,
    })
}
