//! `--model hak|phak|gait2392|SUBJECT.toml`: which kernel model computes the points, and the
//! named points it gives for every row of a motion. All forward kinematics is done by
//! `qgait_kernel::models`; this module picks columns and names the results.

use std::path::Path;

use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::{Gait2392, Gait2392Geometry, Joint, Side, Vec3};

use crate::kinematics::{self, Evaluator, Model};
use crate::mot::{MotionTable, Warning};
use crate::subject;

/// A model chosen on the command line.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelSpec {
    /// HAK or PHAK with segment lengths.
    Stick(Model),
    /// gait2392's chain: the generic model, or a subject file.
    Gait2392 {
        /// The numbers.
        geometry: Box<Gait2392Geometry>,
        /// `gait2392`, or the subject file as given.
        name: String,
    },
}

impl ModelSpec {
    /// `hak`, `phak`, `gait2392`, the path of a `SUBJECT.toml` (read and checked here), or an
    /// OpenSim model `.osim` (its leg chain imported as `qgait model import` does).
    pub fn load(arg: &str) -> Result<Self, String> {
        Self::load_with_notes(arg).map(|(spec, _)| spec)
    }

    /// [`ModelSpec::load`], with the notes of an `.osim` import (where the toe tip came from).
    pub fn load_with_notes(arg: &str) -> Result<(Self, Vec<String>), String> {
        let path = Path::new(arg);
        let is_osim = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("osim"));
        Ok(match arg {
            "hak" => (Self::Stick(Model::Hak), Vec::new()),
            "phak" => (Self::Stick(Model::Phak), Vec::new()),
            "gait2392" => (
                Self::Gait2392 {
                    geometry: Box::new(Gait2392Geometry::generic()),
                    name: arg.to_string(),
                },
                Vec::new(),
            ),
            _ if is_osim => {
                let text =
                    std::fs::read_to_string(path).map_err(|e| format!("{arg}: cannot read: {e}"))?;
                let imported = crate::osim_import::import(&text, arg, None)?;
                // The first note says where it was imported from; the others are worth showing.
                let notes = imported.notes.into_iter().skip(1).collect();
                (
                    Self::Gait2392 {
                        geometry: Box::new(imported.geometry),
                        name: arg.to_string(),
                    },
                    notes,
                )
            }
            _ if arg.ends_with(".toml") || path.is_file() => (
                Self::Gait2392 {
                    geometry: Box::new(subject::read(path)?),
                    name: arg.to_string(),
                },
                Vec::new(),
            ),
            _ => {
                return Err(format!(
                    "unknown model `{arg}` (expected hak, phak, gait2392, a SUBJECT.toml file from `qgait model import`, or an OpenSim model .osim)"
                ))
            }
        })
    }
}

/// The 17 gait2392 coordinates (radians, [`COORDINATES`] order) of every row. The leg columns
/// of PHAK are required; the other 11 count as 0 with one warning each when absent.
pub fn gait2392_coordinates(table: &MotionTable) -> Result<(Vec<[f64; 17]>, Vec<Warning>), String> {
    kinematics::coordinate_rows(table, &COORDINATES)
}

/// Names of the points of [`PointTrack`]: `hip_r, knee_r, ankle_r, toe_r, hip_l, ..., toe_l`,
/// then with `extra` (gait2392 only) `subtalar_r, mtp_r, subtalar_l, mtp_l`.
pub fn point_names(extra: bool) -> Vec<String> {
    let mut names = Vec::new();
    for side in Side::ALL {
        for joint in Joint::ALL {
            names.push(format!("{}_{}", joint.name(), side.suffix()));
        }
    }
    if extra {
        for side in Side::ALL {
            for point in ["subtalar", "mtp"] {
                names.push(format!("{point}_{}", side.suffix()));
            }
        }
    }
    names
}

/// Named points of every row of a motion (metres; origin and axes as the model's CSV).
#[derive(Debug, Clone, PartialEq)]
pub struct PointTrack {
    /// Point names ([`point_names`]).
    pub names: Vec<String>,
    /// Time of each row (s).
    pub time: Vec<f64>,
    /// Per row, one position per name.
    pub rows: Vec<Vec<Vec3<f64>>>,
}

/// Computes the points of every row. `extra` adds subtalar and MTP (gait2392 models only; an
/// error otherwise). `anthropometry` is for HAK/PHAK only.
pub fn compute(
    model: &ModelSpec,
    table: &MotionTable,
    anthropometry: &Anthropometry<f64>,
    extra: bool,
    mut on_row: impl FnMut(),
) -> Result<(PointTrack, Vec<Warning>), String> {
    let rows = match model {
        ModelSpec::Stick(m) => {
            if extra {
                return Err(
                    "--points (subtalar and MTP) needs a gait2392 model (--model gait2392 or SUBJECT.toml)"
                        .into(),
                );
            }
            let (angles, warnings) = kinematics::stick_angles(table, *m)?;
            let evaluator = Evaluator::new(*m, anthropometry)?;
            let rows = angles
                .iter()
                .map(|a| {
                    on_row();
                    evaluator.pose(a).points().to_vec()
                })
                .collect();
            (rows, warnings)
        }
        ModelSpec::Gait2392 { geometry, name } => {
            let (q, warnings) = gait2392_coordinates(table)?;
            let chain = Gait2392::<f64>::new(geometry)
                .map_err(|e| format!("{name}: model rejected by the kernel: {e}"))?;
            let rows = q
                .iter()
                .map(|q| {
                    on_row();
                    let pose = chain.fk(q);
                    let mut p = pose.bilateral().points().to_vec();
                    if extra {
                        for side in Side::ALL {
                            p.push(pose.subtalar(side));
                            p.push(pose.mtp(side));
                        }
                    }
                    p
                })
                .collect();
            (rows, warnings)
        }
    };
    Ok((
        PointTrack {
            names: point_names(extra),
            time: table.time().to_vec(),
            rows: rows.0,
        },
        rows.1,
    ))
}

/// Writes a track as the `qgait fk` CSV: `time`, then `<name>_x,<name>_y,<name>_z` per point.
/// For the standard 8 points this is exactly [`crate::fk_csv::header`].
pub fn write_csv<W: std::io::Write + ?Sized>(
    w: &mut W,
    track: &PointTrack,
    mut on_row: impl FnMut(),
) -> std::io::Result<()> {
    let mut header = vec!["time".to_string()];
    for n in &track.names {
        for axis in ["x", "y", "z"] {
            header.push(format!("{n}_{axis}"));
        }
    }
    writeln!(w, "{}", header.join(","))?;
    for (t, row) in track.time.iter().zip(&track.rows) {
        write!(w, "{t}")?;
        for p in row {
            write!(w, ",{},{},{}", p.x, p.y, p.z)?;
        }
        w.write_all(b"\n")?;
        on_row();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_names_give_the_fk_header() {
        let track = PointTrack {
            names: point_names(false),
            time: vec![],
            rows: vec![],
        };
        let mut out = Vec::new();
        write_csv(&mut out, &track, || {}).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap().trim_end(),
            crate::fk_csv::header()
        );
        assert_eq!(
            point_names(true)[8..],
            ["subtalar_r", "mtp_r", "subtalar_l", "mtp_l"]
        );
    }

    #[test]
    fn model_names_and_errors() {
        assert_eq!(
            ModelSpec::load("hak").unwrap(),
            ModelSpec::Stick(Model::Hak)
        );
        assert!(matches!(
            ModelSpec::load("gait2392").unwrap(),
            ModelSpec::Gait2392 { .. }
        ));
        let e = ModelSpec::load("gait2354").unwrap_err();
        assert!(e.contains("unknown model `gait2354`"), "{e}");
        let e = ModelSpec::load("/nonexistent/s.toml").unwrap_err();
        assert!(e.contains("/nonexistent/s.toml: cannot read"), "{e}");
    }
}
