//! Large files: throughput and peak memory of the `qgait` commands on a million rows.
//!
//! A motion of [`ROWS`] rows (the 18 columns of the shared gait2392 motions, every value
//! printed in full, about 330 MB) and a hub log of the same samples (what the hub sends for
//! them: a PHAK `PoseFrame` per sample computed in `f32`, a `Status` every 100) are written to a
//! temporary directory. The release `qgait` then runs each command on them as a child process;
//! for each: `large.<command>.rows_per_s` (rows or frames), `large.<command>.mb_per_s` (input
//! MB, 10^6 bytes) and `large.<command>.peak_rss_mb` (the child's maximum resident set from
//! `wait4`). `report` adds the size of its largest SVG.

use anyhow::anyhow;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use qgait_proto::device_model::sample_angles;
use qgait_proto::{encode_frame, Kinematics, Message, ModelId, Status, MAX_FRAME_LEN};

use super::figure;
use crate::TempDir;

/// Rows of the generated motion (and samples of the log).
pub const ROWS: usize = 1_000_000;

const LABELS: &str = "time\tpelvis_list\tpelvis_rotation\tpelvis_tilt\thip_flexion_r\thip_adduction_r\thip_rotation_r\tknee_angle_r\tankle_angle_r\thip_flexion_l\thip_adduction_l\thip_rotation_l\tknee_angle_l\tankle_angle_l\tpelvis_ty\tlumbar_bending\tlumbar_rotation\tlumbar_extension";

/// The PHAK angles (degrees, [`qgait_kernel::PhakAngles::NAMES`] order) of row `r`: a gait-like cycle of
/// 100 rows that drifts slowly, so that no two cycles are the same.
fn angles_deg(r: usize) -> [f64; 8] {
    let phase = (r % 100) as f64 * std::f64::consts::TAU / 100.0 + r as f64 * 1e-6;
    let s = phase.sin();
    let c = phase.cos();
    [
        4.0 * s,
        2.0 * c,
        20.0 * s + 10.0,
        -30.0 * c - 30.0,
        10.0 * s,
        -20.0 * s + 10.0,
        30.0 * c - 30.0,
        -10.0 * s,
    ]
}

fn write_motion(path: &Path) -> anyhow::Result<u64> {
    let err = |e: std::io::Error| anyhow!("{}: {e}", path.display());
    let mut f = BufWriter::new(File::create(path).map_err(err)?);
    writeln!(
        f,
        "large\nversion=1\nnRows={ROWS}\nnColumns=18\ninDegrees=yes\nendheader\n{LABELS}"
    )
    .map_err(err)?;
    for r in 0..ROWS {
        let a = angles_deg(r);
        let t = r as f64 * 0.01;
        // PhakAngles order: rotation, list, hip r, knee r, ankle r, hip l, knee l, ankle l.
        let pelvis_tilt = -1.5 + 0.5 * a[0].to_radians().sin();
        writeln!(
            f,
            "{t}\t{}\t{}\t{pelvis_tilt}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t0.96\t0\t0\t0",
            a[1],
            a[0],
            a[2],
            3.0 * a[4].to_radians(),
            -2.0 * a[4].to_radians(),
            a[3],
            a[4],
            a[5],
            -3.0 * a[7].to_radians(),
            2.0 * a[7].to_radians(),
            a[6],
            a[7]
        )
        .map_err(err)?;
    }
    f.flush().map_err(err)?;
    Ok(std::fs::metadata(path).map_err(err)?.len())
}

/// The hub's log for the motion's samples: one PHAK `PoseFrame` per row (the hub's own
/// [`Kinematics`], in `f32`), a `Status` every 100 samples.
fn write_log(path: &Path) -> anyhow::Result<u64> {
    let err = |e: std::io::Error| anyhow!("{}: {e}", path.display());
    let hub = Kinematics::new(ModelId::Phak, None).map_err(|e| anyhow!("{e}"))?;
    let mut f = BufWriter::new(File::create(path).map_err(err)?);
    let mut buf = [0u8; MAX_FRAME_LEN];
    for r in 0..ROWS {
        let angles: [f32; 8] = angles_deg(r).map(|d| d.to_radians() as f32);
        let frame = hub.pose_frame(
            r as u32,
            r as u32 * 10_000,
            &sample_angles(ModelId::Phak, &angles),
            0,
        );
        let bytes =
            encode_frame(&Message::PoseFrame(frame), &mut buf).map_err(|e| anyhow!("{e:?}"))?;
        f.write_all(bytes).map_err(err)?;
        if r % 100 == 99 {
            let status = Status {
                samples_completed: r as u32 + 1,
                frames_sent: r as u32 + 1,
                ..Status::default()
            };
            let bytes =
                encode_frame(&Message::Status(status), &mut buf).map_err(|e| anyhow!("{e:?}"))?;
            f.write_all(bytes).map_err(err)?;
        }
    }
    f.flush().map_err(err)?;
    Ok(std::fs::metadata(path).map_err(err)?.len())
}

/// What one run of a child cost.
struct Cost {
    seconds: f64,
    peak_rss_bytes: u64,
}

/// Runs `exe args` (stdout to `stdout`), waits with `wait4` for its resource usage.
#[allow(clippy::zombie_processes)] // waited for by wait4, which also gives its rusage
fn measure(exe: &Path, args: &[&str], stdout: Option<&Path>) -> anyhow::Result<Cost> {
    eprintln!("==> qgait {}", args.join(" "));
    let out = match stdout {
        Some(p) => Stdio::from(File::create(p).map_err(|e| anyhow!("{}: {e}", p.display()))?),
        None => Stdio::null(),
    };
    let start = Instant::now();
    let child = Command::new(exe)
        .args(args)
        .stdout(out)
        .spawn()
        .map_err(|e| anyhow!("starting {}: {e}", exe.display()))?;
    let mut status = 0;
    // SAFETY: wait4 on our own child, with valid pointers to a status and an rusage.
    let (pid, usage) = unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        let pid = libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage);
        (pid, usage)
    };
    let seconds = start.elapsed().as_secs_f64();
    if pid != child.id() as libc::pid_t {
        return Err(anyhow!(
            "wait4 on qgait {}: {}",
            args.join(" "),
            std::io::Error::last_os_error()
        ));
    }
    if !(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0) {
        return Err(anyhow!("qgait {} failed (status {status})", args.join(" ")));
    }
    // Linux reports ru_maxrss in KiB.
    Ok(Cost {
        seconds,
        peak_rss_bytes: usage.ru_maxrss as u64 * 1024,
    })
}

fn report(name: &str, cost: &Cost, rows: usize, input_bytes: u64) {
    figure(
        &format!("large.{name}.rows_per_s"),
        format!("{:.0}", rows as f64 / cost.seconds),
    );
    figure(
        &format!("large.{name}.mb_per_s"),
        format!("{:.1}", input_bytes as f64 / 1e6 / cost.seconds),
    );
    figure(
        &format!("large.{name}.peak_rss_mb"),
        format!("{:.1}", cost.peak_rss_bytes as f64 / 1e6),
    );
}

/// Generates the files, runs every command on them and prints the figures.
pub fn run() -> anyhow::Result<()> {
    let exe = crate::cargo::qgait_binary()?;
    let dir = TempDir::new("qgait-bench-large")?;
    let at = |name: &str| dir.0.join(name);
    let s = |p: PathBuf| p.to_string_lossy().into_owned();
    eprintln!(
        "==> writing a {ROWS}-row motion and its hub log to {}",
        dir.0.display()
    );
    let motion = at("large.mot");
    let motion_bytes = write_motion(&motion)?;
    let log = at("large.log");
    let log_bytes = write_log(&log)?;
    figure("large.rows", ROWS);
    figure(
        "large.motion_mb",
        format!("{:.1}", motion_bytes as f64 / 1e6),
    );
    figure("large.log_mb", format!("{:.1}", log_bytes as f64 / 1e6));
    let m = s(motion.clone());

    let fk = measure(&exe, &["-q", "fk", &m, "-o", &s(at("fk.csv"))], None)?;
    report("fk", &fk, ROWS, motion_bytes);
    let export = measure(
        &exe,
        &[
            "-q",
            "export",
            &m,
            "--trc",
            &s(at("x.trc")),
            "--sto",
            &s(at("x.sto")),
        ],
        None,
    )?;
    report("export", &export, ROWS, motion_bytes);
    let packets = measure(
        &exe,
        &["-q", "packets", &m, "-o", &s(at("stream.bin"))],
        None,
    )?;
    report("packets", &packets, ROWS, motion_bytes);
    let decode = measure(
        &exe,
        &["-q", "decode", &s(log.clone())],
        Some(&at("frames.csv")),
    )?;
    report("decode", &decode, ROWS, log_bytes);
    let verify = measure(&exe, &["-q", "verify", &s(log.clone())], None)?;
    report("verify", &verify, ROWS, log_bytes);
    let out = at("report");
    let rep = measure(&exe, &["-q", "report", &m, "-o", &s(out.clone())], None)?;
    report("report", &rep, ROWS, motion_bytes);
    let largest_svg = std::fs::read_dir(&out)
        .map_err(|e| anyhow!("{}: {e}", out.display()))?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "svg"))
        .filter_map(|e| e.metadata().ok().map(|m| m.len()))
        .max()
        .unwrap_or(0);
    figure(
        "large.report.largest_svg_mb",
        format!("{:.2}", largest_svg as f64 / 1e6),
    );
    Ok(())
}
