//! What a hub does with a sample its reorder window closes incomplete ([`MissingPolicy`]),
//! set by a [`Config`](crate::Config) or a subject or chain model's configuration.

use serde::{Deserialize, Serialize};

/// What the hub does when a sample is incomplete when its reorder window closes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum MissingPolicy {
    /// Drop the sample: no pose frame is sent.
    Drop = 0,
    /// Use the last received angle of each missing joint and set [`FrameFlags::HELD`](crate::FrameFlags::HELD).
    HoldLast = 1,
}
