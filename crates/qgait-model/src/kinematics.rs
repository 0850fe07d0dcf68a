//! Motion table → kernel input → joint positions. All forward kinematics is done by
//! `qgait_kernel::models`; this module only picks the columns and converts degrees to radians.

use qgait_kernel::models::{Phak, PhakAngles};
use qgait_kernel::BilateralPose;

use crate::choice::Model;
use crate::coords::{KneeFlexion, Picker};
use crate::error::ModelError;
use qgait_opensim::diagnostics::Warning;
use qgait_opensim::mot::MotionTable;

/// The PHAK angles (radians) of every row of a motion. Missing pelvis columns count as 0 with a
/// warning; a missing leg column is an error that names the file and the columns.
pub fn phak_angles(
    table: &MotionTable,
) -> Result<(Vec<PhakAngles<f64>>, Vec<Warning>), ModelError> {
    let (rows, warnings) = coordinate_rows(
        table,
        &PhakAngles::<f64>::NAMES,
        KneeFlexion::Negative,
        [true; 8],
    )?;
    Ok((
        rows.into_iter().map(PhakAngles::from_array).collect(),
        warnings,
    ))
}

/// The coordinates HAK uses: the leg ones of [`PhakAngles::NAMES`].
pub const HAK_NAMES: [&str; 6] = [
    PhakAngles::<f64>::NAMES[2],
    PhakAngles::<f64>::NAMES[3],
    PhakAngles::<f64>::NAMES[4],
    PhakAngles::<f64>::NAMES[5],
    PhakAngles::<f64>::NAMES[6],
    PhakAngles::<f64>::NAMES[7],
];

/// The angles `model` (HAK or PHAK) uses (radians) of every row, as [`PhakAngles`]: for HAK
/// the pelvis columns are not read (0, no warning about them).
pub fn stick_angles(
    table: &MotionTable,
    model: &Model,
) -> Result<(Vec<PhakAngles<f64>>, Vec<Warning>), ModelError> {
    match model {
        Model::Hak { .. } => {
            let (rows, warnings) =
                coordinate_rows(table, &HAK_NAMES, KneeFlexion::Negative, [true; 6])?;
            Ok((rows.into_iter().map(hak_as_phak).collect(), warnings))
        }
        _ => phak_angles(table),
    }
}

/// HAK's six leg angles as [`PhakAngles`] with a level pelvis.
pub fn hak_as_phak(legs: [f64; 6]) -> PhakAngles<f64> {
    let mut all = [0.0; 8];
    all[2..].copy_from_slice(&legs);
    PhakAngles::from_array(all)
}

/// The coordinates `names` (radians, in that order) of every row of a motion, through
/// [`Picker`]: the PHAK leg columns ([`LEG_COLUMNS`](crate::coords::LEG_COLUMNS)) are required, any other missing
/// coordinate counts as 0 with one warning, and angles outside their range are reported; only
/// the names with `read` true are read ([`Picker::new`]).
pub fn coordinate_rows<const N: usize>(
    table: &MotionTable,
    names: &[&'static str; N],
    knee: KneeFlexion,
    read: [bool; N],
) -> Result<(Vec<[f64; N]>, Vec<Warning>), ModelError> {
    let (mut picker, mut warnings) = Picker::new(table.header(), names, knee, read)?;
    let rows = (0..table.rows())
        .map(|r| {
            picker.pick(
                |c| table.value(r, c),
                || match table.line(r) {
                    Some(line) => format!("line {line}"),
                    None => format!("row {}", r + 1),
                },
                |c| table.non_finite_at(r, c),
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    warnings.extend(picker.finish());
    Ok((rows, warnings))
}

/// Evaluates HAK or PHAK one set of angles at a time.
pub struct Evaluator {
    hak: bool,
    phak: Phak<f64>,
}

impl Evaluator {
    /// The kernel model of `model` (HAK or PHAK; `what` names the use in the error for a
    /// gait2392 model); an error if the kernel rejects its lengths.
    pub fn new(model: &Model, what: &'static str) -> Result<Self, ModelError> {
        let Some(lengths) = model.lengths() else {
            return Err(ModelError::StickOnly {
                what,
                name: model.name().to_string(),
            });
        };
        Ok(Self {
            hak: matches!(model, Model::Hak { .. }),
            phak: Phak::new(&lengths).map_err(|error| ModelError::Rejected {
                name: model.name().to_string(),
                error,
            })?,
        })
    }

    /// Joint positions (metres) for one set of angles (radians).
    pub fn pose(&self, a: &PhakAngles<f64>) -> BilateralPose<f64> {
        if self.hak {
            self.phak.fk_hak(a)
        } else {
            self.phak.fk(a)
        }
    }
}

/// Angles at `percent` of the cycle, linearly interpolated between the rows around it
/// (`percent_of_rows` increasing, as from [`MotionTable::percent_of_cycle`]).
pub fn angles_at(
    percent_of_rows: &[f64],
    angles: &[PhakAngles<f64>],
    percent: f64,
) -> PhakAngles<f64> {
    let n = percent_of_rows.len();
    let i = percent_of_rows
        .partition_point(|&p| p <= percent)
        .clamp(1, n.max(2) - 1);
    if n < 2 {
        return angles[0];
    }
    let (p0, p1) = (percent_of_rows[i - 1], percent_of_rows[i]);
    let w = ((percent - p0) / (p1 - p0)).clamp(0.0, 1.0);
    let (a0, a1) = (angles[i - 1].to_array(), angles[i].to_array());
    let mut out = [0.0; 8];
    for k in 0..8 {
        out[k] = a0[k] + w * (a1[k] - a0[k]);
    }
    PhakAngles::from_array(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angles(v: f64) -> PhakAngles<f64> {
        PhakAngles::from_array([v, -v, 2.0 * v, v, v, v, v, 3.0 * v])
    }

    #[test]
    fn angles_at_interpolates_between_rows_and_clamps_at_the_ends() {
        let percent = [0.0, 50.0, 100.0];
        let rows = [angles(0.0), angles(1.0), angles(3.0)];
        assert_eq!(angles_at(&percent, &rows, 0.0), angles(0.0));
        assert_eq!(angles_at(&percent, &rows, 25.0), angles(0.5));
        assert_eq!(angles_at(&percent, &rows, 50.0), angles(1.0));
        assert_eq!(angles_at(&percent, &rows, 75.0), angles(2.0));
        assert_eq!(angles_at(&percent, &rows, 100.0), angles(3.0));
        assert_eq!(angles_at(&percent, &rows, 120.0), angles(3.0));
        assert_eq!(angles_at(&[0.0], &[angles(4.0)], 60.0), angles(4.0));
    }

    #[test]
    fn columns_map_to_the_kernel_order_in_radians() {
        let labels = [
            "time",
            "ankle_angle_l",
            "pelvis_list",
            "hip_flexion_r",
            "knee_angle_r",
            "ankle_angle_r",
        ]
        .into_iter()
        .chain(["hip_flexion_l", "knee_angle_l", "pelvis_rotation"])
        .map(String::from)
        .collect();
        let cols = (0..9)
            .map(|i| vec![i as f64 * 10.0, i as f64 * 10.0 + 1.0])
            .collect();
        let table = MotionTable::new("t", "t.mot", true, labels, cols).unwrap();
        let (a, w) = phak_angles(&table).unwrap();
        // Knees at 40 and 70 degrees, ankles at 50 and 10, pelvis rotation 80: out of range
        // only where the ranges say so (knee -120..10, ankle -40..30, each ± 10).
        let out: Vec<&str> = w
            .iter()
            .map(|w| w.detail().split('`').nth(1).unwrap())
            .collect();
        assert_eq!(
            out,
            ["knee_angle_r", "ankle_angle_r", "knee_angle_l"],
            "{w:?}"
        );
        let deg: Vec<f64> = a[0]
            .to_array()
            .iter()
            .map(|r| r.to_degrees().round())
            .collect();
        // NAMES order: pelvis_rotation, pelvis_list, hip_r, knee_r, ankle_r, hip_l, knee_l, ankle_l.
        assert_eq!(PhakAngles::<f64>::NAMES[0], "pelvis_rotation");
        assert_eq!(deg, vec![80.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 10.0]);
    }
}
