//! The report's files written to a directory: its CSVs (`events.csv`, `spatiotemporal.csv`,
//! `gps.csv`, `cycles/<side>.csv`), its figures ([`crate::figures`]) and one HTML page
//! ([`crate::html`]) with the figures inline.

use std::path::{Path, PathBuf};

use crate::angles::Variable;
use crate::cycles::{Curve, POINTS};
use crate::error::ReportError;
use crate::gps::Scores;
use crate::number::round;
use crate::output::Report;
use crate::spatiotemporal::{Parameter, SIDES};

/// The headline figures of `summary.json` (both sides' values), in order.
pub const HEADLINE: [&str; 6] = [
    "speed",
    "cadence",
    "stride_time",
    "stride_length",
    "step_length",
    "step_width",
];

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
    match &report.events {
        // Written as the recordings were read.
        crate::stream::EventsCsv::File(path) => files.push(path.clone()),
        _ => put(&mut files, "events.csv", events_csv(report)?)?,
    }
    put(
        &mut files,
        "spatiotemporal.csv",
        spatiotemporal_csv(&report.parameters)?,
    )?;
    put(&mut files, "summary.json", summary_json(report))?;
    let bouts: Vec<(&str, Vec<crate::bouts::Bout>)> = report
        .recordings
        .iter()
        .map(|w| (w.source.as_str(), w.bouts.clone()))
        .collect();
    put(
        &mut files,
        "bouts.csv",
        crate::bouts::csv(&bouts).map_err(|error| ReportError::Csv {
            file: "bouts.csv",
            error,
        })?,
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
    put(&mut files, "report.html", crate::html::page(report, &svgs)?)?;
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

/// `events.csv`: `side,event,time` (and `motion` with several recordings), in time order
/// ([`crate::stream::Pool`] writes it as the events are found).
pub fn events_csv(report: &Report) -> Result<String, ReportError> {
    match &report.events {
        crate::stream::EventsCsv::Text(text) => Ok(text.clone()),
        crate::stream::EventsCsv::File(path) => {
            std::fs::read_to_string(path).map_err(|error| ReportError::Io {
                path: path.display().to_string(),
                action: "read",
                error,
            })
        }
        crate::stream::EventsCsv::None => Ok("side,event,time\n".into()),
    }
}

/// `summary.json`: the subject and session as given (`subject`, [`crate::session::Session::summary`]);
/// per recording its mode (`walking`/`running`), ground
/// (`treadmill`/`overground`/`unknown`), speed and how it was found, duty factor, Froude number
/// and leg length, how its events were found, its notes (the rules' doubts, and what its
/// model cannot move: [`crate::angles::Seen::note`]) and `not_seen`, the names of what its
/// model cannot move ([`crate::angles::Seen::not_seen_names`]: variables, then `step_width`);
/// the report's `not_seen` (what it leaves out: what any recording's model cannot move); and
/// the headline figures over all recordings (both sides), each with its method.
pub fn summary_json(report: &Report) -> String {
    let recordings: Vec<SummaryRecording> = report
        .recordings
        .iter()
        .map(|w| {
            let events = w.event_method().map_or_else(
                || crate::spatiotemporal::MIXED_EVENTS.to_string(),
                |m| m.describe(),
            );
            // The rules' doubts, and what the model cannot move.
            let mut notes = w.gait.as_ref().map_or_else(Vec::new, |g| g.notes.clone());
            notes.extend(w.seen.note());
            (w, events, notes)
        })
        .map(|(w, events, notes)| match &w.gait {
            Some(g) => SummaryRecording::Analysed {
                recording: &w.source,
                mode: g.mode.name(),
                ground: g.ground.name(),
                speed: g.speed,
                speed_method: g.speed_method.note(),
                duty_factor: g.duty,
                first_pass_duty_factor: g.first_duty,
                froude: g.froude,
                leg_length: g.leg_length,
                travel_ratio: g.travel_ratio,
                events,
                notes,
                not_seen: w.seen.not_seen_names(),
            },
            None => SummaryRecording::TooFewStrides {
                recording: &w.source,
                mode: None,
                ground: "unknown",
                events,
                notes,
                not_seen: w.seen.not_seen_names(),
            },
        })
        .collect();
    let mut headline = Vec::new();
    for name in HEADLINE {
        if let Some(p) = report
            .parameters
            .iter()
            .find(|p| p.name == name && p.side == "both")
        {
            headline.push((
                name.to_string(),
                Figure {
                    value: p.value,
                    unit: p.unit,
                    method: &p.note,
                },
            ));
        }
    }
    for name in ["stance", "double_support", "flight"] {
        for p in report.parameters.iter().filter(|p| p.name == name) {
            headline.push((
                format!("{name}_{}", p.side),
                Figure {
                    value: p.value,
                    unit: p.unit,
                    method: &p.note,
                },
            ));
        }
    }
    let first = report.recordings.first().and_then(|w| w.gait.as_ref());
    let mut durations: Vec<f64> = report
        .recordings
        .iter()
        .flat_map(|r| &r.bouts)
        .map(|b| b.end - b.start)
        .collect();
    durations.sort_by(f64::total_cmp);
    let summary = Summary {
        subject: report.session.summary(),
        mode: first.map(|g| g.mode.name()),
        ground: first.map_or("unknown", |g| g.ground.name()),
        not_seen: report.seen.not_seen_names(),
        recordings,
        headline: Headline(headline),
        bouts: Bouts {
            count: durations.len(),
            walking_time: durations.iter().sum::<f64>(),
            duration_median: durations.get(durations.len() / 2).copied(),
            duration_max: durations.last().copied(),
            rule: format!(
                "strides at most {} s apart, at least {} of one side (bouts.csv)",
                crate::bouts::MAX_PAUSE,
                crate::bouts::MIN_STRIDES
            ),
        },
        cgm_pelvis: report.recordings.first().map(|w| w.pelvis.describe()),
        warnings: &report.warnings,
    };
    serde_json::to_string_pretty(&summary).unwrap_or_default() + "\n"
}

/// `summary.json`, its fields in the file's order.
#[derive(serde::Serialize)]
struct Summary<'a> {
    subject: crate::session::SubjectSummary<'a>,
    mode: Option<&'static str>,
    ground: &'static str,
    /// What the report leaves out ([`crate::angles::Seen::not_seen_names`]).
    not_seen: Vec<&'static str>,
    recordings: Vec<SummaryRecording<'a>>,
    headline: Headline<'a>,
    bouts: Bouts,
    cgm_pelvis: Option<String>,
    warnings: &'a [String],
}

/// A recording in `summary.json`: analysed by the rules, or too short for them.
#[derive(serde::Serialize)]
#[serde(untagged)]
enum SummaryRecording<'a> {
    Analysed {
        recording: &'a str,
        mode: &'static str,
        ground: &'static str,
        speed: f64,
        speed_method: &'static str,
        duty_factor: Option<f64>,
        first_pass_duty_factor: f64,
        froude: f64,
        leg_length: f64,
        travel_ratio: Option<f64>,
        events: String,
        notes: Vec<String>,
        not_seen: Vec<&'static str>,
    },
    TooFewStrides {
        recording: &'a str,
        mode: Option<&'static str>,
        ground: &'static str,
        events: String,
        notes: Vec<String>,
        not_seen: Vec<&'static str>,
    },
}

/// A headline figure: its value (`null` where the model cannot see it) and unit, and how it
/// was found (or why it has no value).
#[derive(serde::Serialize)]
struct Figure<'a> {
    value: Option<f64>,
    unit: &'static str,
    method: &'a str,
}

/// The headline figures by name, in the order found.
struct Headline<'a>(Vec<(String, Figure<'a>)>);

impl serde::Serialize for Headline<'_> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.0.iter().map(|(name, figure)| (name, figure)))
    }
}

/// The walking bouts over all recordings.
#[derive(serde::Serialize)]
struct Bouts {
    count: usize,
    walking_time: f64,
    duration_median: Option<f64>,
    duration_max: Option<f64>,
    rule: String,
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
            let value = p.value.map_or(String::new(), |v| round(v, 4));
            w.write_record([p.name, p.side, &value, p.unit, &lo, &hi, &p.note])?;
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
