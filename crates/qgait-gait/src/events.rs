//! Gait events without a force plate, from the FK positions: the method of Zeni, Richards and
//! Higginson (2008, Gait & Posture 27:710-714). Heel strike is when the heel is furthest in
//! front of the pelvis along the direction of progression, toe off when the toe tip is
//! furthest behind it. The positions are the kernel's FK, whose origin is the pelvis origin,
//! so they are already relative to the pelvis (Zeni's sacrum); the direction of progression
//! is the heading the pelvis faces, smoothed over about a stride ([`PROGRESSION_WINDOW`],
//! [`progression`]), so that it follows the walker through turns.
//!
//! An extremum counts only if it stands out: its prominence (how far the signal falls on both
//! sides before rising above it again, within [`SEARCH_SPAN`] seconds) must be at least
//! [`PROMINENCE_FRACTION`] of the signal's spread (5th to 95th percentile) and at least
//! [`MIN_PROMINENCE`]. A maximum at the first or last frame is not an event (the recording may
//! have cut a rise short); one close to an end is, if the signal falls all the way from it to
//! that end and stands out on its other side. Standing and turning on the spot move the feet
//! too little to make events.

use qgait_kernel::progression::{heading, horizontal_unit, pelvis_forward};
use qgait_kernel::Vec3;

use crate::trial::{median_step, Frame};

/// Width (s, centred) of the local fit of the pelvis's heading that is the direction of
/// progression ([`progression`]): about one stride. Wider windows lag in sharp turns (a
/// synthetic walk turning at up to 70°/s puts events more than a frame off with 2 s).
pub const PROGRESSION_WINDOW: f64 = 1.2;

/// How far (s) on each side of an extremum its prominence is measured.
pub const SEARCH_SPAN: f64 = 2.0;

/// An extremum's prominence, as a fraction of the signal's 5-95 % spread, for it to be an event.
pub const PROMINENCE_FRACTION: f64 = 0.3;

/// The least prominence (m) of an event.
pub const MIN_PROMINENCE: f64 = 0.05;

/// The kind of an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Heel strike (initial contact).
    HeelStrike,
    /// Toe off (final contact).
    ToeOff,
}

impl Kind {
    /// The name in `events.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Kind::HeelStrike => "heel_strike",
            Kind::ToeOff => "toe_off",
        }
    }
}

/// One event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event {
    /// The frame of the extremum.
    pub frame: usize,
    /// Its time (s), refined between frames by the parabola through the extremum and its two
    /// neighbours.
    pub time: f64,
}

/// The events of both sides (right first), each in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Events {
    /// Heel strikes.
    pub heel_strike: [Vec<Event>; 2],
    /// Toe offs.
    pub toe_off: [Vec<Event>; 2],
}

/// The direction of progression of every frame: the heading of the direction the pelvis
/// faces ([`pelvis_forward`]), smoothed by a local quadratic fit over `window` seconds centred
/// on the frame (the fit's value at the frame). A quadratic follows a turn's acceleration
/// where a moving average lags behind it; over about a stride, the pelvis's rotation within
/// the stride mostly averages out. An infinite `window` gives the recording's mean direction.
pub fn progression(time: &[f64], frames: &[Frame], window: f64) -> Vec<Vec3<f64>> {
    let raw: Vec<Vec3<f64>> = frames
        .iter()
        .scan(Vec3::unit_x(), |last, f| {
            if let Some(v) = pelvis_forward(f[0].hip, f[1].hip) {
                *last = v;
            }
            Some(*last)
        })
        .collect();
    if !window.is_finite() {
        let sum = raw.iter().fold(Vec3::zero(), |s, v| s + *v);
        let mean = horizontal_unit(sum).unwrap_or_else(Vec3::unit_x);
        return vec![mean; raw.len()];
    }
    // Unwrapped headings.
    let mut h: Vec<f64> = Vec::with_capacity(raw.len());
    for v in &raw {
        let a = heading(*v);
        h.push(match h.last() {
            Some(&p) => {
                p + (a - p + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                    - std::f64::consts::PI
            }
            None => a,
        });
    }
    let half = window / 2.0;
    let (mut lo, mut hi) = (0, 0);
    (0..raw.len())
        .map(|i| {
            while hi < raw.len() && time[hi] <= time[i] + half {
                hi += 1;
            }
            while time[lo] < time[i] - half {
                lo += 1;
            }
            // Least squares h = a + b u + c u^2, u = t - t_i: the normal equations.
            let (mut s, mut y) = ([0.0; 5], [0.0; 3]);
            for k in lo..hi {
                let u = time[k] - time[i];
                let mut p = 1.0;
                for m in 0..5 {
                    s[m] += p;
                    if m < 3 {
                        y[m] += p * h[k];
                    }
                    p *= u;
                }
            }
            let a = solve3(
                [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]],
                y,
            )
            .map_or(h[i], |x| x[0]);
            Vec3::new(a.cos(), 0.0, -a.sin())
        })
        .collect()
}

/// Solves a 3x3 linear system by Cramer's rule; `None` if it is (nearly) singular.
fn solve3(m: [[f64; 3]; 3], y: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    let scale = m[0][0] * m[1][1] * m[2][2];
    if d.is_nan() || d.abs() <= 1e-12 * scale.abs() {
        return None;
    }
    let mut out = [0.0; 3];
    for (c, o) in out.iter_mut().enumerate() {
        let mut mc = m;
        for r in 0..3 {
            mc[r][c] = y[r];
        }
        *o = det(mc) / d;
    }
    Some(out)
}

/// The forward position of `point` relative to the pelvis along the direction of progression,
/// every frame.
pub fn along(
    frames: &[Frame],
    forward: &[Vec3<f64>],
    point: impl Fn(&Frame) -> Vec3<f64>,
) -> Vec<f64> {
    frames
        .iter()
        .zip(forward)
        .map(|(f, d)| point(f).dot(*d))
        .collect()
}

/// Detects heel strikes and toe offs of both sides (frames without gaps; see [`detect_in`]).
pub fn detect(time: &[f64], frames: &[Frame], forward: &[Vec3<f64>]) -> Events {
    let span = frames_in(time, SEARCH_SPAN);
    let mut events = Events::default();
    for s in 0..2 {
        let heel = along(frames, forward, |f| f[s].heel);
        let toe: Vec<f64> = along(frames, forward, |f| f[s].toe)
            .into_iter()
            .map(|v| -v)
            .collect();
        events.heel_strike[s] = peaks(&heel, threshold(&heel), span)
            .into_iter()
            .map(|i| refine(time, &heel, i))
            .collect();
        events.toe_off[s] = peaks(&toe, threshold(&toe), span)
            .into_iter()
            .map(|i| refine(time, &toe, i))
            .collect();
    }
    events
}

/// [`detect`] in each of `segments` (stretches of frames between gaps) on its own: no
/// extremum is sought across a gap, and one at a segment's end is treated as at the end of a
/// recording. Frames are those of the whole recording.
pub fn detect_in(
    time: &[f64],
    frames: &[Frame],
    forward: &[Vec3<f64>],
    segments: &[std::ops::Range<usize>],
) -> Events {
    let mut events = Events::default();
    for r in segments {
        let part = detect(&time[r.clone()], &frames[r.clone()], &forward[r.clone()]);
        let shift = |list: Vec<Event>| {
            list.into_iter().map(|e| Event {
                frame: e.frame + r.start,
                time: e.time,
            })
        };
        let [hr, hl] = part.heel_strike;
        let [tr, tl] = part.toe_off;
        for (s, (hs, to)) in [(hr, tr), (hl, tl)].into_iter().enumerate() {
            events.heel_strike[s].extend(shift(hs));
            events.toe_off[s].extend(shift(to));
        }
    }
    events
}

/// The number of frames in `seconds`, from the median frame interval.
pub fn frames_in(time: &[f64], seconds: f64) -> usize {
    match median_step(time) {
        Some(median) if median > 0.0 => ((seconds / median).round() as usize).max(1),
        _ => 1,
    }
}

/// The prominence an event must have in `signal`.
fn threshold(signal: &[f64]) -> f64 {
    let mut sorted = signal.to_vec();
    sorted.sort_by(f64::total_cmp);
    if sorted.is_empty() {
        return MIN_PROMINENCE;
    }
    let at = |p: f64| sorted[((sorted.len() - 1) as f64 * p).round() as usize];
    (PROMINENCE_FRACTION * (at(0.95) - at(0.05))).max(MIN_PROMINENCE)
}

/// The local maxima of `signal` whose prominence within `span` frames on each side is at
/// least `min_prominence`. A plateau counts once, at its first frame. A maximum at either end
/// (or a plateau that reaches one) is not a peak. Near an end, the side towards it counts
/// only if the signal falls all the way to the end (then the other side alone must stand out).
pub fn peaks(signal: &[f64], min_prominence: f64, span: usize) -> Vec<usize> {
    let n = signal.len();
    let mut out = Vec::new();
    let mut i = 1;
    while i + 1 < n {
        let v = signal[i];
        if v.partial_cmp(&signal[i - 1]) != Some(std::cmp::Ordering::Greater) {
            i += 1;
            continue;
        }
        // The end of a plateau.
        let mut j = i + 1;
        while j < n && signal[j] == v {
            j += 1;
        }
        if j == n || signal[j] > v {
            i = j;
            continue;
        }
        // Lowest point on each side before the signal rises above the peak, within the span,
        // and whether that side runs into an end of the recording first, falling all the way.
        let side = |range: &mut dyn Iterator<Item = usize>, end: usize| -> (f64, bool) {
            let (mut low, mut last, mut falling) = (v, v, true);
            for k in range {
                if signal[k] > v {
                    return (low, false);
                }
                falling &= signal[k] <= last;
                last = signal[k];
                low = low.min(signal[k]);
                if k == end {
                    return (low, falling);
                }
            }
            (low, false)
        };
        let (left, left_cut) = side(&mut (i.saturating_sub(span)..i).rev(), 0);
        let (right, right_cut) = side(&mut (j..(j + span).min(n)), n - 1);
        // A side cut by an end of the recording is waived if it falls all the way to that end
        // and the other side stands out: a maximum close to an end is still a maximum.
        let prominence = match (left_cut, right_cut) {
            (true, false) => v - right,
            (false, true) => v - left,
            _ => v - left.max(right),
        };
        if prominence >= min_prominence {
            out.push(i);
        }
        i = j;
    }
    out
}

/// The time of the extremum at frame `i`, refined by the parabola through frames `i - 1`, `i`
/// and `i + 1` (the frame's own time if the three do not bend).
pub(crate) fn refine(time: &[f64], signal: &[f64], i: usize) -> Event {
    let mut t = time[i];
    if i > 0 && i + 1 < signal.len() {
        let (a, b, c) = (signal[i - 1], signal[i], signal[i + 1]);
        let denom = a - 2.0 * b + c;
        if denom < 0.0 {
            let offset = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
            let dt = if offset >= 0.0 {
                time[i + 1] - time[i]
            } else {
                time[i] - time[i - 1]
            };
            t += offset * dt;
        }
    }
    Event { frame: i, time: t }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peaks_need_prominence_and_both_sides() {
        // A cosine with four maxima inside, one at each end.
        let s: Vec<f64> = (0..=400)
            .map(|i| (i as f64 * std::f64::consts::TAU / 100.0).cos())
            .collect();
        assert_eq!(peaks(&s, 0.5, 1000), vec![100, 200, 300]);
        // Too little prominence: nothing.
        assert!(peaks(&s, 2.5, 1000).is_empty());
        // A small wobble on a slope is not a peak.
        let w = [0.0, 1.0, 2.0, 1.9, 3.0, 4.0, 5.0, 0.0];
        assert_eq!(peaks(&w, 0.5, 10), vec![6]);
        // A plateau counts once.
        let p = [0.0, 1.0, 1.0, 1.0, 0.0];
        assert_eq!(peaks(&p, 0.5, 10), vec![1]);
    }

    #[test]
    fn the_refined_time_is_the_parabola_vertex() {
        let time = [0.0, 0.01, 0.02];
        let s = time.map(|t: f64| -(t - 0.012).powi(2));
        let e = refine(&time, &s, 1);
        assert!((e.time - 0.012).abs() < 1e-12, "{}", e.time);
        assert_eq!(e.frame, 1);
    }
}
