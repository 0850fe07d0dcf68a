//! The whole analysis of `qgait gait` and the files it writes: `events.csv`,
//! `spatiotemporal.csv`, `gps.csv`, `cycles/*.csv`, the figures and `report.html`.

use std::io;
use std::path::{Path, PathBuf};

use crate::angles::Variable;
use crate::cycles::{Curve, POINTS};
use crate::figures::FigureError;
use crate::gps::{self, every_2_percent, Scores};
use crate::normative::{Band, Kinematics, NormativeError, Speed, StpNormals, STP_COLUMNS};
use crate::spatiotemporal::{self, Parameter, SIDES};
use crate::{curves, leg_length, toe_off_percent, CycleMode, Walk};

/// Why the report cannot be made or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReportError {
    /// The normative data cannot be used.
    #[error(transparent)]
    Normative(#[from] NormativeError),
    /// A reference motion was named but not analysed.
    #[error("--reference {0}: not analysed")]
    ReferenceNotAnalysed(String),
    /// A file or directory of the report could not be written (or read back).
    #[error("{path}: cannot {action}: {error}")]
    Io {
        /// The file or directory.
        path: String,
        /// `write`, `create`, `read`.
        action: &'static str,
        /// Why.
        error: io::Error,
    },
    /// A CSV could not be formed.
    #[error("{file}: {error}")]
    Csv {
        /// The file (`events.csv`, ...).
        file: &'static str,
        /// Why.
        error: csv::Error,
    },
    /// A figure could not be drawn.
    #[error(transparent)]
    Figure(#[from] FigureError),
}

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
}

/// Everything the report shows.
pub struct Report {
    /// The recordings.
    pub walks: Vec<Walk>,
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

/// Builds the report from analysed walks.
pub fn build(
    walks: Vec<Walk>,
    model: String,
    mode: CycleMode,
    reference: &ReferenceArg,
    reference_walks: Option<Vec<Walk>>,
    normative_dir: &Path,
    subject: Subject,
) -> Result<Report, ReportError> {
    let curves = curves(&walks);
    let toe_off = toe_off_percent(&walks);
    let mut parameters = {
        let list: Vec<spatiotemporal::Walk<'_>> = walks
            .iter()
            .map(|w| (&w.trial, w.forward.as_slice(), &w.cycles))
            .collect();
        spatiotemporal::parameters(&list)
    };
    let speed = spatiotemporal::value(&parameters, "speed", "both");
    let leg = leg_length(&walks);
    let dimensionless_speed = match (speed, leg) {
        (Some(v), Some(l)) if l > 0.0 => Some((v / (9.81 * l).sqrt(), l)),
        _ => None,
    };
    // Normal ranges.
    let mut ranges_for = None;
    let stp_path = normative_dir.join("stp_normals.txt");
    let needs_groups = matches!(reference, ReferenceArg::Normative(None));
    let normals = if subject.age.is_some() || needs_groups {
        Some(StpNormals::read(&stp_path)?)
    } else {
        None
    };
    let cadence = spatiotemporal::value(&parameters, "cadence", "both");
    if let (Some(age), Some(normals)) = (subject.age, &normals) {
        // Asked for the normal ranges of an age the table lacks: an error rather than a report
        // without them (or with another age's) that could be read as age-matched.
        if !normals.holds(age, subject.male) {
            let (min, max) = normals.ages(subject.male).unwrap_or((f64::NAN, f64::NAN));
            return Err(NormativeError::AgeOutside {
                path: stp_path.display().to_string(),
                age,
                sex: sex_words(subject.male),
                min,
                max,
            }
            .into());
        }
        if let Some((pace, choice, ranges)) = normals.ranges(age, subject.male, speed, cadence) {
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
                stp_path.display(),
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
                stp_path.display()
            ));
            speed
        }),
        _ => None,
    };
    let reference = match (reference, reference_walks) {
        (ReferenceArg::Normative(speed), _) => {
            let speed = speed.or(chosen).unwrap_or(Speed::Free);
            normative_reference(&normative_dir.join("Schwartz2008.json"), speed)?
        }
        (ReferenceArg::Motion(m), Some(rw)) => {
            let c = crate::curves(&rw);
            let label = rw
                .first()
                .map_or_else(|| m.clone(), |w| w.trial.label.clone());
            Reference {
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
    let subject_curves: gps::Curves = std::array::from_fn(|s| {
        std::array::from_fn(|v| curves[s][v].as_ref().map(|c| every_2_percent(&c.mean)))
    });
    let reference_curves: gps::Curves = std::array::from_fn(|s| {
        std::array::from_fn(|v| reference.bands[s][v].as_ref().map(|b| b.mean.clone()))
    });
    let has_angles = walks.iter().any(|w| w.angles.is_some());
    let scores = has_angles.then(|| gps::scores(&subject_curves, &reference_curves));
    Ok(Report {
        walks,
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
    })
}

/// The normative data at one speed as a reference.
pub fn normative_reference(path: &Path, speed: Speed) -> Result<Reference, NormativeError> {
    let k = Kinematics::read(path, speed)?;
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
        label: format!("Schwartz et al. 2008, {} speed", speed.key()),
        speed: Some(speed),
        bands,
        extra,
    })
}

/// Writes every file of the report to `dir` (created if needed); returns their paths.
pub fn write(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    let io_error = |path: &Path, action: &'static str| {
        let path = path.display().to_string();
        move |error| ReportError::Io {
            path,
            action,
            error,
        }
    };
    let cycles = dir.join("cycles");
    std::fs::create_dir_all(&cycles).map_err(io_error(&cycles, "create"))?;
    let mut files = Vec::new();
    let put = |files: &mut Vec<PathBuf>, name: &str, text: String| -> Result<(), ReportError> {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io_error(&p, "write"))?;
        files.push(p);
        Ok(())
    };
    put(&mut files, "events.csv", events_csv(report)?)?;
    put(
        &mut files,
        "spatiotemporal.csv",
        spatiotemporal_csv(&report.parameters)?,
    )?;
    if let Some(s) = &report.scores {
        put(&mut files, "gps.csv", gps_csv(s)?)?;
    }
    for (s, side) in SIDES.iter().enumerate() {
        if report.curves[s].iter().any(Option::is_some) {
            put(
                &mut files,
                &format!("cycles/{side}.csv"),
                cycles_csv(&report.curves[s])?,
            )?;
        }
    }
    let mut svgs = Vec::new();
    for written in crate::figures::save_all(report, dir)? {
        if written.extension().is_some_and(|e| e == "svg") {
            let text = std::fs::read_to_string(&written).map_err(io_error(&written, "read"))?;
            svgs.push((
                written
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                text,
            ));
        }
        files.push(written);
    }
    put(&mut files, "report.html", crate::html::page(report, &svgs))?;
    Ok(files)
}

/// The text of a CSV file written by `rows` (through the csv crate: fields quoted when they
/// hold a comma, a quote or a line break).
fn csv_text(
    file: &'static str,
    rows: impl FnOnce(&mut csv::Writer<Vec<u8>>) -> csv::Result<()>,
) -> Result<String, ReportError> {
    let error = |error| ReportError::Csv { file, error };
    let mut w = csv::Writer::from_writer(Vec::new());
    rows(&mut w).map_err(error)?;
    let bytes = w
        .into_inner()
        .map_err(|e| error(csv::Error::from(e.into_error())))?;
    // Every field is UTF-8, so the whole is.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// `events.csv`: `side,event,time` (and `motion` with several recordings), in time order.
pub fn events_csv(report: &Report) -> Result<String, ReportError> {
    let several = report.walks.len() > 1;
    csv_text("events.csv", |w| {
        let mut head = vec!["side", "event", "time"];
        if several {
            head.push("motion");
        }
        w.write_record(&head)?;
        for walk in &report.walks {
            for (s, kind, t) in walk.event_list() {
                let time = round(t, 6);
                let mut row = vec![SIDES[s], kind.name(), time.as_str()];
                if several {
                    row.push(walk.trial.source.as_str());
                }
                w.write_record(&row)?;
            }
        }
        Ok(())
    })
}

/// `spatiotemporal.csv`: `parameter,side,value,unit,normal_min,normal_max,note`.
pub fn spatiotemporal_csv(params: &[Parameter]) -> Result<String, ReportError> {
    csv_text("spatiotemporal.csv", |w| {
        w.write_record([
            "parameter",
            "side",
            "value",
            "unit",
            "normal_min",
            "normal_max",
            "note",
        ])?;
        for p in params {
            let (lo, hi) = p.range.map_or((String::new(), String::new()), |r| {
                (round(r.min, 4), round(r.max, 4))
            });
            w.write_record([p.name, p.side, &round(p.value, 4), p.unit, &lo, &hi, p.note])?;
        }
        Ok(())
    })
}

/// `gps.csv`: `variable,side,gvs_deg`, the nine GVS per side, then `GPS` per side and overall.
pub fn gps_csv(s: &Scores) -> Result<String, ReportError> {
    csv_text("gps.csv", |w| {
        w.write_record(["variable", "side", "gvs_deg"])?;
        for (side, name) in SIDES.iter().enumerate() {
            for (v, var) in Variable::ALL.iter().enumerate() {
                if let Some(g) = s.gvs[side][v] {
                    w.write_record([var.name(), name, &round(g, 4)])?;
                }
            }
        }
        for (side, name) in SIDES.iter().enumerate() {
            if let Some(g) = s.gps[side] {
                w.write_record(["GPS", name, &round(g, 4)])?;
            }
        }
        if let Some(g) = s.overall {
            w.write_record(["GPS", "both", &round(g, 4)])?;
        }
        Ok(())
    })
}

/// `cycles/<side>.csv`: `percent`, then `<variable>_mean,<variable>_sd` per variable (degrees),
/// 101 rows.
pub fn cycles_csv(curves: &[Option<Curve>; 9]) -> Result<String, ReportError> {
    let present: Vec<(usize, &Curve)> = curves
        .iter()
        .enumerate()
        .filter_map(|(v, c)| c.as_ref().map(|c| (v, c)))
        .collect();
    csv_text("cycles.csv", |w| {
        let mut head = vec!["percent".to_string()];
        for (v, _) in &present {
            let n = Variable::ALL[*v].name();
            head.push(format!("{n}_mean"));
            head.push(format!("{n}_sd"));
        }
        w.write_record(&head)?;
        for p in 0..POINTS {
            let mut row = vec![p.to_string()];
            for (_, c) in &present {
                row.push(round(c.mean[p], 4));
                row.push(round(c.sd[p], 4));
            }
            w.write_record(&row)?;
        }
        Ok(())
    })
}

/// A number with at most `decimals` decimals, without trailing zeros.
pub fn round(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}
