//! `SUBJECT.toml`: a gait2392-family subject model, the numbers of
//! [`Gait2392Geometry`] one to one (metres, unit axes, OpenSim frames; knee spline abscissae in
//! radians). Written by `qgait model import`, read by `--model SUBJECT.toml`.
//!
//! ```toml
//! [right]
//! hip_in_pelvis = [-0.0707, -0.0661, 0.0835]
//! hip_axes = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
//! ankle_in_tibia = [0.0, -0.43, 0.0]
//! ankle_axis = [-0.10501355, -0.17402245, 0.97912632]
//! subtalar_in_talus = [-0.04877, -0.04195, 0.00792]
//! subtalar_axis = [0.78717961, 0.60474746, -0.12094949]
//! mtp_in_calcn = [0.1788, -0.002, 0.00108]
//! mtp_axis = [-0.5809544, 0.0, 0.81393611]
//! toetip_in_toes = [0.0812, 0.007, -0.00108]
//!
//! [right.knee_tx]
//! x = [-2.0944, -1.74533, ...]
//! y = [-0.0032, 0.00179, ...]
//!
//! [right.knee_ty]
//! x = [...]
//! y = [...]
//!
//! [left]
//! ...
//! ```
//!
//! Every key is required; unknown keys are errors; the kernel checks the rest (finite numbers,
//! non-zero axes, 2 to 12 knots with increasing `x`) when the model is built.

use std::path::Path;

use qgait_kernel::models::gait2392::{Knots, LegGeometry};
use qgait_kernel::{Gait2392, Gait2392Geometry};
use serde::{Deserialize, Serialize};

use crate::error::ModelError;
use crate::toml_path::{Fault, Step, Step::Index, Step::Key};

/// The file: one table per leg.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubjectFile {
    /// Right leg.
    pub right: LegFile,
    /// Left leg.
    pub left: LegFile,
}

/// One leg; field names and meaning as [`LegGeometry`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[allow(missing_docs)]
pub struct LegFile {
    pub hip_in_pelvis: Vec<f64>,
    pub hip_axes: Vec<Vec<f64>>,
    pub ankle_in_tibia: Vec<f64>,
    pub ankle_axis: Vec<f64>,
    pub subtalar_in_talus: Vec<f64>,
    pub subtalar_axis: Vec<f64>,
    pub mtp_in_calcn: Vec<f64>,
    pub mtp_axis: Vec<f64>,
    pub toetip_in_toes: Vec<f64>,
    pub knee_tx: KnotsFile,
    pub knee_ty: KnotsFile,
}

/// Spline knots: `x` (radians of `knee_angle`), `y` (metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KnotsFile {
    /// Abscissae, strictly increasing.
    pub x: Vec<f64>,
    /// Values, as many as `x`.
    pub y: Vec<f64>,
}

impl KnotsFile {
    fn from_knots(k: &Knots) -> Self {
        Self {
            x: k.x[..k.n].to_vec(),
            y: k.y[..k.n].to_vec(),
        }
    }
}

impl LegFile {
    fn from_leg(l: &LegGeometry) -> Self {
        Self {
            hip_in_pelvis: l.hip_in_pelvis.to_vec(),
            hip_axes: l.hip_axes.iter().map(|a| a.to_vec()).collect(),
            ankle_in_tibia: l.ankle_in_tibia.to_vec(),
            ankle_axis: l.ankle_axis.to_vec(),
            subtalar_in_talus: l.subtalar_in_talus.to_vec(),
            subtalar_axis: l.subtalar_axis.to_vec(),
            mtp_in_calcn: l.mtp_in_calcn.to_vec(),
            mtp_axis: l.mtp_axis.to_vec(),
            toetip_in_toes: l.toetip_in_toes.to_vec(),
            knee_tx: KnotsFile::from_knots(&l.knee_tx),
            knee_ty: KnotsFile::from_knots(&l.knee_ty),
        }
    }

    fn to_leg(&self, side: &'static str) -> Result<LegGeometry, Fault> {
        let knots = |k: &KnotsFile, name: &'static str| {
            if k.x.len() != k.y.len() {
                return Err(Fault {
                    message: format!(
                        "[{side}.{name}]: {} x values but {} y values",
                        k.x.len(),
                        k.y.len()
                    ),
                    at: vec![Key(side), Key(name), Key("y")],
                });
            }
            Ok(Knots::new(&k.x, &k.y))
        };
        let three = |v: &[f64], name: &str, at: Vec<Step>| -> Result<[f64; 3], Fault> {
            <[f64; 3]>::try_from(v).map_err(|_| Fault {
                message: format!("[{side}] {name}: expected 3 numbers, found {}", v.len()),
                at,
            })
        };
        let field = |v: &[f64], name: &'static str| three(v, name, vec![Key(side), Key(name)]);
        let axis = |k: usize| {
            let at = vec![Key(side), Key("hip_axes"), Index(k)];
            three(&self.hip_axes[k], &format!("hip_axes[{k}]"), at)
        };
        Ok(LegGeometry {
            hip_in_pelvis: field(&self.hip_in_pelvis, "hip_in_pelvis")?,
            hip_axes: match self.hip_axes.len() {
                3 => [axis(0)?, axis(1)?, axis(2)?],
                n => {
                    return Err(Fault {
                        message: format!("[{side}] hip_axes: expected 3 axes, found {n}"),
                        at: vec![Key(side), Key("hip_axes")],
                    })
                }
            },
            knee_tx: knots(&self.knee_tx, "knee_tx")?,
            knee_ty: knots(&self.knee_ty, "knee_ty")?,
            ankle_in_tibia: field(&self.ankle_in_tibia, "ankle_in_tibia")?,
            ankle_axis: field(&self.ankle_axis, "ankle_axis")?,
            subtalar_in_talus: field(&self.subtalar_in_talus, "subtalar_in_talus")?,
            subtalar_axis: field(&self.subtalar_axis, "subtalar_axis")?,
            mtp_in_calcn: field(&self.mtp_in_calcn, "mtp_in_calcn")?,
            mtp_axis: field(&self.mtp_axis, "mtp_axis")?,
            toetip_in_toes: field(&self.toetip_in_toes, "toetip_in_toes")?,
        })
    }
}

impl SubjectFile {
    /// The file for a geometry.
    pub fn from_geometry(g: &Gait2392Geometry) -> Self {
        Self {
            right: LegFile::from_leg(&g.right),
            left: LegFile::from_leg(&g.left),
        }
    }

    /// The geometry (not yet checked by the kernel; see [`parse`]).
    pub fn to_geometry(&self) -> Result<Gait2392Geometry, Fault> {
        Ok(Gait2392Geometry {
            right: self.right.to_leg("right")?,
            left: self.left.to_leg("left")?,
        })
    }
}

/// The text of a subject file: `comment` lines (each prefixed with `# `), then the tables.
pub fn to_toml(g: &Gait2392Geometry, comment: &[String]) -> String {
    let mut text = String::new();
    for line in comment {
        text.push_str("# ");
        text.push_str(line);
        text.push('\n');
    }
    if !comment.is_empty() {
        text.push('\n');
    }
    text.push_str(
        &toml::to_string(&SubjectFile::from_geometry(g))
            .expect("plain numbers always serialise to TOML"),
    );
    text
}

/// Parses a subject file and checks it with the kernel; `source` names it in messages.
pub fn parse(text: &str, source: &str) -> Result<Gait2392Geometry, ModelError> {
    let file: SubjectFile =
        toml::from_str(text).map_err(|e| super::toml_error(text, source, e.span(), e.message()))?;
    let g = file
        .to_geometry()
        .map_err(|fault| fault.in_file(text, source))?;
    Gait2392::<f64>::new(&g).map_err(|error| ModelError::Rejected {
        name: source.to_string(),
        error,
    })?;
    Ok(g)
}

/// Reads a subject file.
pub fn read(path: &Path) -> Result<Gait2392Geometry, ModelError> {
    let shown = path.display().to_string();
    let text = crate::error::read_text(path, &shown)?;
    parse(&text, &shown)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generic_round_trips_exactly() {
        let g = Gait2392Geometry::generic();
        let text = to_toml(&g, &["a comment".into()]);
        assert!(text.starts_with("# a comment\n"), "{text}");
        assert_eq!(parse(&text, "s.toml").unwrap(), g);
    }

    #[test]
    fn numbers_refused_are_named_by_line_and_column() {
        let good = to_toml(&Gait2392Geometry::generic(), &[]);
        // The edited value's 1-based line and column in `text`.
        let at = |text: &str, value: &str| {
            let i = text.find(value).unwrap();
            let line = text[..i].matches('\n').count() + 1;
            (line, i - text[..i].rfind('\n').map_or(0, |n| n + 1) + 1)
        };
        let four = good.replacen("hip_in_pelvis = [", "hip_in_pelvis = [1.0, ", 1);
        let (line, column) = at(&four, "[1.0, ");
        let err = parse(&four, "s.toml").unwrap_err().to_string();
        assert!(
            err.starts_with(&format!("s.toml:{line}:{column}: [right] hip_in_pelvis")),
            "{err}"
        );
        // A knee spline's y values, one short: at its `y`.
        let start = good.find("[left.knee_ty]").unwrap();
        let y = start + good[start..].find("y = [").unwrap();
        let comma = y + good[y..].find(", ").unwrap();
        let short = format!("{}{}", &good[..y + 5], &good[comma + 2..]);
        let line = short[..y].matches('\n').count() + 1;
        let column = y - short[..y].rfind('\n').map_or(0, |n| n + 1) + 1 + "y = ".len();
        let err = parse(&short, "s.toml").unwrap_err().to_string();
        assert!(
            err.starts_with(&format!("s.toml:{line}:{column}: [left.knee_ty]")),
            "{err}"
        );
    }

    #[test]
    fn bad_files_are_errors_that_name_the_problem() {
        let good = to_toml(&Gait2392Geometry::generic(), &[]);
        for (text, needle) in [
            (
                good.replace("mtp_axis", "mtp_axes"),
                "unknown field `mtp_axes`",
            ),
            (
                good.replacen(
                    "ankle_axis = [-0.10501355, -0.17402245, 0.97912632]",
                    "ankle_axis = [0.0, 0.0, 0.0]",
                    1,
                ),
                "s.toml: model rejected by the kernel: joint 3 has a zero",
            ),
            (
                good.replacen("x = [-2.0944, ", "x = [", 1),
                "11 x values but 12 y values",
            ),
            (
                good.replacen("hip_in_pelvis = [", "hip_in_pelvis = [1.0, ", 1),
                "[right] hip_in_pelvis: expected 3 numbers, found 4",
            ),
            (good.replacen("mtp_axis = [", "mtp_axis = \"", 1), "s.toml:"),
        ] {
            let err = parse(&text, "s.toml").unwrap_err().to_string();
            assert!(err.contains(needle), "{needle}: {err}");
            assert!(!err.contains('\n'), "{err}");
        }
    }
}
