//! `qgait fidelity`: how far PHAK (8 DoF) is from gait2392, per point, and what each of
//! gait2392's features costs (Markdown).

use std::path::PathBuf;

use clap::Args;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::output::{refuse_overwrite, write_output};
use qgait_model::choice::Model;
use qgait_model::fidelity;
use qgait_model::motion::source::{default_label, load_motion};

/// `qgait fidelity` arguments.
#[derive(Debug, Args)]
pub struct FidelityArgs {
    /// Motion files (.mot/.sto) or `builtin:...`.
    #[arg(required = true)]
    pub motions: Vec<String>,
    /// Label of each motion, in order (default: the file stem).
    #[arg(long = "label", value_name = "NAME")]
    pub labels: Vec<String>,
    /// Also compare PHAK with these imported models (an .osim, a SUBJECT.toml or CHAIN.toml from
    /// `qgait model import`), on every motion; repeatable.
    #[arg(long = "model", value_name = "MODEL.osim|CHAIN.toml")]
    pub models: Vec<String>,
    /// Output Markdown file (default: standard output).
    #[arg(short, long, value_name = "OUT.md")]
    pub output: Option<PathBuf>,
}

/// Runs `qgait fidelity`.
pub fn run_fidelity(a: FidelityArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    if a.labels.len() > a.motions.len() {
        anyhow::bail!(
            "{} --label values for {} motions",
            a.labels.len(),
            a.motions.len()
        );
    }
    let specs: Vec<&str> = a
        .motions
        .iter()
        .chain(&a.models)
        .map(String::as_str)
        .collect();
    refuse_overwrite(a.output.as_deref(), &specs)?;
    let mut models = Vec::new();
    for m in &a.models {
        let (model, _notes) = Model::load(m, None)?;
        models.push(model);
    }
    let mut results = Vec::new();
    let mut comparisons = Vec::new();
    for (i, spec) in a.motions.iter().enumerate() {
        let (table, w) = load_motion(spec)?;
        diagnostics.warn(w);
        let label = a
            .labels
            .get(i)
            .cloned()
            .unwrap_or_else(|| default_label(spec));
        let (r, w) = fidelity::analyse(&label, &table)?;
        diagnostics.warn(w);
        results.push(r);
        for model in &models {
            let (c, _) = fidelity::compare(model, &label, &table)?;
            comparisons.push(c);
        }
    }
    let mut md = fidelity::markdown(&results);
    if !comparisons.is_empty() {
        md.push_str(&fidelity::comparisons_markdown(&comparisons));
    }
    write_output(a.output.as_deref(), |out| out.write_all(md.as_bytes()))
}
