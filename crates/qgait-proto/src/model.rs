//! [`ModelId`]: which kinematic model a pose frame was computed with, and the joints it needs.
//! Its count, wire byte and name conversions are `strum`'s derives.

use serde::{Deserialize, Serialize};
use strum::{Display, EnumCount, EnumString, FromRepr, IntoStaticStr};

use crate::JointId;

/// A kinematic model of the lower limbs.
///
/// On the wire it is one raw byte holding the discriminant below; a byte with no
/// matching model is reported as [`DecodeError::UnknownModel`](crate::DecodeError::UnknownModel).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    EnumCount,
    FromRepr,
    IntoStaticStr,
    EnumString,
    Display,
)]
#[strum(serialize_all = "lowercase")]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum ModelId {
    /// Hip-ankle-knee model of the paper: sagittal joints of both legs only.
    Hak = 0,
    /// Pelvis-hip-ankle-knee model of the paper: HAK plus pelvis rotation and list.
    Phak = 1,
    /// OpenSim gait2392: every [`JointId`].
    Gait2392 = 2,
    /// An imported lower-limb chain (Rajagopal, gait10dof18musc, ...) uploaded as its table
    /// (`ChainTable` parts, switched to by a `ChainTableConfig`): every [`JointId`], as
    /// gait2392.
    Chain = 3,
}

/// HAK's joints: the sagittal ones of the right leg, then the left.
const HAK_JOINTS: [JointId; 6] = [
    JointId::HipFlexionR,
    JointId::KneeAngleR,
    JointId::AnkleAngleR,
    JointId::HipFlexionL,
    JointId::KneeAngleL,
    JointId::AnkleAngleL,
];

/// PHAK's joints: the pelvis rotation and list, then HAK's.
const PHAK_JOINTS: [JointId; 8] = {
    let [h0, h1, h2, h3, h4, h5] = HAK_JOINTS;
    [
        JointId::PelvisRotation,
        JointId::PelvisList,
        h0,
        h1,
        h2,
        h3,
        h4,
        h5,
    ]
};

impl ModelId {
    /// Number of models.
    pub const COUNT: usize = <Self as EnumCount>::COUNT;

    /// Every model, in discriminant order.
    pub const ALL: [ModelId; Self::COUNT] = [
        ModelId::Hak,
        ModelId::Phak,
        ModelId::Gait2392,
        ModelId::Chain,
    ];

    /// The wire byte of this model (its discriminant).
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The model whose wire byte is `index`, or `None` if there is none.
    pub const fn from_index(index: u8) -> Option<ModelId> {
        Self::from_repr(index)
    }

    /// A short lowercase name: `"hak"`, `"phak"`, `"gait2392"` or `"chain"` (also its
    /// `Display`).
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// The model named `name` (as returned by [`ModelId::name`]), or `None`.
    pub fn from_name(name: &str) -> Option<ModelId> {
        name.parse().ok()
    }

    /// The joints this model takes as input, in the order used by
    /// [`PoseFrame::angles`](crate::PoseFrame::angles).
    pub const fn required_joints(self) -> &'static [JointId] {
        match self {
            ModelId::Hak => &HAK_JOINTS,
            ModelId::Phak => &PHAK_JOINTS,
            ModelId::Gait2392 | ModelId::Chain => &JointId::ALL,
        }
    }
}
