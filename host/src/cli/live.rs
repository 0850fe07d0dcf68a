//! The live view of `qgait decode` and `qgait verify` (`--live`): while frames arrive, the
//! hub's latest status counters and what came so far, on standard error.
//!
//! On a terminal the view is a block of lines redrawn in place (at most 10 times a second,
//! and at each status the hub sends, once a second), with messages such as damaged frames
//! printed above it; it stays on the screen at the end. Elsewhere (a log file, a pipe) it is
//! one `status:` line per status frame, which a log keeps. Standard output is never touched,
//! so the frames CSV or JSON lines stay clean.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use qgait_proto::{Message, Status};

use qgait_device::log::Record;

/// Shortest time between two redraws.
const REDRAW: Duration = Duration::from_millis(100);

/// Widest line of the redrawn view (a line longer than the terminal would wrap and upset the
/// redrawing).
const WIDTH: usize = 78;

enum Display {
    Hidden,
    Redrawn(ProgressBar),
    Lines,
}

/// What has come so far and how it is shown.
pub struct LiveView {
    display: Display,
    started: Instant,
    first_pose: Option<Instant>,
    poses: u64,
    damaged: u64,
    last_seq: Option<u32>,
    status: Option<(Status, Instant)>,
    last_draw: Option<Instant>,
}

impl LiveView {
    fn with(display: Display) -> Self {
        LiveView {
            display,
            started: Instant::now(),
            first_pose: None,
            poses: 0,
            damaged: 0,
            last_seq: None,
            status: None,
            last_draw: None,
        }
    }

    /// No view.
    pub fn hidden() -> Self {
        Self::with(Display::Hidden)
    }

    /// A view redrawn in place on standard error (which should be a terminal).
    pub fn redrawn() -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template("{msg}") {
            bar.set_style(style);
        }
        Self::with(Display::Redrawn(bar))
    }

    /// A `status:` line on standard error per status frame.
    pub fn lines() -> Self {
        Self::with(Display::Lines)
    }

    /// Takes note of a record.
    pub fn record(&mut self, record: &Record) {
        match record {
            Record::Message {
                message: Message::PoseFrame(p),
                ..
            } => {
                self.poses += 1;
                self.last_seq = Some(p.seq);
                self.first_pose.get_or_insert_with(Instant::now);
            }
            Record::Message {
                message: Message::Status(s),
                ..
            } => {
                self.status = Some((*s, Instant::now()));
                match &self.display {
                    Display::Lines => eprintln!("{}", status_line(s)),
                    Display::Redrawn(_) => self.last_draw = None,
                    Display::Hidden => {}
                }
            }
            Record::Message { .. } => {}
            Record::Damaged { .. } => self.damaged += 1,
        }
    }

    /// Redraws the view if it is due.
    pub fn refresh(&mut self) {
        let Display::Redrawn(bar) = &self.display else {
            return;
        };
        let now = Instant::now();
        if self.last_draw.is_some_and(|t| now < t + REDRAW) {
            return;
        }
        self.last_draw = Some(now);
        bar.set_message(self.render(now));
    }

    /// Prints `line` on standard error, above the view when it is redrawn.
    pub fn message(&self, line: &str) {
        match &self.display {
            Display::Redrawn(bar) => bar.println(line),
            _ => eprintln!("{line}"),
        }
    }

    /// Draws the view a last time and leaves it on the screen.
    pub fn finish(&mut self) {
        if let Display::Redrawn(bar) = &self.display {
            bar.set_message(self.render(Instant::now()));
            bar.abandon();
        }
    }

    /// The view's text at `now`.
    pub fn render(&self, now: Instant) -> String {
        let rate = match self.first_pose {
            Some(t) if now > t && self.poses > 1 => {
                format!(
                    " ({:.1}/s)",
                    (self.poses - 1) as f64 / (now - t).as_secs_f64()
                )
            }
            _ => String::new(),
        };
        let seq = self
            .last_seq
            .map_or(String::new(), |s| format!(", last seq {s}"));
        let mut text = format!(
            "{} pose frames{rate}{seq}, {} damaged frames, {:.0} s",
            self.poses,
            self.damaged,
            (now - self.started).as_secs_f64()
        );
        match &self.status {
            None => text.push_str("\nno status from the hub yet"),
            Some((s, at)) => {
                text.push_str(&format!(
                    "\nhub status ({:.1} s ago):",
                    (now - *at).as_secs_f64()
                ));
                let mut line = String::new();
                for (k, v) in s.named_counters() {
                    let field = format!("{k}={v}");
                    if !line.is_empty() && line.len() + 2 + field.len() > WIDTH {
                        text.push('\n');
                        text.push_str(&line);
                        line.clear();
                    }
                    line.push_str("  ");
                    line.push_str(&field);
                }
                text.push('\n');
                text.push_str(&line);
            }
        }
        text
    }
}

/// `status: name=value ...`, the status counters on one line.
pub fn status_line(s: &Status) -> String {
    let f: Vec<String> = s
        .named_counters()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    format!("status: {}", f.join(" "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use qgait_proto::{DecodeError, ModelId, PoseFrame};

    #[test]
    fn the_view_shows_what_came_and_every_counter_of_the_last_status() {
        let mut view = LiveView::hidden();
        let start = view.started;
        let text = view.render(start);
        assert_eq!(
            text,
            "0 pose frames, 0 damaged frames, 0 s\nno status from the hub yet"
        );
        for seq in [7, 8] {
            view.record(&Record::Message {
                offset: 0,
                message: Message::PoseFrame(PoseFrame {
                    seq,
                    timestamp_us: seq * 10_000,
                    model: ModelId::Hak,
                    angles: heapless::Vec::from_slice(&[0.0; 6]).unwrap(),
                    points: [[0.0; 3]; 8],
                    distances: [0.0; 3],
                    flags: 0,
                }),
            });
        }
        view.record(&Record::Damaged {
            offset: 3,
            error: DecodeError::Crc,
        });
        let status = Status {
            packets_accepted: 16,
            crc_errors: 1,
            uptime_ms: 2500,
            ..Status::default()
        };
        view.record(&Record::Message {
            offset: 9,
            message: Message::Status(status),
        });
        let text = view.render(view.status.unwrap().1);
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[0].starts_with("2 pose frames (")
                && lines[0].contains("/s), last seq 8, 1 damaged frames"),
            "{text}"
        );
        assert_eq!(lines[1], "hub status (0.0 s ago):");
        assert!(lines.iter().all(|l| l.len() <= WIDTH), "{text}");
        let fields: Vec<String> = lines[2..]
            .iter()
            .flat_map(|l| l.split_whitespace())
            .map(String::from)
            .collect();
        let want: Vec<String> = status
            .named_counters()
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        assert_eq!(fields, want);
        assert!(status_line(&status).starts_with("status: packets_accepted=16 crc_errors=1 "));
    }
}
