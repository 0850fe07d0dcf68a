//! `--model hak|phak|gait2392|SUBJECT.toml`: which kernel model computes the points, and the
//! named points it gives for every row of a motion. All forward kinematics is done by
//! `qgait_kernel::models`; this module picks columns and names the results.

use std::path::Path;

use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::{Gait2392, Gait2392Geometry, Joint, PhakAngles, Side, Vec3};

use crate::model::coords::CoordRows;
use crate::model::kinematics::{self, Evaluator, Model};
use crate::model::subject;
use crate::motion::source::MotionRows;
use crate::opensim::mot::{MotionTable, Warning};

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
                let imported = crate::opensim::osim::import(&text, arg, None)?;
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

/// Names of the points a [`PointModel`] gives: `hip_r, knee_r, ankle_r, toe_r, hip_l, ..., toe_l`,
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

/// A model ready to evaluate rows: the kernel model of a [`ModelSpec`] and the points it gives
/// ([`point_names`]; metres, origin and axes as the model's CSV).
pub struct PointModel {
    kind: Kind,
    extra: bool,
}

enum Kind {
    Stick(Model, Box<Evaluator>),
    Gait2392(Box<Gait2392<f64>>),
}

impl PointModel {
    /// The model of `spec`. `extra` adds subtalar and MTP (gait2392 models only; an error
    /// otherwise). `anthropometry` is for HAK/PHAK only.
    pub fn new(
        spec: &ModelSpec,
        anthropometry: &Anthropometry<f64>,
        extra: bool,
    ) -> Result<Self, String> {
        let kind = match spec {
            ModelSpec::Stick(m) => {
                if extra {
                    return Err(
                        "--points (subtalar and MTP) needs a gait2392 model (--model gait2392, SUBJECT.toml or MODEL.osim)"
                            .into(),
                    );
                }
                Kind::Stick(*m, Box::new(Evaluator::new(*m, anthropometry)?))
            }
            ModelSpec::Gait2392 { geometry, name } => Kind::Gait2392(Box::new(
                Gait2392::<f64>::new(geometry)
                    .map_err(|e| format!("{name}: model rejected by the kernel: {e}"))?,
            )),
        };
        Ok(Self { kind, extra })
    }

    /// The names of the points of each row.
    pub fn names(&self) -> Vec<String> {
        point_names(self.extra)
    }

    /// Evaluates every row of `rows` in turn, handing `each` the row's time and points; memory
    /// does not grow with the number of rows. `warn` gets the warnings about the columns before
    /// the first row; the warnings found while reading (ranges, row count) are returned.
    pub fn run(
        &self,
        rows: MotionRows,
        warn: &dyn Fn(Vec<Warning>),
        mut each: impl FnMut(f64, &[Vec3<f64>]) -> anyhow::Result<()>,
    ) -> anyhow::Result<Vec<Warning>> {
        let mut points = Vec::with_capacity(12);
        match &self.kind {
            Kind::Stick(Model::Hak, evaluator) => {
                drive(rows, &kinematics::HAK_NAMES, warn, |t, legs| {
                    let pose = evaluator.pose(&kinematics::hak_as_phak(legs));
                    each(t, &pose.points())
                })
            }
            Kind::Stick(Model::Phak, evaluator) => {
                drive(rows, &PhakAngles::<f64>::NAMES, warn, |t, a| {
                    each(t, &evaluator.pose(&PhakAngles::from_array(a)).points())
                })
            }
            Kind::Gait2392(chain) => drive(rows, &COORDINATES, warn, |t, q| {
                let pose = chain.fk(&q);
                points.clear();
                points.extend_from_slice(&pose.bilateral().points());
                if self.extra {
                    for side in Side::ALL {
                        points.push(pose.subtalar(side));
                        points.push(pose.mtp(side));
                    }
                }
                each(t, &points)
            }),
        }
    }
}

/// Reads every row of `rows` as the coordinates `names` and hands them to `each`.
pub fn drive<const N: usize>(
    rows: MotionRows,
    names: &[&'static str; N],
    warn: &dyn Fn(Vec<Warning>),
    mut each: impl FnMut(f64, [f64; N]) -> anyhow::Result<()>,
) -> anyhow::Result<Vec<Warning>> {
    let (mut coords, w) = CoordRows::new(rows, names).map_err(anyhow::Error::msg)?;
    warn(w);
    while let Some((t, q)) = coords.next_row()? {
        each(t, q)?;
    }
    Ok(coords.finish())
}

/// The header of the `qgait fk` CSV for these points: `time`, then `<name>_x,<name>_y,<name>_z`
/// per point. For the standard 8 points this is exactly [`crate::model::points_csv::header`].
pub fn csv_header(names: &[String]) -> String {
    let mut header = vec!["time".to_string()];
    for n in names {
        for axis in ["x", "y", "z"] {
            header.push(format!("{n}_{axis}"));
        }
    }
    header.join(",")
}

/// Writes one row of the `qgait fk` CSV.
pub fn write_csv_row<W: std::io::Write + ?Sized>(
    w: &mut W,
    time: f64,
    points: &[Vec3<f64>],
) -> std::io::Result<()> {
    write!(w, "{time}")?;
    for p in points {
        write!(w, ",{},{},{}", p.x, p.y, p.z)?;
    }
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_names_give_the_fk_header() {
        assert_eq!(
            csv_header(&point_names(false)),
            crate::model::points_csv::header()
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
