//! What the library tells its caller besides results: [`Warning`]s about input that was
//! accepted anyway (an enum of kinds, each with a [`WarningText`]: where and what), and the
//! [`Location`] in a file that warnings and errors name. Library functions return warnings
//! (never print); the CLI decides how to show them (`cli::Diagnostics`: on stderr as
//! `warning: ...`, or not at all with `--quiet`).

use std::fmt;

/// A warning about input that was accepted anyway: its kind, where (the file, and the line and
/// column where there is one) and what (one line). Displayed as `where: what`.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Warning {
    /// A line that is not UTF-8, read as Latin-1.
    Encoding(WarningText),
    /// The angles' units assumed (a header that does not say, or says it oddly).
    UnitsAssumed(WarningText),
    /// A header's declared count that disagrees with the file, or is not a count: ignored.
    HeaderMismatch(WarningText),
    /// A row whose time repeats the previous row's replaces it.
    RowReplaced(WarningText),
    /// Rows left out (values that are not finite, a calibration pose of several rows).
    RowsLeftOut(WarningText),
    /// A gap in time: nothing is formed across it.
    Gap(WarningText),
    /// Readings missing (`nan`): the values they determine are held.
    ReadingsMissing(WarningText),
    /// Columns or values missing, taken as 0 (or as gait2392's values).
    MissingDefaulted(WarningText),
    /// A column label that appears more than once.
    DuplicateColumn(WarningText),
    /// Columns or sensors ignored (not in the model, not an IMU of the lower-body set, ...).
    Ignored(WarningText),
    /// Values outside a coordinate's range.
    OutOfRange(WarningText),
    /// A command-line option that does not apply to this input: ignored.
    OptionIgnored(WarningText),
    /// A sign convention other than the one assumed.
    SignConvention(WarningText),
    /// What the analysis cannot do with this input (turns not found, one cycle drawn, ...).
    Limitation(WarningText),
    /// Further warnings like those already given, not shown.
    Suppressed(WarningText),
}

impl Warning {
    /// Where: the file, and the line and column where there is one (`None`: no file).
    pub fn at(&self) -> Option<&Location> {
        self.text().at.as_ref()
    }

    /// What, after the location.
    pub fn detail(&self) -> &str {
        &self.text().detail
    }

    /// Where and what.
    pub fn text(&self) -> &WarningText {
        match self {
            Self::Encoding(t)
            | Self::UnitsAssumed(t)
            | Self::HeaderMismatch(t)
            | Self::RowReplaced(t)
            | Self::RowsLeftOut(t)
            | Self::Gap(t)
            | Self::ReadingsMissing(t)
            | Self::MissingDefaulted(t)
            | Self::DuplicateColumn(t)
            | Self::Ignored(t)
            | Self::OutOfRange(t)
            | Self::OptionIgnored(t)
            | Self::SignConvention(t)
            | Self::Limitation(t)
            | Self::Suppressed(t) => t,
        }
    }
}

/// What a [`Warning`] says: where (the file, and the line and column where there is one;
/// `None`: no file) and what.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WarningText {
    /// Where.
    pub at: Option<Location>,
    /// What, after the location.
    pub detail: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.text() {
            WarningText {
                at: Some(at),
                detail,
            } => write!(f, "{at}: {detail}"),
            WarningText { at: None, detail } => f.write_str(detail),
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
