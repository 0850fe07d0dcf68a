//! `qgait imu-signals`: what IMUs fixed to a model's bodies measure during a motion, as
//! OpenSim's `IMU` component and `IMUDataReporter` give it, with optional sensor noise and bias.
//!
//! Frames (the kernel's `differential::imu_signals`): `orientations.sto` holds the IMU frame's
//! orientation in ground (OpenSense's quaternion `.sto`, `w,x,y,z` per cell);
//! `angular_velocity.sto` the gyroscope, the IMU frame's angular velocity relative to ground
//! expressed in the IMU frame (rad/s); `linear_acceleration.sto` the accelerometer, the IMU
//! origin's acceleration in ground minus gravity `(0, −9.80665, 0)`, expressed in the IMU frame
//! (m/s²). One column per IMU, named as the IMU, each cell `x,y,z`. The pelvis translation of
//! the motion is included (the accelerometer needs its acceleration). With a magnetic field
//! (`--magnetic-field`), `magnetometer.sto` holds that field expressed in the IMU frame (µT).
//!
//! Each IMU's samples are also written as a raw recording in the shared CSV layout
//! (`raw/NAME.csv`: `time`, `gyr_x..z`, `acc_x..z`, and `mag_x..z` with a field), the input
//! of `qgait fuse` and of `qgait packets --raw`: what a raw IMU node would measure.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;
use rand::{Rng, SeedableRng};
use rand_distr::StandardNormal;
use serde::Deserialize;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use crate::cli::three_numbers;
use qgait_kernel::differential::{imu_signals, ImuMount};
use qgait_kernel::Vec3;
use qgait_model::derivatives::{MotionModel, Series};
use qgait_model::motion::source::load_motion;

/// `qgait imu-signals` arguments.
#[derive(Debug, Args)]
pub struct ImuSignalsArgs {
    /// Motion file (.mot, or an OpenSim 4 states .sto whose `/speed` columns are then used).
    pub motion: String,
    /// The model (default gait2392). HAK and PHAK have the bodies pelvis (origin midway
    /// between the hips, not gait2392's), femur, tibia and talus (the whole foot, origin at the
    /// ankle centre) per side, no calcn or toes; HAK's pelvis is level.
    #[command(flatten)]
    pub model: ModelArgs,
    /// The IMUs: TOML, `[[imu]]` tables with `name`, `body` (pelvis, femur_r, tibia_r, talus_r,
    /// calcn_r, toes_r and the same _l; HAK and PHAK: pelvis, femur, tibia, talus), the
    /// `translation` (m, body frame) and `orientation`
    /// (body-fixed X-Y-Z Euler angles, rad: R_body_imu = Rx Ry Rz), as an OpenSim
    /// PhysicalOffsetFrame carrying an IMU.
    #[arg(long, value_name = "PLACEMENT.toml")]
    pub imus: PathBuf,
    /// Output directory: orientations.sto, angular_velocity.sto, linear_acceleration.sto.
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Low-pass cut-off (Hz) of the coordinates before they are differentiated (zero-phase
    /// 4th-order Butterworth; not applied to coordinates whose speeds are in the file).
    #[arg(long, value_name = "HZ")]
    pub lowpass: Option<f64>,
    /// Output sampling rate (Hz): the motion's rate divided by a whole number (every k-th row).
    /// Default: the motion's.
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Gyroscope white noise as a density (rad/s/√Hz): per sample a Gaussian of standard
    /// deviation density·√(rate) on each axis.
    #[arg(long, value_name = "RAD/S/√HZ", conflicts_with = "gyro_noise_std")]
    pub gyro_noise_density: Option<f64>,
    /// Gyroscope white noise as a standard deviation per sample and axis (rad/s).
    #[arg(long, value_name = "RAD/S")]
    pub gyro_noise_std: Option<f64>,
    /// Accelerometer white noise as a density (m/s²/√Hz): standard deviation density·√(rate).
    #[arg(long, value_name = "M/S²/√HZ", conflicts_with = "accel_noise_std")]
    pub accel_noise_density: Option<f64>,
    /// Accelerometer white noise as a standard deviation per sample and axis (m/s²).
    #[arg(long, value_name = "M/S²")]
    pub accel_noise_std: Option<f64>,
    /// Gyroscope constant bias, the same for every IMU, in the IMU frame (rad/s): `X,Y,Z`.
    #[arg(long, value_name = "X,Y,Z", value_parser = three_numbers, allow_hyphen_values = true)]
    pub gyro_bias: Option<[f64; 3]>,
    /// Gyroscope bias random walk (rad/s/√s): each IMU's bias moves by a Gaussian step of
    /// standard deviation walk·√Δt per sample and axis, from the constant bias.
    #[arg(long, value_name = "RAD/S/√S")]
    pub gyro_bias_walk: Option<f64>,
    /// A homogeneous magnetic field in ground (µT, OpenSim axes: x forward, y up, z right),
    /// `X,Y,Z`: adds the magnetometer (the field in the IMU frame, plus `--mag-noise-std`), so
    /// that 9D fusion has a heading reference. Earth's is 25 to 65 µT, pointing down in the
    /// northern hemisphere (y < 0).
    #[arg(long, value_name = "X,Y,Z", value_parser = three_numbers, allow_hyphen_values = true)]
    pub magnetic_field: Option<[f64; 3]>,
    /// Magnetometer white noise as a standard deviation per sample and axis (µT).
    #[arg(long, value_name = "UT", requires = "magnetic_field")]
    pub mag_noise_std: Option<f64>,
    /// Seed of the noise (the same seed and qgait build give the same noise).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// PLACEMENT.toml.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Placement {
    imu: Vec<ImuEntry>,
}

/// One `[[imu]]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ImuEntry {
    name: String,
    body: String,
    translation: [f64; 3],
    orientation: [f64; 3],
}

/// Writes one OpenSim `.sto` of `Vec3` or `Quaternion` cells (as `STOFileAdapter` does).
fn write_sto(
    path: &Path,
    data_type: &str,
    rate: f64,
    names: &[String],
    time: &[f64],
    cells: &[Vec<Vec<f64>>],
) -> anyhow::Result<()> {
    let file = std::fs::File::create(path).with_context(|| path.display().to_string())?;
    let mut w = std::io::BufWriter::new(file);
    writeln!(w, "DataRate={rate:.6}")?;
    writeln!(w, "DataType={data_type}")?;
    writeln!(w, "version=3")?;
    writeln!(w, "OpenSimVersion=4.6")?;
    writeln!(w, "endheader")?;
    writeln!(w, "time\t{}", names.join("\t"))?;
    for (t, row) in time.iter().zip(cells) {
        write!(w, "{t}")?;
        for cell in row {
            let text: Vec<String> = cell.iter().map(|v| v.to_string()).collect();
            write!(w, "\t{}", text.join(","))?;
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}

/// A standard deviation per sample from a density or a standard deviation.
fn per_sample(density: Option<f64>, std: Option<f64>, rate: f64) -> f64 {
    density.map(|d| d * rate.sqrt()).or(std).unwrap_or(0.0)
}

/// Runs `qgait imu-signals`.
pub fn run_imu_signals(a: ImuSignalsArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(&a.imus).with_context(|| a.imus.display().to_string())?;
    let placement: Placement =
        toml::from_str(&text).with_context(|| format!("{}", a.imus.display()))?;
    let model = MotionModel::new(&a.model.load_or("gait2392", diagnostics)?)?;
    let bodies = model.body_names();
    let mounts = placement
        .imu
        .iter()
        .map(|e| {
            let body = bodies.iter().position(|b| *b == e.body).with_context(|| {
                format!(
                    "{}: IMU `{}`: unknown body `{}`: {} has the bodies {}",
                    a.imus.display(),
                    e.name,
                    e.body,
                    a.model.name_or("gait2392"),
                    bodies.join(", ")
                )
            })?;
            Ok((
                body,
                ImuMount::from_xyz(Vec3::from_f64(e.translation), e.orientation),
            ))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let (table, w) = load_motion(&a.motion)?;
    diagnostics.warn(w);
    let (series, w) = Series::of(&table, a.lowpass, &model)?;
    diagnostics.warn(w);
    let input_rate = 1.0 / series.step();
    let every = match a.rate {
        None => 1,
        Some(hz) => {
            let k = (input_rate / hz).round();
            anyhow::ensure!(
                hz > 0.0 && k >= 1.0 && (input_rate / k - hz).abs() <= 1e-6 * hz,
                "--rate {hz}: the motion's rate ({input_rate} Hz) divided by a whole number is needed"
            );
            k as usize
        }
    };
    let rate = input_rate / every as f64;
    let dt = 1.0 / rate;
    let gyro_sd = per_sample(a.gyro_noise_density, a.gyro_noise_std, rate);
    let accel_sd = per_sample(a.accel_noise_density, a.accel_noise_std, rate);
    let walk_sd = a.gyro_bias_walk.unwrap_or(0.0) * dt.sqrt();
    let bias0 = a.gyro_bias.unwrap_or([0.0; 3]);
    let mut bias = vec![bias0; mounts.len()];
    let mut rng = rand::rngs::SmallRng::seed_from_u64(a.seed);
    let mut gauss = |sd: f64| -> f64 {
        if sd == 0.0 {
            0.0
        } else {
            sd * rng.sample::<f64, _>(StandardNormal)
        }
    };
    let field = a.magnetic_field.map(|[x, y, z]| Vec3::new(x, y, z));
    let mag_sd = a.mag_noise_std.unwrap_or(0.0);
    let (mut time, mut orientations, mut gyros, mut accels, mut mags) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for r in (0..series.time.len()).step_by(every) {
        let bodies = model.bodies(&series.q[r], &series.qd[r], &series.qdd[r]);
        let (mut o_row, mut g_row, mut a_row, mut m_row) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, (body, mount)) in mounts.iter().enumerate() {
            let s = imu_signals(&bodies[*body].moved_by(&series.pelvis[r]), mount);
            let q = s.orientation;
            o_row.push(vec![q.w, q.x, q.y, q.z]);
            let b = &mut bias[i];
            g_row.push(
                [s.gyroscope.x, s.gyroscope.y, s.gyroscope.z]
                    .iter()
                    .zip(b.iter())
                    .map(|(v, b)| v + b + gauss(gyro_sd))
                    .collect(),
            );
            for b in b.iter_mut() {
                *b += gauss(walk_sd);
            }
            let acc = s.accelerometer;
            a_row.push(
                [acc.x, acc.y, acc.z]
                    .iter()
                    .map(|v| v + gauss(accel_sd))
                    .collect(),
            );
            if let Some(field) = field {
                // The field in ground, seen from the IMU frame.
                let m = q.conj().rotate(field);
                m_row.push([m.x, m.y, m.z].iter().map(|v| v + gauss(mag_sd)).collect());
            }
        }
        time.push(series.time[r]);
        orientations.push(o_row);
        gyros.push(g_row);
        accels.push(a_row);
        mags.push(m_row);
    }
    std::fs::create_dir_all(&a.output).with_context(|| a.output.display().to_string())?;
    let names: Vec<String> = placement.imu.iter().map(|e| e.name.clone()).collect();
    let files = [
        ("orientations.sto", "Quaternion", &orientations),
        ("angular_velocity.sto", "Vec3", &gyros),
        ("linear_acceleration.sto", "Vec3", &accels),
    ];
    for (file, kind, cells) in files {
        write_sto(&a.output.join(file), kind, rate, &names, &time, cells)?;
    }
    let mags = field.map(|_| &mags);
    if let Some(mags) = mags {
        write_sto(
            &a.output.join("magnetometer.sto"),
            "Vec3",
            rate,
            &names,
            &time,
            mags,
        )?;
    }
    let raw = a.output.join("raw");
    std::fs::create_dir_all(&raw).with_context(|| raw.display().to_string())?;
    for (i, name) in names.iter().enumerate() {
        let column = |rows: &[Vec<Vec<f64>>]| -> Vec<Vec<f64>> {
            rows.iter().map(|row| row[i].clone()).collect()
        };
        write_raw_csv(
            &raw.join(format!("{name}.csv")),
            &time,
            &column(&gyros),
            &column(&accels),
            mags.map(|m| column(m)).as_deref(),
        )?;
    }
    Ok(())
}

/// Writes one IMU's samples as a raw recording in the shared CSV layout (`qgait fuse`'s).
fn write_raw_csv(
    path: &Path,
    time: &[f64],
    gyr: &[Vec<f64>],
    acc: &[Vec<f64>],
    mag: Option<&[Vec<f64>]>,
) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path).with_context(|| path.display().to_string())?;
    let mut header = vec!["time", "gyr_x", "gyr_y", "gyr_z", "acc_x", "acc_y", "acc_z"];
    if mag.is_some() {
        header.extend(["mag_x", "mag_y", "mag_z"]);
    }
    w.write_record(&header)?;
    for (k, t) in time.iter().enumerate() {
        let mut row = vec![t.to_string()];
        let cells = [Some(&gyr[k]), Some(&acc[k]), mag.map(|m| &m[k])];
        for cell in cells.into_iter().flatten() {
            row.extend(cell.iter().map(|v| v.to_string()));
        }
        w.write_record(&row)?;
    }
    w.flush().with_context(|| path.display().to_string())?;
    Ok(())
}
