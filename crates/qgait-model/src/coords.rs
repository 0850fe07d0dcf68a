//! The coordinates a model needs, picked from a motion's columns row by row: the one place that
//! maps labels to a model's inputs, converts degrees to radians, refuses what the model cannot
//! use (a missing leg column, a needed column that appears twice, a `nan` in a needed column)
//! and checks every angle against its physiological range
//! ([`qgait_kernel::models::ranges`]).
//!
//! Range check: an angle outside its range (widened by the kernel's margin) is used as it is and
//! reported once per column at the end (the knee's range mirrored for a model whose knee flexes
//! with positive angles, [`KneeFlexion::Positive`]: Rajagopal's), with the number of such values and the first one (file
//! and line). When a file in radians has values that would all be in range read as degrees, the
//! warning says so: OpenSim's CMC and RRA write `Kinematics_q.sto` in degrees under
//! `inDegrees=no`, and such a file otherwise gives a knee above the hip.

use qgait_kernel::models::gait2392::COORDINATES as GAIT2392_COORDINATES;
use qgait_kernel::models::ranges;

use crate::error::ModelError;
use crate::motion::source::MotionRows;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::mot::{Header, NonFinite};

/// Which sign of `knee_angle` flexes the knee in the model a motion is read for (the kernel's).
pub use qgait_kernel::models::ranges::KneeFlexion;

/// Per picked column: how its values compare with the range.
#[derive(Debug, Clone, Default)]
struct RangeCheck {
    /// Values read.
    n: usize,
    /// Values outside the range (after conversion to radians).
    out: usize,
    /// The first value outside (radians) and where.
    first_out: Option<(f64, String)>,
    /// Values outside the range when read as degrees (for files in radians).
    out_as_degrees: usize,
}

/// Values of an unread coordinate this close to 0 (radians, 0.0057°) are not worth a warning:
/// OpenSense writes a locked coordinate's 0 with noise of about 1e-5 rad.
/// Coordinates that are required: the leg ones of [`PhakAngles::NAMES`](qgait_kernel::models::PhakAngles::NAMES) (after the pelvis).
pub const LEG_COLUMNS: &[&str] = qgait_kernel::models::PhakAngles::<f64>::NAMES.split_at(2).1;

const UNREAD_NOISE_RAD: f64 = 1e-4;

/// Picks `N` named coordinates (radians) from each row of a motion.
#[derive(Debug, Clone)]
pub struct Picker<const N: usize> {
    source: String,
    scale: f64,
    in_degrees: bool,
    names: [&'static str; N],
    /// Column of each name (`None`: absent, taken as 0).
    columns: [Option<usize>; N],
    /// Kernel coordinate index of each name, for the range check.
    range_index: [Option<usize>; N],
    /// The knee flexion of the model: its knee's range is mirrored for
    /// [`KneeFlexion::Positive`].
    knee: KneeFlexion,
    /// Whether the motion is in gait2392's signs ([`Header::gait2392_signs`]): a mirrored knee's
    /// values are then negated into the model's.
    gait2392_signs: bool,
    checks: Vec<RangeCheck>,
    /// Per name the model does not read (a locked or coupled coordinate of an imported
    /// chain): its column, if the motion has one.
    unread: [Option<usize>; N],
    /// Per name, the first value in its unread column beyond [`UNREAD_NOISE_RAD`] (radians)
    /// and where.
    unread_first: Vec<Option<(f64, String)>>,
    /// gait2392 coordinates the motion has and `names` lacks (PHAK has no pelvis list or
    /// rotation, no hip adduction or rotation): name, column, the first value beyond
    /// [`UNREAD_NOISE_RAD`] (radians) and where.
    unmodelled: Vec<(&'static str, usize, Option<FirstValue>)>,
}

/// A column's first value beyond the noise (radians) and where it is.
type FirstValue = (f64, String);

impl<const N: usize> Picker<N> {
    /// Maps `names` to the columns of `header`. The PHAK leg columns ([`LEG_COLUMNS`]) are
    /// required (an error naming the file and the columns); any other missing name counts as 0
    /// with one warning; a needed label that names two columns is an error. `knee`: the sign of
    /// flexion of the model's `knee_angle` (the range checked). Only the names with `read`
    /// true are read: the others are taken as 0 without a warning when absent, and a column of
    /// one with a value other than 0 (beyond the noise `UNREAD_NOISE_RAD`) gets one warning at
    /// the end ([`finish`](Self::finish)): the model ignores it.
    pub fn new(
        header: &Header,
        names: &[&'static str; N],
        knee: KneeFlexion,
        read: [bool; N],
    ) -> Result<(Self, Vec<Warning>), ModelError> {
        // A leg column is required only when the model reads it.
        let unread_name = |c: &str| names.iter().zip(read).any(|(n, r)| *n == c && !r);
        let missing: Vec<&'static str> = LEG_COLUMNS
            .iter()
            .copied()
            .filter(|c| header.index_of(c).is_none() && !unread_name(c))
            .collect();
        if !missing.is_empty() {
            return Err(ModelError::MissingColumns {
                at: header.labels_location(),
                columns: missing,
            });
        }
        let mut warnings = Vec::new();
        for (name, _) in names.iter().zip(read).filter(|(_, r)| *r) {
            if header.is_duplicated(name) {
                return Err(ModelError::AmbiguousColumn {
                    at: header.labels_location(),
                    name,
                });
            }
        }
        let unread: [Option<usize>; N] =
            core::array::from_fn(|k| header.index_of(names[k]).filter(|_| !read[k]));
        let columns: [Option<usize>; N] = core::array::from_fn(|k| {
            let name = names[k];
            if !read[k] {
                return None;
            }
            let c = header.index_of(name);
            if c.is_none() {
                warnings.push(Warning::MissingDefaulted(WarningText {
                    at: Some(Location::file(header.source.clone())),
                    detail: format!("no `{name}` column; taken as 0"),
                }));
            }
            c
        });
        let unmodelled = GAIT2392_COORDINATES
            .iter()
            .filter(|c| !names.contains(c))
            .filter_map(|c| Some((*c, header.index_of(c)?, None)))
            .collect();
        let scale = if header.in_degrees {
            std::f64::consts::PI / 180.0
        } else {
            1.0
        };
        Ok((
            Self {
                source: header.source.clone(),
                scale,
                in_degrees: header.in_degrees,
                names: *names,
                columns,
                range_index: names.map(ranges::index),
                knee,
                gait2392_signs: header.gait2392_signs,
                checks: vec![RangeCheck::default(); N],
                unread,
                unread_first: vec![None; N],
                unmodelled,
            },
            warnings,
        ))
    }

    /// The coordinates of one row: `value(c)` is the value of column `c` as stored; `at` says
    /// where the row is (`line N` or `row N`); `non_finite(c)` where a non-finite value of
    /// column `c` was read. A non-finite needed value is an error naming file, line and column.
    pub fn pick<'a>(
        &mut self,
        value: impl Fn(usize) -> f64,
        at: impl Fn() -> String,
        non_finite: impl Fn(usize) -> Option<&'a NonFinite>,
    ) -> Result<[f64; N], ModelError> {
        let mut out = [0.0; N];
        for (c, first) in self.unread.iter().zip(&mut self.unread_first) {
            let Some(c) = *c else { continue };
            let v = value(c) * self.scale;
            if first.is_none() && v.abs() > UNREAD_NOISE_RAD && v.is_finite() {
                *first = Some((v, at()));
            }
        }
        for (_, c, first) in &mut self.unmodelled {
            let v = value(*c) * self.scale;
            if first.is_none() && v.abs() > UNREAD_NOISE_RAD && v.is_finite() {
                *first = Some((v, at()));
            }
        }
        for (k, slot) in out.iter_mut().enumerate() {
            let Some(c) = self.columns[k] else { continue };
            let raw = value(c);
            if !raw.is_finite() {
                let name = self.names[k];
                return Err(match non_finite(c) {
                    Some(nf) => ModelError::NotFinite {
                        at: format!("{}:{}:{}", self.source, nf.line, nf.column),
                        text: nf.text.clone(),
                        name,
                    },
                    None => ModelError::NotFinite {
                        at: format!("{}: {}", self.source, at()),
                        text: raw.to_string(),
                        name,
                    },
                });
            }
            // A knee of a motion in gait2392's signs, for a model whose knee flexes with
            // positive angles, is turned into the model's signs.
            let flip = if self.mirrored(k) && self.gait2392_signs {
                -1.0
            } else {
                1.0
            };
            let v = raw * self.scale * flip;
            *slot = v;
            if let Some(i) = self.range_index[k] {
                let check = &mut self.checks[k];
                check.n += 1;
                if !ranges::in_model_range(i, v, self.knee) {
                    check.out += 1;
                    if check.first_out.is_none() {
                        check.first_out = Some((v, at()));
                    }
                }
                if !self.in_degrees
                    && !ranges::in_model_range(i, flip * raw.to_radians(), self.knee)
                {
                    check.out_as_degrees += 1;
                }
            }
        }
        Ok(out)
    }

    /// Whether name `k`'s range is mirrored (a knee of [`KneeFlexion::Positive`]).
    fn mirrored(&self, k: usize) -> bool {
        self.range_index[k].is_some_and(|i| self.knee.mirrors(i))
    }

    /// The range warnings: one per column with values outside its range.
    pub fn finish(self) -> Vec<Warning> {
        let mut warnings = Vec::new();
        let mut look_like_degrees = Vec::new();
        for k in 0..N {
            let check = &self.checks[k];
            let (Some(i), Some((first, at))) = (self.range_index[k], &check.first_out) else {
                continue;
            };
            let (lo, hi) = match ranges::RANGES_DEG[i] {
                (lo, hi) if self.mirrored(k) => (-hi, -lo),
                range => range,
            };
            warnings.push(Warning::OutOfRange(WarningText {
 at: Some(Location::file(self.source.clone())),
 detail: format!("column `{}`: {} of {} values outside its range {lo}..{hi}° (± {}°), the first {}° at {at}", self.names[k], check.out, check.n, ranges::MARGIN_DEG, show_degrees(first.to_degrees())),
}));
            if !self.in_degrees && check.out_as_degrees == 0 {
                look_like_degrees.push(format!("`{}`", self.names[k]));
            }
        }
        for (name, first) in self.names.iter().zip(&self.unread_first) {
            if let Some((first, at)) = first {
                warnings.push(Warning::Ignored(WarningText {
 at: Some(Location::file(self.source.clone())),
 detail: format!("column `{name}` ignored: the model does not move with it (locked, or coupled to another coordinate), so its values are not used (the first other than 0: {}° at {at})", show_degrees(first.to_degrees())),
}));
            }
        }
        let moved: Vec<String> = self
            .unmodelled
            .iter()
            .filter_map(|(name, _, first)| {
                let (v, at) = first.as_ref()?;
                Some(format!(
                    "`{name}` ({}° at {at})",
                    show_degrees(v.to_degrees())
                ))
            })
            .collect();
        if !moved.is_empty() {
            warnings.push(Warning::Ignored(WarningText {
 at: Some(Location::file(self.source.clone())),
 detail: format!("the motion moves {}, which the model does not have: they are ignored, so its joint centres differ from those of the motion's own model (gait2392 has them: `--model gait2392`, or the subject's scaled .osim)", moved.join(", ")),
}));
        }
        if !look_like_degrees.is_empty() {
            warnings.push(Warning::UnitsAssumed(WarningText {
 at: Some(Location::file(self.source.clone())),
 detail: format!("the angles are read as radians (the header does not say inDegrees=yes), but {} would all be in range read as degrees: if the file is in degrees (as OpenSim's CMC and RRA write Kinematics_q.sto), set inDegrees=yes in its header", look_like_degrees.join(", ")),
}));
        }
        warnings
    }
}

/// The coordinates `N` names (radians) of each row of a motion read as it goes: a
/// [`MotionRows`] through a [`Picker`], in memory independent of the number of rows.
pub struct CoordRows<const N: usize> {
    rows: MotionRows,
    picker: Picker<N>,
    warnings: Vec<Warning>,
}

impl<const N: usize> CoordRows<N> {
    /// Maps `names` to the columns of `rows` (errors and warnings as [`Picker::new`]).
    pub fn new(
        rows: MotionRows,
        names: &[&'static str; N],
        knee: KneeFlexion,
        read: [bool; N],
    ) -> Result<(Self, Vec<Warning>), ModelError> {
        let (picker, warnings) = Picker::new(rows.header(), names, knee, read)?;
        Ok((
            Self {
                rows,
                picker,
                warnings: Vec::new(),
            },
            warnings,
        ))
    }

    /// The time and the coordinates of the next row; `None` after the last.
    pub fn next_row(&mut self) -> Result<Option<(f64, [f64; N])>, ModelError> {
        let next = self.rows.next_row();
        self.warnings.extend(self.rows.take_warnings());
        let Some((row, at)) = next? else {
            return Ok(None);
        };
        let q = self.picker.pick(
            |c| row.values[c],
            || at.to_string(),
            |c| {
                row.non_finite
                    .iter()
                    .find(|(k, _)| *k == c)
                    .map(|(_, nf)| nf)
            },
        )?;
        Ok(Some((row.values[0], q)))
    }

    /// The warnings found while reading (repeated times, the declared row count) and the range
    /// warnings, once every row has been read.
    pub fn finish(mut self) -> Vec<Warning> {
        self.warnings.extend(self.rows.take_warnings());
        self.warnings.extend(self.picker.finish());
        self.warnings
    }
}

/// An angle in degrees for a message: two decimals, or exponent notation when huge.
fn show_degrees(d: f64) -> String {
    if d.abs() < 1e6 {
        format!("{d:.2}")
    } else {
        format!("{d:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_opensim::mot::MotionTable;

    /// Whether a warning of `w` says `what` (after its location).
    fn warns_about(w: &[Warning], what: &str) -> bool {
        w.iter().any(|w| w.detail().contains(what))
    }

    const NAMES: [&str; 8] = qgait_kernel::PhakAngles::<f64>::NAMES;

    fn table(text: &str) -> MotionTable {
        MotionTable::parse(text, "m.mot").unwrap().0
    }

    fn pick_all(t: &MotionTable) -> Result<(Vec<[f64; 8]>, Vec<Warning>), ModelError> {
        pick_for(t, KneeFlexion::Negative)
    }

    fn pick_for(
        t: &MotionTable,
        knee: KneeFlexion,
    ) -> Result<(Vec<[f64; 8]>, Vec<Warning>), ModelError> {
        let (mut p, mut w) = Picker::new(t.header(), &NAMES, knee, [true; 8])?;
        let mut rows = Vec::new();
        for r in 0..t.rows() {
            rows.push(p.pick(
                |c| t.value(r, c),
                || format!("line {}", t.line(r).unwrap()),
                |c| t.non_finite(c),
            )?);
        }
        w.extend(p.finish());
        Ok((rows, w))
    }

    const HEAD: &str = "m\nversion=1\ninDegrees=yes\nendheader\n";
    const LEGS: &str =
        "hip_flexion_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\tknee_angle_l\tankle_angle_l";

    #[test]
    fn angles_out_of_range_are_warned_once_per_column_with_the_first_line() {
        let text = format!(
            "{HEAD}time\t{LEGS}\n0\t10\t-200\t0\t10\t-20\t0\n1\t10\t1e300\t0\t10\t-20\t0\n2\t10\t-30\t0\t10\t-20\t0\n"
        );
        let (_, w) = pick_all(&table(&text)).unwrap();
        let knee: Vec<&Warning> = w
            .iter()
            .filter(|w| w.detail().contains("knee_angle_r"))
            .collect();
        assert_eq!(knee.len(), 1, "{w:?}");
        assert!(
            knee[0]
                .to_string()
                .contains("2 of 3 values outside its range -120..10°")
                && knee[0].to_string().contains("the first -200.00° at line 6"),
            "{}",
            knee[0]
        );
        assert!(!warns_about(&w, "knee_angle_l"), "{w:?}");
        assert!(!warns_about(&w, "look"), "{w:?}");
    }

    #[test]
    fn a_knee_flexing_with_positive_angles_is_checked_against_the_mirrored_range() {
        // Rajagopal's knee: 60° of flexion is +60; -60 would be hyperextension.
        let text =
            format!("{HEAD}time\t{LEGS}\n0\t10\t60\t0\t10\t-60\t0\n1\t10\t5\t0\t10\t-5\t0\n");
        let (rows, w) = pick_for(&table(&text), KneeFlexion::Positive).unwrap();
        // Values as read: only the check is mirrored.
        assert!((rows[0][3] - 60f64.to_radians()).abs() < 1e-15);
        assert!(!warns_about(&w, "knee_angle_r"), "{w:?}");
        let left: Vec<&Warning> = w
            .iter()
            .filter(|w| w.detail().contains("knee_angle_l"))
            .collect();
        assert_eq!(left.len(), 1, "{w:?}");
        assert!(
            left[0]
                .to_string()
                .contains("1 of 2 values outside its range -10..120°")
                && left[0].to_string().contains("the first -60.00° at line 6"),
            "{}",
            left[0]
        );
        // The same file for gait2392 the other way round.
        let (_, w) = pick_all(&table(&text)).unwrap();
        assert!(warns_about(&w, "knee_angle_r"), "{w:?}");
        assert!(!warns_about(&w, "knee_angle_l"), "{w:?}");
        // A motion in gait2392's signs (a `builtin:`) for that model: its knee is turned into
        // the model's signs, and checked as gait2392's.
        let (rows, w) = pick_for(&table(&text).in_gait2392_signs(), KneeFlexion::Positive).unwrap();
        assert!((rows[0][3] + 60f64.to_radians()).abs() < 1e-15);
        assert!((rows[0][6] - 60f64.to_radians()).abs() < 1e-15);
        assert!(warns_about(&w, "knee_angle_r"), "{w:?}");
        assert!(!warns_about(&w, "knee_angle_l"), "{w:?}");
    }

    #[test]
    fn degrees_under_indegrees_no_are_named_as_such() {
        let text = format!(
            "m\nversion=1\ninDegrees=no\nendheader\ntime\t{LEGS}\n0\t30\t-60\t10\t-5\t-20\t0\n1\t25\t-50\t5\t0\t-10\t2\n"
        );
        let (_, w) = pick_all(&table(&text)).unwrap();
        let hint = w.last().unwrap();
        assert!(
            hint.to_string().contains("does not say inDegrees=yes")
                && hint.to_string().contains("`knee_angle_r`"),
            "{w:?}"
        );
        assert!(w
            .iter()
            .any(|w| w.detail().contains("column `hip_flexion_r`: 2 of 2")));
        // The same values in radians that are plausible give nothing.
        let ok = format!(
            "m\nversion=1\ninDegrees=no\nendheader\ntime\t{LEGS}\n0\t0.3\t-0.6\t0.1\t-0.05\t-0.2\t0\n1\t0.25\t-0.5\t0.05\t0\t-0.1\t0.02\n"
        );
        let (_, w) = pick_all(&table(&ok)).unwrap();
        assert!(!warns_about(&w, "range"), "{w:?}");
    }

    #[test]
    fn nan_and_duplicates_matter_only_in_needed_columns() {
        let text = format!(
            "{HEAD}time\t{LEGS}\tpelvis_tx\tforce\tforce\n0\t10\t-20\t0\t10\t-20\t0\tnan\t1\t2\n1\t10\t-20\t0\t10\t-20\t0\t0.5\t1\t2\n"
        );
        let (rows, _) = pick_all(&table(&text)).unwrap();
        assert_eq!(rows.len(), 2);
        let bad = text.replacen("\t-20\t0\t10", "\tNaN\t0\t10", 1);
        let e = pick_all(&table(&bad)).unwrap_err();
        assert!(
            matches!(&e, ModelError::NotFinite { at, text, name: "knee_angle_r" } if at == "m.mot:6:6" && text == "NaN"),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "m.mot:6:6: value `NaN` in column `knee_angle_r` is not a finite number, and the model needs this column"
        );
        let dup = text.replace("\tforce\tforce", "\tforce\tknee_angle_l");
        let e = pick_all(&table(&dup)).unwrap_err();
        assert!(
            matches!(&e, ModelError::AmbiguousColumn { at, name: "knee_angle_l" } if at == "m.mot:5"),
            "{e:?}"
        );
    }
}
