//! The report's tables, all values in metres (areas in m²), computed with
//! `qgait_kernel::metrics`:
//!
//! - `metrics.csv`: per gait, side, joint and plane, the path statistics (min, max, mean, range
//!   and centroid of both plane axes, and the area enclosed by the path: the net shoelace area of
//!   the closed path, so the lobes of a figure-eight path traversed in opposite directions
//!   cancel);
//! - `hip_shift.csv`: per gait and side, the mean hip position over the cycle minus that of the
//!   first gait (dx, dy, dz) and its length (`shift`);
//! - `distance_stats.csv`: min, max, mean and range of the knee-knee, ankle-ankle and toe-toe
//!   distances;
//! - `metrics.md`: the same three tables in Markdown (4 decimals), with the list of figures.
//!
//! CSV numbers are printed with Rust's `{}` (shortest round-trip representation).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use qgait_kernel::metrics::{path_stats, PathStats, Plane};
use qgait_kernel::{Joint, Side};

use super::distances::MEASURES;
use super::{Analysis, Gait, ReportError};

/// Header of `metrics.csv`.
pub const METRICS_HEADER: &str = "gait,side,joint,plane,axis_a,axis_b,n,min_a,min_b,max_a,max_b,mean_a,mean_b,range_a,range_b,centroid_a,centroid_b,area_m2";
/// Header of `hip_shift.csv`.
pub const HIP_SHIFT_HEADER: &str = "gait,reference,side,dx,dy,dz,shift";
/// Header of `distance_stats.csv`.
pub const DISTANCE_HEADER: &str = "gait,measure,min,max,mean,range";

/// One row of the path statistics.
pub struct PathRow<'a> {
    /// The gait.
    pub gait: &'a Gait,
    /// Limb.
    pub side: Side,
    /// Joint.
    pub joint: Joint,
    /// Plane.
    pub plane: Plane,
    /// The statistics.
    pub stats: PathStats<f64>,
}

/// Path statistics of every gait, side, joint and plane.
pub fn path_rows(analysis: &Analysis) -> Vec<PathRow<'_>> {
    let mut rows = Vec::new();
    for gait in &analysis.gaits {
        for side in Side::ALL {
            for joint in Joint::ALL {
                for plane in Plane::ALL {
                    if let Some(stats) = path_stats(&gait.poses, side, joint, plane) {
                        rows.push(PathRow {
                            gait,
                            side,
                            joint,
                            plane,
                            stats,
                        });
                    }
                }
            }
        }
    }
    rows
}

/// Mean hip position (x, y, z) of a gait over its rows, from the kernel's path statistics.
pub fn mean_hip(gait: &Gait, side: Side) -> Option<[f64; 3]> {
    let sag = path_stats(&gait.poses, side, Joint::Hip, Plane::Sagittal)?;
    let fro = path_stats(&gait.poses, side, Joint::Hip, Plane::Frontal)?;
    Some([sag.mean[0], sag.mean[1], fro.mean[0]])
}

/// Hip shift of each gait relative to the first: (gait, side, [dx, dy, dz], length).
pub fn hip_shifts(analysis: &Analysis) -> Vec<(&Gait, Side, [f64; 3], f64)> {
    let Some(reference) = analysis.gaits.first() else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for gait in &analysis.gaits {
        for side in Side::ALL {
            if let (Some(r), Some(m)) = (mean_hip(reference, side), mean_hip(gait, side)) {
                let d = [m[0] - r[0], m[1] - r[1], m[2] - r[2]];
                out.push((
                    gait,
                    side,
                    d,
                    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
                ));
            }
        }
    }
    out
}

/// Distance statistics: (gait, measure name, min, max, mean).
pub fn distance_stats(analysis: &Analysis) -> Vec<(&Gait, &'static str, f64, f64, f64)> {
    let mut out = Vec::new();
    for gait in &analysis.gaits {
        for (title, measure) in MEASURES {
            let v: Vec<f64> = gait.distances.iter().map(measure).collect();
            let min = v.iter().copied().fold(f64::INFINITY, f64::min);
            let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            out.push((gait, title.trim_end_matches(" distance"), min, max, mean));
        }
    }
    out
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::Right => "right",
        Side::Left => "left",
    }
}

/// Writes a CSV file: the header, then rows of fields (quoted where a field needs it).
fn write_csv<const N: usize>(
    path: &Path,
    header: &str,
    rows: impl IntoIterator<Item = [String; N]>,
) -> Result<(), ReportError> {
    let write = || -> csv::Result<()> {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(header.split(','))?;
        for row in rows {
            w.write_record(&row)?;
        }
        w.flush()?;
        Ok(())
    };
    write().map_err(|e| ReportError::Write {
        path: path.to_path_buf(),
        error: e.into(),
    })
}

/// Writes the CSV files and `metrics.md`; returns their paths.
pub fn write_all(analysis: &Analysis, dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    let paths = path_rows(analysis);
    let shifts = hip_shifts(analysis);
    let dists = distance_stats(analysis);
    let reference = analysis
        .gaits
        .first()
        .map(|g| g.label.as_str())
        .unwrap_or("");

    let file = |name: &str| dir.join(name);
    let written = vec![
        file("metrics.csv"),
        file("hip_shift.csv"),
        file("distance_stats.csv"),
        file("metrics.md"),
    ];
    write_csv(
        &written[0],
        METRICS_HEADER,
        paths.iter().map(|r| {
            let (a, b) = r.plane.axes();
            let s = &r.stats;
            [
                r.gait.label.clone(),
                side_name(r.side).to_string(),
                r.joint.name().to_string(),
                r.plane.name().to_lowercase(),
                a.to_string(),
                b.to_string(),
                s.n.to_string(),
                s.min[0].to_string(),
                s.min[1].to_string(),
                s.max[0].to_string(),
                s.max[1].to_string(),
                s.mean[0].to_string(),
                s.mean[1].to_string(),
                s.range[0].to_string(),
                s.range[1].to_string(),
                s.centroid[0].to_string(),
                s.centroid[1].to_string(),
                s.area.to_string(),
            ]
        }),
    )?;
    write_csv(
        &written[1],
        HIP_SHIFT_HEADER,
        shifts.iter().map(|(g, side, d, len)| {
            [
                g.label.clone(),
                reference.to_string(),
                side_name(*side).to_string(),
                d[0].to_string(),
                d[1].to_string(),
                d[2].to_string(),
                len.to_string(),
            ]
        }),
    )?;
    write_csv(
        &written[2],
        DISTANCE_HEADER,
        dists.iter().map(|(g, name, min, max, mean)| {
            [
                g.label.clone(),
                name.to_string(),
                min.to_string(),
                max.to_string(),
                mean.to_string(),
                (max - min).to_string(),
            ]
        }),
    )?;

    let md = markdown(analysis, &paths, &shifts, &dists, reference);
    std::fs::write(&written[3], md).map_err(|error| ReportError::Write {
        path: written[3].clone(),
        error,
    })?;
    Ok(written)
}

fn markdown(
    analysis: &Analysis,
    paths: &[PathRow<'_>],
    shifts: &[(&Gait, Side, [f64; 3], f64)],
    dists: &[(&Gait, &'static str, f64, f64, f64)],
    reference: &str,
) -> String {
    let mut md = String::from("# qgait report\n\n");
    let _ = write!(
        md,
        "Model: {}; ground axes: x forward, y up, z right. ",
        analysis.model
    );
    md.push_str("Lengths in metres, areas in square metres. Percent of cycle = time normalised from the first to the last row.\n\n");
    md.push_str("| gait | source | rows |\n|---|---|---|\n");
    for g in &analysis.gaits {
        let _ = writeln!(md, "| {} | `{}` | {} |", g.label, g.source, g.poses.len());
    }
    md.push_str("\n## Figures\n\nEach also as `.svg`.\n\n");
    for (stem, title) in [
        (
            "stick_sagittal",
            "Stick figures, sagittal plane (paper Fig 5)",
        ),
        (
            "stick_frontal",
            "Stick figures, frontal plane (paper Fig 6)",
        ),
        (
            "stick_transverse",
            "Stick figures, transverse plane (paper Fig 7)",
        ),
        ("paths_sagittal", "Sagittal joint paths (paper Figs 8-9)"),
        ("distances", "Inter-limb distances (paper Fig 10)"),
    ] {
        let _ = writeln!(md, "- {title}: [{stem}.png]({stem}.png)");
    }
    md.push('\n');

    let _ = writeln!(md, "## Hip position shift relative to {reference}\n");
    md.push_str("Mean hip-centre position over the cycle minus that of the first gait.\n\n");
    md.push_str(
        "| gait | side | dx (m) | dy (m) | dz (m) | shift (m) |\n|---|---|---:|---:|---:|---:|\n",
    );
    for (g, side, d, len) in shifts {
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} |",
            g.label,
            side_name(*side),
            d[0],
            d[1],
            d[2],
            len
        );
    }

    md.push_str("\n## Distance between the legs\n\n| gait | joints | min (m) | max (m) | mean (m) | range (m) |\n|---|---|---:|---:|---:|---:|\n");
    for (g, name, min, max, mean) in dists {
        let _ = writeln!(
            md,
            "| {} | {name} | {min:.4} | {max:.4} | {mean:.4} | {:.4} |",
            g.label,
            max - min
        );
    }

    md.push_str("\n## Joint paths\n\nPer plane, the two axes are given as a / b: sagittal x / y, frontal z / y, transverse x / z. ");
    md.push_str("Area: area enclosed by the path over the cycle (shoelace formula).\n\n");
    md.push_str("| gait | side | joint | plane | min a, b | max a, b | mean a, b | range a, b | centroid a, b | area (m²) |\n");
    md.push_str("|---|---|---|---|---|---|---|---|---|---:|\n");
    for r in paths {
        let s = &r.stats;
        let pair = |v: [f64; 2]| format!("{:.4}, {:.4}", v[0], v[1]);
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.6} |",
            r.gait.label,
            side_name(r.side),
            r.joint.name(),
            r.plane.name().to_lowercase(),
            pair(s.min),
            pair(s.max),
            pair(s.mean),
            pair(s.range),
            pair(s.centroid),
            s.area
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_label_with_a_comma_or_a_quote_is_one_quoted_field() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        write_csv(
            &path,
            "gait,n",
            [
                ["normal, slow".to_string(), "1".to_string()],
                ["say \"hi\"".to_string(), "2".to_string()],
                ["plain".to_string(), "0.25".to_string()],
            ],
        )
        .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "gait,n\n\"normal, slow\",1\n\"say \"\"hi\"\"\",2\nplain,0.25\n"
        );
    }

    #[test]
    fn a_table_that_cannot_be_written_names_its_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing").join("t.csv");
        let e = write_csv(&path, "gait", [["x".to_string()]]).unwrap_err();
        assert!(
            matches!(&e, ReportError::Write { path: p, .. } if *p == path),
            "{e:?}"
        );
        assert!(e.to_string().ends_with("t.csv: cannot write"), "{e}");
    }
}
