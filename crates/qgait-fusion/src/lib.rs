#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod raw;
pub mod sto;

use qgait_kernel::fusion::{ErrorRms, OrientationError, Vqf, VqfParams};

pub use raw::{read_csv, read_xsens, RawRecording};
pub use sto::write_orientations;

/// Why a recording cannot be read, fused or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FusionError {
    /// A file could not be read or written.
    #[error("{path}: {error}")]
    Io {
        /// The file.
        path: String,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A column the command needs is not in the header.
    #[error("{path}:1: no column `{name}` (the raw layout: time, gyr_x..z in rad/s, acc_x..z in m/s², mag_x..z in µT for 9D)")]
    MissingColumn {
        /// The file.
        path: String,
        /// The column's name.
        name: String,
    },
    /// A cell or a row is not what the layout says.
    #[error("{path}:{line}: {message}")]
    Format {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong, naming the column where there is one.
        message: String,
    },
    /// The times do not give one sampling period (VQF needs a constant one).
    #[error("{path}:{line}: {message}")]
    Timing {
        /// The file.
        path: String,
        /// 1-based line of the first time that does not fit.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// 9D asked of a recording without a magnetometer.
    #[error("{path}: no magnetometer columns (mag_x..z or Mag_X..Z): use --mode 6d")]
    NoMagnetometer {
        /// The file.
        path: String,
    },
    /// Several recordings whose samples do not line up.
    #[error("{path}: {message}")]
    Mismatch {
        /// The file that differs from the first.
        path: String,
        /// How.
        message: String,
    },
    /// A vendor file (Xsens) that cannot be read.
    #[error(transparent)]
    Vendor(#[from] qgait_opensim::mot::MotError),
}

/// Which sensors the filter uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Gyroscope, accelerometer and magnetometer: heading from the magnetic field, the earth
    /// frame ENU (x east, y magnetic north, z up).
    NineD,
    /// Gyroscope and accelerometer: the earth frame has z up and the start's heading, which
    /// drifts with the gyroscope's remaining bias.
    SixD,
}

/// VQF (default parameters, `f64`) over a whole recording: the orientation after every sample,
/// `(w, x, y, z)` from the sensor frame to the earth frame. `progress` is told how many samples
/// are done, every 4,096 samples and at the end.
pub fn fuse(
    recording: &RawRecording,
    mode: Mode,
    mut progress: impl FnMut(usize),
) -> Result<Vec<[f64; 4]>, FusionError> {
    let mag = match mode {
        Mode::NineD => Some(
            recording
                .mag
                .as_ref()
                .ok_or_else(|| FusionError::NoMagnetometer {
                    path: recording.source.clone(),
                })?,
        ),
        Mode::SixD => None,
    };
    let mut vqf = Vqf::<f64>::new(&VqfParams::default(), recording.period);
    let n = recording.len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        vqf.update(recording.gyr[i], recording.acc[i], mag.map(|m| m[i]));
        out.push(match mode {
            Mode::NineD => vqf.quat_9d(),
            Mode::SixD => vqf.quat_6d(),
        });
        if (i + 1) % 4096 == 0 {
            progress(i + 1);
        }
    }
    progress(n);
    Ok(out)
}

/// BROAD's errors of `estimate` against the recording's reference orientations
/// ([`RawRecording::truth`]) over its scored rows (`movement` = 1, or every row without that
/// column, where the reference is present): total, heading and inclination RMSE in degrees and
/// the number of rows scored; `None` without reference orientations or scored rows.
pub fn score(recording: &RawRecording, estimate: &[[f64; 4]]) -> Option<([f64; 3], usize)> {
    let truth = recording.truth.as_ref()?;
    let mut rms = ErrorRms::new();
    for (i, (q, opt)) in estimate.iter().zip(truth).enumerate() {
        let moving = recording.movement.as_ref().is_none_or(|m| m[i]);
        if let (true, Some(opt)) = (moving, opt) {
            if let Some(e) = OrientationError::between(*q, *opt) {
                rms.add(e);
            }
        }
    }
    (rms.count() > 0).then(|| (rms.rms_deg(), rms.count()))
}
