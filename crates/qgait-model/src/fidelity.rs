//! `qgait fidelity`: how far the paper's 8-DoF PHAK (with gait2392's segment lengths) is from
//! OpenSim's gait2392 chain on the same motion, and which of gait2392's features costs most.
//!
//! Both models are evaluated by the kernel on every row (gait2392: the generic geometry, the
//! motion's 17 coordinates, absent ones 0; PHAK: [`Anthropometry::gait2392`] and its 8
//! coordinates). Points: hip, knee, ankle, toe (gait2392: the toe tip) of each leg; deviation =
//! Euclidean distance in mm. Two comparisons:
//!
//! - **raw**: both in their own output frame (origin at the pelvis origin, ground axes). PHAK's
//!   hips are at (0, 0, ±w), gait2392's at (-0.0707, -0.0661, ±0.0835) in the pelvis frame, so
//!   this includes a constant ~97 mm hip offset.
//! - **hip-relative**: every point of a leg minus that leg's hip centre, in each model (so the
//!   hips agree by construction and only the leg below the hip is compared).
//!
//! Ablations switch one gait2392 feature off at a time (in the coordinates or the geometry) and
//! report the deviation from PHAK that remains, and the feature's own effect (full gait2392
//! versus gait2392 with that feature off). With all of them off gait2392 becomes PHAK, so the
//! last ablation must give ~0: a check of the whole comparison.

use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::models::gait2392::{Knots, COORDINATES};
use qgait_kernel::{Gait2392, Gait2392Geometry, Phak, PhakAngles, Quat, Spline, Vec3};

use crate::coords::KneeFlexion;
use crate::error::ModelError;
use crate::kinematics;
use crate::points::{gait2392_coordinates, point_names};
use qgait_kernel::models::ranges::KNEES;
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::mot::MotionTable;

/// One gait2392 feature that PHAK lacks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// Hip adduction and rotation (PHAK: flexion only).
    HipAdductionRotation,
    /// Pelvis tilt (PHAK: rotation and list only).
    PelvisTilt,
    /// Knee translation with knee angle (PHAK: a hinge).
    KneeTranslation,
    /// The oblique ankle axis (PHAK: +z).
    AnkleAxis,
    /// Pelvis order tilt, list, rotation (PHAK: rotation, then list).
    PelvisOrder,
    /// Hip centres behind and below the pelvis origin (PHAK: (0, 0, ±w)).
    HipCentres,
    /// Femur and foot directions (PHAK: straight segments along -y and +x).
    SegmentDirections,
}

impl Feature {
    /// All, in report order.
    pub const ALL: [Feature; 7] = [
        Feature::HipAdductionRotation,
        Feature::PelvisTilt,
        Feature::KneeTranslation,
        Feature::AnkleAxis,
        Feature::PelvisOrder,
        Feature::HipCentres,
        Feature::SegmentDirections,
    ];

    /// What switching it off does.
    pub fn off_description(self) -> &'static str {
        match self {
            Feature::HipAdductionRotation => "hip adduction and rotation set to 0",
            Feature::PelvisTilt => "pelvis tilt set to 0",
            Feature::KneeTranslation => "knee translation frozen at its knee_angle = 0 value",
            Feature::AnkleAxis => "ankle axis replaced by +z",
            Feature::PelvisOrder => "pelvis rotation applied before list (PHAK's order)",
            Feature::HipCentres => "hip centres moved to PHAK's (0, 0, ±0.0835)",
            Feature::SegmentDirections => {
                "femur straight down (knee at (0, -femur) at knee_angle = 0) and toe tip on the ankle's +x at PHAK's foot length"
            }
        }
    }
}

/// A warning when a motion's knee angles (`q`, read in gait2392's signs) are nearly all at
/// or above 0 and reach past 20°: flexion with positive angles, a motion in the signs of a
/// model whose knee flexes so (Rajagopal's, as OpenSense writes it), which `fidelity` reads as
/// hyperextension. (gait2392's knee hyperextends at most 10°.)
fn knees_flexing_positive(source: &str, q: &[[f64; 17]]) -> Option<Warning> {
    let values: Vec<f64> = q.iter().flat_map(|row| KNEES.map(|k| row[k])).collect();
    let at_or_above = values.iter().filter(|&&v| v >= 0.0).count();
    let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (10 * at_or_above >= 9 * values.len() && max > 20f64.to_radians()).then(|| {
        Warning::SignConvention(WarningText {
 at: Some(Location::file(source)),
 detail: format!("{at_or_above} of {} knee angles are 0 or more, up to {:.1}°: the knees flex with positive angles, as in Rajagopal's models; fidelity reads a motion in gait2392's signs (knee flexion < 0), so these knees are hyperextended here: give the motion with its knee angles negated", values.len(), max.to_degrees()),
})
    })
}

fn index(name: &str) -> usize {
    COORDINATES
        .iter()
        .position(|c| *c == name)
        .expect("a gait2392 coordinate")
}

fn spline_at_zero(k: &Knots) -> f64 {
    Spline::<f64>::new(&k.x[..k.n], &k.y[..k.n])
        .expect("generic knots are valid")
        .eval(0.0)
}

fn constant(v: f64) -> Knots {
    Knots::new(&[-1.0, 1.0], &[v, v])
}

fn shifted(k: &Knots, d: f64) -> Knots {
    let y: Vec<f64> = k.y[..k.n].iter().map(|v| v + d).collect();
    Knots::new(&k.x[..k.n], &y)
}

/// Tilt, list, rotation (body-fixed Z-X-Y) of the rotation `Rz(tilt) Ry(rotation) Rx(list)`:
/// gait2392's pelvis angles that give PHAK's rotation-then-list order.
fn pelvis_in_phak_order(tilt: f64, list: f64, rotation: f64) -> (f64, f64, f64) {
    let q = Quat::from_axis_angle(Vec3::unit_z(), tilt)
        * Quat::from_axis_angle(Vec3::unit_y(), rotation)
        * Quat::from_axis_angle(Vec3::unit_x(), list);
    let r = q.to_rotation_matrix();
    // Rz(a) Rx(b) Ry(c): r[2][1] = sin b, r[2][0] = -cos b sin c, r[2][2] = cos b cos c,
    // r[0][1] = -sin a cos b, r[1][1] = cos a cos b.
    let b = r[2][1].clamp(-1.0, 1.0).asin();
    let c = (-r[2][0]).atan2(r[2][2]);
    let a = (-r[0][1]).atan2(r[1][1]);
    (a, b, c)
}

/// gait2392 with `off` switched off: its geometry and coordinates.
fn ablate(
    off: &[Feature],
    q: &[[f64; 17]],
    phak: &Anthropometry<f64>,
) -> (Gait2392Geometry, Vec<[f64; 17]>) {
    let generic = Gait2392Geometry::generic();
    let mut g = generic;
    let mut q = q.to_vec();
    for f in off {
        for (leg, orig, side) in [
            (&mut g.right, &generic.right, phak.right),
            (&mut g.left, &generic.left, phak.left),
        ] {
            let sign = orig.hip_in_pelvis[2].signum();
            match f {
                Feature::KneeTranslation => {
                    // Commutes with SegmentDirections: a shift of a constant is a constant.
                    leg.knee_tx = constant(spline_at_zero(&leg.knee_tx));
                    leg.knee_ty = constant(spline_at_zero(&leg.knee_ty));
                }
                Feature::AnkleAxis => leg.ankle_axis = [0.0, 0.0, 1.0],
                Feature::HipCentres => {
                    leg.hip_in_pelvis = [0.0, 0.0, sign * side.pelvis_half_width]
                }
                Feature::SegmentDirections => {
                    leg.knee_tx = shifted(&leg.knee_tx, -spline_at_zero(&orig.knee_tx));
                    leg.knee_ty =
                        shifted(&leg.knee_ty, -side.femur - spline_at_zero(&orig.knee_ty));
                    leg.ankle_in_tibia = [0.0, -side.tibia, 0.0];
                    leg.subtalar_in_talus = [0.0; 3];
                    leg.mtp_in_calcn = [0.0; 3];
                    leg.toetip_in_toes = [side.foot, 0.0, 0.0];
                }
                _ => {}
            }
        }
        for row in q.iter_mut() {
            match f {
                Feature::HipAdductionRotation => {
                    for c in [
                        "hip_adduction_r",
                        "hip_rotation_r",
                        "hip_adduction_l",
                        "hip_rotation_l",
                    ] {
                        row[index(c)] = 0.0;
                    }
                }
                Feature::PelvisTilt => row[index("pelvis_tilt")] = 0.0,
                _ => {}
            }
        }
    }
    // The order change reads the (possibly zeroed) tilt, so it comes last.
    if off.contains(&Feature::PelvisOrder) {
        let (t, l, r) = (
            index("pelvis_tilt"),
            index("pelvis_list"),
            index("pelvis_rotation"),
        );
        for row in q.iter_mut() {
            (row[t], row[l], row[r]) = pelvis_in_phak_order(row[t], row[l], row[r]);
        }
    }
    (g, q)
}

/// Max and mean of a set of distances (metres in, mm out).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Stat {
    /// Largest (mm).
    pub max: f64,
    /// Mean (mm).
    pub mean: f64,
}

fn stat(d: impl Iterator<Item = f64>) -> Stat {
    let (mut max, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for v in d {
        max = max.max(v);
        sum += v;
        n += 1;
    }
    Stat {
        max: max * 1e3,
        mean: if n == 0 { 0.0 } else { sum / n as f64 * 1e3 },
    }
}

/// Per row, the 8 points (PHAK output order).
type Points = Vec<[Vec3<f64>; 8]>;

fn hip_relative(p: &[Vec3<f64>; 8]) -> [Vec3<f64>; 8] {
    core::array::from_fn(|k| p[k] - p[if k < 4 { 0 } else { 4 }])
}

/// Per point k, the distances over all rows.
fn distances(a: &Points, b: &Points, relative: bool) -> [Vec<f64>; 8] {
    core::array::from_fn(|k| {
        a.iter()
            .zip(b)
            .map(|(pa, pb)| {
                let (pa, pb) = if relative {
                    (hip_relative(pa), hip_relative(pb))
                } else {
                    (*pa, *pb)
                };
                Vec3::distance(pa[k], pb[k])
            })
            .collect()
    })
}

/// One ablation's numbers (all points and rows).
#[derive(Debug, Clone, PartialEq)]
pub struct AblationResult {
    /// The features switched off (empty: full gait2392).
    pub off: Vec<Feature>,
    /// Deviation from PHAK that remains, raw.
    pub raw: Stat,
    /// Deviation from PHAK that remains, hip-relative.
    pub relative: Stat,
    /// Full gait2392 versus this ablation (raw): how much the feature moves the points.
    pub own_effect: Stat,
}

/// Everything `qgait fidelity` reports for one motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Fidelity {
    /// The motion's label.
    pub label: String,
    /// Number of rows.
    pub rows: usize,
    /// Per point (`hip_r` ... `toe_l`): (name, raw, hip-relative).
    pub per_point: Vec<(String, Stat, Stat)>,
    /// Full gait2392, each feature off on its own, then all off.
    pub ablations: Vec<AblationResult>,
}

/// Compares PHAK with gait2392 on one motion.
pub fn analyse(label: &str, table: &MotionTable) -> Result<(Fidelity, Vec<Warning>), ModelError> {
    let (q, mut warnings) = gait2392_coordinates(table, KneeFlexion::Negative, [true; 17])?;
    warnings.extend(knees_flexing_positive(table.source(), &q));
    let (angles, w) = kinematics::phak_angles(table)?;
    for x in w {
        if !warnings.contains(&x) {
            warnings.push(x);
        }
    }
    let anthro = Anthropometry::<f64>::gait2392();
    let rejected = |name: &str| {
        let name = name.to_string();
        move |error| ModelError::Rejected { name, error }
    };
    let phak = Phak::<f64>::new(&anthro).map_err(rejected("phak"))?;
    let phak_points: Points = angles
        .iter()
        .map(|a: &PhakAngles<f64>| phak.fk(a).points())
        .collect();
    let gait2392 = |off: &[Feature]| -> Result<Points, ModelError> {
        let (g, q) = ablate(off, &q, &anthro);
        let model = Gait2392::<f64>::new(&g).map_err(rejected("gait2392"))?;
        Ok(q.iter().map(|q| model.fk(q).bilateral().points()).collect())
    };
    let full = gait2392(&[])?;
    let raw = distances(&full, &phak_points, false);
    let rel = distances(&full, &phak_points, true);
    let per_point = per_point(&raw, &rel);
    let mut sets: Vec<Vec<Feature>> = vec![Vec::new()];
    sets.extend(Feature::ALL.iter().map(|f| vec![*f]));
    sets.push(Feature::ALL.to_vec());
    let mut ablations = Vec::new();
    for off in sets {
        let g = gait2392(&off)?;
        let all = |d: [Vec<f64>; 8]| stat(d.into_iter().flatten());
        // Hip-relative: the hips are 0 by construction, so only the 6 points below them count.
        let below_hips = |d: [Vec<f64>; 8]| {
            stat(
                d.into_iter()
                    .enumerate()
                    .filter(|(k, _)| k % 4 != 0)
                    .flat_map(|(_, v)| v),
            )
        };
        ablations.push(AblationResult {
            raw: all(distances(&g, &phak_points, false)),
            relative: below_hips(distances(&g, &phak_points, true)),
            own_effect: all(distances(&full, &g, false)),
            off,
        });
    }
    Ok((
        Fidelity {
            label: label.to_string(),
            rows: table.rows(),
            per_point,
            ablations,
        },
        warnings,
    ))
}

/// PHAK against another imported model on one motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The model's name.
    pub model: String,
    /// The motion's label.
    pub label: String,
    /// Number of rows.
    pub rows: usize,
    /// Whether the model's knee flexes with positive angles (the motion's knee angles, in
    /// gait2392's sign, were negated for it).
    pub knee_negated: bool,
    /// Per point (`hip_r` ... `toe_l`): (name, raw, hip-relative).
    pub per_point: Vec<(String, Stat, Stat)>,
    /// All points, raw.
    pub raw: Stat,
    /// Knee, ankle and toe, hip-relative.
    pub relative: Stat,
}

/// Compares PHAK (gait2392's lengths) with `model` (a gait2392-family or chain model) on one
/// motion given in gait2392's coordinates (PHAK's convention). A model whose knee flexes with
/// positive angles (Rajagopal's) gets the knee angles negated: the same walking in its
/// coordinates. Points: hip, knee, ankle and the toe tip of each leg, as for gait2392.
pub fn compare(
    model: &crate::choice::Model,
    label: &str,
    table: &MotionTable,
) -> Result<(Comparison, Vec<Warning>), ModelError> {
    // The motion is in gait2392's coordinates, whatever the model.
    let (mut q, mut warnings) = gait2392_coordinates(table, KneeFlexion::Negative, [true; 17])?;
    warnings.extend(knees_flexing_positive(table.source(), &q));
    let (angles, w) = kinematics::phak_angles(table)?;
    for x in w {
        if !warnings.contains(&x) {
            warnings.push(x);
        }
    }
    let rejected = |name: &str| {
        let name = name.to_string();
        move |error| ModelError::Rejected { name, error }
    };
    let phak = Phak::<f64>::new(&Anthropometry::gait2392()).map_err(rejected("phak"))?;
    let phak_points: Points = angles.iter().map(|a| phak.fk(a).points()).collect();
    let eight = |p: [Vec3<f64>; 12]| -> [Vec3<f64>; 8] {
        [p[0], p[1], p[2], p[5], p[6], p[7], p[8], p[11]]
    };
    let Some(fk) = crate::points::imported_fk(model)? else {
        return Err(ModelError::NeedsChain {
            what: "fidelity --model",
            name: model.name().to_string(),
        });
    };
    let knee = KneeFlexion::of(&*fk);
    let knee_negated = knee == KneeFlexion::Positive;
    for row in &mut q {
        for k in KNEES {
            row[k] = knee.in_gait2392_signs(k, row[k]);
        }
    }
    let points: Points = q.iter().map(|q| eight(fk(q))).collect();
    let raw = distances(&points, &phak_points, false);
    let rel = distances(&points, &phak_points, true);
    let per_point = per_point(&raw, &rel);
    Ok((
        Comparison {
            model: model.name().to_string(),
            label: label.to_string(),
            rows: table.rows(),
            knee_negated,
            per_point,
            raw: stat(raw.into_iter().flatten()),
            relative: stat(
                rel.into_iter()
                    .enumerate()
                    .filter(|(k, _)| k % 4 != 0)
                    .flat_map(|(_, v)| v),
            ),
        },
        warnings,
    ))
}

/// The comparisons with other models as Markdown (millimetres, 2 decimals).
pub fn comparisons_markdown(results: &[Comparison]) -> String {
    let mm = |v: f64| format!("{v:.2}");
    let mut s = String::from("\n## PHAK (gait2392 lengths) against other models (mm)\n\n");
    s.push_str("The motion in gait2392's coordinates; a model whose knee flexes with positive angles gets them negated. Raw: all 8 points; hip-relative: knee, ankle and toe tip relative to the hip.\n\n");
    s.push_str("| model | motion | rows | knee negated | raw max | raw mean | hip-relative max | hip-relative mean | worst point (hip-relative max) |\n");
    s.push_str("|---|---|---:|---|---:|---:|---:|---:|---|\n");
    for c in results {
        let worst = c
            .per_point
            .iter()
            .max_by(|a, b| a.2.max.total_cmp(&b.2.max))
            .map(|(n, _, r)| format!("{n} {}", mm(r.max)))
            .unwrap_or_default();
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            c.model,
            c.label,
            c.rows,
            if c.knee_negated { "yes" } else { "no" },
            mm(c.raw.max),
            mm(c.raw.mean),
            mm(c.relative.max),
            mm(c.relative.mean),
            worst
        ));
    }
    s
}

/// Per point (`hip_r` ... `toe_l`): (name, raw, hip-relative) of the distances.
fn per_point(raw: &[Vec<f64>; 8], rel: &[Vec<f64>; 8]) -> Vec<(String, Stat, Stat)> {
    point_names(false)
        .into_iter()
        .enumerate()
        .map(|(k, name)| {
            (
                name,
                stat(raw[k].iter().copied()),
                stat(rel[k].iter().copied()),
            )
        })
        .collect()
}

fn off_name(off: &[Feature]) -> String {
    match off {
        [] => "none (full gait2392)".into(),
        [f] => f.off_description().into(),
        _ => "all of the above (gait2392 becomes PHAK)".into(),
    }
}

/// The report as Markdown: summaries over the motions, then per motion the per-point and the
/// ablation tables. Millimetres with 2 decimals; the all-features-off row in scientific
/// notation (it must be ~0).
pub fn markdown(results: &[Fidelity]) -> String {
    let mut s = String::new();
    let mm = |v: f64| format!("{v:.2}");
    let features = 1..=Feature::ALL.len();
    s.push_str("## Summary: deviation of PHAK (gait2392 lengths) from gait2392 (mm)\n\n");
    s.push_str("Raw: all 8 points in each model's own frame. Hip-relative: knee, ankle and toe of each leg relative to that leg's hip.\n\n");
    s.push_str("| motion | rows | raw max | raw mean | hip-relative max | hip-relative mean |\n");
    s.push_str("|---|---:|---:|---:|---:|---:|\n");
    for r in results {
        let full = &r.ablations[0];
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            r.label,
            r.rows,
            mm(full.raw.max),
            mm(full.raw.mean),
            mm(full.relative.max),
            mm(full.relative.mean)
        ));
    }
    let header = |s: &mut String| {
        s.push_str("| gait2392 feature switched off |");
        for r in results {
            s.push_str(&format!(" {} |", r.label));
        }
        s.push_str("\n|---|");
        for _ in results {
            s.push_str("---:|");
        }
        s.push('\n');
    };
    // One row per ablation `rows`, one `mean / max` column per motion of `stat`.
    let table = |s: &mut String, rows: &[usize], stat: fn(&AblationResult) -> &Stat| {
        header(s);
        for &i in rows {
            s.push_str(&format!("| {} |", off_name(&r_off(results, i))));
            for r in results {
                let a = stat(&r.ablations[i]);
                s.push_str(&format!(" {} / {} |", mm(a.mean), mm(a.max)));
            }
            s.push('\n');
        }
    };
    s.push_str("\n## Summary: what each gait2392 feature costs (mm, mean / max over all points and rows)\n\n");
    s.push_str("Own effect: how far switching the feature off moves gait2392's points (raw).\n\n");
    let own: Vec<usize> = features.clone().collect();
    table(&mut s, &own, |a| &a.own_effect);
    s.push_str("\nHip-relative deviation from PHAK that remains with the feature off (full gait2392 first):\n\n");
    let all: Vec<usize> = std::iter::once(0).chain(features).collect();
    table(&mut s, &all, |a| &a.relative);
    for r in results {
        s.push_str(&format!("\n## {} ({} rows)\n\n", r.label, r.rows));
        s.push_str("Deviation of PHAK from gait2392 per point (mm):\n\n");
        s.push_str("| point | raw max | raw mean | hip-relative max | hip-relative mean |\n");
        s.push_str("|---|---:|---:|---:|---:|\n");
        for (name, raw, rel) in &r.per_point {
            s.push_str(&format!(
                "| {name} | {} | {} | {} | {} |\n",
                mm(raw.max),
                mm(raw.mean),
                mm(rel.max),
                mm(rel.mean)
            ));
        }
        s.push_str("\ngait2392 features switched off one at a time (mm): deviation from PHAK that remains (raw: all points; hip-relative: knee, ankle, toe), and the feature's own effect (full gait2392 vs gait2392 without it, raw):\n\n");
        s.push_str("| switched off | raw max | raw mean | hip-relative max | hip-relative mean | own effect max | own effect mean |\n");
        s.push_str("|---|---:|---:|---:|---:|---:|---:|\n");
        for a in &r.ablations {
            let fmt = |v: f64| {
                if a.off.len() > 1 {
                    format!("{v:.2e}")
                } else {
                    mm(v)
                }
            };
            s.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} |\n",
                off_name(&a.off),
                fmt(a.raw.max),
                fmt(a.raw.mean),
                fmt(a.relative.max),
                fmt(a.relative.mean),
                mm(a.own_effect.max),
                mm(a.own_effect.mean)
            ));
        }
    }
    s
}

/// The features switched off in ablation `i` (the same for every motion).
fn r_off(results: &[Fidelity], i: usize) -> Vec<Feature> {
    results
        .first()
        .map(|r| r.ablations[i].off.clone())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pelvis_order_angles_reproduce_phak_rotation() {
        let (t, l, r) = pelvis_in_phak_order(0.0, 0.2, -0.4);
        let gait = Quat::from_axis_angle(Vec3::unit_z(), t)
            * Quat::from_axis_angle(Vec3::unit_x(), l)
            * Quat::from_axis_angle(Vec3::unit_y(), r);
        let phak = Quat::from_axis_angle(Vec3::unit_y(), -0.4)
            * Quat::from_axis_angle(Vec3::unit_x(), 0.2);
        let v = Vec3::new(0.3, -0.7, 0.5);
        assert!(gait.rotate(v).max_abs_diff(phak.rotate(v)) < 1e-15);
        assert!(t.abs() > 1e-3, "the orders differ, so tilt is needed: {t}");
    }
}
