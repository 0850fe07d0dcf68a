//! `qgait gait`: clinical gait analysis on the kernel's forward kinematics. Gait events and
//! cycles from the feet's positions relative to the pelvis ([`events`], [`cycles`]),
//! spatiotemporal parameters ([`spatiotemporal`]), joint angles in the Conventional Gait
//! Model's conventions ([`angles`]) against normative bands ([`normative`]), the Gait Profile
//! Score ([`gps`]), figures ([`figures`]) and one HTML report ([`html`]).
//! `docs/gait-analysis.md` describes the methods and the conventions.

pub mod angles;
pub mod cycles;
pub mod events;
pub mod figures;
pub mod gps;
pub mod html;
pub mod normative;
pub mod output;
pub mod spatiotemporal;
pub mod trial;

use qgait_kernel::Vec3;

use crate::gait::cycles::{Curve, Cycle, Dropped};
use crate::gait::events::{Events, Kind};
use crate::gait::trial::Trial;

/// How the cycles are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
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
    /// The nine variables of each frame (`[side][variable][frame]`, degrees), when the
    /// recording has joint angles.
    pub angles: Option<[[Vec<f64>; 9]; 2]>,
}

/// Analyses one recording.
pub fn analyse(trial: Trial, mode: CycleMode) -> anyhow::Result<Walk> {
    let n = trial.time.len();
    if n < 3 {
        anyhow::bail!("{}: {n} rows; a gait analysis needs a walk", trial.source);
    }
    let window = match mode {
        CycleMode::Auto => events::PROGRESSION_WINDOW,
        // One cycle: its mean direction.
        CycleMode::Whole => f64::INFINITY,
    };
    let forward = events::progression(&trial.time, &trial.frames, window);
    let events = events::detect(&trial.time, &trial.frames, &forward);
    let (cycles, dropped) = match mode {
        CycleMode::Auto => cycles::strides(&trial.time, &events, &forward),
        CycleMode::Whole => {
            let heel = [0, 1].map(|s| events::along(&trial.frames, &forward, |f| f[s].heel));
            let [r, l] = cycles::whole(&trial.time, [&heel[0], &heel[1]], &events);
            ([vec![r], vec![l]], [Dropped::default(); 2])
        }
    };
    let angles = angles::angles(&trial, &forward);
    Ok(Walk {
        trial,
        forward,
        events,
        cycles,
        dropped,
        angles,
    })
}

impl Walk {
    /// The events to report, in time order: `(side, kind, time)`. With `--cycle whole`, the
    /// heel strikes that bound the declared cycles, and the toe offs inside.
    pub fn event_list(&self, mode: CycleMode) -> Vec<(usize, Kind, f64)> {
        let mut out = Vec::new();
        match mode {
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

    /// The number of cycles of each side.
    pub fn strides(&self) -> [usize; 2] {
        [self.cycles[0].len(), self.cycles[1].len()]
    }
}

/// Mean and SD over every cycle of every walk, per side and variable (101 points); `None`
/// where no walk has angles or a side has no cycle.
pub fn curves(walks: &[Walk]) -> [[Option<Curve>; 9]; 2] {
    std::array::from_fn(|s| {
        std::array::from_fn(|v| {
            let all: Vec<Vec<f64>> = walks
                .iter()
                .filter_map(|w| w.angles.as_ref().map(|a| (w, &a[s][v])))
                .flat_map(|(w, a)| w.cycles[s].iter().map(move |c| c.normalise(|f| a[f])))
                .collect();
            Curve::of(&all)
        })
    })
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
