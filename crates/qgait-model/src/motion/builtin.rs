//! A built-in normative gait cycle, usable wherever a motion file is: `builtin:normal`,
//! `builtin:crouch=0.6` (crouch severity 0..1), optionally followed by `,rows=N` (default 101
//! rows over one cycle of 1 s).
//!
//! # How it is made
//! Each coordinate is a smooth periodic curve: the key-event values below (degrees, right limb,
//! percent of the cycle from right initial contact) are joined by straight lines, and the
//! result is reduced to its mean plus the first [`HARMONICS`] Fourier harmonics (a truncated
//! discrete Fourier series over 400 samples). The left limb is the right limb half a cycle
//! later. The output columns carry OpenSim gait2392 names and signs (hip flexion > 0, knee
//! flexion < 0 as `knee_angle`, ankle dorsiflexion > 0), in degrees. The fitted curves pass
//! within 3.6° of every key event (the largest miss is the knee's swing peak, 56.6° for 60°;
//! hip and ankle within 1.7°, pelvis within 0.4°).
//!
//! # Sources of the values
//! Typical adult values at the gait events of Perry J. & Burnfield J. M., *Gait Analysis: Normal
//! and Pathological Function*, 2nd ed., SLACK, 2010 (chapters on the ankle, knee, hip and
//! pelvis), which agree with the mean curves of Kadaba M. P. et al., "Measurement of lower
//! extremity kinematics during level walking", *J. Orthop. Res.* 8(3):383-392, 1990, and of
//! Winter D. A., *Biomechanics and Motor Control of Human Movement*, 4th ed., Wiley, 2009. Values
//! are rounded to whole degrees; they describe a typical adult, not a specific subject.
//!
//! | coordinate (clinical sign) | key events: (% cycle, degrees) |
//! |---|---|
//! | hip flexion | (0, 30) initial contact, (10, 29), (30, 10), (50, -10) peak extension, (62, 0) toe-off, (75, 22), (87, 33) peak flexion, (100, 30) |
//! | knee flexion | (0, 5), (13, 18) loading-response peak, (38, 5), (50, 10), (62, 40) toe-off, (73, 60) swing peak, (87, 25), (97, 2), (100, 5) |
//! | ankle dorsiflexion | (0, 0), (10, -5) loading-response plantarflexion, (30, 5), (48, 10) peak dorsiflexion, (62, -15) toe-off, (75, -5), (87, 0), (100, 0) |
//! | pelvis rotation (+ = right side forward) | (0, 5), (25, 0), (50, -5), (75, 0), (100, 5) |
//! | pelvic obliquity, OpenSim `pelvis_list` (+ = right side down) | (0, 0), (15, -4) contralateral drop, (35, -2), (50, 0), (65, 4), (85, 2), (100, 0) |
//!
//! # Crouch severity
//! `crouch=s` (0 ≤ s ≤ 1) moves the sagittal angles toward a severe crouch gait like the shared
//! OpenSim `crouch4.mot` (cycle means: hip flexion 45°, knee flexion 50°, ankle dorsiflexion
//! 23° right and 5° left, with a smaller knee and ankle excursion than normal gait). The normal
//! curves have cycle means of 15° hip flexion, 21° knee flexion and -1° ankle dorsiflexion; at
//! s = 1 they become 48°, 49° and 14°. Each angle becomes
//! `mean + (1 - s (1 - k)) (curve - mean) + s Δ` with
//!
//! | coordinate | Δ at s = 1 | excursion factor k at s = 1 |
//! |---|---|---|
//! | hip flexion | +33° | 1.0 |
//! | knee flexion | +28° | 0.6 |
//! | ankle dorsiflexion | +15° | 0.65 |
//!
//! The pelvis curves are left as in normal gait (the large constant pelvis rotation and list of
//! `crouch4.mot` come from that subject's heading and posture, not from crouch itself).

use qgait_kernel::PhakAngles;

use qgait_opensim::mot::MotionTable;

/// Number of Fourier harmonics kept per coordinate.
pub const HARMONICS: usize = 6;

/// Default number of rows of a built-in motion (0 %, 1 %, ..., 100 %).
pub const DEFAULT_ROWS: usize = 101;

/// Most rows of a built-in motion: one cycle sampled at 1 MHz. The motion is generated whole
/// (about 80 MB at this size), so the count is bounded.
pub const MAX_ROWS: usize = 1_000_000;

/// Samples used to compute the Fourier coefficients of the key-event polyline.
const FIT_SAMPLES: usize = 400;

/// Key events (% cycle, degrees, clinical sign) of one coordinate.
type KeyEvents = &'static [(f64, f64)];

/// Hip flexion, degrees.
pub const HIP_FLEXION: KeyEvents = &[
    (0.0, 30.0),
    (10.0, 29.0),
    (30.0, 10.0),
    (50.0, -10.0),
    (62.0, 0.0),
    (75.0, 22.0),
    (87.0, 33.0),
    (100.0, 30.0),
];
/// Knee flexion (clinical sign: flexion > 0), degrees.
pub const KNEE_FLEXION: KeyEvents = &[
    (0.0, 5.0),
    (13.0, 18.0),
    (38.0, 5.0),
    (50.0, 10.0),
    (62.0, 40.0),
    (73.0, 60.0),
    (87.0, 25.0),
    (97.0, 2.0),
    (100.0, 5.0),
];
/// Ankle dorsiflexion, degrees.
pub const ANKLE_DORSIFLEXION: KeyEvents = &[
    (0.0, 0.0),
    (10.0, -5.0),
    (30.0, 5.0),
    (48.0, 10.0),
    (62.0, -15.0),
    (75.0, -5.0),
    (87.0, 0.0),
    (100.0, 0.0),
];
/// Pelvis rotation (right side forward > 0), degrees.
pub const PELVIS_ROTATION: KeyEvents = &[
    (0.0, 5.0),
    (25.0, 0.0),
    (50.0, -5.0),
    (75.0, 0.0),
    (100.0, 5.0),
];
/// Pelvic obliquity as OpenSim `pelvis_list` (right side down > 0), degrees.
pub const PELVIS_LIST: KeyEvents = &[
    (0.0, 0.0),
    (15.0, -4.0),
    (35.0, -2.0),
    (50.0, 0.0),
    (65.0, 4.0),
    (85.0, 2.0),
    (100.0, 0.0),
];

/// Crouch change of one sagittal coordinate at severity 1.
struct Crouch {
    offset_deg: f64,
    excursion_factor: f64,
}
const HIP_CROUCH: Crouch = Crouch {
    offset_deg: 33.0,
    excursion_factor: 1.0,
};
const KNEE_CROUCH: Crouch = Crouch {
    offset_deg: 28.0,
    excursion_factor: 0.6,
};
const ANKLE_CROUCH: Crouch = Crouch {
    offset_deg: 15.0,
    excursion_factor: 0.65,
};

/// A parsed `builtin:` specification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuiltinSpec {
    /// Crouch severity, 0 (normal gait) to 1 (severe crouch).
    pub crouch: f64,
    /// Number of rows over the cycle (at least 2).
    pub rows: usize,
}

/// A `builtin:` spec that names no built-in gait: the spec and what is wrong with it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{spec}: {problem}")]
pub struct BuiltinError {
    /// The spec as given.
    pub spec: String,
    /// What is wrong.
    pub problem: Problem,
}

const USAGE: &str = "expected `builtin:normal` or `builtin:crouch=S` (0 <= S <= 1), optionally followed by `,rows=N`";

/// What is wrong with a `builtin:` spec.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Problem {
    /// Not `normal` or `crouch=S`.
    #[error("unknown built-in gait `{0}`; {USAGE}")]
    Unknown(String),
    /// `crouch=S` with S not a number.
    #[error("crouch severity `{0}` is not a number; {USAGE}")]
    Severity(String),
    /// `crouch=S` with S outside 0..1.
    #[error("crouch severity {0} is outside 0..1")]
    SeverityOutside(f64),
    /// `rows=N` with N not a whole number from 2 to [`MAX_ROWS`].
    #[error("rows must be a whole number from 2 to {MAX_ROWS}, found `{0}`")]
    Rows(String),
    /// An option other than `rows=N`.
    #[error("unknown option `{0}`; {USAGE}")]
    Option(String),
    /// `rows=N` given twice.
    #[error("`rows` given twice; {USAGE}")]
    Repeated,
}

impl BuiltinSpec {
    /// Parses the text after `builtin:`: `normal` or `crouch=S`, then optionally `,rows=N`.
    pub fn parse(text: &str) -> Result<Self, BuiltinError> {
        let bad = |problem| BuiltinError {
            spec: format!("builtin:{text}"),
            problem,
        };
        let mut parts = text.split(',');
        let kind = parts.next().unwrap_or("").trim();
        let crouch = if kind == "normal" {
            0.0
        } else if let Some(s) = kind.strip_prefix("crouch=") {
            let s: f64 = s
                .trim()
                .parse()
                .map_err(|_| bad(Problem::Severity(s.to_string())))?;
            if !(0.0..=1.0).contains(&s) {
                return Err(bad(Problem::SeverityOutside(s)));
            }
            s
        } else {
            return Err(bad(Problem::Unknown(kind.to_string())));
        };
        let mut rows = None;
        for part in parts {
            match part.trim().strip_prefix("rows=") {
                Some(_) if rows.is_some() => return Err(bad(Problem::Repeated)),
                Some(n) => {
                    rows = n
                        .trim()
                        .parse()
                        .ok()
                        .filter(|n| (2..=MAX_ROWS).contains(n))
                        .map(Some)
                        .ok_or_else(|| bad(Problem::Rows(n.to_string())))?
                }
                None => return Err(bad(Problem::Option(part.to_string()))),
            }
        }
        Ok(Self {
            crouch,
            rows: rows.unwrap_or(DEFAULT_ROWS),
        })
    }

    /// The spec as text, e.g. `builtin:crouch=0.6`.
    pub fn label(&self) -> String {
        if self.crouch == 0.0 {
            "builtin:normal".into()
        } else {
            format!("builtin:crouch={}", self.crouch)
        }
    }
}

/// A truncated Fourier series `a0 + Σ (a_k cos kθ + b_k sin kθ)`, θ = 2π · percent / 100.
#[derive(Debug, Clone, PartialEq)]
pub struct Harmonics {
    /// Mean value.
    pub a0: f64,
    /// Cosine coefficients for k = 1..=HARMONICS.
    pub a: [f64; HARMONICS],
    /// Sine coefficients for k = 1..=HARMONICS.
    pub b: [f64; HARMONICS],
}

impl Harmonics {
    /// Fits the key-event polyline (which must start at 0 % and end at 100 %).
    pub fn fit(events: KeyEvents) -> Self {
        let samples: Vec<f64> = (0..FIT_SAMPLES)
            .map(|i| polyline(events, 100.0 * i as f64 / FIT_SAMPLES as f64))
            .collect();
        let n = FIT_SAMPLES as f64;
        let a0 = samples.iter().sum::<f64>() / n;
        let (mut a, mut b) = ([0.0; HARMONICS], [0.0; HARMONICS]);
        for k in 1..=HARMONICS {
            for (i, v) in samples.iter().enumerate() {
                let (s, c) = (std::f64::consts::TAU * (k * i) as f64 / n).sin_cos();
                a[k - 1] += 2.0 / n * v * c;
                b[k - 1] += 2.0 / n * v * s;
            }
        }
        Self { a0, a, b }
    }

    /// Value at `percent` of the cycle (periodic).
    pub fn eval(&self, percent: f64) -> f64 {
        let theta = std::f64::consts::TAU * percent / 100.0;
        (1..=HARMONICS).fold(self.a0, |acc, k| {
            let (s, c) = (k as f64 * theta).sin_cos();
            acc + self.a[k - 1] * c + self.b[k - 1] * s
        })
    }
}

/// Linear interpolation of the key events at `percent` (0..100).
fn polyline(events: KeyEvents, percent: f64) -> f64 {
    let i = events
        .iter()
        .rposition(|&(p, _)| p <= percent)
        .unwrap_or(0)
        .min(events.len() - 2);
    let ((p0, v0), (p1, v1)) = (events[i], events[i + 1]);
    v0 + (v1 - v0) * (percent - p0) / (p1 - p0)
}

/// One sagittal coordinate, with its crouch change applied.
fn crouched(h: &Harmonics, crouch: &Crouch, severity: f64, percent: f64) -> f64 {
    let scale = 1.0 - severity * (1.0 - crouch.excursion_factor);
    h.a0 + scale * (h.eval(percent) - h.a0) + severity * crouch.offset_deg
}

/// The OpenSim column names of a built-in motion, after `time`: PHAK's coordinates
/// ([`PhakAngles::NAMES`]) with `pelvis_list` first.
pub const COLUMNS: [&str; 8] = {
    let n = PhakAngles::<f64>::NAMES;
    [n[1], n[0], n[2], n[3], n[4], n[5], n[6], n[7]]
};

/// Generates the motion (degrees, one cycle over 1 s).
pub fn generate(spec: &BuiltinSpec) -> MotionTable {
    let (hip, knee, ankle) = (
        Harmonics::fit(HIP_FLEXION),
        Harmonics::fit(KNEE_FLEXION),
        Harmonics::fit(ANKLE_DORSIFLEXION),
    );
    let (rotation, list) = (Harmonics::fit(PELVIS_ROTATION), Harmonics::fit(PELVIS_LIST));
    let s = spec.crouch;
    let leg = |p: f64| {
        [
            crouched(&hip, &HIP_CROUCH, s, p),
            -crouched(&knee, &KNEE_CROUCH, s, p),
            crouched(&ankle, &ANKLE_CROUCH, s, p),
        ]
    };
    let mut columns = vec![Vec::with_capacity(spec.rows); COLUMNS.len() + 1];
    for i in 0..spec.rows {
        let p = 100.0 * i as f64 / (spec.rows - 1) as f64;
        let (right, left) = (leg(p), leg(p + 50.0));
        let row = [
            p / 100.0,
            list.eval(p),
            rotation.eval(p),
            right[0],
            right[1],
            right[2],
            left[0],
            left[1],
            left[2],
        ];
        for (col, v) in columns.iter_mut().zip(row) {
            col.push(v);
        }
    }
    let labels = std::iter::once("time")
        .chain(COLUMNS)
        .map(str::to_string)
        .collect();
    let name = spec.label().replace(':', "_");
    MotionTable::new(name, spec.label(), true, labels, columns)
        .expect("generated motion is well formed")
        .in_gait2392_signs()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_specs_say_what_is_wrong() {
        let problem = |t: &str| BuiltinSpec::parse(t).unwrap_err().problem;
        assert_eq!(problem("crouch=2"), Problem::SeverityOutside(2.0));
        assert_eq!(problem("crouch=x"), Problem::Severity("x".into()));
        assert_eq!(problem("run"), Problem::Unknown("run".into()));
        assert_eq!(problem("normal,rows=1"), Problem::Rows("1".into()));
        assert_eq!(
            problem("normal,rows=1000001"),
            Problem::Rows("1000001".into())
        );
        assert_eq!(
            problem("normal,rows=18446744073709551615"),
            Problem::Rows("18446744073709551615".into())
        );
        assert!(BuiltinSpec::parse("normal,rows=1000000").is_ok());
        assert_eq!(problem("normal,fast"), Problem::Option("fast".into()));
        assert_eq!(problem("crouch=0.5,rows=2,rows=3"), Problem::Repeated);
        let e = BuiltinSpec::parse("crouch=2").unwrap_err().to_string();
        assert_eq!(e, "builtin:crouch=2: crouch severity 2 is outside 0..1");
        assert_eq!(
            BuiltinSpec::parse("crouch=0.5,rows=11").unwrap(),
            BuiltinSpec {
                crouch: 0.5,
                rows: 11
            }
        );
    }

    #[test]
    fn harmonics_follow_the_key_events() {
        for events in [
            HIP_FLEXION,
            KNEE_FLEXION,
            ANKLE_DORSIFLEXION,
            PELVIS_ROTATION,
            PELVIS_LIST,
        ] {
            let h = Harmonics::fit(events);
            for &(p, v) in events {
                assert!(
                    (h.eval(p) - v).abs() < 4.5,
                    "at {p} %: {} vs {v}",
                    h.eval(p)
                );
            }
        }
    }

    #[test]
    fn spec_parsing() {
        assert_eq!(
            BuiltinSpec::parse("normal").unwrap(),
            BuiltinSpec {
                crouch: 0.0,
                rows: 101
            }
        );
        assert_eq!(
            BuiltinSpec::parse("crouch=0.6,rows=11").unwrap(),
            BuiltinSpec {
                crouch: 0.6,
                rows: 11
            }
        );
        assert!(BuiltinSpec::parse("crouch=1.5").is_err());
        assert!(BuiltinSpec::parse("crouch=x").is_err());
        assert!(BuiltinSpec::parse("run").is_err());
        assert!(BuiltinSpec::parse("normal,rows=1").is_err());
    }
}
