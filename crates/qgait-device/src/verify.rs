//! `qgait verify`: every `PoseFrame` recomputed from its echoed angles by the `f64` kernel, with
//! the model and segment lengths the hub used; error statistics per point and missing samples.
//! With the hub's velocities on (protocol.md 4.11), every `PoseVelocities` recomputed the same
//! way: the backward difference of the echoed angles of its pose frame and the one before, in
//! `f64`, then the `f64` kernel's forward velocities.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use qgait_kernel::metrics::distances;
use qgait_proto::{
    backward_difference, JointId, Message, ModelId, PoseFrame, PoseModels, PoseVelocities,
};

use qgait_model::points::point_names;

/// Max and mean of an error (metres).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ErrorStat {
    /// Largest error (infinite if the hub sent a non-finite value).
    pub max: f64,
    sum: f64,
    n: u64,
}

impl ErrorStat {
    fn add(&mut self, e: f64) {
        let e = if e.is_finite() { e } else { f64::INFINITY };
        self.max = self.max.max(e);
        self.sum += e;
        self.n += 1;
    }

    /// Mean error.
    pub fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum / self.n as f64
        }
    }
}

/// Names of the error rows: the 8 points, then the 3 distances.
pub fn error_names() -> Vec<String> {
    let mut names = point_names(false);
    names.extend(["knee-knee", "ankle-ankle", "toe-toe"].map(String::from));
    names
}

/// The result of verifying a set of frames.
#[derive(Debug, Clone, Default)]
pub struct Verification {
    /// Frames checked.
    pub frames: u64,
    /// Per point (distance between the hub's point and the f64 one), then per leg distance
    /// (absolute difference); [`error_names`] order.
    pub errors: Vec<ErrorStat>,
    /// The frame with the largest error: (seq, error in metres).
    pub worst: Option<(u32, f64)>,
    /// Sequence numbers expected but not seen (how many).
    pub missing: u64,
    /// The first (lowest) [`MISSING_LISTED`] of them, ascending.
    pub missing_first: Vec<u32>,
    /// Frames whose sequence number had been seen already.
    pub duplicates: u64,
    /// Frames by model.
    pub models: Vec<(ModelId, u64)>,
    /// Frames of an uploaded chain verified without the chain (each an infinite error).
    pub without_chain: u64,
    /// The model the frames must be of (the one `--model` names), if it is known: a frame of
    /// another model fails the verification (its points may all be right for the model it
    /// is of, but the hub did not compute what it was meant to).
    pub expected_model: Option<ModelId>,
    /// `PoseVelocities` checked (each against its pose frame and the one before it).
    pub velocity_frames: u64,
    /// Per point, the distance between the hub's velocity and the f64 one (m/s).
    pub velocity_errors: Vec<ErrorStat>,
    /// The velocities with the largest error: (seq, error in m/s).
    pub velocity_worst: Option<(u32, f64)>,
    /// `PoseVelocities` that do not follow their pose frame and the one before it (`seq − 1`,
    /// the same model) in the log: not recomputable, a failure.
    pub velocity_unmatched: u64,
    /// Pose frames that follow the one before by one `seq` and came without velocities, in a
    /// log with velocities (the hub sends none after a configuration takes effect: not a
    /// failure by itself).
    pub velocity_absent: u64,
    /// The tolerance on the velocities (m/s): [`VELOCITY_TOLERANCE`] unless set.
    pub velocity_tolerance: f64,
}

/// The tolerance on the hub's velocities against the host's `f64` ones: 1 mm/s.
pub const VELOCITY_TOLERANCE: f64 = 1e-3;

/// A pose frame's `seq`, model and echoed angles, as a sample's (`f64`).
type Posed = (u32, ModelId, [f64; JointId::COUNT]);

/// How many missing sequence numbers a [`Verification`] lists.
pub const MISSING_LISTED: usize = 10;

/// Most runs of consecutive sequence numbers a [`Verifier`] keeps apart (each run costs a few
/// tens of bytes): beyond it, the two lowest runs are joined and the gap between them is
/// counted as missing for good.
pub const MAX_RUNS: usize = 65_536;

/// Which sequence numbers must be there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Expected {
    /// Every number from the first seen to the last seen.
    FirstToLast,
    /// Exactly `first .. first + count` (what was sent).
    Range {
        /// First sequence number sent.
        first: u32,
        /// Samples sent.
        count: u32,
    },
}

/// Verification of frames one at a time, as they arrive (memory independent of their number).
///
/// Sequence numbers are kept as runs of consecutive numbers relative to the base (the first
/// expected one, or the first seen), so a clean log of any length holds one run and a damaged
/// one a run per gap. Frames may come in any order (the hub sends them in completion order)
/// and the result is the same as sorting them all, unless a log has more than [`MAX_RUNS`]
/// gaps: then the lowest gaps are counted as missing for good, and a frame arriving later in
/// one of them counts as a repeat instead of filling it.
pub struct Verifier<'m> {
    model: &'m PoseModels<f64>,
    expected: Expected,
    v: Verification,
    base: Option<u32>,
    /// Runs of seen sequence numbers (relative to `base`): start -> end, inclusive, disjoint and
    /// not adjacent.
    runs: BTreeMap<i64, i64>,
    /// Gaps between runs joined by the [`MAX_RUNS`] limit: how many numbers, and the lowest.
    joined_missing: u64,
    joined_first: Vec<i64>,
    /// The last pose frame and the one before it, for the velocities that follow the last.
    last: Option<Posed>,
    before: Option<Posed>,
    /// Whether the last pose frame follows the one before by one `seq`, and its velocities
    /// have not come yet.
    awaiting: bool,
}

impl<'m> Verifier<'m> {
    /// A verifier of frames computed with `model`.
    pub fn new(model: &'m PoseModels<f64>, expected: Expected) -> Self {
        Verifier {
            model,
            expected,
            v: Verification {
                errors: vec![ErrorStat::default(); 11],
                velocity_tolerance: VELOCITY_TOLERANCE,
                ..Verification::default()
            },
            base: match expected {
                Expected::Range { first, .. } => Some(first),
                Expected::FirstToLast => None,
            },
            runs: BTreeMap::new(),
            joined_missing: 0,
            joined_first: Vec::new(),
            last: None,
            before: None,
            awaiting: false,
        }
    }

    /// Checks the velocities of the last pose frame: recomputed in `f64` from its echoed
    /// angles and those of the frame before it (`seq − 1`).
    pub fn add_velocities(&mut self, velocities: &PoseVelocities) {
        let v = &mut self.v;
        if v.velocity_errors.is_empty() {
            v.velocity_errors = vec![ErrorStat::default(); 8];
        }
        let want = match (&self.last, &self.before) {
            (Some((seq, model, now)), Some((seq_before, model_before, before)))
                if *seq == velocities.seq
                    && seq_before.wrapping_add(1) == *seq
                    && model == model_before =>
            {
                let rates = backward_difference(before, now, f64::from(velocities.dt_us) * 1e-6);
                self.model.velocities(*model, now, &rates)
            }
            _ => None,
        };
        let Some(want) = want.filter(|_| self.awaiting) else {
            v.velocity_unmatched += 1;
            return;
        };
        self.awaiting = false;
        v.velocity_frames += 1;
        let mut worst = 0.0f64;
        for (i, (got, want)) in velocities.velocities.iter().zip(want).enumerate() {
            let d = (0..3)
                .map(|k| (f64::from(got[k]) - want.to_array()[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            v.velocity_errors[i].add(d);
            worst = worst.max(if d.is_finite() { d } else { f64::INFINITY });
        }
        if v.velocity_worst.is_none_or(|(_, w)| worst > w) {
            v.velocity_worst = Some((velocities.seq, worst));
        }
    }

    /// Checks what a hub sent, message by message in the order it sent them: a pose frame, or
    /// the velocities that follow one. Any other message is not the verifier's.
    pub fn add_message(&mut self, message: &Message) {
        match message {
            Message::PoseFrame(frame) => self.add(frame),
            Message::PoseVelocities(velocities) => self.add_velocities(velocities),
            _ => {}
        }
    }

    /// Records a pose frame as the last one, for the velocities that may follow.
    fn posed(&mut self, frame: &PoseFrame) {
        if self.awaiting {
            self.v.velocity_absent += 1;
        }
        self.before = self.last.take();
        self.last = Some((frame.seq, frame.model, frame.joint_angles()));
        self.awaiting = self
            .before
            .as_ref()
            .is_some_and(|(seq, _, _)| seq.wrapping_add(1) == frame.seq);
    }

    /// Frames checked so far.
    pub fn frames(&self) -> u64 {
        self.v.frames
    }

    /// Runs of consecutive sequence numbers held (1 for a log without gaps).
    #[cfg(test)]
    fn runs(&self) -> usize {
        self.runs.len()
    }

    /// Checks one frame.
    pub fn add(&mut self, frame: &PoseFrame) {
        self.posed(frame);
        let v = &mut self.v;
        v.frames += 1;
        match v.models.iter_mut().find(|(m, _)| *m == frame.model) {
            Some((_, n)) => *n += 1,
            None => v.models.push((frame.model, 1)),
        }
        // A chain's frame with no chain to recompute it with: every point unverified.
        let Some(pose) = self.model.frame_pose(frame) else {
            v.without_chain += 1;
            for e in &mut v.errors {
                e.add(f64::INFINITY);
            }
            if v.worst.is_none_or(|(_, w)| w < f64::INFINITY) {
                v.worst = Some((frame.seq, f64::INFINITY));
            }
            self.see_seq(frame.seq);
            return;
        };
        let mut worst = 0.0f64;
        for (i, (got, want)) in frame.points.iter().zip(pose.points()).enumerate() {
            let d = (0..3)
                .map(|k| (f64::from(got[k]) - want.to_array()[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            v.errors[i].add(d);
            worst = worst.max(if d.is_finite() { d } else { f64::INFINITY });
        }
        for (i, (got, want)) in frame
            .distances
            .iter()
            .zip(distances(&pose).to_array())
            .enumerate()
        {
            let d = (f64::from(*got) - want).abs();
            v.errors[8 + i].add(d);
            worst = worst.max(if d.is_finite() { d } else { f64::INFINITY });
        }
        if v.worst.is_none_or(|(_, w)| worst > w) {
            v.worst = Some((frame.seq, worst));
        }
        self.see_seq(frame.seq);
    }

    /// Records the sequence number `seq`.
    fn see_seq(&mut self, seq: u32) {
        // Relative to the first one, so that a log crossing 2^32 still works.
        let base = *self.base.get_or_insert(seq);
        self.see(i64::from(seq.wrapping_sub(base) as i32));
    }

    /// Records the relative sequence number `r`.
    fn see(&mut self, r: i64) {
        let below = self.runs.range(..=r).next_back().map(|(&s, &e)| (s, e));
        if below.is_some_and(|(_, e)| e >= r) {
            self.v.duplicates += 1;
            return;
        }
        let above = self.runs.get(&(r + 1)).copied();
        match (below.filter(|&(_, e)| e + 1 == r), above) {
            (Some((s, _)), Some(e2)) => {
                self.runs.remove(&(r + 1));
                self.runs.insert(s, e2);
            }
            (Some((s, _)), None) => {
                self.runs.insert(s, r);
            }
            (None, Some(e2)) => {
                self.runs.remove(&(r + 1));
                self.runs.insert(r, e2);
            }
            (None, None) => {
                self.runs.insert(r, r);
            }
        }
        if self.runs.len() > MAX_RUNS {
            self.join_lowest();
        }
    }

    /// The numbers expected: `lo..=hi` (relative); `None` before any frame of a first-to-last
    /// check.
    fn bounds(&self) -> Option<(i64, i64)> {
        match self.expected {
            Expected::Range { count, .. } => Some((0, i64::from(count) - 1)),
            Expected::FirstToLast => {
                Some((*self.runs.keys().next()?, *self.runs.values().next_back()?))
            }
        }
    }

    /// The missing numbers in `a..=b` clipped to the expected range: how many, and the lowest
    /// (at most [`MISSING_LISTED`]) appended to `first`.
    fn gap(&self, a: i64, b: i64, first: &mut Vec<i64>) -> u64 {
        let (a, b) = match (self.expected, self.bounds()) {
            (Expected::Range { .. }, Some((lo, hi))) => (a.max(lo), b.min(hi)),
            _ => (a, b),
        };
        if a > b {
            return 0;
        }
        first.extend((a..=b).take(MISSING_LISTED));
        if first.len() > MISSING_LISTED {
            first.sort_unstable();
            first.truncate(MISSING_LISTED);
        }
        (b - a + 1) as u64
    }

    /// Joins the two lowest runs, counting the gap between them as missing.
    fn join_lowest(&mut self) {
        let mut it = self.runs.iter();
        let (Some((&s1, &e1)), Some((&s2, &e2))) = (it.next(), it.next()) else {
            return;
        };
        let mut first = std::mem::take(&mut self.joined_first);
        self.joined_missing += self.gap(e1 + 1, s2 - 1, &mut first);
        self.joined_first = first;
        self.runs.remove(&s2);
        self.runs.insert(s1, e2);
    }

    /// The result.
    pub fn finish(mut self) -> Verification {
        if self.v.velocity_frames == 0 {
            self.v.velocity_absent = 0;
        } else if self.awaiting {
            self.v.velocity_absent += 1;
        }
        let Some((lo, hi)) = self.bounds() else {
            return self.v;
        };
        let mut first = std::mem::take(&mut self.joined_first);
        let mut missing = self.joined_missing;
        let mut next = lo;
        for (&s, &e) in &self.runs {
            if s > hi {
                break;
            }
            if s > next {
                missing += self.gap(next, s - 1, &mut first);
            }
            next = next.max(e + 1);
        }
        missing += self.gap(next, hi, &mut first);
        first.sort_unstable();
        first.truncate(MISSING_LISTED);
        let base = self.base.unwrap_or(0);
        self.v.missing = missing;
        self.v.missing_first = first
            .into_iter()
            .map(|r| base.wrapping_add(r as u32))
            .collect();
        self.v
    }
}

impl Verification {
    /// Checks `frames` against `model` (a [`Verifier`] fed every frame).
    pub fn run<'a>(
        model: &PoseModels<f64>,
        frames: impl IntoIterator<Item = &'a PoseFrame>,
        expected: Expected,
    ) -> Verification {
        let mut v = Verifier::new(model, expected);
        frames.into_iter().for_each(|f| v.add(f));
        v.finish()
    }

    /// The largest error over all points and distances (metres).
    pub fn max_error(&self) -> f64 {
        self.errors.iter().map(|e| e.max).fold(0.0, f64::max)
    }

    /// Whether every error is within `tolerance_m`, nothing is missing, no sequence number
    /// came twice, there was a frame and every frame is of the
    /// [`expected_model`](Self::expected_model). (A hub sends each sample once: a number that
    /// comes again is a restart, or two sessions in one log, whose gaps one sequence cannot
    /// tell apart.)
    pub fn passed(&self, tolerance_m: f64) -> bool {
        self.frames > 0
            && self.max_error() <= tolerance_m
            && self.missing == 0
            && self.duplicates == 0
            && self.of_other_models() == 0
            && self.velocity_max_error() <= self.velocity_tolerance
            && self.velocity_unmatched == 0
    }

    /// The largest error of the velocities (m/s; 0 without any).
    pub fn velocity_max_error(&self) -> f64 {
        self.velocity_errors
            .iter()
            .map(|e| e.max)
            .fold(0.0, f64::max)
    }

    /// The velocities' lines of the report (none in a log without velocities).
    fn velocity_report(&self, s: &mut String) {
        if self.velocity_frames == 0 && self.velocity_unmatched == 0 {
            return;
        }
        let _ = writeln!(
            s,
            "{} velocity frames checked against the f64 kernel (the same backward difference of the echoed angles)",
            self.velocity_frames
        );
        error_table(s, ("velocity", "mm/s", 1e3, 6), &self.velocity_errors);
        if let Some((seq, w)) = self.velocity_worst {
            let _ = writeln!(
                s,
                "largest velocity error {:.6} mm/s (seq {seq}); tolerance {} mm/s",
                w * 1e3,
                self.velocity_tolerance * 1e3
            );
        }
        if self.velocity_absent > 0 {
            let _ = writeln!(
                s,
                "pose frames following the one before without velocities: {} (none after a configuration takes effect)",
                self.velocity_absent
            );
        }
        if self.velocity_unmatched > 0 {
            let _ = writeln!(
                s,
                "velocity frames not right after their pose frame and the one before it: {} (cannot be recomputed)",
                self.velocity_unmatched
            );
        }
    }

    /// Frames not of the [`expected_model`](Self::expected_model).
    pub fn of_other_models(&self) -> u64 {
        let other = |m: &ModelId| self.expected_model.is_some_and(|e| e != *m);
        self.models
            .iter()
            .filter(|(m, _)| other(m))
            .map(|(_, n)| n)
            .sum()
    }

    /// The report: a table of max and mean error per point (µm), then the verdict lines.
    pub fn report(&self, tolerance_m: f64) -> String {
        let mut s = String::new();
        let models: Vec<String> = self
            .models
            .iter()
            .map(|(m, n)| format!("{n} {m}"))
            .collect();
        let _ = writeln!(
            s,
            "{} frames ({}) checked against the f64 kernel",
            self.frames,
            models.join(", ")
        );
        if self.frames == 0 {
            let _ = writeln!(s, "no pose frame to check: the hub sent none");
        }
        if self.without_chain > 0 {
            let _ = writeln!(
                s,
                "{} frame{} of an uploaded chain (model `chain`) cannot be recomputed without \
                 it: give the chain the hub computed with, --model CHAIN.toml or its .osim",
                self.without_chain,
                if self.without_chain == 1 { "" } else { "s" }
            );
        }
        error_table(&mut s, ("point", "µm", 1e6, 4), &self.errors);
        if let Some((seq, w)) = self.worst {
            let _ = writeln!(
                s,
                "largest error {:.4} µm (seq {seq}); tolerance {} µm",
                w * 1e6,
                tolerance_m * 1e6
            );
        }
        let _ = writeln!(
            s,
            "missing samples: {}{}",
            self.missing,
            preview(&self.missing_first, self.missing)
        );
        if self.duplicates > 0 {
            let _ = writeln!(
                s,
                "repeated sequence numbers: {} (a hub sends each sample once: a restart, or two \
                 sessions in one log, whose gaps cannot be told apart; verify each session's \
                 log on its own)",
                self.duplicates
            );
        }
        if let (Some(model), n @ 1..) = (self.expected_model, self.of_other_models()) {
            let _ = writeln!(
                s,
                "frames of another model than `{model}`, the one --model names: {n}{}",
                if model == ModelId::Chain {
                    " (a hub built without the `chain` feature keeps its model and counts a \
                     chain's parts as malformed: firmware built with --features chain takes them)"
                } else {
                    ""
                }
            );
        }
        self.velocity_report(&mut s);
        let verdict = if self.passed(tolerance_m) {
            "ok"
        } else {
            "FAILED"
        };
        let _ = write!(s, "verify: {verdict}");
        s
    }
}

/// A table of max and mean error per row of [`error_names`]: `(first column's title, unit,
/// the unit per SI unit, decimals)`.
fn error_table(
    s: &mut String,
    (title, unit, scale, decimals): (&str, &str, f64, usize),
    errors: &[ErrorStat],
) {
    let (max, mean) = (format!("max ({unit})"), format!("mean ({unit})"));
    let _ = writeln!(s, "{title:<12} {max:>12} {mean:>12}");
    for (name, e) in error_names().iter().zip(errors) {
        let _ = writeln!(
            s,
            "{:<12} {:>12.decimals$} {:>12.decimals$}",
            name,
            e.max * scale,
            e.mean() * scale
        );
    }
}

/// ` (3, 7, 9, ...)` for the first of `total` numbers (none when there are none).
pub fn preview(first: &[u32], total: u64) -> String {
    if first.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = first.iter().map(u32::to_string).collect();
    format!(
        " ({}{})",
        shown.join(", "),
        if total > first.len() as u64 {
            ", ..."
        } else {
            ""
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(model: &PoseModels<f64>, m: ModelId, seq: u32) -> PoseFrame {
        let mut angles = heapless::Vec::new();
        for (i, _) in m.required_joints().iter().enumerate() {
            angles
                .push(0.05 * (i as f32 + seq as f32 * 0.3).sin())
                .unwrap();
        }
        let mut f = PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: m,
            angles,
            points: [[0.0; 3]; 8],
            distances: [0.0; 3],
            flags: 0,
        };
        let pose = model.frame_pose(&f).expect("a hub's own model");
        f.points = pose.points().map(|p| p.to_array().map(|x| x as f32));
        f.distances = distances(&pose).to_array().map(|x| x as f32);
        f
    }

    /// The hub's velocities of `frame` after `before`, recomputed in `f32` as a hub does.
    fn velocities(before: &PoseFrame, frame: &PoseFrame, dt_us: u32) -> PoseVelocities {
        let f32s = PoseModels::<f32>::defaults();
        let (a, b) = (before.joint_angles::<f32>(), frame.joint_angles::<f32>());
        let rates = backward_difference(&a, &b, dt_us as f32 * 1e-6);
        let v = f32s.velocities(frame.model, &b, &rates).expect("built in");
        PoseVelocities {
            seq: frame.seq,
            dt_us,
            velocities: v.map(|p| p.to_array()),
        }
    }

    #[test]
    fn velocities_are_checked_against_the_f64_difference() {
        let model = PoseModels::defaults();
        for m in [ModelId::Hak, ModelId::Phak, ModelId::Gait2392] {
            let frames: Vec<PoseFrame> = (0..6).map(|s| frame(&model, m, s)).collect();
            let mut v = Verifier::new(&model, Expected::FirstToLast);
            v.add(&frames[0]);
            for w in frames.windows(2) {
                v.add(&w[1]);
                v.add_velocities(&velocities(&w[0], &w[1], 10_000));
            }
            let r = v.finish();
            let report = r.report(10e-6);
            assert!(r.passed(10e-6), "{report}");
            assert_eq!((r.velocity_frames, r.velocity_absent), (5, 0));
            assert!(r.velocity_max_error() < 1e-5, "{report}");
            assert!(report.contains("5 velocity frames checked"), "{report}");
            // A wrong velocity fails; one whose frame before is not in the log is unmatched.
            let mut v = Verifier::new(&model, Expected::FirstToLast);
            v.add(&frames[0]);
            v.add(&frames[1]);
            let mut wrong = velocities(&frames[0], &frames[1], 10_000);
            wrong.velocities[3][0] += 2e-3;
            v.add_velocities(&wrong);
            v.add(&frames[3]);
            v.add_velocities(&velocities(&frames[2], &frames[3], 10_000));
            let r = v.finish();
            assert!(!r.passed(10e-6));
            assert!((r.velocity_max_error() - 2e-3).abs() < 1e-5);
            assert_eq!((r.velocity_frames, r.velocity_unmatched), (1, 1));
        }
    }

    #[test]
    fn chain_frames_without_the_chain_fail_saying_what_to_give() {
        let chain = qgait_kernel::models::fixtures::walker_chain();
        let with_chain = PoseModels::defaults().with_chain(chain);
        let frames: Vec<PoseFrame> = (0..3)
            .map(|s| frame(&with_chain, ModelId::Chain, s))
            .collect();
        let v = Verification::run(&with_chain, &frames, Expected::FirstToLast);
        assert!(v.passed(1e-6) && v.without_chain == 0, "{}", v.report(1e-6));
        let v = Verification::run(&PoseModels::defaults(), &frames, Expected::FirstToLast);
        assert_eq!(v.without_chain, 3);
        let report = v.report(10e-6);
        assert!(
            report.contains("3 frames of an uploaded chain")
                && report.contains("--model CHAIN.toml")
                && report.ends_with("verify: FAILED"),
            "{report}"
        );
    }

    #[test]
    fn exact_frames_pass_and_a_moved_point_or_a_gap_fails() {
        let model = PoseModels::defaults();
        let mut frames: Vec<PoseFrame> = (0..5).map(|s| frame(&model, ModelId::Phak, s)).collect();
        frames.push(frame(&model, ModelId::Gait2392, 5));
        frames.push(frame(&model, ModelId::Hak, 6));
        let v = Verification::run(&model, &frames, Expected::FirstToLast);
        assert!(v.passed(1e-6), "{}", v.report(1e-6));
        assert!(v.max_error() < 1e-7);
        frames[2].points[3][1] += 20e-6;
        frames.remove(4);
        let v = Verification::run(&model, &frames, Expected::FirstToLast);
        assert!(!v.passed(10e-6));
        assert_eq!((v.missing, v.missing_first.as_slice()), (1, &[4][..]));
        assert_eq!(v.worst.unwrap().0, 2);
        assert!(
            (v.errors[3].max - 20e-6).abs() < 1e-7,
            "{}",
            v.errors[3].max
        );
        let report = v.report(10e-6);
        assert!(
            report.contains("missing samples: 1 (4)") && report.ends_with("verify: FAILED"),
            "{report}"
        );
        let v = Verification::run(&model, &frames[..3], Expected::Range { first: 0, count: 5 });
        assert_eq!((v.missing, v.missing_first.as_slice()), (2, &[3, 4][..]));
    }

    #[test]
    fn a_sequence_number_that_comes_again_fails() {
        let model = PoseModels::defaults();
        let f = |s| frame(&model, ModelId::Phak, s);
        // A second session from 0 whose gap (3) the first session's numbers hide.
        let mut frames: Vec<PoseFrame> = (0..10).map(f).collect();
        frames.extend([0, 1, 2, 4, 5].map(f));
        let v = Verification::run(&model, &frames, Expected::FirstToLast);
        assert_eq!((v.missing, v.duplicates), (0, 5));
        assert!(!v.passed(1e-6));
        let report = v.report(1e-6);
        assert!(
            report.contains("repeated sequence numbers: 5 (a hub sends each sample once")
                && report.ends_with("verify: FAILED"),
            "{report}"
        );
    }

    #[test]
    fn frames_of_another_model_than_the_expected_one_fail() {
        let model = PoseModels::defaults();
        let frames: Vec<PoseFrame> = (0..4).map(|s| frame(&model, ModelId::Phak, s)).collect();
        let mut v = Verification::run(&model, &frames, Expected::FirstToLast);
        assert!(v.passed(1e-6));
        v.expected_model = Some(ModelId::Phak);
        assert!(v.passed(1e-6) && v.of_other_models() == 0);
        v.expected_model = Some(ModelId::Hak);
        assert_eq!(v.of_other_models(), 4);
        let report = v.report(1e-6);
        assert!(
            report.contains("frames of another model than `hak`, the one --model names: 4\n")
                && report.ends_with("verify: FAILED"),
            "{report}"
        );
        v.expected_model = Some(ModelId::Chain);
        assert!(v.report(1e-6).contains("--features chain"));
    }

    #[test]
    fn hak_hangs_the_legs_at_the_hips_and_nan_fails() {
        let model = PoseModels::defaults();
        let mut f = frame(&model, ModelId::Hak, 1);
        assert!((f.points[0][2] - 0.0835).abs() < 1e-7, "{:?}", f.points[0]);
        f.points[7][0] = f32::NAN;
        let v = Verification::run(&model, [&f], Expected::FirstToLast);
        assert_eq!(v.max_error(), f64::INFINITY);
        assert!(!v.passed(1.0));
    }

    /// What the verification of sequence numbers was before it streamed: all of them sorted.
    fn sorted_reference(seqs: &[u32], expected: Expected) -> (u64, Vec<u32>, u64) {
        let base = match expected {
            Expected::Range { first, .. } => first,
            Expected::FirstToLast => seqs.first().copied().unwrap_or(0),
        };
        let mut rel: Vec<i64> = seqs
            .iter()
            .map(|s| i64::from(s.wrapping_sub(base) as i32))
            .collect();
        rel.sort_unstable();
        let before = rel.len();
        rel.dedup();
        let duplicates = (before - rel.len()) as u64;
        let (lo, hi) = match expected {
            Expected::Range { count, .. } => (0, i64::from(count) - 1),
            Expected::FirstToLast => (
                rel.first().copied().unwrap_or(0),
                rel.last().copied().unwrap_or(-1),
            ),
        };
        let missing: Vec<u32> = (lo..=hi)
            .filter(|r| rel.binary_search(r).is_err())
            .map(|r| base.wrapping_add(r as u32))
            .collect();
        let first = missing.iter().take(MISSING_LISTED).copied().collect();
        (missing.len() as u64, first, duplicates)
    }

    fn seq_check(seqs: &[u32], expected: Expected) -> Verification {
        let model = PoseModels::defaults();
        let mut v = Verifier::new(&model, expected);
        seqs.iter().for_each(|&s| v.see_seq(s));
        v.finish()
    }

    #[test]
    fn streamed_sequence_check_equals_the_sorted_one_in_any_order() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        for case in 0..400 {
            let start = [0u32, 1000, u32::MAX - 50][case % 3];
            let len = 1 + next(300) as u32;
            // Completion order with gaps, repeats, and now and then a far jump (a node reboot).
            let mut seqs = Vec::new();
            for i in 0..len {
                match next(20) {
                    0..=2 => {}
                    3 => seqs.extend([start.wrapping_add(i); 2]),
                    4 => seqs.push(start.wrapping_add(i).wrapping_sub(next(5000) as u32)),
                    _ => seqs.push(start.wrapping_add(i)),
                }
            }
            for i in (1..seqs.len()).rev() {
                if next(4) == 0 {
                    let j = i - next(i.min(8) as u64 + 1) as usize;
                    seqs.swap(i, j);
                }
            }
            for expected in [
                Expected::FirstToLast,
                Expected::Range {
                    first: start,
                    count: len + next(3) as u32,
                },
            ] {
                let v = seq_check(&seqs, expected);
                assert_eq!(
                    (v.missing, v.missing_first.clone(), v.duplicates),
                    sorted_reference(&seqs, expected),
                    "case {case} {expected:?}: {seqs:?}"
                );
            }
        }
        let v = seq_check(&[], Expected::FirstToLast);
        assert_eq!((v.missing, v.duplicates), (0, 0));
    }

    #[test]
    fn memory_holds_a_run_per_gap_up_to_a_bound_and_counts_stay_exact_in_order() {
        let model = PoseModels::defaults();
        let mut v = Verifier::new(&model, Expected::FirstToLast);
        for s in 0..1_000_000u32 {
            v.see_seq(s);
        }
        assert_eq!(v.runs(), 1, "a clean log is one run");
        // Every other number missing: far more gaps than MAX_RUNS.
        let n = 3 * MAX_RUNS as u32;
        let mut v = Verifier::new(
            &model,
            Expected::Range {
                first: 0,
                count: 2 * n,
            },
        );
        for s in (0..2 * n).step_by(2) {
            v.see_seq(s);
            assert!(v.runs() <= MAX_RUNS);
        }
        let r = v.finish();
        assert_eq!(r.missing, u64::from(n));
        assert_eq!(
            r.missing_first,
            (0..10).map(|i| 2 * i + 1).collect::<Vec<_>>()
        );
        assert_eq!(r.duplicates, 0);
    }
}
