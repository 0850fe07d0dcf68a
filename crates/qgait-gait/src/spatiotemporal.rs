//! Spatiotemporal parameters from the cycles and the feet's FK positions at heel strike.
//!
//! Per stride of a side (heel strike to heel strike): stride time; step time (the other side's
//! heel strike to the side's next); stance (to the side's toe off) and swing as % of the
//! stride; double support (both feet down: heel strike to the other side's toe off, and the
//! other side's heel strike to the side's toe off) as % of the stride. At the side's heel
//! strike: step length, the heels' distance along the stride's direction of travel, and step
//! width, their distance across it (horizontal). The direction of travel is the pelvis's
//! horizontal displacement over the stride as the feet give it ([`stride_direction`]); for a
//! cycle without all four events, as the lower foot gives it ([`lowest_foot_direction`]);
//! only without either, the direction the pelvis faces at the heel strike (a pelvis can face
//! well away from the way the feet go: crouch4's, 35°). Stride length: the pelvis's horizontal
//! displacement over the stride where the motion has `pelvis_tx`/`pelvis_tz`, else the sum of
//! the two sides' mean step lengths (the FK positions are relative to the pelvis, and at heel
//! strike both feet are down). Speed: stride length over stride time. Each is the mean over
//! the side's strides; `both` is over all strides, except the step width's, the mean of the
//! two sides' (a direction of progression a few degrees off the feet's path widens one side's
//! steps and narrows the other's by the same amount, to first order). A model that
//! cannot move a foot sideways relative to the other ([`Trial::seen`],
//! [`crate::angles::Seen::step_width`]: a planar one) has no step width: a `both` row without a
//! value says why. Each
//! parameter's note says how it was found, those of the events with the events' method
//! ([`EventMethod`]).

use qgait_kernel::progression::horizontal_unit;
use qgait_kernel::Vec3;

use crate::angles::Seen;
use crate::cycles::Cycle;
use crate::normative::Range;
use crate::rules::{EventMethod, Gait, Mode};
use crate::trial::{lowest_point, Trial};

/// One parameter of one side.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Name (`cadence`, `stride_time`, ...).
    pub name: &'static str,
    /// `right`, `left` or `both`.
    pub side: &'static str,
    /// Value; `None` for a parameter the model cannot see (the note says why).
    pub value: Option<f64>,
    /// Unit.
    pub unit: &'static str,
    /// Normal range, where known.
    pub range: Option<Range>,
    /// How it was obtained (or why it has no value).
    pub note: String,
}

/// Side names, [`qgait_kernel::Side::ALL`] order.
pub const SIDES: [&str; 2] = ["right", "left"];

/// One analysed recording: the trial, its direction of progression, its cycles and what the
/// rules found ([`crate::rules`]).
pub type Walk<'a> = (
    &'a Trial,
    &'a [Vec3<f64>],
    &'a [Vec<Cycle>; 2],
    Option<&'a Gait>,
);

/// The note of a length from the speed: speed times a time.
pub const FROM_SPEED: &str = "speed x stride time";
/// The note of a step length from the speed.
pub const STEP_FROM_SPEED: &str =
    "speed x step time (heel strike to the other foot's): the distance travelled between contacts of opposite feet";

/// The direction of travel over a stride (horizontal unit vector), from the feet alone: a foot
/// in stance stands still on the ground, so relative to the pelvis its forefoot (gait2392's
/// MTP joint, the toe tip without a foot) moves back by exactly what the pelvis moves forward.
/// Summing that over the stride with the foot in stance at each moment (the other foot's from
/// the heel strike to its toe off, the side's own to its toe off, then the other's; the
/// trailing foot's during double support, whose forefoot stays down until it leaves the
/// ground) gives the pelvis's displacement over the stride, and the side-to-side sway of the
/// pelvis within it cancels. `None` for a cycle without its toe offs and the other side's heel
/// strike, or without a displacement.
pub fn stride_direction(trial: &Trial, c: &Cycle) -> Option<Vec3<f64>> {
    let (to, ohs, oto) = (c.toe_off?, c.opposite_strike?, c.opposite_toe_off?);
    if !(oto <= ohs && ohs <= to) {
        return None;
    }
    let stance = |t: f64| {
        if t >= oto && t < to {
            c.side
        } else {
            1 - c.side
        }
    };
    let inside: Vec<(usize, f64)> = c
        .samples
        .iter()
        .copied()
        .filter(|(_, t)| (0.0..=c.duration).contains(t))
        .collect();
    let mut moved = Vec3::new(0.0, 0.0, 0.0);
    for w in inside.windows(2) {
        let ((f0, t0), (f1, _)) = (w[0], w[1]);
        let foot = stance(t0);
        moved = moved - (trial.frames[f1][foot].forefoot - trial.frames[f0][foot].forefoot);
    }
    horizontal_unit(moved)
}

/// The direction of travel over a cycle without the events [`stride_direction`] needs: as
/// there, from the backward displacement of a foot on the ground relative to the pelvis, with
/// the point on the ground at each moment taken to be the lowest ([`lowest_point`]). `None`
/// without a horizontal displacement.
pub fn lowest_foot_direction(trial: &Trial, c: &Cycle) -> Option<Vec3<f64>> {
    let inside: Vec<usize> = c
        .samples
        .iter()
        .filter(|(_, t)| (0.0..=c.duration).contains(t))
        .map(|&(f, _)| f)
        .collect();
    let mut moved = Vec3::new(0.0, 0.0, 0.0);
    for w in inside.windows(2) {
        let (a, b) = (&trial.frames[w[0]], &trial.frames[w[1]]);
        let (side, point) = lowest_point(a);
        moved = moved - (b[side].at(point) - a[side].at(point));
    }
    horizontal_unit(moved)
}

/// What the parameters need of one stride, computed while its recording (or window of a long
/// recording, [`crate::stream`]) is in memory: a few numbers, so that the strides of a day of
/// data can be kept.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stride {
    /// Its heel strike (s).
    pub start: f64,
    /// Duration (s).
    pub duration: f64,
    /// Toe off of the side, since the start (s).
    pub toe_off: Option<f64>,
    /// Heel strike of the other side, since the start (s).
    pub opposite_strike: Option<f64>,
    /// Toe off of the other side, since the start (s).
    pub opposite_toe_off: Option<f64>,
    /// At its heel strike, the heels' distance along the direction of travel (m).
    pub along: f64,
    /// At its heel strike, the heels' horizontal distance across it (m).
    pub across: f64,
    /// The distance travelled over the stride (m): the rules' speed times its duration, else
    /// from the pelvis translation; `None` without either.
    pub moved: Option<f64>,
    /// The rules' speed of its recording (m/s), when the rules ran.
    pub speed: Option<f64>,
    /// The rules found running.
    pub running: bool,
    /// What its recording's model can move ([`Trial::seen`]).
    pub seen: Seen,
}

impl Stride {
    /// The stride of cycle `c` (of side `c.side`) of `trial`.
    pub fn of(trial: &Trial, forward: &[Vec3<f64>], c: &Cycle, g: Option<&Gait>) -> Self {
        let (s, o) = (c.side, 1 - c.side);
        let f = &trial.frames[c.strike_frame];
        let d = stride_direction(trial, c)
            .or_else(|| lowest_foot_direction(trial, c))
            .unwrap_or(forward[c.strike_frame]);
        let between = f[s].heel - f[o].heel;
        let across = Vec3::new(-d.z, 0.0, d.x);
        let moved = match g {
            Some(g) => Some(g.speed * c.duration),
            None => trial.translation.as_ref().and_then(|tr| {
                let (a, b) = (tr[c.span.0], tr[c.span.1]);
                let t = trial.time[c.span.1] - trial.time[c.span.0];
                // Per second of the frames spanned, times the stride's duration.
                // A translation that is not a finite number (a column the model does not read)
                // gives none: the step lengths are estimated instead.
                let d = (b[0] - a[0]).hypot(b[1] - a[1]);
                (t > 0.0 && d.is_finite()).then(|| d / t * c.duration)
            }),
        };
        Self {
            start: c.start,
            duration: c.duration,
            toe_off: c.toe_off,
            opposite_strike: c.opposite_strike,
            opposite_toe_off: c.opposite_toe_off,
            along: between.dot(d),
            across: between.dot(across).abs(),
            moved,
            speed: g.map(|g| g.speed),
            running: g.is_some_and(|g| g.mode == Mode::Running),
            seen: trial.seen,
        }
    }

    /// An event time (s since the start) as a percentage of the stride.
    pub fn percent(&self, since_start: f64) -> f64 {
        100.0 * since_start / self.duration
    }
}

/// A sum and a count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Sum(f64, usize);

impl Sum {
    fn add(&mut self, v: Option<f64>) {
        if let Some(v) = v {
            self.0 += v;
            self.1 += 1;
        }
    }

    fn mean(self) -> Option<f64> {
        (self.1 > 0).then(|| self.0 / self.1 as f64)
    }
}

/// What the parameters need of a side's strides, summed stride by stride ([`Sums::add`]): its
/// memory does not grow with the strides, and each mean is the sum in the strides' order over
/// their number, as over a list of them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sums {
    n: usize,
    with_speed: usize,
    duration: Sum,
    step_from_speed: Sum,
    along: Sum,
    across: Sum,
    moved: Sum,
    step_time: Sum,
    stance: Sum,
    flight: Sum,
    double_support: Sum,
    running: bool,
    /// What every stride's model can move.
    seen: Seen,
}

impl Sums {
    /// One more stride.
    pub fn add(&mut self, c: &Stride) {
        self.n += 1;
        self.with_speed += usize::from(c.speed.is_some());
        self.duration.add(Some(c.duration));
        self.step_from_speed
            .add((|| Some(c.speed? * (c.duration - c.opposite_strike?)))());
        self.along.add(Some(c.along));
        self.across.add(Some(c.across));
        self.moved.add(c.moved);
        self.step_time
            .add(c.opposite_strike.map(|o| c.duration - o));
        self.stance.add(c.toe_off.map(|t| c.percent(t)));
        self.flight.add((|| {
            let (to, ohs) = (c.toe_off?, c.opposite_strike?);
            (ohs > to).then(|| c.percent(ohs - to))
        })());
        self.double_support
            .add(match (c.toe_off, c.opposite_strike, c.opposite_toe_off) {
                (Some(to), Some(ohs), Some(oto)) if ohs <= to => {
                    Some(c.percent(oto) + c.percent(to - ohs))
                }
                _ => None,
            });
        self.running |= c.running;
        self.seen = self.seen.and(c.seen);
    }

    /// The strides summed.
    pub fn count(&self) -> usize {
        self.n
    }
}

/// The parameters of the cycles of both sides, over every stride of every recording.
pub fn parameters(walks: &[Walk<'_>]) -> Vec<Parameter> {
    let sums: [Sums; 2] = std::array::from_fn(|s| {
        let mut sums = Sums::default();
        for (t, f, c, g) in walks {
            for c in &c[s] {
                sums.add(&Stride::of(t, f, c, *g));
            }
        }
        sums
    });
    let rules: Vec<Option<&Gait>> = walks.iter().map(|w| w.3).collect();
    let events = one_method(rules.iter().map(|g| Some(EventMethod::of(*g))));
    parameters_of(&sums, &rules, events)
}

/// The one method of the events of every recording (each `None` where a recording's own
/// differ between its windows); `None` when they differ.
pub fn one_method(each: impl IntoIterator<Item = Option<EventMethod>>) -> Option<EventMethod> {
    let mut all = each.into_iter();
    let first = all.next()??;
    all.all(|m| m == Some(first)).then_some(first)
}

/// The note of the events' method when the recordings' (or a long recording's windows')
/// differ.
pub const MIXED_EVENTS: &str =
    "events: each recording's own (the rules R where they applied, else Zeni et al. 2008; summary.json's recordings say which)";

/// The parameters of the strides of each side, summed; `rules` holds what the rules found of
/// each recording (`None` where they did not run), `events` the one method of every
/// recording's events (`None` when they differ: [`one_method`]).
pub fn parameters_of(
    sums: &[Sums; 2],
    rules: &[Option<&Gait>],
    events: Option<EventMethod>,
) -> Vec<Parameter> {
    let mut out = Vec::new();
    let mut push = |name, side, value: Option<f64>, unit, note: &str| {
        if let Some(value) = value.filter(|v: &f64| v.is_finite()) {
            out.push(Parameter {
                name,
                side,
                value: Some(value),
                unit,
                range: None,
                note: note.to_string(),
            });
        }
    };
    // The events' method: of the heel strikes alone, and of both.
    let (strikes, both_events) = match events {
        Some(m) => (
            m.heel_strike().to_string(),
            format!("{}; {}", m.heel_strike(), m.toe_off()),
        ),
        None => (MIXED_EVENTS.to_string(), MIXED_EVENTS.to_string()),
    };
    let cadence_note = format!("120 / stride time; {strikes}");
    let stride_note = format!("heel strike to the next of the same side; {strikes}");
    let mut step_length = [None; 2];
    let mut step_width = [None; 2];
    let mut stride_time = [None; 2];
    let mut displacement = [None; 2];
    let mut all_durations = Sum::default();
    let mut step_note = "heels at heel strike";
    for s in 0..2 {
        let c = &sums[s];
        all_durations.0 += c.duration.0;
        all_durations.1 += c.duration.1;
        stride_time[s] = c.duration.mean();
        // With a speed from the rules: speed x step time, whatever the pelvis does.
        let from_speed = c.with_speed == c.n;
        step_length[s] = if from_speed {
            c.step_from_speed.mean()
        } else {
            c.along.mean()
        };
        if c.moved.1 == c.n {
            displacement[s] = c.moved.mean();
        }
        let side = SIDES[s];
        push(
            "cadence",
            side,
            stride_time[s].map(|t| 120.0 / t),
            "steps/min",
            &cadence_note,
        );
        push("stride_time", side, stride_time[s], "s", &stride_note);
        push(
            "step_time",
            side,
            c.step_time.mean(),
            "s",
            &format!("the other side's heel strike to this side's next; {strikes}"),
        );
        let stance = c.stance.mean();
        push(
            "stance",
            side,
            stance,
            "%",
            &format!("heel strike to toe off; {both_events}"),
        );
        push(
            "swing",
            side,
            stance.map(|s| 100.0 - s),
            "%",
            &format!("toe off to the next heel strike; {both_events}"),
        );
        if c.running {
            // Running: no double support; the flight from the side's toe off to the other
            // foot's contact.
            push(
                "flight",
                side,
                c.flight.mean(),
                "%",
                &format!(
                    "the side's toe off to the other foot's heel strike (running); {both_events}"
                ),
            );
        } else {
            push(
                "double_support",
                side,
                c.double_support.mean(),
                "%",
                &format!("both feet down: heel strike to the other side's toe off, and the other side's heel strike to this side's toe off; {both_events}"),
            );
        }
        push(
            "step_length",
            side,
            step_length[s],
            "m",
            if from_speed {
                step_note = STEP_FROM_SPEED;
                step_note
            } else {
                step_note
            },
        );
        if c.seen.step_width() {
            step_width[s] = c.across.mean();
            push(
                "step_width",
                side,
                step_width[s],
                "m",
                "heels at heel strike",
            );
        }
    }
    // Stride length and speed per side, then both.
    let estimated = "estimated: the two mean step lengths (no pelvis translation)";
    let every = rules.len();
    let rules: Vec<&Gait> = rules.iter().filter_map(|g| *g).collect();
    let measured = match rules.first() {
        Some(g) if rules.len() == every => g.speed_method.note(),
        _ => "pelvis_tx/pelvis_tz",
    };
    let stride_length = |s: usize| -> Option<(f64, &'static str)> {
        match displacement[s] {
            Some(d) => Some((d, measured)),
            None => Some((step_length[0]? + step_length[1]?, estimated)),
        }
    };
    let mut lengths = Vec::new();
    for s in 0..2 {
        if let (Some((l, note)), Some(t)) = (stride_length(s), stride_time[s]) {
            push("stride_length", SIDES[s], Some(l), "m", length_note(note));
            push("speed", SIDES[s], Some(l / t), "m/s", note);
            lengths.push((l, note));
        }
    }
    if let [Some(r), Some(l)] = step_length {
        push("step_length", "both", Some((r + l) / 2.0), "m", step_note);
    }
    if let [Some(r), Some(l)] = step_width {
        push(
            "step_width",
            "both",
            Some((r + l) / 2.0),
            "m",
            "the mean of the two sides",
        );
    }
    let seen = sums
        .iter()
        .filter(|c| c.n > 0)
        .fold(Seen::ALL, |a, c| a.and(c.seen));
    // What the rules found (one recording's, or the first's of several).
    if let Some(g) = rules.first() {
        push(
            "duty_factor",
            "both",
            g.duty.or(Some(g.first_duty)),
            "",
            match g.mode {
                Mode::Running => "running (duty factor below 0.5, Froude number at least 0.25): flight instead of double support; the normal ranges and normative bands are walking's",
                Mode::Walking => "walking (duty factor at least 0.5, or Froude number below 0.25)",
            },
        );
        push(
            "froude",
            "both",
            Some(g.froude),
            "",
            if g.travel_ratio.is_none() {
                "speed^2 / (g x leg length), the walk-run transition near 0.5; ground unknown: no changing pelvis translation"
            } else {
                "speed^2 / (g x leg length); the walk-run transition is near 0.5"
            },
        );
        push(
            "leg_length",
            "both",
            Some(g.leg_length),
            "m",
            "hip centre to the lowest foot point",
        );
        if let Some(r) = g.travel_ratio {
            let ground = g.ground;
            push(
                "travel_ratio",
                "both",
                Some(r),
                "",
                if ground == crate::rules::Ground::Treadmill {
                    "treadmill: the pelvis travels less than half of speed x stride time per stride"
                } else {
                    "overground: the pelvis travels at least half of speed x stride time per stride"
                },
            );
        }
    }
    let t = all_durations.mean();
    push(
        "cadence",
        "both",
        t.map(|t| 120.0 / t),
        "steps/min",
        &cadence_note,
    );
    push("stride_time", "both", t, "s", &stride_note);
    if let (Some(t), Some(&(_, note))) = (t, lengths.first()) {
        let l = lengths.iter().map(|x| x.0).sum::<f64>() / lengths.len() as f64;
        push("stride_length", "both", Some(l), "m", length_note(note));
        push("speed", "both", Some(l / t), "m/s", note);
    }
    if !seen.step_width() {
        // Where the step width would be (after the step length): why there is none.
        let at = out
            .iter()
            .position(|p| p.name == "step_length" && p.side == "both")
            .map_or(out.len(), |i| i + 1);
        out.insert(
            at,
            Parameter {
                name: "step_width",
                side: "both",
                value: None,
                unit: "m",
                range: None,
                note: seen.note().unwrap_or_default(),
            },
        );
    }
    out
}

/// The note of a stride length whose speed's note is `note`.
fn length_note(note: &'static str) -> &'static str {
    if note.starts_with("foot velocity") || note.starts_with("given") {
        FROM_SPEED
    } else {
        note
    }
}

/// The value of a parameter of `side`.
pub fn value(params: &[Parameter], name: &str, side: &str) -> Option<f64> {
    params
        .iter()
        .find(|p| p.name == name && p.side == side)
        .and_then(|p| p.value)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trial::{Frame, Limb};

    /// A trial of `frames` at `time`, nothing else.
    fn trial_of(time: Vec<f64>, frames: Vec<Frame>) -> Trial {
        Trial {
            label: "t".into(),
            source: "t".into(),
            time,
            frames,
            coordinates: None,
            translation: None,
            breaks: Vec::new(),
            seen: Seen::ALL,
            velocities: None,
        }
    }

    /// A stride along a direction 20° off x, the pelvis swaying 3 cm side to side and facing
    /// elsewhere: the feet give the direction of travel exactly, and the step is measured
    /// along it.
    #[test]
    fn the_feet_give_the_direction_of_travel() {
        let u = Vec3::new(20f64.to_radians().cos(), 0.0, -20f64.to_radians().sin());
        let n = Vec3::new(-u.z, 0.0, u.x);
        let (duration, frames) = (1.0, 100);
        let (oto, ohs, to) = (0.1, 0.5, 0.6);
        let pelvis = |t: f64| u * (1.2 * t) + n * (0.03 * (2.0 * std::f64::consts::PI * t).sin());
        // World positions of the forefeet: the right (this side) down from 0 to its toe off;
        // the left down until its toe off, then at its next contact from its heel strike.
        let right = u * 0.35 + n * 0.06;
        let left = |t: f64| {
            if t <= oto {
                u * (-0.25) - n * 0.06
            } else if t >= ohs {
                u * 0.95 - n * 0.06
            } else {
                u * (2.0 * t) + Vec3::new(0.0, 0.1, 0.0)
            }
        };
        let time: Vec<f64> = (0..=frames).map(|k| k as f64 / frames as f64).collect();
        let limb = |p: Vec3<f64>| Limb {
            heel: p - u * 0.2,
            forefoot: p,
            ..Limb::default()
        };
        let trial = trial_of(
            time.clone(),
            time.iter()
                .map(|&t| {
                    let swing = u * (1.4 * (t - to)) + Vec3::new(0.0, 0.1, 0.0);
                    let r = if t <= to { right } else { right + swing };
                    [limb(r - pelvis(t)), limb(left(t) - pelvis(t))]
                })
                .collect(),
        );
        let cycle = Cycle {
            side: 0,
            start: 0.0,
            duration,
            strike_frame: 0,
            samples: time.iter().enumerate().map(|(f, t)| (f, *t)).collect(),
            toe_off: Some(to),
            opposite_strike: Some(ohs),
            opposite_toe_off: Some(oto),
            span: (0, frames),
        };
        let d = stride_direction(&trial, &cycle).unwrap();
        assert!(Vec3::distance(d, u) < 1e-12, "{d:?}");
        // At the heel strike the right heel is 0.6 m ahead of the left and 0.12 m to its
        // right, whatever the pelvis faces.
        let facing = vec![Vec3::new(1.0, 0.0, 0.0); time.len()];
        let cycles = [vec![cycle], Vec::new()];
        let p = parameters(&[(&trial, &facing, &cycles, None)]);
        let length = value(&p, "step_length", "right").unwrap();
        let width = value(&p, "step_width", "right").unwrap();
        assert!((length - 0.6).abs() < 1e-12, "{length}");
        assert!((width - 0.12).abs() < 1e-12, "{width}");
    }

    /// A cycle without its toe offs (as `--cycle whole` can give), the pelvis facing 35° off
    /// the way the feet go (as crouch4's does): the lower foot gives the direction of travel,
    /// and the step is measured along it, not along the pelvis.
    #[test]
    fn without_events_the_lower_foot_gives_the_direction_of_travel() {
        let (len, width) = (0.6, 0.15);
        let frames = 50;
        let time: Vec<f64> = (0..=frames).map(|k| k as f64 / frames as f64).collect();
        // Relative to the pelvis: the right foot on the ground sliding back along x over the
        // first half, the left one 5 cm up; then the other way round.
        let limb = |x: f64, y: f64, z: f64| Limb {
            heel: Vec3::new(x - 0.2, y, z),
            forefoot: Vec3::new(x, y, z),
            ..Limb::default()
        };
        let trial = trial_of(
            time.clone(),
            time.iter()
                .map(|&t| {
                    let back = len * (0.5 - 2.0 * t.min(0.5));
                    let later = len * (0.5 - 2.0 * (t - 0.5).max(0.0));
                    let (ry, ly) = if t < 0.5 { (0.0, 0.05) } else { (0.05, 0.0) };
                    [
                        limb(back, ry, width / 2.0),
                        limb(if t < 0.5 { -back } else { later }, ly, -width / 2.0),
                    ]
                })
                .collect(),
        );
        let cycle = Cycle {
            side: 0,
            start: 0.0,
            duration: 1.0,
            strike_frame: 0,
            samples: time.iter().enumerate().map(|(f, t)| (f, *t)).collect(),
            toe_off: None,
            opposite_strike: None,
            opposite_toe_off: None,
            span: (0, frames),
        };
        assert!(stride_direction(&trial, &cycle).is_none());
        let d = lowest_foot_direction(&trial, &cycle).unwrap();
        assert!(Vec3::distance(d, Vec3::unit_x()) < 1e-12, "{d:?}");
        let off = 35f64.to_radians();
        let facing = vec![Vec3::new(off.cos(), 0.0, off.sin()); time.len()];
        let cycles = [vec![cycle], Vec::new()];
        let p = parameters(&[(&trial, &facing, &cycles, None)]);
        let length = value(&p, "step_length", "right").unwrap();
        let step_width = value(&p, "step_width", "right").unwrap();
        assert!((length - len).abs() < 1e-12, "{length}");
        assert!((step_width - width).abs() < 1e-12, "{step_width}");
    }

    /// Feet 0.6 m apart along the walk and 0.15 m across it at each heel strike, seen along a
    /// direction of progression turned 8° off the walk: each side's width moves by the step
    /// length times sin 8°, one up, one down; their mean is the width times cos 8°.
    #[test]
    fn a_heading_offset_cancels_in_the_mean_step_width() {
        let (len, width, off) = (0.6, 0.15, 8f64.to_radians());
        let heel = |x: f64, z: f64| Limb {
            heel: Vec3::new(x, 0.0, z),
            ..Limb::default()
        };
        // Frame 0: right heel strike (right ahead); frame 1: left heel strike (left ahead).
        let frames = vec![
            [heel(len / 2.0, width / 2.0), heel(-len / 2.0, -width / 2.0)],
            [heel(-len / 2.0, width / 2.0), heel(len / 2.0, -width / 2.0)],
        ];
        let trial = trial_of(vec![0.0, 0.5], frames);
        let forward = vec![Vec3::new(off.cos(), 0.0, off.sin()); 2];
        let cycle = |side: usize, frame: usize| Cycle {
            side,
            start: 0.0,
            duration: 1.0,
            strike_frame: frame,
            samples: Vec::new(),
            toe_off: None,
            opposite_strike: None,
            opposite_toe_off: None,
            span: (frame, frame),
        };
        let cycles = [vec![cycle(0, 0)], vec![cycle(1, 1)]];
        let p = parameters(&[(&trial, &forward, &cycles, None)]);
        let r = value(&p, "step_width", "right").unwrap();
        let l = value(&p, "step_width", "left").unwrap();
        let shift = len * off.sin();
        assert!((r - (width * off.cos() - shift).abs()).abs() < 1e-12, "{r}");
        assert!((l - (width * off.cos() + shift)).abs() < 1e-12, "{l}");
        let both = value(&p, "step_width", "both").unwrap();
        assert!((both - width * off.cos()).abs() < 1e-12, "{both}");
    }
}
