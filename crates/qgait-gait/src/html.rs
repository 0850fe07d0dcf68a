//! `report.html`: one self-contained page (no external resources; the figures inline as SVG)
//! with the recordings, the settings, the spatiotemporal parameters beside their normal
//! ranges, the Gait Profile Score and the figures.
//!
//! The page is an askama template (`templates/report.html`, one partial per section under
//! `templates/report/`), compiled into the crate and checked against [`Page`]'s fields at build
//! time; askama escapes every field for HTML except the SVG figures, which are inserted as they
//! are. This module only prepares the fields: the numbers rounded, the cells' classes chosen.

use askama::Template;

use crate::angles::Variable;
use crate::cycles::Dropped;
use crate::output::{round, Report};
use crate::spatiotemporal::SIDES;

/// The page's fields, one group per section (`templates/report/*.html`).
#[derive(Template)]
#[template(path = "report.html")]
pub struct Page<'a> {
    /// The recordings' labels, for the title.
    title: String,
    /// Section `recordings`: one row per recording.
    recordings: Vec<Recording<'a>>,
    /// Section `recordings`: the settings, name and value.
    settings: Vec<(&'static str, String)>,
    /// Section `spatiotemporal`: one row per parameter.
    parameters: Vec<ParameterRow>,
    /// Section `gps`: what the scores are against.
    reference: &'a str,
    /// Section `gps`: the scores, when the recordings have joint angles.
    gps: Option<GpsTable>,
    /// Section `figures`.
    figures: Vec<Figure<'a>>,
    /// The side names, for the closing note.
    sides: String,
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
    name: &'static str,
    unit: &'static str,
    /// Right, left, both.
    cells: [Cell; 3],
    /// `min – max`, or empty.
    range: String,
    note: &'static str,
}

/// A value cell: `in` or `out` of the normal range when there is one; empty when the parameter
/// has no value for that side.
#[derive(Default)]
struct Cell {
    class: Option<&'static str>,
    value: String,
}

/// The scores, rounded.
struct GpsTable {
    /// Variable, right, left (empty where unknown).
    rows: Vec<(&'static str, String, String)>,
    /// GPS right and left.
    gps: [String; 2],
    overall: String,
}

/// An inline figure.
struct Figure<'a> {
    stem: &'a str,
    /// The SVG element (its XML declaration removed).
    svg: &'a str,
}

impl<'a> Page<'a> {
    /// The page's fields from the report. `svgs`: the figures' stems and SVG texts.
    pub fn new(r: &'a Report, svgs: &'a [(String, String)]) -> Self {
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
        Self {
            title: names.join(", "),
            recordings,
            settings: settings(r),
            parameters: parameters(r),
            reference: &r.reference.label,
            gps: r.scores.as_ref().map(|s| {
                let cell = |v: Option<f64>| v.map_or(String::new(), |v| round(v, 2));
                GpsTable {
                    rows: Variable::ALL
                        .iter()
                        .enumerate()
                        .map(|(v, var)| (var.name(), cell(s.gvs[0][v]), cell(s.gvs[1][v])))
                        .collect(),
                    gps: s.gps.map(cell),
                    overall: cell(s.overall),
                }
            }),
            figures: svgs
                .iter()
                .map(|(stem, svg)| {
                    let svg = svg.trim_start();
                    let svg = svg.strip_prefix("<?xml").map_or(svg, |rest| {
                        rest.find("?>").map_or(svg, |e| rest[e + 2..].trim_start())
                    });
                    Figure { stem, svg }
                })
                .collect(),
            sides: SIDES.join(", "),
        }
    }
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
    if r.recordings.iter().any(|w| w.planar) {
        s.push((
            "planar model",
            "the model moves the legs in the sagittal plane only: no step width or other frontal or transverse quantity is reported".into(),
        ));
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

/// The spatiotemporal table: one row per parameter (in the report's order), a cell per side.
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
            let cells = ["right", "left", "both"].map(|side| {
                ps.iter()
                    .find(|p| p.side == side)
                    .map_or_else(Cell::default, |p| Cell {
                        class: p.range.map(|rg| {
                            if p.value < rg.min || p.value > rg.max {
                                "out"
                            } else {
                                "in"
                            }
                        }),
                        value: round(p.value, 3),
                    })
            });
            let range = ps.iter().find_map(|p| p.range).map_or(String::new(), |rg| {
                format!("{} – {}", round(rg.min, 3), round(rg.max, 3))
            });
            ParameterRow {
                name,
                unit: ps[0].unit,
                cells,
                range,
                note: ps[0].note,
            }
        })
        .collect()
}

/// The page. `svgs`: the figures' stems and SVG texts.
pub fn page(r: &Report, svgs: &[(String, String)]) -> Result<String, askama::Error> {
    Page::new(r, svgs).render()
}
