//! Raw inertial recordings of one sensor: the shared CSV layout ([`read_csv`]) and Xsens MT
//! Manager `.txt` files with raw channels ([`read_xsens`]), each read whole into a
//! [`RawRecording`] with one sampling period.

use std::path::Path;

use qgait_opensim::vendor::XsensRaw;

use crate::FusionError;

/// One sensor's raw samples, in the sensor's frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RawRecording {
    /// The file, as named in messages.
    pub source: String,
    /// Sampling period, s.
    pub period: f64,
    /// Each sample's time, s (the file's own, or `k · period`).
    pub times: Vec<f64>,
    /// Each sample's 1-based line in the file.
    pub lines: Vec<usize>,
    /// Angular rate, rad/s.
    pub gyr: Vec<[f64; 3]>,
    /// Specific force, m/s² (about +9.81 along the upward axis at rest).
    pub acc: Vec<[f64; 3]>,
    /// Magnetic field (µT in the CSV layout; any unit: VQF uses its direction and relative
    /// changes of its norm), when the file has it.
    pub mag: Option<Vec<[f64; 3]>>,
    /// Reference orientations (`opt_w..z`: sensor to ENU), `None` in rows whose four cells are
    /// empty; absent without those columns.
    pub truth: Option<Vec<Option<[f64; 4]>>>,
    /// The rows BROAD's metric scores (`movement` = 1), when the file has that column.
    pub movement: Option<Vec<bool>>,
}

impl RawRecording {
    /// The number of samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }
}

/// Reads a CSV in the shared raw layout: a header naming the columns, then one row per sample.
/// By header name, in any order: `time` (s), `gyr_x..z` (rad/s), `acc_x..z` (m/s²), optionally
/// `mag_x..z` (µT), `opt_w..z` (a reference orientation, empty cells allowed) and `movement`
/// (0/1); any other column is ignored. The sampling period is `(t_last − t_0) / (rows − 1)`;
/// the times must increase and every time lie within a quarter period of `t_0 + k · period`
/// (no dropped or repeated samples, no drifting clock). Errors name the file, the line and the
/// column.
pub fn read_csv(path: &Path) -> Result<RawRecording, FusionError> {
    let source = path.display().to_string();
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| csv_error(&source, e))?;
    let header = reader.headers().map_err(|e| csv_error(&source, e))?.clone();
    let find = |name: &str| header.iter().position(|h| h == name);
    let need = |name: &str| {
        find(name).ok_or_else(|| FusionError::MissingColumn {
            path: source.clone(),
            name: name.to_string(),
        })
    };
    let time_at = need("time")?;
    let gyr_at = [need("gyr_x")?, need("gyr_y")?, need("gyr_z")?];
    let acc_at = [need("acc_x")?, need("acc_y")?, need("acc_z")?];
    let all = |names: &[&str]| -> Option<Vec<usize>> { names.iter().map(|n| find(n)).collect() };
    let mag_at = all(&["mag_x", "mag_y", "mag_z"]);
    let opt_at = all(&["opt_w", "opt_x", "opt_y", "opt_z"]);
    let movement_at = find("movement");
    let mut rec = RawRecording {
        source: source.clone(),
        mag: mag_at.as_ref().map(|_| Vec::new()),
        truth: opt_at.as_ref().map(|_| Vec::new()),
        movement: movement_at.map(|_| Vec::new()),
        ..RawRecording::default()
    };
    let mut record = csv::StringRecord::new();
    loop {
        match reader.read_record(&mut record) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(csv_error(&source, e)),
        }
        let line = record.position().map_or(0, |p| p.line() as usize);
        let num = |c: usize| -> Result<f64, FusionError> {
            let cell = record.get(c).unwrap_or("");
            cell.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| FusionError::Format {
                    path: source.clone(),
                    line,
                    message: format!(
                        "column {} (`{}`): `{cell}` is not a finite number",
                        c + 1,
                        &header[c]
                    ),
                })
        };
        let v3 = |at: &[usize]| -> Result<[f64; 3], FusionError> {
            Ok([num(at[0])?, num(at[1])?, num(at[2])?])
        };
        rec.times.push(num(time_at)?);
        rec.gyr.push(v3(&gyr_at)?);
        rec.acc.push(v3(&acc_at)?);
        if let (Some(at), Some(m)) = (&mag_at, &mut rec.mag) {
            m.push(v3(at)?);
        }
        if let (Some(at), Some(t)) = (&opt_at, &mut rec.truth) {
            let empty = at.iter().all(|&c| record.get(c).unwrap_or("").is_empty());
            t.push(if empty {
                None
            } else {
                Some([num(at[0])?, num(at[1])?, num(at[2])?, num(at[3])?])
            });
        }
        if let (Some(at), Some(m)) = (movement_at, &mut rec.movement) {
            m.push(num(at)? == 1.0);
        }
        rec.lines.push(line);
    }
    rec.period = regular_period(&source, &rec.times, &rec.lines)?;
    Ok(rec)
}

/// Reads an Xsens MT Manager `.txt` with raw channels (`Acc_*` m/s², `Gyr_*` rad/s and, for
/// 9D, `Mag_*` in Xsens' arbitrary units normalised to about 1; [`XsensRaw`]). The sampling
/// rate is the file's `// Update Rate` comment, else `rate` (Hz); sample `k` is at
/// `k / rate` s.
pub fn read_xsens(path: &Path, rate: Option<f64>) -> Result<RawRecording, FusionError> {
    let raw = XsensRaw::read(path, rate)?;
    let period = 1.0 / raw.rate;
    Ok(RawRecording {
        source: raw.source,
        period,
        times: (0..raw.lines.len()).map(|k| k as f64 * period).collect(),
        lines: raw.lines,
        gyr: raw.gyr,
        acc: raw.acc,
        mag: raw.mag,
        truth: None,
        movement: None,
    })
}

/// The one sampling period of `times`, or why there is none.
fn regular_period(source: &str, times: &[f64], lines: &[usize]) -> Result<f64, FusionError> {
    let timing = |line: usize, message: String| FusionError::Timing {
        path: source.to_string(),
        line,
        message,
    };
    if times.len() < 2 {
        return Err(timing(
            lines.first().copied().unwrap_or(1),
            format!(
                "{} sample(s): the sampling period needs at least two",
                times.len()
            ),
        ));
    }
    for k in 1..times.len() {
        if times[k] <= times[k - 1] {
            return Err(timing(
                lines[k],
                format!(
                    "time {} is not after the previous row's {} (the period must be positive)",
                    times[k],
                    times[k - 1]
                ),
            ));
        }
    }
    let n = times.len();
    let period = (times[n - 1] - times[0]) / (n - 1) as f64;
    for (k, (&t, &line)) in times.iter().zip(lines).enumerate() {
        let expected = times[0] + k as f64 * period;
        if (t - expected).abs() > 0.25 * period {
            return Err(timing(
                line,
                format!(
                    "time {t} is {:.3} periods off the regular grid t0 + k·{period:.6} s (irregular sampling: a dropped or repeated sample, or a drifting clock; VQF needs one period)",
                    (t - expected) / period
                ),
            ));
        }
    }
    Ok(period)
}

/// A CSV error with the file and, where the `csv` crate knows it, the line.
fn csv_error(source: &str, e: csv::Error) -> FusionError {
    let line = e.position().map_or(1, |p| p.line() as usize);
    match e.kind() {
        csv::ErrorKind::Io(_) => FusionError::Io {
            path: source.to_string(),
            error: match e.into_kind() {
                csv::ErrorKind::Io(io) => io,
                _ => unreachable!("matched as Io"),
            },
        },
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => FusionError::Format {
            path: source.to_string(),
            line,
            message: format!("{len} cells, but the header names {expected_len} columns"),
        },
        _ => FusionError::Format {
            path: source.to_string(),
            line,
            message: e.to_string(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("qgait-fusion-raw-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    const HEADER: &str = "movement,acc_x,acc_y,acc_z,time,gyr_x,gyr_y,gyr_z,extra\n";

    #[test]
    fn columns_by_name_in_any_order() {
        let p = write(
            "order.csv",
            &format!("{HEADER}1,0,0,9.8,0,0.1,0.2,0.3,x\n1,0,0,9.8,0.01,0.1,0.2,0.3,y\n1,0,0,9.8,0.02,0.1,0.2,0.3,\n"),
        );
        let r = read_csv(&p).unwrap();
        assert_eq!(r.len(), 3);
        assert!((r.period - 0.01).abs() < 1e-12);
        assert_eq!(r.gyr[1], [0.1, 0.2, 0.3]);
        assert_eq!(r.acc[2], [0.0, 0.0, 9.8]);
        assert_eq!(r.lines, [2, 3, 4]);
        assert!(r.mag.is_none() && r.truth.is_none());
        assert_eq!(r.movement, Some(vec![true; 3]));
    }

    #[test]
    fn a_bad_cell_names_line_and_column() {
        let p = write(
            "bad.csv",
            &format!("{HEADER}1,0,0,9.8,0,0.1,0.2,0.3,\n1,0,0,9.8,0.01,0.1,oops,0.3,\n"),
        );
        let e = read_csv(&p).unwrap_err().to_string();
        assert!(
            e.contains("bad.csv:3:") && e.contains("column 7 (`gyr_y`)"),
            "{e}"
        );
        assert!(e.contains("`oops`"), "{e}");
    }

    #[test]
    fn a_short_row_names_its_line() {
        let p = write(
            "short.csv",
            &format!("{HEADER}1,0,0,9.8,0,0.1,0.2,0.3,\n1,0,0,9.8\n"),
        );
        let e = read_csv(&p).unwrap_err().to_string();
        assert!(e.contains("short.csv:3:") && e.contains("4 cells"), "{e}");
    }

    #[test]
    fn a_missing_column_is_named() {
        let p = write("nogyr.csv", "time,acc_x,acc_y,acc_z\n0,0,0,9.8\n");
        let e = read_csv(&p).unwrap_err().to_string();
        assert!(e.contains("no column `gyr_x`"), "{e}");
    }

    fn rows(times: &[f64]) -> String {
        let mut s = HEADER.to_string();
        for t in times {
            s += &format!("1,0,0,9.8,{t},0,0,0,\n");
        }
        s
    }

    #[test]
    fn irregular_or_non_positive_periods_are_refused() {
        let e = read_csv(&write("back.csv", &rows(&[0.0, 0.01, 0.01, 0.03])))
            .unwrap_err()
            .to_string();
        assert!(e.contains("back.csv:4:") && e.contains("not after"), "{e}");
        // A dropped sample (0.02 missing) in 0.01 s steps.
        let times: Vec<f64> = (0..20)
            .filter(|&k| k != 10)
            .map(|k| k as f64 * 0.01)
            .collect();
        let e = read_csv(&write("gap.csv", &rows(&times)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("irregular sampling"), "{e}");
        let e = read_csv(&write("one.csv", &rows(&[0.0])))
            .unwrap_err()
            .to_string();
        assert!(e.contains("at least two"), "{e}");
        // Jitter within a quarter period is accepted.
        let times: Vec<f64> = (0..20)
            .map(|k| k as f64 * 0.01 + if k % 2 == 1 { 0.001 } else { 0.0 })
            .collect();
        assert!(read_csv(&write("jitter.csv", &rows(&times))).is_ok());
    }

    #[test]
    fn empty_truth_cells_are_none() {
        let p = write(
            "truth.csv",
            "time,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z,opt_w,opt_x,opt_y,opt_z\n0,0,0,0,0,0,9.8,,,,\n0.01,0,0,0,0,0,9.8,1,0,0,0\n",
        );
        let r = read_csv(&p).unwrap();
        assert_eq!(r.truth, Some(vec![None, Some([1.0, 0.0, 0.0, 0.0])]));
    }
}
