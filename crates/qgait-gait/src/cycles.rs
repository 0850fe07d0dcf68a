//! Gait cycles: each stride of each side from one heel strike to the next of the same side,
//! time-normalised to 0-100 % of its own duration; mean and SD over strides. A single-cycle
//! file can instead be declared one whole cycle ([`whole`]).

use qgait_kernel::progression::angle_about_vertical;
use qgait_kernel::Vec3;

use crate::events::Events;

/// Points of a time-normalised curve: 0, 1, ..., 100 % of the cycle.
pub const POINTS: usize = 101;

/// A stride whose direction of progression turns by more than this (degrees) from its first
/// heel strike to its last is a turning stride and left out. Gentler curves are kept: events,
/// pelvis angles and foot progression are all relative to the direction of progression, which
/// follows the walker; a sharper turn changes the gait itself.
pub const MAX_TURN_DEG: f64 = 30.0;

/// A stride that lasts less than this fraction of the side's median stride, or more than its
/// inverse, is left out (a missed or a spurious event, or the first steps from standing).
pub const DURATION_TOLERANCE: f64 = 0.75;

/// One cycle of one side.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// 0 right, 1 left.
    pub side: usize,
    /// Time of its heel strike (s).
    pub start: f64,
    /// Duration (s).
    pub duration: f64,
    /// The frame of its heel strike (for step length and width).
    pub strike_frame: usize,
    /// The frames it covers with their time since its start (s), in order; may reach a frame
    /// beyond each end, for interpolation.
    pub samples: Vec<(usize, f64)>,
    /// Toe off of the side, since the start (s).
    pub toe_off: Option<f64>,
    /// Heel strike of the other side, since the start (s).
    pub opposite_strike: Option<f64>,
    /// Toe off of the other side, since the start (s).
    pub opposite_toe_off: Option<f64>,
    /// First and last frame, for the pelvis's displacement over the cycle.
    pub span: (usize, usize),
}

impl Cycle {
    /// `value` of each frame resampled at 0, 1, ..., 100 % of the cycle (linear between frames).
    pub fn normalise(&self, value: impl Fn(usize) -> f64) -> Vec<f64> {
        let s = &self.samples;
        let mut k = 0;
        (0..POINTS)
            .map(|p| {
                let t = self.duration * p as f64 / (POINTS - 1) as f64;
                while k + 2 < s.len() && s[k + 1].1 < t {
                    k += 1;
                }
                let (f0, t0) = s[k];
                let Some(&(f1, t1)) = s.get(k + 1) else {
                    return value(f0);
                };
                let w = if t1 > t0 {
                    ((t - t0) / (t1 - t0)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let (a, b) = (value(f0), value(f1));
                a + w * (b - a)
            })
            .collect()
    }

    /// An event time (s since the start) as a percentage of the cycle.
    pub fn percent(&self, since_start: f64) -> f64 {
        100.0 * since_start / self.duration
    }
}

/// Why strides were left out, per side.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Dropped {
    /// Without exactly one toe off of the side, or without the other side's heel strike and
    /// toe off in between.
    pub incomplete: usize,
    /// Much shorter or longer than the side's median stride.
    pub duration: usize,
    /// Turning.
    pub turning: usize,
}

/// Why a stride was left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reason {
    /// [`Dropped::incomplete`].
    Incomplete,
    /// [`Dropped::duration`].
    Duration,
    /// [`Dropped::turning`].
    Turning,
}

impl Dropped {
    /// One more stride left out for `reason`.
    pub fn count(&mut self, reason: Reason) {
        match reason {
            Reason::Incomplete => self.incomplete += 1,
            Reason::Duration => self.duration += 1,
            Reason::Turning => self.turning += 1,
        }
    }
}

/// The start (s) and the reason of each stride left out, per side.
pub type LeftOut = [Vec<(f64, Reason)>; 2];

/// The strides of each side from detected events, with the start and the reason of each
/// stride left out ([`strides`]).
pub fn strides_and_left_out(
    time: &[f64],
    events: &Events,
    forward: &[Vec3<f64>],
    segments: &[std::ops::Range<usize>],
) -> ([Vec<Cycle>; 2], LeftOut) {
    let mut left_out: LeftOut = Default::default();
    let out = strides_noting(time, events, forward, segments, &mut |s, t, r| {
        left_out[s].push((t, r))
    });
    (out, left_out)
}

/// The strides of each side from detected events. `segments` are the stretches of frames
/// between gaps ([`Trial::segments`](crate::trial::Trial::segments)): two heel strikes
/// in different segments make no stride (what happened in the gap is unknown), and a
/// stride's frames stay within its segment.
pub fn strides(
    time: &[f64],
    events: &Events,
    forward: &[Vec3<f64>],
    segments: &[std::ops::Range<usize>],
) -> ([Vec<Cycle>; 2], [Dropped; 2]) {
    let mut dropped = [Dropped::default(); 2];
    let out = strides_noting(time, events, forward, segments, &mut |s, _, r| {
        dropped[s].count(r)
    });
    (out, dropped)
}

fn strides_noting(
    time: &[f64],
    events: &Events,
    forward: &[Vec3<f64>],
    segments: &[std::ops::Range<usize>],
    drop: &mut dyn FnMut(usize, f64, Reason),
) -> [Vec<Cycle>; 2] {
    let mut out: [Vec<Cycle>; 2] = Default::default();
    let segment_of = |frame: usize| segments.partition_point(|r| r.end <= frame);
    for (s, kept) in out.iter_mut().enumerate() {
        let o = 1 - s;
        let hs = &events.heel_strike[s];
        let pairs: Vec<_> = hs
            .windows(2)
            .filter(|w| segment_of(w[0].frame) == segment_of(w[1].frame))
            .collect();
        let mut durations: Vec<f64> = pairs.iter().map(|w| w[1].time - w[0].time).collect();
        durations.sort_by(f64::total_cmp);
        let median = durations.get(durations.len() / 2).copied().unwrap_or(0.0);
        for w in pairs {
            let (a, b) = (w[0], w[1]);
            let segment = segments
                .get(segment_of(a.frame))
                .cloned()
                .unwrap_or(0..time.len());
            let within = |list: &[crate::events::Event], from: f64, to: f64| -> Vec<f64> {
                list.iter()
                    .filter(|e| e.time > from && e.time < to)
                    .map(|e| e.time - a.time)
                    .collect()
            };
            let to = within(&events.toe_off[s], a.time, b.time);
            let ohs = within(&events.heel_strike[o], a.time, b.time);
            let oto = within(&events.toe_off[o], a.time, b.time);
            if to.len() != 1 || ohs.len() != 1 || oto.len() != 1 {
                drop(s, a.time, Reason::Incomplete);
                continue;
            }
            let d = b.time - a.time;
            if d < DURATION_TOLERANCE * median || d * DURATION_TOLERANCE > median {
                drop(s, a.time, Reason::Duration);
                continue;
            }
            let turn = angle_about_vertical(forward[a.frame], forward[b.frame]).to_degrees();
            if turn.abs() > MAX_TURN_DEG {
                drop(s, a.time, Reason::Turning);
                continue;
            }
            let first = a.frame.saturating_sub(1).max(segment.start);
            let last = (b.frame + 1).min(segment.end - 1);
            kept.push(Cycle {
                side: s,
                start: a.time,
                duration: d,
                strike_frame: a.frame,
                samples: (first..=last).map(|f| (f, time[f] - a.time)).collect(),
                toe_off: Some(to[0]),
                opposite_strike: Some(ohs[0]),
                opposite_toe_off: Some(oto[0]),
                span: (a.frame, b.frame),
            });
        }
    }
    out
}

/// The whole recording as one cycle (a single-cycle file, `--cycle whole`), taken as periodic
/// (its last frame is the first frame of the next cycle). Each side's cycle starts at its
/// detected heel strike: at the first frame when one is detected within [`AT_AN_END`] of the
/// period from either end (a file cut at heel strike, as single-cycle files are), else at the
/// first one inside the recording (a recording that starts mid-swing): frames from that strike
/// to the end, then from the second frame up to the strike. A side without a detected heel
/// strike has the recording as it is for its cycle. Toe offs and the other side's events are
/// the detected ones inside the recording.
pub fn whole(time: &[f64], heel_forward: [&[f64]; 2], events: &Events) -> [Cycle; 2] {
    let n = time.len();
    let (t0, t_end) = (time[0], time[n - 1]);
    let period = t_end - t0;
    let first = if heel_forward[0][0] >= heel_forward[1][0] {
        0
    } else {
        1
    };
    let starts = [0, 1].map(|s: usize| -> f64 {
        let strikes = &events.heel_strike[s];
        let near_an_end = |t: f64| (t - t0).min(t_end - t) <= AT_AN_END * period;
        if strikes.iter().any(|e| near_an_end(e.time)) {
            t0
        } else {
            strikes.first().map_or(t0, |e| e.time)
        }
    });
    let detected = [0, 1].map(|s| !events.heel_strike[s].is_empty());
    let start_of = |s: usize| starts[s];
    let phase = |t: f64, start: f64| (t - start).rem_euclid(period);
    let one = |list: &[crate::events::Event], start: f64| -> Option<f64> {
        list.first().map(|e| phase(e.time, start))
    };
    [0, 1].map(|s| {
        let o = 1 - s;
        let start = start_of(s);
        let mut samples: Vec<(usize, f64)> = Vec::with_capacity(n + 1);
        if start == t0 {
            samples.extend((0..n).map(|f| (f, time[f] - t0)));
        } else {
            // From the frame before the strike to the end, then around from the second frame.
            let k = time.partition_point(|&t| t <= start).saturating_sub(1);
            samples.extend((k..n).map(|f| (f, time[f] - start)));
            samples.extend((1..n).map(|f| (f, time[f] - t0 + t_end - start)));
        }
        let strike_frame = samples
            .iter()
            .find(|(_, t)| *t >= 0.0)
            .map_or(0, |&(f, _)| f);
        Cycle {
            side: s,
            start,
            duration: period,
            strike_frame,
            samples,
            toe_off: one(&events.toe_off[s], start),
            opposite_strike: if detected[o] {
                Some(phase(starts[o], start)).filter(|p| *p > 0.0)
            } else if o == first {
                Some(phase(t0, start)).filter(|p| *p > 0.0)
            } else {
                None
            },
            opposite_toe_off: one(&events.toe_off[o], start),
            span: (0, n - 1),
        }
    })
}

/// A heel strike detected within this fraction of the period of either end of a whole
/// recording is taken as the recording's start (a single-cycle file cut at heel strike; the
/// detectors place an event at an end a frame or two in).
pub const AT_AN_END: f64 = 0.05;

/// Mean and SD at each point of curves of equal length.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Mean.
    pub mean: Vec<f64>,
    /// Sample standard deviation (0 for a single curve).
    pub sd: Vec<f64>,
    /// Number of curves.
    pub n: usize,
}

impl Curve {
    /// Mean and SD of `curves` (`None` if there are none).
    pub fn of(curves: &[Vec<f64>]) -> Option<Self> {
        let n = curves.len();
        let len = curves.first()?.len();
        let mean: Vec<f64> = (0..len)
            .map(|i| curves.iter().map(|c| c[i]).sum::<f64>() / n as f64)
            .collect();
        let sd = (0..len)
            .map(|i| {
                if n < 2 {
                    return 0.0;
                }
                let ss: f64 = curves.iter().map(|c| (c[i] - mean[i]).powi(2)).sum();
                (ss / (n - 1) as f64).sqrt()
            })
            .collect();
        Some(Self { mean, sd, n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cycle_is_resampled_on_its_own_duration() {
        // Frames every 0.1 s; the cycle starts between frames 1 and 2.
        let time: Vec<f64> = (0..30).map(|i| i as f64 * 0.1).collect();
        let start = 0.15;
        let c = Cycle {
            side: 0,
            start,
            duration: 2.0,
            strike_frame: 1,
            samples: (1..=22).map(|f| (f, time[f] - start)).collect(),
            toe_off: None,
            opposite_strike: None,
            opposite_toe_off: None,
            span: (1, 21),
        };
        // A value linear in time resamples exactly.
        let v = c.normalise(|f| 3.0 * time[f]);
        for (p, got) in v.iter().enumerate() {
            let want = 3.0 * (start + 2.0 * p as f64 / 100.0);
            assert!((got - want).abs() < 1e-12, "{p}: {got} vs {want}");
        }
        assert_eq!(c.percent(0.5), 25.0);
    }

    #[test]
    fn mean_and_sample_sd() {
        let c = Curve::of(&[vec![1.0, 2.0], vec![3.0, 2.0]]).unwrap();
        assert_eq!(c.mean, vec![2.0, 2.0]);
        assert!((c.sd[0] - 2f64.sqrt()).abs() < 1e-12 && c.sd[1] == 0.0);
        assert!(Curve::of(&[]).is_none());
    }
}
