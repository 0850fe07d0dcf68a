//! Where a value of a TOML file is: the line and column of the value a path of keys and
//! array indices leads to, for errors about what a file says rather than how it is written
//! (those `toml` locates itself).

use crate::error::ModelError;
use qgait_opensim::diagnostics::Location;

/// What a file says, refused: why, and the path to the value refused (empty: the file as a
/// whole).
#[derive(Debug, Clone, PartialEq)]
pub struct Fault {
    /// Why.
    pub message: String,
    /// Where.
    pub at: Vec<Step>,
}

impl Fault {
    /// A refusal of the file as a whole.
    pub fn whole(message: String) -> Self {
        Self {
            message,
            at: Vec::new(),
        }
    }

    /// The refusal as an error of file `source` with this `text`, at the value's line and
    /// column ([`locate`]).
    pub fn in_file(self, text: &str, source: &str) -> ModelError {
        ModelError::File {
            at: locate(text, source, &self.at),
            message: self.message,
        }
    }

    /// The refusal as an error of model `name`, its text not at hand (the file as a whole).
    pub fn in_model(self, name: &str) -> ModelError {
        ModelError::File {
            at: Location::file(name),
            message: self.message,
        }
    }
}

/// One step down a TOML document: a key of a table, or an index into an array of tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// A key.
    Key(&'static str),
    /// An index.
    Index(usize),
}

/// The location in `text` (file `source`) of the value `path` leads to: its line and
/// column, or the nearest enclosing table's the path reaches, or the whole file.
pub fn locate(text: &str, source: &str, path: &[Step]) -> Location {
    let Ok(document) = toml_edit::Document::parse(text) else {
        return Location::file(source);
    };
    let mut item = document.as_item();
    let mut span = None;
    for step in path {
        let next = match step {
            Step::Key(key) => item.get(*key),
            Step::Index(i) => item.get(*i),
        };
        let Some(next) = next else { break };
        item = next;
        span = item.span().or(span);
    }
    match span {
        Some(range) => Location::in_text(source, text, range.start),
        None => Location::file(source),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_leads_to_its_value_or_the_nearest_table() {
        let text = "# c\n[[joints]]\nname = \"a\"\n\n[[joints]]\nname = \"b\"\n[[joints.rotations]]\naxis = [1, 0, 0]\ncoordinate = \"x\"\n";
        let at = |path: &[Step]| {
            let l = locate(text, "f.toml", path);
            (l.line, l.column)
        };
        use Step::{Index, Key};
        assert_eq!(
            at(&[Key("joints"), Index(1), Key("name")]),
            (Some(6), Some(8))
        );
        assert_eq!(
            at(&[
                Key("joints"),
                Index(1),
                Key("rotations"),
                Index(0),
                Key("coordinate")
            ]),
            (Some(9), Some(14))
        );
        // A missing key: the table that lacks it.
        assert_eq!(
            at(&[Key("joints"), Index(0), Key("body")]),
            (Some(2), Some(1))
        );
        assert_eq!(at(&[Key("nothing")]), (None, None));
        assert_eq!(locate("= broken", "f.toml", &[Key("a")]).line, None);
    }
}
