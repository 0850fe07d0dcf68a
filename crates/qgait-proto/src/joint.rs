//! [`JointId`]: every joint coordinate the models use, with its OpenSim name.

use serde::{Deserialize, Serialize};
use strum::EnumCount;

/// A joint coordinate of the PHAK or gait2392 model, named as in OpenSim.
///
/// On the wire it is one raw byte holding the discriminant below; a byte with no
/// matching joint is reported as [`DecodeError::UnknownJoint`](crate::DecodeError::UnknownJoint).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, EnumCount,
)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum JointId {
    /// `pelvis_tilt`: pelvis rotation about the right (z) axis.
    PelvisTilt = 0,
    /// `pelvis_list`: pelvis rotation about the forward (x) axis (the paper's "tilt").
    PelvisList = 1,
    /// `pelvis_rotation`: pelvis rotation about the vertical (y) axis.
    PelvisRotation = 2,
    /// `hip_flexion_r`: right hip flexion, > 0 forward.
    HipFlexionR = 3,
    /// `hip_adduction_r`: right hip adduction.
    HipAdductionR = 4,
    /// `hip_rotation_r`: right hip internal rotation.
    HipRotationR = 5,
    /// `knee_angle_r`: right knee, < 0 is flexion.
    KneeAngleR = 6,
    /// `ankle_angle_r`: right ankle, > 0 dorsiflexion.
    AnkleAngleR = 7,
    /// `subtalar_angle_r`: right subtalar joint.
    SubtalarAngleR = 8,
    /// `mtp_angle_r`: right metatarsophalangeal joint.
    MtpAngleR = 9,
    /// `hip_flexion_l`: left hip flexion, > 0 forward.
    HipFlexionL = 10,
    /// `hip_adduction_l`: left hip adduction.
    HipAdductionL = 11,
    /// `hip_rotation_l`: left hip internal rotation.
    HipRotationL = 12,
    /// `knee_angle_l`: left knee, < 0 is flexion.
    KneeAngleL = 13,
    /// `ankle_angle_l`: left ankle, > 0 dorsiflexion.
    AnkleAngleL = 14,
    /// `subtalar_angle_l`: left subtalar joint.
    SubtalarAngleL = 15,
    /// `mtp_angle_l`: left metatarsophalangeal joint.
    MtpAngleL = 16,
}

impl JointId {
    /// Number of joints.
    pub const COUNT: usize = <Self as EnumCount>::COUNT;

    /// Every joint, in discriminant order (`ALL[i].index() == i`).
    pub const ALL: [JointId; Self::COUNT] = [
        JointId::PelvisTilt,
        JointId::PelvisList,
        JointId::PelvisRotation,
        JointId::HipFlexionR,
        JointId::HipAdductionR,
        JointId::HipRotationR,
        JointId::KneeAngleR,
        JointId::AnkleAngleR,
        JointId::SubtalarAngleR,
        JointId::MtpAngleR,
        JointId::HipFlexionL,
        JointId::HipAdductionL,
        JointId::HipRotationL,
        JointId::KneeAngleL,
        JointId::AnkleAngleL,
        JointId::SubtalarAngleL,
        JointId::MtpAngleL,
    ];

    /// The OpenSim names, in discriminant order: the wire order is the kernel's gait2392
    /// coordinate order, so a sample's 17 angles index the kernel's input directly.
    const NAMES: [&'static str; Self::COUNT] = qgait_kernel::models::gait2392::COORDINATES;

    /// The wire byte of this joint (its discriminant), `0..COUNT`.
    pub const fn index(self) -> u8 {
        self as u8
    }

    /// The joint whose wire byte is `index`, or `None` if there is none.
    // By hand, not strum's `FromRepr` (a 17-arm match): the hub decodes one joint byte per
    // packet, and the table lookup costs about 15 instructions less a packet on the device.
    pub const fn from_index(index: u8) -> Option<JointId> {
        if (index as usize) < Self::COUNT {
            Some(Self::ALL[index as usize])
        } else {
            None
        }
    }

    /// The OpenSim coordinate name, e.g. `"hip_flexion_r"`.
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The joint with OpenSim coordinate name `name` (exact, case-sensitive), or `None`.
    pub fn from_name(name: &str) -> Option<JointId> {
        Self::NAMES
            .iter()
            .position(|n| *n == name)
            .and_then(|i| Self::ALL.get(i).copied())
    }
}

impl core::fmt::Display for JointId {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}
