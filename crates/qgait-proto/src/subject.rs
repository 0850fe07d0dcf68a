//! Subject-specific gait2392 models sent by the host to the hub: [`SubjectLeg`] and
//! [`SubjectKnee`] carry the numbers of the model in small parts, [`SubjectConfig`] switches
//! the hub to the assembled model.
//!
//! A whole model is 6 parts: one [`SubjectLeg`] per leg and one [`SubjectKnee`] per leg and
//! [`KneeDirection`]. Every part names the `upload` it belongs to (an id the host picks); the
//! hub gathers the parts of one upload, and a [`SubjectConfig`] with that id switches it to
//! the model only if all 6 arrived and the model is valid. The numbers are those of the
//! kernel's `Gait2392Geometry` (metres, unit axes, OpenSim frames), in `f32`, the precision the
//! hub computes in.

use serde::{Deserialize, Serialize};
use strum::FromRepr;

use crate::MissingPolicy;

/// The most knots of one knee spline (the kernel's `spline::MAX_KNOTS`).
pub const MAX_KNEE_KNOTS: usize = 12;

/// Number of parts of a complete subject model: 2 legs, 2 knee splines per leg.
pub const SUBJECT_PARTS: usize = 6;

/// A leg of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, FromRepr)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Leg {
    /// The right leg.
    Right = 0,
    /// The left leg.
    Left = 1,
}

impl Leg {
    /// Both legs, in wire order.
    pub const ALL: [Leg; 2] = [Leg::Right, Leg::Left];

    /// The wire byte (0 right, 1 left).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The leg of wire byte `index`, or `None`.
    pub const fn from_index(index: u8) -> Option<Leg> {
        Self::from_repr(index)
    }
}

/// Which knee translation a [`SubjectKnee`] spline gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, FromRepr)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum KneeDirection {
    /// Translation of the knee centre along the femur's x axis (`knee_tx`).
    Tx = 0,
    /// Translation of the knee centre along the femur's y axis (`knee_ty`).
    Ty = 1,
}

impl KneeDirection {
    /// Both directions, in wire order.
    pub const ALL: [KneeDirection; 2] = [KneeDirection::Tx, KneeDirection::Ty];

    /// The wire byte (0 tx, 1 ty).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The direction of wire byte `index`, or `None`.
    pub const fn from_index(index: u8) -> Option<KneeDirection> {
        Self::from_repr(index)
    }
}

/// The joint geometry of one leg of a subject gait2392 model (everything but the knee
/// splines): positions in metres in the parent body's frame, unit rotation axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SubjectLeg {
    /// The upload this part belongs to.
    pub upload: u8,
    /// The leg it describes.
    pub leg: Leg,
    /// Hip centre in the pelvis frame.
    pub hip_in_pelvis: [f32; 3],
    /// Hip flexion, adduction and rotation axes (body-fixed sequence).
    pub hip_axes: [[f32; 3]; 3],
    /// Ankle centre in the tibia frame.
    pub ankle_in_tibia: [f32; 3],
    /// Ankle axis.
    pub ankle_axis: [f32; 3],
    /// Subtalar centre in the talus frame.
    pub subtalar_in_talus: [f32; 3],
    /// Subtalar axis.
    pub subtalar_axis: [f32; 3],
    /// MTP centre in the calcaneus frame.
    pub mtp_in_calcn: [f32; 3],
    /// MTP axis.
    pub mtp_axis: [f32; 3],
    /// Toe tip in the toes frame.
    pub toetip_in_toes: [f32; 3],
}

/// One knee translation spline of one leg of a subject gait2392 model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SubjectKnee {
    /// The upload this part belongs to.
    pub upload: u8,
    /// The leg it describes.
    pub leg: Leg,
    /// Which translation.
    pub direction: KneeDirection,
    /// The knots `[x, y]`: `x` the knee angle (radians, strictly increasing), `y` the
    /// translation (metres). The kernel needs 2 to [`MAX_KNEE_KNOTS`].
    pub knots: heapless::Vec<[f32; 2], MAX_KNEE_KNOTS>,
}

/// Switches the hub to gait2392 with the subject model of `upload`, with these settings (the
/// fields of [`Config`](crate::Config) a subject model does not fix).
///
/// The hub refuses it (and counts it in [`Status::config_rejected`](crate::Status)) unless
/// all [`SUBJECT_PARTS`] parts of `upload` arrived and the kernel accepts the model; the
/// model in force then stays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SubjectConfig {
    /// The upload whose parts make the model.
    pub upload: u8,
    /// What to do with incomplete samples.
    pub missing_policy: MissingPolicy,
    /// How many samples the hub waits for late packets before closing a sample:
    /// `1..=`[`MAX_REORDER_WINDOW`](crate::MAX_REORDER_WINDOW), as in [`Config`](crate::Config).
    pub reorder_window: u8,
    /// `true` asks the hub to answer with a [`Status`](crate::Status) message.
    pub request_status: bool,
}
