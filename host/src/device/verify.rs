//! `qgait verify`: every `PoseFrame` recomputed from its echoed angles by the `f64` kernel, with
//! the model and segment lengths the hub used; error statistics per point and missing samples.

use std::fmt::Write as _;

use qgait_kernel::anthropometry::Anthropometry;
use qgait_kernel::metrics::distances;
use qgait_kernel::models::{Phak, PhakAngles};
use qgait_kernel::{BilateralPose, Gait2392, Gait2392Geometry};
use qgait_proto::{ModelId, PoseFrame};

use crate::model_spec::point_names;

/// What the hub computes each model with (its configuration).
pub struct DeviceModel {
    phak: Phak<f64>,
    gait2392: Gait2392<f64>,
}

impl DeviceModel {
    /// HAK and PHAK with `anthropometry`, gait2392 with `geometry` (the hub's defaults are
    /// gait2392's lengths and the generic model).
    pub fn new(
        anthropometry: &Anthropometry<f64>,
        geometry: &Gait2392Geometry,
    ) -> Result<Self, String> {
        Ok(DeviceModel {
            phak: Phak::new(anthropometry)
                .map_err(|e| format!("segment lengths rejected by the kernel: {e}"))?,
            gait2392: Gait2392::new(geometry)
                .map_err(|e| format!("gait2392 model rejected by the kernel: {e}"))?,
        })
    }

    /// The hub's defaults: gait2392 lengths for HAK/PHAK, the generic gait2392.
    pub fn defaults() -> Self {
        Self::new(&Anthropometry::gait2392(), &Gait2392Geometry::generic())
            .expect("the kernel accepts its own defaults")
    }

    /// The pose the hub should have sent for `frame`'s angles, in `f64`. HAK is the kernel's
    /// [`Phak::fk_hak`], as on the hub and in `qgait fk --model hak`: the legs hung at the hips
    /// of a level, forward-facing pelvis.
    pub fn pose(&self, frame: &PoseFrame) -> BilateralPose<f64> {
        let a: Vec<f64> = frame.angles.iter().map(|&x| f64::from(x)).collect();
        match frame.model {
            ModelId::Phak => self
                .phak
                .fk(&PhakAngles::from_array(core::array::from_fn(|i| a[i]))),
            // HAK's six angles are PHAK's after the two pelvis ones.
            ModelId::Hak => self
                .phak
                .fk_hak(&PhakAngles::from_array(core::array::from_fn(|i| {
                    if i < 2 {
                        0.0
                    } else {
                        a[i - 2]
                    }
                }))),
            ModelId::Gait2392 => self
                .gait2392
                .fk(&core::array::from_fn(|i| a[i]))
                .bilateral(),
        }
    }
}

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
    /// Sequence numbers expected but not seen.
    pub missing: Vec<u32>,
    /// Frames whose sequence number had been seen already.
    pub duplicates: u64,
    /// Frames by model.
    pub models: Vec<(ModelId, u64)>,
}

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

impl Verification {
    /// Checks `frames` against `model`.
    pub fn run<'a>(
        model: &DeviceModel,
        frames: impl IntoIterator<Item = &'a PoseFrame>,
        expected: Expected,
    ) -> Verification {
        let mut v = Verification {
            errors: vec![ErrorStat::default(); 11],
            ..Verification::default()
        };
        let mut seqs = Vec::new();
        for frame in frames {
            v.frames += 1;
            seqs.push(frame.seq);
            match v.models.iter_mut().find(|(m, _)| *m == frame.model) {
                Some((_, n)) => *n += 1,
                None => v.models.push((frame.model, 1)),
            }
            let pose = model.pose(frame);
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
        }
        // Sequence numbers relative to the first one, so that a log crossing 2^32 still works.
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
        v.duplicates = (before - rel.len()) as u64;
        let (lo, hi) = match expected {
            Expected::Range { count, .. } => (0, i64::from(count) - 1),
            Expected::FirstToLast => (
                rel.first().copied().unwrap_or(0),
                rel.last().copied().unwrap_or(-1),
            ),
        };
        let mut next = rel.iter().peekable();
        for r in lo..=hi {
            while next.next_if(|&&x| x < r).is_some() {}
            if next.next_if_eq(&&r).is_none() {
                v.missing.push(base.wrapping_add(r as u32));
            }
        }
        v
    }

    /// The largest error over all points and distances (metres).
    pub fn max_error(&self) -> f64 {
        self.errors.iter().map(|e| e.max).fold(0.0, f64::max)
    }

    /// Whether every error is within `tolerance_m`, nothing is missing and there was a frame.
    pub fn passed(&self, tolerance_m: f64) -> bool {
        self.frames > 0 && self.max_error() <= tolerance_m && self.missing.is_empty()
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
        let _ = writeln!(s, "{:<12} {:>12} {:>12}", "point", "max (µm)", "mean (µm)");
        for (name, e) in error_names().iter().zip(&self.errors) {
            let _ = writeln!(
                s,
                "{:<12} {:>12.4} {:>12.4}",
                name,
                e.max * 1e6,
                e.mean() * 1e6
            );
        }
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
            self.missing.len(),
            preview(&self.missing)
        );
        if self.duplicates > 0 {
            let _ = writeln!(s, "repeated sequence numbers: {}", self.duplicates);
        }
        let verdict = if self.passed(tolerance_m) {
            "ok"
        } else {
            "FAILED"
        };
        let _ = write!(s, "verify: {verdict}");
        s
    }
}

/// ` (3, 7, 9, ...)` for a non-empty list.
fn preview(seqs: &[u32]) -> String {
    if seqs.is_empty() {
        return String::new();
    }
    let shown: Vec<String> = seqs.iter().take(10).map(u32::to_string).collect();
    format!(
        " ({}{})",
        shown.join(", "),
        if seqs.len() > 10 { ", ..." } else { "" }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(model: &DeviceModel, m: ModelId, seq: u32) -> PoseFrame {
        let mut angles = heapless::Vec::new();
        for (i, _) in m.required_joints().iter().enumerate() {
            angles
                .push(0.05 * (i as f32 + seq as f32 * 0.3).sin())
                .unwrap();
        }
        let mut f = PoseFrame {
            seq,
            model: m,
            angles,
            points: [[0.0; 3]; 8],
            distances: [0.0; 3],
            flags: 0,
        };
        let pose = model.pose(&f);
        f.points = pose.points().map(|p| p.to_array().map(|x| x as f32));
        f.distances = distances(&pose).to_array().map(|x| x as f32);
        f
    }

    #[test]
    fn exact_frames_pass_and_a_moved_point_or_a_gap_fails() {
        let model = DeviceModel::defaults();
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
        assert_eq!(v.missing, [4]);
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
        assert_eq!(v.missing, [3, 4]);
    }

    #[test]
    fn hak_hangs_the_legs_at_the_hips_and_nan_fails() {
        let model = DeviceModel::defaults();
        let mut f = frame(&model, ModelId::Hak, 1);
        assert!((f.points[0][2] - 0.0835).abs() < 1e-7, "{:?}", f.points[0]);
        f.points[7][0] = f32::NAN;
        let v = Verification::run(&model, [&f], Expected::FirstToLast);
        assert_eq!(v.max_error(), f64::INFINITY);
        assert!(!v.passed(1.0));
    }
}
