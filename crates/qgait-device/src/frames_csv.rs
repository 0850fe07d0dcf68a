//! The frames CSV of `qgait emulate --frames-csv` and `qgait decode --format csv`: the `qgait fk`
//! columns (`time`, then hip/knee/ankle/toe × x,y,z, right leg then left) with `seq` in front,
//! one row per `PoseFrame`. `time` is the frame's sample time in seconds: its `timestamp_us`, the
//! nodes' sensor clock, which wraps after 2³² µs (71.6 min; [`FramesTable::in_time_order`]
//! continues across the wrap). A CSV of older hubs' frames, which carried no time, has it empty.
//! Points as the hub sent them (f32, printed as f64).

use std::io::{self, Write};

use qgait_proto::PoseFrame;

use qgait_model::points::{csv_header, point_names, PointsCsv};
use qgait_opensim::diagnostics::{Location, Warning, WarningText};

/// Whether `path` names a frames CSV: its extension is `csv`, in any case (`FRAMES.CSV` too).
pub fn is_frames_csv(path: &str) -> bool {
    std::path::Path::new(path)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// The header line (without the newline).
pub fn header() -> String {
    format!("seq,{}", csv_header(&point_names(false)))
}

/// A frames CSV being written (with the `csv` crate, through [`PointsCsv`]): the [`header`],
/// then one row per frame.
pub struct FramesCsv<W: Write>(PointsCsv<W>);

impl<W: Write> FramesCsv<W> {
    /// Writes the header.
    pub fn new(w: W) -> io::Result<Self> {
        Ok(Self(PointsCsv::new(w, &point_names(false), true)?))
    }

    /// Writes the row of one frame at `time_s` (s): its [`sample_time`] unless the caller
    /// knows better (`qgait decode --rate`).
    pub fn row(&mut self, f: &PoseFrame, time_s: f64) -> io::Result<()> {
        let points = f.points.iter().map(|p| p.map(f64::from));
        Ok(self.0.row(f.seq, Some(time_s), points)?)
    }

    /// Passes every row written on to the writer and flushes it.
    pub fn flush(&mut self) -> io::Result<()> {
        self.0.flush_through()
    }
}

/// The time of `frame`'s sample (s): its `timestamp_us`, the nodes' sensor clock (wrapping).
pub fn sample_time(frame: &PoseFrame) -> f64 {
    f64::from(frame.timestamp_us) * 1e-6
}

/// Writes the header and one row per frame, each at its [`sample_time`].
pub fn write<W: Write + ?Sized>(w: &mut W, frames: &[PoseFrame]) -> io::Result<()> {
    let mut csv = FramesCsv::new(w)?;
    for f in frames {
        csv.row(f, sample_time(f))?;
    }
    csv.flush()
}

/// A frames CSV read back: per row the sequence number, the time (s) if present, and the 8
/// points (m).
#[derive(Debug, Clone, PartialEq)]
pub struct FramesTable {
    /// Sequence numbers.
    pub seq: Vec<u32>,
    /// Times (s), `None` where the column is empty.
    pub time: Vec<Option<f64>>,
    /// The 8 points of each row, [`qgait_model::points::point_names`] order.
    pub points: Vec<[[f64; 3]; 8]>,
    /// Where each row is: its 1-based line and the 1-based column where its `time` starts.
    pub at: Vec<(usize, usize)>,
}

impl FramesTable {
    /// The rows in time order, as a gait analysis needs them: every row must have a time (an
    /// error naming the line and column of an empty one); the rows are taken in sequence
    /// order (a hub sends a sample that completes first first, so its frames may come out of
    /// order within its reorder window), times continuing across the hub's timestamp wrap
    /// (2³² µs, 71.6 min); then, by the rules of a `.mot`, a time before the previous row's is
    /// an error and a row whose time repeats the previous row's (a frame written twice)
    /// replaces it with a warning. `source` names the file.
    pub fn in_time_order(self, source: &str) -> Result<(Self, Vec<Warning>), FramesCsvError> {
        let at = |(line, column): (usize, usize)| Location {
            path: source.to_string(),
            line: Some(line),
            column: Some(column),
        };
        let mut rows = Vec::with_capacity(self.seq.len());
        for (((seq, time), points), here) in self
            .seq
            .into_iter()
            .zip(self.time)
            .zip(self.points)
            .zip(self.at)
        {
            let Some(t) = time else {
                return Err(FramesCsvError::NoTime { at: at(here) });
            };
            rows.push((seq, t, points, here));
        }
        // Sequence order relative to the first frame (numbers wrap at 2³²).
        let first = rows.first().map_or(0, |r| r.0);
        rows.sort_by_key(|r| r.0.wrapping_sub(first));
        let mut out = FramesTable {
            seq: Vec::with_capacity(rows.len()),
            time: Vec::with_capacity(rows.len()),
            points: Vec::with_capacity(rows.len()),
            at: Vec::with_capacity(rows.len()),
        };
        let mut warnings = Vec::new();
        let mut wraps = 0.0;
        for (seq, t, points, here) in rows {
            let mut t = t + wraps;
            if let (Some(Some(p)), Some(&before), Some(&before_seq)) =
                (out.time.last(), out.at.last(), out.seq.last())
            {
                if *p - t > TIMESTAMP_WRAP_S / 2.0 {
                    // The hub's microsecond timestamp wrapped.
                    wraps += TIMESTAMP_WRAP_S;
                    t += TIMESTAMP_WRAP_S;
                }
                if t < *p {
                    return Err(FramesCsvError::TimeBack {
                        at: at(here),
                        time: t,
                        previous: *p,
                        previous_line: before.0,
                    });
                }
                if t == *p {
                    warnings.push(Warning::RowReplaced(WarningText {
 at: Some(at(here)),
 detail: format!("time {t} (seq {seq}) repeats the previous frame's (line {}, seq {before_seq}); this row replaces it, as in a .mot", before.0),
}));
                    out.seq.pop();
                    out.time.pop();
                    out.points.pop();
                    out.at.pop();
                }
            }
            out.seq.push(seq);
            out.time.push(Some(t));
            out.points.push(points);
            out.at.push(here);
        }
        Ok((out, warnings))
    }
}

/// The span of a hub's `timestamp_us` (2³² µs) in seconds: a frames CSV's times from a device
/// go back by it when the timestamp wraps.
const TIMESTAMP_WRAP_S: f64 = 4_294.967_296;

/// Why a file is not a frames CSV: where and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FramesCsvError {
    /// The first line is not the header.
    #[error("{at}: not a frames CSV (expected the header `{expected}`)")]
    Header {
        /// The file's first line.
        at: Location,
        /// The header a frames CSV starts with.
        expected: String,
    },
    /// A motion (OpenSim's `endheader`, or `time` as the first column) written with commas.
    #[error("{at}: a comma-separated motion, not a frames CSV: a motion (.mot/.sto) needs tab- or space-separated columns, the first `time` (save it with tabs and the .mot extension)")]
    CommaSeparatedMotion {
        /// The line that shows it (`endheader`, or the `time,...` labels).
        at: Location,
    },
    /// The CSV reader refused the text.
    #[error("{at}: not CSV: {message}")]
    Unreadable {
        /// Where it stopped.
        at: Location,
        /// Its reason.
        message: String,
    },
    /// A row has another number of values.
    #[error("{at}: {found} values, expected 26")]
    Width {
        /// The row's line.
        at: Location,
        /// How many it has.
        found: usize,
    },
    /// A row without a time, where every row's is needed (a frames CSV with times).
    #[error("{at}: no time in this row (the other rows have one: every frame's is needed)")]
    NoTime {
        /// The row's line and the column of its empty `time`.
        at: Location,
    },
    /// A time before the previous frame's (in sequence order).
    #[error("{at}: time {time} is before the previous frame's {previous} (line {previous_line})")]
    TimeBack {
        /// The row's line and the column of its `time`.
        at: Location,
        /// Its time (s).
        time: f64,
        /// The previous row's (s).
        previous: f64,
        /// The previous row's line.
        previous_line: usize,
    },
    /// A value is not a number (or not finite).
    #[error("{at}: bad {what} `{text}`")]
    Value {
        /// The row's line.
        at: Location,
        /// `seq`, `time` or `number`.
        what: &'static str,
        /// The value as written.
        text: String,
    },
}

/// Parses a frames CSV; errors name the line.
pub fn parse(text: &str, source: &str) -> Result<FramesTable, FramesCsvError> {
    let line_at = |line: usize| Location {
        path: source.to_string(),
        line: Some(line),
        column: None,
    };
    // A UTF-8 byte order mark (a spreadsheet's "UTF-8 CSV") is not part of the header.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Rows of any width (a wrong one is refused below, naming its line); blank lines skipped;
    // spaces after a value (a trimmed line before) ignored.
    let mut rows = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::Fields)
        .from_reader(text.as_bytes())
        .into_records();
    let unreadable = |e: csv::Error| FramesCsvError::Unreadable {
        at: Location::in_text(source, text, e.position().map_or(0, |p| p.byte() as usize)),
        message: e.to_string(),
    };
    match rows.next().transpose().map_err(unreadable)? {
        Some(h) if h.iter().collect::<Vec<_>>().join(",") == header() => {}
        _ => {
            // What a motion has: OpenSim's header, or the labels line first.
            let motion = text.lines().take(100).position(|l| {
                let l = l.trim();
                l.eq_ignore_ascii_case("endheader")
                    || l.split(',').next().is_some_and(|f| f.trim() == "time") && l.contains(',')
            });
            return Err(match motion {
                Some(k) => FramesCsvError::CommaSeparatedMotion { at: line_at(k + 1) },
                None => FramesCsvError::Header {
                    at: line_at(1),
                    expected: header(),
                },
            });
        }
    }
    let mut t = FramesTable {
        seq: Vec::new(),
        time: Vec::new(),
        points: Vec::new(),
        at: Vec::new(),
    };
    // The line of a row from its byte offset (the reader's own count leaves blank lines out).
    let (mut counted_to, mut line) = (0, 1);
    for row in rows {
        let cells = row.map_err(unreadable)?;
        let mut start = cells.position().map_or(counted_to, |p| p.byte() as usize);
        // (The reader's offset is before the blank lines it skipped.)
        while matches!(text.as_bytes().get(start), Some(b'\n' | b'\r')) {
            start += 1;
        }
        line += text.as_bytes()[counted_to..start]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        counted_to = start;
        if cells.len() != 26 {
            return Err(FramesCsvError::Width {
                at: line_at(line),
                found: cells.len(),
            });
        }
        let bad = |what: &'static str, v: &str| FramesCsvError::Value {
            at: line_at(line),
            what,
            text: v.to_string(),
        };
        t.seq
            .push(cells[0].parse().map_err(|_| bad("seq", &cells[0]))?);
        t.time.push(if cells[1].is_empty() {
            None
        } else {
            Some(
                cells[1]
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad("time", &cells[1]))?,
            )
        });
        let mut p = [[0.0; 3]; 8];
        for (k, v) in cells.iter().skip(2).enumerate() {
            p[k / 3][k % 3] = v
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad("number", v))?;
        }
        t.points.push(p);
        t.at.push((line, cells[0].chars().count() + 2));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_proto::ModelId;

    #[test]
    fn a_frames_csv_is_known_by_its_extension_in_any_case() {
        assert!(is_frames_csv("a/frames.csv"));
        assert!(is_frames_csv("FRAMES.CSV"));
        assert!(is_frames_csv("f.Csv"));
        assert!(!is_frames_csv("walk.mot"));
        assert!(!is_frames_csv("csv"));
        assert!(!is_frames_csv("walk.csv.mot"));
    }

    #[test]
    fn errors_name_the_line_after_blank_lines() {
        let points = vec!["0.5"; 24].join(",");
        let text = format!("{}\n0,0,{points}\n\n1,0.01,{points},9\n", header());
        assert_eq!(
            parse(&text, "f.csv").unwrap_err().to_string(),
            "f.csv:4: 27 values, expected 26"
        );
        let text = format!("{}\n0,0,{points}  \r\n\n1,x,{points}\n", header());
        assert_eq!(
            parse(&text, "f.csv").unwrap_err().to_string(),
            "f.csv:4: bad time `x`"
        );
    }

    #[test]
    fn a_byte_order_mark_before_the_header_is_skipped() {
        let points = vec!["0.5"; 24].join(",");
        let text = format!("\u{feff}{}\n0,0,{points}\n", header());
        let t = parse(&text, "f.csv").unwrap();
        assert_eq!((t.seq.as_slice(), t.at[0]), (&[0][..], (2, 3)));
    }

    #[test]
    fn rows_in_time_order_as_in_a_mot() {
        let points = vec!["0.5"; 24].join(",");
        let csv = |rows: &[(&str, &str)]| {
            let mut text = format!("{}\n", header());
            for (seq, t) in rows {
                text.push_str(&format!("{seq},{t},{points}\n"));
            }
            parse(&text, "f.csv").unwrap()
        };
        // A frame written twice: the later replaces it, with a warning.
        let (t, w) = csv(&[("0", "0"), ("1", "0.01"), ("1", "0.01"), ("2", "0.02")])
            .in_time_order("f.csv")
            .unwrap();
        assert_eq!(t.seq, [0, 1, 2]);
        assert_eq!(t.time, [Some(0.0), Some(0.01), Some(0.02)]);
        assert_eq!(t.at.iter().map(|a| a.0).collect::<Vec<_>>(), [2, 4, 5]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(
            w[0].to_string(),
            "f.csv:4:3: time 0.01 (seq 1) repeats the previous frame's (line 3, seq 1); this row replaces it, as in a .mot"
        );
        // Frames as a hub sends them (a sample that completes first, first): in sequence
        // order; the hub's timestamp wrapping after 2³² µs continues.
        let (t, w) = csv(&[
            ("4294967295", "4294.96"),
            ("1", "0.02"),
            ("0", "0.01"),
            ("2", "0.03"),
        ])
        .in_time_order("f.csv")
        .unwrap();
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(t.seq, [4294967295, 0, 1, 2]);
        let times: Vec<f64> = t.time.iter().flatten().copied().collect();
        for (got, want) in times
            .iter()
            .zip([4294.96, 4294.977296, 4294.987296, 4294.997296])
        {
            assert!((got - want).abs() < 1e-9, "{times:?}");
        }
        // Time going back: an error at its line and column.
        let e = csv(&[("8", "0"), ("9", "0.5"), ("10", "0.25")])
            .in_time_order("f.csv")
            .unwrap_err();
        assert!(
            matches!(
                &e,
                FramesCsvError::TimeBack {
                    previous_line: 3,
                    ..
                }
            ),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "f.csv:4:4: time 0.25 is before the previous frame's 0.5 (line 3)"
        );
        // One row without a time: named by line and column.
        let e = csv(&[("0", "0"), ("1", ""), ("2", "0.02")])
            .in_time_order("f.csv")
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "f.csv:3:3: no time in this row (the other rows have one: every frame's is needed)"
        );
    }

    #[test]
    fn frames_round_trip_through_the_csv() {
        let frame = |seq: u32| PoseFrame {
            seq,
            timestamp_us: seq * 10_000,
            model: ModelId::Hak,
            angles: heapless::Vec::from_slice(&[0.0; 6]).unwrap(),
            points: core::array::from_fn(|i| [i as f32 * 0.25, -0.5, seq as f32]),
            distances: [0.0; 3],
            flags: 0,
        };
        let mut out = Vec::new();
        write(&mut out, &[frame(3), frame(4)]).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("seq,time,hip_r_x,"));
        // Numbers as Rust's `{}` prints the f32 widened to f64; the time is the frame's.
        let rows: Vec<&str> = text.lines().collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0], header());
        assert_eq!(
            rows[1],
            "3,0.03,0,-0.5,3,0.25,-0.5,3,0.5,-0.5,3,0.75,-0.5,3,1,-0.5,3,1.25,-0.5,3,1.5,-0.5,3,1.75,-0.5,3"
        );
        assert!(rows[2].starts_with("4,0.04,0,-0.5,4,0.25,"), "{}", rows[2]);
        let t = parse(&text, "f.csv").unwrap();
        assert_eq!(t.seq, [3, 4]);
        assert_eq!(t.time, [Some(0.03), Some(0.04)]);
        assert_eq!(t.points[1][7], [1.75, -0.5, 4.0]);
        let e = parse("seq,time\n", "x.csv").unwrap_err().to_string();
        assert!(e.starts_with("x.csv:1: not a frames CSV"), "{e}");
        // A motion saved with commas under a .csv name: said so, at the line that shows it.
        for (motion, line) in [
            (
                "walk\nversion=1\ninDegrees=yes\nendheader\ntime,hip_flexion_r\n0,1\n",
                4,
            ),
            ("time,pelvis_tilt,hip_flexion_r\n0,1,2\n", 1),
        ] {
            let e = parse(motion, "m.csv").unwrap_err();
            assert!(
                matches!(&e, FramesCsvError::CommaSeparatedMotion { at } if at.line == Some(line)),
                "{e:?}"
            );
            assert!(e.to_string().contains("comma-separated motion"), "{e}");
        }
        let e = parse(&text.replace("0.03", "abc"), "f.csv").unwrap_err();
        assert!(
            matches!(&e, FramesCsvError::Value { what: "time", text, .. } if text == "abc"),
            "{e:?}"
        );
        let e = e.to_string();
        assert!(e.contains("f.csv:2: bad time `abc`"), "{e}");
        let mut odd = frame(5);
        odd.points[0] = [0.1, f32::NAN, f32::INFINITY];
        let mut out = Vec::new();
        let mut csv = FramesCsv::new(&mut out).unwrap();
        csv.row(&odd, 1e-7).unwrap();
        csv.flush().unwrap();
        drop(csv);
        let odd_text = String::from_utf8(out).unwrap();
        assert_eq!(
            odd_text
                .lines()
                .nth(1)
                .unwrap()
                .split(',')
                .take(5)
                .collect::<Vec<_>>(),
            ["5", "0.0000001", "0.10000000149011612", "NaN", "inf"]
        );
    }
}
