//! Walking bouts: a free-living recording is walking between standing, sitting and lying.
//!
//! A bout is a run of strides (both sides' cycles, [`crate::cycles`]) in which each stride
//! starts at most [`MAX_PAUSE`] after the bout so far has ended, holding at least
//! [`MIN_STRIDES`] strides of one side. This is the definition of the wearable-gait literature
//! (the Mobilise-D consortium's: strides separated by at most 3 s belong to one bout, Kluge et
//! al. 2021; Micó-Amigo et al. 2023), with three strides rather than two as the least bout, so
//! that a bout's cadence is a mean over at least three cycles. Strides left out of the analysis
//! (turning, a missed event, a gap in the recording) count as pauses, which is how a long turn
//! splits a bout.

use crate::Walk;

/// The longest pause (s) between the end of a bout's strides and the next stride's start.
pub const MAX_PAUSE: f64 = 3.0;

/// The fewest strides of one side in a bout.
pub const MIN_STRIDES: usize = 3;

/// One walking bout.
#[derive(Clone, Debug, PartialEq)]
pub struct Bout {
    /// The first stride's heel strike (s).
    pub start: f64,
    /// The last stride's end: its next heel strike (s).
    pub end: f64,
    /// Strides of the right and the left side.
    pub strides: [usize; 2],
    /// Steps per minute: 120 over the bout's mean stride time.
    pub cadence: f64,
    /// Median of the speeds measured over the bout's strides ([`crate::rules::Gait::local_speeds`]), else
    /// the recording's speed; `None` without a speed.
    pub speed: Option<f64>,
}

/// The bouts of a recording, in time order.
pub fn bouts(walk: &Walk) -> Vec<Bout> {
    let strides: Vec<(f64, f64, usize)> = (0..2)
        .flat_map(|s| {
            walk.cycles[s]
                .iter()
                .map(move |c| (c.start, c.start + c.duration, s))
        })
        .collect();
    let (local, speed) = match &walk.gait {
        Some(g) => (g.local_speeds.as_slice(), Some(g.speed)),
        None => (&[][..], None),
    };
    of(strides, local, speed)
}

/// The bouts of the strides `(start, end, side)` of a recording (in any order), in time order;
/// `local_speeds` are the speeds measured over spans of it ([`Gait::local_speeds`]), `speed`
/// the recording's (`None`: no speed, the rules did not run).
///
/// [`Gait::local_speeds`]: crate::rules::Gait::local_speeds
pub fn of(
    mut strides: Vec<(f64, f64, usize)>,
    local_speeds: &[(f64, f64, f64)],
    speed: Option<f64>,
) -> Vec<Bout> {
    strides.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut finder = Finder::default();
    finder.speeds(local_speeds.iter().copied());
    for (start, end, side) in strides {
        finder.stride(start, end, side);
    }
    finder.finish(speed)
}

/// The bouts of strides that come in the order of their starts, one at a time: what [`of`]
/// finds, holding only the bout being formed and the local speeds not before it.
#[derive(Clone, Debug, Default)]
pub struct Finder {
    /// The bout being formed: start, end (the latest stride end), strides per side, the sum
    /// of the strides' durations and their number.
    open: Option<(f64, f64, [usize; 2], f64, usize)>,
    /// Local speeds that may still fall in a bout.
    local: Vec<(f64, f64, f64)>,
    /// Bouts found, each with the median of its local speeds.
    found: Vec<(Bout, Option<f64>)>,
}

impl Finder {
    /// Local speeds `(start, end, speed)` measured over spans of the recording: those that
    /// start where a stride to come can still start.
    pub fn speeds(&mut self, speeds: impl IntoIterator<Item = (f64, f64, f64)>) {
        self.local.extend(speeds);
    }

    /// The next stride (from `start` to `end`, of `side`), its start not before the last's.
    pub fn stride(&mut self, start: f64, end: f64, side: usize) {
        if let Some(g) = &mut self.open {
            if start <= g.1 + MAX_PAUSE {
                g.1 = g.1.max(end);
                g.2[side] += 1;
                g.3 += end - start;
                g.4 += 1;
                return;
            }
        }
        self.close();
        let mut strides = [0; 2];
        strides[side] = 1;
        self.open = Some((start, end, strides, end - start, 1));
        // A local speed that starts before this bout falls in no bout to come.
        self.local.retain(|(a, _, _)| *a >= start - 1e-9);
    }

    fn close(&mut self) {
        let Some((start, end, strides, sum, n)) = self.open.take() else {
            return;
        };
        if strides.iter().all(|&n| n < MIN_STRIDES) {
            return;
        }
        let v: Vec<f64> = self
            .local
            .iter()
            .filter(|(a, b, _)| *a >= start - 1e-9 && *b <= end + 1e-9)
            .map(|x| x.2)
            .collect();
        self.found.push((
            Bout {
                start,
                end,
                strides,
                cadence: 120.0 / (sum / n as f64),
                speed: None,
            },
            crate::rules::median(v),
        ));
    }

    /// The bouts, in time order; `speed` is the recording's, a bout's where none of its local
    /// speeds is (`None`: no speed, the rules did not run).
    pub fn finish(mut self, speed: Option<f64>) -> Vec<Bout> {
        self.close();
        self.found
            .into_iter()
            .map(|(mut b, local)| {
                b.speed = speed.and_then(|v| local.or_else(|| v.is_finite().then_some(v)));
                b
            })
            .collect()
    }
}

/// `bouts.csv`: `recording,start,end,duration,strides_right,strides_left,cadence,speed` (s,
/// s, s, -, -, steps/min, m/s; an empty speed where there is none).
pub fn csv(recordings: &[(&str, Vec<Bout>)]) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "recording",
        "start",
        "end",
        "duration",
        "strides_right",
        "strides_left",
        "cadence",
        "speed",
    ])?;
    for (label, bouts) in recordings {
        for b in bouts {
            w.write_record([
                label.to_string(),
                format!("{:.3}", b.start),
                format!("{:.3}", b.end),
                format!("{:.3}", b.end - b.start),
                b.strides[0].to_string(),
                b.strides[1].to_string(),
                format!("{:.2}", b.cadence),
                b.speed.map_or(String::new(), |v| format!("{v:.3}")),
            ])?;
        }
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8(bytes).unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cycles::Cycle;

    fn cycle(side: usize, start: f64, duration: f64) -> Cycle {
        Cycle {
            side,
            start,
            duration,
            strike_frame: 0,
            samples: Vec::new(),
            toe_off: None,
            opposite_strike: None,
            opposite_toe_off: None,
            span: (0, 0),
        }
    }

    fn strides_between(t0: f64, t1: f64, period: f64) -> [Vec<Cycle>; 2] {
        let mut out: [Vec<Cycle>; 2] = Default::default();
        for (s, offset) in [(0, 0.0), (1, period / 2.0)] {
            let mut t = t0 + offset;
            while t + period <= t1 + 1e-9 {
                out[s].push(cycle(s, t, period));
                t += period;
            }
        }
        out
    }

    #[test]
    fn pauses_over_three_seconds_split_bouts_and_short_runs_are_not_bouts() {
        let [mut r, mut l] = strides_between(5.0, 20.0, 1.0);
        // A pause of 2.5 s does not split; one of 10 s does; two strides are no bout.
        for (t0, t1) in [(22.5, 30.0), (40.0, 50.0), (60.0, 62.2)] {
            let [a, b] = strides_between(t0, t1, 1.0);
            r.extend(a);
            l.extend(b);
        }
        let walk = crate::tests::walk_with_cycles([r, l]);
        let b = bouts(&walk);
        assert_eq!(b.len(), 2, "{b:?}");
        assert_eq!((b[0].start, b[0].end), (5.0, 30.0));
        assert_eq!((b[1].start, b[1].end), (40.0, 50.0));
        assert_eq!(b[1].strides, [10, 9]);
        assert!((b[1].cadence - 120.0).abs() < 1e-9);
        let text = csv(&[("w", b)]).unwrap();
        assert_eq!(text.lines().count(), 3, "{text}");
        assert!(text
            .lines()
            .nth(2)
            .unwrap()
            .starts_with("w,40.000,50.000,10.000,10,9,120.00,"));
    }
}
