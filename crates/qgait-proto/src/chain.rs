//! Imported lower-limb chains sent by the host to the hub (an OpenSim model that is not
//! gait2392's shape: Rajagopal 2015/2016, gait10dof18musc, ...): the kernel's packed chain
//! table (`qgait_kernel::models::packed::PackedChain` in `f32`, the hub's
//! [`DeviceChain`](crate::DeviceChain)) as the bytes of its image.
//!
//! The host packs the chain, cuts the image into [`ChainTable`] parts, each written by the hub
//! straight into its model slot, then sends a [`ChainTableConfig`] giving the image's length
//! and CRC, which switches the hub to the table if the bytes it holds are those.

use serde::{Deserialize, Serialize};

use crate::MissingPolicy;

/// Wire tag of [`ChainTable`].
pub const CHAIN_TABLE_TAG: u32 = 9;
/// Wire tag of [`ChainTableConfig`].
pub const CHAIN_TABLE_CONFIG_TAG: u32 = 10;

/// Bodies of a chain: the pelvis, then femur, tibia, talus, calcaneus and toes of the right
/// leg, then of the left (the kernel's `LowerLimb`). Joint `b` moves body `b`.
pub const CHAIN_BODIES: usize = 11;
/// The most splines of one chain (Rajagopal's walker knees: four each).
pub const MAX_CHAIN_SPLINES: usize = 8;
/// The most moving transform axes of one chain (Rajagopal: 21).
pub const MAX_CHAIN_DRIVES: usize = 24;
/// The most numbers of one chain's table (Rajagopal 2015 and 2016: 333).
pub const MAX_CHAIN_WORDS: usize = 384;
/// The most bytes of the image one [`ChainTable`] carries.
pub const MAX_CHAIN_TABLE_BYTES: usize = 128;

/// Bytes `at..at + bytes.len()` of the image of chain `upload`'s table.
///
/// The hub writes them into its model slot as they arrive: the first part of an upload stops
/// the model in force (its open samples closed under it) until a [`ChainTableConfig`] switches
/// to the table; a part of another upload than the one held starts from an empty table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainTable {
    /// The upload this part belongs to.
    pub upload: u8,
    /// Where in the image its bytes go.
    pub at: u16,
    /// The bytes (at most [`MAX_CHAIN_TABLE_BYTES`]).
    pub bytes: heapless::Vec<u8, MAX_CHAIN_TABLE_BYTES>,
}

/// Switches the hub to the table of `upload`, whose image's first `len` bytes have CRC-32C
/// `crc`, with these settings.
///
/// The hub refuses it (and counts it in [`Status::config_rejected`](crate::Status)) unless it
/// holds `upload`'s table, the CRC of its first `len` bytes is `crc`, and the table is one the
/// hub can compute (its counts within the table's sizes, its numbers finite); it then stays as
/// it was.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ChainTableConfig {
    /// The upload whose table to switch to.
    pub upload: u8,
    /// How many bytes of the image the host sent (the codes and the numbers in use).
    pub len: u16,
    /// Their CRC-32C (the frames' CRC, section 2.2 of the protocol).
    pub crc: u32,
    /// The model's knee flexes with positive `knee_angle` (Rajagopal's walker knee), as the
    /// host finds from its forward kinematics: the hub judges the knee's range mirrored.
    pub knee_flexes_positive: bool,
    /// What to do with incomplete samples.
    pub missing_policy: MissingPolicy,
    /// How many samples the hub waits for late packets:
    /// `1..=`[`MAX_REORDER_WINDOW`](crate::MAX_REORDER_WINDOW).
    pub reorder_window: u8,
    /// `true` asks the hub to answer with a [`Status`](crate::Status) message.
    pub request_status: bool,
}
