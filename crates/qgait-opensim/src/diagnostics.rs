//! What the library tells its caller besides results: [`Warning`]s about input that was
//! accepted anyway (an enum of kinds, each with where and what), and the [`Location`] in a file
//! that warnings and errors name. Library functions return them (never print); the CLI decides how to show
//! them (`cli::Diagnostics`: on stderr as `warning: ...`, or not at all with `--quiet`).

use std::fmt;

/// A warning about input that was accepted anyway: its kind, where (the file, and the line and
/// column where there is one) and what (one line). Displayed as `where: what`.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Warning {
    /// A line that is not UTF-8, read as Latin-1.
    Encoding {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// The angles' units assumed (a header that does not say, or says it oddly).
    UnitsAssumed {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A header's declared count that disagrees with the file, or is not a count: ignored.
    HeaderMismatch {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A row whose time repeats the previous row's replaces it.
    RowReplaced {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Rows left out (values that are not finite, a calibration pose of several rows).
    RowsLeftOut {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A gap in time: nothing is formed across it.
    Gap {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Readings missing (`nan`): the values they determine are held.
    ReadingsMissing {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Columns or values missing, taken as 0 (or as gait2392's values).
    MissingDefaulted {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A column label that appears more than once.
    DuplicateColumn {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Columns or sensors ignored (not in the model, not an IMU of the lower-body set, ...).
    Ignored {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Values outside a coordinate's range.
    OutOfRange {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A command-line option that does not apply to this input: ignored.
    OptionIgnored {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// A sign convention other than the one assumed.
    SignConvention {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// What the analysis cannot do with this input (turns not found, one cycle drawn, ...).
    Limitation {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
    /// Further warnings like those already given, not shown.
    Suppressed {
        /// Where.
        at: Option<Location>,
        /// What.
        detail: String,
    },
}

impl Warning {
    /// Where: the file, and the line and column where there is one (`None`: no file).
    pub fn at(&self) -> Option<&Location> {
        self.parts().0
    }

    /// What, after the location.
    pub fn detail(&self) -> &str {
        self.parts().1
    }

    fn parts(&self) -> (Option<&Location>, &str) {
        match self {
            Self::Encoding { at, detail }
            | Self::UnitsAssumed { at, detail }
            | Self::HeaderMismatch { at, detail }
            | Self::RowReplaced { at, detail }
            | Self::RowsLeftOut { at, detail }
            | Self::Gap { at, detail }
            | Self::ReadingsMissing { at, detail }
            | Self::MissingDefaulted { at, detail }
            | Self::DuplicateColumn { at, detail }
            | Self::Ignored { at, detail }
            | Self::OutOfRange { at, detail }
            | Self::OptionIgnored { at, detail }
            | Self::SignConvention { at, detail }
            | Self::Limitation { at, detail }
            | Self::Suppressed { at, detail } => (at.as_ref(), detail),
        }
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.parts() {
            (Some(at), detail) => write!(f, "{at}: {detail}"),
            (None, detail) => f.write_str(detail),
        }
    }
}

/// Where in a text file something is: `path`, `path:line` or `path:line:column` (1-based).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file as named on the command line (or a label such as `builtin:normal`).
    pub path: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based character column, when known.
    pub column: Option<usize>,
}

impl Location {
    /// A whole file.
    pub fn file(path: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            line: None,
            column: None,
        }
    }

    /// A line of a file.
    pub fn line(path: impl Into<String>, line: usize) -> Self {
        Self {
            path: path.into(),
            line: Some(line),
            column: None,
        }
    }

    /// The location of byte offset `at` of `text` (line and character column), in file `path`.
    pub fn in_text(path: impl Into<String>, text: &str, at: usize) -> Self {
        let before = &text[..at.min(text.len())];
        Self {
            path: path.into(),
            line: Some(before.matches('\n').count() + 1),
            column: Some(before.rsplit('\n').next().unwrap_or("").chars().count() + 1),
        }
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.path)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_location_in_text_counts_lines_and_characters() {
        let text = "a = 1\nbé = x\n";
        let at = text.find('x').unwrap();
        assert_eq!(
            Location::in_text("f.toml", text, at).to_string(),
            "f.toml:2:6"
        );
        assert_eq!(Location::file("f.toml").to_string(), "f.toml");
    }
}
