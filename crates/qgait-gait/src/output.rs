//! The whole analysis of `qgait gait` and the files it writes: `events.csv`,
//! `spatiotemporal.csv`, `gps.csv`, `cycles/*.csv`, the figures and `report.html`.

use crate::angles::{Seen, Variable};
use crate::cycles::Curve;
use crate::error::ReportError;
use crate::gps::{self, every_2_percent, Scores};
use crate::normative::{Band, Kinematics, NormativeError, Range, Speed, StpNormals, STP_COLUMNS};
use crate::number::round;
use crate::rules::Mode;
use crate::session::Session;
use crate::spatiotemporal::{self, Parameter};
use crate::stream::{EventsCsv, Finished, Pool, Recording};
use crate::{CycleMode, Walk};

/// `--reference`.
#[derive(Clone, Debug, PartialEq)]
pub enum ReferenceArg {
    /// The normative data at a speed (`None`: from the measured speed).
    Normative(Option<Speed>),
    /// Another recording, analysed the same way.
    Motion(String),
}

impl ReferenceArg {
    /// `normative`, `normative:SPEED` or a motion.
    pub fn parse(s: &str) -> Result<Self, NormativeError> {
        match s.split_once(':') {
            None if s == "normative" => Ok(Self::Normative(None)),
            Some(("normative", speed)) => Speed::parse(speed)
                .map(|v| Self::Normative(Some(v)))
                .ok_or_else(|| NormativeError::UnknownSpeed {
                    arg: s.to_string(),
                    speed: speed.to_string(),
                }),
            _ => Ok(Self::Motion(s.to_string())),
        }
    }
}

/// The reference curves: mean and SD at 51 points per side and variable.
pub struct Reference {
    /// What it is, for titles (`Schwartz 2008, free speed` or the motion's label).
    pub label: String,
    /// The normative speed, when the reference is the normative data.
    pub speed: Option<Speed>,
    /// Bands per side and variable ([`Variable::ALL`] order).
    pub bands: [[Option<Band>; 9]; 2],
    /// Normative bands of angles the models do not give (knee varus/valgus and rotation), by
    /// (row, column) of the kinematics figure.
    pub extra: Vec<((usize, usize), String, Band)>,
    /// The reference recording's own spatiotemporal parameters (none for the normative data).
    pub parameters: Vec<Parameter>,
    /// The reference's toe off per side (% of the cycle): the normal one ([`Reference::toe_off_range`]'s
    /// centre, both sides) or the reference recording's measured mean.
    pub toe_off: [Option<f64>; 2],
    /// The normal range of the toe off (the stance phase's normal range), for the normative data.
    pub toe_off_range: Option<Range>,
    /// Where [`Reference::toe_off`] comes from, for legends (empty when there is none).
    pub toe_off_from: String,
}

impl Reference {
    /// What the reference is, for legends and captions: the normative data's label, or
    /// `reference recording LABEL` (a recording's label alone could read as a normative
    /// group: `normal`).
    pub fn legend(&self) -> String {
        if self.speed.is_some() {
            self.label.clone()
        } else {
            format!("reference recording {}", self.label)
        }
    }
}

/// Everything the report shows.
pub struct Report {
    /// The recordings.
    pub recordings: Vec<Recording>,
    /// `events.csv`: written as the recordings were read, or its text.
    pub events: EventsCsv,
    /// Individual strides' curves per side (`[variable][point]`, degrees): a bounded sample
    /// ([`crate::stream::STRIDE_SAMPLE`]) spread over the recordings.
    pub stride_sample: [Vec<[Vec<f64>; 9]>; 2],
    /// The model's name.
    pub model: String,
    /// `--cycle`.
    pub mode: CycleMode,
    /// Mean and SD per side and variable (101 points).
    pub curves: [[Option<Curve>; 9]; 2],
    /// Mean toe off per side (% of the cycle).
    pub toe_off: [Option<f64>; 2],
    /// Spatiotemporal parameters with their normal ranges where known.
    pub parameters: Vec<Parameter>,
    /// The pace group of the normal ranges (`Normal`, `Slow`, ...), and for whom.
    pub ranges_for: Option<String>,
    /// The reference.
    pub reference: Reference,
    /// Scores against the reference, when the recordings have joint angles.
    pub scores: Option<Scores>,
    /// Non-dimensional walking speed and leg length (m), when known.
    pub dimensionless_speed: Option<(f64, f64)>,
    /// How the normative speed group was chosen from the cadence, when it was.
    pub speed_choice: Option<String>,
    /// The scores a member of the reference population has ([`gps::normal_scores`]), when the
    /// subject has scores: the MAP's normal reference.
    pub normal_scores: Option<Scores>,
    /// What every recording's (and the reference recording's) model can move
    /// ([`crate::trial::Trial::seen`]): the report leaves out the other variables (and step
    /// width when it cannot be seen), and says why ([`Seen::note`]).
    pub seen: Seen,
    /// The subject and the session, for the header ([`build`] leaves it empty: the caller
    /// fills it in).
    pub session: Session,
    /// Every warning the run emitted about its inputs, in order (the caller's: [`build`]
    /// leaves it empty).
    pub warnings: Vec<String>,
}

impl Report {
    /// The joint angles the report shows ([`Seen::variables`]).
    pub fn variables(&self) -> Vec<Variable> {
        self.seen.variables()
    }
}

/// Subject details for the normal ranges.
#[derive(Clone, Copy, Debug, Default)]
pub struct Subject {
    /// Age in years.
    pub age: Option<f64>,
    /// `Some(true)` male, `Some(false)` female, `None` either.
    pub male: Option<bool>,
}

/// `male`, `female` or `male or female`, for messages.
fn sex_words(male: Option<bool>) -> &'static str {
    match male {
        Some(true) => "male",
        Some(false) => "female",
        None => "male or female",
    }
}

/// Folds walks in memory, each a whole recording, into a pool (`events.csv` kept as text).
pub fn pool_of(walks: &[Walk]) -> Result<Finished, ReportError> {
    let mut pool = Pool::in_memory(walks.len() > 1);
    for w in walks {
        pool.add(w, f64::NEG_INFINITY..f64::INFINITY, true)
            .map_err(|error| ReportError::Csv {
                file: "events.csv",
                error,
            })?;
    }
    finish(pool)
}

/// [`Pool::finish`] as a report's error.
pub fn finish(pool: Pool) -> Result<Finished, ReportError> {
    pool.finish().map_err(|error| ReportError::Io {
        path: "events.csv".into(),
        action: "write",
        error,
    })
}

/// Builds the report from analysed walks, each a whole recording held in memory.
pub fn build(
    walks: Vec<Walk>,
    model: String,
    mode: CycleMode,
    reference: &ReferenceArg,
    reference_walks: Option<Vec<Walk>>,
    normative: &crate::normative::Source,
    subject: Subject,
) -> Result<Report, ReportError> {
    let pool = pool_of(&walks)?;
    drop(walks);
    let reference_pool = match reference_walks {
        Some(rw) => Some(pool_of(&rw)?),
        None => None,
    };
    build_from(
        pool,
        model,
        mode,
        reference,
        reference_pool,
        normative,
        subject,
    )
}

/// Builds the report from recordings folded into a pool ([`crate::stream`]); `reference_pool`
/// holds the reference motion's (`--reference MOTION`).
pub fn build_from(
    pool: Finished,
    model: String,
    mode: CycleMode,
    reference: &ReferenceArg,
    reference_pool: Option<Finished>,
    normative: &crate::normative::Source,
    subject: Subject,
) -> Result<Report, ReportError> {
    let Finished(pool, events) = pool;
    // The report leaves out each angle a model cannot move (its curves are flat), the
    // reference's too: what every recording's model and the reference recording's can move.
    let seen = pool
        .recordings
        .iter()
        .chain(reference_pool.iter().flat_map(|p| &p.0.recordings))
        .fold(Seen::ALL, |a, r| a.and(r.seen));
    let variables = seen.variables();
    let shown = |v: usize| variables.contains(&Variable::ALL[v]);
    let mut curves = pool.curves();
    for side in &mut curves {
        for (v, c) in side.iter_mut().enumerate() {
            if !shown(v) {
                *c = None;
            }
        }
    }
    let toe_off = pool.toe_off_percent();
    let mut parameters = parameters_of_pool(&pool);
    let walks = &pool.recordings;
    check_possible(walks, pool.leg_length(), &parameters)?;
    let running = walks
        .iter()
        .any(|w| w.gait.as_ref().is_some_and(|g| g.mode == Mode::Running));
    let speed = spatiotemporal::value(&parameters, "speed", "both");
    let speed_measured = speed;
    let leg = pool.leg_length();
    let dimensionless_speed = match (speed, leg) {
        (Some(v), Some(l)) if l > 0.0 => Some((v / (9.81 * l).sqrt(), l)),
        _ => None,
    };
    // Normal ranges.
    let mut ranges_for = None;
    let stp_name = normative.name("stp_normals.txt");
    let needs_groups = matches!(reference, ReferenceArg::Normative(None));
    let normals = if subject.age.is_some() || needs_groups {
        Some(StpNormals::load(normative)?)
    } else {
        // Only for the normal toe off: without the table, the figure has no such line.
        StpNormals::load(normative).ok()
    };
    let cadence = spatiotemporal::value(&parameters, "cadence", "both");
    if let (Some(age), Some(normals)) = (subject.age, &normals) {
        // Asked for the normal ranges of an age the table lacks: an error rather than a report
        // without them (or with another age's) that could be read as age-matched.
        if !normals.holds(age, subject.male) {
            let (min, max) = normals.ages(subject.male).unwrap_or((f64::NAN, f64::NAN));
            return Err(NormativeError::AgeOutside {
                path: stp_name.clone(),
                age,
                sex: sex_words(subject.male),
                min,
                max,
            }
            .into());
        }
        if running {
            ranges_for =
                Some("not shown: the normal ranges are walking's, and this is running".to_string());
        } else if let Some((pace, choice, ranges)) =
            normals.ranges(age, subject.male, speed, cadence)
        {
            for p in parameters.iter_mut() {
                if let Some(k) = STP_COLUMNS.iter().position(|c| c.0 == p.name) {
                    p.range = ranges[k];
                }
            }
            let sex = sex_words(subject.male);
            // (The kinematic bands' speed group is picked by cadence, below: the two may
            // differ when the speed picks the pace.)
            let by_speed = matches!(choice, crate::normative::PaceChoice::Speed { .. });
            ranges_for = Some(format!(
                "{sex}, {age} years, pace `{pace}` {} ({}){}",
                choice.words(),
                stp_name,
                if by_speed && needs_groups {
                    "; the kinematic bands' speed group is picked by cadence, so the two may differ"
                } else {
                    ""
                }
            ));
        }
    }
    // The normative speed group from the cadence.
    let mut speed_choice = None;
    let chosen = match (needs_groups, cadence, &normals) {
        (true, Some(c), Some(n)) => n.cadence_groups(subject.age, subject.male).map(|g| {
            let speed = g.group(c);
            let range = match g.range(speed) {
                (None, Some(hi)) => format!("below {}", round(hi, 1)),
                (Some(lo), None) => format!("from {}", round(lo, 1)),
                (Some(lo), Some(hi)) => format!("{} to {}", round(lo, 1), round(hi, 1)),
                (None, None) => String::new(),
            };
            speed_choice = Some(format!(
                "{}: cadence {} steps/min, in its range {range} steps/min (from the slow, normal and fast cadence of {}, {})",
                speed.words(),
                round(c, 1),
                g.from,
                stp_name
            ));
            speed
        }),
        _ => None,
    };
    let reference = match (reference, reference_pool) {
        (ReferenceArg::Normative(speed), _) => {
            let speed = speed.or(chosen).unwrap_or(Speed::Free);
            let mut r = normative_reference(normative, speed)?;
            // The normal toe off: the end of the normal stance phase, walking's only.
            let range = normals
                .as_ref()
                .filter(|_| !running)
                .and_then(|n| n.stance(subject.age, subject.male, speed_measured, cadence));
            if let Some(range) = range {
                let centre = (range.min + range.max) / 2.0;
                r.toe_off = [Some(centre); 2];
                r.toe_off_range = Some(range);
                r.toe_off_from = format!(
                    "normal stance {}-{} % ({}, {})",
                    round(range.min, 1),
                    round(range.max, 1),
                    match subject.age {
                        Some(a) => format!("{}, {} years", sex_words(subject.male), round(a, 1)),
                        None => format!("{} adults", sex_words(subject.male)),
                    },
                    stp_name
                );
            }
            r
        }
        (ReferenceArg::Motion(m), Some(rw)) => {
            let c = rw.0.curves();
            let label =
                rw.0.recordings
                    .first()
                    .map_or_else(|| m.clone(), |w| w.label.clone());
            let reference_parameters = parameters_of_pool(&rw.0);
            let toe_off = rw.0.toe_off_percent();
            Reference {
                toe_off_from: if toe_off.iter().any(Option::is_some) {
                    format!("{label}'s mean toe off")
                } else {
                    String::new()
                },
                parameters: reference_parameters,
                toe_off,
                toe_off_range: None,
                label,
                speed: None,
                bands: std::array::from_fn(|s| {
                    std::array::from_fn(|v| {
                        c[s][v].as_ref().map(|c| Band {
                            mean: every_2_percent(&c.mean),
                            sd: every_2_percent(&c.sd),
                        })
                    })
                }),
                extra: Vec::new(),
            }
        }
        (ReferenceArg::Motion(m), None) => {
            return Err(ReportError::ReferenceNotAnalysed(m.clone()))
        }
    };
    let mut reference = reference;
    if !seen.is_all() {
        for side in &mut reference.bands {
            for (v, b) in side.iter_mut().enumerate() {
                if !shown(v) {
                    *b = None;
                }
            }
        }
        // Knee varus and rotation: frontal and transverse, drawn only where the model moves
        // some frontal or transverse quantity.
        if seen.is_planar() {
            reference.extra.clear();
        }
    }
    let subject_curves: gps::Curves = std::array::from_fn(|s| {
        std::array::from_fn(|v| curves[s][v].as_ref().map(|c| every_2_percent(&c.mean)))
    });
    let reference_curves: gps::Curves = std::array::from_fn(|s| {
        std::array::from_fn(|v| reference.bands[s][v].as_ref().map(|b| b.mean.clone()))
    });
    let has_angles = walks.iter().any(|w| w.has_angles);
    let scores =
        has_angles.then(|| gps::scores_over(&subject_curves, &reference_curves, &variables));
    let reference_sd: gps::Curves = std::array::from_fn(|s| {
        std::array::from_fn(|v| reference.bands[s][v].as_ref().map(|b| b.sd.clone()))
    });
    let normal_scores = has_angles.then(|| gps::normal_scores_over(&reference_sd, &variables));
    let stride_sample = pool.stride_sample().clone();
    Ok(Report {
        recordings: pool.recordings,
        events,
        stride_sample,
        model,
        mode,
        curves,
        toe_off,
        parameters,
        ranges_for,
        reference,
        scores,
        dimensionless_speed,
        speed_choice,
        normal_scores,
        seen,
        session: Session::default(),
        warnings: Vec::new(),
    })
}

/// The spatiotemporal parameters of a pool's strides, with the rules' findings of each
/// recording that had them in every window and the events' method.
fn parameters_of_pool(pool: &Pool) -> Vec<Parameter> {
    let rules: Vec<Option<&crate::rules::Gait>> = pool
        .recordings
        .iter()
        .map(|r| r.gait.as_ref().filter(|_| r.rules_everywhere))
        .collect();
    let events = spatiotemporal::one_method(pool.recordings.iter().map(Recording::event_method));
    spatiotemporal::parameters_of(&pool.strides, &rules, events)
}

/// What a human can do, per parameter: `(name, least, most)`; the leg length is checked
/// apart.
pub const POSSIBLE: [(&str, f64, f64); 9] = [
    ("cadence", 20.0, 300.0),
    ("stance", 0.0, 100.0),
    ("swing", 0.0, 100.0),
    ("double_support", 0.0, 100.0),
    ("flight", 0.0, 100.0),
    ("speed", 0.0, 12.5),
    ("stride_length", 0.0, 6.0),
    ("step_length", 0.0, 6.0),
    ("duty_factor", 0.0, 1.0),
];

/// Leg length (m) a human can have.
pub const POSSIBLE_LEG: (f64, f64) = (0.3, 1.5);

/// [`ReportError::Impossible`] for the first parameter outside [`POSSIBLE`] or a leg length
/// outside [`POSSIBLE_LEG`]; `leg_length` is the longest hip-to-ankle distance of the
/// recordings.
pub fn check_possible(
    walks: &[Recording],
    leg_length: Option<f64>,
    parameters: &[Parameter],
) -> Result<(), ReportError> {
    let recordings = walks
        .iter()
        .map(|w| w.source.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    for p in parameters {
        let (Some(&(_, min, max)), Some(value)) =
            (POSSIBLE.iter().find(|c| c.0 == p.name), p.value)
        else {
            continue;
        };
        {
            if !(value >= min && value <= max) {
                return Err(ReportError::Impossible {
                    recordings,
                    what: format!("{} ({})", p.name, p.side),
                    value: round(value, 3),
                    unit: p.unit,
                    min,
                    max,
                });
            }
        }
    }
    // The rules' speed, which stands even without a complete stride.
    for w in walks {
        if let Some(g) = &w.gait {
            let (_, min, max) = POSSIBLE[5];
            if !(g.speed >= min && g.speed <= max) {
                return Err(ReportError::Impossible {
                    recordings: w.source.clone(),
                    what: format!("speed ({})", g.speed_method.note()),
                    value: round(g.speed, 3),
                    unit: "m/s",
                    min,
                    max,
                });
            }
        }
    }
    let legs = walks
        .iter()
        .filter_map(|w| w.gait.as_ref().map(|g| g.leg_length))
        .chain(leg_length.filter(|_| walks.iter().all(|w| w.gait.is_none())));
    for l in legs {
        let (min, max) = POSSIBLE_LEG;
        if !(l >= min && l <= max) {
            return Err(ReportError::Impossible {
                recordings,
                what: "leg length".into(),
                value: round(l, 3),
                unit: "m",
                min,
                max,
            });
        }
    }
    Ok(())
}

/// The normative data at one speed as a reference.
pub fn normative_reference(
    source: &crate::normative::Source,
    speed: Speed,
) -> Result<Reference, NormativeError> {
    let k = Kinematics::load(source, speed)?;
    let mut bands: [[Option<Band>; 9]; 2] = Default::default();
    for (v, var) in Variable::ALL.iter().enumerate() {
        let (name, axis) = var.normative();
        let b = k.band(name, axis)?;
        bands[0][v] = b.clone();
        bands[1][v] = b;
    }
    let mut extra = Vec::new();
    for (cell, name, axis, title) in [
        ((2, 1), "KneeAngles", "Y", "Knee varus (var +)"),
        ((2, 2), "KneeAngles", "Z", "Knee rotation (int +)"),
    ] {
        if let Some(b) = k.band(name, axis)? {
            extra.push((cell, title.to_string(), b));
        }
    }
    Ok(Reference {
        label: format!(
            "Schwartz et al. 2008, {} speed ({})",
            speed.key(),
            source.describe()
        ),
        speed: Some(speed),
        bands,
        extra,
        parameters: Vec::new(),
        toe_off: [None; 2],
        toe_off_range: None,
        toe_off_from: String::new(),
    })
}
