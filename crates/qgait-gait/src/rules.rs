//! Gait events, speed, mode (walking or running) and ground (treadmill or overground) from the
//! kinematics alone: the rules R of `docs/gait-analysis.md`, chosen there by measurement
//! against force plates and markers.
//!
//! Zeni's events ([`crate::events`]) serve as cycle anchors only. A first pass finds contact
//! where the heel's speed over the surface falls below 0.78 v and toe off where the toe tip's
//! rises above 0.66 v (Bruening & Ridge 2014), v the mid-stance speed. Its duty factor and the
//! Froude number say walking or running (Alexander 1989). Walking, with the lowest-point
//! stride-integral speed v: heel strike where the heel's speed falls below the fixed 0.5 m/s
//! of Ghoussayni et al. (2004), toe off where the toe tip's rises above 0.66 v; running:
//! the first pass's heel strike and toe off at the peak knee extension late in stance (Fellin
//! et al. 2010), the speed the mid-stance median.
//!
//! The foot's speed over the surface is its velocity relative to the pelvis plus the walking
//! speed forward: overground the pelvis moves forward at v, on a treadmill the belt moves back
//! at v. Hence the rules need no pelvis translation and apply unchanged to treadmill and
//! overground recordings and to IMU solutions. The velocities are the kernel's differential
//! kinematics where the recording has them ([`crate::trial::foot_velocities`]), else
//! [`foot_velocities`] differences the positions.

use qgait_kernel::Vec3;

use crate::events::{refine, Event, Events};
use crate::trial::{lowest_point, FootVelocity, Frame};

/// Bruening & Ridge 2014: the heel's sagittal speed is below this fraction of the walking speed
/// at contact.
pub const HS_FRACTION: f64 = 0.78;
/// Bruening & Ridge 2014: the toe's sagittal speed is above this fraction of the walking speed
/// after toe off.
pub const TO_FRACTION: f64 = 0.66;
/// Ghoussayni et al. 2004: the heel's threshold at contact in walking (m/s). Their toe
/// threshold is the same 0.5 m/s; walking's toe off uses [`TO_FRACTION`] of the speed instead
/// (docs/gait-events-methods.md, "What the numbers say").
pub const WALK_SPEED: f64 = 0.5;
/// Alexander 1989: running is a duty factor below one half (a flight phase).
pub const RUN_DUTY: f64 = 0.5;
/// Alexander 1989, Kram et al. 1997: humans change from walking to running near this Froude
/// number.
pub const FROUDE_RUN: f64 = 0.5;
/// No running below this Froude number (half the transition's): a guard against a first
/// pass's short stance at walking pace.
pub const FROUDE_FLOOR: f64 = 0.25;
/// Pelvis travel over a stride, as a fraction of the speed times the stride time, from which a
/// recording is overground (about 1 overground, about 0 on a treadmill).
pub const OVERGROUND: f64 = 0.5;
/// The search half-window, as a fraction of the median stride time.
pub const HALF: f64 = 0.5;
/// The window for a foot's swing peak next to its mid-stance, as a fraction of the median
/// stride time: from mid-stance (about 30 % of the cycle) the same foot's swing peak is about
/// 45 % of a stride away, the other stance's mid-point a whole stride.
pub const SWING: f64 = 0.75;
/// The knee-extension window ends this fraction of the stride time after Zeni's toe off.
pub const KNEE_AFTER: f64 = 0.1;
/// Gravity (m/s²), for the Froude number.
pub const G: f64 = 9.81;

/// Walking or running.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Duty factor at least one half (double support).
    Walking,
    /// Duty factor below one half (flight).
    Running,
}

impl Mode {
    /// `walking` or `running`.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Walking => "walking",
            Mode::Running => "running",
        }
    }
}

/// What the subject moved over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ground {
    /// The pelvis stays put while the feet move (a belt).
    Treadmill,
    /// The pelvis travels a stride length per stride.
    Overground,
    /// No changing pelvis translation (an IMU solution): cannot be told.
    Unknown,
}

impl Ground {
    /// `treadmill`, `overground` or `unknown`.
    pub fn name(self) -> &'static str {
        match self {
            Ground::Treadmill => "treadmill",
            Ground::Overground => "overground",
            Ground::Unknown => "unknown",
        }
    }
}

/// How the speed was obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpeedMethod {
    /// Walking: minus the forward velocity relative to the pelvis of the lowest foot point,
    /// averaged over each stride; the median over strides.
    LowestPointStrideIntegral,
    /// Running: minus the forward velocity relative to the pelvis of the MTP centre in the
    /// middle third of each stance; the median.
    MidStanceMedian,
    /// `--treadmill-speed`.
    Given,
}

impl SpeedMethod {
    /// A note for the files.
    pub fn note(self) -> &'static str {
        match self {
            SpeedMethod::LowestPointStrideIntegral => {
                "foot velocity relative to the pelvis: lowest foot point, stride integral"
            }
            SpeedMethod::MidStanceMedian => {
                "foot velocity relative to the pelvis: forefoot in mid-stance, median"
            }
            SpeedMethod::Given => "given (--treadmill-speed)",
        }
    }
}

/// How a recording's heel strikes and toe offs were found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventMethod {
    /// Walking (step 6 of R): heel strike at Ghoussayni's fixed 0.5 m/s, toe off at 0.66 v.
    Walking,
    /// Running with knee angles: the first pass's heel strike (0.78 v), toe off at the peak knee
    /// extension late in stance.
    RunningKnee,
    /// Running without knee angles (a device's points): the first pass's heel strike and toe
    /// off.
    RunningFirstPass,
    /// Too few strides for the rules: Zeni et al.'s extrema.
    Zeni,
}

impl EventMethod {
    /// The method of the events of a recording the rules found `gait` of (`None`: they did not
    /// run).
    pub fn of(gait: Option<&Gait>) -> Self {
        gait.map_or(EventMethod::Zeni, |g| g.events)
    }

    /// How the heel strikes were found, for the files' notes.
    pub fn heel_strike(self) -> &'static str {
        match self {
            EventMethod::Walking => {
                "heel strike: the heel's speed over the surface falls through 0.5 m/s (Ghoussayni et al. 2004)"
            }
            EventMethod::RunningKnee | EventMethod::RunningFirstPass => {
                "heel strike: the heel's speed over the surface falls through 0.78 x speed (Bruening & Ridge 2014)"
            }
            EventMethod::Zeni => {
                "heel strike: the heel furthest in front of the pelvis (Zeni et al. 2008)"
            }
        }
    }

    /// How the toe offs were found, for the files' notes.
    pub fn toe_off(self) -> &'static str {
        match self {
            EventMethod::Walking | EventMethod::RunningFirstPass => {
                "toe off: the toe tip's speed over the surface rises through 0.66 x speed (Bruening & Ridge 2014)"
            }
            EventMethod::RunningKnee => {
                "toe off: the peak knee extension late in stance (Fellin et al. 2010)"
            }
            EventMethod::Zeni => {
                "toe off: the toe tip furthest behind the pelvis (Zeni et al. 2008)"
            }
        }
    }

    /// Both, and which rules, for `summary.json`.
    pub fn describe(self) -> String {
        let rules = match self {
            EventMethod::Walking => "rules R, walking (docs/gait-analysis.md)",
            EventMethod::RunningKnee | EventMethod::RunningFirstPass => {
                "rules R, running (docs/gait-analysis.md)"
            }
            EventMethod::Zeni => "Zeni et al. 2008 (too few strides for the rules)",
        };
        format!("{rules}: {}; {}", self.heel_strike(), self.toe_off())
    }
}

/// What the rules found about a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Gait {
    /// Walking or running.
    pub mode: Mode,
    /// Treadmill, overground or unknown.
    pub ground: Ground,
    /// Speed over the surface (m/s).
    pub speed: f64,
    /// How it was obtained.
    pub speed_method: SpeedMethod,
    /// The first pass's duty factor (stance over stride), which decided the mode.
    pub first_duty: f64,
    /// The final events' duty factor, when a stride has them all.
    pub duty: Option<f64>,
    /// Leg length (m): hip centre to the lowest foot point, 95th percentile.
    pub leg_length: f64,
    /// Froude number v²/(g L).
    pub froude: f64,
    /// Median pelvis travel per stride over speed × stride time, when the motion has a changing
    /// pelvis translation.
    pub travel_ratio: Option<f64>,
    /// How the events were found.
    pub events: EventMethod,
    /// Doubts about the mode (a slow jog, a fast walk, a duty factor against the mode).
    pub notes: Vec<String>,
    /// The speed measured over each stride (walking) or stance (running) the speed came from:
    /// `(start, end, speed)` in s, s, m/s, in no particular order (none for a given speed).
    pub local_speeds: Vec<(f64, f64, f64)>,
}

/// The velocity of each frame's heel, forefoot and toe tip relative to the pelvis (ground
/// axes), per side: central differences of the FK points within each segment (one-sided at
/// its ends, zero for a one-frame segment), no filter. The one place the rules get velocities
/// from, so that the kernel's exact differential kinematics can take its place.
pub fn foot_velocities(
    time: &[f64],
    frames: &[Frame],
    segments: &[std::ops::Range<usize>],
) -> Vec<[FootVelocity; 2]> {
    let mut out = vec![[FootVelocity::default(); 2]; frames.len()];
    for r in segments {
        if r.len() < 2 {
            continue;
        }
        for i in r.clone() {
            let (a, b) = (i.max(r.start + 1) - 1, (i + 1).min(r.end - 1));
            let (a, b) = if i == r.start { (i, i + 1) } else { (a, b) };
            let dt = time[b] - time[a];
            if dt <= 0.0 {
                continue;
            }
            for s in 0..2 {
                let d = |p: fn(&crate::trial::Limb) -> Vec3<f64>| {
                    (p(&frames[b][s]) - p(&frames[a][s])) * (1.0 / dt)
                };
                out[i][s] = FootVelocity {
                    heel: d(|l| l.heel),
                    forefoot: d(|l| l.forefoot),
                    toe: d(|l| l.toe),
                };
            }
        }
    }
    out
}

/// Everything the rules read of a recording.
pub struct Input<'a> {
    /// Time of each frame (s).
    pub time: &'a [f64],
    /// Points of each frame.
    pub frames: &'a [Frame],
    /// Direction of progression of each frame.
    pub forward: &'a [Vec3<f64>],
    /// Stretches without gaps.
    pub segments: &'a [std::ops::Range<usize>],
    /// The knee angle of each side and frame (gait2392's sign: 0 straight, flexion negative).
    pub knee: Option<[Vec<f64>; 2]>,
    /// `pelvis_tx`, `pelvis_tz` of each frame, when they change.
    pub translation: Option<&'a [[f64; 2]]>,
    /// A known belt speed (m/s).
    pub given_speed: Option<f64>,
    /// The feet's velocities from the kernel's differential kinematics, where the recording
    /// has them ([`crate::trial::Trial::velocities`]); else [`foot_velocities`] differentiates
    /// the positions.
    pub velocities: Option<&'a [[FootVelocity; 2]]>,
}

/// Per-frame signals of one recording.
struct Signals<'a> {
    input: &'a Input<'a>,
    vel: Vec<[FootVelocity; 2]>,
    /// Segment of each frame.
    seg: Vec<usize>,
    /// Median stride time of the anchors (s).
    stride: f64,
}

impl Signals<'_> {
    fn fwd(&self, i: usize, v: Vec3<f64>) -> f64 {
        v.dot(self.input.forward[i])
    }
    /// Speed over the surface at walking speed `v` of a point's velocity.
    fn over(&self, i: usize, p: Vec3<f64>, v: f64) -> f64 {
        (self.fwd(i, p) + v).hypot(p.y)
    }
    /// The frames of the segment of frame `at` with times in `[t0, t1]`.
    fn frames(&self, at: usize, t0: f64, t1: f64) -> std::ops::Range<usize> {
        let r = &self.input.segments[self.seg[at]];
        let t = self.input.time;
        let lo = r.start + t[r.clone()].partition_point(|&x| x < t0);
        let hi = r.start + t[r.clone()].partition_point(|&x| x <= t1);
        lo..hi.max(lo)
    }
    fn argmin(&self, r: std::ops::Range<usize>, f: impl Fn(usize) -> f64) -> Option<usize> {
        r.min_by(|&a, &b| f(a).total_cmp(&f(b)))
    }
    fn argmax(&self, r: std::ops::Range<usize>, f: impl Fn(usize) -> f64) -> Option<usize> {
        r.max_by(|&a, &b| f(a).total_cmp(&f(b)))
    }
}

/// The time where `f` crosses `level` between frames `k - 1` and `k` (linear).
fn cross(time: &[f64], f: &impl Fn(usize) -> f64, k: usize, level: f64) -> f64 {
    let (a, b) = (f(k - 1), f(k));
    let w = if b != a { (level - a) / (b - a) } else { 0.0 };
    time[k - 1] + w.clamp(0.0, 1.0) * (time[k] - time[k - 1])
}

/// The median of the finite values of `v`.
pub(crate) fn median(mut v: Vec<f64>) -> Option<f64> {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    })
}

fn event(time: &[f64], t: f64) -> Event {
    let k = time.partition_point(|&x| x < t).min(time.len() - 1);
    let frame = if k > 0 && (t - time[k - 1]) < (time[k] - t) {
        k - 1
    } else {
        k
    };
    Event { frame, time: t }
}

/// Heel strikes and toe offs from speed thresholds at walking speed `v` (step 4 of R).
fn threshold_pass(
    s: &Signals,
    anchors: &Events,
    v: f64,
    heel_level: f64,
    toe_level: f64,
) -> Events {
    let (time, half) = (s.input.time, HALF * s.stride);
    let mut out = Events::default();
    for side in 0..2 {
        let fore = |i: usize| s.over(i, s.vel[i][side].forefoot, v);
        let heel = |i: usize| s.over(i, s.vel[i][side].heel, v);
        let toe = |i: usize| s.over(i, s.vel[i][side].toe, v);
        for h in &anchors.heel_strike[side] {
            let Some(c) = s.argmin(s.frames(h.frame, h.time, h.time + half), fore) else {
                continue;
            };
            // The first fall below the level after the heel's swing peak: on the steep flank
            // of the swing, not where the speed hovers near the level in early stance (slow
            // walking, an IMU solution's noisier feet).
            let Some(p) = s.argmax(s.frames(c, time[c] - SWING * s.stride, time[c]), heel) else {
                continue;
            };
            let found = (p + 1..=c)
                .find(|&k| heel(k - 1) >= heel_level && heel(k) < heel_level)
                .map(|k| cross(time, &heel, k, heel_level));
            if let Some(t) = found {
                keep(&mut out.heel_strike[side], event(time, t), half);
            }
        }
        for o in &anchors.toe_off[side] {
            let Some(c) = s.argmin(s.frames(o.frame, o.time - half, o.time), fore) else {
                continue;
            };
            // The last rise above the level before the toe's swing peak (as for heel strike).
            let Some(p) = s.argmax(s.frames(c, time[c], time[c] + SWING * s.stride), toe) else {
                continue;
            };
            let found = (c.max(1)..=p)
                .rev()
                .find(|&k| toe(k - 1) <= toe_level && toe(k) > toe_level)
                .map(|k| cross(time, &toe, k, toe_level));
            if let Some(t) = found {
                keep(&mut out.toe_off[side], event(time, t), half);
            }
        }
    }
    out
}

/// Adds `e` unless it is within `half` of the last kept event.
fn keep(list: &mut Vec<Event>, e: Event, half: f64) {
    if list.last().is_none_or(|l| e.time - l.time > half) {
        list.push(e);
    }
}

/// Complete strides of one side: consecutive heel strikes in one segment with exactly one toe
/// off between them: `(hs, next hs, toe off)` times.
fn strides(s: &Signals, e: &Events, side: usize) -> Vec<(f64, f64, f64)> {
    e.heel_strike[side]
        .windows(2)
        .filter(|w| s.seg[w[0].frame] == s.seg[w[1].frame])
        .filter_map(|w| {
            let mut to = e.toe_off[side]
                .iter()
                .filter(|o| o.time > w[0].time && o.time < w[1].time);
            match (to.next(), to.next()) {
                (Some(o), None) => Some((w[0].time, w[1].time, o.time)),
                _ => None,
            }
        })
        .collect()
}

fn duty(s: &Signals, e: &Events) -> Option<f64> {
    let d: Vec<f64> = (0..2)
        .flat_map(|side| strides(s, e, side))
        .map(|(a, b, o)| (o - a) / (b - a))
        .collect();
    (!d.is_empty()).then(|| d.iter().sum::<f64>() / d.len() as f64)
}

/// Applies the rules to a recording with Zeni's `anchors`; `None` when there are too few
/// anchors for a stride time or a speed (the anchors then stand as the events).
pub fn apply(input: &Input, anchors: &Events) -> Option<(Events, Gait)> {
    let time = input.time;
    let n = time.len();
    if n < 3 {
        return None;
    }
    let mut seg = vec![0; n];
    for (k, r) in input.segments.iter().enumerate() {
        for i in r.clone() {
            seg[i] = k;
        }
    }
    let seg_of = seg.clone();
    let same = |a: usize, b: usize| seg_of[a] == seg_of[b];
    let stride = median(
        (0..2)
            .flat_map(|side| anchors.heel_strike[side].windows(2))
            .filter(|w| same(w[0].frame, w[1].frame))
            .map(|w| w[1].time - w[0].time)
            .collect(),
    )?;
    let s = Signals {
        input,
        vel: match input.velocities {
            Some(v) if v.len() == n => v.to_vec(),
            _ => foot_velocities(time, input.frames, input.segments),
        },
        seg,
        stride,
    };
    // Step 2: the mid-stance median.
    let mut samples = Vec::new();
    let mut stance_speeds = Vec::new();
    for side in 0..2 {
        for h in &anchors.heel_strike[side] {
            let Some(o) = anchors.toe_off[side]
                .iter()
                .find(|o| o.time > h.time && o.time - h.time < stride && same(o.frame, h.frame))
            else {
                continue;
            };
            let d = o.time - h.time;
            let r = s.frames(h.frame, h.time + d / 3.0, h.time + 2.0 * d / 3.0);
            if let Some(m) = median(
                r.map(|i| -s.fwd(i, s.vel[i][side].forefoot))
                    .collect::<Vec<_>>(),
            ) {
                samples.push(m);
                stance_speeds.push((h.time, o.time, m));
            }
        }
    }
    let (v0, mut method) = match input.given_speed {
        Some(v) => (v, SpeedMethod::Given),
        None => (median(samples)?, SpeedMethod::MidStanceMedian),
    };
    if v0.is_nan() || v0 <= 0.0 {
        return None;
    }
    // Step 4: the first pass.
    let first = threshold_pass(&s, anchors, v0, HS_FRACTION * v0, TO_FRACTION * v0);
    let first_duty = duty(&s, &first)?;
    let leg_length = (0..2)
        .filter_map(|side| {
            percentile_95(
                input
                    .frames
                    .iter()
                    .map(|f| {
                        let l = &f[side];
                        l.hip.y - l.heel.y.min(l.forefoot.y).min(l.toe.y)
                    })
                    .collect(),
            )
        })
        .sum::<f64>()
        / 2.0;
    let running = first_duty < RUN_DUTY && v0 * v0 / (G * leg_length) >= FROUDE_FLOOR;
    let mut local = Vec::new();
    let mut method_of_events = EventMethod::Walking;
    let (mode, speed, events) = if running {
        // Step 5b.
        let mut events = Events {
            heel_strike: first.heel_strike.clone(),
            toe_off: first.toe_off.clone(),
        };
        method_of_events = EventMethod::RunningFirstPass;
        if let Some(knee) = &input.knee {
            method_of_events = EventMethod::RunningKnee;
            for (side, knee) in knee.iter().enumerate() {
                let fore = |i: usize| s.over(i, s.vel[i][side].forefoot, v0);
                let mut list = Vec::new();
                for o in &anchors.toe_off[side] {
                    let Some(c) = s.argmin(s.frames(o.frame, o.time - HALF * stride, o.time), fore)
                    else {
                        continue;
                    };
                    let r = s.frames(c, time[c], o.time + KNEE_AFTER * stride);
                    let Some(k) = r.clone().max_by(|&a, &b| knee[a].total_cmp(&knee[b])) else {
                        continue;
                    };
                    if k == r.start || k + 1 == r.end {
                        continue;
                    }
                    keep(&mut list, refine(time, knee, k), HALF * stride);
                }
                events.toe_off[side] = list;
            }
        }
        if input.given_speed.is_none() {
            local = stance_speeds;
        }
        (Mode::Running, v0, events)
    } else {
        // Step 5a.
        let v = match input.given_speed {
            Some(v) => v,
            None => {
                let per_stride: Vec<(f64, f64, f64)> = (0..2)
                    .flat_map(|side| strides(&s, &first, side))
                    .filter_map(|(a, b, _)| {
                        let r = s.frames(event(time, a).frame, a, b);
                        let values: Vec<f64> = r
                            .map(|i| {
                                let (side, point) = lowest_point(&input.frames[i]);
                                let vel = s.vel[i][side];
                                -s.fwd(i, vel.at(point))
                            })
                            .collect();
                        (!values.is_empty())
                            .then(|| (a, b, values.iter().sum::<f64>() / values.len() as f64))
                    })
                    .collect();
                method = SpeedMethod::LowestPointStrideIntegral;
                let v = median(per_stride.iter().map(|p| p.2).collect())?;
                local = per_stride;
                v
            }
        };
        // Heel strike at Ghoussayni's fixed level, toe off at Bruening & Ridge's scaled one:
        // each rule's better half on the plates (the scaled heel level is 15-18 ms early, the
        // fixed toe level 8-11 ms early).
        let events = threshold_pass(&s, anchors, v, WALK_SPEED, TO_FRACTION * v);
        (Mode::Walking, v, events)
    };
    // Step 6: checks.
    let mut notes = Vec::new();
    let final_duty = duty(&s, &events);
    let froude = speed * speed / (G * leg_length);
    if let Some(d) = final_duty {
        if (mode == Mode::Running) != (d < RUN_DUTY) {
            notes.push(format!(
                "mode uncertain: the {} rules give a duty factor of {d:.3}",
                mode.name()
            ));
        }
    }
    if (mode == Mode::Running) != (froude > FROUDE_RUN) {
        notes.push(format!(
            "Froude number {froude:.2} is on the other side of the walk-run transition (0.5): {}",
            if mode == Mode::Running {
                "a slow jog"
            } else {
                "a fast walk"
            }
        ));
    }
    // Ground.
    let travel_ratio = input.translation.and_then(|tr| {
        median(
            (0..2)
                .flat_map(|side| events.heel_strike[side].windows(2))
                .filter(|w| same(w[0].frame, w[1].frame))
                .map(|w| {
                    let (a, b) = (tr[w[0].frame], tr[w[1].frame]);
                    let dt = time[w[1].frame] - time[w[0].frame];
                    (b[0] - a[0]).hypot(b[1] - a[1]) / (speed * dt)
                })
                .collect(),
        )
    });
    let ground = match (input.translation, travel_ratio) {
        (None, _) => Ground::Unknown,
        (Some(_), Some(r)) if r >= OVERGROUND => Ground::Overground,
        (Some(_), Some(_)) => Ground::Treadmill,
        (Some(_), None) => Ground::Unknown,
    };
    Some((
        events,
        Gait {
            mode,
            ground,
            speed,
            speed_method: method,
            first_duty,
            duty: final_duty,
            leg_length,
            froude,
            travel_ratio,
            events: method_of_events,
            notes,
            local_speeds: local,
        },
    ))
}

fn percentile_95(mut v: Vec<f64>) -> Option<f64> {
    v.retain(|x| x.is_finite());
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(v[((v.len() - 1) as f64 * 0.95).round() as usize])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trial::Limb;

    #[test]
    fn velocities_are_central_differences_within_segments() {
        let time: Vec<f64> = (0..6).map(|i| i as f64 * 0.1).collect();
        let frames: Vec<Frame> = time
            .iter()
            .map(|&t| {
                let l = Limb {
                    heel: Vec3::new(t * t, 0.0, 0.0),
                    forefoot: Vec3::new(0.0, 2.0 * t, 0.0),
                    toe: Vec3::new(0.0, 0.0, -t),
                    ..Limb::default()
                };
                [l, l]
            })
            .collect();
        let v = foot_velocities(&time, &frames, &[0..3, 3..6]);
        // Central: d(t²)/dt = 2t exactly at inner frames.
        assert!((v[1][0].heel.x - 0.2).abs() < 1e-12);
        assert!((v[4][1].heel.x - 0.8).abs() < 1e-12);
        // One-sided at a segment's ends (no difference across the break).
        assert!((v[2][0].heel.x - 0.3).abs() < 1e-12, "{:?}", v[2][0]);
        assert!((v[3][0].heel.x - 0.7).abs() < 1e-12, "{:?}", v[3][0]);
        assert!((v[0][0].forefoot.y - 2.0).abs() < 1e-12);
        assert!((v[5][0].toe.z + 1.0).abs() < 1e-12);
    }
}

#[cfg(test)]
mod possible {
    use crate::error::ReportError;
    use crate::output::check_possible;
    use crate::spatiotemporal::Parameter;

    fn p(name: &'static str, value: f64) -> Parameter {
        Parameter {
            name,
            side: "both",
            value: Some(value),
            unit: "steps/min",
            range: None,
            note: String::new(),
        }
    }

    /// A cadence of 1,830/min or a double support of 131.7 % is an error, not a figure.
    #[test]
    fn impossible_results_are_errors() {
        for (name, v) in [
            ("cadence", 1830.0),
            ("double_support", 131.7),
            ("stance", -1.0),
        ] {
            let e = check_possible(&[], None, &[p("cadence", 100.0), p(name, v)]).unwrap_err();
            assert!(
                matches!(&e, ReportError::Impossible { what, .. } if what.starts_with(name)),
                "{e}"
            );
        }
        assert!(check_possible(&[], None, &[p("cadence", 100.0), p("stance", 62.0)]).is_ok());
    }
}
