//! The models qgait evaluates and their inputs: which model (`--model`, [`spec`]), a motion's
//! columns picked for it ([`coords`]), the kernel evaluation ([`kinematics`]), subject models
//! ([`subject`], [`anthropometry`]), the named points and their CSV ([`points_csv`]), and how far
//! the paper's model is from gait2392 ([`fidelity`]).

pub mod anthropometry;
pub mod coords;
pub mod fidelity;
pub mod kinematics;
pub mod points_csv;
pub mod spec;
pub mod subject;

/// `source:line:column: message` for a TOML file's error at byte range `span` of `text` (lines
/// and columns counted from 1, columns in characters), `source: message` without a span; the
/// message on one line.
pub(crate) fn toml_message(
    text: &str,
    source: &str,
    span: Option<std::ops::Range<usize>>,
    message: &str,
) -> String {
    let message = message.split_whitespace().collect::<Vec<_>>().join(" ");
    match span {
        Some(span) => {
            let before = text.get(..span.start.min(text.len())).unwrap_or(text);
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
            format!("{source}:{line}:{column}: {message}")
        }
        None => format!("{source}: {message}"),
    }
}
