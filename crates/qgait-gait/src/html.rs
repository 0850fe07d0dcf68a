//! `report.html`: one self-contained page (no external resources; the figures inline as SVG),
//! in the order a clinician reads a Vicon Polygon or pyCGM2 report: the subject and session
//! (what was given, the model, the files, the condition detected and given), every warning of
//! the run, the joint angles against the reference, the Movement Analysis Profile with the
//! scores and their normal reference, the spatiotemporal parameters (readable names and units,
//! normal ranges, flags, a reference recording's own values), every event of `events.csv`, the
//! recordings and the settings. Each figure has a caption that says what it shows.
//!
//! The page is an askama template (`templates/report.html`, one partial per section under
//! `templates/report/`), compiled into the crate and checked against [`Page`]'s fields at build
//! time; askama escapes every field for HTML except the SVG figures, which are inserted as they
//! are. This module only prepares the fields: the numbers rounded, the cells' classes chosen.

use askama::Template;

use crate::angles::{Plane, Seen, Variable};
use crate::cycles::Dropped;
use crate::number::round;
use crate::output::Report;
use crate::spatiotemporal::{Parameter, SIDES};

/// The page's fields, one group per section (`templates/report/*.html`).
#[derive(Template)]
#[template(path = "report.html")]
pub struct Page<'a> {
    /// The subject ID, else the recordings' labels, for the title.
    title: String,
    /// Section `header`: the subject and the session, name and value.
    header: Vec<(&'static str, String)>,
    /// Section `warnings`: every warning of the run.
    warnings: &'a [String],
    /// Section `events`: one row per event of `events.csv`.
    events: Vec<EventRow>,
    /// Section `events`: whether the rows name their recording (several recordings).
    several: bool,
    /// Section `events`: the number of events in `events.csv` (the table may list fewer).
    events_total: usize,
    /// Section `recordings`: one row per recording.
    recordings: Vec<Recording<'a>>,
    /// Section `recordings`: the settings, name and value.
    settings: Vec<(&'static str, String)>,
    /// Section `spatiotemporal`: one row per parameter.
    parameters: Vec<ParameterRow>,
    /// Section `spatiotemporal`: the reference recording's label, when its values have a
    /// column.
    reference_column: Option<&'a str>,
    /// Section `gps`: what the scores are against.
    reference: &'a str,
    /// Section `gps`: the scores, when the recordings have joint angles.
    gps: Option<GpsTable>,
    /// The figures by section: the joint angles, the MAP, the events.
    kinematics: Option<Figure<'a>>,
    map: Option<Figure<'a>>,
    events_figure: Option<Figure<'a>>,
    /// The side names, for the closing note.
    sides: String,
}

/// A row of the event table.
struct EventRow {
    side: String,
    event: String,
    /// Seconds, as in `events.csv`.
    time: String,
    recording: String,
}

/// The events table's rows: the first [`MAX_EVENT_ROWS`] of `events.csv`, and how many it holds.
#[derive(Default)]
pub struct EventRows {
    rows: Vec<EventRow>,
    total: usize,
}

/// The events the page lists at most: a clinical recording's every event; a day's recording
/// (over 100,000 events) lists its first ones and leaves the rest to `events.csv`, so the page
/// stays a size a browser opens.
pub const MAX_EVENT_ROWS: usize = 2_000;

/// The rows of `events.csv` (`side,event,time[,motion]`) for the events table.
fn event_rows(r: &Report) -> Result<EventRows, crate::error::ReportError> {
    // Read as a stream: a day's events.csv is not held whole.
    let source: Box<dyn std::io::Read + '_> = match &r.events {
        crate::stream::EventsCsv::File(path) => Box::new(std::fs::File::open(path).map_err(
            |error| crate::error::ReportError::Io {
                path: path.display().to_string(),
                action: "read",
                error,
            },
        )?),
        crate::stream::EventsCsv::Text(text) => Box::new(text.as_bytes()),
        crate::stream::EventsCsv::None => Box::new(&b"side,event,time\n"[..]),
    };
    let mut reader = csv::Reader::from_reader(std::io::BufReader::new(source));
    let mut out = EventRows::default();
    for record in reader.records() {
        let record = record.map_err(|e| crate::error::ReportError::Csv {
            file: "events.csv",
            error: e,
        })?;
        out.total += 1;
        if out.rows.len() < MAX_EVENT_ROWS {
            let field = |k: usize| record.get(k).unwrap_or("").to_string();
            out.rows.push(EventRow {
                side: field(0),
                event: field(1).replace('_', " "),
                time: field(2),
                recording: field(3),
            });
        }
    }
    Ok(out)
}

/// A row of the recordings table.
struct Recording<'a> {
    source: &'a str,
    frames: usize,
    /// Seconds, rounded.
    duration: String,
    /// Strides kept, right and left.
    strides: [usize; 2],
    /// Strides left out, right and left.
    dropped: &'a [Dropped; 2],
}

/// A row of the spatiotemporal table.
struct ParameterRow {
    /// Readable name ([`title`]).
    name: String,
    /// Readable unit ([`unit`]).
    unit: &'static str,
    /// Right, left, both.
    cells: [Cell; 3],
    /// The reference recording's value (both sides, else right / left), when it has one.
    reference: String,
    /// `min – max`, or empty.
    range: String,
    /// The sides outside the normal range, in words (`below: right, left`), or empty.
    flag: String,
    note: String,
}

/// A value cell: `in` or `out` of the normal range when there is one (an arrow says which
/// way it is out); empty when the parameter has no value for that side.
#[derive(Default)]
struct Cell {
    class: Option<&'static str>,
    value: String,
}

/// The scores, rounded.
struct GpsTable {
    /// Variable, right, left, a member of the reference's (empty where unknown).
    rows: Vec<(&'static str, String, String, String)>,
    /// GPS right and left, and a member of the reference's.
    gps: [String; 3],
    /// Overall GPS, and a member of the reference's.
    overall: [String; 2],
    /// What the overall GPS is over, in words.
    over: String,
}

/// What the overall GPS over `variables` (of a report that sees `seen`) is over: `15
/// variables, the pelvis once` for all nine; for a planar model's sagittal four, `7 sagittal
/// variables, the pelvic tilt once` and why ([`Seen::note`]); for others, e.g. `11 variables,
/// the pelvic tilt once` and why.
fn over(variables: &[Variable], seen: Seen) -> String {
    let pelvis: Vec<Variable> = variables
        .iter()
        .copied()
        .filter(|v| v.is_pelvis())
        .collect();
    let n = pelvis.len() + 2 * (variables.len() - pelvis.len());
    let once = match pelvis.len() {
        0 => "no pelvic variable".to_string(),
        3 => "the pelvis once".to_string(),
        _ => format!(
            "the {} once",
            pelvis
                .iter()
                .map(|v| v.name().replace('_', " "))
                .collect::<Vec<_>>()
                .join(" and ")
        ),
    };
    let sagittal = if variables.iter().all(|v| v.plane() == Plane::Sagittal) {
        " sagittal"
    } else {
        ""
    };
    match seen.note() {
        None => format!("{n} variables, {once}"),
        Some(note) => format!("{n}{sagittal} variables, {once}; {note}"),
    }
}

/// An inline figure with its caption.
struct Figure<'a> {
    stem: &'a str,
    /// The SVG element (its XML declaration removed).
    svg: &'a str,
    /// What it shows.
    caption: String,
}

/// A parameter's readable name: `stride_time` is `Stride time`; a name this table does not
/// know is its words, capitalised.
pub fn title(name: &str) -> String {
    let known = match name {
        "cadence" => "Cadence",
        "stride_time" => "Stride time",
        "step_time" => "Step time",
        "stance" => "Stance phase",
        "swing" => "Swing phase",
        "double_support" => "Double support",
        "flight" => "Flight phase",
        "step_length" => "Step length",
        "step_width" => "Step width",
        "stride_length" => "Stride length",
        "speed" => "Speed",
        "duty_factor" => "Duty factor (stance / stride)",
        "froude" => "Froude number",
        "leg_length" => "Leg length (hip to ankle)",
        "travel_ratio" => "Pelvis travel / (speed × stride time)",
        _ => "",
    };
    if !known.is_empty() {
        return known.to_string();
    }
    let words = name.replace('_', " ");
    let mut c = words.chars();
    c.next()
        .map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

/// A unit as the table shows it: `%` is of the gait cycle, a ratio says it has none.
pub fn unit(unit: &'static str) -> &'static str {
    match unit {
        "%" => "% gait cycle",
        "" => "(ratio)",
        u => u,
    }
}

/// `below` or `above` when `value` is outside `range`, else `None`.
pub fn outside(value: f64, range: crate::normative::Range) -> Option<&'static str> {
    if value < range.min {
        Some("below")
    } else if value > range.max {
        Some("above")
    } else {
        None
    }
}

impl<'a> Page<'a> {
    /// The page's fields from the report. `svgs`: the figures' stems and SVG texts.
    pub fn new(r: &'a Report, svgs: &'a [(String, String)], events: EventRows) -> Self {
        let names: Vec<&str> = r.recordings.iter().map(|w| w.label.as_str()).collect();
        let recordings = r
            .recordings
            .iter()
            .map(|w| Recording {
                source: &w.source,
                frames: w.frames,
                duration: round(w.duration(), 3),
                strides: w.strides(),
                dropped: &w.dropped,
            })
            .collect();
        let figure = |stem: &str| {
            svgs.iter().find(|(s, _)| s == stem).map(|(stem, svg)| {
                let svg = svg.trim_start();
                let svg = svg.strip_prefix("<?xml").map_or(svg, |rest| {
                    rest.find("?>").map_or(svg, |e| rest[e + 2..].trim_start())
                });
                Figure {
                    stem,
                    svg,
                    caption: caption(r, stem),
                }
            })
        };
        let motion_reference = !r.reference.parameters.is_empty();
        Self {
            title: r
                .session
                .subject_id
                .clone()
                .unwrap_or_else(|| names.join(", ")),
            header: header(r),
            warnings: &r.warnings,
            several: r.recordings.len() > 1,
            events_total: events.total,
            events: events.rows,
            recordings,
            settings: settings(r),
            parameters: parameters(r),
            reference_column: motion_reference.then_some(r.reference.label.as_str()),
            reference: &r.reference.label,
            gps: r.scores.as_ref().map(|s| {
                let cell = |v: Option<f64>| v.map_or(String::new(), |v| round(v, 2));
                // A member of the reference's scores: one value when both sides' are the same
                // (the normative data), else right / left.
                let both = |a: Option<f64>, b: Option<f64>| match (a, b) {
                    (Some(a), Some(b)) if round(a, 2) != round(b, 2) => {
                        format!("{} / {}", round(a, 2), round(b, 2))
                    }
                    (a, b) => cell(a.or(b)),
                };
                let n = r.normal_scores.as_ref();
                GpsTable {
                    rows: Variable::ALL
                        .iter()
                        .enumerate()
                        .filter(|(_, var)| s.variables.contains(var))
                        .map(|(v, var)| {
                            (
                                var.title(),
                                cell(s.gvs[0][v]),
                                cell(s.gvs[1][v]),
                                n.map_or(String::new(), |n| both(n.gvs[0][v], n.gvs[1][v])),
                            )
                        })
                        .collect(),
                    gps: [
                        cell(s.gps[0]),
                        cell(s.gps[1]),
                        n.map_or(String::new(), |n| both(n.gps[0], n.gps[1])),
                    ],
                    overall: [
                        cell(s.overall),
                        n.map_or(String::new(), |n| cell(n.overall)),
                    ],
                    over: over(&s.variables, r.seen),
                }
            }),
            kinematics: figure("kinematics"),
            map: figure("map"),
            events_figure: figure("events"),
            sides: SIDES.join(", "),
        }
    }
}

/// What a figure shows, in a sentence or two (its caption).
fn caption(r: &Report, stem: &str) -> String {
    let reference = r.reference.legend();
    match stem {
        "kinematics" => format!(
            "Joint angles (degrees) over the gait cycle (0-100 %, heel strike to the next heel strike of the same side): rows pelvis, hip, knee, ankle and foot; columns sagittal, frontal and transverse planes. Each side's mean ± 1 SD over {} strides (right red, left blue; thin lines: up to {} strides a side, spread over the recording), against {reference}: its mean ± 1 SD in grey. Vertical lines: each side's measured toe off (solid){}. Only the angles the model gives or the reference has are drawn{}.",
            match r.recordings.iter().map(|w| w.strides()).fold([0, 0], |a, b| [a[0] + b[0], a[1] + b[1]]) {
                [rt, lt] => format!("{rt} right and {lt} left"),
            },
            crate::figures::MAX_STRIDE_LINES,
            if r.reference.toe_off_from.is_empty() {
                String::new()
            } else {
                format!(" and the reference's (dashed: {})", r.reference.toe_off_from)
            },
            match r.seen.note() {
                Some(note) if r.seen == Seen::SAGITTAL => format!("; the sagittal ones only: {note}"),
                Some(note) => format!("; only those the model can move: {note}"),
                None => String::new(),
            }
        ),
        "map" => format!(
            "Movement Analysis Profile (Baker et al. 2009): the Gait Variable Score of each joint angle and side, the RMS difference in degrees between the subject's mean curve and the mean of {reference}, and the Gait Profile Score of each side and overall. Green ticks: the scores of a typical member of the reference (the RMS of its SD over the cycle); bars well above them are the angles furthest from the reference.",
        ),
        "events" => "Gait events over time, to check them: the heel (thick) and the toe tip (thin) forward of the pelvis along the direction of progression; triangles mark heel strikes, dots toe offs (right red, left blue). Each event's time is in the event table.".to_string(),
        other => other.to_string(),
    }
}

/// The header block: the subject and session (what was given), the model, the files, the
/// condition as detected and as given, the strides.
fn header(r: &Report) -> Vec<(&'static str, String)> {
    let s = &r.session;
    let mut h = vec![(
        "Subject ID",
        s.subject_id.clone().unwrap_or_else(|| "not given".into()),
    )];
    h.push((
        "Session date",
        match (&s.date, &s.date_from) {
            (Some(d), Some(from)) if from != "given" => {
                format!("{d} (modification date of {from})")
            }
            (Some(d), _) => d.clone(),
            (None, _) => "not given".into(),
        },
    ));
    if let Some(a) = s.age {
        h.push(("Age", format!("{} years", round(a, 1))));
    }
    if let Some(x) = s.sex {
        h.push(("Sex", x.to_string()));
    }
    if let Some(v) = s.height {
        h.push(("Height", format!("{} m", round(v, 3))));
    }
    if let Some(v) = s.mass {
        h.push(("Mass", format!("{} kg", round(v, 1))));
    }
    if let Some(v) = s.bmi() {
        h.push(("BMI", format!("{} kg/m²", round(v, 1))));
    }
    h.push(("Model", r.model.clone()));
    h.push((
        "Files",
        r.recordings
            .iter()
            .map(|w| w.source.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    ));
    for w in &r.recordings {
        let text = match &w.gait {
            Some(g) => format!(
                "{}, {}, {} m/s{}",
                g.mode.name(),
                match g.ground {
                    crate::rules::Ground::Unknown =>
                        "treadmill or overground unknown (no pelvis translation)",
                    other => other.name(),
                },
                round(g.speed, 2),
                if r.recordings.len() > 1 {
                    format!(" ({})", w.label)
                } else {
                    String::new()
                }
            ),
            None => format!(
                "not determined: too few strides for the rules ({})",
                w.label
            ),
        };
        h.push(("Condition (detected)", text));
    }
    if let Some(c) = &s.condition {
        h.push(("Condition (as given)", c.clone()));
    }
    let [rt, lt] = r
        .recordings
        .iter()
        .map(|w| w.strides())
        .fold([0, 0], |a, b| [a[0] + b[0], a[1] + b[1]]);
    h.push(("Strides analysed", format!("right {rt}, left {lt}")));
    h.push(("Reference", r.reference.label.clone()));
    h
}

/// The settings table: the model, how the cycles were taken, the reference and the normal
/// ranges, qgait's version.
fn settings(r: &Report) -> Vec<(&'static str, String)> {
    let mut s = vec![("model", r.model.clone())];
    // (A `builtin:` gait is taken whole whatever `--cycle` says.)
    let builtin_whole = r.recordings.iter().any(|w| w.mode != r.mode);
    s.push((
        "cycles",
        match r.mode {
            crate::CycleMode::Auto if builtin_whole => {
                "auto: heel strike to heel strike of each side; a builtin: gait whole (it is one cycle)".into()
            }
            crate::CycleMode::Auto => {
                "auto: heel strike to heel strike of each side".into()
            }
            crate::CycleMode::Whole => "whole: each recording is one cycle".into(),
        },
    ));
    for w in &r.recordings {
        let text = match &w.gait {
            Some(g) => format!(
                "{}: {} on {} ground ({}); speed {} m/s ({}); duty factor {}, Froude number {}, leg length {} m; events by the rules of docs/gait-analysis.md{}{}",
                w.label,
                g.mode.name(),
                g.ground.name(),
                match g.travel_ratio {
                    Some(t) => format!("pelvis travel {} of speed x stride time", round(t, 3)),
                    None => "no changing pelvis translation".into(),
                },
                round(g.speed, 3),
                g.speed_method.note(),
                round(g.duty.unwrap_or(g.first_duty), 3),
                round(g.froude, 2),
                round(g.leg_length, 3),
                if g.mode == crate::rules::Mode::Running {
                    "; the normative bands and normal ranges are walking's"
                } else {
                    ""
                },
                g.notes.iter().map(|n| format!("; {n}")).collect::<String>(),
            ),
            None => format!(
                "{}: too few strides for the rules: Zeni's events, mode and ground unknown",
                w.label
            ),
        };
        s.push(("gait", text));
    }
    if let Some(note) = r.seen.note() {
        let label = if r.seen == Seen::SAGITTAL {
            "planar model"
        } else {
            "not seen"
        };
        s.push((label, note));
    }
    if let Some(w) = r.recordings.first() {
        s.push(("pelvis (CGM)", w.pelvis.describe()));
    }
    s.push(("reference", r.reference.label.clone()));
    if let Some(c) = &r.speed_choice {
        s.push(("normative speed group", c.clone()));
    }
    if let Some((v, l)) = r.dimensionless_speed {
        s.push((
            "non-dimensional speed",
            format!(
                "{} (leg length {} m, hip to ankle)",
                round(v, 3),
                round(l, 3)
            ),
        ));
    }
    s.push((
        "normal ranges",
        r.ranges_for
            .clone()
            .unwrap_or_else(|| "not shown (give --age, and --sex, for the subject's)".into()),
    ));
    s.push(("qgait", format!("version {}", env!("CARGO_PKG_VERSION"))));
    s
}

/// The spatiotemporal table: one row per parameter (in the report's order), a cell per side,
/// the reference recording's value where it has one.
fn parameters(r: &Report) -> Vec<ParameterRow> {
    let mut names: Vec<&str> = Vec::new();
    for p in &r.parameters {
        if !names.contains(&p.name) {
            names.push(p.name);
        }
    }
    names
        .into_iter()
        .map(|name| {
            let ps: Vec<_> = r.parameters.iter().filter(|p| p.name == name).collect();
            // The sides outside the range, by which way.
            let mut out: Vec<(&str, &str)> = Vec::new();
            let cells = ["right", "left", "both"].map(|side| {
                ps.iter()
                    .find(|p| p.side == side)
                    .and_then(|p| p.value.map(|v| (p, v)))
                    .map_or_else(Cell::default, |(p, value)| {
                        let off = p.range.and_then(|rg| outside(value, rg));
                        if let Some(way) = off {
                            out.push((way, side));
                        }
                        Cell {
                            class: p.range.map(|_| if off.is_some() { "out" } else { "in" }),
                            value: match off {
                                Some("below") => format!("{} ↓", round(value, 3)),
                                Some(_) => format!("{} ↑", round(value, 3)),
                                None => round(value, 3),
                            },
                        }
                    })
            });
            let range = ps.iter().find_map(|p| p.range).map_or(String::new(), |rg| {
                format!("{} – {}", round(rg.min, 3), round(rg.max, 3))
            });
            ParameterRow {
                name: title(name),
                unit: unit(ps[0].unit),
                cells,
                reference: reference_value(&r.reference.parameters, name),
                range,
                flag: flag(&out),
                note: ps[0].note.clone(),
            }
        })
        .collect()
}

/// The flag column's words for the sides outside the normal range, `(way, side)` each:
/// `below: right, left` (and `; above: ...`); empty when none is.
pub fn flag(out: &[(&str, &str)]) -> String {
    ["below", "above"]
        .iter()
        .filter_map(|way| {
            let sides: Vec<&str> = out.iter().filter(|o| o.0 == *way).map(|o| o.1).collect();
            (!sides.is_empty()).then(|| format!("{way}: {}", sides.join(", ")))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// A reference recording's value of a parameter: both sides', else right / left; empty when
/// it has none.
fn reference_value(params: &[Parameter], name: &str) -> String {
    let get = |side: &str| {
        params
            .iter()
            .find(|p| p.name == name && p.side == side)
            .and_then(|p| p.value.map(|v| round(v, 3)))
    };
    match (get("both"), get("right"), get("left")) {
        (Some(b), _, _) => b,
        (None, Some(r), Some(l)) => format!("{r} / {l}"),
        (None, r, l) => r.or(l).unwrap_or_default(),
    }
}

/// The page. `svgs`: the figures' stems and SVG texts.
pub fn page(r: &Report, svgs: &[(String, String)]) -> Result<String, askama::Error> {
    let events = event_rows(r).map_err(|e| askama::Error::Custom(Box::new(e)))?;
    Page::new(r, svgs, events).render()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normative::Range;

    #[test]
    fn names_units_and_flags_read_as_words() {
        assert_eq!(title("stride_time"), "Stride time");
        assert_eq!(title("double_support"), "Double support");
        // A name the table does not know: its words, capitalised.
        assert_eq!(title("single_support_time"), "Single support time");
        assert_eq!(title(""), "");
        assert_eq!(unit("%"), "% gait cycle");
        assert_eq!(unit(""), "(ratio)");
        assert_eq!(unit("m/s"), "m/s");
        let r = Range { min: 1.0, max: 2.0 };
        assert_eq!(outside(0.99, r), Some("below"));
        assert_eq!(outside(1.0, r), None);
        assert_eq!(outside(2.0, r), None);
        assert_eq!(outside(2.01, r), Some("above"));
        assert_eq!(
            flag(&[("below", "right"), ("above", "left"), ("below", "both")]),
            "below: right, both; above: left"
        );
        assert_eq!(flag(&[]), "");
    }
}
