#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod anthropometry;
pub mod chain;
pub mod choice;
pub mod coords;
pub mod derivatives;
pub mod error;
pub mod fidelity;
pub mod kinematics;
pub mod leg_chain;
pub mod motion;
pub mod points;
pub mod subject;
pub mod toml_path;

/// A TOML file's error at byte range `span` of `text` (line and column of its start, counted
/// from 1, columns in characters; the whole file without a span), the message on one line.
pub fn toml_error(
    text: &str,
    source: &str,
    span: Option<std::ops::Range<usize>>,
    message: &str,
) -> error::ModelError {
    error::ModelError::File {
        at: match span {
            Some(span) => qgait_opensim::diagnostics::Location::in_text(source, text, span.start),
            None => qgait_opensim::diagnostics::Location::file(source),
        },
        message: message.split_whitespace().collect::<Vec<_>>().join(" "),
    }
}
