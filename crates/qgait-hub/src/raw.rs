//! [`RawInput`]: raw IMU samples to fused orientations, by the rules of `docs/protocol.md`
//! section 4.10, for as many segments at once as its capacity `N`: one implementation for the
//! IMU node (`qgait-node`, one segment) and the hub's raw input (up to eight), so both fuse a
//! sensor's samples the same way, bit for bit.

use crate::counters::bump;
use qgait_kernel::fusion::{FusionReal, Vqf, VqfParams};
use qgait_proto::{
    segment_bit, FusionMode, RawImuConfig, RawImuSample, RawImuStatus, SampleHeader, SegmentId,
    SegmentOrientation, PROTOCOL_VERSION,
};

/// The farthest a sample may be ahead of or behind the previous one of its segment without
/// restarting the segment's fusion (protocol.md 4.10, rule 2).
pub const MAX_SEQ_STEP: u32 = 1024;

/// A [`RawImuConfig`] for `segments` of ICM-20948 sensors (±2000 °/s at 16.4 counts per °/s,
/// ±16 g at 2048 counts per g, the AK09916's 0.15 µT per count) at 100 Hz, an orientation
/// every sample, no status request.
pub fn icm20948_config(segments: u8, fusion: FusionMode) -> RawImuConfig {
    RawImuConfig {
        segments,
        fusion,
        rate_hz: 100,
        output_every: 1,
        gyro_per_count: RawImuConfig::gyro_per_count_of(16.4),
        accel_per_count: RawImuConfig::accel_per_count_of(2048.0),
        mag_per_count: 0.15,
        request_status: false,
    }
}

/// What [`RawInput::push`] did with a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RawOutcome<T> {
    /// Its segment is not configured (`not_configured`): dropped.
    NotConfigured,
    /// Repeated or out of order (`stale_samples`): dropped.
    Stale,
    /// Fused; with the segment's orientation (`w, x, y, z`, sensor frame to the fusion's z-up
    /// world) if its `seq` is a multiple of `output_every`.
    Fused(Option<[T; 4]>),
}

/// One segment's fusion.
#[derive(Debug, Clone, Copy)]
struct Slot<T: FusionReal> {
    segment: SegmentId,
    vqf: Vqf<T>,
    /// `seq` and timestamp of the last sample used; `None`: the fusion starts afresh with the
    /// next sample.
    last: Option<(u32, u32)>,
}

/// The raw input of a receiver: its [`RawImuConfig`], one kernel [`Vqf`] per configured
/// segment (at most `N`), and its counters. Generic over the scalar: `f32` on a device, `f64`
/// on the host (the same rules, the reference's arithmetic).
#[derive(Debug, Clone)]
pub struct RawInput<T: FusionReal, const N: usize> {
    config: RawImuConfig,
    slots: [Option<Slot<T>>; N],
    status: RawImuStatus,
}

/// The settings before any [`RawImuConfig`]: no raw segment.
const UNCONFIGURED: RawImuConfig = RawImuConfig {
    segments: 0,
    fusion: FusionMode::NineD,
    rate_hz: 100,
    output_every: 1,
    gyro_per_count: 1.0,
    accel_per_count: 1.0,
    mag_per_count: 1.0,
    request_status: false,
};

impl<T: FusionReal, const N: usize> Default for RawInput<T, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: FusionReal, const N: usize> RawInput<T, N> {
    /// No raw segment until a [`configure`](Self::configure); every counter 0.
    pub fn new() -> Self {
        RawInput {
            config: UNCONFIGURED,
            slots: [None; N],
            status: RawImuStatus::default(),
        }
    }

    /// Writes [`new`](Self::new)'s value into `this` field by field, slot by slot, so that no
    /// whole `RawInput` (eight filters, kilobytes) is a temporary on the stack on its way there
    /// (`Hub::init`).
    ///
    /// # Safety
    ///
    /// `this` must be valid for writes of a `RawInput` and properly aligned.
    #[cfg(feature = "raw")]
    #[allow(unsafe_code)]
    pub(crate) unsafe fn write_new(this: *mut Self) {
        // SAFETY: the caller's promise; each field is written once through a pointer to it,
        // the slots one element at a time, and nothing is read.
        unsafe {
            core::ptr::addr_of_mut!((*this).config).write(UNCONFIGURED);
            core::ptr::addr_of_mut!((*this).status).write(RawImuStatus::default());
            let slots = core::ptr::addr_of_mut!((*this).slots).cast::<Option<Slot<T>>>();
            for i in 0..N {
                slots.add(i).write(None);
            }
        }
    }

    /// The settings in force (`segments` 0 before any accepted configuration; its
    /// `request_status` always `false`).
    pub fn config(&self) -> RawImuConfig {
        self.config
    }

    /// The counters.
    pub fn status(&self) -> RawImuStatus {
        self.status
    }

    /// Takes `config` if it is [`usable`](RawImuConfig::usable) and names at most `N` segments:
    /// each of its segments' fusion starts afresh (the counters go on). `false`: refused,
    /// the settings in force stay (a receiver counts it in `config_rejected`).
    pub fn configure(&mut self, config: &RawImuConfig) -> bool {
        if !config.usable() || config.segments.count_ones() as usize > N {
            return false;
        }
        let vqf = Vqf::new(&VqfParams::default(), 1.0 / f64::from(config.rate_hz));
        let mut segments = SegmentId::ALL
            .into_iter()
            .filter(|&s| config.segments & segment_bit(s) != 0);
        for slot in self.slots.iter_mut() {
            *slot = segments.next().map(|segment| Slot {
                segment,
                vqf,
                last: None,
            });
        }
        self.config = RawImuConfig {
            request_status: false,
            ..*config
        };
        true
    }

    /// One sample, by protocol.md 4.10's rules 1 to 6 (counted in [`status`](Self::status)).
    pub fn push(&mut self, sample: &RawImuSample) -> RawOutcome<T> {
        let c = self.config;
        let status = &mut self.status;
        // Rule 1: a configured segment.
        let Some(slot) = self
            .slots
            .iter_mut()
            .flatten()
            .find(|s| s.segment == sample.header.segment)
        else {
            bump(&mut status.not_configured);
            return RawOutcome::NotConfigured;
        };
        // Rule 2: placed against the previous sample of the segment.
        let mut steps = 1u32;
        let mut dt_us = None;
        match slot.last {
            None => slot.vqf.reset_state(),
            Some((seq, timestamp)) => {
                let d = sample.header.seq.wrapping_sub(seq);
                if d == 0 || d >= 0u32.wrapping_sub(MAX_SEQ_STEP) {
                    bump(&mut status.stale_samples);
                    return RawOutcome::Stale;
                } else if d > MAX_SEQ_STEP {
                    bump(&mut status.resyncs);
                    slot.vqf.reset_state();
                } else {
                    if d > 1 {
                        bump(&mut status.rate_gaps);
                        status.samples_lost = status.samples_lost.wrapping_add(d - 1);
                    }
                    steps = d;
                    dt_us = Some(sample.header.timestamp_us.wrapping_sub(timestamp));
                }
            }
        }
        slot.last = Some((sample.header.seq, sample.header.timestamp_us));
        // Rule 3.
        bump(&mut status.samples_accepted);
        if sample.saturated() {
            bump(&mut status.saturated);
        }
        // Rule 4.
        let nine_d = c.fusion == FusionMode::NineD;
        if nine_d && sample.mag.is_none() {
            bump(&mut status.missing_magnetometer);
        }
        // Rule 5: the step, as dt / T (the rate in Hz, times in µs: |dt - d·T| ≤ T / 2 is
        // |dt·rate - d·1e6| ≤ 5e5, in integers).
        let rate = u64::from(c.rate_hz);
        let scale = match dt_us {
            // The first sample of a fusion: one period.
            None => None,
            Some(dt) => {
                let (measured, nominal) = (u64::from(dt) * rate, u64::from(steps) * 1_000_000);
                if 2 * measured.abs_diff(nominal) > 1_000_000 {
                    bump(&mut status.timing_errors);
                    (steps > 1).then(|| T::from_f32(steps as f32))
                } else if measured != 1_000_000 {
                    // dt × rate / 1e6, dt exact in f32 below 2^24 µs (16 s).
                    Some(T::from_f32(dt as f32) * T::from_f32(c.rate_hz.into()) / T::from_f32(1e6))
                } else {
                    None
                }
            }
        };
        // Rule 6: fused. The filter runs at the period T: a step of dt integrates the rate
        // times dt / T.
        let f = |x: f32| T::from_f32(x);
        let mut gyr = sample.gyro.map(|g| f(g.into()) * f(c.gyro_per_count));
        if let Some(k) = scale {
            gyr = gyr.map(|g| g * k);
        }
        let acc = sample.accel.map(|a| f(a.into()) * f(c.accel_per_count));
        let mag = sample
            .mag
            .filter(|_| nine_d)
            .map(|m| m.map(|m| f(m.into()) * f(c.mag_per_count)));
        slot.vqf.update(gyr, acc, mag);
        RawOutcome::Fused(
            sample
                .header
                .seq
                .is_multiple_of(c.output_every.into())
                .then(|| {
                    if nine_d {
                        slot.vqf.quat_9d()
                    } else {
                        slot.vqf.quat_6d()
                    }
                }),
        )
    }
}

/// The [`SegmentOrientation`] a node sends for `sample`'s orientation `q`: the same node,
/// segment, `seq` and timestamp, `q` in Q14 (protocol.md 4.7), quality 0.
pub fn orientation_packet<T: FusionReal>(sample: &RawImuSample, q: [T; 4]) -> SegmentOrientation {
    SegmentOrientation {
        header: SampleHeader {
            version: PROTOCOL_VERSION,
            ..sample.header
        },
        q14: SegmentOrientation::q14_of(q.map(T::to_f64)),
        quality: 0,
    }
}
