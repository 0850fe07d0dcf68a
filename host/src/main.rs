//! The `qgait` binary: parses the command line, runs it, and reports any error as one line.

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = qgait::cli::Cli::parse();
    match qgait::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // `{:#}` joins the error and its causes on one line: "outer: inner".
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
