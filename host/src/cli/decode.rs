//! `qgait decode`: a hub log (a file, a pipe or a serial port) decoded to text, JSON lines or a
//! frames CSV; damaged frames reported and skipped.

use std::io::{self, BufWriter, Write};

use anyhow::Context;
use clap::{Args, ValueEnum};
use qgait_proto::Message;

use crate::cli::device_args::{warn_cut_off, PortArgs};
use crate::cli::jsonl;
use qgait_device::frames_csv;
use qgait_device::log::{LogDecoder, Record};
use qgait_device::port;

/// `qgait decode` arguments.
#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// Hub log: a file, `-` for standard input, or a serial port (e.g. /dev/ttyACM0), opened
    /// raw 8N1 at --baud.
    pub log: String,
    /// Output format on standard output.
    #[arg(long, value_enum, default_value = "csv")]
    pub format: Format,
    /// The nodes' sampling rate (Hz): the CSV's `time` is then each frame's sample `seq` over
    /// it, instead of the sample's sensor time the frame carries (for nodes whose clocks are
    /// not to be trusted: a sample's `seq` counts the samples the nodes took).
    #[arg(long, value_name = "HZ", value_parser = positive_rate)]
    pub rate: Option<f64>,
    /// Reading a live hub: baud rate, when to stop, live view.
    #[command(flatten)]
    pub port: PortArgs,
}

/// `--rate`: a finite number of hertz above 0.
fn positive_rate(s: &str) -> anyhow::Result<f64> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(anyhow::anyhow!(
            "`{s}` is not a sampling rate in Hz (a number above 0)"
        )),
    }
}

/// What a damaged frame the decoder reported at byte `offset` is, for a message.
fn damage_message(offset: u64, error: &qgait_proto::DecodeError) -> String {
    match error {
        qgait_proto::DecodeError::Oversize => format!(
            "a frame longer than {} bytes, at byte {offset}: skipped to the next delimiter",
            qgait_proto::MAX_FRAME_LEN - 1
        ),
        _ => format!("damaged frame ending at byte {offset}: {error} (skipped)"),
    }
}

/// `qgait decode --format`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// One row per pose frame: seq, time (the sample's sensor time, or `seq / --rate`), the `fk` columns
    /// (other messages are only counted, by kind, in the summary on standard error).
    Csv,
    /// One JSON object per frame, every kind of message with its fields, and per damaged frame.
    Jsonl,
}

/// Runs `qgait decode`, the output on standard output.
pub fn run_decode(args: DecodeArgs, quiet: bool) -> anyhow::Result<()> {
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    decode_to(&args, &mut out, quiet)
}

/// Where `qgait decode` writes: frame rows of a frames CSV (with the sampling rate, if known),
/// or JSON lines.
enum DecodeOut<'a> {
    Csv(Box<frames_csv::FramesCsv<&'a mut dyn Write>>, Option<f64>),
    Jsonl(&'a mut dyn Write),
}

impl<'a> DecodeOut<'a> {
    /// Starts the output (the CSV's header).
    fn new(format: Format, out: &'a mut dyn Write, rate: Option<f64>) -> io::Result<Self> {
        Ok(match format {
            Format::Csv => DecodeOut::Csv(Box::new(frames_csv::FramesCsv::new(out)?), rate),
            Format::Jsonl => DecodeOut::Jsonl(out),
        })
    }

    /// Writes what `record` gives in this format; whether it gave anything.
    fn record(&mut self, record: &Record) -> io::Result<bool> {
        match self {
            DecodeOut::Csv(csv, rate) => match record {
                Record::Message {
                    message: Message::PoseFrame(p),
                    ..
                } => {
                    let time =
                        rate.map_or_else(|| frames_csv::sample_time(p), |r| f64::from(p.seq) / r);
                    csv.row(p, time).map(|()| true)
                }
                _ => Ok(false),
            },
            DecodeOut::Jsonl(out) => writeln!(out, "{}", jsonl_line(record)).map(|()| true),
        }
    }

    /// Passes everything written on and flushes the writer.
    fn flush(&mut self) -> io::Result<()> {
        match self {
            DecodeOut::Csv(csv, _) => csv.flush(),
            DecodeOut::Jsonl(out) => out.flush(),
        }
    }
}

/// The JSON line of `qgait decode` for `record`.
fn jsonl_line(record: &Record) -> String {
    match record {
        Record::Message { message, .. } => jsonl::message(message),
        Record::Damaged { offset, error } => jsonl::damaged(*offset, error),
    }
}

/// `qgait decode` writing to `out` (flushed after each chunk read from a serial port, so rows
/// come out as frames arrive). Memory is independent of the log's length.
pub fn decode_to(args: &DecodeArgs, out: &mut dyn Write, quiet: bool) -> anyhow::Result<()> {
    // The `status:` lines of the CSV format are the live view's lines.
    let (mut input, mut view) =
        args.port
            .open(&args.log, args.format == Format::Csv && !quiet, true, quiet)?;
    let mut out = DecodeOut::new(args.format, out, args.rate)?;
    let live = input.is_serial();
    let mut decoder = LogDecoder::new();
    let mut reported = 0u32;
    let mut write_error = None;
    let mut pending = false;
    let end = port::read_log(&mut input, &mut decoder, args.port.until(), |event| {
        let record = match event {
            port::Event::Record(r) => r,
            port::Event::Chunk => {
                if live && pending && write_error.is_none() {
                    pending = false;
                    if let Err(e) = out.flush() {
                        write_error = Some(e);
                    }
                }
                view.refresh();
                return write_error.is_none();
            }
        };
        view.record(&record);
        if let Record::Damaged { offset, error } = &record {
            if !quiet && reported < 20 {
                view.message(&format!("{}: {}", args.log, damage_message(*offset, error)));
            }
            reported += 1;
        }
        match out.record(&record) {
            Ok(wrote) => pending |= wrote,
            Err(e) => {
                write_error.get_or_insert(e);
            }
        }
        true
    });
    view.finish();
    let flushed = match write_error {
        Some(e) => Err(e),
        None => out.flush(),
    };
    match flushed {
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => return Ok(()),
        other => other.context("cannot write to standard output")?,
    }
    if reported > 20 && !quiet {
        eprintln!("... {} more damaged frames", reported - 20);
    }
    if let Some(why) = end.describe().filter(|_| !quiet) {
        eprintln!("{why}");
    }
    let counts = decoder.counts();
    eprintln!("decoded {counts}");
    warn_cut_off(&args.log, counts.unterminated);
    match end {
        port::End::Failed(e) => Err(e.into()),
        // A file (garbage, a `.mot`) read to its end without a single good frame: nothing
        // was found. (A live input stopped by --seconds or --idle may simply have been quiet.)
        port::End::InputEnded if !live && counts.poses + counts.statuses + counts.other == 0 => {
            anyhow::bail!(
                "{}: nothing was found: {} bytes without a single qgait frame (not a device log; a .mot/.sto motion goes to `qgait gait` or `qgait fk`)",
                args.log,
                counts.bytes
            )
        }
        _ => Ok(()),
    }
}
