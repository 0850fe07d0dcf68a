//! Memory does not grow with the number of rows: `fk`, `export` and `packets` on a motion and on
//! one ten times longer peak at about the same resident memory (the child's own peak, from
//! `wait4`). Not timed. Whole-file reading held the text and every column: tens of MB more for
//! the longer file.

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
#[allow(clippy::zombie_processes)] // waited for by wait4, which also gives its rusage
fn peak_kib(args: &[&str]) -> i64 {
    let child = Command::new(qgait_system_tests::qgait_bin())
        .args(args)
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
