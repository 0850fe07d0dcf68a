//! [`HubModel`]: the one model choice of a host configuring a hub.

use std::boxed::Box;

use qgait_kernel::models::ranges::KneeFlexion;
use qgait_kernel::models::LowerLimb;
use qgait_kernel::{Anthropometry, Gait2392Geometry, ModelError};

use crate::device_model::PoseModels;
use crate::{segment, ModelId};

/// The model a hub is configured with: what a host sends it (a `Config`, or a subject model's
/// parts and its `SubjectConfig`), and what the host recomputes its frames with
/// ([`pose_models`](Self::pose_models)).
#[derive(Debug, Clone, PartialEq)]
pub enum HubModel {
    /// HAK or PHAK, with segment lengths or the hub's current ones (`None`).
    Stick {
        /// `ModelId::Hak` or `ModelId::Phak`.
        model: ModelId,
        /// Segment lengths.
        anthropometry: Option<Anthropometry<f64>>,
    },
    /// The generic gait2392.
    Gait2392,
    /// A subject gait2392 model, sent in parts under `upload` (`None`: the sender picks one).
    Subject {
        /// The model.
        geometry: Box<Gait2392Geometry>,
        /// The upload id.
        upload: Option<u8>,
    },
    /// An imported lower-limb chain (`ModelId::Chain`), sent in parts under `upload` (`None`:
    /// the sender picks one).
    Chain {
        /// The chain, as the host computes it.
        chain: Box<LowerLimb<f64>>,
        /// The upload id.
        upload: Option<u8>,
    },
}

impl HubModel {
    /// The wire's model: the one the hub's pose frames name.
    pub fn id(&self) -> ModelId {
        match self {
            HubModel::Stick { model, .. } => *model,
            HubModel::Gait2392 | HubModel::Subject { .. } => ModelId::Gait2392,
            HubModel::Chain { .. } => ModelId::Chain,
        }
    }

    /// The segment lengths a `Config` carries (right, left; [`segment`] order, rounded to
    /// `f32`): `None` keeps the hub's.
    pub fn lengths(&self) -> Option<[[f32; segment::COUNT]; 2]> {
        match self {
            HubModel::Stick {
                anthropometry: Some(a),
                ..
            } => Some([a.right, a.left].map(|limb| limb.to_array().map(|l| l as f32))),
            _ => None,
        }
    }

    /// Which sign of `knee_angle` flexes this model's knee, as the hub finds it
    /// ([`Kinematics::knee_flexion`](crate::Kinematics::knee_flexion)): the chain's, by its
    /// forward kinematics; negative for the others.
    pub fn knee_flexion(&self) -> KneeFlexion {
        match self {
            HubModel::Chain { chain, .. } => KneeFlexion::of(|q| chain.forward(q)),
            _ => KneeFlexion::Negative,
        }
    }

    /// What the hub computes with after this configuration, in `f64`: HAK and PHAK with these
    /// segment lengths (else gait2392's, the hub's default), gait2392 with this geometry (else
    /// the generic one), the chain if it is one.
    pub fn pose_models(&self) -> Result<PoseModels<f64>, ModelError> {
        let generic = Gait2392Geometry::generic();
        let gait2392 = Anthropometry::gait2392();
        match self {
            HubModel::Stick { anthropometry, .. } => {
                PoseModels::new(anthropometry.as_ref().unwrap_or(&gait2392), &generic)
            }
            HubModel::Gait2392 => PoseModels::new(&gait2392, &generic),
            HubModel::Subject { geometry, .. } => PoseModels::new(&gait2392, geometry),
            HubModel::Chain { chain, .. } => {
                Ok(PoseModels::new(&gait2392, &generic)?.with_chain(**chain))
            }
        }
    }
}
