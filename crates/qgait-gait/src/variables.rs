//! The nine kinematic variables of the Gait Profile Score ([`Variable`]), their planes, and
//! which of them a model can move from the gait2392 coordinates it reads ([`Seen`]): what a
//! trial knows of its model ([`Trial::seen`](crate::trial::Trial::seen)) and what the
//! [`angles`](crate::angles) and the report show.

use qgait_kernel::models::gait2392::COORDINATES;

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
/// The rule, from how [`angles`](crate::angles::angles) and the step width
/// ([`crate::spatiotemporal`]) are computed: a variable is seen when the model reads any
/// coordinate of [`Variable::movers`]; a side's coordinate counts when either side's is read (a
/// model reads both sides in practice, and the report shows both sides' curves of a variable or
/// neither).
///
/// - Pelvic tilt, obliquity and rotation: `pelvis_tilt`, `pelvis_list`, `pelvis_rotation`.
///   The three are re-expressed against the direction of progression and in the CGM's pelvis
///   frame (gait2392's turned about its lateral axis by
///   [`pelvis_tilt_offset`](crate::angles::pelvis_tilt_offset), 5.87°), then decomposed again:
///   that couples them through the frame's forward tilt (the offset plus `pelvis_tilt`), so a
///   rotation without list reads as an obliquity of about the sine of that tilt times the
///   rotation, and a list without rotation as a rotation likewise (the gait
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
