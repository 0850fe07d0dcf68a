//! What the library tells its caller besides results: [`Warning`]s about input that was
//! accepted anyway. Library functions return them (never print); the CLI decides how to show
//! them (`cli::Diagnostics`: on stderr as `warning: ...`, or not at all with `--quiet`).

use std::fmt;

/// A warning about input that was accepted anyway: where and what (one line).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning(pub String);

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
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
