//! Why a hub refuses a configuration ([`ConfigError`]), and the limit on its lengths.

use crate::KneeDirection;

/// The longest segment length accepted, and the largest coordinate of a subject model's
/// positions and knee translations (metres).
pub const MAX_SEGMENT_M: f32 = 2.0;

/// Why a configuration cannot be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigError {
    /// Segment lengths were given with gait2392, whose lengths are in its model (generic or
    /// subject).
    AnthropometryWithGait2392,
    /// A segment length is not a finite number in `(0, MAX_SEGMENT_M]`.
    BadSegment {
        /// 0 = right leg, 1 = left leg.
        leg: u8,
        /// Index into the leg's lengths ([`segment`](crate::segment)).
        segment: u8,
    },
    /// The kernel refused the model: for HAK and PHAK this cannot happen with lengths that
    /// passed the checks above; for a subject gait2392, e.g. a zero axis or knots out of order.
    Kernel,
    /// A subject model was asked for before all its parts arrived.
    SubjectIncomplete {
        /// The upload asked for.
        upload: u8,
        /// Parts of it held (of [`SUBJECT_PARTS`](crate::SUBJECT_PARTS)).
        parts: u8,
    },
    /// A position or knee spline value of a subject model is not a finite number within
    /// `MAX_SEGMENT_M`.
    SubjectOutOfRange {
        /// 0 = right leg, 1 = left leg.
        leg: u8,
    },
    /// The reorder window asked for is not in `1..=MAX_REORDER_WINDOW`
    /// ([`MAX_REORDER_WINDOW`](crate::MAX_REORDER_WINDOW)).
    ReorderWindow(u8),
    /// A chain was asked for whose table the hub does not hold whole: another upload's, a part
    /// missing or changed (the image's CRC differs), or one it cannot compute (counts past the
    /// table's sizes, a number not finite); or by a `Config`, which cannot name one.
    ChainIncomplete {
        /// The upload asked for.
        upload: u8,
    },
    /// A chain cannot be sent to a hub: more splines, moving axes or numbers than a hub's table
    /// holds.
    ChainTooLarge,
    /// A chain with polynomial functions (OpenSim `PolynomialFunction`, Rajagopal-Lai-Uhlrich
    /// 2023's knee) cannot be sent to a hub: a hub's table holds constants, lines and splines.
    ChainPolynomial,
    /// A knee spline has more knots than a `SubjectKnee` carries.
    SubjectKnots {
        /// 0 = right leg, 1 = left leg.
        leg: u8,
        /// The spline.
        direction: KneeDirection,
    },
    /// The orientation input takes a gait2392 model (generic or a subject's): an
    /// [`ImuConfig`](crate::ImuConfig) for it with HAK or PHAK in force, or a
    /// [`Config`](crate::Config) for HAK or PHAK while it is in force.
    ImuNeedsGait2392,
    /// An [`ImuConfig`](crate::ImuConfig) for the orientation input whose segments leave out
    /// the pelvis (every coordinate is relative to it).
    ImuWithoutPelvis,
    /// An [`ImuConfig`](crate::ImuConfig) whose sensor-to-OpenSim rotation is not finite.
    ImuSettings,
    /// An [`ImuConfig`](crate::ImuConfig) for the orientation input to a hub built without it
    /// (the firmware's `imu` feature).
    ImuNotBuiltIn,
    /// A [`VelocityConfig`](crate::VelocityConfig) turning velocities on with a period of 0
    /// or over [`MAX_VELOCITY_PERIOD_US`](crate::MAX_VELOCITY_PERIOD_US) µs. No payload: a `u32`
    /// here widens every `Result<_, ConfigError>` the hub's receive loop carries, and spilled
    /// registers cost its frame 96 B of stack (the RAM budget's margin).
    VelocityPeriod,
    /// A [`VelocityConfig`](crate::VelocityConfig) turning velocities on, to a hub built
    /// without them (the firmware's `velocity` feature).
    VelocitiesNotBuiltIn,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        const LEGS: [&str; 2] = ["right", "left"];
        let leg = |l: &u8| LEGS.get(usize::from(*l)).copied().unwrap_or("?");
        match self {
            ConfigError::AnthropometryWithGait2392 => {
                f.write_str("segment lengths given with gait2392, which has its own")
            }
            ConfigError::BadSegment { leg: l, segment } => write!(
                f,
                "{} leg: segment length {segment} is not in (0, {MAX_SEGMENT_M}] m",
                leg(l)
            ),
            ConfigError::Kernel => f.write_str("the kernel refused the model"),
            ConfigError::SubjectIncomplete { upload, parts } => write!(
                f,
                "subject model {upload}: {parts} of {} parts arrived",
                crate::SUBJECT_PARTS
            ),
            ConfigError::SubjectOutOfRange { leg: l } => write!(
                f,
                "subject model, {} leg: a position or knee value is not within {MAX_SEGMENT_M} m",
                leg(l)
            ),
            ConfigError::ReorderWindow(w) => write!(
                f,
                "reorder window {w} is not in 1..={}",
                crate::MAX_REORDER_WINDOW
            ),
            ConfigError::ChainIncomplete { upload } => write!(
                f,
                "chain {upload}: the hub does not hold its whole table (a part missing or changed)"
            ),
            ConfigError::ChainTooLarge => write!(
                f,
                "the chain does not fit a hub's table: at most {} splines, {} moving axes and {} \
                 numbers",
                crate::MAX_CHAIN_SPLINES,
                crate::MAX_CHAIN_DRIVES,
                crate::MAX_CHAIN_WORDS
            ),
            ConfigError::ChainPolynomial => f.write_str(
                "the chain has polynomial functions (PolynomialFunction), which a hub does not take",
            ),
            ConfigError::SubjectKnots { leg: l, direction } => write!(
                f,
                "{} knee_{}: more than {} knots cannot be sent to the hub",
                leg(l),
                ["tx", "ty"][*direction as usize],
                crate::MAX_KNEE_KNOTS
            ),
            ConfigError::ImuNeedsGait2392 => {
                f.write_str("the orientation input takes a gait2392 model")
            }
            ConfigError::ImuWithoutPelvis => {
                f.write_str("the orientation input needs the pelvis segment")
            }
            ConfigError::ImuSettings => {
                f.write_str("a sensor-to-OpenSim angle of the IMU settings is not finite")
            }
            ConfigError::ImuNotBuiltIn => {
                f.write_str("this hub was built without the orientation input")
            }
            ConfigError::VelocityPeriod => write!(
                f,
                "velocities over a sample period not in 1..={} µs",
                crate::MAX_VELOCITY_PERIOD_US
            ),
            ConfigError::VelocitiesNotBuiltIn => {
                f.write_str("this hub was built without the points' velocities")
            }
        }
    }
}

impl core::error::Error for ConfigError {}
