//! The models qgait evaluates and their inputs: the one model choice ([`choice::Model`], what
//! `--model` and `--anthropometry` load) and its errors ([`error::ModelError`]), a motion's
//! columns picked for it ([`coords`]), the kernel evaluation of HAK and PHAK ([`kinematics`]),
//! subject models and lengths, imported chains of other OpenSim models ([`chain`]), ([`subject`], [`anthropometry`]), the named points every model
//! gives and their CSV ([`points`]), and how far the paper's model is from gait2392
//! ([`fidelity`]).

pub mod anthropometry;
pub mod chain;
pub mod choice;
pub mod coords;
pub mod error;
pub(crate) mod fidelity;
pub mod kinematics;
pub mod leg_chain;
pub mod points;
pub mod subject;
pub(crate) mod toml_path;

/// A TOML file's error at byte range `span` of `text` (line and column of its start, counted
/// from 1, columns in characters; the whole file without a span), the message on one line.
pub(crate) fn toml_error(
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
