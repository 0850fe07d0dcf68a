//! The gait analysis against force plates and markers: the shared gait-lab recordings
//! (`../shared/data/gaitlab/`, skipped with a printed reason when absent). The truth comes
//! from the ground reaction forces (a foot's vertical force crossing 20 N) and from the
//! markers (the belt speed from the feet's backward velocity in mid-stance), never from the
//! joint angles the analysis reads.

use std::path::{Path, PathBuf};

use qgait_gait::angles::{Seen, PLANAR_NOTE};
use qgait_gait::events::Kind;
use qgait_gait::rules::{Ground, Mode};
use qgait_gait::spatiotemporal::value;
use qgait_gait::{analyse_with, trial, CycleMode, Walk};
use qgait_model::choice::Model;
use qgait_opensim::mot::MotionTable;

/// Vertical force (N) whose crossing is contact.
const THRESHOLD: f64 = 20.0;
/// Events this close (s) to an end of the records are not scored.
const MARGIN: f64 = 0.2;
/// A detected event matches a true one of the same side and kind within this (s).
const MATCH: f64 = 0.15;

fn dir() -> Option<PathBuf> {
    let d = std::env::var_os("QGAIT_GAITLAB")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/gaitlab")
        });
    let d = if d.is_dir() {
        d
    } else {
        PathBuf::from("/work/shared/data/gaitlab")
    };
    if d.is_dir() {
        Some(d)
    } else {
        eprintln!(
            "skipped: no gait-lab recordings at {} (set QGAIT_GAITLAB)",
            d.display()
        );
        None
    }
}

/// Plate events per side: `(heel strikes, toe offs)`, times (s), and the GRF's time span.
type Plate = ([Vec<f64>; 2], [Vec<f64>; 2], (f64, f64));

fn plate_events(grf: &Path) -> Plate {
    let (table, _) = MotionTable::read(grf).expect("GRF reads");
    let t = table.time();
    let mut hs: [Vec<f64>; 2] = Default::default();
    let mut to: [Vec<f64>; 2] = Default::default();
    for (s, name) in ["ground_force_vy", "1_ground_force_vy"].iter().enumerate() {
        let f = table.column(name).expect("vertical force");
        for k in 1..f.len() {
            let (a, b) = (f[k - 1] - THRESHOLD, f[k] - THRESHOLD);
            if (a < 0.0) != (b < 0.0) {
                let at = t[k - 1] + (-a / (b - a)) * (t[k] - t[k - 1]);
                if b >= 0.0 {
                    hs[s].push(at);
                } else {
                    to[s].push(at);
                }
            }
        }
    }
    (hs, to, (t[0], t[t.len() - 1]))
}

/// The markers of a `.trc` (m), by name: per frame x, y, z; and the times.
fn markers(trc: &Path, names: &[&str]) -> (Vec<f64>, Vec<Vec<[f64; 3]>>) {
    let text = std::fs::read_to_string(trc).expect("trc reads");
    let lines: Vec<&str> = text.lines().collect();
    let units = lines[2].split('\t').nth(4).unwrap_or("mm").trim();
    let scale = if units == "mm" { 1e-3 } else { 1.0 };
    let labels: Vec<&str> = lines[3].split('\t').collect();
    let cols: Vec<usize> = names
        .iter()
        .map(|n| labels.iter().position(|l| l.trim() == *n).expect(n))
        .collect();
    let (mut time, mut out) = (Vec::new(), vec![Vec::new(); names.len()]);
    for l in &lines[5..] {
        let v: Vec<f64> = l
            .split('\t')
            .map(|x| x.trim().parse().unwrap_or(f64::NAN))
            .collect();
        if v.len() < 2 || !v[1].is_finite() {
            continue;
        }
        time.push(v[1]);
        for (m, &c) in cols.iter().enumerate() {
            out[m].push([v[c] * scale, v[c + 1] * scale, v[c + 2] * scale]);
        }
    }
    (time, out)
}

/// The belt speed: per plate stance, the median over its middle third of the heel and toe
/// markers' backward velocity, averaged; the median over stances.
fn belt_speed(trc: &Path, plate: &Plate) -> f64 {
    let sides = [["R.Heel", "R.Toe.Tip"], ["L.Heel", "L.Toe.Tip"]];
    let mut per_stance = Vec::new();
    for (s, names) in sides.iter().enumerate() {
        let (time, m) = markers(trc, names);
        for &h in &plate.0[s] {
            let Some(&o) = plate.1[s].iter().find(|&&o| o > h) else {
                continue;
            };
            let (a, b) = (h + (o - h) / 3.0, h + 2.0 * (o - h) / 3.0);
            let mut per_marker = Vec::new();
            for p in &m {
                let mut v: Vec<f64> = (1..time.len() - 1)
                    .filter(|&k| time[k] >= a && time[k] <= b)
                    .map(|k| -(p[k + 1][0] - p[k - 1][0]) / (time[k + 1] - time[k - 1]))
                    .filter(|v| v.is_finite())
                    .collect();
                if v.is_empty() {
                    continue;
                }
                v.sort_by(f64::total_cmp);
                per_marker.push(v[v.len() / 2]);
            }
            if per_marker.len() == 2 {
                per_stance.push((per_marker[0] + per_marker[1]) / 2.0);
            }
        }
    }
    per_stance.sort_by(f64::total_cmp);
    per_stance[per_stance.len() / 2]
}

struct Scored {
    mean_ms: f64,
    worst_ms: f64,
    matched: usize,
    missed: usize,
    false_events: usize,
}

/// Matches detected to true events of one side and kind in `span`.
fn score(detected: &[f64], truth: &[f64], span: (f64, f64)) -> (Vec<f64>, usize, usize) {
    let inside = |t: &f64| *t >= span.0 && *t <= span.1;
    let mut errors = Vec::new();
    let mut missed = 0;
    for &t in truth.iter().filter(|t| inside(t)) {
        match detected
            .iter()
            .map(|d| d - t)
            .filter(|e| e.abs() <= MATCH)
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        {
            Some(e) => errors.push(e),
            None => missed += 1,
        }
    }
    let false_events = detected
        .iter()
        .filter(|d| inside(d) && !truth.iter().any(|t| (*d - t).abs() <= MATCH))
        .count();
    (errors, missed, false_events)
}

/// Stance as % of each plate stride of a side.
fn plate_stance(plate: &Plate, s: usize) -> f64 {
    let hs = &plate.0[s];
    let v: Vec<f64> = hs
        .windows(2)
        .filter_map(|w| {
            let to = plate.1[s].iter().find(|&&o| o > w[0] && o < w[1])?;
            Some(100.0 * (to - w[0]) / (w[1] - w[0]))
        })
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}

fn plate_stride(plate: &Plate) -> f64 {
    let v: Vec<f64> = (0..2)
        .flat_map(|s| plate.0[s].windows(2).map(|w| w[1] - w[0]))
        .collect();
    v.iter().sum::<f64>() / v.len() as f64
}

struct Case {
    dir: &'static str,
    ik: &'static str,
    model: &'static str,
    grf: &'static str,
    trc: &'static str,
    mode: Mode,
}

const CASES: [Case; 2] = [
    Case {
        dir: "subject01_walk1",
        ik: "subject01_walk1_ik.mot",
        model: "subject01_simbody.osim",
        grf: "subject01_walk1_grf.mot",
        trc: "subject01_walk1.trc",
        mode: Mode::Walking,
    },
    Case {
        dir: "subject02_running",
        ik: "subject02_running_ik.mot",
        model: "subject02_scaled.osim",
        grf: "subject02_running_grf.mot",
        trc: "subject02_running.trc",
        mode: Mode::Running,
    },
];

/// How a recording's pelvis translation is given to the analysis.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Translation {
    /// As recorded (on the treadmill: the pelvis stays put).
    Recorded,
    /// Zeroed, as an IMU solution has it.
    Zeroed,
    /// The belt's travel added to `pelvis_tx`: the same steps made overground.
    Overground,
}

impl Translation {
    const ALL: [Self; 3] = [Self::Recorded, Self::Zeroed, Self::Overground];

    fn label(self) -> &'static str {
        match self {
            Self::Recorded => "with pelvis translation",
            Self::Zeroed => "without",
            Self::Overground => "overground",
        }
    }

    /// What the rules must say of the ground.
    fn ground(self) -> Ground {
        match self {
            Self::Recorded => Ground::Treadmill,
            Self::Zeroed => Ground::Unknown,
            Self::Overground => Ground::Overground,
        }
    }
}

fn run(case: &Case, root: &Path, translation: Translation) -> (Walk, Plate, (f64, f64), f64) {
    let d = root.join(case.dir);
    let (model, _) = Model::load(d.join(case.model).to_str().unwrap(), None).expect("model");
    let ik = d.join(case.ik);
    let plate = plate_events(&d.join(case.grf));
    let belt = belt_speed(&d.join(case.trc), &plate);
    // Each call its own directory: the tests run in parallel.
    let tmp = tempfile::tempdir().unwrap();
    let source = if translation == Translation::Recorded {
        ik.to_str().unwrap().to_string()
    } else {
        let (table, _) = MotionTable::read(&ik).unwrap();
        let labels: Vec<String> = table.labels().to_vec();
        let time = table.column("time").unwrap().to_vec();
        let columns: Vec<Vec<f64>> = labels
            .iter()
            .map(|l| {
                let c = table.column(l).unwrap();
                match (translation, l.as_str()) {
                    (Translation::Zeroed, "pelvis_tx" | "pelvis_ty" | "pelvis_tz") => {
                        vec![0.0; c.len()]
                    }
                    // The belt carries the feet back at `belt`: overground the body goes
                    // forward at it instead.
                    (Translation::Overground, "pelvis_tx") => c
                        .iter()
                        .zip(&time)
                        .map(|(x, t)| x + belt * (t - time[0]))
                        .collect(),
                    _ => c.to_vec(),
                }
            })
            .collect();
        let t = MotionTable::new("changed", "mem", table.in_degrees(), labels, columns).unwrap();
        let out = tmp
            .path()
            .join(format!("{}_{:?}.mot", case.dir, translation));
        let mut f = std::fs::File::create(&out).unwrap();
        t.write_mot(&mut f).unwrap();
        out.to_str().unwrap().to_string()
    };
    let (t, _) = trial::load(&source, &model).expect("loads");
    let ik_span = (t.time[0], *t.time.last().unwrap());
    let walk = analyse_with(t, CycleMode::Auto, None).expect("analyses");
    let (mtime, _) = markers(&d.join(case.trc), &["R.Heel"]);
    let span = (
        ik_span.0.max(plate.2 .0).max(mtime[0]) + MARGIN,
        ik_span.1.min(plate.2 .1).min(*mtime.last().unwrap()) - MARGIN,
    );
    (walk, plate, span, belt)
}

fn events_of(walk: &Walk, side: usize, kind: Kind) -> Vec<f64> {
    let e = match kind {
        Kind::HeelStrike => &walk.events.heel_strike[side],
        Kind::ToeOff => &walk.events.toe_off[side],
    };
    e.iter().map(|e| e.time).collect()
}

#[test]
fn events_speed_and_lengths_match_the_plates_and_markers() {
    let Some(root) = dir() else { return };
    for case in &CASES {
        for translation in Translation::ALL {
            let (walk, plate, span, belt) = run(case, &root, translation);
            let label = format!("{} ({})", case.dir, translation.label());
            let gait = walk.gait.as_ref().expect("the rules apply");
            assert_eq!(gait.mode, case.mode, "{label}: {gait:?}");
            assert_eq!(gait.ground, translation.ground(), "{label}");
            // Each kind's errors, both sides pooled: the issue's "heel strike and toe off
            // within 10 ms mean".
            let mut by_kind = [Vec::new(), Vec::new()];
            for side in 0..2 {
                for (k, (kind, truth)) in [(Kind::HeelStrike, &plate.0), (Kind::ToeOff, &plate.1)]
                    .into_iter()
                    .enumerate()
                {
                    let (errors, missed, false_events) =
                        score(&events_of(&walk, side, kind), &truth[side], span);
                    let s = Scored {
                        mean_ms: 1e3 * errors.iter().sum::<f64>() / errors.len().max(1) as f64,
                        worst_ms: 1e3 * errors.iter().fold(0.0f64, |m, e| m.max(e.abs())),
                        matched: errors.len(),
                        missed,
                        false_events,
                    };
                    eprintln!(
                        "{label} {} {}: mean {:+.1} ms, worst {:.1} ms, {} matched, {} missed, {} false",
                        ["right", "left"][side],
                        kind.name(),
                        s.mean_ms,
                        s.worst_ms,
                        s.matched,
                        s.missed,
                        s.false_events
                    );
                    assert!(s.matched > 0, "{label}: nothing matched");
                    assert_eq!((s.missed, s.false_events), (0, 0), "{label}");
                    assert!(s.worst_ms <= 25.0, "{label}: worst {} ms", s.worst_ms);
                    by_kind[k].extend(errors);
                }
            }
            for (kind, errors) in ["heel strike", "toe off"].iter().zip(&by_kind) {
                let mean = 1e3 * errors.iter().sum::<f64>() / errors.len() as f64;
                let absolute =
                    1e3 * errors.iter().map(|e| e.abs()).sum::<f64>() / errors.len() as f64;
                eprintln!("{label} {kind}: mean {mean:+.1} ms, mean absolute {absolute:.1} ms");
                assert!(mean.abs() <= 10.0, "{label}: {kind} mean {mean} ms");
                assert!(
                    absolute <= 10.0,
                    "{label}: {kind} mean absolute {absolute} ms"
                );
            }
            // Spatiotemporal parameters against the plates and the belt.
            let p = walk_parameters(&walk);
            let speed = value(&p, "speed", "both").unwrap();
            let stride = value(&p, "stride_length", "both").unwrap();
            let step = value(&p, "step_length", "both").unwrap();
            let cadence = value(&p, "cadence", "both").unwrap();
            let t = plate_stride(&plate);
            let rel = |a: f64, b: f64| (a - b) / b * 100.0;
            eprintln!(
                "{label}: speed {speed:.3} (belt {belt:.3}, {:+.1} %), stride {stride:.3} ({:+.1} %), step {step:.3} ({:+.1} %), cadence {cadence:.1} ({:+.2} %)",
                rel(speed, belt),
                rel(stride, belt * t),
                rel(step, belt * t / 2.0),
                rel(cadence, 120.0 / t)
            );
            assert!(rel(speed, belt).abs() <= 3.0, "{label}: speed {speed}");
            assert!(
                rel(stride, belt * t).abs() <= 3.0,
                "{label}: stride {stride}"
            );
            assert!(
                rel(step, belt * t / 2.0).abs() <= 5.0,
                "{label}: step {step}"
            );
            assert!(
                rel(cadence, 120.0 / t).abs() <= 1.0,
                "{label}: cadence {cadence}"
            );
            for side in 0..2 {
                let stance = value(&p, "stance", ["right", "left"][side]).unwrap();
                let truth = plate_stance(&plate, side);
                eprintln!("{label}: stance {side} {stance:.1} % (plates {truth:.1} %)");
                assert!(
                    (stance - truth).abs() <= 2.0,
                    "{label}: stance {stance} vs {truth}"
                );
            }
            let names: Vec<&str> = p.iter().map(|p| p.name).collect();
            match case.mode {
                Mode::Running => {
                    assert!(names.contains(&"flight"), "{names:?}");
                    assert!(!names.contains(&"double_support"), "{names:?}");
                }
                Mode::Walking => {
                    assert!(names.contains(&"double_support"), "{names:?}");
                    assert!(!names.contains(&"flight"), "{names:?}");
                }
            }
        }
    }
}

fn walk_parameters(walk: &Walk) -> Vec<qgait_gait::spatiotemporal::Parameter> {
    qgait_gait::spatiotemporal::parameters(&[(
        &walk.trial,
        walk.forward.as_slice(),
        &walk.cycles,
        walk.gait.as_ref(),
    )])
}

/// The walk's angles written in degrees under `inDegrees=no` (what OpenSim's CMC writes in
/// `Kinematics_q.sto`): refused with the header line; read right with `--angles-in deg`.
#[test]
fn degrees_declared_radians_are_refused_with_the_header_line() {
    let Some(root) = dir() else { return };
    let ik = root.join("subject01_walk1/subject01_walk1_ik.mot");
    let text = std::fs::read_to_string(&ik).unwrap();
    let line = text
        .lines()
        .position(|l| l.trim() == "inDegrees=yes")
        .expect("inDegrees line")
        + 1;
    let wrong = text.replacen("inDegrees=yes", "inDegrees=no", 1);
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("Kinematics_q.sto");
    std::fs::write(&path, wrong).unwrap();
    let model = Model::load("gait2392", None).unwrap().0;
    let source = path.to_str().unwrap();
    let e = trial::load(source, &model).err().expect("refused");
    let message = e.to_string();
    assert!(
        message.starts_with(&format!("{source}:{line}: ")),
        "{message}"
    );
    assert!(message.contains("inDegrees=no"), "{message}");
    assert!(message.contains("--angles-in deg"), "{message}");
    // Stated: the same analysis as the original.
    let (t, _) = trial::load_with(source, &model, Some(trial::AngleUnit::Deg)).unwrap();
    let (o, _) = trial::load(ik.to_str().unwrap(), &model).unwrap();
    assert_eq!(t.frames, o.frames);
    // Stated radians: read as the header says, and the analysis refuses the impossible
    // result instead of reporting it.
    let (t, _) = trial::load_with(source, &model, Some(trial::AngleUnit::Rad)).unwrap();
    let walk = analyse_with(t, CycleMode::Auto, None).unwrap();
    let e = report(vec![walk], &root).err();
    match e {
        Some(e) => {
            let m = e.to_string();
            assert!(m.contains("outside what a human can do"), "{m}");
        }
        None => panic!("an impossible walk was reported"),
    }
}

fn report(
    walks: Vec<Walk>,
    root: &Path,
) -> Result<qgait_gait::output::Report, qgait_gait::error::ReportError> {
    let reference = walks.iter().map(|w| w.trial.source.clone()).next().unwrap();
    let model = Model::load("gait2392", None).unwrap().0;
    let (t, _) = trial::load(
        root.join("subject01_walk1/subject01_walk1_ik.mot")
            .to_str()
            .unwrap(),
        &model,
    )
    .unwrap();
    let r = analyse_with(t, CycleMode::Auto, None).unwrap();
    qgait_gait::output::build(
        walks,
        "gait2392".into(),
        CycleMode::Auto,
        &qgait_gait::output::ReferenceArg::Motion(reference),
        Some(vec![r]),
        &qgait_gait::normative::Source::Dir("/nonexistent".into()),
        qgait_gait::output::Subject::default(),
    )
}

/// The report says the mode and the ground in `summary.json` and `spatiotemporal.csv`; a
/// run gets flight, no double support.
#[test]
fn the_report_says_mode_and_ground() {
    let Some(root) = dir() else { return };
    for (case, translation, mode, ground) in [
        (&CASES[0], Translation::Recorded, "walking", "treadmill"),
        (&CASES[0], Translation::Overground, "walking", "overground"),
        (&CASES[1], Translation::Recorded, "running", "treadmill"),
        (&CASES[1], Translation::Zeroed, "running", "unknown"),
    ] {
        let (walk, ..) = run(case, &root, translation);
        let r = report(vec![walk], &root).expect("report");
        let summary: serde_json::Value =
            serde_json::from_str(&qgait_gait::files::summary_json(&r)).unwrap();
        assert_eq!(summary["mode"], mode, "{summary}");
        assert_eq!(summary["ground"], ground, "{summary}");
        assert!(summary["headline"]["speed"]["value"].as_f64().unwrap() > 1.0);
        let csv = qgait_gait::files::spatiotemporal_csv(&r.parameters).unwrap();
        assert!(csv.contains("duty_factor,both,"), "{csv}");
        assert!(csv.contains(mode), "{csv}");
        if ground == "unknown" {
            assert!(csv.contains("ground unknown"), "{csv}");
        } else {
            assert!(
                csv.contains(&format!("{ground}: the pelvis travels")),
                "{csv}"
            );
        }
        if mode == "running" {
            assert!(csv.contains("flight,right"), "{csv}");
            assert!(!csv.contains("double_support"), "{csv}");
            assert!(csv.contains("normative bands are walking's"), "{csv}");
        }
    }
}

/// A planar model (gait10dof18musc) cannot see step width or any frontal or transverse angle:
/// the report leaves them out of the scores, `gps.csv`, `cycles/*.csv` and the figures, its
/// GPS is over the sagittal angles, and `spatiotemporal.csv` (where step width would be),
/// `summary.json`'s notes and the page say why. The 3-D subject's model reports them all.
#[test]
fn a_planar_model_reports_the_sagittal_plane_only() {
    let Some(root) = dir() else { return };
    let osim = root.join("../opensim/gait10dof18musc.osim");
    if !osim.is_file() {
        eprintln!("skipped: no {}", osim.display());
        return;
    }
    let model = Model::load(osim.to_str().unwrap(), None).unwrap().0;
    let ik = root.join("subject01_walk1/subject01_walk1_ik.mot");
    let (t, _) = trial::load(ik.to_str().unwrap(), &model).unwrap();
    assert_eq!(t.seen, Seen::SAGITTAL);
    let walk = analyse_with(t, CycleMode::Auto, None).unwrap();
    let p = walk_parameters(&walk);
    assert_eq!(value(&p, "step_width", "both"), None);
    assert!(p
        .iter()
        .filter(|p| p.name == "step_width")
        .all(|p| p.side == "both" && p.value.is_none() && p.note == PLANAR_NOTE));
    assert!(value(&p, "step_length", "both").is_some());
    let planar = report(vec![walk], &root).expect("report");
    // The 3-D subject's model, the same walk.
    let (walk, ..) = run(&CASES[0], &root, Translation::Recorded);
    assert_eq!(walk.trial.seen, Seen::ALL);
    assert!(value(&walk_parameters(&walk), "step_width", "both").is_some());
    let full = report(vec![walk], &root).expect("report");
    let unseen = [
        "pelvic_obliquity",
        "pelvic_rotation",
        "hip_abduction",
        "hip_rotation",
        "foot_progression",
    ];
    let seen = [
        "pelvic_tilt",
        "hip_flexion",
        "knee_flexion",
        "ankle_dorsiflexion",
    ];
    for (r, is_planar) in [(&planar, true), (&full, false)] {
        assert_eq!(r.seen == Seen::SAGITTAL, is_planar);
        let scores = r.scores.as_ref().expect("scores");
        let gps = qgait_gait::files::gps_csv(scores).unwrap();
        let cycles = qgait_gait::files::cycles_csv(&r.curves[0]).unwrap();
        let head = cycles.lines().next().unwrap().to_string();
        for name in unseen {
            assert_eq!(gps.contains(&format!("{name},")), !is_planar, "{gps}");
            assert_eq!(head.contains(&format!("{name}_mean")), !is_planar, "{head}");
        }
        for name in seen {
            assert!(gps.contains(&format!("{name},right,")), "{gps}");
            assert!(head.contains(&format!("{name}_mean")), "{head}");
        }
        // The GPS: the RMS of the GVS scored, over seven (planar) or fifteen.
        let g: Vec<f64> = scores.gvs[0].iter().flatten().copied().collect();
        assert_eq!(g.len(), if is_planar { 4 } else { 9 });
        let rms = (g.iter().map(|x| x * x).sum::<f64>() / g.len() as f64).sqrt();
        assert!((scores.gps[0].unwrap() - rms).abs() < 1e-12);
        let mut all: Vec<f64> = Vec::new();
        for (v, var) in qgait_gait::angles::Variable::ALL.iter().enumerate() {
            if var.is_pelvis() {
                all.extend(scores.gvs[1][v]);
            } else {
                all.extend(scores.gvs[0][v]);
                all.extend(scores.gvs[1][v]);
            }
        }
        assert_eq!(all.len(), if is_planar { 7 } else { 15 });
        let overall = (all.iter().map(|x| x * x).sum::<f64>() / all.len() as f64).sqrt();
        assert!((scores.overall.unwrap() - overall).abs() < 1e-12);
        assert!(r.normal_scores.as_ref().unwrap().gvs[0][1].is_some() != is_planar);
        // The files: the note where step width would be, in summary.json's notes, on the page;
        // the figures without the frontal and transverse panels and bars.
        let tmp = tempfile::tempdir().unwrap();
        qgait_gait::files::write(r, tmp.path()).unwrap();
        let read = |name: &str| std::fs::read_to_string(tmp.path().join(name)).unwrap();
        let st = read("spatiotemporal.csv");
        let summary: serde_json::Value = serde_json::from_str(&read("summary.json")).unwrap();
        let notes = summary["recordings"][0]["notes"]
            .as_array()
            .unwrap()
            .clone();
        let page = read("report.html");
        let kinematics = read("kinematics.svg");
        let map = read("map.svg");
        if is_planar {
            assert!(
                st.lines().any(|l| l.starts_with("step_width,both,,m,,,")
                    && l.contains("planar model: it moves neither hip")),
                "{st}"
            );
            assert!(notes.iter().any(|n| n == PLANAR_NOTE), "{notes:?}");
            assert!(
                summary["headline"]["step_width"]["value"].is_null(),
                "{summary}"
            );
            assert_eq!(summary["headline"]["step_width"]["method"], PLANAR_NOTE);
            assert!(
                page.contains("overall GPS over 7 sagittal variables"),
                "{page}"
            );
        } else {
            assert!(!st.contains("planar"), "{st}");
            assert!(notes.iter().all(|n| n != PLANAR_NOTE), "{notes:?}");
            assert!(page.contains("overall GPS over 15 variables"), "{page}");
        }
        assert_eq!(page.contains("planar model"), is_planar);
        for text in ["Pelvic obliquity", "Hip rotation", "Foot progression"] {
            assert_eq!(kinematics.contains(text), !is_planar, "{text}");
        }
        assert!(kinematics.contains("Knee flexion"));
        for word in ["obliquity", "progression"] {
            assert_eq!(map.contains(word), !is_planar, "{word}");
        }
        assert!(map.contains("flexion"));
    }
}

/// `text` (an `.osim`) with the coordinates `names` locked: the model no longer moves them
/// (imported as a general chain that holds each at its default).
fn locking(text: &str, names: &[&str]) -> String {
    let mut text = text.to_string();
    for name in names {
        let at = text
            .find(&format!("<Coordinate name=\"{name}\">"))
            .unwrap_or_else(|| panic!("no coordinate {name}"));
        let end = at + text[at..].find("</Coordinate>").expect("its end");
        let body = text[at..end].replace("<locked>false</locked>", "<locked>true</locked>");
        assert!(body.contains("<locked>true</locked>"), "{name} not locked");
        text.replace_range(at..end, &body);
    }
    text
}

/// A model that moves only some frontal and transverse coordinates: the subject's gait2392
/// with its pelvis list and rotation and both hip rotations locked, hip adduction free. Its
/// report leaves out exactly the pelvic obliquity, the pelvic rotation and the hip rotation
/// (scores, `gps.csv`, `cycles/*.csv`, figures), keeps the foot progression and the step width
/// (the adduction moves them), its GPS is over six variables a side (eleven overall), and
/// `summary.json` (`not_seen`, notes), `spatiotemporal.csv` and the page say which and why.
/// The same model with the pelvis rotation free instead of the hip adduction loses the hip
/// abduction instead of the pelvic rotation (ten overall: two pelvic variables once).
#[test]
fn a_model_that_moves_some_frontal_and_transverse_coordinates_reports_those_only() {
    use qgait_gait::angles::Variable::{self, *};
    let Some(root) = dir() else { return };
    let d = root.join(CASES[0].dir);
    let text = std::fs::read_to_string(d.join(CASES[0].model)).unwrap();
    let ik = d.join(CASES[0].ik);
    for (locked, not_seen) in [
        (
            &[
                "pelvis_list",
                "pelvis_rotation",
                "hip_rotation_r",
                "hip_rotation_l",
            ][..],
            [PelvicObliquity, PelvicRotation, HipRotation],
        ),
        (
            &[
                "pelvis_list",
                "hip_adduction_r",
                "hip_adduction_l",
                "hip_rotation_r",
                "hip_rotation_l",
            ][..],
            [PelvicObliquity, HipAbduction, HipRotation],
        ),
    ] {
        let (model, _) = Model::import(&locking(&text, locked), "locked.osim", None).unwrap();
        assert!(matches!(model, Model::Chain { .. }));
        let (t, _) = trial::load(ik.to_str().unwrap(), &model).unwrap();
        assert_eq!(t.seen.not_seen(), not_seen);
        assert!(t.seen.step_width());
        let walk = analyse_with(t, CycleMode::Auto, None).unwrap();
        // A locked hip's curves are flat; every variable seen moves.
        let angles = walk.angles.as_ref().unwrap();
        for (v, var) in Variable::ALL.iter().enumerate() {
            let c = &angles[0][v];
            let range = c.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
                - c.iter().fold(f64::INFINITY, |a, &b| a.min(b));
            if [HipRotation, HipAbduction].contains(var) && not_seen.contains(var) {
                assert!(range < 1e-9, "{var:?} moves {range}");
            } else if !not_seen.contains(var) {
                assert!(range > 1.0, "{var:?} moves {range} only");
            }
        }
        let p = walk_parameters(&walk);
        assert!(value(&p, "step_width", "both").is_some());
        let r = report(vec![walk], &root).expect("report");
        let seen: Vec<Variable> = Variable::ALL
            .into_iter()
            .filter(|v| !not_seen.contains(v))
            .collect();
        assert_eq!(r.variables(), seen);
        let scores = r.scores.as_ref().expect("scores");
        assert_eq!(scores.variables, seen);
        let gps = qgait_gait::files::gps_csv(scores).unwrap();
        let cycles = qgait_gait::files::cycles_csv(&r.curves[0]).unwrap();
        let head = cycles.lines().next().unwrap();
        for (v, var) in Variable::ALL.into_iter().enumerate() {
            let shown = !not_seen.contains(&var);
            assert_eq!(gps.contains(&format!("{},", var.name())), shown, "{gps}");
            assert_eq!(
                head.contains(&format!("{}_mean", var.name())),
                shown,
                "{head}"
            );
            for s in 0..2 {
                assert_eq!(scores.gvs[s][v].is_some(), shown, "{var:?}");
            }
        }
        // Six GVS a side; overall, the others of both sides and the pelvic ones once: eleven
        // (the pelvic tilt) or ten (the pelvic tilt and rotation).
        let pelvic = seen.iter().filter(|v| v.is_pelvis()).count();
        let n = pelvic + 2 * (6 - pelvic);
        assert_eq!(n, if pelvic == 1 { 11 } else { 10 });
        for s in 0..2 {
            let g: Vec<f64> = scores.gvs[s].iter().flatten().copied().collect();
            assert_eq!(g.len(), 6);
            let rms = (g.iter().map(|x| x * x).sum::<f64>() / 6.0).sqrt();
            assert!((scores.gps[s].unwrap() - rms).abs() < 1e-12);
        }
        let mut all: Vec<f64> = Vec::new();
        for (v, var) in Variable::ALL.iter().enumerate() {
            all.extend(scores.gvs[1][v]);
            if !var.is_pelvis() {
                all.extend(scores.gvs[0][v]);
            }
        }
        assert_eq!(all.len(), n);
        let overall = (all.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt();
        assert!((scores.overall.unwrap() - overall).abs() < 1e-12);
        // The files say which and why.
        let note = r.seen.note().unwrap();
        assert!(
            note.starts_with("the model cannot move: pelvic obliquity (no pelvis_list), "),
            "{note}"
        );
        assert!(
            note.contains("the GPS is over the 6 variables it can move"),
            "{note}"
        );
        let tmp = tempfile::tempdir().unwrap();
        qgait_gait::files::write(&r, tmp.path()).unwrap();
        let read = |name: &str| std::fs::read_to_string(tmp.path().join(name)).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&read("summary.json")).unwrap();
        let names: Vec<&str> = not_seen.iter().map(|v| v.name()).collect();
        assert_eq!(summary["not_seen"], serde_json::json!(names), "{summary}");
        assert_eq!(
            summary["recordings"][0]["not_seen"],
            serde_json::json!(names)
        );
        let notes = summary["recordings"][0]["notes"].as_array().unwrap();
        assert!(notes.iter().any(|n| n == note.as_str()), "{notes:?}");
        assert!(summary["headline"]["step_width"]["value"]
            .as_f64()
            .is_some());
        let st = read("spatiotemporal.csv");
        assert!(st.contains("step_width,both,0."), "{st}");
        assert!(!st.contains("planar"), "{st}");
        let page = read("report.html");
        assert!(!page.contains("planar model"));
        let over = if pelvic == 1 {
            "overall GPS over 11 variables, the pelvic tilt once; the model cannot move"
        } else {
            "overall GPS over 10 variables, the pelvic tilt and pelvic rotation once; the model cannot move"
        };
        assert!(page.contains(over), "{page}");
        let kinematics = read("kinematics.svg");
        let map = read("map.svg");
        for var in Variable::ALL {
            let shown = !not_seen.contains(&var);
            let title = var.title().split(" (").next().unwrap();
            assert_eq!(kinematics.contains(title), shown, "{title}");
            // The map's labels, a word a line: the pelvis's second words, the others' first
            // (the hip's first word is also the knee's and ankle's).
            let word = match var {
                PelvicTilt | PelvicObliquity | PelvicRotation => title.split(' ').nth(1),
                HipFlexion | HipAbduction | HipRotation => None,
                _ => title.split(' ').next(),
            };
            if let Some(word) = word {
                assert_eq!(map.contains(&format!("\n{word}\n")), shown, "{word}");
            }
        }
    }
}

/// Every number names its method: no spatiotemporal note and no headline method is empty,
/// and those of the events name the events' method actually used: walking's thresholds on
/// the walk, running's knee-extension toe off on the run.
#[test]
fn every_number_names_its_method() {
    let Some(root) = dir() else { return };
    for (case, heel, toe) in [
        (
            &CASES[0],
            "falls through 0.5 m/s (Ghoussayni",
            "rises through 0.66 x speed",
        ),
        (
            &CASES[1],
            "falls through 0.78 x speed",
            "peak knee extension late in stance (Fellin",
        ),
    ] {
        let (walk, ..) = run(case, &root, Translation::Recorded);
        let r = report(vec![walk], &root).expect("report");
        for p in &r.parameters {
            assert!(
                !p.note.is_empty(),
                "{}: {} {} has no note",
                case.dir,
                p.name,
                p.side
            );
        }
        let csv = qgait_gait::files::spatiotemporal_csv(&r.parameters).unwrap();
        for line in csv.lines().skip(1) {
            assert!(!line.ends_with(','), "{}: {line}", case.dir);
        }
        // Every side's row of a parameter.
        let notes = |name: &str| -> Vec<String> {
            let n: Vec<String> = r
                .parameters
                .iter()
                .filter(|p| p.name == name)
                .map(|p| p.note.clone())
                .collect();
            assert!(!n.is_empty(), "{}: no {name}", case.dir);
            n
        };
        for name in ["cadence", "stride_time", "step_time"] {
            for n in notes(name) {
                assert!(n.contains(heel) && !n.contains("toe off:"), "{name}: {n}");
            }
        }
        let contact = if case.mode == Mode::Running {
            "flight"
        } else {
            "double_support"
        };
        for name in ["stance", "swing", contact] {
            for n in notes(name) {
                assert!(n.contains(heel) && n.contains(toe), "{name}: {n}");
            }
        }
        assert!(notes("stance")[0].starts_with("heel strike to toe off; "));
        let summary: serde_json::Value =
            serde_json::from_str(&qgait_gait::files::summary_json(&r)).unwrap();
        let headline = summary["headline"].as_object().unwrap();
        assert!(headline.contains_key("cadence") && headline.contains_key("stance_right"));
        for (name, figure) in headline {
            let method = figure["method"].as_str().unwrap_or("");
            assert!(
                !method.is_empty(),
                "{}: headline {name} has no method",
                case.dir
            );
        }
        assert!(headline["cadence"]["method"]
            .as_str()
            .unwrap()
            .contains(heel));
        let events = summary["recordings"][0]["events"].as_str().unwrap();
        assert!(events.contains(heel) && events.contains(toe), "{events}");
    }
}

/// The CGM's pelvic tilt against the lab's own pelvis markers (`R.ASIS`, `L.ASIS`,
/// `V.Sacral` in the `.trc`: the CGM defines the pelvis by them): the mean tilt over the
/// recording with the fixed offset is within 1° of the markers', on the walk and on the run.
/// The scaled models' own pelvis markers give an offset 2-3.5° smaller, which puts the
/// tilt 2-3° below the lab markers' (the numbers the docs quote, printed).
#[test]
fn the_pelvic_tilt_is_the_lab_markers() {
    let Some(root) = dir() else { return };
    for case in &CASES {
        let (walk, _, _, _) = run(case, &root, Translation::Recorded);
        let d = root.join(case.dir);
        let (time, m) = markers(&d.join(case.trc), &["R.ASIS", "L.ASIS", "V.Sacral"]);
        let lab: Vec<f64> = (0..time.len())
            .filter_map(|i| {
                let v = [0, 1, 2].map(|k| (m[0][i][k] + m[1][i][k]) / 2.0 - m[2][i][k]);
                let tilt = (-v[1]).atan2(v[0].hypot(v[2])).to_degrees();
                tilt.is_finite().then_some(tilt)
            })
            .collect();
        let lab = lab.iter().sum::<f64>() / lab.len() as f64;
        let mean_tilt = |w: &Walk| {
            let t = &w.angles.as_ref().expect("angles")[0][0];
            t.iter().sum::<f64>() / t.len() as f64
        };
        let fixed = mean_tilt(&walk);
        let text = std::fs::read_to_string(d.join(case.model)).unwrap();
        let l = qgait_opensim::pelvis_markers::pelvis_landmarks(&text).expect("markers");
        let offset = qgait_gait::angles::tilt_offset(l.mid_asis, l.posterior);
        let walk = walk.with_cgm_pelvis(qgait_gait::angles::CgmPelvis::Markers(
            qgait_gait::angles::ModelMarkers {
                offset,
                names: l.names,
            },
        ));
        let own = mean_tilt(&walk);
        println!(
            "{}: pelvic tilt mean {fixed:.2}° (fixed offset), {own:.2}° (the model's markers, {:.2}°), lab markers {lab:.2}°",
            case.dir,
            offset.to_degrees()
        );
        assert!((fixed - lab).abs() < 1.0, "{fixed} vs {lab}");
        let shift = offset.to_degrees() - qgait_gait::angles::pelvis_tilt_offset().to_degrees();
        assert!((own - fixed - shift).abs() < 0.05, "{own} {fixed} {shift}");
    }
}
