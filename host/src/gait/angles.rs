//! The clinical joint angles of each frame in the Conventional Gait Model's conventions (the
//! normative data's), from gait2392's coordinates and the FK: the nine variables of the Gait
//! Profile Score. `docs/gait-analysis.md` says how each maps and what is not the same angle.
//!
//! - Pelvis: gait2392's tilt, list and rotation re-expressed relative to the direction of
//!   progression ([`heading_free_pelvis`]), then in the CGM's signs: tilt anterior positive
//!   (`-pelvis_tilt`), obliquity positive with the side up (`-list` right, `+list` left),
//!   rotation positive with the side forward (`+rotation` right, `-rotation` left).
//! - Hip flexion, adduction (the GPS's "hip abduction" variable, adduction positive as the
//!   CGM) and internal rotation: gait2392's `hip_*` as they are.
//! - Knee flexion: `-knee_angle`. Ankle dorsiflexion: `ankle_angle`.
//! - Foot progression: from the FK, the foot's long axis (heel to MTP joint: gait2392's
//!   calcaneus origin to its MTP centre, nearly horizontal standing) in the horizontal plane
//!   against the direction of progression ([`foot_progression`]), internal positive.

use qgait_kernel::imu::heading_free_pelvis;
use qgait_kernel::progression::{foot_progression, heading};
use qgait_kernel::{Gait2392, Gait2392Geometry, Side, Vec3};

use crate::gait::trial::{coordinate, Trial};

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

    /// A pelvis variable (one pelvis for both sides).
    pub fn is_pelvis(self) -> bool {
        matches!(
            self,
            Variable::PelvicTilt | Variable::PelvicObliquity | Variable::PelvicRotation
        )
    }
}

/// The nine variables (degrees) of every frame of a trial, per side: `[side][variable][frame]`.
/// `None` for a trial without joint angles (a device's frames).
pub fn angles(trial: &Trial, forward: &[Vec3<f64>]) -> Option<[[Vec<f64>; 9]; 2]> {
    let q = trial.coordinates.as_ref()?;
    // The pelvis's axes are the same in every gait2392 (tilt z, list x, rotation y).
    let model = Gait2392::<f64>::new(&Gait2392Geometry::generic()).ok()?;
    let [tilt, list, rot] = ["pelvis_tilt", "pelvis_list", "pelvis_rotation"].map(coordinate);
    let pelvis: Vec<[f64; 3]> = q
        .iter()
        .zip(forward)
        .map(|(q, f)| {
            heading_free_pelvis(&model, [q[tilt], q[list], q[rot]], heading(*f))
                .map(f64::to_degrees)
        })
        .collect();
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
                    Variable::HipFlexion => q[f][hf].to_degrees(),
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
