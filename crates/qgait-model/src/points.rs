//! The named points a [`Model`] gives for every row of a motion ([`PointModel`]) and their CSV
//! (`qgait fk`): one row per motion row, `time,hip_r_x,hip_r_y,hip_r_z,knee_r_x,...,toe_l_z`
//! (then `subtalar_r_x..z, mtp_r_x..z, ...` with `--points`), metres in ground axes, numbers
//! printed with Rust's `{}` for `f64` (the shortest text that reads back to the same value).
//! All forward kinematics is done by `qgait_kernel::models`; this module picks columns and
//! names the results.

use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::models::LowerLimb;
use qgait_kernel::{Gait2392, Joint, PhakAngles, Side, Vec3};

use crate::choice::Model;
use crate::coords::{CoordRows, KneeFlexion};
use crate::error::ModelError;
use crate::kinematics::{self, Evaluator};
use crate::motion::source::MotionRows;
use qgait_opensim::diagnostics::Warning;
use qgait_opensim::mot::MotionTable;

/// The 17 gait2392 coordinates (radians, [`COORDINATES`] order) of every row, for a model whose
/// knee flexes with `knee` angles and that reads the coordinates with `read` true. The leg
/// columns of PHAK are required; the other 11 count as 0 with one warning each when absent.
pub fn gait2392_coordinates(
    table: &MotionTable,
    knee: KneeFlexion,
    read: [bool; 17],
) -> Result<(Vec<[f64; 17]>, Vec<Warning>), ModelError> {
    kinematics::coordinate_rows(table, &COORDINATES, knee, read)
}

/// Forward kinematics of an imported model: the 12 points of
/// [`POINTS`](qgait_kernel::models::gait2392::POINTS) for the 17 coordinates of [`COORDINATES`].
pub type ImportedFk = Box<dyn Fn(&[f64; 17]) -> [Vec3<f64>; 12]>;

/// The kernel's evaluation of a gait2392-family or chain model (`None` for HAK and PHAK).
pub fn imported_fk(model: &Model) -> Result<Option<ImportedFk>, ModelError> {
    Ok(Some(match model {
        Model::Gait2392 { geometry, name } => {
            let g = Gait2392::<f64>::new(geometry).map_err(|error| ModelError::Rejected {
                name: name.clone(),
                error,
            })?;
            Box::new(move |q| g.chain().forward(q))
        }
        Model::Chain { chain, name } => {
            let c = chain_of(chain, name)?;
            Box::new(move |q| c.forward(q))
        }
        Model::Hak { .. } | Model::Phak { .. } => return Ok(None),
    }))
}

/// The kernel table of a chain model `name`.
fn chain_of(chain: &crate::chain::ChainModel, name: &str) -> Result<LowerLimb<f64>, ModelError> {
    chain.chain(name)
}

/// Names of the points a [`PointModel`] gives: `hip_r, knee_r, ankle_r, toe_r, hip_l, ..., toe_l`,
/// then with `extra` (gait2392 and chain models only) `subtalar_r, mtp_r, subtalar_l, mtp_l`.
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

/// A model ready to evaluate rows: the kernel model of a [`Model`] and the points it gives
/// ([`point_names`]; metres, origin and axes as the model's CSV).
pub struct PointModel {
    kind: Kind,
    extra: bool,
    /// The sign of the model's knee flexion (the motion's range check).
    knee: KneeFlexion,
    /// Which of the 17 coordinates the model reads.
    reads: [bool; 17],
}

enum Kind {
    Hak(Box<Evaluator>),
    Phak(Box<Evaluator>),
    Gait2392(Box<Gait2392<f64>>),
    Chain(Box<LowerLimb<f64>>),
}

/// Where [`point_names`]' points are in a [`LowerLimb`]'s output
/// ([`POINTS`](qgait_kernel::models::gait2392::POINTS) order): hip, knee, ankle, toe tip per side,
/// then subtalar and MTP per side.
pub const CHAIN_ORDER: [usize; 12] = [0, 1, 2, 5, 6, 7, 8, 11, 3, 4, 9, 10];

impl PointModel {
    /// The kernel model of `model`. `extra` adds subtalar and MTP (gait2392 models only; an
    /// error otherwise).
    pub fn new(model: &Model, extra: bool) -> Result<Self, ModelError> {
        let kind = match model {
            Model::Gait2392 { geometry, name } => Kind::Gait2392(Box::new(
                Gait2392::<f64>::new(geometry).map_err(|error| ModelError::Rejected {
                    name: name.clone(),
                    error,
                })?,
            )),
            Model::Chain { chain, name } => Kind::Chain(Box::new(chain_of(chain, name)?)),
            _ if extra => return Err(ModelError::PointsNeedGait2392),
            Model::Hak { .. } => Kind::Hak(Box::new(Evaluator::new(model, "fk")?)),
            Model::Phak { .. } => Kind::Phak(Box::new(Evaluator::new(model, "fk")?)),
        };
        let (knee, reads) = match &kind {
            Kind::Chain(chain) => (
                KneeFlexion::of(|q| chain.forward(q)),
                core::array::from_fn(|i| chain.reads(i)),
            ),
            _ => (KneeFlexion::Negative, [true; 17]),
        };
        Ok(Self {
            kind,
            extra,
            knee,
            reads,
        })
    }

    /// Which sign of `knee_angle` flexes the model's knee.
    pub fn knee(&self) -> KneeFlexion {
        self.knee
    }

    /// Which of the 17 coordinates ([`COORDINATES`] order) the model reads: all but an
    /// imported chain's locked or coupled ones ([`CustomChain::reads`](qgait_kernel::models::CustomChain::reads)).
    pub fn reads(&self) -> [bool; 17] {
        self.reads
    }

    /// The names of the points of each row.
    pub fn names(&self) -> Vec<String> {
        point_names(self.extra)
    }

    /// Evaluates every row of `rows` in turn, handing `each` the row's time and points; memory
    /// does not grow with the number of rows. `warn` gets the warnings about the columns before
    /// the first row; the warnings found while reading (ranges, row count) are returned. An
    /// error of `each` ends the run and is returned; so is the motion's or the model's, as `E`.
    pub fn run<E: From<ModelError>>(
        &self,
        rows: MotionRows,
        warn: &dyn Fn(Vec<Warning>),
        mut each: impl FnMut(f64, &[Vec3<f64>]) -> Result<(), E>,
    ) -> Result<Vec<Warning>, E> {
        let mut points = Vec::with_capacity(12);
        match &self.kind {
            Kind::Hak(evaluator) => {
                drive(rows, &kinematics::HAK_NAMES, self.knee, warn, |t, legs| {
                    let pose = evaluator.pose(&kinematics::hak_as_phak(legs));
                    each(t, &pose.points())
                })
            }
            Kind::Phak(evaluator) => {
                drive(rows, &PhakAngles::<f64>::NAMES, self.knee, warn, |t, a| {
                    each(t, &evaluator.pose(&PhakAngles::from_array(a)).points())
                })
            }
            Kind::Gait2392(chain) => drive(rows, &COORDINATES, self.knee, warn, |t, q| {
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
            Kind::Chain(chain) => {
                drive_reading(rows, &COORDINATES, self.knee, self.reads, warn, |t, q| {
                    let all = chain.forward(&q);
                    let n = if self.extra { 12 } else { 8 };
                    points.clear();
                    points.extend(CHAIN_ORDER[..n].iter().map(|&i| all[i]));
                    each(t, &points)
                })
            }
        }
    }
}

/// Reads every row of `rows` as the coordinates `names` of a model whose knee flexes with
/// `knee` angles and hands them to `each`.
pub fn drive<const N: usize, E: From<ModelError>>(
    rows: MotionRows,
    names: &[&'static str; N],
    knee: KneeFlexion,
    warn: &dyn Fn(Vec<Warning>),
    each: impl FnMut(f64, [f64; N]) -> Result<(), E>,
) -> Result<Vec<Warning>, E> {
    drive_reading(rows, names, knee, [true; N], warn, each)
}

/// [`drive`] for a model that reads only the names with `read` true
/// ([`Picker::new`](crate::coords::Picker::new)).
fn drive_reading<const N: usize, E: From<ModelError>>(
    rows: MotionRows,
    names: &[&'static str; N],
    knee: KneeFlexion,
    read: [bool; N],
    warn: &dyn Fn(Vec<Warning>),
    mut each: impl FnMut(f64, [f64; N]) -> Result<(), E>,
) -> Result<Vec<Warning>, E> {
    let (mut coords, w) = CoordRows::new(rows, names, knee, read)?;
    warn(w);
    while let Some((t, q)) = coords.next_row()? {
        each(t, q)?;
    }
    Ok(coords.finish())
}

/// The header of the `qgait fk` CSV for these points: `time`, then `<name>_x,<name>_y,<name>_z`
/// per point.
pub fn csv_header(names: &[String]) -> String {
    let mut header = vec!["time".to_string()];
    for n in names {
        for axis in ["x", "y", "z"] {
            header.push(format!("{n}_{axis}"));
        }
    }
    header.join(",")
}

/// A points CSV being written with the `csv` crate: the header ([`csv_header`], with `seq` in
/// front for a device's frames), then one row per call. Numbers are written with Rust's `{}`
/// for `f64`; an unknown time is an empty field.
pub struct PointsCsv<W: std::io::Write> {
    csv: csv::Writer<PassOn<W>>,
    field: String,
    seq: bool,
}

impl<W: std::io::Write> PointsCsv<W> {
    /// Writes the header for the points `names` (and a first `seq` column if `seq`).
    pub fn new(w: W, names: &[String], seq: bool) -> csv::Result<Self> {
        Self::with_axes(w, names, seq, &["x", "y", "z"])
    }

    /// [`PointsCsv::new`] with the columns `<name>_<axis>` for each of `axes` per point (in
    /// groups of three per row value: `fk --derivatives` writes `x, y, z, vx, ..., az`).
    pub fn with_axes(w: W, names: &[String], seq: bool, axes: &[&str]) -> csv::Result<Self> {
        let mut csv = csv::WriterBuilder::new()
            .buffer_capacity(1 << 16)
            .from_writer(PassOn {
                w,
                flush: std::cell::Cell::new(false),
            });
        let seq_column = seq.then_some("seq".to_string());
        let header = std::iter::once("time".to_string()).chain(
            names
                .iter()
                .flat_map(|n| axes.iter().map(move |a| format!("{n}_{a}"))),
        );
        csv.write_record(seq_column.into_iter().chain(header))?;
        Ok(Self {
            csv,
            field: String::with_capacity(32),
            seq,
        })
    }

    fn number(&mut self, x: impl std::fmt::Display) -> csv::Result<()> {
        use std::fmt::Write as _;
        self.field.clear();
        let _ = write!(self.field, "{x}");
        self.csv.write_field(&self.field)
    }

    /// Writes one row: the sequence number (when the file has that column), the time, the points.
    pub fn row(
        &mut self,
        seq: u32,
        time: Option<f64>,
        points: impl IntoIterator<Item = [f64; 3]>,
    ) -> csv::Result<()> {
        if self.seq {
            self.number(seq)?;
        }
        match time {
            Some(t) => self.number(t)?,
            None => self.csv.write_field("")?,
        }
        for p in points {
            for x in p {
                self.number(x)?;
            }
        }
        self.csv.write_record(None::<&[u8]>)
    }

    /// Passes what is buffered on to the writer (which the caller flushes).
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.csv.flush()
    }

    /// Passes what is buffered on to the writer and flushes the writer.
    pub fn flush_through(&mut self) -> std::io::Result<()> {
        self.csv.get_ref().flush.set(true);
        let flushed = self.csv.flush();
        self.csv.get_ref().flush.set(false);
        flushed
    }
}

/// The writer under a [`PointsCsv`]: bytes are passed on, flushing is left to the owner of the
/// writer (the `csv` writer flushes its writer when dropped, which would push an unfinished
/// output through when a row fails), except in [`PointsCsv::flush_through`].
struct PassOn<W> {
    w: W,
    flush: std::cell::Cell<bool>,
}

impl<W: std::io::Write> std::io::Write for PassOn<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.w.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.flush.get() {
            self.w.flush()
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_numbers_as_rust_prints_them_and_an_unknown_time_is_empty() {
        let names = vec!["hip_r".to_string()];
        let mut out = Vec::new();
        let mut w = PointsCsv::new(&mut out, &names, true).unwrap();
        w.row(7, Some(0.1), [[1e-7, -0.5, 3.0]]).unwrap();
        w.row(8, None, [[0.0, 1.0, f64::NAN]]).unwrap();
        w.flush().unwrap();
        drop(w);
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "seq,time,hip_r_x,hip_r_y,hip_r_z\n7,0.1,0.0000001,-0.5,3\n8,,0,1,NaN\n"
        );
    }

    #[test]
    fn the_standard_header_and_the_extra_points() {
        assert!(
            csv_header(&point_names(false)).starts_with("time,hip_r_x,hip_r_y,hip_r_z,knee_r_x,")
        );
        assert!(csv_header(&point_names(false)).ends_with(",toe_l_x,toe_l_y,toe_l_z"));
        assert_eq!(
            point_names(true)[8..],
            ["subtalar_r", "mtp_r", "subtalar_l", "mtp_l"]
        );
    }

    /// Counts its flushes and keeps what it was given.
    #[derive(Default)]
    struct Flushes(Vec<u8>, usize);

    impl std::io::Write for Flushes {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.extend_from_slice(buf);
            Ok(buf.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            self.1 += 1;
            Ok(())
        }
    }

    #[test]
    fn only_flush_through_flushes_the_writer() {
        let mut out = Flushes::default();
        let mut w = PointsCsv::new(&mut out, &["toe_l".to_string()], false).unwrap();
        w.row(0, Some(1.0), [[0.0; 3]]).unwrap();
        w.flush().unwrap();
        w.row(0, Some(2.0), [[0.0; 3]]).unwrap();
        w.flush_through().unwrap();
        drop(w);
        assert_eq!(out.1, 1);
        assert_eq!(
            String::from_utf8(out.0).unwrap(),
            "time,toe_l_x,toe_l_y,toe_l_z\n1,0,0,0\n2,0,0,0\n"
        );
    }
}
