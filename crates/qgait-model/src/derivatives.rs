//! Differential kinematics of a motion (`qgait fk --derivatives`, `qgait imu-signals`): the
//! coordinates of every row with their speeds and accelerations ([`Series`]), and the kernel's
//! evaluators of a model on them ([`MotionModel`]: an OpenSim leg chain, HAK or PHAK). All the maths is
//! `qgait_kernel::differential`'s; this module reads the motion and picks the numbers.
//!
//! **Where `q̇` and `q̈` come from.** A coordinate whose speed is in the file (an OpenSim 4
//! states `.sto`: `/jointset/<joint>/<coordinate>/speed`) takes it as it is, and its
//! acceleration is the speed differentiated. Otherwise `q̇` and `q̈` are the kernel's
//! [`differentiate`] of the coordinate (five-point central differences, fourth order; relative
//! errors `(ωΔt)⁴/30` and `(ωΔt)⁴/90` on a component of angular frequency `ω`; the two samples
//! at each end one-sided), optionally after a low-pass filter ([`lowpass`]). On
//! `scripts/opensim_derivatives.py`'s analytic motion (components up to 3.8 Hz) the points'
//! velocities are within 1.0e-8 m/s of OpenSim's at 1 kHz and 1.0e-4 m/s at 100 Hz,
//! accelerations within 1.2e-7 and 1.2e-3 m/s² (the kernel README's measurements).
//!
//! **Frames.** Points: ground axes, origin at the pelvis origin (the positions `qgait fk`
//! writes, and their time derivatives: the pelvis translation is not in them). Bodies
//! ([`MotionModel::bodies`]): orientation, angular velocity and acceleration relative to
//! ground, in ground axes; their origins moved by the pelvis translation when the motion has
//! one ([`Series::pelvis`]).

use biquad::{Biquad, Coefficients, DirectForm2Transposed, ToHertz, Type};
use qgait_kernel::differential::{differentiate, FrameMotion, PointMotion};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::models::{LowerLimb, Phak, PhakAngles};
use qgait_kernel::{Gait2392, Vec3};
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::mot::{MotionTable, StateColumn};

use crate::choice::Model;
use crate::error::ModelError;
use crate::points::CHAIN_ORDER;

/// The pelvis translations (metres), after the 17 [`COORDINATES`].
pub const TRANSLATIONS: [&str; 3] = ["pelvis_tx", "pelvis_ty", "pelvis_tz"];

/// The bodies of a leg chain, in the order of [`MotionModel::bodies`] (gait2392's bodies; an
/// imported chain's joint frames are its bodies' frames). HAK's and PHAK's: [`STICK_BODIES`].
pub const BODIES: [&str; 11] = [
    "pelvis", "femur_r", "tibia_r", "talus_r", "calcn_r", "toes_r", "femur_l", "tibia_l",
    "talus_l", "calcn_l", "toes_l",
];

/// The coordinates of a motion with their first and second time derivatives, row by row.
#[derive(Debug, Clone)]
pub struct Series {
    /// Time of each row (s).
    pub time: Vec<f64>,
    /// The 17 [`COORDINATES`] (radians).
    pub q: Vec<[f64; 17]>,
    /// Their speeds (rad/s).
    pub qd: Vec<[f64; 17]>,
    /// Their accelerations (rad/s²).
    pub qdd: Vec<[f64; 17]>,
    /// The pelvis translation (ground, m), its velocity and acceleration; zero without columns.
    pub pelvis: Vec<PointMotion<f64>>,
    /// How many of the 20 coordinates took their speeds from the file.
    pub speeds_from_file: usize,
}

/// One coordinate's samples and, when the file has it, its speeds.
struct Column {
    values: Vec<f64>,
    speeds: Option<Vec<f64>>,
}

fn file_error(table: &MotionTable, message: String) -> ModelError {
    ModelError::File {
        at: Location::file(table.source()),
        message,
    }
}

impl Series {
    /// The coordinates of `table` (a `.mot`, or an OpenSim 4 states `.sto` whose other states,
    /// muscles' and the like, are passed over), with speeds from the file where it has them and
    /// from [`differentiate`] otherwise; `lowpass` (Hz) filters coordinates that are
    /// differentiated first ([`lowpass`]). Only the coordinates `model` reads
    /// ([`MotionModel::reads`]) are read; a coordinate it does not read is 0 with its speed
    /// and acceleration, and so is one without a column (one warning). Rows must be uniformly
    /// sampled (to 0.1 % of the step), at least five of them.
    pub fn of(
        table: &MotionTable,
        lowpass_hz: Option<f64>,
        model: &MotionModel,
    ) -> Result<(Self, Vec<Warning>), ModelError> {
        let n = table.rows();
        let time = table.time().to_vec();
        if n < 5 {
            return Err(file_error(
                table,
                format!("{n} rows: derivatives need at least 5 uniformly sampled rows"),
            ));
        }
        let dt = (time[n - 1] - time[0]) / (n - 1) as f64;
        if let Some(w) = time
            .windows(2)
            .find(|w| ((w[1] - w[0]) - dt).abs() > 1e-3 * dt)
        {
            return Err(file_error(
                table,
                format!(
                    "rows are not uniformly sampled (step {} s at time {}, mean {dt} s): derivatives need a constant step",
                    w[1] - w[0],
                    w[0]
                ),
            ));
        }
        if let Some(hz) = lowpass_hz {
            if !(hz > 0.0 && hz < 0.5 / dt) {
                return Err(file_error(
                    table,
                    format!("--lowpass {hz} Hz: the cut-off must be above 0 and below half the sampling rate ({} Hz)", 0.5 / dt),
                ));
            }
        }
        let mut warnings = Vec::new();
        let mut missing = Vec::new();
        let mut filtered_with_speeds = false;
        let names = COORDINATES.iter().chain(&TRANSLATIONS);
        let columns: Vec<Column> = names
            .enumerate()
            .map(|(i, name)| {
                let mut values = None;
                let mut speeds = None;
                for (c, label) in table.labels().iter().enumerate() {
                    match StateColumn::parse(label) {
                        Some(StateColumn::Value(s)) if s == *name => values = Some((c, true)),
                        Some(StateColumn::Speed(s)) if s == *name => speeds = Some(c),
                        None if label == name && values.is_none() => values = Some((c, false)),
                        _ => {}
                    }
                }
                let column = |c: usize| (0..n).map(|r| table.value(r, c)).collect::<Vec<f64>>();
                let Some((c, state)) = values.filter(|_| model.reads(name)) else {
                    if model.reads(name) {
                        missing.push(*name);
                    }
                    return Column {
                        values: vec![0.0; n],
                        speeds: None,
                    };
                };
                // States files are in radians; a .mot's angles may be in degrees.
                let scale = if i < 17 && table.in_degrees() && !state {
                    1f64.to_radians()
                } else {
                    1.0
                };
                let mut values = column(c);
                let mut speeds = speeds.map(column);
                if scale != 1.0 {
                    values.iter_mut().for_each(|v| *v *= scale);
                    if let Some(s) = &mut speeds {
                        s.iter_mut().for_each(|v| *v *= scale);
                    }
                }
                if let Some(hz) = lowpass_hz {
                    if speeds.is_none() {
                        values = lowpass(&values, dt, hz);
                    } else {
                        filtered_with_speeds = true;
                    }
                }
                Column { values, speeds }
            })
            .collect();
        if !missing.is_empty() {
            warnings.push(Warning::MissingDefaulted(WarningText {
                at: Some(table.labels_at()),
                detail: format!("no column for {}: taken as 0", missing.join(", ")),
            }));
        }
        if filtered_with_speeds {
            warnings.push(Warning::OptionIgnored(WarningText {
 at: Some(table.labels_at()),
 detail: "--lowpass not applied to the coordinates whose speeds are in the file (their values and speeds are used as they are)".to_string(),
}));
        }
        let mut d = vec![[0.0; 20]; n];
        let mut dd = vec![[0.0; 20]; n];
        let (mut first, mut second) = (vec![0.0; n], vec![0.0; n]);
        let mut speeds_from_file = 0;
        for (k, column) in columns.iter().enumerate() {
            match &column.speeds {
                Some(speeds) => {
                    speeds_from_file += 1;
                    differentiate(speeds, dt, &mut first, &mut second);
                    for r in 0..n {
                        d[r][k] = speeds[r];
                        dd[r][k] = first[r];
                    }
                }
                None => {
                    differentiate(&column.values, dt, &mut first, &mut second);
                    for r in 0..n {
                        d[r][k] = first[r];
                        dd[r][k] = second[r];
                    }
                }
            }
        }
        let pick17 = |row: &[f64; 20]| -> [f64; 17] { core::array::from_fn(|i| row[i]) };
        let q: Vec<[f64; 17]> = (0..n)
            .map(|r| core::array::from_fn(|i| columns[i].values[r]))
            .collect();
        let t3 = |row: &[f64; 20]| Vec3::new(row[17], row[18], row[19]);
        let pelvis = (0..n)
            .map(|r| PointMotion {
                position: Vec3::new(
                    columns[17].values[r],
                    columns[18].values[r],
                    columns[19].values[r],
                ),
                velocity: t3(&d[r]),
                acceleration: t3(&dd[r]),
            })
            .collect();
        Ok((
            Self {
                time,
                q,
                qd: d.iter().map(pick17).collect(),
                qdd: dd.iter().map(pick17).collect(),
                pelvis,
                speeds_from_file,
            },
            warnings,
        ))
    }

    /// The sampling step (s).
    pub fn step(&self) -> f64 {
        let n = self.time.len();
        (self.time[n - 1] - self.time[0]) / (n - 1) as f64
    }
}

/// A zero-phase low-pass filter of a uniformly sampled series, `dt` apart, cut-off `hz`, as
/// OpenSim's tools offer one (`lowpass_cutoff_frequency`): a 4th-order Butterworth (two
/// biquad sections, the `biquad` crate's bilinear-transform designs with Q 0.5412 and 1.3066)
/// run forward and then backward over the series (no phase lag; the magnitude is the
/// Butterworth's squared, `1 / (1 + (f/f_c)⁸)`: −6 dB at the cut-off, 0.39 % down at half
/// of it). Before filtering the series is extended at each end by its odd reflection (6 cut-off
/// periods, at most the series' length) and each pass starts from its first sample, so the
/// ends carry no start-up transient of note. The reflection keeps the level and slope at an
/// end but flips its curvature: within about two cut-off periods of an end the derivatives
/// are biased (the host README gives figures).
pub fn lowpass(x: &[f64], dt: f64, hz: f64) -> Vec<f64> {
    let n = x.len();
    if n < 2 {
        return x.to_vec();
    }
    let fs = 1.0 / dt;
    let pad = ((6.0 * fs / hz).ceil() as usize).clamp(1, n - 1);
    let mut y: Vec<f64> = Vec::with_capacity(n + 2 * pad);
    y.extend((1..=pad).rev().map(|k| 2.0 * x[0] - x[k]));
    y.extend_from_slice(x);
    y.extend((1..=pad).map(|k| 2.0 * x[n - 1] - x[n - 1 - k]));
    let pass = |y: &mut Vec<f64>| {
        let start = y[0];
        let mut sections = [0.541_196_100_146_197, 1.306_562_964_876_376_7].map(|q| {
            let c = Coefficients::<f64>::from_params(Type::LowPass, fs.hz(), hz.hz(), q)
                .expect("the cut-off is checked to be below half the sampling rate");
            DirectForm2Transposed::<f64>::new(c)
        });
        for v in y.iter_mut() {
            let mut s = *v - start;
            for f in &mut sections {
                s = f.run(s);
            }
            *v = s + start;
        }
    };
    pass(&mut y);
    y.reverse();
    pass(&mut y);
    y.reverse();
    y[pad..pad + n].to_vec()
}

/// The bodies of HAK and PHAK, in the order of [`MotionModel::bodies`]: their joint frames,
/// named as the gait2392 bodies they stand for. `pelvis`: origin midway between the hip
/// centres (not gait2392's pelvis origin), turned by pelvis rotation and list only (PHAK has no
/// tilt; HAK's is level). `femur`, `tibia`: origins at the hip and knee centres, as gait2392's.
/// `talus`: the whole foot, one rigid segment from the ankle centre (gait2392's talus origin)
/// to the toe tip, turned by the ankle angle about the pelvis's z axis. There is no `calcn` or
/// `toes`: the foot has no subtalar or MTP joint.
pub const STICK_BODIES: [&str; 7] = [
    "pelvis", "femur_r", "tibia_r", "talus_r", "femur_l", "tibia_l", "talus_l",
];

/// The kernel's differential kinematics of a model: an OpenSim leg chain (a gait2392-family
/// model or an imported chain), or HAK or PHAK.
pub enum MotionModel {
    /// A gait2392-family model.
    Gait2392(Box<Gait2392<f64>>),
    /// An imported chain.
    Chain(Box<LowerLimb<f64>>),
    /// PHAK, or HAK (`hak`: PHAK with a level pelvis, [`Phak::fk_hak`]).
    Stick {
        /// The chain.
        phak: Box<Phak<f64>>,
        /// HAK: the pelvis angles are not read and count as 0, and so do their speeds.
        hak: bool,
    },
}

/// Where each of [`PhakAngles::NAMES`] is in [`COORDINATES`].
fn phak_in_coordinates() -> [usize; 8] {
    PhakAngles::<f64>::NAMES.map(|name| {
        COORDINATES
            .iter()
            .position(|c| *c == name)
            .expect("PHAK's coordinates are gait2392's")
    })
}

impl MotionModel {
    /// The evaluators of `model`.
    pub fn new(model: &Model) -> Result<Self, ModelError> {
        let rejected = |error| ModelError::Rejected {
            name: model.name().to_string(),
            error,
        };
        Ok(match model {
            Model::Gait2392 { geometry, .. } => {
                Self::Gait2392(Box::new(Gait2392::<f64>::new(geometry).map_err(rejected)?))
            }
            Model::Chain { chain, name } => Self::Chain(Box::new(chain.chain(name)?)),
            Model::Hak { .. } | Model::Phak { .. } => Self::Stick {
                phak: Box::new(
                    Phak::new(&model.lengths().expect("a stick model")).map_err(rejected)?,
                ),
                hak: matches!(model, Model::Hak { .. }),
            },
        })
    }

    /// Whether the model reads coordinate `name` (of [`COORDINATES`] and [`TRANSLATIONS`]):
    /// every one for a leg chain; PHAK's eight and the translations for PHAK; HAK's six leg
    /// angles and the translations for HAK.
    pub fn reads(&self, name: &str) -> bool {
        match self {
            Self::Gait2392(_) | Self::Chain(_) => true,
            Self::Stick { hak, .. } => {
                let names = &PhakAngles::<f64>::NAMES[if *hak { 2 } else { 0 }..];
                names.contains(&name) || TRANSLATIONS.contains(&name)
            }
        }
    }

    /// The points of [`point_names`](crate::points::point_names): positions, velocities and
    /// accelerations in ground axes, relative to the pelvis origin (the positions `qgait fk`
    /// writes for the model, and their time derivatives). A leg chain gives the 12 of
    /// `point_names(true)`, HAK and PHAK the 8 of `point_names(false)`.
    pub fn points(&self, q: &[f64; 17], qd: &[f64; 17], qdd: &[f64; 17]) -> Vec<PointMotion<f64>> {
        let chain_points = |p: [PointMotion<f64>; 12]| CHAIN_ORDER.iter().map(|&i| p[i]).collect();
        match self {
            Self::Gait2392(g) => chain_points(g.chain().forward_motion(q, qd, qdd)),
            Self::Chain(c) => chain_points(c.forward_motion(q, qd, qdd)),
            Self::Stick { phak, .. } => {
                let [q, qd, qdd] = self.stick([q, qd, qdd]);
                phak.chain().forward_motion(&q, &qd, &qdd).to_vec()
            }
        }
    }

    /// The names of the bodies [`MotionModel::bodies`] gives, in its order: [`BODIES`] for a
    /// leg chain, [`STICK_BODIES`] for HAK and PHAK.
    pub fn body_names(&self) -> &'static [&'static str] {
        match self {
            Self::Gait2392(_) | Self::Chain(_) => &BODIES,
            Self::Stick { .. } => &STICK_BODIES,
        }
    }

    /// The bodies' motions in ground (origins relative to the pelvis origin), in
    /// [`MotionModel::body_names`] order.
    pub fn bodies(&self, q: &[f64; 17], qd: &[f64; 17], qdd: &[f64; 17]) -> Vec<FrameMotion<f64>> {
        match self {
            Self::Gait2392(g) => g.chain().motions(q, qd, qdd).to_vec(),
            Self::Chain(c) => c.motions(q, qd, qdd).to_vec(),
            Self::Stick { phak, .. } => {
                let [q, qd, qdd] = self.stick([q, qd, qdd]);
                phak.chain().motions(&q, &qd, &qdd).to_vec()
            }
        }
    }

    /// PHAK's inputs (coordinates, speeds or accelerations) from gait2392's: HAK's pelvis
    /// ones 0 ([`PhakAngles::level_pelvis`]).
    fn stick(&self, rows: [&[f64; 17]; 3]) -> [[f64; 8]; 3] {
        let hak = matches!(self, Self::Stick { hak: true, .. });
        let at = phak_in_coordinates();
        rows.map(|row| {
            let a = PhakAngles::from_array(at.map(|i| row[i]));
            if hak { a.level_pelvis() } else { a }.to_array()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lowpass_keeps_what_is_well_below_the_cut_off_and_removes_what_is_above() {
        let dt = 0.001;
        let wave = |f: f64| -> Vec<f64> {
            (0..4000)
                .map(|i| (2.0 * std::f64::consts::PI * f * i as f64 * dt).sin())
                .collect()
        };
        let gain = |f: f64| {
            let y = lowpass(&wave(f), dt, 6.0);
            // The amplitude in the middle of the series.
            y[1000..3000].iter().fold(0.0f64, |m, v| m.max(v.abs()))
        };
        // 1 / (1 + (f/fc)^8): 0.9961 at half the cut-off, 0.5 at it, 0.0039 at twice it.
        assert!((gain(3.0) - 0.9961).abs() < 2e-3, "{}", gain(3.0));
        assert!((gain(6.0) - 0.5).abs() < 1e-2, "{}", gain(6.0));
        assert!(gain(12.0) < 0.006, "{}", gain(12.0));
        // A constant and a straight line pass unchanged (ends included).
        let line: Vec<f64> = (0..3000).map(|i| 0.3 + 0.002 * i as f64).collect();
        let y = lowpass(&line, dt, 6.0);
        let worst = y
            .iter()
            .zip(&line)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(worst < 1e-6, "{worst}");
    }
}
