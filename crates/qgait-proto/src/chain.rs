//! Imported lower-limb chains sent by the host to the hub (an OpenSim model that is not
//! gait2392's shape: Rajagopal 2015/2016, gait10dof18musc, ...): the kernel's chain table
//! (`qgait_kernel::models::CustomChain`) in small parts.
//!
//! A whole chain is [`CHAIN_BODIES`] [`ChainJoint`]s (each body's offset frames and output
//! point), [`CHAIN_BODIES`] [`ChainAxes`] (each joint's moving transform axes) and one
//! [`ChainSpline`] per spline the axes use; a [`ChainConfig`] then names the upload, says how
//! many splines it has, carries its couplers and toe tips, and switches the hub to it if every
//! part arrived and the kernel accepts the chain. Numbers are the kernel's (metres, unit
//! quaternions `[w, x, y, z]`, radians), in `f32`, the precision the hub computes in.

use serde::{Deserialize, Serialize};

use crate::MissingPolicy;

/// Wire tag of [`ChainJoint`].
pub const CHAIN_JOINT_TAG: u32 = 9;
/// Wire tag of [`ChainAxes`].
pub const CHAIN_AXES_TAG: u32 = 10;
/// Wire tag of [`ChainSpline`].
pub const CHAIN_SPLINE_TAG: u32 = 11;
/// Wire tag of [`ChainConfig`].
pub const CHAIN_CONFIG_TAG: u32 = 12;

/// Bodies of a chain: the pelvis, then femur, tibia, talus, calcaneus and toes of the right
/// leg, then of the left (the kernel's `LowerLimb`). Joint `b` moves body `b`.
pub const CHAIN_BODIES: usize = 11;
/// The most splines of one chain (Rajagopal's walker knees: four each).
pub const MAX_CHAIN_SPLINES: usize = 8;
/// The most knots of one spline (Rajagopal's knee: 13).
pub const MAX_CHAIN_KNOTS: usize = 13;
/// The most coupled coordinates of one chain (the kernel's `MAX_COUPLERS`).
pub const MAX_CHAIN_COUPLERS: usize = 4;
/// [`ChainJoint::parent`] of the body hanging on ground (the pelvis).
pub const CHAIN_GROUND: u8 = u8::MAX;

/// A fixed transform: a translation (metres) and an orientation (unit quaternion `[w, x, y,
/// z]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainOffset {
    /// Origin of the frame in its body.
    pub translation: [f32; 3],
    /// Orientation of the frame in its body.
    pub rotation: [f32; 4],
}

/// The frames of the joint that moves one body, and the body's output point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainJoint {
    /// The upload this part belongs to.
    pub upload: u8,
    /// The body (`0..CHAIN_BODIES`).
    pub body: u8,
    /// The parent body, or [`CHAIN_GROUND`].
    pub parent: u8,
    /// The parent offset frame in the parent body.
    pub in_parent: ChainOffset,
    /// The child offset frame in this body.
    pub in_child: ChainOffset,
    /// The body's output point in its frame (the joint centre: hip, knee, ankle, subtalar,
    /// MTP); ignored for the pelvis.
    pub point: [f32; 3],
}

/// What a transform axis's value is: the kernel's `Function`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ChainFunction {
    /// A constant.
    Constant(f32),
    /// `slope · x + intercept`.
    Linear {
        /// Slope.
        slope: f32,
        /// Value at 0.
        intercept: f32,
    },
    /// Spline `k` of the upload ([`ChainSpline::index`]).
    Spline(u8),
}

/// What a function is evaluated at: the kernel's `Argument`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ChainArgument {
    /// Nothing (evaluated at 0).
    None,
    /// Input coordinate `i` (a `JointId` index).
    Coordinate(u8),
    /// Coupled coordinate `k` ([`ChainConfig::couplers`]).
    Coupled(u8),
}

/// One transform axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainAxis {
    /// Direction: rotations in the frame left by the joint's earlier rotations, translations
    /// in the parent offset frame.
    pub axis: [f32; 3],
    /// The value (radians or metres) as a function of `argument`.
    pub function: ChainFunction,
    /// What the function is evaluated at.
    pub argument: ChainArgument,
}

/// The moving transform axes of the joint that moves one body: rotations (body-fixed, in
/// order), then translations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainAxes {
    /// The upload this part belongs to.
    pub upload: u8,
    /// The body (`0..CHAIN_BODIES`).
    pub body: u8,
    /// Rotations, in order.
    pub rotations: heapless::Vec<ChainAxis, 3>,
    /// Translations.
    pub translations: heapless::Vec<ChainAxis, 3>,
}

/// One spline of a chain: OpenSim's `SimmSpline` (section 9.3 of the protocol document) or,
/// with `linear`, its `PiecewiseLinearFunction`, through the knots.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainSpline {
    /// The upload this part belongs to.
    pub upload: u8,
    /// Its index (`0..MAX_CHAIN_SPLINES`), as [`ChainFunction::Spline`] names it.
    pub index: u8,
    /// Straight lines between the knots instead of the cubic.
    pub linear: bool,
    /// The knots `[x, y]`, `x` strictly increasing: 2 to [`MAX_CHAIN_KNOTS`].
    pub knots: heapless::Vec<[f32; 2], MAX_CHAIN_KNOTS>,
}

/// A coupled coordinate: `function(independent)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainCoupler {
    /// The input coordinate it follows (a `JointId` index).
    pub independent: u8,
    /// The coupling function.
    pub function: ChainFunction,
}

/// A point fixed in a body.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainPoint {
    /// The body (`0..CHAIN_BODIES`).
    pub body: u8,
    /// Position in the body's frame (metres).
    pub offset: [f32; 3],
}

/// Switches the hub to the chain of `upload` (its [`CHAIN_BODIES`] joints and axes and its
/// first `splines` splines, with these couplers and toe tips), with these settings.
///
/// The hub refuses it (and counts it in [`Status::config_rejected`](crate::Status)) unless
/// every part arrived and the kernel accepts the chain; the model in force then stays.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainConfig {
    /// The upload whose parts make the chain.
    pub upload: u8,
    /// How many splines it has (`0..=MAX_CHAIN_SPLINES`).
    pub splines: u8,
    /// Its coupled coordinates.
    pub couplers: heapless::Vec<ChainCoupler, MAX_CHAIN_COUPLERS>,
    /// The toe tips, right then left.
    pub toe_tips: [ChainPoint; 2],
    /// What to do with incomplete samples.
    pub missing_policy: MissingPolicy,
    /// How many samples the hub waits for late packets:
    /// `1..=`[`MAX_REORDER_WINDOW`](crate::MAX_REORDER_WINDOW).
    pub reorder_window: u8,
    /// `true` asks the hub to answer with a [`Status`](crate::Status) message.
    pub request_status: bool,
}
