//! Memory does not grow with the number of rows: `fk`, `export` and `packets` on a motion and on
//! one ten times longer peak at about the same resident memory (the child's own peak, from
//! `wait4`), and `gait` on an hour of walking peaks as on ten minutes, under 100 MB. Not timed.
//! Whole-file reading held the text and every column: tens of MB more for the longer file.

use std::path::Path;
use std::process::Command;

/// A motion of `rows` rows with the 17 coordinate columns of the shared gait2392 files.
fn write_motion(path: &Path, rows: usize) {
    use std::io::Write;
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    writeln!(
        f,
        "long\nversion=1\nnRows={rows}\nnColumns=18\ninDegrees=yes\nendheader"
    )
    .unwrap();
    writeln!(f, "time\tpelvis_list\tpelvis_rotation\tpelvis_tilt\thip_flexion_r\thip_adduction_r\thip_rotation_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\thip_adduction_l\thip_rotation_l\tknee_angle_l\tankle_angle_l\tpelvis_ty\tlumbar_bending\tlumbar_rotation\tlumbar_extension").unwrap();
    for r in 0..rows {
        let p = (r % 100) as f64 * std::f64::consts::TAU / 100.0;
        let s = p.sin();
        writeln!(
            f,
            "{}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t{:.4}\t0.96\t0\t0\t0",
            r as f64 * 0.01,
            2.0 * s,
            4.0 * s,
            -1.5,
            20.0 * s + 10.0,
            3.0 * s,
            2.0 * s,
            -30.0 * s - 30.0,
            10.0 * s,
            -20.0 * s + 10.0,
            -3.0 * s,
            -2.0 * s,
            30.0 * s - 30.0,
            -10.0 * s
        )
        .unwrap();
    }
}

/// Runs qgait and returns its peak resident memory in KiB.
///
/// glibc's malloc is given a fixed mmap threshold (128 KiB, its default start). Left to
/// itself it raises the threshold each time a large block is freed, after which the windows'
/// buffers come from the heap, and the peak then depends on how that heap fragmented: the same
/// 10-minute file peaked anywhere from 52 to 61 MB, the hour 62-63 MB, while the live heap
/// (heaptrack) was 36.7 and 37.3 MB. With the threshold fixed the peak follows the live heap
/// (47.3-47.6 MB and 47.9-48.2 MB), so a growth of a few MB means memory held, not luck.
#[allow(clippy::zombie_processes)] // waited for by wait4, which also gives its rusage
fn peak_kib(args: &[&str]) -> i64 {
    let child = Command::new(qgait_system_tests::qgait_bin())
        .args(args)
        .env("GLIBC_TUNABLES", "glibc.malloc.mmap_threshold=131072")
        .spawn()
        .expect("qgait runs");
    let mut status = 0;
    // SAFETY: wait4 on our own child, with valid pointers to a status and an rusage.
    let (pid, usage) = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        let pid = libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage);
        (pid, usage)
    };
    assert_eq!(pid, child.id() as libc::pid_t, "wait4");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "qgait {args:?} failed"
    );
    usage.ru_maxrss
}

#[test]
fn fk_export_and_packets_do_not_hold_the_rows() {
    let dir = tempfile::tempdir().unwrap();
    let (short, long) = (dir.path().join("short.mot"), dir.path().join("long.mot"));
    write_motion(&short, 10_000);
    write_motion(&long, 100_000);
    let long_mib = std::fs::metadata(&long).unwrap().len() as f64 / (1 << 20) as f64;
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let s = |p: &Path| p.to_str().unwrap().to_string();
    let commands: [(&str, Vec<String>); 4] = [
        (
            "fk",
            vec![
                "-q".into(),
                "fk".into(),
                "M".into(),
                "-o".into(),
                out("a.csv"),
            ],
        ),
        (
            "fk gait2392",
            vec![
                "-q".into(),
                "fk".into(),
                "M".into(),
                "--model".into(),
                "gait2392".into(),
                "-o".into(),
                out("b.csv"),
            ],
        ),
        (
            "export",
            vec![
                "-q".into(),
                "export".into(),
                "M".into(),
                "--trc".into(),
                out("c.trc"),
                "--sto".into(),
                out("c.sto"),
            ],
        ),
        (
            "packets",
            vec![
                "-q".into(),
                "packets".into(),
                "M".into(),
                "-o".into(),
                out("d.bin"),
            ],
        ),
    ];
    for (name, args) in commands {
        let run = |motion: &Path| {
            let a: Vec<String> = args
                .iter()
                .map(|x| if x == "M" { s(motion) } else { x.clone() })
                .collect();
            peak_kib(&a.iter().map(String::as_str).collect::<Vec<_>>())
        };
        let (small, large) = (run(&short), run(&long));
        let grew_mib = (large - small) as f64 / 1024.0;
        eprintln!("{name}: peak {small} KiB on 10,000 rows, {large} KiB on 100,000 rows ({long_mib:.1} MiB file)");
        // Holding the long file's rows would cost more than its size again.
        assert!(
            grew_mib < 0.2 * long_mib,
            "{name}: peak memory grew by {grew_mib:.1} MiB for a {long_mib:.1} MiB file"
        );
    }
}

/// The IMU walk (`qgait imu`'s joint angles of OpenSense's tutorial walk, 24.31 s at 100 Hz)
/// repeated end to end to `minutes`, times continuing at 100 Hz, values rounded to 1e-4
/// (`scripts/long_recording.py` builds the day of BENCHMARKS.md the same way).
fn repeated_walk(walk: &Path, minutes: f64, path: &Path) -> usize {
    use std::io::Write;
    let text = std::fs::read_to_string(walk).unwrap();
    let mut lines = text.lines();
    lines
        .by_ref()
        .find(|l| l.trim().eq_ignore_ascii_case("endheader"))
        .expect("a header");
    let labels = lines.next().expect("column labels");
    let rest: Vec<String> = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split('\t')
                .skip(1)
                .map(|v| format!("{:.4}", v.parse::<f64>().unwrap()))
                .collect::<Vec<_>>()
                .join("\t")
        })
        .collect();
    let rows = (minutes * 60.0 * 100.0).round() as usize;
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    writeln!(
        f,
        "long_walk\nversion=1\nnRows={rows}\nnColumns={}\ninDegrees=yes\nendheader\n{labels}",
        labels.split('\t').count()
    )
    .unwrap();
    for i in 0..rows {
        writeln!(f, "{:.2}\t{}", i as f64 / 100.0, rest[i % rest.len()]).unwrap();
    }
    rows
}

/// `gait` on the IMU walk repeated to 10 and to 60 minutes: the peak does not grow with the
/// recording (it is read as rows and analysed in windows of at most 24,000 rows,
/// `qgait_gait::stream`) and stays under 100 MB; both are analysed whole (as many events and
/// bouts per repetition of the walk); the events figure shows a minute of either. Whole-recording analysis held about 1.2 kB a row: 430 MB for the hour.
#[test]
fn gait_does_not_hold_the_recording() {
    let Some(imu) = qgait_system_tests::imu_dir() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let walk = dir.path().join("walk.mot");
    qgait_system_tests::run_imu_tutorial(&imu, &walk, &[]);
    let mut peaks = Vec::new();
    let mut counts = Vec::new();
    let mut figures = Vec::new();
    for minutes in [10.0, 60.0] {
        let motion = dir.path().join(format!("walk_{minutes}.mot"));
        let rows = repeated_walk(&walk, minutes, &motion);
        let out = dir.path().join(format!("out_{minutes}"));
        let peak = peak_kib(&[
            "-q",
            "gait",
            motion.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        let lines = |f: &str| {
            std::fs::read_to_string(out.join(f))
                .unwrap()
                .lines()
                .count()
                - 1
        };
        let (events, bouts) = (lines("events.csv"), lines("bouts.csv"));
        // The events figure: a minute of the recording, whatever its length (a marker for
        // every event of the hour would be a solid blob).
        let figure = std::fs::metadata(out.join("events.svg")).unwrap().len();
        figures.push(figure);
        eprintln!(
            "gait: peak {peak} KiB on {rows} rows ({minutes} min): {events} events, {bouts} bouts"
        );
        peaks.push(peak);
        counts.push((events, bouts));
        std::fs::remove_file(&motion).unwrap();
    }
    // The whole recording analysed: as many events and bouts per repetition of the walk in
    // the hour as in the ten minutes (24.7 and 148.1 repetitions: the last one cut short).
    let walk_rows = std::fs::read_to_string(&walk)
        .unwrap()
        .lines()
        .skip_while(|l| !l.trim().eq_ignore_ascii_case("endheader"))
        .skip(2)
        .filter(|l| !l.trim().is_empty())
        .count() as f64;
    let repetitions = [60_000.0 / walk_rows, 360_000.0 / walk_rows];
    for (name, a, b) in [
        ("events", counts[0].0, counts[1].0),
        ("bouts", counts[0].1, counts[1].1),
    ] {
        assert!(a > 0, "no {name}");
        let (per_a, per_b) = (a as f64 / repetitions[0], b as f64 / repetitions[1]);
        assert!(
            (per_b / per_a - 1.0).abs() < 0.05,
            "{name}: {a} in 10 min, {b} in 60 min"
        );
    }
    assert!(
        figures[1] as f64 <= 1.1 * figures[0] as f64,
        "events.svg: {} bytes for 10 minutes, {} for 60",
        figures[0],
        figures[1]
    );
    let grew_mib = (peaks[1] - peaks[0]) as f64 / 1024.0;
    assert!(
        // 300,000 more rows: 5 MiB is 17 bytes a row, two f64 columns held.
        grew_mib < 5.0,
        "gait: peak memory grew by {grew_mib:.1} MiB from 10 to 60 minutes"
    );
    assert!(
        peaks[1] < 100 * 1000 * 1000 / 1024,
        "gait: peak {} KiB on an hour, over 100 MB",
        peaks[1]
    );
}
