//! [`ModelId`]: which kinematic model a pose frame was computed with, and the joints it needs.

use serde::{Deserialize, Serialize};

use crate::JointId;

/// A kinematic model of the lower limbs.
///
/// On the wire it is one raw byte holding the discriminant below; a byte with no
/// matching model is reported as [`DecodeError::UnknownModel`](crate::DecodeError::UnknownModel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum ModelId {
    /// Hip-ankle-knee model of the paper: sagittal joints of both legs only.
    Hak = 0,
    /// Pelvis-hip-ankle-knee model of the paper: HAK plus pelvis rotation and list.
    Phak = 1,
    /// OpenSim gait2392: every [`JointId`].
    Gait2392 = 2,
}

const HAK_JOINTS: [JointId; 6] = [
    JointId::HipFlexionR,
    JointId::KneeAngleR,
    JointId::AnkleAngleR,
    JointId::HipFlexionL,
    JointId::KneeAngleL,
    JointId::AnkleAngleL,
];

const PHAK_JOINTS: [JointId; 8] = [
    JointId::PelvisRotation,
    JointId::PelvisList,
    JointId::HipFlexionR,
    JointId::KneeAngleR,
    JointId::AnkleAngleR,
    JointId::HipFlexionL,
    JointId::KneeAngleL,
    JointId::AnkleAngleL,
];

impl ModelId {
    /// Number of models.
    pub const COUNT: usize = 3;

    /// Every model, in discriminant order.
    pub const ALL: [ModelId; Self::COUNT] = [ModelId::Hak, ModelId::Phak, ModelId::Gait2392];

    /// The wire byte of this model (its discriminant).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The model whose wire byte is `index`, or `None` if there is none.
    pub const fn from_index(index: u8) -> Option<ModelId> {
        if (index as usize) < Self::COUNT {
            Some(Self::ALL[index as usize])
        } else {
            None
        }
    }

    /// A short lowercase name: `"hak"`, `"phak"` or `"gait2392"`.
    pub const fn name(self) -> &'static str {
        match self {
            ModelId::Hak => "hak",
            ModelId::Phak => "phak",
            ModelId::Gait2392 => "gait2392",
        }
    }

    /// The model named `name` (as returned by [`ModelId::name`]), or `None`.
    pub fn from_name(name: &str) -> Option<ModelId> {
        Self::ALL.iter().copied().find(|m| m.name() == name)
    }

    /// The joints this model takes as input, in the order used by
    /// [`PoseFrame::angles`](crate::PoseFrame::angles).
    pub const fn required_joints(self) -> &'static [JointId] {
        match self {
            ModelId::Hak => &HAK_JOINTS,
            ModelId::Phak => &PHAK_JOINTS,
            ModelId::Gait2392 => &JointId::ALL,
        }
    }
}

impl core::fmt::Display for ModelId {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
