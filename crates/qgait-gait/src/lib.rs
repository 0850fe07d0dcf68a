#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod angles;
pub mod bouts;
pub mod cycles;
pub mod error;
pub mod events;
pub mod figures;
pub mod files;
pub mod gps;
pub mod html;
pub mod normative;
pub mod number;
pub mod output;
pub mod rules;
pub mod session;
pub mod spatiotemporal;
pub mod stream;
pub mod trial;
pub mod variables;

use qgait_kernel::Vec3;

use crate::cycles::{Curve, Cycle, Dropped};
use crate::events::{Events, Kind};
use crate::trial::Trial;

/// Why a recording cannot be analysed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// Too few rows for a walk.
    #[error("{recording}: {rows} rows; a gait analysis needs a walk")]
    TooShort {
        /// The recording.
        recording: String,
        /// Its rows.
        rows: usize,
    },
    /// `--cycle whole` on a recording with a gap or rows left out.
    #[error("{recording}: --cycle whole takes the recording as one cycle, but it has a gap in time or rows left out (see the warnings)")]
    WholeWithGap {
        /// The recording.
        recording: String,
    },
    /// Not one complete stride on either side.
    #[error(
        "{recording}: no complete stride found ({right} heel strikes right, {left} left){hint}"
    )]
    NoStride {
        /// The recording.
        recording: String,
        /// Right heel strikes detected.
        right: usize,
        /// Left heel strikes detected.
        left: usize,
        /// What may help, where something does ([`Walk::require_strides`]).
        hint: String,
    },
}

/// The longest recording for which `--cycle whole` is suggested (s): a gait cycle lasts about
/// 0.6 s (a run) to 1.6 s (a slow walk); a recording of 2 s or more would hold strides.
pub const ONE_CYCLE_AT_MOST: f64 = 2.0;

/// The shortest gait cycle (s): a stride at 300 steps/min, the highest cadence a result may
/// have ([`output`]'s checks).
pub const ONE_CYCLE_AT_LEAST: f64 = 0.4;

/// How the cycles are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum CycleMode {
    /// From the detected heel strikes: every complete, straight stride of each side.
    Auto,
    /// The whole recording is one cycle (a single-cycle file).
    Whole,
}

impl CycleMode {
    /// The option's value.
    pub fn name(self) -> &'static str {
        match self {
            CycleMode::Auto => "auto",
            CycleMode::Whole => "whole",
        }
    }
}

/// One recording, analysed.
pub struct Walk {
    /// The recording.
    pub trial: Trial,
    /// Direction of progression of each frame.
    pub forward: Vec<Vec3<f64>>,
    /// Detected events.
    pub events: Events,
    /// The cycles of each side.
    pub cycles: [Vec<Cycle>; 2],
    /// Strides left out, per side.
    pub dropped: [Dropped; 2],
    /// The start (s) and the reason of each stride left out, per side.
    pub left_out: cycles::LeftOut,
    /// The nine variables of each frame (`[side][variable][frame]`, degrees), when the
    /// recording has joint angles.
    pub angles: Option<[[Vec<f64>; 9]; 2]>,
    /// How its cycles were taken (a `builtin:` gait whole whatever `--cycle` says).
    pub mode: CycleMode,
    /// Mode, ground and speed from the rules ([`rules`]), when the recording has the strides
    /// for them (its events are then the rules'; else Zeni's).
    pub gait: Option<rules::Gait>,
    /// How the CGM's pelvis frame was had ([`Walk::with_cgm_pelvis`]).
    pub pelvis: angles::CgmPelvis,
}

/// Analyses one recording.
pub fn analyse(trial: Trial, mode: CycleMode) -> Result<Walk, AnalysisError> {
    analyse_with(trial, mode, None)
}

/// Analyses one recording; `given_speed` is a known belt speed (m/s, `--treadmill-speed`).
pub fn analyse_with(
    trial: Trial,
    mode: CycleMode,
    given_speed: Option<f64>,
) -> Result<Walk, AnalysisError> {
    analyse_with_pelvis(trial, mode, given_speed, angles::CgmPelvis::FIXED)
}

/// [`analyse_with`], the joint angles in the CGM's pelvis frame `pelvis`
/// ([`Walk::with_cgm_pelvis`], without computing them twice).
pub fn analyse_with_pelvis(
    trial: Trial,
    mode: CycleMode,
    given_speed: Option<f64>,
    pelvis: angles::CgmPelvis,
) -> Result<Walk, AnalysisError> {
    let n = trial.time.len();
    if n < 3 {
        return Err(AnalysisError::TooShort {
            recording: trial.source,
            rows: n,
        });
    }
    let window = match mode {
        CycleMode::Auto => events::PROGRESSION_WINDOW,
        // One cycle: its mean direction.
        CycleMode::Whole => f64::INFINITY,
    };
    if mode == CycleMode::Whole && !trial.breaks.is_empty() {
        return Err(AnalysisError::WholeWithGap {
            recording: trial.source,
        });
    }
    // Each stretch between gaps on its own: its direction of progression, its events, its
    // strides.
    let segments = trial.segments();
    let forward: Vec<Vec3<f64>> = segments
        .iter()
        .flat_map(|r| events::progression(&trial.time[r.clone()], &trial.frames[r.clone()], window))
        .collect();
    let anchors = events::detect_in(&trial.time, &trial.frames, &forward, &segments);
    let knee = trial.coordinates.as_ref().map(|c| {
        ["knee_angle_r", "knee_angle_l"].map(|name| {
            let k = trial::coordinate(name);
            c.iter().map(|row| row[k]).collect::<Vec<f64>>()
        })
    });
    let input = rules::Input {
        time: &trial.time,
        frames: &trial.frames,
        forward: &forward,
        segments: &segments,
        knee,
        translation: trial.translation.as_deref(),
        given_speed,
        velocities: trial.velocities.as_deref(),
    };
    let (events, gait) = match rules::apply(&input, &anchors) {
        Some((e, g)) => (e, Some(g)),
        None => (anchors, None),
    };
    let (cycles, left_out) = match mode {
        CycleMode::Auto => cycles::strides_and_left_out(&trial.time, &events, &forward, &segments),
        CycleMode::Whole => {
            let heel = [0, 1].map(|s| events::along(&trial.frames, &forward, |f| f[s].heel));
            let [r, l] = cycles::whole(&trial.time, [&heel[0], &heel[1]], &events);
            ([vec![r], vec![l]], Default::default())
        }
    };
    let dropped = left_out.each_ref().map(|l| {
        let mut d = Dropped::default();
        for (_, r) in l {
            d.count(*r);
        }
        d
    });
    let angles = angles::angles(&trial, &forward, &pelvis);
    Ok(Walk {
        trial,
        forward,
        events,
        cycles,
        dropped,
        left_out,
        angles,
        mode,
        gait,
        pelvis,
    })
}

impl Walk {
    /// The walk with its joint angles in the CGM's pelvis frame `pelvis` (e.g. from the
    /// model's own pelvis markers) instead of the fixed one.
    pub fn with_cgm_pelvis(mut self, pelvis: angles::CgmPelvis) -> Self {
        self.angles = angles::angles(&self.trial, &self.forward, &pelvis);
        self.pelvis = pelvis;
        self
    }

    /// The events to report, in time order: `(side, kind, time)`. Taken whole, the heel
    /// strikes that bound the declared cycles, and the toe offs inside.
    pub fn event_list(&self) -> Vec<(usize, Kind, f64)> {
        let mut out = Vec::new();
        match self.mode {
            CycleMode::Auto => {
                for s in 0..2 {
                    out.extend(
                        self.events.heel_strike[s]
                            .iter()
                            .map(|e| (s, Kind::HeelStrike, e.time)),
                    );
                    out.extend(
                        self.events.toe_off[s]
                            .iter()
                            .map(|e| (s, Kind::ToeOff, e.time)),
                    );
                }
            }
            CycleMode::Whole => {
                let end = *self.trial.time.last().unwrap_or(&0.0);
                for (s, c) in self.cycles.iter().enumerate() {
                    for c in c {
                        out.push((s, Kind::HeelStrike, c.start));
                        if c.start == self.trial.time[0] {
                            out.push((s, Kind::HeelStrike, end));
                        }
                        out.extend(
                            self.events.toe_off[s]
                                .iter()
                                .map(|e| (s, Kind::ToeOff, e.time)),
                        );
                    }
                }
            }
        }
        out.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
        out
    }

    /// `Ok` when either side has a cycle, else [`AnalysisError::NoStride`].
    pub fn require_strides(&self) -> Result<(), AnalysisError> {
        if self.cycles.iter().any(|c| !c.is_empty()) {
            return Ok(());
        }
        let t = &self.trial.time;
        Err(no_stride(
            &self.trial.source,
            [
                self.events.heel_strike[0].len(),
                self.events.heel_strike[1].len(),
            ],
            self.trial.breaks.len(),
            t[t.len() - 1] - t[0],
            self.trial.wrap(),
        ))
    }

    /// The number of cycles of each side.
    pub fn strides(&self) -> [usize; 2] {
        [self.cycles[0].len(), self.cycles[1].len()]
    }
}

/// [`AnalysisError::NoStride`] for a recording of `duration` seconds with `heel_strikes` per
/// side and `breaks` gaps in time, with the hint that fits it.
pub(crate) fn no_stride(
    source: &str,
    heel_strikes: [usize; 2],
    breaks: usize,
    duration: f64,
    wrap: Option<trial::Wrap>,
) -> AnalysisError {
    let hint = if breaks > 0 {
        format!(
            "; its {} stretches between gaps in time are each too short for a stride (see the warnings about gaps)",
            breaks + 1
        )
    } else if duration < ONE_CYCLE_AT_LEAST {
        format!(
            "; the recording is {duration:.2} s long, shorter than any gait cycle ({ONE_CYCLE_AT_LEAST} s at 300 steps/min)"
        )
    } else if duration <= ONE_CYCLE_AT_MOST {
        match wrap.filter(|w| !w.leads_back()) {
            None => format!(
                "; the recording is {duration:.2} s long: for a file that holds one gait cycle, use --cycle whole"
            ),
            Some(w) => format!(
                "; the recording is {duration:.2} s long, but {}: it may hold part of a cycle or more than one, which --cycle whole would take as one",
                w.describe()
            ),
        }
    } else {
        format!("; in {duration:.1} s without a gap, no stride whose events pair up: is it a walk or a run?")
    };
    AnalysisError::NoStride {
        recording: source.to_string(),
        right: heel_strikes[0],
        left: heel_strikes[1],
        hint,
    }
}

/// Mean and SD over every cycle of every walk, per side and variable (101 points); `None`
/// where no walk has angles or a side has no cycle.
pub fn curves(walks: &[Walk]) -> [[Option<Curve>; 9]; 2] {
    std::array::from_fn(|s| std::array::from_fn(|v| Curve::of(&stride_curves(walks, s, v))))
}

/// Every cycle of side `s` of every walk with angles, variable `v` ([`Variable::ALL`] order)
/// time-normalised to 101 points: the strides whose mean and SD [`curves`] gives, and which
/// the kinematics figure draws one by one.
///
/// [`Variable::ALL`]: angles::Variable::ALL
pub fn stride_curves(walks: &[Walk], s: usize, v: usize) -> Vec<Vec<f64>> {
    walks
        .iter()
        .filter_map(|w| w.angles.as_ref().map(|a| (w, &a[s][v])))
        .flat_map(|(w, a)| w.cycles[s].iter().map(move |c| c.normalise(|f| a[f])))
        .collect()
}

/// The mean percentage of the cycle at which each side's toe comes off.
pub fn toe_off_percent(walks: &[Walk]) -> [Option<f64>; 2] {
    std::array::from_fn(|s| {
        let v: Vec<f64> = walks
            .iter()
            .flat_map(|w| w.cycles[s].iter())
            .filter_map(|c| c.toe_off.map(|t| c.percent(t)))
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    })
}

/// The longest hip-to-ankle distance of either side over the walks (m): the leg length that
/// makes the walking speed non-dimensional.
pub fn leg_length(walks: &[Walk]) -> Option<f64> {
    walks
        .iter()
        .flat_map(|w| w.trial.frames.iter())
        .flat_map(|f| f.iter().map(|l| Vec3::distance(l.hip, l.ankle)))
        .fold(None, |m: Option<f64>, d| Some(m.map_or(d, |m| m.max(d))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::{FigureError, ReportError};
    use crate::figures;
    use crate::files;
    use crate::normative::NormativeError;
    use crate::output::{self, ReferenceArg, Subject};
    use crate::trial::{Limb, TrialError};

    /// The `both`-or-first parameter `name` of `report`.
    fn parameter<'a>(report: &'a output::Report, name: &str) -> &'a spatiotemporal::Parameter {
        report.parameters.iter().find(|p| p.name == name).unwrap()
    }

    fn gait2392() -> qgait_model::choice::Model {
        qgait_model::choice::Model::load("gait2392", None)
            .expect("gait2392")
            .0
    }

    /// The built-in normal walk with `cycles` in place of its own (a test of what reads
    /// only the cycles).
    pub(crate) fn walk_with_cycles(cycles: [Vec<Cycle>; 2]) -> Walk {
        let mut w = builtin_walk("cycles");
        w.cycles = cycles;
        w.gait = None;
        w
    }

    /// The built-in normal cycle, analysed as one whole cycle.
    fn builtin_walk(label: &str) -> Walk {
        let (mut t, _) = trial::load("builtin:normal", &gait2392()).expect("loads");
        t.source = label.to_string();
        analyse(t, CycleMode::Whole).expect("analyses")
    }

    /// The feet's velocities come from the kernel's differential kinematics for a motion on a
    /// leg chain, and they are the time derivatives of the positions: against central
    /// differences of the FK points of a finely sampled cycle. HAK has none (its points are
    /// differenced by the rules).
    #[test]
    fn foot_velocities_are_the_derivatives_of_the_positions() {
        let (t, _) = trial::load("builtin:normal,rows=2001", &gait2392()).expect("loads");
        let v = t.velocities.as_ref().expect("kernel velocities");
        let mut worst = 0.0f64;
        for (i, vi) in v.iter().enumerate().take(t.time.len() - 2).skip(2) {
            let dt = t.time[i + 1] - t.time[i - 1];
            for (s, vs) in vi.iter().enumerate() {
                let d = |p: fn(&trial::Limb) -> qgait_kernel::Vec3<f64>| {
                    (p(&t.frames[i + 1][s]) - p(&t.frames[i - 1][s])) * (1.0 / dt)
                };
                for (a, b) in [
                    (vs.heel, d(|l| l.heel)),
                    (vs.forefoot, d(|l| l.forefoot)),
                    (vs.toe, d(|l| l.toe)),
                ] {
                    worst = worst.max((a - b).norm());
                }
            }
        }
        assert!(worst < 2e-3, "worst {worst} m/s");
        let hak = qgait_model::choice::Model::load("hak", None).unwrap().0;
        let (t, _) = trial::load("builtin:normal", &hak).expect("loads");
        assert!(t.velocities.is_none());
    }

    #[test]
    fn loading_errors_name_what_failed() {
        let model = gait2392();
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("none.csv");
        let e = trial::load(missing.to_str().unwrap(), &model)
            .err()
            .unwrap();
        assert!(matches!(e, TrialError::Read { .. }), "{e}");
        // A device's frames without times.
        let frames = dir.path().join("frames.csv");
        let row = format!("0,{}", vec!["0.1"; 24].join(","));
        let text = format!(
            "{}\n{}\n",
            qgait_device::frames_csv::header(),
            row.replacen(",", ",,", 1)
        );
        std::fs::write(&frames, text).unwrap();
        let e = trial::load(frames.to_str().unwrap(), &model).err().unwrap();
        assert!(matches!(e, TrialError::NoTimes(_)), "{e}");
        // The extension in capitals is a frames CSV still, not a motion.
        let upper = dir.path().join("FRAMES.CSV");
        std::fs::copy(&frames, &upper).unwrap();
        let e = trial::load(upper.to_str().unwrap(), &model).err().unwrap();
        assert!(matches!(e, TrialError::NoTimes(_)), "{e}");
        // A comma-separated motion is said to be one.
        let comma = dir.path().join("comma.mot");
        std::fs::write(
            &comma,
            "m\nversion=1\ninDegrees=yes\nendheader\ntime,pelvis_tilt,hip_flexion_r\n0,1,2\n",
        )
        .unwrap();
        let e = trial::load(comma.to_str().unwrap(), &model).err().unwrap();
        assert!(e.to_string().contains("comma-separated"), "{e}");
        let e = trial::load("builtin:walk", &model).err().unwrap();
        assert!(matches!(e, TrialError::Source(_)), "{e}");
    }

    #[test]
    fn analysis_errors_say_why() {
        let still = |rows: usize| Trial {
            label: "still".into(),
            source: "still.mot".into(),
            time: (0..rows).map(|i| i as f64 / 100.0).collect(),
            frames: vec![[Limb::default(); 2]; rows],
            coordinates: None,
            translation: None,
            breaks: Vec::new(),
            seen: angles::Seen::ALL,
            velocities: None,
        };
        let e = analyse(still(2), CycleMode::Auto).err().unwrap();
        assert!(matches!(e, AnalysisError::TooShort { rows: 2, .. }), "{e}");
        let w = analyse(still(300), CycleMode::Auto).unwrap();
        let e = w.require_strides().err().unwrap();
        assert!(
            matches!(
                e,
                AnalysisError::NoStride {
                    right: 0,
                    left: 0,
                    ..
                }
            ),
            "{e}"
        );
        assert!(builtin_walk("w").require_strides().is_ok());
        // One cycle cannot have a gap.
        let mut gap = still(300);
        gap.breaks = vec![150];
        let e = analyse(gap, CycleMode::Whole).err().unwrap();
        assert!(matches!(e, AnalysisError::WholeWithGap { .. }), "{e}");
    }

    #[test]
    fn report_errors_say_why() {
        let e = ReferenceArg::parse("normative:medium").err().unwrap();
        assert!(
            matches!(&e, NormativeError::UnknownSpeed { speed, .. } if speed == "medium"),
            "{e}"
        );
        let build = |reference: &ReferenceArg, walks: Option<Vec<Walk>>| {
            output::build(
                vec![builtin_walk("a,b.mot"), builtin_walk("c.mot")],
                "gait2392".into(),
                CycleMode::Whole,
                reference,
                walks,
                &crate::normative::Source::Dir("/nonexistent".into()),
                Subject::default(),
            )
        };
        let motion = ReferenceArg::Motion("ref.mot".into());
        let e = build(&motion, None).err().unwrap();
        assert!(matches!(e, ReportError::ReferenceNotAnalysed(_)), "{e}");
        // The normative data are read from the directory given.
        let e = build(&ReferenceArg::Normative(None), None).err().unwrap();
        assert!(
            matches!(e, ReportError::Normative(NormativeError::Read { .. })),
            "{e}"
        );
        let report = build(&motion, Some(vec![builtin_walk("ref.mot")])).unwrap();
        // The CSVs through the csv crate: a field with a comma is quoted.
        let events = files::events_csv(&report).unwrap();
        assert!(events.starts_with("side,event,time,motion\n"), "{events}");
        assert!(events.contains(",\"a,b.mot\"\n"), "{events}");
        assert!(events.contains(",c.mot\n"), "{events}");
        let dir = tempfile::tempdir().unwrap();
        let e = figures::save_all(&report, &dir.path().join("missing"))
            .err()
            .unwrap();
        assert!(matches!(e, FigureError::Save { .. }), "{e}");
        let file = dir.path().join("file");
        std::fs::write(&file, "").unwrap();
        let e = files::write(&report, &file.join("out")).err().unwrap();
        assert!(
            matches!(
                e,
                ReportError::Io {
                    action: "create",
                    ..
                }
            ),
            "{e}"
        );
        let files = files::write(&report, &dir.path().join("out")).unwrap();
        assert!(files.iter().any(|f| f.ends_with("report.html")));
    }

    /// A recording too short for the rules (one cycle) names Zeni's events in every note of
    /// its events; recordings whose events' methods differ say each recording's own were
    /// used; one method is named when all share it.
    #[test]
    fn the_notes_name_the_events_method() {
        use crate::rules::EventMethod;
        use crate::spatiotemporal::{one_method, MIXED_EVENTS};
        let walk = builtin_walk("one.mot");
        assert!(walk.gait.is_none());
        let report = output::build(
            vec![walk],
            "gait2392".into(),
            CycleMode::Whole,
            &ReferenceArg::Motion("ref.mot".into()),
            Some(vec![builtin_walk("ref.mot")]),
            &crate::normative::Source::Dir("/nonexistent".into()),
            Subject::default(),
        )
        .unwrap();
        for name in [
            "cadence",
            "stride_time",
            "stance",
            "swing",
            "double_support",
        ] {
            let p = parameter(&report, name);
            assert!(
                p.note.contains(EventMethod::Zeni.heel_strike()),
                "{name}: {}",
                p.note
            );
        }
        let stance = parameter(&report, "stance");
        assert!(
            stance.note.contains(EventMethod::Zeni.toe_off()),
            "{}",
            stance.note
        );
        let summary: serde_json::Value =
            serde_json::from_str(&files::summary_json(&report)).unwrap();
        assert_eq!(
            summary["recordings"][0]["events"],
            EventMethod::Zeni.describe(),
            "{summary}"
        );
        assert!(EventMethod::Zeni
            .describe()
            .contains("too few strides for the rules"));
        // One method for all, or none when they differ (or a recording's own differ).
        let (w, r) = (Some(EventMethod::Walking), Some(EventMethod::RunningKnee));
        assert_eq!(one_method([w, w]), w);
        assert_eq!(one_method([w, r]), None);
        assert_eq!(one_method([w, None]), None);
        assert_eq!(one_method(std::iter::empty()), None);
        let mut sums: [crate::spatiotemporal::Sums; 2] = Default::default();
        let stride = crate::spatiotemporal::Stride {
            start: 0.0,
            duration: 1.0,
            toe_off: Some(0.6),
            opposite_strike: Some(0.5),
            opposite_toe_off: Some(0.1),
            along: 0.6,
            across: 0.1,
            moved: None,
            speed: None,
            running: false,
            seen: angles::Seen::ALL,
        };
        sums[0].add(&stride);
        let p = crate::spatiotemporal::parameters_of(&sums, &[None, None], None);
        for name in ["cadence", "stance", "double_support"] {
            let p = p.iter().find(|p| p.name == name).unwrap();
            assert!(p.note.ends_with(MIXED_EVENTS), "{name}: {}", p.note);
        }
        // Running without knee angles: the first pass's toe off.
        assert_eq!(
            EventMethod::RunningFirstPass.toe_off(),
            EventMethod::Walking.toe_off()
        );
        assert_ne!(
            EventMethod::RunningKnee.toe_off(),
            EventMethod::Walking.toe_off()
        );
    }

    /// Against the normative data: the normal toe off is the centre of the stance range of
    /// the subject's age (shaded by the range, both sides alike), and the MAP's normal
    /// reference is the RMS of the bands' SD. Skipped (with the reason printed) without the
    /// data compiled in.
    #[test]
    fn the_normative_reference_has_a_normal_toe_off_and_typical_scores() {
        if crate::normative::EMBEDDED.is_none() {
            eprintln!(
                "skipped: no normative data compiled in (../shared/data/normative at build time)"
            );
            return;
        }
        let source = crate::normative::Source::Embedded;
        let build = |age: Option<f64>| {
            output::build(
                vec![builtin_walk("n.mot")],
                "gait2392".into(),
                CycleMode::Whole,
                &ReferenceArg::Normative(None),
                None,
                &source,
                Subject {
                    age,
                    male: Some(true),
                },
            )
            .unwrap()
        };
        let report = build(Some(30.0));
        let r = &report.reference;
        let range = r.toe_off_range.expect("a normal stance range");
        assert!(
            range.min > 45.0 && range.max < 80.0 && range.min < range.max,
            "{range:?}"
        );
        assert_eq!(r.toe_off, [Some((range.min + range.max) / 2.0); 2]);
        assert!(
            r.toe_off_from.contains("male, 30 years"),
            "{}",
            r.toe_off_from
        );
        // The stance row of the table has the same range.
        let stance = parameter(&report, "stance").range.unwrap();
        assert_eq!(stance, range);
        // Without an age: the adults'.
        assert!(build(None).reference.toe_off_from.contains("male adults"));
        // The typical scores: the RMS of each band's SD.
        let n = report.normal_scores.as_ref().unwrap();
        let knee = &r.bands[0][6].as_ref().unwrap().sd;
        let rms = (knee.iter().map(|v| v * v).sum::<f64>() / knee.len() as f64).sqrt();
        assert!((n.gvs[0][6].unwrap() - rms).abs() < 1e-12);
        assert!(n.overall.is_some());
    }

    /// The page: every field escaped (askama's numeric character references), the figures inline without their XML declaration, the
    /// sections in order, the scores' table when there are scores and a note when not.
    #[test]
    fn the_page_escapes_text_and_inlines_the_figures() {
        let mut walk = builtin_walk("a<b>&\"c\".mot");
        walk.trial.label = "x&y".into();
        let motion = ReferenceArg::Motion("ref.mot".into());
        let mut report = output::build(
            vec![walk],
            "gait<2392>".into(),
            CycleMode::Whole,
            &motion,
            Some(vec![builtin_walk("ref.mot")]),
            &crate::normative::Source::Dir("/nonexistent".into()),
            Subject::default(),
        )
        .unwrap();
        let svgs = [(
            "map".to_string(),
            "<?xml version=\"1.0\"?>\n<svg><text>a &amp; b</text></svg>".to_string(),
        )];
        let page = html::page(&report, &svgs).unwrap();
        assert!(page.starts_with("<!DOCTYPE html>\n"), "{page}");
        assert!(page.ends_with("</body></html>\n"), "{page}");
        assert!(
            page.contains("<title>Gait analysis: x&#38;y</title>"),
            "{page}"
        );
        assert!(page.contains("a&#60;b&#62;&#38;&#34;c&#34;.mot"), "{page}");
        assert!(page.contains("gait&#60;2392&#62;"), "{page}");
        assert!(
            page.contains("<figure id=\"fig-map\"><svg><text>a &amp; b</text></svg><figcaption>Movement Analysis Profile (Baker et al. 2009)"),
            "{page}"
        );
        assert!(!page.contains("<?xml"), "{page}");
        let at = |s: &str| page.find(s).unwrap_or_else(|| panic!("no {s}: {page}"));
        let sections = [
            "<th class=\"l\">Subject ID</th><td class=\"l\">not given</td>",
            "<h2 id=\"warnings\">Warnings</h2>",
            "<h2>Kinematics</h2>",
            "<h2>Movement Analysis Profile and Gait Profile Score</h2>",
            "<h2>Spatiotemporal parameters</h2>",
            "<h2>Gait events</h2>",
            "<h2>Recordings and settings</h2>",
            "Sides: right, left.",
        ];
        assert!(sections.windows(2).all(|w| at(w[0]) < at(w[1])), "{page}");
        assert!(page.contains("<th class=\"l\">GPS overall</th>"), "{page}");
        assert_eq!(
            page.matches("<tr><td class=\"l\">Knee flexion (flex +)</td>")
                .count(),
            1
        );
        // No warning: the section says so. The spatiotemporal table: readable names and units,
        // the reference recording's column.
        assert!(page.contains("the run emitted no warning"), "{page}");
        assert!(page.contains("<td class=\"l\">Stride time</td><td class=\"l unit\">s</td>"));
        assert!(page
            .contains("<td class=\"l\">Stance phase</td><td class=\"l unit\">% gait cycle</td>"));
        assert!(!page.contains(">stride_time<"), "{page}");
        assert!(
            page.contains("<th class=\"ref\">reference: builtin:normal</th>"),
            "{page}"
        );
        // Every event, as events.csv has it.
        let events = files::events_csv(&report).unwrap();
        assert!(events.lines().count() > 3);
        for line in events.lines().skip(1) {
            let f: Vec<&str> = line.split(',').collect();
            let row = format!(
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td></tr>",
                f[0],
                f[1].replace('_', " "),
                f[2]
            );
            assert!(page.contains(&row), "no {row}: {page}");
        }
        // The subject and session, and the warnings, escaped.
        report.session = crate::session::Session {
            subject_id: Some("P<7>".into()),
            date: Some("2026-03-04".into()),
            date_from: Some("given".into()),
            age: Some(41.0),
            sex: Some("female"),
            height: Some(1.7),
            mass: Some(65.0),
            condition: Some("barefoot & cane".into()),
        };
        report.warnings = vec!["w.mot:9: a <gap>".into(), "second".into()];
        let page = html::page(&report, &[]).unwrap();
        for want in [
            "<title>Gait analysis: P&#60;7&#62;</title>",
            "<td class=\"l\">2026-03-04</td>",
            "<td class=\"l\">41 years</td>",
            "<td class=\"l\">1.7 m</td>",
            "<td class=\"l\">65 kg</td>",
            "<td class=\"l\">22.5 kg/m²</td>",
            "<td class=\"l\">barefoot &#38; cane</td>",
            "<li>w.mot:9: a &#60;gap&#62;</li>",
            "with 2 warnings",
        ] {
            assert!(page.contains(want), "no {want}: {page}");
        }
        report.scores = None;
        let page = html::page(&report, &[]).unwrap();
        assert!(
            page.contains("<p>Not computed: the recording has no joint angles"),
            "{page}"
        );
        assert!(!page.contains("<figure"), "{page}");
    }
}
