//! The points' velocities (protocol.md 4.11): the angles' first-order backward difference
//! between consecutive samples, in `f32`, which the kernel's `forward_velocities` turns into
//! the points' velocities ([`Kinematics::encode_pose_velocities`]).
//!
//! `q̇ₖ = (qₖ − qₖ₋₁) / T`: causal, half a sample late (`T / 2`). There is a difference only
//! when the sample follows the last one sent by one `seq`: none for the first sample after the
//! start, a [`VelocityConfig`] that changes the setting, a configuration that takes effect
//! ([`reset`](Differentiator::reset)), or a gap in `seq`.
//!
//! Only with the feature `velocity` (about 8.6 KB of flash on the Cortex-M4F); without it the
//! differentiator holds nothing, refuses to turn velocities on
//! ([`ConfigError::VelocitiesNotBuiltIn`]) and never gives a difference, so no velocity code is
//! linked.
//!
//! [`Kinematics::encode_pose_velocities`]: qgait_proto::Kinematics::encode_pose_velocities

#[cfg(feature = "velocity")]
use qgait_proto::backward_difference;
use qgait_proto::{ConfigError, JointId, VelocityConfig};

/// The velocity setting in force and the last sample posed under it.
#[derive(Debug, Clone)]
pub struct Differentiator {
    #[cfg(feature = "velocity")]
    config: VelocityConfig,
    /// The `seq` and angles of the last sample posed since the last reset, if any.
    #[cfg(feature = "velocity")]
    last: Option<(u32, [f32; JointId::COUNT])>,
}

impl Differentiator {
    /// Velocities off, nothing posed yet (the hub's start).
    pub const OFF: Differentiator = Differentiator {
        #[cfg(feature = "velocity")]
        config: VelocityConfig::OFF,
        #[cfg(feature = "velocity")]
        last: None,
    };

    /// The setting in force (`request_status` always false).
    pub fn config(&self) -> VelocityConfig {
        #[cfg(feature = "velocity")]
        {
            self.config
        }
        #[cfg(not(feature = "velocity"))]
        {
            VelocityConfig::OFF
        }
    }

    /// Without the feature `velocity`: "off" is taken (it changes nothing), "on" refused.
    #[cfg(not(feature = "velocity"))]
    pub fn configure(&mut self, config: &VelocityConfig) -> Result<(), ConfigError> {
        if config.enabled {
            Err(ConfigError::VelocitiesNotBuiltIn)
        } else {
            Ok(())
        }
    }

    /// Without the feature `velocity`: nothing to forget.
    #[cfg(not(feature = "velocity"))]
    pub fn reset(&mut self) {}

    /// Without the feature `velocity`: never a difference.
    #[cfg(not(feature = "velocity"))]
    #[inline(always)]
    pub fn next(
        &mut self,
        _seq: u32,
        _angles: &[f32; JointId::COUNT],
    ) -> Option<([f32; JointId::COUNT], u32)> {
        None
    }
}

#[cfg(feature = "velocity")]
impl Differentiator {
    /// Takes `config` if a hub can use it ([`VelocityConfig::is_usable`]); a change of setting
    /// forgets the last sample, the same setting changes nothing. Refused
    /// ([`ConfigError::VelocityPeriod`]), the setting in force stays.
    pub fn configure(&mut self, config: &VelocityConfig) -> Result<(), ConfigError> {
        if !config.is_usable() {
            return Err(ConfigError::VelocityPeriod);
        }
        let config = VelocityConfig {
            request_status: false,
            // Off, the period means nothing: every "off" is the same setting.
            period_us: if config.enabled { config.period_us } else { 0 },
            ..*config
        };
        if config != self.config {
            self.config = config;
            self.reset();
        }
        Ok(())
    }

    /// Forgets the last sample: the next one has no difference (a configuration took
    /// effect).
    pub fn reset(&mut self) {
        self.last = None;
    }

    /// The sample `seq` with these angles is being posed: its angles' speeds (rad/s, indexed
    /// by [`JointId::index`]) and the period they are over (µs), if velocities are on and the
    /// last sample posed was `seq − 1` (wrapping). Remembered as the last sample either way
    /// (when on).
    pub fn next(
        &mut self,
        seq: u32,
        angles: &[f32; JointId::COUNT],
    ) -> Option<([f32; JointId::COUNT], u32)> {
        if !self.config.enabled {
            return None;
        }
        let before = self.last.replace((seq, *angles));
        let (last_seq, last_angles) = before?;
        if seq != last_seq.wrapping_add(1) {
            return None;
        }
        let period_us = self.config.period_us;
        let dt = period_us as f32 * 1e-6;
        Some((backward_difference(&last_angles, angles, dt), period_us))
    }
}

#[cfg(all(test, feature = "velocity"))]
mod tests {
    use super::*;

    fn on(period_us: u32) -> VelocityConfig {
        VelocityConfig {
            enabled: true,
            period_us,
            request_status: false,
        }
    }

    fn angles(x: f32) -> [f32; JointId::COUNT] {
        core::array::from_fn(|i| x * (i as f32 + 1.0))
    }

    #[test]
    fn off_gives_nothing_and_remembers_nothing() {
        let mut d = Differentiator::OFF;
        assert_eq!(d.next(1, &angles(0.1)), None);
        d.configure(&on(10_000)).unwrap();
        // Sample 1 was not remembered: 2 is a first sample.
        assert_eq!(d.next(2, &angles(0.2)), None);
    }

    #[test]
    fn consecutive_samples_give_the_backward_difference() {
        let mut d = Differentiator::OFF;
        d.configure(&on(10_000)).unwrap();
        // The first sample: no previous one.
        assert_eq!(d.next(7, &angles(0.0)), None);
        let (rates, dt) = d.next(8, &angles(0.01)).unwrap();
        assert_eq!(dt, 10_000);
        for (i, r) in rates.iter().enumerate() {
            // 0.01·(i+1) rad over 10 ms.
            assert!((r - (i as f32 + 1.0)).abs() < 1e-4, "{i}: {r}");
        }
        // seq wraps.
        let mut d = Differentiator::OFF;
        d.configure(&on(5_000)).unwrap();
        assert_eq!(d.next(u32::MAX, &angles(0.0)), None);
        assert!(d.next(0, &angles(0.0)).is_some());
    }

    #[test]
    fn a_gap_or_a_reset_starts_again() {
        let mut d = Differentiator::OFF;
        d.configure(&on(10_000)).unwrap();
        assert_eq!(d.next(1, &angles(0.0)), None);
        // Sample 2 missing: 3 has no difference, 4 has one (against 3).
        assert_eq!(d.next(3, &angles(0.3)), None);
        let (rates, _) = d.next(4, &angles(0.3)).unwrap();
        assert_eq!(rates, [0.0; JointId::COUNT]);
        d.reset();
        assert_eq!(d.next(5, &angles(0.3)), None);
        assert!(d.next(6, &angles(0.3)).is_some());
        // The same setting again changes nothing; another period starts again.
        d.configure(&on(10_000)).unwrap();
        assert!(d.next(7, &angles(0.3)).is_some());
        d.configure(&on(20_000)).unwrap();
        assert_eq!(d.next(8, &angles(0.3)), None);
    }

    #[test]
    fn unusable_periods_are_refused_and_the_setting_stays() {
        let mut d = Differentiator::OFF;
        d.configure(&on(10_000)).unwrap();
        assert_eq!(d.configure(&on(0)), Err(ConfigError::VelocityPeriod));
        assert_eq!(
            d.configure(&on(1_000_001)),
            Err(ConfigError::VelocityPeriod)
        );
        assert_eq!(d.config(), on(10_000));
        // Off takes any period.
        d.configure(&VelocityConfig {
            enabled: false,
            period_us: 0,
            request_status: true,
        })
        .unwrap();
        assert_eq!(d.config(), VelocityConfig::OFF);
    }
}
