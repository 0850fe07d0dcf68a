//! The clinical joint angles of each frame in the Conventional Gait Model's conventions (the
//! normative data's), from gait2392's coordinates and the FK: the nine variables of the Gait
//! Profile Score. `docs/gait-analysis.md` says how each maps and what is not the same angle.
//!
//! - Pelvis: gait2392's tilt, list and rotation re-expressed relative to the direction of
//!   progression ([`heading_free_pelvis`]), the pelvis frame turned about its lateral axis onto
//!   the CGM's (whose forward axis runs from the mid-PSIS to the mid-ASIS point,
//!   [`pelvis_tilt_offset`]), then in the CGM's signs: tilt anterior positive (`-tilt`),
//!   obliquity positive with the side up (`-list` right, `+list` left), rotation positive with
//!   the side forward (`+rotation` right, `-rotation` left).
//! - Hip flexion, adduction (the GPS's "hip abduction" variable, adduction positive as the
//!   CGM) and internal rotation: gait2392's `hip_*`, relative to the CGM's pelvis frame: the
//!   flexion (the first rotation, about the same lateral axis) plus [`pelvis_tilt_offset`],
//!   exactly; adduction and rotation as they are.
//! - Knee flexion: `-knee_angle`. Ankle dorsiflexion: `ankle_angle`.
//! - Foot progression: from the FK, the foot's long axis (heel to MTP joint: gait2392's
//!   calcaneus origin to its MTP centre, nearly horizontal standing) in the horizontal plane
//!   against the direction of progression ([`foot_progression`]), internal positive.
//!
//! Which of the nine a model can move, from the coordinates it reads, and so which a report
//! shows: [`Seen`] (in [`variables`](crate::variables), re-exported here).

use qgait_kernel::imu::heading_free_pelvis;
use qgait_kernel::imu::math::three_axes;
use qgait_kernel::progression::{foot_progression, heading};
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat, Side, Vec3};

use crate::trial::{coordinate, Trial};
pub use crate::variables::{Plane, Seen, Variable, PLANAR_NOTE, STEP_WIDTH_MOVERS};

/// The mid-ASIS point in gait2392's pelvis frame (x forward, y up; metres): the `RASI` and
/// `LASI` markers of Rajagopal et al.'s (2016) model, whose pelvis carries gait2392's bone
/// meshes unscaled (`Rajagopal2016.osim`; gait2392's own files have no markers).
pub const MID_ASIS: [f64; 2] = [0.009_530_47, 0.018_081_6];

/// The mid-PSIS point, as [`MID_ASIS`]: the `RPSI` and `LPSI` markers.
pub const MID_PSIS: [f64; 2] = [-0.155, 0.035];

/// The CGM's pelvic tilt when gait2392's pelvis frame is level (radians, anterior positive):
/// the angle of the line from the mid-PSIS to the mid-ASIS point below the pelvis frame's
/// forward axis (5.87°). The CGM's pelvis frame is gait2392's turned by it about the lateral
/// axis.
pub fn pelvis_tilt_offset() -> f64 {
    tilt_offset(
        [MID_ASIS[0], MID_ASIS[1], 0.0],
        [MID_PSIS[0], MID_PSIS[1], 0.0],
    )
}

/// The tilt of the CGM's pelvis when the model's pelvis frame is level (radians, anterior
/// positive): the angle of the line from `posterior` (mid-PSIS or sacrum) to `mid_asis`
/// below the frame's forward axis, both in the pelvis frame (x forward, y up).
pub fn tilt_offset(mid_asis: [f64; 3], posterior: [f64; 3]) -> f64 {
    (posterior[1] - mid_asis[1]).atan2(mid_asis[0] - posterior[0])
}

/// How the CGM's pelvis frame is had from the model's.
#[derive(Clone, Debug, PartialEq)]
pub enum CgmPelvis {
    /// [`pelvis_tilt_offset`]: Rajagopal 2016's ASIS and PSIS markers on gait2392's pelvis.
    /// `model_markers`: the model's own pelvis markers, which `--cgm-pelvis model-markers`
    /// would take the offset from; `None` when the model has none.
    Fixed {
        /// The model's own pelvis markers, not used.
        model_markers: Option<ModelMarkers>,
    },
    /// From the model's own pelvis markers.
    Markers(ModelMarkers),
}

/// A model's own pelvis markers and the offset they give.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelMarkers {
    /// [`tilt_offset`] of the markers (radians).
    pub offset: f64,
    /// The markers, as the model names them.
    pub names: Vec<String>,
}

impl CgmPelvis {
    /// The fixed offset for a model without pelvis markers.
    pub const FIXED: CgmPelvis = CgmPelvis::Fixed {
        model_markers: None,
    };

    /// The tilt of the CGM's pelvis in the model's level pelvis frame (radians).
    pub fn offset(&self) -> f64 {
        match self {
            CgmPelvis::Fixed { .. } => pelvis_tilt_offset(),
            CgmPelvis::Markers(m) => m.offset,
        }
    }

    /// What the report says.
    pub fn describe(&self) -> String {
        let fixed = pelvis_tilt_offset().to_degrees();
        match self {
            CgmPelvis::Fixed {
                model_markers: None,
            } => format!(
                "the model's pelvis frame turned {fixed:.2}° anteriorly (the ASIS-PSIS line of Rajagopal 2016's markers; the model has no pelvis markers)"
            ),
            CgmPelvis::Fixed {
                model_markers: Some(m),
            } => format!(
                "the model's pelvis frame turned {fixed:.2}° anteriorly, the fixed offset (the ASIS-PSIS line of Rajagopal 2016's markers, --cgm-pelvis fixed); --cgm-pelvis model-markers would take it from the model's own markers {} ({:.2}°)",
                m.names.join(", "),
                m.offset.to_degrees()
            ),
            CgmPelvis::Markers(m) => format!(
                "the model's pelvis frame turned {:.2}° anteriorly, from its own markers {}",
                m.offset.to_degrees(),
                m.names.join(", ")
            ),
        }
    }
}

/// The CGM's pelvis angles `[tilt, list, rotation]` (radians, still in gait2392's signs and
/// sequence: tilt about the lateral z, list about x, rotation about y) of a pelvis whose
/// gait2392 angles relative to the direction of progression are `pelvis`: the frame turned
/// anteriorly by `offset` ([`CgmPelvis::offset`]) about its own lateral axis, decomposed again.
pub fn cgm_pelvis(pelvis: [f64; 3], offset: f64) -> [f64; 3] {
    let axes = [Vec3::unit_z(), Vec3::unit_x(), Vec3::unit_y()];
    let q = Quat::from_axis_angle(axes[0], pelvis[0])
        * Quat::from_axis_angle(axes[1], pelvis[1])
        * Quat::from_axis_angle(axes[2], pelvis[2])
        * Quat::from_axis_angle(axes[0], -offset);
    three_axes(q, axes)
}

/// The nine variables (degrees) of every frame of a trial, per side: `[side][variable][frame]`,
/// the CGM's pelvis as `pelvis` says. `None` for a trial without joint angles (a device's
/// frames).
pub fn angles(
    trial: &Trial,
    forward: &[Vec3<f64>],
    pelvis_frame: &CgmPelvis,
) -> Option<[[Vec<f64>; 9]; 2]> {
    let q = trial.coordinates.as_ref()?;
    // The pelvis's axes are the same in every gait2392 (tilt z, list x, rotation y).
    let model = Gait2392::<f64>::new(&Gait2392Geometry::generic()).ok()?;
    let [tilt, list, rot] = ["pelvis_tilt", "pelvis_list", "pelvis_rotation"].map(coordinate);
    let pelvis: Vec<[f64; 3]> = q
        .iter()
        .zip(forward)
        .map(|(q, f)| {
            cgm_pelvis(
                heading_free_pelvis(&model, [q[tilt], q[list], q[rot]], heading(*f)),
                pelvis_frame.offset(),
            )
            .map(f64::to_degrees)
        })
        .collect();
    let offset = pelvis_frame.offset().to_degrees();
    let mut out: [[Vec<f64>; 9]; 2] = Default::default();
    for (s, side) in Side::ALL.into_iter().enumerate() {
        let sign = if s == 0 { 1.0 } else { -1.0 };
        let c = |name: &str| coordinate(&format!("{name}_{}", side.suffix()));
        let [hf, ha, hr, knee, ankle] = [
            c("hip_flexion"),
            c("hip_adduction"),
            c("hip_rotation"),
            c("knee_angle"),
            c("ankle_angle"),
        ];
        for v in Variable::ALL {
            let i = Variable::ALL.iter().position(|x| *x == v).unwrap_or(0);
            out[s][i] = (0..q.len())
                .map(|f| match v {
                    Variable::PelvicTilt => -pelvis[f][0],
                    Variable::PelvicObliquity => -sign * pelvis[f][1],
                    Variable::PelvicRotation => sign * pelvis[f][2],
                    Variable::HipFlexion => q[f][hf].to_degrees() + offset,
                    Variable::HipAbduction => q[f][ha].to_degrees(),
                    Variable::HipRotation => q[f][hr].to_degrees(),
                    Variable::KneeFlexion => -q[f][knee].to_degrees(),
                    Variable::AnkleDorsiflexion => q[f][ankle].to_degrees(),
                    Variable::FootProgression => {
                        let limb = trial.frames[f][s];
                        foot_progression(side, limb.heel, limb.forefoot, forward[f]).to_degrees()
                    }
                })
                .collect();
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_kernel::models::gait2392::COORDINATES;

    /// The fixed offset says "no pelvis markers" only for a model without them; for one with
    /// them it names them and the option that would use them.
    #[test]
    fn the_pelvis_text_says_whether_the_model_has_markers() {
        let none = CgmPelvis::FIXED.describe();
        assert!(
            none.contains("5.87°") && none.contains("the model has no pelvis markers"),
            "{none}"
        );
        let names = vec!["R.ASIS".to_string(), "L.ASIS".into(), "V.Sacral".into()];
        let with = CgmPelvis::Fixed {
            model_markers: Some(ModelMarkers {
                offset: 2.45f64.to_radians(),
                names: names.clone(),
            }),
        };
        let text = with.describe();
        assert!(!text.contains("no pelvis markers"), "{text}");
        assert!(
            text.contains("5.87°") && text.contains("the fixed offset"),
            "{text}"
        );
        assert!(
            text.contains("--cgm-pelvis model-markers would take it from the model's own markers R.ASIS, L.ASIS, V.Sacral (2.45°)"),
            "{text}"
        );
        assert_eq!(with.offset(), pelvis_tilt_offset());
        let used = CgmPelvis::Markers(ModelMarkers {
            offset: 2.45f64.to_radians(),
            names,
        });
        assert!(used
            .describe()
            .contains("2.45° anteriorly, from its own markers R.ASIS"));
    }

    /// The coordinates of [`COORDINATES`] named (a side's stem counts both sides).
    fn reading(names: &[&str]) -> [bool; 17] {
        COORDINATES.map(|c| {
            names
                .iter()
                .any(|n| c == *n || c.strip_suffix("_r").or(c.strip_suffix("_l")) == Some(n))
        })
    }

    /// The visibility rule from sets of coordinates: gait2392 sees everything, gait10dof18musc
    /// the sagittal four without step width; a model with hip adduction but no hip rotation
    /// and no pelvis list or rotation loses the pelvic obliquity and rotation and the hip
    /// rotation, but its adduction still moves a foot sideways (step width) and turns a
    /// pitched foot (foot progression); either side's coordinate counts; the subtalar joint
    /// turns the foot, not the heel.
    #[test]
    fn a_variable_is_seen_when_the_model_reads_a_coordinate_that_moves_it() {
        let sagittal = ["pelvis_tilt", "hip_flexion", "knee_angle", "ankle_angle"];
        let gait2392 = Seen::from_reads([true; 17]);
        assert_eq!(gait2392, Seen::ALL);
        assert!(gait2392.step_width() && gait2392.note().is_none());
        assert!(gait2392.not_seen_names().is_empty());

        let planar = Seen::from_reads(reading(&sagittal));
        assert_eq!(planar, Seen::SAGITTAL);
        assert_eq!(
            planar.variables(),
            [
                Variable::PelvicTilt,
                Variable::HipFlexion,
                Variable::KneeFlexion,
                Variable::AnkleDorsiflexion
            ]
        );
        assert!(planar.is_planar() && !planar.step_width());
        assert_eq!(planar.note().as_deref(), Some(PLANAR_NOTE));
        assert_eq!(
            planar.not_seen_names(),
            [
                "pelvic_obliquity",
                "pelvic_rotation",
                "hip_abduction",
                "hip_rotation",
                "foot_progression",
                "step_width"
            ]
        );

        let adduction = Seen::from_reads(reading(&[&sagittal[..], &["hip_adduction"]].concat()));
        assert_eq!(
            adduction.not_seen(),
            [
                Variable::PelvicObliquity,
                Variable::PelvicRotation,
                Variable::HipRotation
            ]
        );
        assert!(adduction.sees(Variable::FootProgression) && adduction.step_width());
        assert!(!adduction.is_planar() && !adduction.is_all());
        assert_eq!(
            adduction.note().unwrap(),
            "the model cannot move: pelvic obliquity (no pelvis_list), pelvic rotation (no pelvis_rotation), hip rotation (no hip_rotation_r/l); these are not reported, and the GPS is over the 6 variables it can move (pelvic tilt, hip flexion, hip abduction, knee flexion, ankle dorsiflexion, foot progression)"
        );
        // One side's coordinate is enough.
        let right = Seen::from_reads(reading(&[&sagittal[..], &["hip_adduction_r"]].concat()));
        assert_eq!(right, adduction);

        // Pelvis rotation alone: the pelvic rotation, foot progression and step width.
        let rotation = Seen::from_reads(reading(&[&sagittal[..], &["pelvis_rotation"]].concat()));
        assert_eq!(
            rotation.not_seen(),
            [
                Variable::PelvicObliquity,
                Variable::HipAbduction,
                Variable::HipRotation
            ]
        );
        assert!(rotation.step_width());

        // The subtalar joint alone: the foot progression, no step width; the note says both.
        let subtalar = Seen::from_reads(reading(&[&sagittal[..], &["subtalar_angle"]].concat()));
        assert_eq!(subtalar.variables().len(), 5);
        assert!(subtalar.sees(Variable::FootProgression) && !subtalar.step_width());
        assert!(!subtalar.is_planar());
        let note = subtalar.note().unwrap();
        assert!(
            note.contains("step width (none of pelvis_list, pelvis_rotation, hip_adduction_r/l, hip_rotation_r/l)"),
            "{note}"
        );
        assert_eq!(subtalar.not_seen_names().last(), Some(&"step_width"));

        // A locked ankle: a sagittal variable too.
        let no_ankle = Seen::from_reads(reading(&["pelvis_tilt", "hip_flexion", "knee_angle"]));
        assert_eq!(no_ankle.variables().len(), 3);
        assert!(no_ankle
            .note()
            .unwrap()
            .contains("ankle dorsiflexion (no ankle_angle_r/l)"));
        // What two models both see.
        assert_eq!(gait2392.and(adduction), adduction);
        assert_eq!(adduction.and(planar), planar);
    }

    #[test]
    fn the_cgm_pelvis_is_tilted_forward_by_the_asis_psis_line() {
        let offset = pelvis_tilt_offset().to_degrees();
        assert!((offset - 5.87).abs() < 0.01, "{offset}");
        // A level gait2392 pelvis reads the offset as anterior tilt (CGM tilt = -tilt).
        let [t, l, r] = cgm_pelvis([0.0; 3], pelvis_tilt_offset());
        assert!((-t.to_degrees() - offset).abs() < 1e-9);
        assert!(l.abs() < 1e-12 && r.abs() < 1e-12);
        // With no list or rotation, the offset adds to the tilt exactly; with both, the frame
        // turns about its own lateral axis, not the ground's.
        let [t, ..] = cgm_pelvis([(-8f64).to_radians(), 0.0, 0.0], pelvis_tilt_offset());
        assert!((-t.to_degrees() - (8.0 + offset)).abs() < 1e-9);
        let p = [0.1, 0.15, 0.3];
        let [t, l, r] = cgm_pelvis(p, pelvis_tilt_offset());
        let back = Quat::from_axis_angle(Vec3::unit_z(), t)
            * Quat::from_axis_angle(Vec3::unit_x(), l)
            * Quat::from_axis_angle(Vec3::unit_y(), r);
        let x = back.rotate(Vec3::unit_x());
        let want = Quat::from_axis_angle(Vec3::unit_z(), p[0])
            * Quat::from_axis_angle(Vec3::unit_x(), p[1])
            * Quat::from_axis_angle(Vec3::unit_y(), p[2]);
        let asis = Vec3::new(MID_ASIS[0] - MID_PSIS[0], MID_ASIS[1] - MID_PSIS[1], 0.0);
        let along = want.rotate(asis);
        assert!(Vec3::distance(x, along.normalized()) < 1e-12);
    }
}
