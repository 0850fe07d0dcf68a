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
//! shows: [`Seen`].

use qgait_kernel::imu::heading_free_pelvis;
use qgait_kernel::imu::math::three_axes;
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::progression::{foot_progression, heading};
use qgait_kernel::{Gait2392, Gait2392Geometry, Quat, Side, Vec3};

use crate::trial::{coordinate, Trial};

/// A Gait Profile Score variable, in Baker et al.'s (2009) order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variable {
    /// Pelvic tilt (anterior positive).
    PelvicTilt,
    /// Pelvic obliquity (the side up positive).
    PelvicObliquity,
    /// Pelvic rotation (the side forward positive).
    PelvicRotation,
    /// Hip flexion.
    HipFlexion,
    /// Hip ab/adduction (adduction positive).
    HipAbduction,
    /// Hip rotation (internal positive).
    HipRotation,
    /// Knee flexion.
    KneeFlexion,
    /// Ankle dorsiflexion.
    AnkleDorsiflexion,
    /// Foot progression (internal positive).
    FootProgression,
}

impl Variable {
    /// All nine.
    pub const ALL: [Variable; 9] = [
        Variable::PelvicTilt,
        Variable::PelvicObliquity,
        Variable::PelvicRotation,
        Variable::HipFlexion,
        Variable::HipAbduction,
        Variable::HipRotation,
        Variable::KneeFlexion,
        Variable::AnkleDorsiflexion,
        Variable::FootProgression,
    ];

    /// The name in `gps.csv` and the `cycles/` files.
    pub fn name(self) -> &'static str {
        match self {
            Variable::PelvicTilt => "pelvic_tilt",
            Variable::PelvicObliquity => "pelvic_obliquity",
            Variable::PelvicRotation => "pelvic_rotation",
            Variable::HipFlexion => "hip_flexion",
            Variable::HipAbduction => "hip_abduction",
            Variable::HipRotation => "hip_rotation",
            Variable::KneeFlexion => "knee_flexion",
            Variable::AnkleDorsiflexion => "ankle_dorsiflexion",
            Variable::FootProgression => "foot_progression",
        }
    }

    /// A title for figures and tables, with the positive direction.
    pub fn title(self) -> &'static str {
        match self {
            Variable::PelvicTilt => "Pelvic tilt (ant +)",
            Variable::PelvicObliquity => "Pelvic obliquity (up +)",
            Variable::PelvicRotation => "Pelvic rotation (fwd +)",
            Variable::HipFlexion => "Hip flexion (flex +)",
            Variable::HipAbduction => "Hip adduction (add +)",
            Variable::HipRotation => "Hip rotation (int +)",
            Variable::KneeFlexion => "Knee flexion (flex +)",
            Variable::AnkleDorsiflexion => "Ankle dorsiflexion (dors +)",
            Variable::FootProgression => "Foot progression (int +)",
        }
    }

    /// The normative data's variable and axis.
    pub fn normative(self) -> (&'static str, &'static str) {
        match self {
            Variable::PelvicTilt => ("PelvisAngles", "X"),
            Variable::PelvicObliquity => ("PelvisAngles", "Y"),
            Variable::PelvicRotation => ("PelvisAngles", "Z"),
            Variable::HipFlexion => ("HipAngles", "X"),
            Variable::HipAbduction => ("HipAngles", "Y"),
            Variable::HipRotation => ("HipAngles", "Z"),
            Variable::KneeFlexion => ("KneeAngles", "X"),
            Variable::AnkleDorsiflexion => ("AnkleAngles", "X"),
            Variable::FootProgression => ("FootProgressAngles", "Z"),
        }
    }

    /// The anatomical plane of the angle.
    pub fn plane(self) -> Plane {
        match self {
            Variable::PelvicTilt
            | Variable::HipFlexion
            | Variable::KneeFlexion
            | Variable::AnkleDorsiflexion => Plane::Sagittal,
            Variable::PelvicObliquity | Variable::HipAbduction => Plane::Frontal,
            Variable::PelvicRotation | Variable::HipRotation | Variable::FootProgression => {
                Plane::Transverse
            }
        }
    }

    /// The gait2392 coordinates (without the side's `_r`/`_l`) any one of which, read by the
    /// model, lets it move the variable ([`Seen`] says why each).
    pub fn movers(self) -> &'static [&'static str] {
        match self {
            Variable::PelvicTilt => &["pelvis_tilt"],
            Variable::PelvicObliquity => &["pelvis_list"],
            Variable::PelvicRotation => &["pelvis_rotation"],
            Variable::HipFlexion => &["hip_flexion"],
            Variable::HipAbduction => &["hip_adduction"],
            Variable::HipRotation => &["hip_rotation"],
            Variable::KneeFlexion => &["knee_angle"],
            Variable::AnkleDorsiflexion => &["ankle_angle"],
            Variable::FootProgression => &[
                "pelvis_list",
                "pelvis_rotation",
                "hip_adduction",
                "hip_rotation",
                "subtalar_angle",
            ],
        }
    }

    /// A pelvis variable (one pelvis for both sides).
    pub fn is_pelvis(self) -> bool {
        matches!(
            self,
            Variable::PelvicTilt | Variable::PelvicObliquity | Variable::PelvicRotation
        )
    }
}

/// The anatomical plane an angle is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Plane {
    /// Flexion and extension (the sagittal plane).
    Sagittal,
    /// Ab/adduction, obliquity (the frontal plane).
    Frontal,
    /// Rotation about the long axis, foot progression (the transverse plane).
    Transverse,
}

/// What a report of a planar model ([`Seen::is_planar`]: it moves none of the coordinates
/// that could move a frontal or transverse quantity) says about what it leaves out, and why
/// ([`Seen::note`]).
pub const PLANAR_NOTE: &str = "planar model: it moves neither hip in adduction or rotation, nor the pelvis in list or rotation, nor a subtalar joint, so its legs move in the pelvis's sagittal plane only and no frontal or transverse quantity can be seen; step width, pelvic obliquity and rotation, hip abduction and rotation and foot progression are not reported, and the GPS is over the sagittal angles only (pelvic tilt, hip flexion, knee flexion, ankle dorsiflexion)";

/// The coordinates (without the side's `_r`/`_l`) any one of which, read by the model, lets it
/// move one foot sideways relative to the other: step width ([`Seen::step_width`]).
pub const STEP_WIDTH_MOVERS: [&str; 4] = [
    "pelvis_list",
    "pelvis_rotation",
    "hip_adduction",
    "hip_rotation",
];

/// Which of the nine variables ([`Variable::ALL`] order) a model can move, from the gait2392
/// coordinates it reads ([`Seen::from_reads`]); a report leaves out the others and step width
/// when the model cannot move it, and says which and why ([`Seen::note`]).
///
/// The rule, from how [`angles`] and the step width ([`crate::spatiotemporal`]) are computed:
/// a variable is seen when the model reads any coordinate of [`Variable::movers`]; a side's
/// coordinate counts when either side's is read (a model reads both sides in practice, and the
/// report shows both sides' curves of a variable or neither).
///
/// - Pelvic tilt, obliquity and rotation: `pelvis_tilt`, `pelvis_list`, `pelvis_rotation`.
///   The three are re-expressed against the direction of progression and in the CGM's pelvis
///   frame (gait2392's turned about its lateral axis by [`pelvis_tilt_offset`], 5.87°), then
///   decomposed again: that couples them through the frame's forward tilt (the offset plus
///   `pelvis_tilt`), so a rotation without list reads as an obliquity of about the sine of
///   that tilt times the rotation, and a list without rotation as a rotation likewise (the gait
///   lab's walk with `pelvis_list` locked: 0.9° of obliquity for 3.8° of rotation). That
///   fraction is the re-expression's, not a list the model makes (its own tilt-list-rotation
///   sequence has none), so it does not count: each pelvic angle needs its own coordinate.
/// - Hip flexion, abduction (adduction positive) and rotation, knee flexion, ankle
///   dorsiflexion: the coordinates themselves (`hip_flexion`, `hip_adduction`,
///   `hip_rotation`, `knee_angle`, `ankle_angle`; the hip flexion plus the fixed offset).
/// - Foot progression: from the FK, the heel-to-MTP line in the lab's horizontal plane, so any
///   coordinate that turns the foot about the vertical moves it: `pelvis_rotation` and
///   `hip_rotation` directly; `pelvis_list` and `hip_adduction`, about the forward axis, turn
///   a pitched foot's horizontal line (by about tan(pitch) × sin(angle): a few degrees in
///   swing, where knee and ankle pitch the foot); `subtalar_angle`, whose axis is about 37°
///   from the vertical, turns the MTP about the heel. The sagittal coordinates turn about
///   lateral axes: alone they leave the foot's line where the model's geometry sets it (its
///   built-in toe-out; gait2392's ankle axis, 10° off the lateral, adds a fixed sixth of the
///   dorsiflexion), which is not a transverse movement and does not count.
/// - Step width ([`STEP_WIDTH_MOVERS`]): the heels' (subtalar centres') distance across the
///   direction of travel at one instant, so any coordinate that moves one heel sideways
///   relative to the other: `pelvis_rotation` turns the step (its length along, its width
///   across) about the vertical; `pelvis_list` turns it about the forward axis, moving the
///   heels across by their height difference; `hip_adduction` swings a leg sideways;
///   `hip_rotation` turns the heel, which is off the femur's long axis (behind the ankle,
///   below a flexed knee), about it. `subtalar_angle` does not: the heel point is on its
///   axis. The sagittal coordinates alone keep the heels at the model's fixed hip width (its
///   pelvis translation is not part of the distance, taken at one instant). Step width is
///   seen exactly when pelvic obliquity, pelvic rotation, hip abduction or hip rotation is.
///
/// gait2392 reads all seventeen: everything is seen. gait10dof18musc reads only the sagittal
/// coordinates: the sagittal four, no step width (a planar model, [`PLANAR_NOTE`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Seen(pub [bool; 9]);

impl Default for Seen {
    fn default() -> Self {
        Seen::ALL
    }
}

impl Seen {
    /// All nine (a model that reads every coordinate; also a source without joint angles).
    pub const ALL: Seen = Seen([true; 9]);

    /// The sagittal four: a planar model's.
    pub const SAGITTAL: Seen = Seen([true, false, false, true, false, false, true, true, false]);

    /// What a model that reads the gait2392 coordinates `reads` ([`COORDINATES`] order) can
    /// move ([`Seen`]'s rule).
    ///
    /// [`COORDINATES`]: qgait_kernel::models::gait2392::COORDINATES
    pub fn from_reads(reads: [bool; 17]) -> Seen {
        Seen(Variable::ALL.map(|v| v.movers().iter().any(|c| reads_any(reads, c))))
    }

    /// The variables seen, [`Variable::ALL`] order.
    pub fn variables(self) -> Vec<Variable> {
        Variable::ALL
            .into_iter()
            .filter(|v| self.sees(*v))
            .collect()
    }

    /// The variables not seen, [`Variable::ALL`] order.
    pub fn not_seen(self) -> Vec<Variable> {
        Variable::ALL
            .into_iter()
            .filter(|v| !self.sees(*v))
            .collect()
    }

    /// Whether `v` is seen.
    pub fn sees(self, v: Variable) -> bool {
        Variable::ALL
            .iter()
            .position(|x| *x == v)
            .is_some_and(|i| self.0[i])
    }

    /// Whether step width can be seen: exactly when a coordinate of [`STEP_WIDTH_MOVERS`] is
    /// read, i.e. when pelvic obliquity, pelvic rotation, hip abduction or hip rotation is seen.
    pub fn step_width(self) -> bool {
        [
            Variable::PelvicObliquity,
            Variable::PelvicRotation,
            Variable::HipAbduction,
            Variable::HipRotation,
        ]
        .into_iter()
        .any(|v| self.sees(v))
    }

    /// Every variable seen (and so step width).
    pub fn is_all(self) -> bool {
        self == Seen::ALL
    }

    /// No frontal or transverse variable seen and no step width: a planar model.
    pub fn is_planar(self) -> bool {
        !self.step_width()
            && Variable::ALL
                .into_iter()
                .all(|v| v.plane() == Plane::Sagittal || !self.sees(v))
    }

    /// What both see: a report of several recordings (and a reference recording) shows only
    /// what every one of their models can move.
    pub fn and(self, other: Seen) -> Seen {
        Seen(std::array::from_fn(|i| self.0[i] && other.0[i]))
    }

    /// The names of what is left out, for `summary.json`'s `not_seen`: the variables'
    /// ([`Variable::name`]), then `step_width` when it is not seen.
    pub fn not_seen_names(self) -> Vec<&'static str> {
        let mut names: Vec<&'static str> =
            self.not_seen().into_iter().map(Variable::name).collect();
        if !self.step_width() {
            names.push("step_width");
        }
        names
    }

    /// What a report says about what it leaves out, and why; `None` when it leaves out
    /// nothing. A planar model's is [`PLANAR_NOTE`]; otherwise, e.g. `the model cannot move:
    /// pelvic obliquity (no pelvis_list), pelvic rotation (no pelvis_rotation), hip rotation
    /// (no hip_rotation_r/l); these are not reported, and the GPS is over the 6 variables it
    /// can move (...)`.
    pub fn note(self) -> Option<String> {
        if self.is_all() {
            return None;
        }
        if self == Seen::SAGITTAL {
            return Some(PLANAR_NOTE.to_string());
        }
        let mut out: Vec<String> = self
            .not_seen()
            .into_iter()
            .map(|v| format!("{} ({})", lower(v), without(v.movers())))
            .collect();
        if !self.step_width() {
            out.push(format!("step width ({})", without(&STEP_WIDTH_MOVERS)));
        }
        let seen = self.variables();
        Some(format!(
            "the model cannot move: {}; {} not reported, and the GPS is over the {} variables it can move ({})",
            out.join(", "),
            if out.len() == 1 { "it is" } else { "these are" },
            seen.len(),
            seen.iter().map(|v| lower(*v)).collect::<Vec<_>>().join(", ")
        ))
    }
}

/// Whether `reads` has the coordinate `stem`, or either side's `stem_r`/`stem_l`.
fn reads_any(reads: [bool; 17], stem: &str) -> bool {
    COORDINATES.iter().zip(reads).any(|(name, r)| {
        r && (*name == stem
            || name.strip_suffix("_r").or_else(|| name.strip_suffix("_l")) == Some(stem))
    })
}

/// A variable's name in words: `pelvic obliquity`.
fn lower(v: Variable) -> String {
    v.name().replace('_', " ")
}

/// Why a variable is not seen: `no pelvis_list`, `none of pelvis_list, hip_adduction_r/l`.
fn without(stems: &[&str]) -> String {
    let named: Vec<String> = stems
        .iter()
        .map(|s| {
            if s.starts_with("pelvis") {
                s.to_string()
            } else {
                format!("{s}_r/l")
            }
        })
        .collect();
    match named.as_slice() {
        [one] => format!("no {one}"),
        _ => format!("none of {}", named.join(", ")),
    }
}

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
