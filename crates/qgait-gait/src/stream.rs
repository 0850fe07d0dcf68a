//! `qgait gait` on recordings of any length in bounded memory: a recording is read as a stream
//! of rows and analysed in windows of at most [`WINDOW_ROWS`] rows, each by the batch analysis
//! ([`crate::analyse_with_pelvis`]), and what the report needs is folded into a [`Pool`] as each
//! window is done: the sums of the strides' numbers ([`Stride`] into [`Sums`]), the running
//! mean and SD of the time-normalised curves (Welford), a bounded sample of individual stride
//! curves, the events written to `events.csv` as they are found, the walking bouts as they
//! close ([`crate::bouts::Finder`]), and [`EXCERPT`] seconds of each recording for the events
//! figure.
//!
//! Consecutive windows overlap by [`OVERLAP`] seconds, and the boundary between them is the
//! middle of the overlap: each window keeps the strides that start, and the events that
//! happen, on its side of it. A stride lasts well under 3 s, and the event detection looks at
//! most [`events::SEARCH_SPAN`] s and the direction of progression
//! [`events::PROGRESSION_WINDOW`] s around a frame, so a stride kept lies wholly in its window
//! with more than [`OVERLAP`]` / 2 - 3` s of recording on either side of it: each stride is
//! kept exactly once, and found as the analysis of the whole recording would find it (the
//! rules' thresholds, [`crate::rules`], are each window's own: a window of 4 minutes holds a
//! couple of hundred strides). A recording of at most [`WINDOW_ROWS`] rows is one window: its
//! results are the batch analysis's.
//!
//! Not streamed: a device's frames CSV and a `builtin:` gait (read whole, as before), and
//! `--cycle whole` (one cycle is one window, whatever its length).

use std::io::Write;

use qgait_kernel::Vec3;
use qgait_model::choice::Model;
use qgait_model::motion::source::{default_label, MotionRows, SourceError, BUILTIN_PREFIX};
use qgait_opensim::diagnostics::{Location, Warning, WarningText};
use qgait_opensim::mot::{MotionTable, Row};

use crate::angles::CgmPelvis;
use crate::bouts::Bout;
use crate::cycles::{Curve, Dropped, POINTS};
use crate::events::{self, Kind};
use crate::rules::Gait;
use crate::spatiotemporal::{Stride, Sums, SIDES};
use crate::trial::{self, AngleUnit, TrialError};
use crate::{AnalysisError, CycleMode, Walk};

/// The most rows of one window: 4 minutes at 100 Hz. The batch analysis holds about 1.2 kB
/// per row, so a window peaks near 30 MB whatever the recording's length.
pub const WINDOW_ROWS: usize = 24_000;

/// The overlap of consecutive windows (s); at most half a window's rows.
pub const OVERLAP: f64 = 20.0;

/// The seconds of each recording drawn in the events figure: the whole of a short recording,
/// a minute of a long one (a day's events on one axis would be a solid blob).
pub const EXCERPT: f64 = 60.0;

/// The seconds before a recording's first stride that the events figure shows.
pub const LEAD_IN: f64 = 2.0;

/// Individual strides' curves kept per side for the figures, at most (evenly spread over the
/// recordings: every k-th stride, k doubling as they come).
pub const STRIDE_SAMPLE: usize = 40;

/// Why a recording cannot be analysed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StreamError {
    /// It cannot be read or evaluated.
    #[error(transparent)]
    Trial(#[from] TrialError),
    /// It cannot be analysed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// `events.csv` cannot be written.
    #[error("events.csv: {0}")]
    Events(#[from] csv::Error),
}

/// The first seconds of a recording as the events figure draws them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Excerpt {
    /// Time of each frame (s).
    pub time: Vec<f64>,
    /// Heel of each side forward of the pelvis along the direction of progression (m).
    pub heel: [Vec<f64>; 2],
    /// Toe tip of each side, likewise (m).
    pub toe: [Vec<f64>; 2],
    /// Detected heel strikes of each side: the index into [`Excerpt::time`].
    pub heel_strikes: [Vec<usize>; 2],
    /// Detected toe offs of each side: the index into [`Excerpt::time`].
    pub toe_offs: [Vec<usize>; 2],
}

/// One recording as the report shows it, its strides folded into the [`Pool`].
#[derive(Clone, Debug)]
pub struct Recording {
    /// Label (the file stem).
    pub label: String,
    /// Where it came from (the path or `builtin:` spec).
    pub source: String,
    /// Its frames (rows analysed).
    pub frames: usize,
    /// Time of its first frame (s).
    pub start: f64,
    /// Time of its last frame (s).
    pub end: f64,
    /// The windows it was analysed in.
    pub windows: usize,
    /// Strides of each side.
    pub strides: [usize; 2],
    /// Strides left out, per side.
    pub dropped: [Dropped; 2],
    /// Heel strikes detected, per side.
    pub heel_strikes: [usize; 2],
    /// Its gaps in time and runs of rows left out.
    pub breaks: usize,
    /// How its last row leads back into its first (`None` when it was read in several
    /// windows: too long to be one cycle).
    pub wrap: Option<crate::trial::Wrap>,
    /// How its cycles were taken.
    pub mode: CycleMode,
    /// What the rules found in its first window ([`crate::rules`]); `None` when they did not run
    /// there.
    pub gait: Option<Gait>,
    /// The rules ran in every window.
    pub rules_everywhere: bool,
    /// What the model can move ([`crate::trial::Trial::seen`]).
    pub seen: crate::angles::Seen,
    /// The CGM's pelvis frame.
    pub pelvis: CgmPelvis,
    /// It has joint angles.
    pub has_angles: bool,
    /// The longest hip-to-ankle distance (m).
    pub leg_length: Option<f64>,
    /// Its walking bouts, in time order ([`Recording::bouts`] after [`Pool::finish`]).
    pub bouts: Vec<Bout>,
    /// The events figure's excerpt: [`EXCERPT`] seconds from its start, or from [`LEAD_IN`]
    /// before its first stride when that comes more than half of [`EXCERPT`] after the start.
    pub excerpt: Excerpt,
    /// The bouts, found as the strides come.
    finder: crate::bouts::Finder,
    /// Over the windows the rules ran in, weighted by their strides: the sums of weight,
    /// speed, duty factor (with its weight) and travel ratio (with its weight).
    merged: [f64; 7],
}

impl Recording {
    /// The number of cycles of each side.
    pub fn strides(&self) -> [usize; 2] {
        self.strides
    }

    /// How its events were found; `None` when its windows differ (the rules in some, Zeni's
    /// in others).
    pub fn event_method(&self) -> Option<crate::rules::EventMethod> {
        if self.rules_everywhere || self.gait.is_none() {
            Some(crate::rules::EventMethod::of(self.gait.as_ref()))
        } else {
            None
        }
    }

    /// Its duration (s).
    pub fn duration(&self) -> f64 {
        self.end - self.start
    }

    /// `Ok` when either side has a cycle, else [`AnalysisError::NoStride`].
    pub fn require_strides(&self) -> Result<(), AnalysisError> {
        if self.strides.iter().any(|&n| n > 0) {
            return Ok(());
        }
        Err(crate::no_stride(
            &self.source,
            self.heel_strikes,
            self.breaks,
            self.duration(),
            self.wrap,
        ))
    }
}

/// The running mean and sum of squared deviations of curves of [`POINTS`] points (Welford).
#[derive(Clone, Debug)]
struct Running {
    n: usize,
    mean: Vec<f64>,
    m2: Vec<f64>,
}

impl Running {
    fn new() -> Self {
        Self {
            n: 0,
            mean: vec![0.0; POINTS],
            m2: vec![0.0; POINTS],
        }
    }

    fn add(&mut self, curve: &[f64]) {
        self.n += 1;
        let n = self.n as f64;
        for ((m, m2), &x) in self.mean.iter_mut().zip(&mut self.m2).zip(curve) {
            let d = x - *m;
            *m += d / n;
            *m2 += d * (x - *m);
        }
    }

    fn curve(&self) -> Option<Curve> {
        (self.n > 0).then(|| Curve {
            mean: self.mean.clone(),
            sd: self
                .m2
                .iter()
                .map(|m2| {
                    if self.n < 2 {
                        0.0
                    } else {
                        (m2 / (self.n - 1) as f64).sqrt()
                    }
                })
                .collect(),
            n: self.n,
        })
    }
}

/// Where `events.csv` goes: a file written as the events are found, or memory (a report built
/// from walks in memory, [`crate::output::build`]).
enum Sink {
    File(
        std::path::PathBuf,
        csv::Writer<std::io::BufWriter<std::fs::File>>,
    ),
    Memory(csv::Writer<Vec<u8>>),
    None,
}

/// `events.csv` once the pool is finished.
#[derive(Clone, Debug, PartialEq)]
pub enum EventsCsv {
    /// Written to this file.
    File(std::path::PathBuf),
    /// Its text.
    Text(String),
    /// Not kept (a reference motion's).
    None,
}

/// What the report needs of every recording, folded window by window.
pub struct Pool {
    /// The recordings, in order.
    pub recordings: Vec<Recording>,
    /// The strides' numbers of each side over every recording, summed.
    pub strides: [Sums; 2],
    running: [[Running; 9]; 2],
    toe_off: [(f64, usize); 2],
    sample: [Vec<[Vec<f64>; 9]>; 2],
    sample_every: [usize; 2],
    sample_seen: [usize; 2],
    several: bool,
    sink: Sink,
}

/// What each window of a recording is analysed with.
#[derive(Clone, Debug)]
pub struct Settings {
    /// How the cycles are found.
    pub mode: CycleMode,
    /// A known belt speed (m/s).
    pub given_speed: Option<f64>,
    /// The motions' angle unit whatever their headers say.
    pub angles_in: Option<AngleUnit>,
    /// The CGM's pelvis frame.
    pub pelvis: CgmPelvis,
}

impl Pool {
    /// A pool whose `events.csv` is written to `path` as the events are found; `several`: the
    /// file has a `motion` column (more than one recording).
    pub fn to_file(path: &std::path::Path, several: bool) -> Result<Self, std::io::Error> {
        let file = std::fs::File::create(path)?;
        let w = csv::Writer::from_writer(std::io::BufWriter::new(file));
        Self::with(Sink::File(path.to_path_buf(), w), several)
            .map_err(|e| std::io::Error::other(e.to_string()))
    }

    /// A pool that keeps `events.csv` in memory.
    pub fn in_memory(several: bool) -> Self {
        Self::with(Sink::Memory(csv::Writer::from_writer(Vec::new())), several)
            .expect("writing to memory cannot fail")
    }

    /// A pool that keeps no events (a reference motion's).
    pub fn without_events() -> Self {
        Self::with(Sink::None, false).expect("no writer")
    }

    fn with(mut sink: Sink, several: bool) -> Result<Self, csv::Error> {
        let mut head = vec!["side", "event", "time"];
        if several {
            head.push("motion");
        }
        match &mut sink {
            Sink::File(_, w) => w.write_record(&head)?,
            Sink::Memory(w) => w.write_record(&head)?,
            Sink::None => {}
        }
        Ok(Self {
            recordings: Vec::new(),
            strides: Default::default(),
            running: std::array::from_fn(|_| std::array::from_fn(|_| Running::new())),
            toe_off: [(0.0, 0); 2],
            sample: Default::default(),
            sample_every: [1; 2],
            sample_seen: [0; 2],
            several,
            sink,
        })
    }

    /// Folds one window of a recording in: the strides that start, and the events that
    /// happen, in `core` (s). `first`: the recording's first window (a new recording).
    pub fn add(
        &mut self,
        walk: &Walk,
        core: std::ops::Range<f64>,
        first: bool,
    ) -> Result<(), csv::Error> {
        let t = &walk.trial.time;
        let inside = |time: f64| time >= core.start && time < core.end;
        if first {
            self.recordings.push(Recording {
                label: walk.trial.label.clone(),
                source: walk.trial.source.clone(),
                frames: 0,
                start: t[0],
                end: t[0],
                windows: 0,
                strides: [0; 2],
                dropped: [Dropped::default(); 2],
                heel_strikes: [0; 2],
                breaks: 0,
                wrap: walk.trial.wrap(),
                mode: walk.mode,
                gait: walk.gait.clone(),
                rules_everywhere: true,
                seen: walk.trial.seen,
                pelvis: walk.pelvis.clone(),
                has_angles: walk.angles.is_some(),
                leg_length: None,
                bouts: Vec::new(),
                excerpt: Excerpt::default(),
                finder: Default::default(),
                merged: [0.0; 7],
            });
        }
        let several = self.several;
        let rec = self
            .recordings
            .last_mut()
            .expect("a recording's first window comes first");
        // Frames: those in the core (a frame in two windows counts once).
        rec.frames += t.iter().filter(|&&x| inside(x)).count();
        rec.end = rec.end.max(*t.last().unwrap_or(&t[0]));
        rec.windows += 1;
        if rec.windows > 1 {
            rec.wrap = None;
        }
        // The rules' findings from the first window that has them (a day may start at rest);
        // a window without the rules matters only if it keeps strides.
        if rec.gait.is_none() {
            rec.gait = walk.gait.clone();
        }
        let keeps_strides = walk.cycles.iter().flatten().any(|c| inside(c.start));
        rec.rules_everywhere &= walk.gait.is_some() || !keeps_strides;
        rec.breaks += walk
            .trial
            .breaks
            .iter()
            .filter(|&&b| b < t.len() && inside(t[b]))
            .count();
        for s in 0..2 {
            rec.heel_strikes[s] += walk.events.heel_strike[s]
                .iter()
                .filter(|e| inside(e.time))
                .count();
        }
        for s in 0..2 {
            for (start, reason) in &walk.left_out[s] {
                if inside(*start) {
                    rec.dropped[s].count(*reason);
                }
            }
        }
        let leg = walk
            .trial
            .frames
            .iter()
            .flat_map(|f| f.iter().map(|l| Vec3::distance(l.hip, l.ankle)))
            .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))));
        rec.leg_length = match (rec.leg_length, leg) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        // The excerpt: from a little before the first stride kept, once there is one.
        let first_stride = walk
            .cycles
            .iter()
            .flatten()
            .filter(|c| inside(c.start))
            .map(|c| c.start)
            .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.min(t))));
        if rec.strides == [0, 0] {
            if let Some(t) = first_stride {
                // The recording's start when the walking starts early enough in it.
                let from = if t - rec.start <= EXCERPT / 2.0 {
                    rec.start
                } else {
                    t - LEAD_IN
                };
                rec.excerpt = excerpt(walk, from);
            } else if first {
                rec.excerpt = excerpt(walk, t[0]);
            }
        }
        // The bouts: the local speeds first, then the strides in the order of their starts.
        if let Some(g) = &walk.gait {
            rec.finder.speeds(
                g.local_speeds
                    .iter()
                    .filter(|(a, _, _)| inside(*a))
                    .copied(),
            );
        }
        let mut spans: Vec<(f64, f64, usize)> = (0..2)
            .flat_map(|s| {
                walk.cycles[s]
                    .iter()
                    .filter(|c| inside(c.start))
                    .map(move |c| (c.start, c.start + c.duration, s))
            })
            .collect();
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (start, end, side) in spans {
            rec.finder.stride(start, end, side);
        }
        if let Some(g) = &walk.gait {
            let w = walk
                .cycles
                .iter()
                .flatten()
                .filter(|c| inside(c.start))
                .count() as f64;
            let m = &mut rec.merged;
            m[0] += w;
            m[1] += w * g.speed;
            if let Some(d) = g.duty {
                m[2] += w;
                m[3] += w * d;
            }
            if let Some(r) = g.travel_ratio {
                m[4] += w;
                m[5] += w * r;
            }
        }
        // Strides.
        for s in 0..2 {
            for c in walk.cycles[s].iter().filter(|c| inside(c.start)) {
                rec.strides[s] += 1;
                self.strides[s].add(&Stride::of(
                    &walk.trial,
                    &walk.forward,
                    c,
                    walk.gait.as_ref(),
                ));
                if let Some(to) = c.toe_off {
                    self.toe_off[s].0 += c.percent(to);
                    self.toe_off[s].1 += 1;
                }
                if let Some(a) = &walk.angles {
                    let curves: [Vec<f64>; 9] =
                        std::array::from_fn(|v| c.normalise(|f| a[s][v][f]));
                    for (r, curve) in self.running[s].iter_mut().zip(&curves) {
                        r.add(curve);
                    }
                    if self.sample_seen[s] % self.sample_every[s] == 0 {
                        self.sample[s].push(curves);
                        if self.sample[s].len() >= 2 * STRIDE_SAMPLE {
                            // Keep every other one, and from now on every other one of those.
                            let kept: Vec<_> = std::mem::take(&mut self.sample[s])
                                .into_iter()
                                .step_by(2)
                                .collect();
                            self.sample[s] = kept;
                            self.sample_every[s] *= 2;
                        }
                    }
                    self.sample_seen[s] += 1;
                }
            }
        }
        // Events, in time order.
        let source = walk.trial.source.as_str();
        let mut write = |side: usize, kind: Kind, time: f64| -> Result<(), csv::Error> {
            let time = crate::number::round(time, 6);
            let mut row = vec![SIDES[side], kind.name(), time.as_str()];
            if several {
                row.push(source);
            }
            match &mut self.sink {
                Sink::File(_, w) => w.write_record(&row),
                Sink::Memory(w) => w.write_record(&row),
                Sink::None => Ok(()),
            }
        };
        for (s, kind, time) in walk.event_list() {
            if inside(time) || walk.mode == CycleMode::Whole {
                write(s, kind, time)?;
            }
        }
        Ok(())
    }

    /// The mean and SD of every stride's curve, per side and variable (101 points); `None`
    /// where no recording has angles or a side has no cycle.
    pub fn curves(&self) -> [[Option<Curve>; 9]; 2] {
        std::array::from_fn(|s| std::array::from_fn(|v| self.running[s][v].curve()))
    }

    /// The mean percentage of the cycle at which each side's toe comes off.
    pub fn toe_off_percent(&self) -> [Option<f64>; 2] {
        self.toe_off.map(|(sum, n)| (n > 0).then(|| sum / n as f64))
    }

    /// The longest hip-to-ankle distance of either side over the recordings (m).
    pub fn leg_length(&self) -> Option<f64> {
        self.recordings
            .iter()
            .filter_map(|r| r.leg_length)
            .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))))
    }

    /// A sample of individual strides' curves per side (`[variable][point]`, degrees), at
    /// most [`STRIDE_SAMPLE`] and some, spread over the recordings.
    pub fn stride_sample(&self) -> &[Vec<[Vec<f64>; 9]>; 2] {
        &self.sample
    }

    /// Ends the pool: the bouts of each recording, `events.csv` flushed.
    pub fn finish(mut self) -> Result<Finished, std::io::Error> {
        for r in &mut self.recordings {
            // A long recording's rules: the mode, ground and notes of the first window that
            // has them, the strides' mean of the windows' speed, duty factor and travel ratio.
            let m = r.merged;
            if let (Some(g), true) = (&mut r.gait, r.windows > 1 && m[0] > 0.0) {
                g.speed = m[1] / m[0];
                if m[2] > 0.0 {
                    g.duty = Some(m[3] / m[2]);
                }
                if m[4] > 0.0 {
                    g.travel_ratio = Some(m[5] / m[4]);
                }
                g.froude = g.speed * g.speed / (crate::rules::G * g.leg_length);
            }
            r.bouts = std::mem::take(&mut r.finder).finish(r.gait.as_ref().map(|g| g.speed));
        }
        let events = match std::mem::replace(&mut self.sink, Sink::None) {
            Sink::File(path, w) => {
                let mut inner = w.into_inner().map_err(|e| e.into_error())?;
                inner.flush()?;
                EventsCsv::File(path)
            }
            Sink::Memory(w) => {
                let bytes = w.into_inner().map_err(|e| e.into_error())?;
                EventsCsv::Text(String::from_utf8_lossy(&bytes).into_owned())
            }
            Sink::None => EventsCsv::None,
        };
        Ok(Finished(self, events))
    }
}

/// A pool whose recordings are complete ([`Pool::finish`]), and its `events.csv`.
pub struct Finished(pub Pool, pub EventsCsv);

/// The [`EXCERPT`] seconds of a window from `from` (s; its first frame at the earliest).
fn excerpt(walk: &Walk, from: f64) -> Excerpt {
    let t = &walk.trial.time;
    let a = t.partition_point(|&x| x < from).min(t.len() - 1);
    let n = t.partition_point(|&x| x <= t[a] + EXCERPT).max(a + 1);
    let frames = &walk.trial.frames[a..n];
    let forward = &walk.forward[a..n];
    let keep = |list: &[events::Event]| -> Vec<usize> {
        list.iter()
            .map(|e| e.frame)
            .filter(|&f| f >= a && f < n)
            .map(|f| f - a)
            .collect()
    };
    Excerpt {
        time: t[a..n].to_vec(),
        heel: [0, 1].map(|s| events::along(frames, forward, |f| f[s].heel)),
        toe: [0, 1].map(|s| events::along(frames, forward, |f| f[s].toe)),
        heel_strikes: [0, 1].map(|s| keep(&walk.events.heel_strike[s])),
        toe_offs: [0, 1].map(|s| keep(&walk.events.toe_off[s])),
    }
}

/// Analyses `source` (a `.mot`/`.sto` motion, a `builtin:` gait or a device's frames CSV) with
/// `model` into `pool`, window by window; `warn` gets the warnings (each text once).
pub fn analyse_into(
    pool: &mut Pool,
    source: &str,
    model: &Model,
    settings: &Settings,
    warn: &mut dyn FnMut(Vec<Warning>),
) -> Result<(), StreamError> {
    analyse_in_windows(pool, source, model, settings, WINDOW_ROWS, warn)
}

/// A recording read from a motion file: not a `builtin:` gait (one cycle by construction) nor a
/// device's frames CSV (points only, read whole).
pub fn is_motion_file(source: &str) -> bool {
    !source.starts_with(BUILTIN_PREFIX) && !qgait_device::frames_csv::is_frames_csv(source)
}

/// [`analyse_into`] with windows of at most `window_rows` rows (at least 2 × 100).
pub fn analyse_in_windows(
    pool: &mut Pool,
    source: &str,
    model: &Model,
    settings: &Settings,
    window_rows: usize,
    warn: &mut dyn FnMut(Vec<Warning>),
) -> Result<(), StreamError> {
    let window_rows = window_rows.max(200);
    // Each warning once: a row in two windows is warned about once, and a column's summary
    // (`column `x`: 100 of 24000 values outside its range ...`) once per recording, from the
    // first window that has it, the others counted.
    let (mut exact, mut like) = (
        std::collections::HashSet::new(),
        std::collections::HashSet::new(),
    );
    let mut like_seen = 0usize;
    let mut warn_once = |w: Vec<Warning>| {
        let fresh: Vec<Warning> = w
            .into_iter()
            .filter(|w| {
                let text = w.to_string();
                let column_summary = text.contains(": column `");
                let like_text = text.replace(|c: char| c.is_ascii_digit(), "");
                let exact_new = exact.insert(text);
                if !column_summary {
                    return exact_new;
                }
                let like_new = like.insert(like_text);
                if !like_new && exact_new {
                    like_seen += 1;
                }
                like_new
            })
            .collect();
        if !fresh.is_empty() {
            warn(fresh);
        }
    };
    let analyse = |t| {
        crate::analyse_with_pelvis(
            t,
            settings.mode,
            settings.given_speed,
            settings.pelvis.clone(),
        )
    };
    let whole = !is_motion_file(source) || settings.mode == CycleMode::Whole;
    if whole {
        let (t, w) = trial::load_with(source, model, settings.angles_in)?;
        warn_once(w);
        if settings.mode == CycleMode::Whole {
            if let Some(w) = t.wrap().filter(|w| !w.leads_back()) {
                warn_once(vec![Warning::Limitation(WarningText {
                    at: Some(Location::file(source)),
                    detail: format!(
                        "--cycle whole takes the recording as one gait cycle, but {}: its percentages are of the recording's {:.2} s",
                        w.describe(),
                        t.time[t.time.len() - 1] - t.time[0]
                    ),
                })]);
            }
        }
        let walk = analyse(t)?;
        pool.add(&walk, f64::NEG_INFINITY..f64::INFINITY, true)?;
        return Ok(());
    }
    let (mut rows, w) = MotionRows::open(source).map_err(TrialError::Source)?;
    warn_once(w);
    let header = rows.header().clone();
    let label = default_label(source);
    let mut buffer: Vec<Row> = Vec::new();
    let mut from = f64::NEG_INFINITY;
    let mut first = true;
    loop {
        let next = rows
            .next_row()
            .map_err(|e| TrialError::Source(SourceError::File(e)))?;
        let done = next.is_none();
        if let Some((row, _)) = next {
            buffer.push(row);
        }
        if buffer.len() < window_rows && !done {
            continue;
        }
        if buffer.is_empty() {
            break;
        }
        let last = buffer[buffer.len() - 1].values[0];
        // The rows carried into the next window, and the boundary between the two.
        let (carry, to) = if done {
            (buffer.len(), f64::INFINITY)
        } else {
            let carry = buffer
                .partition_point(|r| r.values[0] <= last - OVERLAP)
                .max(buffer.len() / 2);
            (carry, (buffer[carry].values[0] + last) / 2.0)
        };
        let table = MotionTable::from_rows(&header, &buffer);
        let (t, w) = trial::from_table(
            source,
            label.clone(),
            table,
            rows.take_warnings(),
            model,
            settings.angles_in,
        )?;
        warn_once(w);
        let walk = analyse(t)?;
        pool.add(&walk, from..to, first)?;
        drop(walk);
        first = false;
        from = to;
        buffer.drain(..carry);
        if done {
            break;
        }
    }
    warn_once(rows.take_warnings());
    if like_seen > 0 {
        warn(vec![Warning::Suppressed(WarningText {
            at: Some(Location::file(source)),
            detail: format!(
                "{like_seen} more warnings about its columns in later windows of {window_rows} rows, like those above, not shown"
            ),
        })]);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output;

    #[test]
    fn welford_is_the_two_pass_mean_and_sd() {
        let curves: Vec<Vec<f64>> = (0..7)
            .map(|k| {
                (0..POINTS)
                    .map(|p| (p as f64 * 0.1 + k as f64).sin() * 30.0 + 1e3)
                    .collect()
            })
            .collect();
        let mut r = Running::new();
        for c in &curves {
            r.add(c);
        }
        let (a, b) = (r.curve().unwrap(), Curve::of(&curves).unwrap());
        assert_eq!(a.n, b.n);
        for p in 0..POINTS {
            assert!((a.mean[p] - b.mean[p]).abs() < 1e-9, "{p}");
            assert!((a.sd[p] - b.sd[p]).abs() < 1e-9, "{p}");
        }
        assert!(Running::new().curve().is_none());
    }

    /// gait2392 and the default settings (`--cycle auto`, no belt speed, the fixed CGM pelvis).
    fn gait2392_auto() -> (qgait_model::choice::Model, Settings) {
        let model = qgait_model::choice::Model::load("gait2392", None)
            .unwrap()
            .0;
        let settings = Settings {
            mode: CycleMode::Auto,
            given_speed: None,
            angles_in: None,
            pelvis: CgmPelvis::FIXED,
        };
        (model, settings)
    }

    /// A straight walk of the built-in cycle repeated at 100 Hz for `walk` s, a stand of
    /// `stand` s, and the walk again for `again` s, as a `.mot`.
    fn walk_stand_walk(path: &std::path::Path, walk: f64, stand: f64, again: f64) {
        let (table, _) = qgait_model::motion::source::load_motion("builtin:normal").unwrap();
        let t = table.time();
        let period = t[t.len() - 1] - t[0];
        let labels = table.labels().to_vec();
        let at = |c: usize, phase: f64| {
            let x = t[0] + phase.rem_euclid(1.0) * period;
            let k = t.partition_point(|&v| v <= x).clamp(1, t.len() - 1);
            let w = (x - t[k - 1]) / (t[k] - t[k - 1]);
            table.value(k - 1, c) * (1.0 - w) + table.value(k, c) * w
        };
        let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
        let rows = ((walk + stand + again) * 100.0) as usize;
        qgait_opensim::mot::write_mot_header(
            &mut f,
            "walk",
            &labels,
            table.in_degrees(),
            Some(rows),
            false,
        )
        .unwrap();
        for i in 0..rows {
            let time = i as f64 / 100.0;
            // Standing: the pose at the end of the first walk.
            let moving = if time < walk {
                time
            } else if time < walk + stand {
                walk
            } else {
                time - stand
            };
            let mut row = vec![time];
            row.extend((1..labels.len()).map(|c| at(c, 0.37 + moving / period)));
            qgait_opensim::mot::write_mot_row(&mut f, &row).unwrap();
        }
    }

    /// A recording that starts at rest (a day's first minutes): the rules' findings come from
    /// the first window that walks, and the windows at rest do not mark the rules as missing.
    #[test]
    fn a_recording_that_starts_at_rest_has_the_rules_of_its_walk() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rest_then_walk.mot");
        walk_stand_walk(&path, 0.0, 60.0, 60.0);
        let (model, settings) = gait2392_auto();
        let mut pool = Pool::in_memory(false);
        let source = path.to_str().unwrap();
        analyse_in_windows(&mut pool, source, &model, &settings, 4_000, &mut |_| {}).unwrap();
        let finished = output::finish(pool).unwrap();
        let r = &finished.0.recordings[0];
        assert!(r.windows >= 3, "{}", r.windows);
        assert!(r.strides[0] > 30 && r.strides[1] > 30, "{:?}", r.strides);
        let gait = r.gait.as_ref().expect("the rules of the walk");
        assert_eq!(gait.mode, crate::rules::Mode::Walking);
        assert!(r.rules_everywhere);
        assert_eq!(r.bouts.len(), 1, "{:?}", r.bouts);
        assert!(r.bouts[0].start > 55.0, "{:?}", r.bouts[0]);
    }

    /// A recording analysed in windows of 40 s gives what it gives whole: every event once, the
    /// same strides, bouts, parameters and curves.
    #[test]
    fn windows_give_what_the_whole_recording_gives() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("walk.mot");
        walk_stand_walk(&path, 50.0, 15.0, 50.0);
        let source = path.to_str().unwrap();
        let (model, settings) = gait2392_auto();
        let run = |window: usize| {
            let mut pool = Pool::in_memory(false);
            analyse_in_windows(&mut pool, source, &model, &settings, window, &mut |_| {}).unwrap();
            output::finish(pool).unwrap()
        };
        let (whole, windowed) = (run(usize::MAX), run(4_000));
        let (a, b) = (&whole.0.recordings[0], &windowed.0.recordings[0]);
        assert_eq!(a.windows, 1);
        assert!(b.windows >= 4, "{}", b.windows);
        assert_eq!(a.frames, b.frames);
        assert!(a.strides[0] > 50 && a.strides[1] > 50, "{:?}", a.strides);
        assert_eq!(a.strides, b.strides);
        // The one "stride" across the stand (heel strike to heel strike 16 s apart, left out
        // whole as incomplete) is in no window whole: not counted.
        for s in 0..2 {
            let (x, y) = (a.dropped[s], b.dropped[s]);
            assert_eq!((x.incomplete, x.duration, x.turning), (1, 0, 0), "{x:?}");
            assert_eq!((y.incomplete, y.duration, y.turning), (0, 0, 0), "{y:?}");
        }
        assert_eq!(a.bouts.len(), 2, "{:?}", a.bouts);
        assert_eq!(a.bouts.len(), b.bouts.len());
        for (x, y) in a.bouts.iter().zip(&b.bouts) {
            assert!(
                (x.start - y.start).abs() < 1e-4 && (x.end - y.end).abs() < 1e-4,
                "{x:?} {y:?}"
            );
            assert_eq!(x.strides, y.strides);
        }
        let events = |f: &Finished| -> Vec<(String, String, f64)> {
            let EventsCsv::Text(text) = &f.1 else {
                panic!("events in memory")
            };
            text.lines()
                .skip(1)
                .map(|l| {
                    let v: Vec<&str> = l.split(',').collect();
                    (v[0].to_string(), v[1].to_string(), v[2].parse().unwrap())
                })
                .collect()
        };
        let (ea, eb) = (events(&whole), events(&windowed));
        assert_eq!(ea.len(), eb.len());
        for (x, y) in ea.iter().zip(&eb) {
            assert_eq!((&x.0, &x.1), (&y.0, &y.1));
            assert!((x.2 - y.2).abs() < 1e-4, "{x:?} {y:?}");
        }
        let rules = |f: &Finished| -> Vec<Option<Gait>> {
            f.0.recordings.iter().map(|r| r.gait.clone()).collect()
        };
        let (ra, rb) = (rules(&whole), rules(&windowed));
        let method = |f: &Finished| {
            crate::spatiotemporal::one_method(f.0.recordings.iter().map(Recording::event_method))
        };
        let pa = crate::spatiotemporal::parameters_of(
            &whole.0.strides,
            &ra.iter().map(Option::as_ref).collect::<Vec<_>>(),
            method(&whole),
        );
        let pb = crate::spatiotemporal::parameters_of(
            &windowed.0.strides,
            &rb.iter().map(Option::as_ref).collect::<Vec<_>>(),
            method(&windowed),
        );
        assert_eq!(pa.len(), pb.len());
        for (x, y) in pa.iter().zip(&pb) {
            assert_eq!((x.name, x.side, &x.note), (y.name, y.side, &y.note));
            let (x_value, y_value) = (x.value.unwrap(), y.value.unwrap());
            // The rules' numbers of a recording (duty factor, Froude number) are each window's
            // own, merged: within 1 %; the strides' means within 0.1 %.
            let rules = ["duty_factor", "froude", "travel_ratio"].contains(&x.name);
            let tolerance = if rules { 1e-2 } else { 1e-3 };
            assert!(
                (x_value - y_value).abs() <= tolerance * x_value.abs().max(1.0),
                "{} {}: {} against {}",
                x.name,
                x.side,
                x_value,
                y_value
            );
        }
        let (ca, cb) = (whole.0.curves(), windowed.0.curves());
        for s in 0..2 {
            for v in 0..9 {
                let (x, y) = (ca[s][v].as_ref().unwrap(), cb[s][v].as_ref().unwrap());
                assert_eq!(x.n, y.n);
                for p in 0..POINTS {
                    assert!(
                        (x.mean[p] - y.mean[p]).abs() < 1e-3,
                        "{} {}",
                        x.mean[p],
                        y.mean[p]
                    );
                    assert!((x.sd[p] - y.sd[p]).abs() < 1e-3, "{} {}", x.sd[p], y.sd[p]);
                }
            }
        }
        // The stride sample stays bounded.
        assert!(windowed.0.stride_sample()[0].len() < 2 * STRIDE_SAMPLE);
        assert!(!windowed.0.stride_sample()[0].is_empty());
        // The excerpt is a minute at most, from the start (the walk starts at once).
        let x = &b.excerpt;
        assert_eq!(x.time[0], 0.0);
        assert!(x.time[x.time.len() - 1] - x.time[0] <= EXCERPT + 1e-9);
        assert!(!x.heel_strikes[0].is_empty());
    }
}
