//! The points' velocities: [`VelocityConfig`] (host to hub: turn them on, with the nodes'
//! sample period) and [`PoseVelocities`] (hub to host: the velocities of a [`PoseFrame`]'s
//! points, sent right after it), protocol.md 4.11.
//!
//! The hub differentiates the angles it echoes: a first-order backward difference between two
//! consecutive samples, `q̇ₖ = (qₖ − qₖ₋₁) / T` (`T` the configured period), then the kernel's
//! `forward_velocities`. It is causal and half a sample late (`T / 2`); it exists only
//! between consecutive samples (`seq` one apart), so the first frame after a start, a
//! configuration or a gap has none.
//!
//! [`PoseFrame`]: crate::PoseFrame

use serde::{Deserialize, Serialize};

use crate::point;

/// Wire tag of [`VelocityConfig`].
pub const VELOCITY_CONFIG_TAG: u32 = 14;
/// Wire tag of [`PoseVelocities`].
pub const POSE_VELOCITIES_TAG: u32 = 15;

/// Host to hub: whether the hub sends the points' velocities, and the time between two
/// consecutive samples (`seq` one apart) it differentiates over.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct VelocityConfig {
    /// `true`: a [`PoseVelocities`] after every pose frame whose sample follows the previous
    /// pose's; `false`: none (the hub starts so).
    pub enabled: bool,
    /// The nodes' sample period, microseconds: `1..=`[`MAX_VELOCITY_PERIOD_US`] when enabled
    /// (a hub rejects another and keeps the setting in force).
    pub period_us: u32,
    /// `true` asks the hub to answer with a [`Status`](crate::Status).
    pub request_status: bool,
}

/// The longest sample period a [`VelocityConfig`] may give: one second (1 Hz).
pub const MAX_VELOCITY_PERIOD_US: u32 = 1_000_000;

impl VelocityConfig {
    /// Velocities off (the hub's setting when it starts).
    pub const OFF: VelocityConfig = VelocityConfig {
        enabled: false,
        period_us: 0,
        request_status: false,
    };

    /// Whether a hub takes this setting: off, or on with a period in
    /// `1..=`[`MAX_VELOCITY_PERIOD_US`].
    pub fn is_usable(&self) -> bool {
        !self.enabled || (1..=MAX_VELOCITY_PERIOD_US).contains(&self.period_us)
    }
}

/// Hub to host: the velocities of the points of the [`PoseFrame`](crate::PoseFrame) of the same
/// `seq`, sent right after it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PoseVelocities {
    /// The pose frame's `seq`; the angles were differenced against those of the pose frame
    /// `seq − 1` (wrapping).
    pub seq: u32,
    /// The time the difference is over, microseconds (the configured period).
    pub dt_us: u32,
    /// The points' velocities, metres per second, in [`point`] order and the pose frame's
    /// axes (ground, relative to the pelvis origin).
    pub velocities: [[f32; 3]; point::COUNT],
}

/// First-order backward difference of two samples' angles over `dt` seconds:
/// `(now − before) / dt`, joint by joint, in `T` (`f32` on the hub, `f64` on the host).
#[inline(always)]
pub fn backward_difference<T, const N: usize>(before: &[T; N], now: &[T; N], dt: T) -> [T; N]
where
    T: Copy + core::ops::Sub<Output = T> + core::ops::Div<Output = T>,
{
    core::array::from_fn(|i| (now[i] - before[i]) / dt)
}
