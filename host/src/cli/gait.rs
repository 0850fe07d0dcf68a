//! `qgait gait`: clinical gait analysis of one or more recordings (crate `qgait_gait`).

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use anyhow::Context;
use qgait_gait::output::{self, ReferenceArg, Subject};
use qgait_gait::stream::{self, Pool, Settings};
use qgait_gait::{self as gait, trial, CycleMode};
use qgait_model::choice::Model;
use qgait_opensim::diagnostics::{Warning, WarningText};

/// Arguments of `qgait gait`.
#[derive(Debug, Args, Clone)]
pub struct GaitArgs {
    /// Recordings of one subject: OpenSim motions (.mot/.sto, e.g. `qgait imu` output),
    /// `builtin:...`, or a device's frames CSVs (`qgait emulate --frames-csv`: events and
    /// spatiotemporal parameters only). Their strides are pooled.
    #[arg(required = true)]
    pub motions: Vec<String>,
    /// The model whose FK gives the heel, toe and foot positions: gait2392 (the default here;
    /// heel at the calcaneus, foot axis ankle to MTP), SUBJECT.toml, MODEL.osim, phak or hak
    /// (heel at the ankle; hak has a level, forward-facing pelvis and cannot follow turns).
    #[command(flatten)]
    pub model: ModelArgs,
    /// `auto`: every complete, straight stride from the detected events; `whole`: each
    /// recording is one gait cycle (single-cycle files). Applies to a reference motion too.
    #[arg(long, value_enum, default_value_t = CycleArg::Auto)]
    pub cycle: CycleArg,
    /// `normative` (Schwartz et al. 2008 at the speed group of the measured cadence, against
    /// the slow, normal and fast cadence of `stp_normals.txt` for --age and --sex, adults'
    /// without), `normative:SPEED` (very-slow, slow, free, fast, very-fast), or another
    /// recording (e.g. the same patient's earlier visit).
    #[arg(
        long,
        default_value = "normative",
        value_name = "normative[:SPEED]|MOTION"
    )]
    pub reference: String,
    /// The subject's age in years, for the normal ranges of the spatiotemporal parameters
    /// (an age that `stp_normals.txt` has no rows for is an error).
    #[arg(long, value_name = "YEARS", value_parser = parse_age)]
    pub age: Option<f64>,
    /// The subject's sex, for the normal ranges (default: the range of either).
    #[arg(long, value_enum)]
    pub sex: Option<SexArg>,
    /// The subject's identifier, for the report's header, its title and `summary.json`.
    #[arg(long, value_name = "ID")]
    pub subject_id: Option<String>,
    /// The session's date, YYYY-MM-DD (default: the first recording's modification date, UTC).
    #[arg(long, value_name = "YYYY-MM-DD", value_parser = parse_date)]
    pub date: Option<String>,
    /// The subject's height in metres, for the report's header (with --mass, the BMI).
    #[arg(long, value_name = "M", value_parser = parse_height)]
    pub height: Option<f64>,
    /// The subject's body mass in kilograms, for the report's header.
    #[arg(long, value_name = "KG", value_parser = parse_mass)]
    pub mass: Option<f64>,
    /// The session's condition in words (shoes, orthoses, assistive device, ...), shown beside
    /// the condition the analysis detects (walking or running, treadmill or overground, speed).
    #[arg(long, value_name = "TEXT")]
    pub condition: Option<String>,
    /// A directory with `Schwartz2008.json` and `stp_normals.txt` to use instead of the data
    /// compiled into qgait (default: `$QGAIT_NORMATIVE`, else those compiled in).
    #[arg(long, value_name = "DIR")]
    pub normative: Option<PathBuf>,
    /// A known belt speed (m/s) of the subject's recordings: used for their event thresholds
    /// and lengths instead of the speed estimated from the feet (a `--reference MOTION` keeps
    /// its own estimated speed).
    #[arg(long, value_name = "V", value_parser = parse_speed)]
    pub treadmill_speed: Option<f64>,
    /// The unit of the motions' angles whatever their headers say (OpenSim's CMC/RRA
    /// `Kinematics_q.sto` are in degrees under `inDegrees=no`).
    #[arg(long, value_enum, value_name = "deg|rad")]
    pub angles_in: Option<trial::AngleUnit>,
    /// The Conventional Gait Model's pelvis frame in the model's: `fixed` (the ASIS-PSIS line
    /// of Rajagopal 2016's markers, 5.87°) or `model-markers` (the `--model` .osim's own ASIS
    /// and PSIS or sacral markers; `fixed` when it has none). On the gait-lab recordings `fixed`
    /// is within 0.6° of the tilt the lab's own markers give, `model-markers` 2.1-2.9° below it
    /// (docs/gait-analysis.md).
    #[arg(long, value_enum, default_value = "fixed")]
    pub cgm_pelvis: CgmPelvisArg,
    /// Each motion on its own (not pooled as one subject's): one report per motion in
    /// `DIR/<name>/` and `DIR/recordings.csv` with every recording's headline figures and
    /// errors, the recordings analysed in parallel on every core.
    #[arg(long)]
    pub each: bool,
    /// Output directory (created if needed).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
}

/// `--treadmill-speed`: a finite speed above 0 m/s.
fn parse_speed(text: &str) -> anyhow::Result<f64> {
    crate::cli::amount(text, 0.0, false).ok_or_else(|| {
        anyhow::anyhow!("`{text}` is not a speed: expected a finite number of m/s above 0")
    })
}

/// `--age`: a finite number of years, 0 or more.
fn parse_age(text: &str) -> anyhow::Result<f64> {
    crate::cli::amount(text, 0.0, true).ok_or_else(|| {
        anyhow::anyhow!("`{text}` is not an age: expected a finite number of years, 0 or more")
    })
}

/// `--date`: a calendar date, YYYY-MM-DD.
fn parse_date(text: &str) -> anyhow::Result<String> {
    qgait_gait::session::parse_date(text).ok_or_else(|| {
        anyhow::anyhow!("`{text}` is not a date: expected YYYY-MM-DD, a day that exists")
    })
}

/// `--height`: a finite number of metres above 0 and at most 3.
fn parse_height(text: &str) -> anyhow::Result<f64> {
    crate::cli::amount(text, 0.0, false)
        .filter(|h| *h <= 3.0)
        .ok_or_else(|| {
            anyhow::anyhow!(
                "`{text}` is not a height: expected metres above 0 and at most 3 (1.75, not 175)"
            )
        })
}

/// `--mass`: a finite number of kilograms above 0 and at most 500.
fn parse_mass(text: &str) -> anyhow::Result<f64> {
    crate::cli::amount(text, 0.0, false)
        .filter(|m| *m <= 500.0)
        .ok_or_else(|| {
            anyhow::anyhow!(
                "`{text}` is not a body mass: expected kilograms above 0 and at most 500"
            )
        })
}

/// `--cgm-pelvis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CgmPelvisArg {
    /// Rajagopal 2016's ASIS and PSIS markers on gait2392's pelvis.
    Fixed,
    /// The model's own pelvis markers.
    ModelMarkers,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CycleArg {
    /// From the events.
    Auto,
    /// One cycle per recording.
    Whole,
}

/// `--sex`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SexArg {
    /// Male.
    Male,
    /// Female.
    Female,
}

/// Analyses `motions` with the model of `args` into `pool`, each read as a stream of rows
/// and analysed window by window (`qgait_gait::stream`).
fn analyse_all(
    pool: &mut Pool,
    motions: &[String],
    model: &Model,
    settings: &Settings,
    warn: &dyn Fn(Vec<Warning>),
) -> anyhow::Result<()> {
    for m in motions {
        // A built-in gait is one cycle by construction: taken whole whatever `--cycle`
        // says (its single pair of heel strikes holds no complete stride).
        let mut settings = settings.clone();
        if m.starts_with("builtin:") {
            settings.mode = CycleMode::Whole;
        }
        stream::analyse_into(pool, m, model, &settings, &mut |w| warn(w))?;
    }
    Ok(())
}

/// The CGM's pelvis frame `chosen` for `model`: for `model-markers`, from an `.osim` model's
/// own pelvis markers (ASIS with PSIS or sacrum) where it has them, else the fixed offset; for
/// `fixed`, the fixed offset, naming the model's markers where it has them.
fn cgm_pelvis(chosen: CgmPelvisArg, model: Option<&str>) -> gait::angles::CgmPelvis {
    let markers = model
        .filter(|m| m.to_ascii_lowercase().ends_with(".osim"))
        .and_then(|m| std::fs::read_to_string(m).ok())
        .and_then(|text| qgait_opensim::pelvis_markers::pelvis_landmarks(&text))
        .map(|l| gait::angles::ModelMarkers {
            offset: gait::angles::tilt_offset(l.mid_asis, l.posterior),
            names: l.names,
        });
    match (chosen, markers) {
        (CgmPelvisArg::ModelMarkers, Some(m)) => gait::angles::CgmPelvis::Markers(m),
        (_, model_markers) => gait::angles::CgmPelvis::Fixed { model_markers },
    }
}

/// The warnings a report lists at most; the rest are counted in one line (a file with a fault
/// in every row warns per row).
const REPORT_WARNINGS: usize = 200;

/// The run's warnings as the report lists them: the first [`REPORT_WARNINGS`], and how many
/// more there were.
#[derive(Default)]
struct Kept {
    list: std::cell::RefCell<Vec<String>>,
    more: std::cell::Cell<usize>,
}

impl Kept {
    fn keep(&self, warnings: &[Warning]) {
        let mut list = self.list.borrow_mut();
        for w in warnings {
            if list.len() < REPORT_WARNINGS {
                list.push(w.to_string());
            } else {
                self.more.set(self.more.get() + 1);
            }
        }
    }

    fn for_report(&self) -> Vec<String> {
        let mut list = self.list.borrow().clone();
        if self.more.get() > 0 {
            list.push(format!(
                "... and {} more warnings, as printed on the terminal",
                self.more.get()
            ));
        }
        list
    }
}

/// Runs `qgait gait` on one recording, or several analysed together (`--each`, each on its
/// own, is [`gait_each::run`](crate::cli::gait_each::run)).
pub fn run_gait(args: GaitArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    // Every warning is shown as it comes and kept for the report's warnings section.
    let kept = Kept::default();
    let warn = |w: Vec<Warning>| {
        kept.keep(&w);
        diagnostics.warn(w)
    };
    let mode = match args.cycle {
        CycleArg::Auto => CycleMode::Auto,
        CycleArg::Whole => CycleMode::Whole,
    };
    let reference = ReferenceArg::parse(&args.reference)?;
    let (model, model_warnings) = args.model.load_or_keeping("gait2392", diagnostics)?;
    kept.keep(&model_warnings);
    if let Some(w) = generic_model_warning(&args) {
        warn(vec![w]);
    }
    let pelvis = cgm_pelvis(args.cgm_pelvis, args.model.model.as_deref());
    let settings = Settings {
        mode,
        given_speed: args.treadmill_speed,
        angles_in: args.angles_in,
        pelvis,
    };
    // events.csv is written as the recordings are read.
    let existed = args.output.exists();
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create", args.output.display()))?;
    let events = args.output.join("events.csv");
    let result = analyse_and_write(&args, &reference, &model, &settings, &events, &warn, &kept);
    if result.is_err() {
        // No partial events.csv is left behind, nor a directory made for it.
        let _ = std::fs::remove_file(&events);
        if !existed {
            let _ = std::fs::remove_dir(&args.output);
        }
    }
    let (report, files) = result?;
    if !diagnostics.quiet() {
        let strides: usize = report
            .recordings
            .iter()
            .map(|w| w.strides[0] + w.strides[1])
            .sum();
        let gps = report
            .scores
            .as_ref()
            .and_then(|s| s.overall)
            .map_or(String::new(), |g| {
                format!(", GPS {}°", qgait_gait::number::round(g, 2))
            });
        eprintln!(
            "{strides} stride{}{gps}; wrote {} files to {}",
            if strides == 1 { "" } else { "s" },
            files.len(),
            args.output.display()
        );
    }
    Ok(())
}

/// The subject and the session as given; the date, when not given, the first recording's
/// modification date (none for a `builtin:` gait).
fn session(args: &GaitArgs) -> gait::session::Session {
    let (date, date_from) = match &args.date {
        Some(d) => (Some(d.clone()), Some("given".to_string())),
        None => args
            .motions
            .iter()
            .find_map(|m| gait::session::file_date(m).map(|d| (d, m.clone())))
            .map_or((None, None), |(d, m)| (Some(d), Some(m))),
    };
    gait::session::Session {
        subject_id: args.subject_id.clone(),
        date,
        date_from,
        age: args.age,
        sex: args.sex.map(|s| match s {
            SexArg::Male => "male",
            SexArg::Female => "female",
        }),
        height: args.height,
        mass: args.mass,
        condition: args.condition.clone(),
    }
}

/// Without `--model` a motion's feet are placed by the generic gait2392, whose segments are
/// an adult of 1.8 m's: the speed and the lengths the rules measure from the feet's motion
/// relative to the pelvis scale with those segments, not the subject's (the gait-lab walk's
/// speed reads 8.5 % low through it). Said unless the speed is given (`--treadmill-speed`:
/// the lengths are then speed × time) or no recording is a motion file.
fn generic_model_warning(args: &GaitArgs) -> Option<Warning> {
    let generic = args.model.model.is_none() && args.treadmill_speed.is_none();
    (generic && args.motions.iter().any(|m| stream::is_motion_file(m))).then(|| {
        Warning::Limitation(WarningText {
            at: None,
            detail: GENERIC_MODEL.to_string(),
        })
    })
}

/// [`generic_model_warning`]'s text.
const GENERIC_MODEL: &str = "no --model: the generic gait2392 (an adult of 1.8 m) places the feet, so the speed, stride and step lengths scale with its segments, not the subject's; give the subject's scaled model (--model SUBJECT.osim) or the belt's speed (--treadmill-speed)";

/// The analysis of every recording, `events.csv` written to `events` as it goes, then the
/// report and its files.
fn analyse_and_write(
    args: &GaitArgs,
    reference: &ReferenceArg,
    model: &Model,
    settings: &Settings,
    events: &std::path::Path,
    warn: &dyn Fn(Vec<Warning>),
    kept: &Kept,
) -> anyhow::Result<(output::Report, Vec<PathBuf>)> {
    let mut pool = Pool::to_file(events, args.motions.len() > 1)
        .with_context(|| format!("{}: cannot write", events.display()))?;
    analyse_all(&mut pool, &args.motions, model, settings, warn)?;
    let pool = output::finish(pool)?;
    let reference_pool = match reference {
        ReferenceArg::Motion(m) => {
            let mut pool = Pool::without_events();
            // The belt speed is the subject's: the reference is analysed with its own speed.
            let own_speed = Settings {
                given_speed: None,
                ..settings.clone()
            };
            analyse_all(&mut pool, std::slice::from_ref(m), model, &own_speed, warn)?;
            Some(output::finish(pool)?)
        }
        ReferenceArg::Normative(_) => None,
    };
    for w in pool
        .0
        .recordings
        .iter()
        .chain(reference_pool.iter().flat_map(|p| p.0.recordings.iter()))
    {
        w.require_strides()?;
    }
    let normative = match &args.normative {
        Some(dir) => gait::normative::Source::Dir(dir.clone()),
        None => gait::normative::Source::default_for_run(),
    };
    let subject = Subject {
        age: args.age,
        male: args.sex.map(|s| s == SexArg::Male),
    };
    // Every recording taken whole (`builtin:` gaits are): the report says so.
    let mode = if pool.0.recordings.iter().all(|w| w.mode == CycleMode::Whole) {
        CycleMode::Whole
    } else {
        settings.mode
    };
    let mut report = output::build_from(
        pool,
        model.name().to_string(),
        mode,
        reference,
        reference_pool,
        &normative,
        subject,
    )?;
    report.session = session(args);
    report.warnings = kept.for_report();
    let files = qgait_gait::files::write(&report, &args.output)?;
    Ok((report, files))
}
