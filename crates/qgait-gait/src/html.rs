//! `report.html`: one self-contained page (no external resources; the figures inline as SVG)
//! with the recordings, the settings, the spatiotemporal parameters beside their normal
//! ranges, the Gait Profile Score and the figures.

use std::fmt::Write as _;

use crate::angles::Variable;
use crate::output::{round, Report};
use crate::spatiotemporal::SIDES;

/// Escapes text for HTML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

const STYLE: &str = "body{font-family:sans-serif;margin:2em;max-width:1300px;color:#222}\
table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #ccc;padding:4px 10px;text-align:right}\
th{background:#f3f3f3}td.l,th.l{text-align:left}.out{background:#fde2e1;font-weight:bold}.in{background:#e3f4e3}\
figure{margin:1em 0}figure svg{max-width:100%;height:auto}.note{color:#555;font-size:0.9em}";

/// The page. `svgs`: the figures' stems and SVG texts.
pub fn page(r: &Report, svgs: &[(String, String)]) -> String {
    let mut h = String::new();
    let names: Vec<String> = r.walks.iter().map(|w| w.trial.label.clone()).collect();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Gait analysis: {}</title><style>{STYLE}</style></head><body>\n",
        escape(&names.join(", "))
    );
    let _ = writeln!(h, "<h1>Gait analysis: {}</h1>", escape(&names.join(", ")));
    // Recordings and settings.
    h.push_str("<h2>Recordings and settings</h2>\n<table><tr><th class=\"l\">recording</th><th>frames</th><th>duration (s)</th><th>strides right</th><th>strides left</th><th class=\"l\">left out (incomplete / duration / turning)</th></tr>\n");
    for w in &r.walks {
        let t = &w.trial.time;
        let [sr, sl] = w.strides();
        let d = &w.dropped;
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{sr}</td><td>{sl}</td><td class=\"l\">right {} / {} / {}, left {} / {} / {}</td></tr>",
            escape(&w.trial.source),
            t.len(),
            round(t[t.len() - 1] - t[0], 3),
            d[0].incomplete,
            d[0].duration,
            d[0].turning,
            d[1].incomplete,
            d[1].duration,
            d[1].turning
        );
    }
    h.push_str("</table>\n<table>");
    let mut setting = |k: &str, v: String| {
        let _ = writeln!(
            h,
            "<tr><th class=\"l\">{k}</th><td class=\"l\">{}</td></tr>",
            escape(&v)
        );
    };
    setting("model", r.model.clone());
    // (A `builtin:` gait is taken whole whatever `--cycle` says.)
    let builtin_whole = r.walks.iter().any(|w| w.mode != r.mode);
    setting(
        "cycles",
        match r.mode {
            crate::CycleMode::Auto if builtin_whole => {
                "auto: heel strike to heel strike of each side (Zeni et al. 2008); a builtin: gait whole (it is one cycle)".into()
            }
            crate::CycleMode::Auto => {
                "auto: heel strike to heel strike of each side (Zeni et al. 2008)".into()
            }
            crate::CycleMode::Whole => "whole: each recording is one cycle".into(),
        },
    );
    setting("reference", r.reference.label.clone());
    if let Some(c) = &r.speed_choice {
        setting("normative speed group", c.clone());
    }
    if let Some((v, l)) = r.dimensionless_speed {
        setting(
            "non-dimensional speed",
            format!(
                "{} (leg length {} m, hip to ankle)",
                round(v, 3),
                round(l, 3)
            ),
        );
    }
    setting(
        "normal ranges",
        r.ranges_for
            .clone()
            .unwrap_or_else(|| "not shown (give --age, and --sex, for the subject's)".into()),
    );
    setting("qgait", format!("version {}", env!("CARGO_PKG_VERSION")));
    h.push_str("</table>\n");

    // Spatiotemporal parameters.
    h.push_str("<h2>Spatiotemporal parameters</h2>\n<table><tr><th class=\"l\">parameter</th><th class=\"l\">unit</th>");
    let sides = ["right", "left", "both"];
    for s in sides {
        let _ = write!(h, "<th>{s}</th>");
    }
    h.push_str("<th>normal range</th><th class=\"l\">note</th></tr>\n");
    let mut names: Vec<&str> = Vec::new();
    for p in &r.parameters {
        if !names.contains(&p.name) {
            names.push(p.name);
        }
    }
    for name in names {
        let ps: Vec<_> = r.parameters.iter().filter(|p| p.name == name).collect();
        let first = ps[0];
        let _ = write!(
            h,
            "<tr><td class=\"l\">{name}</td><td class=\"l\">{}</td>",
            first.unit
        );
        for s in sides {
            match ps.iter().find(|p| p.side == s) {
                Some(p) => {
                    let class = match p.range {
                        Some(rg) if p.value < rg.min || p.value > rg.max => " class=\"out\"",
                        Some(_) => " class=\"in\"",
                        None => "",
                    };
                    let _ = write!(h, "<td{class}>{}</td>", round(p.value, 3));
                }
                None => h.push_str("<td></td>"),
            }
        }
        let range = ps.iter().find_map(|p| p.range).map_or(String::new(), |rg| {
            format!("{} – {}", round(rg.min, 3), round(rg.max, 3))
        });
        let _ = writeln!(
            h,
            "<td>{range}</td><td class=\"l\">{}</td></tr>",
            escape(first.note)
        );
    }
    h.push_str("</table>\n<p class=\"note\">Green: inside the normal range, red: outside.</p>\n");

    // GPS.
    if let Some(s) = &r.scores {
        let _ = writeln!(
            h,
            "<h2>Gait Profile Score</h2>\n<p>Against {} (Baker et al. 2009: RMS difference over 51 points of the cycle; overall GPS over 15 variables, the pelvis once).</p>",
            escape(&r.reference.label)
        );
        h.push_str(
            "<table><tr><th class=\"l\">variable</th><th>right (°)</th><th>left (°)</th></tr>\n",
        );
        let cell = |v: Option<f64>| v.map_or(String::new(), |v| round(v, 2));
        for (v, var) in Variable::ALL.iter().enumerate() {
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td></tr>",
                var.name(),
                cell(s.gvs[0][v]),
                cell(s.gvs[1][v])
            );
        }
        let _ = writeln!(
            h,
            "<tr><th class=\"l\">GPS</th><th>{}</th><th>{}</th></tr><tr><th class=\"l\">GPS overall</th><th colspan=\"2\">{}</th></tr></table>",
            cell(s.gps[0]),
            cell(s.gps[1]),
            cell(s.overall)
        );
    } else {
        h.push_str("<h2>Gait Profile Score</h2><p>Not computed: the recording has no joint angles (a device's points only).</p>\n");
    }

    // Figures.
    h.push_str("<h2>Figures</h2>\n");
    for (stem, svg) in svgs {
        let svg = svg.trim_start();
        let svg = svg.strip_prefix("<?xml").map_or(svg, |rest| {
            rest.find("?>").map_or(svg, |e| rest[e + 2..].trim_start())
        });
        let _ = writeln!(
            h,
            "<figure id=\"fig-{}\">{svg}<figcaption>{}</figcaption></figure>",
            escape(stem),
            escape(stem)
        );
    }
    h.push_str("<p class=\"note\">Joint angles in the Conventional Gait Model's conventions, mapped from OpenSim's coordinates; see qgait's docs/gait-analysis.md for the mapping and its caveats. ");
    let _ = write!(h, "Sides: {}.", SIDES.join(", "));
    h.push_str("</p>\n</body></html>\n");
    h
}
